//! Thread paths at one φ: where each path touches its guides, the arcs it
//! lays on rollers and cams, and the polylines drawn (morphing smoothly in
//! an animation).

use crate::error::Error;
use crate::eval::path_error;
use crate::geometry::V3;
use crate::thread::{CamModel, PathError, Span, Threads, cam, wrap};

/// One one-sided guide (pin or cam) of a path at one φ.
#[derive(Debug, Clone, Copy)]
pub(super) struct GuideState {
    pub(super) engaged: bool,
}

/// A thread path at one φ: the points the thread runs through, per node
/// (`None`: a free one-sided guide), and the state of each guide node.
#[derive(Debug, Clone)]
pub(super) struct PathFrame {
    pub(super) pieces: Vec<Option<Vec<V3<f64>>>>,
    pub(super) guides: Vec<Option<GuideState>>,
}

/// Samples of an arc about the axis `a` through `c` from `t0` to `t1`,
/// turning in the sense `s`, heights interpolated: the thread on a roller.
fn roller_arc(c: V3<f64>, a: V3<f64>, r: f64, s: f64, t0: V3<f64>, t1: V3<f64>) -> Vec<V3<f64>> {
    let (h0, h1) = ((t0 - c).dot(&a), (t1 - c).dot(&a));
    let d0 = (t0 - c) - a * h0;
    if d0.norm() <= 0.0 || r <= 0.0 {
        return vec![t0, t1];
    }
    let e1 = d0 / d0.norm();
    let e2 = a.cross(&e1);
    let d1 = (t1 - c) - a * h1;
    let ang = d1.dot(&e2).atan2(d1.dot(&e1));
    let sweep = if s > 0.0 {
        ang.rem_euclid(std::f64::consts::TAU)
    } else {
        -(-ang).rem_euclid(std::f64::consts::TAU)
    };
    let k = (sweep.abs() / 10f64.to_radians()).ceil().max(1.0) as usize;
    (0..=k)
        .map(|j| {
            let t = j as f64 / k as f64;
            let th = sweep * t;
            c + (e1 * th.cos() + e2 * th.sin()) * r + a * (h0 + (h1 - h0) * t)
        })
        .collect()
}

/// The thread on a cam from `t0` to `t1` along the profile in the sense `s`.
fn cam_arc(profile: &cam::Profile, at: &cam::CamPlacement<f64>, s: f64, t0: V3<f64>, t1: V3<f64>) -> Vec<V3<f64>> {
    let local = |p: V3<f64>| {
        let d = p - at.center;
        (d.dot(&at.v).atan2(d.dot(&at.u)), d.dot(&at.w))
    };
    let ((a0, h0), (a1, h1)) = (local(t0), local(t1));
    let sweep = if s > 0.0 {
        (a1 - a0).rem_euclid(std::f64::consts::TAU)
    } else {
        -(a0 - a1).rem_euclid(std::f64::consts::TAU)
    };
    let k = (sweep.abs() / 6f64.to_radians()).ceil().max(1.0) as usize;
    let mut out = vec![t0];
    for j in 1..k {
        let t = j as f64 / k as f64;
        let th = a0 + sweep * t;
        let rho = profile.rho(th);
        out.push(at.center + (at.u * th.cos() + at.v * th.sin()) * rho + at.w * (h0 + (h1 - h0) * t));
    }
    out.push(t1);
    out
}

/// Every path of `threads` at one φ (`p`: the slots' positions).
pub(super) fn thread_frame(threads: &Threads<f64>, p: &[V3<f64>], phi_deg: f64) -> Result<Vec<PathFrame>, Error> {
    let mut out = Vec::with_capacity(threads.paths.len());
    for path in threads.paths.iter() {
        let m = path.nodes.len();
        let mut pieces = Vec::with_capacity(m);
        let mut guides = Vec::with_capacity(m);
        for i in 0..m {
            let Some(s) = path.pin_span[i] else {
                pieces.push(Some(vec![p[path.nodes[i]]]));
                guides.push(None);
                continue;
            };
            let (a, b) = (p[path.nodes[i - 1]], p[path.nodes[i + 1]]);
            let inside = |message: String| {
                path_error(
                    PathError {
                        path: path.name.clone(),
                        k: 0,
                        message,
                    },
                    phi_deg,
                )
            };
            let piece = match &threads.spans[s] {
                Span::Pin {
                    c,
                    axis,
                    r,
                    sense,
                    name,
                    ..
                } => {
                    let w = wrap::pin_wrap(a, b, p[*c], *axis, *r, *sense)
                        .ok_or_else(|| inside(format!("a thread end lies inside the guide at `{name}`")))?;
                    match w.touch {
                        Some([t0, t1]) if w.engaged => Some(if *r > 0.0 {
                            roller_arc(p[*c], *axis, *r, *sense, t0, t1)
                        } else {
                            vec![t0, t1]
                        }),
                        _ => None,
                    }
                }
                Span::Cam { cam: ci, contact, .. } => {
                    let c = &threads.cams[*ci];
                    let no_lay = || inside(format!("the thread cannot be laid on cam `{}`", c.name));
                    let at = cam::CamPlacement::new(p[c.center], p[c.marker], c.axis).ok_or_else(no_lay)?;
                    let (w, sense) = match contact {
                        CamModel::Exact { sense } => (cam::exact_contact(&c.profile, &at, a, b, *sense), *sense),
                        CamModel::Offset { gamma_rad } => (cam::offset_contact(&c.profile, &at, a, b, *gamma_rad), 1.0),
                    };
                    let w = w.ok_or_else(no_lay)?;
                    match (w.touch, contact) {
                        (Some([t0, t1]), CamModel::Exact { .. }) if w.engaged => {
                            Some(cam_arc(&c.profile, &at, sense, t0, t1))
                        }
                        (Some([t0, _]), CamModel::Offset { .. }) => Some(vec![t0]),
                        _ => None,
                    }
                }
                Span::Straight { .. } => Some(vec![p[path.nodes[i]]]),
            };
            guides.push(Some(GuideState {
                engaged: piece.is_some(),
            }));
            pieces.push(piece.map(dedup));
        }
        out.push(PathFrame { pieces, guides });
    }
    Ok(out)
}

/// Consecutive coincident points once.
fn dedup(v: Vec<V3<f64>>) -> Vec<V3<f64>> {
    let mut out: Vec<V3<f64>> = Vec::with_capacity(v.len());
    for p in v {
        if out.last().is_none_or(|q| (p - q).norm() > 1e-9) {
            out.push(p);
        }
    }
    out
}

/// The polyline of a path at each frame. Static: the points the thread
/// touches. Animated: a free guide gets a point on the straight thread
/// (its nearest) and every node as many points in every frame, so the
/// polyline morphs smoothly.
pub(super) fn thread_polylines(frames: &[PathFrame], guide_pts: &[V3<f64>], animate: bool) -> Vec<Vec<V3<f64>>> {
    if !animate {
        return frames
            .iter()
            .map(|f| f.pieces.iter().flatten().flatten().copied().collect())
            .collect();
    }
    let m = frames.first().map_or(0, |f| f.pieces.len());
    let mut filled: Vec<Vec<Vec<V3<f64>>>> = frames
        .iter()
        .enumerate()
        .map(|(k, f)| {
            (0..m)
                .map(|i| match &f.pieces[i] {
                    Some(v) => v.clone(),
                    None => {
                        let before = f.pieces[..i]
                            .iter()
                            .rev()
                            .flatten()
                            .next()
                            .and_then(|v| v.last())
                            .copied();
                        let after = f.pieces[i + 1..]
                            .iter()
                            .flatten()
                            .next()
                            .and_then(|v| v.first())
                            .copied();
                        match (before, after) {
                            (Some(a), Some(b)) => {
                                let d = b - a;
                                let t = if d.norm_squared() > 0.0 {
                                    ((guide_pts[k * m + i] - a).dot(&d) / d.norm_squared()).clamp(0.0, 1.0)
                                } else {
                                    0.0
                                };
                                vec![a + d * t]
                            }
                            _ => Vec::new(),
                        }
                    }
                })
                .collect()
        })
        .collect();
    for i in 0..m {
        let most = filled.iter().map(|f| f[i].len()).max().unwrap_or(0);
        for f in filled.iter_mut() {
            if let Some(&last) = f[i].last() {
                while f[i].len() < most {
                    f[i].push(last);
                }
            }
        }
    }
    filled.into_iter().map(|f| f.into_iter().flatten().collect()).collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_relative_eq;

    #[test]
    fn arcs_run_the_wrap_sense() {
        // A roller of radius 1 about z through the origin, thread from
        // (1, 0) counter-clockwise to (0, 1): a quarter turn.
        let arc = roller_arc(
            V3::zeros(),
            V3::z(),
            1.0,
            1.0,
            V3::new(1.0, 0.0, 0.0),
            V3::new(0.0, 1.0, 2.0),
        );
        assert!(arc.len() >= 3);
        for p in &arc {
            assert_relative_eq!(p.xy().norm(), 1.0, epsilon = 1e-12);
            assert!(p.x >= -1e-12 && p.y >= -1e-12);
        }
        assert_relative_eq!(arc.last().unwrap().z, 2.0, epsilon = 1e-12);
        // Clockwise the other way round: three quarters.
        let cw = roller_arc(
            V3::zeros(),
            V3::z(),
            1.0,
            -1.0,
            V3::new(1.0, 0.0, 0.0),
            V3::new(0.0, 1.0, 0.0),
        );
        assert!(cw.iter().any(|p| p.x < -0.9));
    }
}
