//! A cycle's thread-path columns: ξ, the take-up P (split at B for a
//! needle-eye path), its analogs, the guides' engagement and wrap angles,
//! the capstan tension, and each path's summary.
//!
//! The columns grow a piece of the cycle at a time ([`PathColumns::add`]),
//! from the pose of that piece alone; the summaries are read off the whole
//! columns at the end ([`PathColumns::finish`]).

use rayon::prelude::*;

use crate::error::Error;
use crate::mechanism::{Mechanism, Pose};
use crate::scalar::Real;
use crate::thread::{
    Convention, PathTrack, SplitPoint, ThreadPath, ThreadWork, Threads, Turns, capstan, capstan_factor,
};

use super::{
    Column, CycleOptions, FLAT_MIN_DEG, FLAT_SLOPE_MM_PER_DEG, PathSummary, extremes, path_error, take_up_name,
    tracks_at_phi0, wrap_deg,
};

/// Every path's columns under construction.
pub(super) struct PathColumns<T: Real> {
    /// Every path at φ0.
    at0: Vec<PathTrack<T>>,
    work: ThreadWork<T>,
    paths: Vec<PathValues>,
    analogs: bool,
    lean: bool,
    /// For each path whose thread's tension is solved, what the solver
    /// needs of it at every φ.
    courses: Vec<Option<PathCourse>>,
}

/// A path over the cycle as the thread's tension needs it: the length
/// between each pair of consecutive nodes and the angle the thread turns
/// through at each node, one row per φ.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct PathCourse {
    /// n × (nodes − 1), mm ([`Threads::gap_lengths`]).
    pub gaps_mm: Vec<f64>,
    /// n × nodes, rad ([`Threads::wrap_angles`]).
    pub wraps_rad: Vec<f64>,
    /// The capstan factors e^{μ_j·θ_j} of the guides between the
    /// regulator and the eye (nodes 1 … nodes − 2), n × (nodes − 2), with
    /// the friction they were taken at ([`Self::keep_capstan`]); empty
    /// until a study keeps them.
    capstan: Vec<f64>,
    capstan_mu: Vec<f64>,
}

impl PathCourse {
    /// Adds the first `n` positions of `pose`, whose thread pieces `work`
    /// holds (`Threads::evaluate_into` of that pose).
    pub fn extend<T: Real>(
        &mut self,
        threads: &Threads<T>,
        path: &ThreadPath,
        pose: &Pose<T>,
        work: &ThreadWork<T>,
        n: usize,
    ) {
        let mut gaps = Vec::new();
        let mut turns = Turns::default();
        for k in 0..n {
            threads.gap_lengths(path, pose, work, k, &mut gaps);
            self.gaps_mm.extend_from_slice(&gaps);
            self.wraps_rad
                .extend_from_slice(threads.wrap_angles(path, pose, k, &mut turns));
        }
    }

    /// The wrap angles of the last `rows` positions added, `nodes` a row.
    fn last_wraps(&self, rows: usize, nodes: usize) -> &[f64] {
        &self.wraps_rad[self.wraps_rad.len() - rows * nodes..]
    }

    /// Empty, keeping its buffers.
    pub fn clear(&mut self) {
        self.gaps_mm.clear();
        self.wraps_rad.clear();
        self.capstan.clear();
        self.capstan_mu.clear();
    }

    /// Takes the guides' capstan factors at the path's `friction` (one per
    /// node) once and keeps them while the course and the friction stay:
    /// a study over the stitch alone solves the tension over the same
    /// course at every setting.
    pub fn keep_capstan(&mut self, friction: &[f64]) {
        let nodes = friction.len();
        if nodes < 2 || !self.wraps_rad.len().is_multiple_of(nodes) {
            return;
        }
        let guides = &friction[1..nodes - 1];
        let n = self.wraps_rad.len() / nodes;
        if self.capstan_mu == guides && self.capstan.len() == n * guides.len() {
            return;
        }
        self.capstan.clear();
        for k in 0..n {
            for (j, &mu) in guides.iter().enumerate() {
                self.capstan.push(capstan_factor(mu, self.wraps_rad[k * nodes + j + 1]));
            }
        }
        self.capstan_mu.clear();
        self.capstan_mu.extend_from_slice(guides);
    }

    /// The capstan factors of the guides between the regulator and the eye
    /// at position `k`, kept at `friction` ([`Self::keep_capstan`]), or
    /// `None` when none are kept for it.
    pub fn kept_capstan(&self, friction: &[f64], k: usize) -> Option<&[f64]> {
        let guides = friction.len().checked_sub(2)?;
        (!self.capstan.is_empty() && self.capstan_mu == friction[1..friction.len() - 1])
            .then(|| self.capstan.get(k * guides..(k + 1) * guides))
            .flatten()
    }
}

/// One path's values over the positions added so far.
#[derive(Default)]
struct PathValues {
    xi: Vec<f64>,
    /// P and its first and second analogs (with analogs).
    p: Vec<f64>,
    d1: Vec<f64>,
    d2: Vec<f64>,
    /// A path split at B: P at the moving eye.
    p_eye: Option<Vec<f64>>,
    /// Per pin, whether the thread bears on it.
    engaged: Vec<Vec<bool>>,
    /// Per node, the angle the thread turns through, deg (not lean).
    wrap_deg: Vec<Vec<f64>>,
    /// The capstan tension at the eye, N, and the largest after each node
    /// (with a regulator tension, not lean).
    eye_tension_n: Vec<f64>,
    max_tension_n: Vec<f64>,
}

impl<T: Real> PathColumns<T> {
    /// The columns of every path; `record[i]`: keep path i's course for
    /// its thread's tension.
    pub(super) fn new(
        mech: &Mechanism<T>,
        threads: &Threads<T>,
        opts: &CycleOptions,
        record: &[bool],
    ) -> Result<Self, Error> {
        let at0 = tracks_at_phi0(mech, threads)?;
        let paths = threads
            .paths
            .iter()
            .zip(&threads.split_up)
            .map(|(path, up)| PathValues {
                // Split at B: the eye's height rides along, as in a cycle's track.
                p_eye: (up.is_some() && !path.nodes.is_empty()).then(Vec::new),
                engaged: vec![Vec::new(); path.pin_names().len()],
                wrap_deg: vec![Vec::new(); path.nodes.len()],
                max_tension_n: vec![f64::MIN; path.nodes.len()],
                ..Default::default()
            })
            .collect();
        Ok(PathColumns {
            at0,
            work: ThreadWork::for_pieces(),
            paths,
            analogs: opts.analogs,
            lean: opts.lean,
            courses: (0..threads.paths.len())
                .map(|i| record.get(i).copied().unwrap_or(false).then(PathCourse::default))
                .collect(),
        })
    }

    /// Adds the positions of `pose`, solved at `phis` (the next piece of
    /// the cycle).
    pub(super) fn add(&mut self, threads: &Threads<T>, pose: &Pose<T>, phis: &[f64]) -> Result<(), Error> {
        threads.evaluate_into(pose, None, &mut self.work).map_err(|e| {
            let phi = phis[e.k];
            path_error(e, phi)
        })?;
        let n = phis.len();
        let work = &self.work;
        self.courses
            .par_iter_mut()
            .zip(threads.paths.par_iter())
            .for_each(|(course, path)| {
                if let Some(course) = course {
                    course.extend(threads, path, pose, work, n);
                }
            });
        let (analogs, lean) = (self.analogs, self.lean);
        // The wrap angles are most of a full table's work, and the paths are
        // independent: one per core. A lean table computes none of them, and
        // its paths stay on this core (one piece: rayon does not split it).
        let min_len = if lean { usize::MAX } else { 1 };
        threads
            .paths
            .par_iter()
            .zip(&self.work.tracks)
            .zip(&self.at0)
            .zip(&self.courses)
            .zip(&mut self.paths)
            .with_min_len(min_len)
            .for_each(|((((path, track), at0), course), v)| {
                let piece = Piece {
                    track,
                    at0,
                    pose,
                    n,
                    wraps: course.as_ref().map(|c| c.last_wraps(n, path.nodes.len())),
                };
                v.add(threads, path, piece, analogs, lean)
            });
        Ok(())
    }

    /// Moves each path's columns into `columns` and returns the paths'
    /// summaries and the words that say how P is counted…
    /// …and the courses kept for the threads' tensions.
    pub(super) fn finish(
        self,
        threads: &Threads<T>,
        phis: &[f64],
        opts: &CycleOptions,
        columns: &mut Vec<Column>,
    ) -> (Vec<PathSummary>, Option<String>, Vec<Option<PathCourse>>) {
        let summaries = threads
            .paths
            .iter()
            .zip(self.paths)
            .zip(&self.at0)
            .map(|((path, v), at0)| one_path(path, v, at0, phis, opts, columns))
            .collect();
        (summaries, Some(convention_words(threads)), self.courses)
    }
}

/// A piece of the cycle as one path's columns read it.
struct Piece<'a, T: Real> {
    /// The path over the piece and at φ0.
    track: &'a PathTrack<T>,
    at0: &'a PathTrack<T>,
    pose: &'a Pose<T>,
    /// The piece's positions: the first `n` of `pose`.
    n: usize,
    /// The path's wrap angles over the piece, n × nodes, rad, where its
    /// thread's course already holds them.
    wraps: Option<&'a [f64]>,
}

impl PathValues {
    /// Adds the positions of `piece`.
    fn add<T: Real>(
        &mut self,
        threads: &Threads<T>,
        path: &ThreadPath,
        piece: Piece<'_, T>,
        analogs: bool,
        lean: bool,
    ) {
        let Piece {
            track,
            at0,
            pose,
            n,
            wraps,
        } = piece;
        let conv = &threads.convention;
        let xi0 = at0.xi_at_split(0);
        for k in 0..n {
            let p = conv.take_up(track.xi_at_split(k), xi0);
            self.xi.push(track.xi[k].re());
            self.p.push(p.re());
            if analogs {
                self.d1.push(p.d1());
                self.d2.push(p.d2());
            }
        }
        if let Some(p_eye) = &mut self.p_eye {
            p_eye.extend(track.xi[..n].iter().map(|x| conv.take_up(*x, at0.xi[0]).re()));
        }
        for (flags, e) in self.engaged.iter_mut().zip(&track.engaged) {
            flags.extend_from_slice(&e[..n]);
        }
        if lean {
            return;
        }
        // Each position's wrap angles and tensions stand alone: on every core,
        // into rows of `m` (the course's angles where it holds them).
        let m = path.nodes.len();
        let computed: Vec<f64>;
        let theta = match wraps {
            Some(w) => w,
            None => {
                let mut rows = vec![0.0; n * m];
                rows.par_chunks_mut(m.max(1))
                    .enumerate()
                    .for_each_init(Turns::default, |turns, (k, row)| {
                        row.copy_from_slice(threads.wrap_angles(path, pose, k, turns));
                    });
                computed = rows;
                &computed
            }
        };
        for row in theta.chunks_exact(m.max(1)).take(n) {
            for (col, t) in self.wrap_deg.iter_mut().zip(row) {
                col.push(t.to_degrees());
            }
            if let Some(t0) = threads.tension_n {
                let mut eye = t0;
                for (max, t) in self.max_tension_n.iter_mut().zip(capstan(row, &path.friction, t0)) {
                    *max = max.max(t);
                    eye = t;
                }
                self.eye_tension_n.push(eye);
            }
        }
    }
}

/// One path's columns and summary.
fn one_path<T: Real>(
    path: &ThreadPath,
    v: PathValues,
    at0: &PathTrack<T>,
    phis: &[f64],
    opts: &CycleOptions,
    columns: &mut Vec<Column>,
) -> PathSummary {
    let name = &path.name;
    let split = v.p_eye.is_some();
    let pn = take_up_name(split);
    let mut col = |n: String, values: Vec<f64>| {
        columns.push(Column {
            name: format!("{name}.{n}"),
            values,
        })
    };
    let (imin, imax) = extremes(&v.p);
    let summary = PathSummary {
        path: name.clone(),
        thread: path.label.clone(),
        split: if split { SplitPoint::B } else { SplitPoint::End },
        p_column: format!("{name}.{pn}_mm"),
        max_p_eye_mm: v.p_eye.as_ref().map(|e| e.iter().cloned().fold(f64::MIN, f64::max)),
        max_p_mm: v.p[imax],
        phi_at_max_deg: wrap_deg(phis[imax]),
        min_p_mm: v.p[imin],
        phi_at_min_deg: wrap_deg(phis[imin]),
        xi0_mm: at0.xi[0].re(),
        engaged: path
            .pin_names()
            .iter()
            .zip(&v.engaged)
            .map(|(pin, flags)| (pin.to_string(), crate::thread::intervals(flags, phis)))
            .collect(),
        flat: flat_intervals(&v.d1, &v.p, phis, opts),
        max_tension_n: if v.eye_tension_n.is_empty() {
            Vec::new()
        } else {
            path.node_names.iter().cloned().zip(v.max_tension_n).collect()
        },
        eye_tension_n: (!v.eye_tension_n.is_empty()).then(|| {
            [
                v.eye_tension_n.iter().cloned().fold(f64::MAX, f64::min),
                v.eye_tension_n.iter().cloned().fold(f64::MIN, f64::max),
            ]
        }),
    };
    col("xi_mm".into(), v.xi);
    col(format!("{pn}_mm"), v.p);
    if opts.analogs {
        if let Some(rpm) = opts.rpm {
            let w = rpm * std::f64::consts::TAU / 60.0;
            let vel = v.d1.iter().map(|x| x * w).collect();
            col(format!("d{pn}_dphi_mm_per_rad"), v.d1);
            col(format!("d2{pn}_dphi2_mm_per_rad2"), v.d2);
            col(format!("v{pn}_mm_per_s"), vel);
        } else {
            col(format!("d{pn}_dphi_mm_per_rad"), v.d1);
            col(format!("d2{pn}_dphi2_mm_per_rad2"), v.d2);
        }
    }
    // The same thread measured at the moving eye (P_eye = P_B − S + S(φ0)).
    if let Some(p_eye) = v.p_eye {
        col("P_eye_mm".into(), p_eye);
    }
    // Per guide between the ends: whether a pin is engaged, the wrap angle;
    // then the eye's tension.
    let (mut engaged, mut wraps) = (v.engaged.into_iter(), v.wrap_deg.into_iter().skip(1));
    for i in 1..path.nodes.len().saturating_sub(1) {
        let node = &path.node_names[i];
        if path.pin_span[i].is_some() {
            let flags = engaged.next().expect("one flag column per pin");
            col(
                format!("{node}_engaged"),
                flags.iter().map(|&e| if e { 1.0 } else { 0.0 }).collect(),
            );
        }
        let wrap = wraps.next().expect("one wrap column per node");
        if !opts.lean {
            col(format!("{node}_wrap_deg"), wrap);
        }
    }
    if !v.eye_tension_n.is_empty() {
        col("tension_eye_N".into(), v.eye_tension_n);
    }
    summary
}

/// Where P dwells: intervals of at least FLAT_MIN_DEG where |dP/dφ| stays
/// under FLAT_SLOPE_MM_PER_DEG. The slope is exact with analogs (`d1`, mm
/// per rad); otherwise the central difference on the (periodic) grid of
/// `p`, enough to classify dwells.
fn flat_intervals(d1: &[f64], p: &[f64], phis: &[f64], opts: &CycleOptions) -> Vec<crate::thread::Interval> {
    let slope_mm_per_deg: Vec<f64> = if opts.analogs {
        d1.iter().map(|x| x * std::f64::consts::PI / 180.0).collect()
    } else {
        let n = p.len();
        (0..n)
            .map(|k| (p[(k + 1) % n] - p[(k + n - 1) % n]) / (2.0 * opts.step_deg))
            .collect()
    };
    let flat_flags: Vec<bool> = slope_mm_per_deg
        .iter()
        .map(|s| s.abs() < FLAT_SLOPE_MM_PER_DEG)
        .collect();
    crate::thread::intervals(&flat_flags, phis)
        .into_iter()
        .filter(|iv| iv.to_deg - iv.from_deg >= FLAT_MIN_DEG)
        .collect()
}

/// How P is counted, for the table's notes (seed 000 eq. 2, seed 001
/// eq. 22-23, seed 004 §2.3).
fn convention_words<T: Real>(threads: &Threads<T>) -> String {
    let mut words = match threads.convention {
        Convention::Release => format!(
            "P = xi(phi0) - xi(phi), phi0 = {} deg ({} eq. 2)",
            threads.phi0_deg,
            crate::references::cite(0)
        ),
        Convention::Feed { elongation_mm } => format!(
            "P = xi(phi) - xi(phi0) + dP, dP = {elongation_mm} mm, phi0 = {} deg ({} eq. 22-23)",
            threads.phi0_deg,
            crate::references::cite(1)
        ),
    };
    if threads.split_up.iter().any(Option::is_some) {
        words += &format!(
            "; needle-eye paths split at B, the eye's top position: P_B = P_eye + S(phi) - S(phi0), S the needle's travel \
             below B ({} sec. 2.3)",
            crate::references::cite(4)
        );
    }
    words
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The kept capstan factors are those taken afresh, and are not read at
    /// another friction or past the rows they were taken for.
    #[test]
    fn kept_capstan_factors_are_the_guides_own() {
        let nodes = 4;
        let wraps_rad: Vec<f64> = (0..3 * nodes).map(|i| 0.1 * i as f64).collect();
        let mut course = PathCourse {
            gaps_mm: vec![1.0; 3 * (nodes - 1)],
            wraps_rad,
            ..Default::default()
        };
        let friction = [0.0, 0.2, 0.3, 0.15];
        assert!(course.kept_capstan(&friction, 0).is_none(), "nothing kept yet");
        course.keep_capstan(&friction);
        for k in 0..3 {
            let fresh: Vec<f64> = (1..nodes - 1)
                .map(|j| capstan_factor(friction[j], course.wraps_rad[k * nodes + j]))
                .collect();
            assert_eq!(course.kept_capstan(&friction, k), Some(&fresh[..]), "row {k}");
        }
        assert!(course.kept_capstan(&friction, 3).is_none(), "past the rows");
        assert!(
            course.kept_capstan(&[0.0, 0.25, 0.3, 0.15], 0).is_none(),
            "another friction"
        );
        course.clear();
        assert!(course.kept_capstan(&friction, 0).is_none(), "cleared");
    }
}
