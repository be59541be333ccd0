//! A cycle's thread-path columns: ξ, the take-up P (split at B for a
//! needle-eye path), its analogs, the guides' engagement and wrap angles,
//! the capstan tension, and each path's summary.

use crate::error::Error;
use crate::mechanism::{Mechanism, Pose};
use crate::scalar::Real;
use crate::thread::{Convention, PathTrack, SplitPoint, ThreadPath, Threads};

use super::{
    Column, CycleOptions, FLAT_MIN_DEG, FLAT_SLOPE_MM_PER_DEG, PathSummary, extremes, path_error, take_up_name,
    tracks_at_phi0, wrap_deg,
};

/// Adds each path's columns and returns the paths' summaries and the words
/// that say how P is counted.
pub(super) fn path_columns<T: Real>(
    mech: &Mechanism<T>,
    threads: &Threads<T>,
    pose: &Pose<T>,
    phis: &[f64],
    opts: &CycleOptions,
    columns: &mut Vec<Column>,
) -> Result<(Vec<PathSummary>, Option<String>), Error> {
    let at0 = tracks_at_phi0(mech, threads)?;
    let tracks = threads.evaluate(pose, None).map_err(|e| {
        let phi = phis[e.k];
        path_error(e, phi)
    })?;
    let summaries = threads
        .paths
        .iter()
        .zip(tracks)
        .zip(at0)
        .map(|((path, track), at0)| one_path(threads, path, &track, &at0, pose, phis, opts, columns))
        .collect();
    Ok((summaries, Some(convention_words(threads))))
}

/// One path's columns and summary.
#[allow(clippy::too_many_arguments)]
fn one_path<T: Real>(
    threads: &Threads<T>,
    path: &ThreadPath,
    track: &PathTrack<T>,
    at0: &PathTrack<T>,
    pose: &Pose<T>,
    phis: &[f64],
    opts: &CycleOptions,
    columns: &mut Vec<Column>,
) -> PathSummary {
    let name = &path.name;
    let split = !track.eye_up.is_empty();
    let pn = take_up_name(split);
    let p: Vec<T> = (0..track.xi.len())
        .map(|k| threads.convention.take_up(track.xi_at_split(k), at0.xi_at_split(0)))
        .collect();
    let mut col = |n: String, v: Vec<f64>| {
        columns.push(Column {
            name: format!("{name}.{n}"),
            values: v,
        })
    };
    col("xi_mm".into(), track.xi.iter().map(|x| x.re()).collect());
    col(format!("{pn}_mm"), p.iter().map(|x| x.re()).collect());
    if opts.analogs {
        col(format!("d{pn}_dphi_mm_per_rad"), p.iter().map(|x| x.d1()).collect());
        col(format!("d2{pn}_dphi2_mm_per_rad2"), p.iter().map(|x| x.d2()).collect());
        if let Some(rpm) = opts.rpm {
            let w = rpm * std::f64::consts::TAU / 60.0;
            col(format!("v{pn}_mm_per_s"), p.iter().map(|x| x.d1() * w).collect());
        }
    }
    // The same thread measured at the moving eye (P_eye = P_B − S + S(φ0)).
    let p_eye: Option<Vec<f64>> = split.then(|| {
        track
            .xi
            .iter()
            .map(|x| threads.convention.take_up(*x, at0.xi[0]).re())
            .collect()
    });
    if let Some(v) = &p_eye {
        col("P_eye_mm".into(), v.clone());
    }
    let tensions = guide_columns(threads, path, track, pose, phis, opts, &mut col);
    let p_re: Vec<f64> = p.iter().map(|x| x.re()).collect();
    let (imin, imax) = extremes(&p_re);
    let pins = path.pin_names();
    PathSummary {
        path: name.clone(),
        thread: path.label.clone(),
        split: if split { SplitPoint::B } else { SplitPoint::End },
        p_column: format!("{name}.{pn}_mm"),
        max_p_eye_mm: p_eye.as_ref().map(|v| v.iter().cloned().fold(f64::MIN, f64::max)),
        max_p_mm: p_re[imax],
        phi_at_max_deg: wrap_deg(phis[imax]),
        min_p_mm: p_re[imin],
        phi_at_min_deg: wrap_deg(phis[imin]),
        xi0_mm: at0.xi[0].re(),
        engaged: pins
            .iter()
            .enumerate()
            .map(|(j, pin)| (pin.to_string(), crate::thread::intervals(&track.engaged[j], phis)))
            .collect(),
        flat: flat_intervals(&p, &p_re, phis, opts),
        max_tension_n: max_tensions(path, tensions.as_deref()),
        eye_tension_n: eye_tension_range(tensions.as_deref()),
    }
}

/// The angle the thread turns through at every node, per φ: a column per
/// guide between the ends (and whether a pin is engaged), and the capstan
/// tension from them, the eye's as a column (left out of lean runs).
/// Returns the tension after each node at each φ.
fn guide_columns<T: Real>(
    threads: &Threads<T>,
    path: &ThreadPath,
    track: &PathTrack<T>,
    pose: &Pose<T>,
    phis: &[f64],
    opts: &CycleOptions,
    col: &mut impl FnMut(String, Vec<f64>),
) -> Option<Vec<Vec<f64>>> {
    let wraps: Vec<Vec<f64>> = if opts.lean {
        Vec::new()
    } else {
        (0..phis.len()).map(|k| threads.wrap_angles(path, pose, k)).collect()
    };
    let mut pin = 0;
    for i in 1..path.nodes.len().saturating_sub(1) {
        let node = &path.node_names[i];
        if path.pin_span[i].is_some() {
            col(
                format!("{node}_engaged"),
                track.engaged[pin].iter().map(|&e| if e { 1.0 } else { 0.0 }).collect(),
            );
            pin += 1;
        }
        if !opts.lean {
            col(
                format!("{node}_wrap_deg"),
                wraps.iter().map(|w| w[i].to_degrees()).collect(),
            );
        }
    }
    let tensions: Option<Vec<Vec<f64>>> = threads.tension_n.filter(|_| !opts.lean).map(|t0| {
        wraps
            .iter()
            .map(|theta| crate::thread::capstan(theta, &path.friction, t0))
            .collect()
    });
    if let Some(t) = &tensions {
        col(
            "tension_eye_N".into(),
            t.iter().map(|row| *row.last().unwrap_or(&0.0)).collect(),
        );
    }
    tensions
}

/// The highest tension after each node over the cycle.
fn max_tensions(path: &ThreadPath, tensions: Option<&[Vec<f64>]>) -> Vec<(String, f64)> {
    match tensions {
        Some(t) => (0..path.nodes.len())
            .map(|i| {
                (
                    path.node_names[i].clone(),
                    t.iter().map(|row| row[i]).fold(f64::MIN, f64::max),
                )
            })
            .collect(),
        None => Vec::new(),
    }
}

/// The eye's tension range [min, max] over the cycle.
fn eye_tension_range(tensions: Option<&[Vec<f64>]>) -> Option<[f64; 2]> {
    let eye: Vec<f64> = tensions?.iter().map(|row| *row.last().unwrap_or(&0.0)).collect();
    Some([
        eye.iter().cloned().fold(f64::MAX, f64::min),
        eye.iter().cloned().fold(f64::MIN, f64::max),
    ])
}

/// Where P dwells: intervals of at least FLAT_MIN_DEG where |dP/dφ| stays
/// under FLAT_SLOPE_MM_PER_DEG. The slope is exact with analogs; otherwise
/// the central difference on the (periodic) grid, enough to classify
/// dwells.
fn flat_intervals<T: Real>(p: &[T], p_re: &[f64], phis: &[f64], opts: &CycleOptions) -> Vec<crate::thread::Interval> {
    let slope_mm_per_deg: Vec<f64> = if opts.analogs {
        p.iter().map(|x| x.d1() * std::f64::consts::PI / 180.0).collect()
    } else {
        let n = p_re.len();
        (0..n)
            .map(|k| (p_re[(k + 1) % n] - p_re[(k + n - 1) % n]) / (2.0 * opts.step_deg))
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
            "P = xi(phi0) - xi(phi), phi0 = {} deg (seed 000 eq. 2)",
            threads.phi0_deg
        ),
        Convention::Feed { elongation_mm } => format!(
            "P = xi(phi) - xi(phi0) + dP, dP = {elongation_mm} mm, phi0 = {} deg (seed 001 eq. 22-23)",
            threads.phi0_deg
        ),
    };
    if threads.split_up.iter().any(Option::is_some) {
        words += "; needle-eye paths split at B, the eye's top position: P_B = P_eye + S(phi) - S(phi0), S the needle's travel below B \
                  (seed 004 sec. 2.3)";
    }
    words
}
