//! A thread feed cam: a convex profile ρ(θ) turning with its shaft, the
//! thread between two guides bearing on it (seed 004 §2.5).
//!
//! Two contact models:
//! - **exact** — the taut thread runs from one guide tangent to the profile,
//!   along it, and tangent again to the other guide (seen along the shaft);
//!   tangent points solve `(c(θ) − p) × c'(θ) = 0`, the arc is integrated
//!   along the profile, and the climb along the shaft is unrolled as for a
//!   pin, so the length is `√(L⊥² + Δh²)`;
//! - **offset** — seed 004's simplification: the contact point is the end of
//!   the profile radius turned by a fixed angle γ from the one facing the
//!   guides, `ξ = |p − A| + |A − q|`, γ = 0.4…0.8 rad by the thesis. With
//!   symmetric guides and γ = 0 this is seed 004 §2.5's `ξ(φ) = 2·|O₂ − A(φ)|`;
//!   with γ ≠ 0 the two pieces differ and the seed's doubled distance is an
//!   approximation of this sum.

use nalgebra::ComplexField;

use crate::geometry::{V2, V3};
use crate::numeric::PeriodicCubic;
use crate::scalar::Real;

/// The shape of a polar profile ρ(θ), θ in radians in the cam's own frame.
#[derive(Debug, Clone, PartialEq)]
pub enum Shape {
    /// A disc of radius `r` whose centre is `e` from the shaft along θ = 0:
    /// `ρ(θ) = e cos θ + √(r² − e² sin² θ)`.
    Eccentric { r: f64, e: f64 },
    /// A periodic cubic spline through `(θ_i, ρ_i)`, θ increasing over one turn.
    Spline(PeriodicCubic),
}

/// A cam profile with its points sampled once (the starting guesses of the
/// exact contact), so nothing is recomputed per φ.
#[derive(Debug, Clone, PartialEq)]
pub struct Profile {
    pub shape: Shape,
    /// (θ, point) every degree.
    samples: Vec<(f64, V2<f64>)>,
}

impl Profile {
    fn new(shape: Shape) -> Profile {
        let mut p = Profile {
            shape,
            samples: Vec::new(),
        };
        p.samples = (0..N_SAMPLES)
            .map(|k| {
                let th = k as f64 * std::f64::consts::TAU / N_SAMPLES as f64;
                (th, p.point_f64(th).0)
            })
            .collect();
        p
    }

    /// A disc of radius `r` set `e` off the shaft toward θ = 0.
    pub fn disc(r: f64, e: f64) -> Profile {
        Profile::new(Shape::Eccentric { r, e })
    }

    /// A periodic cubic spline through the points (θ in rad, strictly
    /// increasing within one turn; ρ in mm).
    pub fn spline(theta: &[f64], rho: &[f64]) -> Profile {
        Profile::new(Shape::Spline(PeriodicCubic::new(theta, rho, std::f64::consts::TAU)))
    }

    /// ρ(θ), generic so θ may carry derivatives.
    pub fn rho<T: Real>(&self, theta: T) -> T {
        match &self.shape {
            Shape::Eccentric { r, e } => {
                let (s, c) = theta.sin_cos();
                c * T::cst(*e) + (T::cst(r * r) - s * s * T::cst(e * e)).sqrt()
            }
            Shape::Spline(spline) => spline.eval(theta),
        }
    }

    /// The profile point at θ in the cam's frame, with its first and second
    /// derivatives with respect to θ (by dual numbers through [`Self::rho`]).
    fn point_f64(&self, theta: f64) -> (V2<f64>, V2<f64>, V2<f64>) {
        let d = num_dual::Dual2_64::new(theta, 1.0, 0.0);
        let r = self.rho(d);
        let (s, c) = d.sin_cos();
        let (x, y) = (r * c, r * s);
        (V2::new(x.re, y.re), V2::new(x.v1, y.v1), V2::new(x.v2, y.v2))
    }

    /// Smallest curvature numerator `ρ² + 2ρ'² − ρρ''` over the turn: positive
    /// for a convex profile.
    pub fn convexity(&self) -> f64 {
        (0..720)
            .map(|k| {
                let d = num_dual::Dual2_64::new(k as f64 * std::f64::consts::TAU / 720.0, 1.0, 0.0);
                let r = self.rho(d);
                r.re * r.re + 2.0 * r.v1 * r.v1 - r.re * r.v2
            })
            .fold(f64::MAX, f64::min)
    }

    /// Smallest radius over the turn.
    pub fn min_radius(&self) -> f64 {
        (0..720)
            .map(|k| self.rho(k as f64 * std::f64::consts::TAU / 720.0))
            .fold(f64::MAX, f64::min)
    }
}

/// Where a cam is at one φ: its centre, the unit vectors of its frame
/// (`u` toward profile angle 0, `v = w × u`) and the shaft axis `w`.
#[derive(Debug, Clone, Copy)]
pub struct CamPlacement<T: Real> {
    pub center: V3<T>,
    pub u: V3<T>,
    pub v: V3<T>,
    pub w: V3<T>,
}

impl<T: Real> CamPlacement<T> {
    /// From the shaft centre, a marker point turning with the cam (its
    /// direction is profile angle 0) and the shaft axis.
    pub fn new(center: V3<T>, marker: V3<T>, w: V3<T>) -> Option<Self> {
        let m = marker - center;
        let u = m - w * m.dot(&w);
        let n = u.norm();
        if n.re() <= 0.0 {
            return None;
        }
        let u = u / n;
        Some(CamPlacement {
            center,
            u,
            v: w.cross(&u),
            w,
        })
    }

    /// Coordinates of a world point in the cam's frame: (in-plane, height).
    fn local(&self, p: V3<T>) -> (V2<T>, T) {
        let d = p - self.center;
        (V2::new(d.dot(&self.u), d.dot(&self.v)), d.dot(&self.w))
    }
}

/// The thread on a cam at one φ.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CamContact<T: Real> {
    pub length: T,
    pub engaged: bool,
    /// Angle the thread turns through on the cam, rad.
    pub wrap_rad: f64,
    /// Where the thread meets and leaves the cam; `None` when it does not bear.
    pub touch: Option<[V3<f64>; 2]>,
}

/// Seed 004's contact model: the thread from `p` to `q` through the end of
/// the profile radius at the profile angle facing the guides (the bisector
/// of their directions from the centre) turned by `gamma` (rad, in the
/// cam's positive sense).
pub fn offset_contact<T: Real>(
    profile: &Profile,
    at: &CamPlacement<T>,
    p: V3<T>,
    q: V3<T>,
    gamma: f64,
) -> Option<CamContact<T>> {
    let (pl, _) = at.local(p);
    let (ql, _) = at.local(q);
    let (np, nq) = (pl.norm(), ql.norm());
    if np.re() <= 0.0 || nq.re() <= 0.0 {
        return None;
    }
    let bis = pl / np + ql / nq;
    // Guides facing each other through the shaft: no direction faces them.
    if bis.norm().re() < 1e-9 {
        return None;
    }
    let beta = bis.y.angle_of(bis.x) + T::cst(gamma);
    let rho = profile.rho(beta);
    let (s, c) = beta.sin_cos();
    let a = at.center + (at.u * c + at.v * s) * rho;
    let (u_in, u_out) = ((a - p).map(|x| x.re()), (q - a).map(|x| x.re()));
    let turn = (u_in.normalize().dot(&u_out.normalize())).clamp(-1.0, 1.0).acos();
    let ar = a.map(|x| x.re());
    Some(CamContact {
        length: (a - p).norm() + (q - a).norm(),
        engaged: true,
        wrap_rad: turn,
        touch: Some([ar, ar]),
    })
}

/// Profile samples per turn.
const N_SAMPLES: usize = 360;

/// The exact taut-thread wrap over a convex profile from `p` to `q`,
/// turning in the sense `s` about the shaft axis (`+1` counter-clockwise,
/// i.e. the cam on the thread's left). Free when the straight thread misses
/// the profile on that side. `None` when an end lies inside the profile.
pub fn exact_contact<T: Real>(
    profile: &Profile,
    at: &CamPlacement<T>,
    p: V3<T>,
    q: V3<T>,
    s: f64,
) -> Option<CamContact<T>> {
    let (pl, hp) = at.local(p);
    let (ql, hq) = at.local(q);
    let (pr, qr) = (pl.map(|x| x.re()), ql.map(|x| x.re()));
    // Ends must lie outside the profile.
    for e in [pr, qr] {
        if e.norm() <= profile.rho(e.y.atan2(e.x)) {
            return None;
        }
    }
    // Does the straight thread keep the whole profile on its `s` side?
    let d = qr - pr;
    let samples = &profile.samples;
    let side = |pt: V2<f64>| s * (d.x * (pt.y - pr.y) - d.y * (pt.x - pr.x));
    let min_side = samples.iter().map(|(_, pt)| side(*pt)).fold(f64::MAX, f64::min);
    if min_side >= 0.0 {
        return Some(CamContact {
            length: (q - p).norm(),
            engaged: false,
            wrap_rad: 0.0,
            touch: None,
        });
    }
    // Tangent points: from p, the profile point whose direction is most
    // clockwise (for s = +1) as seen from p; toward q, the most
    // counter-clockwise as seen from q. Start from the samples, refine by
    // Newton on f(θ) = (c(θ) − e) × c'(θ).
    let extreme = |e: V2<f64>, sign: f64| {
        let base = (-e).y.atan2(-e.x);
        samples
            .iter()
            .map(|(th, pt)| {
                let a = (pt.y - e.y).atan2(pt.x - e.x) - base;
                let a = (a + std::f64::consts::PI).rem_euclid(std::f64::consts::TAU) - std::f64::consts::PI;
                (*th, sign * a)
            })
            .min_by(|x, y| x.1.total_cmp(&y.1))
            .map(|(th, _)| th)
            .unwrap_or(0.0)
    };
    let tangent = |e: V2<T>, th0: f64| -> T {
        let er = e.map(|x| x.re());
        let mut th = th0;
        for _ in 0..30 {
            let (c, c1, c2) = profile.point_f64(th);
            let f = (c.x - er.x) * c1.y - (c.y - er.y) * c1.x;
            let df = (c.x - er.x) * c2.y - (c.y - er.y) * c2.x;
            if df == 0.0 {
                break;
            }
            let step = f / df;
            th -= step;
            if step.abs() < 1e-14 {
                break;
            }
        }
        // Exact derivatives: two Newton steps in T with the real slope.
        let (c, _, c2) = profile.point_f64(th);
        let df = (c.x - er.x) * c2.y - (c.y - er.y) * c2.x;
        let mut t = T::cst(th);
        for _ in 0..2 {
            let (cp, c1) = point_t(profile, t);
            let f = (cp.x - e.x) * c1.y - (cp.y - e.y) * c1.x;
            t -= f / T::cst(df);
        }
        t
    };
    let th_p = tangent(pl, extreme(pr, s));
    let th_q = tangent(ql, extreme(qr, -s));
    // Arc from θp to θq in the sense s.
    let tau = std::f64::consts::TAU;
    let mut span = (th_q - th_p) * T::cst(s);
    while span.re() < 0.0 {
        span += T::cst(tau);
    }
    while span.re() >= tau {
        span -= T::cst(tau);
    }
    let arc = arc_length(profile, th_p, span * T::cst(s));
    let (cp, c1p) = point_t(profile, th_p);
    let (cq, c1q) = point_t(profile, th_p + span * T::cst(s));
    let l_perp = (cp - pl).norm() + arc + (ql - cq).norm();
    let dh = hq - hp;
    let length = (l_perp * l_perp + dh * dh).sqrt();
    // The thread turns by the change of the tangent direction along the arc.
    let (t_in, t_out) = (c1p.map(|x| x.re()) * s, c1q.map(|x| x.re()) * s);
    let turn = (t_in.normalize().dot(&t_out.normalize())).clamp(-1.0, 1.0).acos();
    let turn = if span.re() > std::f64::consts::PI {
        tau - turn
    } else {
        turn
    };
    // Tangent points in the world, at the heights of the unrolled line.
    let (lp_re, len_re) = (l_perp.re(), length.re());
    let world = |c: V2<T>, frac: f64| {
        let (c, h) = (c.map(|x| x.re()), hp.re() + dh.re() * frac);
        at.center.map(|x| x.re()) + at.u.map(|x| x.re()) * c.x + at.v.map(|x| x.re()) * c.y + at.w.map(|x| x.re()) * h
    };
    let (t_in, t_out) = ((cp - pl).norm().re(), (ql - cq).norm().re());
    let touch = [world(cp, t_in / lp_re), world(cq, 1.0 - t_out / lp_re)];
    Some(CamContact {
        length,
        engaged: true,
        wrap_rad: turn * lp_re / len_re,
        touch: Some(touch),
    })
}

/// Profile point and its θ-derivative at a dual angle.
fn point_t<T: Real>(profile: &Profile, th: T) -> (V2<T>, V2<T>) {
    // c(θ) = ρ(θ)(cos θ, sin θ); c'(θ) = ρ'(cos, sin) + ρ(−sin, cos), with ρ'
    // from the profile's closed form (`rho_prime`).
    let rho = profile.rho(th);
    let rho1 = rho_prime(profile, th);
    let (s, c) = th.sin_cos();
    (
        V2::new(rho * c, rho * s),
        V2::new(rho1 * c - rho * s, rho1 * s + rho * c),
    )
}

/// ρ'(θ) for a dual θ, from the profile's closed form.
fn rho_prime<T: Real>(profile: &Profile, th: T) -> T {
    match &profile.shape {
        Shape::Eccentric { r, e } => {
            let (s, c) = th.sin_cos();
            let root = (T::cst(r * r) - s * s * T::cst(e * e)).sqrt();
            -s * T::cst(*e) - s * c * T::cst(e * e) / root
        }
        Shape::Spline(spline) => spline.slope(th),
    }
}

/// Arc length of the profile from `th0` over the signed angle `dth`:
/// composite 5-point Gauss–Legendre on |c'(θ)| = √(ρ² + ρ'²).
fn arc_length<T: Real>(profile: &Profile, th0: T, dth: T) -> T {
    const X: [f64; 5] = [
        0.0,
        -0.538_469_310_105_683,
        0.538_469_310_105_683,
        -0.906_179_845_938_664,
        0.906_179_845_938_664,
    ];
    const W: [f64; 5] = [
        0.568_888_888_888_889,
        0.478_628_670_499_366,
        0.478_628_670_499_366,
        0.236_926_885_056_189,
        0.236_926_885_056_189,
    ];
    let pieces = ((dth.re().abs() / (std::f64::consts::PI / 24.0)).ceil() as usize).max(1);
    let h = dth / T::cst(pieces as f64);
    let mut sum = T::zero();
    for j in 0..pieces {
        let mid = th0 + h * T::cst(j as f64 + 0.5);
        for (x, w) in X.iter().zip(W) {
            let th = mid + h * T::cst(0.5 * x);
            let (r, r1) = (profile.rho(th), rho_prime(profile, th));
            sum += (r * r + r1 * r1).sqrt() * T::cst(w);
        }
    }
    (sum * h * T::cst(0.5)).abs()
}

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_relative_eq;

    fn at(angle: f64) -> CamPlacement<f64> {
        CamPlacement {
            center: V3::zeros(),
            u: V3::new(angle.cos(), angle.sin(), 0.0),
            v: V3::new(-angle.sin(), angle.cos(), 0.0),
            w: V3::z(),
        }
    }

    #[test]
    fn eccentric_disc_radius() {
        let p = Profile::disc(10.0, 3.0);
        assert_relative_eq!(p.rho(0.0), 13.0, epsilon = 1e-12);
        assert_relative_eq!(p.rho(std::f64::consts::PI), 7.0, epsilon = 1e-12);
        assert_relative_eq!(
            p.rho(std::f64::consts::FRAC_PI_2),
            (100.0f64 - 9.0).sqrt(),
            epsilon = 1e-12
        );
        assert!(p.convexity() > 0.0);
    }

    #[test]
    fn spline_interpolates_and_closes_smoothly() {
        let th: Vec<f64> = (0..12).map(|k| k as f64 * std::f64::consts::TAU / 12.0).collect();
        let rho: Vec<f64> = th.iter().map(|t| 20.0 + 3.0 * t.cos()).collect();
        let p = Profile::spline(&th, &rho);
        for (t, r) in th.iter().zip(&rho) {
            assert_relative_eq!(p.rho(*t), *r, epsilon = 1e-12);
        }
        // Close to the smooth function between the knots, and periodic.
        assert!((p.rho(0.3) - (20.0 + 3.0 * 0.3f64.cos())).abs() < 2e-3);
        assert_relative_eq!(p.rho(0.3), p.rho(0.3 + std::f64::consts::TAU), epsilon = 1e-12);
        assert_relative_eq!(p.rho(-0.3), p.rho(std::f64::consts::TAU - 0.3), epsilon = 1e-12);
    }

    #[test]
    fn exact_wrap_around_a_centred_disc_is_the_roller_formula() {
        // A disc of radius 5 centred on the shaft: the cam's turning does not
        // matter, and the wrap equals a roller's (tangents plus arc).
        let prof = Profile::disc(5.0, 0.0);
        let (p, q) = (V3::new(-20.0, -5.0, 0.0), V3::new(-20.0, 5.0, 0.0));
        for angle in [0.0, 1.0, 2.5] {
            let c = exact_contact(&prof, &at(angle), p, q, 1.0).unwrap();
            assert!(c.engaged);
            assert_relative_eq!(c.length, 40.0 + 5.0 * std::f64::consts::PI, epsilon = 1e-9);
            let r = crate::thread::wrap::pin_wrap(p, q, V3::zeros(), V3::z(), 5.0, 1.0).unwrap();
            assert_relative_eq!(c.length, r.length, epsilon = 1e-9);
            assert_relative_eq!(c.wrap_rad, r.wrap_rad, epsilon = 1e-6);
        }
        // The other sense: the straight thread (x = −20) misses the disc.
        assert!(!exact_contact(&prof, &at(0.0), p, q, -1.0).unwrap().engaged);
    }

    #[test]
    fn exact_wrap_around_an_eccentric_disc() {
        // A disc of radius 6 whose centre sits 2 mm from the shaft at angle
        // `a`: the wrap equals a roller's around the disc's own centre.
        let prof = Profile::disc(6.0, 2.0);
        let (p, q) = (V3::new(-30.0, -4.0, 0.0), V3::new(25.0, -9.0, 3.0));
        for a in [0.0f64, 0.7, 2.0, 4.0] {
            let disc = V3::new(2.0 * a.cos(), 2.0 * a.sin(), 0.0);
            let want = crate::thread::wrap::pin_wrap(p, q, disc, V3::z(), 6.0, -1.0).unwrap();
            let got = exact_contact(&prof, &at(a), p, q, -1.0).unwrap();
            assert_eq!(got.engaged, want.engaged);
            assert_relative_eq!(got.length, want.length, epsilon = 1e-9);
        }
    }

    #[test]
    fn exact_wrap_analogs_are_derivatives() {
        use num_dual::Dual2_64;
        // The disc turning with φ; its analogs against central differences.
        let prof = Profile::disc(6.0, 2.0);
        let len = |phi: Dual2_64| {
            let at = CamPlacement {
                center: V3::zeros(),
                u: V3::new(phi.cos(), phi.sin(), Dual2_64::from_re(0.0)),
                v: V3::new(-phi.sin(), phi.cos(), Dual2_64::from_re(0.0)),
                w: V3::z().map(Dual2_64::from_re),
            };
            let p = V3::new(-30.0, -4.0, 0.0).map(Dual2_64::from_re);
            let q = V3::new(25.0, -9.0, 3.0).map(Dual2_64::from_re);
            exact_contact(&prof, &at, p, q, -1.0).unwrap().length
        };
        for phi in [0.3, 1.7, 4.0] {
            let d = len(Dual2_64::new(phi, 1.0, 0.0));
            let h = 1e-4;
            let f = |x: f64| len(Dual2_64::from_re(x)).re;
            assert_relative_eq!(d.v1, (f(phi + h) - f(phi - h)) / (2.0 * h), epsilon = 1e-7);
            assert_relative_eq!(d.v2, (f(phi + h) - 2.0 * f(phi) + f(phi - h)) / (h * h), epsilon = 1e-4);
        }
    }

    #[test]
    fn offset_model_with_symmetric_guides_is_twice_the_distance() {
        let prof = Profile::disc(10.0, 3.0);
        let o2 = V3::new(-20.0, 30.0, 0.0);
        let o2s = V3::new(20.0, 30.0, 0.0);
        // Facing the guides (+y), turned by γ = 0.5 rad.
        let c = offset_contact(&prof, &at(0.0), o2, o2s, 0.5).unwrap();
        let beta = std::f64::consts::FRAC_PI_2 + 0.5;
        let a = V3::new(beta.cos(), beta.sin(), 0.0) * prof.rho(beta);
        assert_relative_eq!(c.length, (o2 - a).norm() + (o2s - a).norm(), epsilon = 1e-12);
        let c0 = offset_contact(&prof, &at(0.0), o2, o2s, 0.0).unwrap();
        let a0 = V3::new(0.0, prof.rho(std::f64::consts::FRAC_PI_2), 0.0);
        assert_relative_eq!(c0.length, 2.0 * (o2 - a0).norm(), epsilon = 1e-12);
    }
}
