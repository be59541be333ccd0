//! One cycle of a model as a table: the columns' layout, the rows filled
//! from a solved pose, and the summaries read off the columns.

use crate::error::Error;
use crate::mechanism::analogs::{PieceSolver, solve_cycle};
use crate::mechanism::{Mechanism, Pose};
use crate::model::{Machine, Model, Params};
use crate::scalar::Real;
use crate::thread::Threads;

use super::PathCourse;
use super::paths::PathColumns;
use super::tension::PathInput;
use super::{
    Column, CycleOptions, CycleTable, MU_MAX_DEG, MU_MIN_DEG, PathSummary, RangeSummary, TransmissionSummary,
    cycle_phis_deg, extremes, stitch_process, wrap_deg,
};
use crate::thread::tension::ThreadPhysics;

/// Columns under construction, each with room for a cycle's rows.
pub(super) struct Builder {
    pub(super) columns: Vec<Column>,
    rows: usize,
}

impl Builder {
    fn col(&mut self, name: String) -> usize {
        self.columns.push(Column {
            name,
            values: Vec::with_capacity(self.rows),
        });
        self.columns.len() - 1
    }

    /// A quantity's value column and, with analogs, its first and second
    /// analogs and (with a speed) its real rates: `[value, d1, d2, v, a]`.
    fn scalar_cols(
        &mut self,
        opts: &CycleOptions,
        base: &str,
        unit: &str,
        d_unit: &str,
        rates: (&str, &str),
    ) -> [Option<usize>; 5] {
        let value = Some(self.col(format!("{base}_{unit}")));
        if !opts.analogs {
            return [value, None, None, None, None];
        }
        let d1 = Some(self.col(format!("{base}.d_dphi_{d_unit}_per_rad")));
        let d2 = Some(self.col(format!("{base}.d2_dphi2_{d_unit}_per_rad2")));
        let (v, a) = if opts.rpm.is_some() {
            (
                Some(self.col(format!("{base}.{}", rates.0))),
                Some(self.col(format!("{base}.{}", rates.1))),
            )
        } else {
            (None, None)
        };
        [value, d1, d2, v, a]
    }
}

/// A point's columns: coordinates, then analogs, then real velocities and
/// accelerations (each one per axis, or empty when not asked for).
struct PointCols {
    slot: usize,
    pos: Vec<usize>,
    d1: Vec<usize>,
    d2: Vec<usize>,
    v: Vec<usize>,
    acc: Vec<usize>,
}

/// Where every quantity of the mechanism goes in the table.
struct Layout {
    phi: usize,
    points: Vec<PointCols>,
    angles: Vec<[Option<usize>; 5]>,
    mus: Vec<usize>,
    measures: Vec<[Option<usize>; 5]>,
}

impl Layout {
    fn new(b: &mut Builder, model: &Model, opts: &CycleOptions) -> Layout {
        let phi = b.col("phi_deg".into());
        let axes: &[&str] = if model.planar { &["x", "y"] } else { &["x", "y", "z"] };
        let slots: Vec<usize> = opts.points.clone().unwrap_or_else(|| model.output_points.clone());
        let per_axis = |on: bool, b: &mut Builder, name: &str, f: &dyn Fn(&str) -> String| -> Vec<usize> {
            if on {
                axes.iter().map(|a| b.col(format!("{name}.{}", f(a)))).collect()
            } else {
                Vec::new()
            }
        };
        let rates = opts.analogs && opts.rpm.is_some();
        let points = slots
            .into_iter()
            .map(|slot| {
                let name = &model.point_names[slot];
                PointCols {
                    slot,
                    pos: per_axis(true, b, name, &|a| format!("{a}_mm")),
                    d1: per_axis(opts.analogs, b, name, &|a| format!("d{a}_dphi_mm_per_rad")),
                    d2: per_axis(opts.analogs, b, name, &|a| format!("d2{a}_dphi2_mm_per_rad2")),
                    v: per_axis(rates, b, name, &|a| format!("v{a}_mm_per_s")),
                    acc: per_axis(rates, b, name, &|a| format!("a{a}_mm_per_s2")),
                }
            })
            .collect();
        // Link angles are columns only (no summary or study figure reads
        // them): a lean run leaves them out.
        let angles = if opts.lean {
            Vec::new()
        } else {
            let angle = ("omega_rad_per_s", "eps_rad_per_s2");
            model
                .link_angle_names
                .iter()
                .map(|a| b.scalar_cols(opts, a, "deg", "rad", angle))
                .collect()
        };
        let mus = model.dyads.iter().map(|d| b.col(format!("mu_{}_deg", d.key))).collect();
        let rates = ("v_mm_per_s", "a_mm_per_s2");
        let measures = model
            .measure_names
            .iter()
            .map(|m| b.scalar_cols(opts, m, "mm", "mm", rates))
            .collect();
        Layout {
            phi,
            points,
            angles,
            mus,
            measures,
        }
    }

    /// One row per φ from the solved pose.
    fn fill<T: Real>(&self, cols: &mut [Column], mech: &Mechanism<T>, pose: &Pose<T>, phis: &[f64], w: f64) {
        let push = |cols: &mut [Column], c: Option<usize>, v: f64| {
            if let Some(c) = c {
                cols[c].values.push(v);
            }
        };
        let (mut angles, mut mus, mut measures) = (Vec::new(), Vec::new(), Vec::new());
        for (k, &phi_deg) in phis.iter().enumerate() {
            cols[self.phi].values.push(phi_deg);
            for pc in &self.points {
                let q = pose.point(pc.slot, k);
                for j in 0..pc.pos.len() {
                    cols[pc.pos[j]].values.push(q[j].re());
                    if !pc.d1.is_empty() {
                        cols[pc.d1[j]].values.push(q[j].d1());
                        cols[pc.d2[j]].values.push(q[j].d2());
                    }
                    if !pc.v.is_empty() {
                        cols[pc.v[j]].values.push(q[j].d1() * w);
                        cols[pc.acc[j]].values.push(q[j].d2() * w * w);
                    }
                }
            }
            if !self.angles.is_empty() {
                mech.link_angles(pose, k, &mut angles);
            }
            for (a, c) in angles.iter().zip(&self.angles) {
                let row = [a.re().to_degrees(), a.d1(), a.d2(), a.d1() * w, a.d2() * w * w];
                for (j, val) in row.into_iter().enumerate() {
                    push(cols, c[j], val);
                }
            }
            mech.transmission_angles(pose, k, &mut mus);
            for (m, &c) in mus.iter().zip(&self.mus) {
                cols[c].values.push(m.re().to_degrees());
            }
            mech.measures(pose, k, &mut measures);
            for (m, c) in measures.iter().zip(&self.measures) {
                for (j, val) in [m.re(), m.d1(), m.d2(), m.d1() * w, m.d2() * w * w]
                    .into_iter()
                    .enumerate()
                {
                    push(cols, c[j], val);
                }
            }
        }
    }
}

/// Positions solved at a time: the mechanism's pose of one piece (for the
/// MF-7923D's 46 points in dual numbers, 72 B a point and φ) is 14 MB
/// whatever the step, where a whole cycle of 0.001° steps took 1.2 GB.
const PIECE: usize = 4096;

/// A full cycle in scalar type `T` (`f64`, or dual numbers for analogs);
/// without the stitch process (its columns, summary and the thread's
/// tension) unless `with_stitch`.
pub(super) fn cycle<T: Real>(
    model: &Model,
    params: &Params,
    opts: &CycleOptions,
    prepared: Option<&stitch_process::Prepared>,
    with_stitch: bool,
) -> Result<CycleTable, Error> {
    cycle_in_pieces::<T>(model, params, opts, prepared, with_stitch, PIECE)
}

/// [`cycle`], the mechanism solved `piece` positions at a time.
fn cycle_in_pieces<T: Real>(
    model: &Model,
    params: &Params,
    opts: &CycleOptions,
    prepared: Option<&stitch_process::Prepared>,
    with_stitch: bool,
    piece: usize,
) -> Result<CycleTable, Error> {
    let Machine {
        mechanism: mech,
        threads,
    } = model.machine::<T>(params)?;
    let phis = cycle_phis_deg(model.phi_start_deg(), opts.step_deg);
    let mut b = Builder {
        columns: Vec::new(),
        rows: phis.len(),
    };
    let layout = Layout::new(&mut b, model, opts);
    // Analogs in closed form where every group has one (mechanism::analogs):
    // about 2× faster than dual numbers for the four-bar and needle876. With
    // thread paths the dual pose feeds the paths' own analogs, and building
    // it from the closed form costs more than it saves (mf7923d: about 10 %
    // slower per cycle, docs/benchmarks.md), so those stay dual.
    let closed_form = opts.analogs && threads.is_none();
    let plain = if closed_form {
        Some(model.mechanism::<f64>(params)?)
    } else {
        None
    };
    // The paths whose thread's tension is solved: those a stitch thread is
    // compared with, when they carry thread physics.
    let physics = model.thread_physics(params)?;
    let stitch_paths = model.stitch_paths();
    let record: Vec<bool> = threads.as_ref().map_or(Vec::new(), |t| {
        t.paths
            .iter()
            .zip(&physics)
            .map(|(p, ph)| with_stitch && ph.is_some() && stitch_paths.iter().flatten().any(|n| *n == p.name))
            .collect()
    });
    let solved = Pieces {
        mech: &mech,
        plain: plain.as_ref(),
        threads: threads.as_ref(),
        phis: &phis,
        opts,
        record: &record,
    };
    // The stitch process needs the mechanism's columns only at the end: it
    // is prepared on another core while they are solved.
    let (solved_columns, own_prepared) = rayon::join(
        || solved.columns(&layout, piece, &mut b.columns),
        || match prepared {
            Some(_) => Ok(None),
            None if !with_stitch => Ok(None),
            None => stitch_process::prepare(model, params, opts.step_deg),
        },
    );
    let (paths, take_up, courses) = match solved_columns {
        Ok(p) => p,
        // A long cycle that fails may fail in several ways: say the one a
        // solve of the whole cycle at once meets first.
        Err(e) if phis.len() > piece => return Err(solved.whole_cycle_error(e)),
        Err(e) => return Err(e),
    };
    let own_prepared = own_prepared?;
    let stitch = match prepared.or(own_prepared.as_ref()).filter(|_| with_stitch) {
        Some(p) => {
            let inputs = tension_inputs(threads.as_ref(), &p.setup.paths, &physics, &courses);
            Some(stitch_process::stitch_columns(
                p,
                &phis,
                opts.lean,
                &inputs,
                &mut b.columns,
            )?)
        }
        None => None,
    };
    let columns = b.columns;
    check_finite(&columns, &phis)?;
    let mut warnings: Vec<String> = stitch.iter().flat_map(|s| s.warnings.iter().cloned()).collect();
    let transmission = transmission_summaries(model, &columns, &layout.mus, &phis, &mut warnings);
    let ranges = range_summaries(model, &columns, &layout.measures, &phis);
    let cams = if mech
        .steps
        .iter()
        .any(|s| matches!(s, crate::mechanism::Step::CamFollower(_)))
    {
        super::cams::cam_summaries(model, params, &phis, opts.rpm.or(model.rpm()))?
    } else {
        Vec::new()
    };
    Ok(CycleTable {
        step_deg: opts.step_deg,
        rpm: opts.rpm,
        columns,
        transmission,
        ranges,
        paths,
        take_up,
        stitch,
        cams,
        warnings,
    })
}

/// For each stitch thread (compared with the path named in `paths`), what
/// its tension is solved from, when its path carries thread physics.
fn tension_inputs<'a, T: Real>(
    threads: Option<&'a Threads<T>>,
    paths: &[Option<String>],
    physics: &'a [Option<ThreadPhysics>],
    courses: &'a [Option<PathCourse>],
) -> Vec<Option<PathInput<'a>>> {
    let Some(threads) = threads else {
        return vec![None; paths.len()];
    };
    paths
        .iter()
        .map(|name| {
            let i = threads.paths.iter().position(|p| Some(&p.name) == name.as_ref())?;
            Some(PathInput {
                physics: physics.get(i)?.as_ref()?,
                path: &threads.paths[i],
                course: courses.get(i)?.as_ref()?,
            })
        })
        .collect()
}

/// The paths' summaries, how P is counted, and the courses kept for the
/// threads' tensions.
type SolvedPaths = (Vec<PathSummary>, Option<String>, Vec<Option<PathCourse>>);

/// A cycle's mechanism and thread paths, to be solved piece by piece.
struct Pieces<'a, T: Real> {
    mech: &'a Mechanism<T>,
    /// The mechanism in `f64`, for analogs in closed form.
    plain: Option<&'a Mechanism<f64>>,
    threads: Option<&'a Threads<T>>,
    phis: &'a [f64],
    opts: &'a CycleOptions,
    /// The paths whose course the threads' tensions need.
    record: &'a [bool],
}

impl<T: Real> Pieces<'_, T> {
    /// Fills the mechanism's columns (`layout`) and adds the thread paths'
    /// to `columns`, `piece` positions at a time; returns the paths'
    /// summaries and how P is counted.
    fn columns(&self, layout: &Layout, piece: usize, columns: &mut Vec<Column>) -> Result<SolvedPaths, Error> {
        let omega = self.opts.rpm.map_or(0.0, |r| r * std::f64::consts::TAU / 60.0);
        let mut solver = PieceSolver::new(self.mech, self.plain, piece.min(self.phis.len()));
        let mut paths: Option<PathColumns<T>> = None;
        for phis in self.phis.chunks(piece) {
            let pose = solver.solve(phis)?;
            let mut fill = || layout.fill(columns, self.mech, pose, phis, omega);
            if let Some(threads) = self.threads {
                let p = match &mut paths {
                    Some(p) => p,
                    None => paths.insert(PathColumns::new(self.mech, threads, self.opts, self.record)?),
                };
                // The mechanism's columns and the paths' are apart: one
                // core each.
                rayon::join(fill, || p.add(threads, pose, phis)).1?;
            } else {
                fill();
            }
        }
        Ok(match (paths, self.threads) {
            (Some(p), Some(threads)) => p.finish(threads, self.phis, self.opts, columns),
            _ => (Vec::new(), None, Vec::new()),
        })
    }

    /// The error a solve of the whole cycle at once meets first (the
    /// mechanism at every φ, then the thread paths); `fallback` if it
    /// meets none.
    fn whole_cycle_error(&self, fallback: Error) -> Error {
        let pose = match solve_cycle(self.mech, self.plain, self.phis) {
            Ok(pose) => pose,
            Err(e) => return e.into(),
        };
        let Some(threads) = self.threads else {
            return fallback;
        };
        match PathColumns::new(self.mech, threads, self.opts, self.record)
            .and_then(|mut p| p.add(threads, &pose, self.phis))
        {
            Err(e) => e,
            Ok(()) => fallback,
        }
    }
}

/// Never NaN or infinity in output.
fn check_finite(columns: &[Column], phis: &[f64]) -> Result<(), Error> {
    for c in columns {
        if let Some(k) = c.values.iter().position(|v| !v.is_finite()) {
            return Err(super::not_finite(&c.name, c.values[k], phis[k]));
        }
    }
    Ok(())
}

/// Each dyad's transmission angle at its extremes, with a warning where it
/// leaves the band of seed 002 eq. 15.
fn transmission_summaries(
    model: &Model,
    columns: &[Column],
    mu_cols: &[usize],
    phis: &[f64],
    warnings: &mut Vec<String>,
) -> Vec<TransmissionSummary> {
    model
        .dyads
        .iter()
        .zip(mu_cols)
        .map(|(d, &c)| {
            let v = &columns[c].values;
            let (i0, i1) = extremes(v);
            let ok = v[i0] >= MU_MIN_DEG && v[i1] <= MU_MAX_DEG;
            if !ok {
                warnings.push(format!(
                    "transmission angle of {} leaves {MU_MIN_DEG}°…{MU_MAX_DEG}°: {:.2}° at φ = {:.1}° … {:.2}° at φ = {:.1}° (risk of jamming)",
                    d.label, v[i0], wrap_deg(phis[i0]), v[i1], wrap_deg(phis[i1])
                ));
            }
            TransmissionSummary {
                key: d.key.clone(),
                group: d.label.clone(),
                min_deg: v[i0],
                phi_at_min_deg: wrap_deg(phis[i0]),
                max_deg: v[i1],
                phi_at_max_deg: wrap_deg(phis[i1]),
                ok,
            }
        })
        .collect()
}

/// Each measure's range over the cycle.
fn range_summaries(
    model: &Model,
    columns: &[Column],
    measure_cols: &[[Option<usize>; 5]],
    phis: &[f64],
) -> Vec<RangeSummary> {
    model
        .measure_names
        .iter()
        .zip(measure_cols)
        .map(|(name, c)| {
            let v = &columns[c[0].expect("value column always present")].values;
            let (i0, i1) = extremes(v);
            RangeSummary {
                name: name.clone(),
                unit: "mm",
                min: v[i0],
                phi_at_min_deg: wrap_deg(phis[i0]),
                max: v[i1],
                phi_at_max_deg: wrap_deg(phis[i1]),
                range: v[i1] - v[i0],
            }
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use num_dual::Dual2_64;

    /// A cycle solved in pieces is the cycle solved whole, bit for bit:
    /// every preset, with and without analogs (dual or closed form), with
    /// a speed, lean; pieces of one position, of 7, and the whole.
    #[test]
    fn pieces_give_the_whole_cycle() {
        for preset in crate::presets::ALL {
            let model = Model::preset(preset.name).unwrap();
            let params = model.defaults();
            for (analogs, lean, rpm) in [(true, false, Some(1200.0)), (false, false, None), (false, true, None)] {
                let opts = CycleOptions {
                    step_deg: 2.5,
                    rpm,
                    analogs,
                    lean,
                    ..Default::default()
                };
                let run = |piece: usize| {
                    if analogs {
                        cycle_in_pieces::<Dual2_64>(&model, &params, &opts, None, true, piece)
                    } else {
                        cycle_in_pieces::<f64>(&model, &params, &opts, None, true, piece)
                    }
                    .unwrap()
                };
                let whole = run(usize::MAX);
                for piece in [1, 7] {
                    assert!(run(piece) == whole, "{} in pieces of {piece}, {opts:?}", preset.name);
                }
            }
        }
    }

    /// A cycle that fails in several ways says what the whole cycle's solve
    /// meets first, however it is cut: here the first dyad fails from
    /// φ ≈ 43° on, the second at φ = 0, which the first piece meets first.
    #[test]
    fn pieces_fail_as_the_whole_cycle() {
        let model = Model::from_toml_str(
            r#"
[model]
name = "two-dyads"
[points]
O1 = [0, 0]
O2 = [60, 0]
O3 = [-60, 0]
[[drivers]]
type = "crank"
center = "O1"
out = "A"
radius = 15
[[groups]]
type = "rrr"
joints = ["A", "O2"]
lengths = [30, 20]
out = "B"
branch = "left"
[[groups]]
type = "rrr"
joints = ["A", "O3"]
lengths = [30, 20]
out = "C"
branch = "left"
"#,
            "two-dyads.toml",
        )
        .unwrap();
        let params = model.defaults();
        let opts = CycleOptions::default();
        let whole = cycle_in_pieces::<Dual2_64>(&model, &params, &opts, None, true, usize::MAX)
            .unwrap_err()
            .to_string();
        assert!(whole.contains("φ = 43.000°"), "{whole}");
        for piece in [1, 7, 100] {
            let e = cycle_in_pieces::<Dual2_64>(&model, &params, &opts, None, true, piece).unwrap_err();
            assert_eq!(e.to_string(), whole, "pieces of {piece}");
        }
    }
}
