//! A thread bearing on a one-sided cylindrical guide: a pin (radius 0) or
//! a roller, with its axis through `c` along the unit vector `a`.
//!
//! Seen along the axis, the thread runs from `p` tangent to the circle, along
//! the arc `r·θ`, and tangent again to `q`; along the axis it climbs by the
//! difference of the end heights `Δh`. Unrolling the cylinder and the two
//! tangent planes into one plane makes the whole path a straight line, so
//! the length is `√(L⊥² + Δh²)` with `L⊥ = t_p + r·θ + t_q`, the contact
//! sliding freely along the axis. When the straight thread `p → q` clears
//! the guide on the side it may pass, the guide is disengaged and the length
//! is `|q − p|`; both agree at the switch, so the length is continuous
//! (seed 000 eq. 1: guide G4 engages only part of the cycle).

use num_dual::Dual2_64;

use crate::geometry::V3;
use crate::scalar::Real;

/// The thread around a guide at one position.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PinContact<T: Real> {
    /// Length from `p` to `q`, mm.
    pub length: T,
    /// Whether the thread bears on the guide.
    pub engaged: bool,
    /// Angle the thread turns through on the guide (the capstan angle), rad;
    /// 0 when disengaged.
    pub wrap_rad: f64,
    /// Where the thread meets and leaves the guide (the same point on a
    /// thin pin); `None` when disengaged.
    pub touch: Option<[V3<f64>; 2]>,
}

/// Length of the thread from `p` to `q` past the guide, and whether it bears
/// on it: [`pin_wrap`] without its angle, and without any trigonometry for a
/// thin pin (`r = 0`), whose engaged length is `√((ρp + ρq)² + Δh²)`.
#[inline]
pub fn pin_length<T: Real>(p: V3<T>, q: V3<T>, c: V3<T>, a: V3<T>, r: T, s: f64) -> Option<(T, bool)> {
    if r.re() > 0.0 {
        return pin_wrap(p, q, c, a, r, s).map(|w| (w.length, w.engaged));
    }
    let t = ThinPin::at(p, q, c, a, s);
    if !t.engaged {
        return Some((t.l2.sqrt(), false));
    }
    if t.rho_p2.re() <= 0.0 || t.rho_q2.re() <= 0.0 {
        return None;
    }
    let rho = t.rho_p2.sqrt() + t.rho_q2.sqrt();
    Some(((t.l2 + rho * rho).sqrt(), true))
}

/// A thin pin at one position, before any square root.
struct ThinPin<T: Real> {
    engaged: bool,
    /// |q − p|² when free; Δh² (the climb along the axis) when engaged.
    l2: T,
    /// Squared distances of the ends from the axis (when engaged).
    rho_p2: T,
    rho_q2: T,
}

impl<T: Real> ThinPin<T> {
    /// With w = end − c and h = w·a: ρ² = |w|² − h²; the thread across the
    /// axis is d = q⊥ − p⊥ with |d|² = |q − p|² − Δh², and it passes the
    /// pin on the side given by the sign of (p⊥ × q⊥)·a = (wp × wq)·a.
    #[inline(always)]
    fn at(p: V3<T>, q: V3<T>, c: V3<T>, a: V3<T>, s: f64) -> Self {
        let (wp, wq, e) = (p - c, q - c, q - p);
        let (hp, hq) = (wp.dot(&a), wq.dot(&a));
        let dh = hq - hp;
        let e2 = e.norm_squared();
        let d2 = e2 - dh * dh;
        // The pin stands on the side the thread turns toward: it does not touch.
        let free = d2.re() > 0.0 && s * wp.cross(&wq).dot(&a).re() >= 0.0;
        ThinPin {
            engaged: !free,
            l2: if free { e2 } else { dh * dh },
            rho_p2: wp.norm_squared() - hp * hp,
            rho_q2: wq.norm_squared() - hq * hq,
        }
    }
}

/// Tracks over a cycle of a span's two ends and the pin it bears on.
pub type EndTracks<'a, T> = (&'a [V3<T>], &'a [V3<T>], &'a [V3<T>]);

/// [`pin_length`] of a thin pin (`r = 0`) at every position of a cycle:
/// the ends' tracks `(p, q)` and the pin's `c`, axis `a`, sense `s`. One
/// loop without branches (both lengths computed, one kept), so it runs on
/// the vector unit; the same arithmetic as [`pin_length`], so the same
/// bits. On an end inside the pin, the first failing position's index.
#[inline(always)]
pub fn thin_pin_lengths<T: Real>(
    (tp, tq, tc): EndTracks<'_, T>,
    a: V3<T>,
    s: f64,
    len: &mut Vec<T>,
    engaged: &mut Vec<bool>,
) -> Result<(), usize> {
    let n = tp.len().min(tq.len()).min(tc.len());
    len.clear();
    len.resize(n, T::zero());
    engaged.clear();
    engaged.resize(n, false);
    let (tp, tq, tc, len_, on_) = (&tp[..n], &tq[..n], &tc[..n], &mut len[..n], &mut engaged[..n]);
    let mut bad = false;
    for k in 0..n {
        let t = ThinPin::at(tp[k], tq[k], tc[k], a, s);
        bad |= t.engaged & ((t.rho_p2.re() <= 0.0) | (t.rho_q2.re() <= 0.0));
        // √(Δh² + (ρp + ρq)²) when it bears, else |q − p| (as `pin_length`).
        let rho = t.rho_p2.sqrt() + t.rho_q2.sqrt();
        let engaged_l2 = t.l2 + rho * rho;
        len_[k] = if t.engaged { engaged_l2 } else { t.l2 }.sqrt();
        on_[k] = t.engaged;
    }
    if bad {
        return Err((0..n)
            .position(|k| {
                let t = ThinPin::at(tp[k], tq[k], tc[k], a, s);
                t.engaged && (t.rho_p2.re() <= 0.0 || t.rho_q2.re() <= 0.0)
            })
            .unwrap_or(0));
    }
    Ok(())
}

/// [`pin_length`] of a thin pin (`r = 0`) with its first and second
/// φ-analogs, from the ends' and the pin's positions and analogs
/// (`[x, x′, x″]`) and the fixed axis `a`. In closed form: with
/// P = ρp² = |wp|² − hp², ρp′ = P′/(2ρp), ρp″ = (P″/2 − ρp′²)/ρp (likewise
/// for q), ρ = ρp + ρq and F = Δh² + ρ², the length is L = √F with
/// L′ = F′/(2L), L″ = (F″/2 − L′²)/L; a free thread is a straight piece.
/// The value is bit for bit [`pin_length`]'s.
#[inline(always)]
pub fn thin_pin_jets(
    p: [V3<f64>; 3],
    q: [V3<f64>; 3],
    c: [V3<f64>; 3],
    a: V3<f64>,
    s: f64,
) -> Option<(Dual2_64, bool)> {
    let (l, engaged, inside) = thin_pin_jet(p, q, c, a, s);
    if inside { None } else { Some((l, engaged)) }
}

/// [`thin_pin_jets`] without branches (both lengths computed, one kept),
/// so a cycle's loop of it runs on the vector unit: the length, whether the
/// thread bears, and whether an end lies on the pin's axis (no path).
#[inline(always)]
pub fn thin_pin_jet(p: [V3<f64>; 3], q: [V3<f64>; 3], c: [V3<f64>; 3], a: V3<f64>, s: f64) -> (Dual2_64, bool, bool) {
    let t = ThinPin::at(p[0], q[0], c[0], a, s);
    let free = straight_jet([q[0] - p[0], q[1] - p[1], q[2] - p[2]]);
    // ρ of one end and its analogs, from w = end − c and h = w·a.
    let rho = |e: [V3<f64>; 3]| {
        let w = [e[0] - c[0], e[1] - c[1], e[2] - c[2]];
        let h = [w[0].dot(&a), w[1].dot(&a), w[2].dot(&a)];
        let big_p = w[0].norm_squared() - h[0] * h[0];
        let p1 = 2.0 * (w[0].dot(&w[1]) - h[0] * h[1]);
        let p2 = 2.0 * (w[1].norm_squared() + w[0].dot(&w[2]) - h[1] * h[1] - h[0] * h[2]);
        let r = big_p.sqrt();
        let r1 = p1 / (2.0 * r);
        ([r, r1, (0.5 * p2 - r1 * r1) / r], h)
    };
    let (rp, hp) = rho(p);
    let (rq, hq) = rho(q);
    let r = [rp[0] + rq[0], rp[1] + rq[1], rp[2] + rq[2]];
    let dh = [hq[0] - hp[0], hq[1] - hp[1], hq[2] - hp[2]];
    let f = dh[0] * dh[0] + r[0] * r[0];
    let f1 = 2.0 * (dh[0] * dh[1] + r[0] * r[1]);
    let f2 = 2.0 * (dh[1] * dh[1] + dh[0] * dh[2] + r[1] * r[1] + r[0] * r[2]);
    let l = f.sqrt();
    let l1 = f1 / (2.0 * l);
    let l2 = (0.5 * f2 - l1 * l1) / l;
    let e = t.engaged;
    let pick = |x: f64, y: f64| if e { x } else { y };
    let len = Dual2_64::new(pick(l, free.re), pick(l1, free.v1), pick(l2, free.v2));
    (len, e, e & ((t.rho_p2 <= 0.0) | (t.rho_q2 <= 0.0)))
}

/// The length L = |d| of a straight piece with its analogs, from
/// `[d, d′, d″]`: L′ = d·d′/L, L″ = (|d′|² + d·d″ − L′²)/L. The value is
/// `√(d·d)`, as the thread paths compute it without analogs.
#[inline(always)]
pub fn straight_jet([d, d1, d2]: [V3<f64>; 3]) -> Dual2_64 {
    let l = d.norm_squared().sqrt();
    let inv = 1.0 / l;
    let l1 = d.dot(&d1) * inv;
    Dual2_64::new(l, l1, (d1.norm_squared() + d.dot(&d2) - l1 * l1) * inv)
}

/// Thread from `p` to `q` on a guide (axis through `c` along unit `a`,
/// radius `r`) it may only turn around in the sense `s` about `a` (`+1`
/// counter-clockwise, `−1` clockwise, right-hand rule).
///
/// Returns `None` when an end lies inside the guide (the path is impossible).
#[inline]
pub fn pin_wrap<T: Real>(p: V3<T>, q: V3<T>, c: V3<T>, a: V3<T>, r: T, s: f64) -> Option<PinContact<T>> {
    let (wp, wq) = (p - c, q - c);
    let (hp, hq) = (wp.dot(&a), wq.dot(&a));
    // Projections on the plane across the axis, from the axis.
    let (pp, qq) = (wp - a * hp, wq - a * hq);
    let d = qq - pp;
    // Distance of the axis from the straight thread, positive on its left
    // (counter-clockwise side about a).
    let d_norm = d.norm().re();
    let left = if d_norm > 0.0 {
        pp.cross(&d).dot(&a).re() / d_norm
    } else {
        0.0
    };
    if s * left >= r.re() && d_norm > 0.0 {
        return Some(PinContact {
            length: (q - p).norm(),
            engaged: false,
            wrap_rad: 0.0,
            touch: None,
        });
    }
    let (rho_p2, rho_q2) = (pp.norm_squared(), qq.norm_squared());
    let r2 = r * r;
    if rho_p2.re() <= r2.re() || rho_q2.re() <= r2.re() {
        return None;
    }
    let (rho_p, rho_q) = (rho_p2.sqrt(), rho_q2.sqrt());
    let (t_p, t_q) = ((rho_p2 - r2).sqrt(), (rho_q2 - r2).sqrt());
    // Angle from pp to qq about a, then the arc between the tangent points:
    // θ = s·∠(pp, qq) − acos(r/ρp) − acos(r/ρq), reduced to [−π/2, 3π/2).
    let turn = pp.cross(&qq).dot(&a).angle_of(pp.dot(&qq)) * T::cst(s);
    let mut theta = turn - (r / rho_p).acos() - (r / rho_q).acos();
    let two_pi = T::cst(std::f64::consts::TAU);
    while theta.re() < -std::f64::consts::FRAC_PI_2 {
        theta += two_pi;
    }
    while theta.re() >= 1.5 * std::f64::consts::PI {
        theta -= two_pi;
    }
    if theta.re() < 0.0 {
        // Grazing within rounding: the straight thread.
        theta = T::zero();
    }
    let l_perp = t_p + t_q + r * theta;
    let dh = hq - hp;
    let length = (l_perp * l_perp + dh * dh).sqrt();
    let (lp, len) = (l_perp.re(), length.re());
    let (across, axial) = (lp / len, dh.re() / len);
    let wrap_rad = if r.re() > 0.0 {
        // A helix turns through θ·cos(helix angle).
        theta.re() * across
    } else {
        // A sharp bend: both straight pieces climb with the same slope Δh/L
        // and turn by θ across the axis, so cos ψ = (L⊥/L)²·cos θ + (Δh/L)².
        (across * across * theta.re().cos() + axial * axial)
            .clamp(-1.0, 1.0)
            .acos()
    };
    // Tangent points: turned by ±acos(r/ρ) from the ends' directions, at the
    // heights of the unrolled straight line.
    let (cr, ar, rr) = (c.map(|v| v.re()), a.map(|v| v.re()), r.re());
    let at_angle = |from: V3<f64>, ang: f64, h: f64| {
        let e1 = from.normalize();
        let e2 = ar.cross(&e1);
        cr + (e1 * ang.cos() + e2 * ang.sin()) * rr + ar * h
    };
    let (lp, lq) = (
        if lp > 0.0 { t_p.re() / lp } else { 0.5 },
        if lp > 0.0 { t_q.re() / lp } else { 0.5 },
    );
    let (hpr, dhr) = (hp.re(), dh.re());
    let touch = if rr > 0.0 {
        [
            at_angle(pp.map(|v| v.re()), s * (rr / rho_p.re()).acos(), hpr + dhr * lp),
            at_angle(
                qq.map(|v| v.re()),
                -s * (rr / rho_q.re()).acos(),
                hpr + dhr * (1.0 - lq),
            ),
        ]
    } else {
        let x = cr + ar * (hpr + dhr * rho_p.re() / (rho_p.re() + rho_q.re()));
        [x, x]
    };
    Some(PinContact {
        length,
        engaged: true,
        wrap_rad,
        touch: Some(touch),
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_relative_eq;

    const Z: V3<f64> = V3::new(0.0, 0.0, 1.0);

    #[test]
    fn free_when_the_straight_thread_clears_the_pin() {
        // Thread along y = 5 from x = -10 to 10; pin at the origin, thread
        // turning clockwise (pin on its right): the pin is on its right, free.
        let (p, q) = (V3::new(-10.0, 5.0, 0.0), V3::new(10.0, 5.0, 0.0));
        let w = pin_wrap(p, q, V3::zeros(), Z, 0.0, -1.0).unwrap();
        assert!(!w.engaged);
        assert_relative_eq!(w.length, 20.0);
        // The other sense: the straight thread would cross the pin, it bears on it.
        let w = pin_wrap(p, q, V3::zeros(), Z, 0.0, 1.0).unwrap();
        assert!(w.engaged);
        assert_relative_eq!(w.length, 2.0 * (100.0f64 + 25.0).sqrt(), epsilon = 1e-12);
    }

    #[test]
    fn pin_deflection_and_continuity_at_the_switch() {
        // The straight thread from (-3, -4) to (3, -4) has the pin on its
        // left; a thread that must turn clockwise (pin on its right) goes
        // over the pin: (-3, -4) → (0, 0) → (3, -4).
        let (p, q) = (V3::new(-3.0, -4.0, 0.0), V3::new(3.0, -4.0, 0.0));
        assert!(!pin_wrap(p, q, V3::zeros(), Z, 0.0, 1.0).unwrap().engaged);
        let w = pin_wrap(p, q, V3::zeros(), Z, 0.0, -1.0).unwrap();
        assert!(w.engaged);
        assert_relative_eq!(w.length, 10.0, epsilon = 1e-12);
        // Turning angle: between (3, 4)/5 and (3, -4)/5.
        assert_relative_eq!(w.wrap_rad, (-7.0f64 / 25.0).acos(), epsilon = 1e-12);
        // Just either side of the switch the length is continuous.
        for eps in [1e-9, -1e-9] {
            let (p, q) = (V3::new(-3.0, eps, 0.0), V3::new(3.0, eps, 0.0));
            let w = pin_wrap(p, q, V3::zeros(), Z, 0.0, 1.0).unwrap();
            assert_relative_eq!(w.length, 6.0, epsilon = 1e-8);
        }
    }

    #[test]
    fn contact_slides_along_the_pin_axis() {
        // Ends at different heights: the unrolled path is straight.
        let (p, q) = (V3::new(-3.0, -4.0, 0.0), V3::new(3.0, -4.0, 10.0));
        let w = pin_wrap(p, q, V3::zeros(), Z, 0.0, -1.0).unwrap();
        assert_relative_eq!(w.length, (100.0f64 + 100.0).sqrt(), epsilon = 1e-12);
        // The bend, with both pieces climbing 5 over 10: cos ψ = ½·cos θ + ½.
        let theta = (-7.0f64 / 25.0).acos();
        assert_relative_eq!(w.wrap_rad, (0.5 * theta.cos() + 0.5).acos(), epsilon = 1e-12);
    }

    #[test]
    fn thin_pin_length_agrees_with_the_full_wrap() {
        let a = V3::new(0.3, -0.2, 1.0).normalize();
        for k in 0..50 {
            let t = k as f64 * 0.37;
            let p = V3::new(-10.0 + t.sin(), 3.0 * t.cos(), 2.0 * t);
            let q = V3::new(8.0 * t.cos(), -5.0 + t.sin(), -t);
            let c = V3::new(0.5 * t.sin(), 0.2, 1.0);
            for s in [1.0, -1.0] {
                let full = pin_wrap(p, q, c, a, 0.0, s).unwrap();
                let (len, on) = pin_length(p, q, c, a, 0.0, s).unwrap();
                assert_relative_eq!(len, full.length, epsilon = 1e-12);
                assert_eq!(on, full.engaged);
            }
        }
    }

    #[test]
    fn thin_pin_over_a_cycle_equals_one_position_at_a_time() {
        use num_dual::Dual2_64;
        // Tracks sweeping the thread across the pin, so it engages and releases.
        let a = V3::new(0.1, 0.2, 1.0).normalize();
        let track = |f: &dyn Fn(f64) -> V3<f64>| -> Vec<V3<Dual2_64>> {
            (0..97)
                .map(|k| {
                    let t = k as f64 * 0.065;
                    let (v, d, dd) = (f(t), (f(t + 1e-4) - f(t - 1e-4)) / 2e-4, V3::zeros());
                    V3::new(
                        Dual2_64::new(v.x, d.x, dd.x),
                        Dual2_64::new(v.y, d.y, dd.y),
                        Dual2_64::new(v.z, d.z, dd.z),
                    )
                })
                .collect()
        };
        let tp = track(&|t| V3::new(-10.0, 4.0 * t.sin(), t));
        let tq = track(&|t| V3::new(9.0, 3.0 * t.cos(), -2.0 * t));
        let tc = track(&|t| V3::new(0.3 * t, 0.0, 0.5));
        let ad = a.map(Dual2_64::from_re);
        for s in [1.0, -1.0] {
            let (mut len, mut on) = (Vec::new(), Vec::new());
            thin_pin_lengths((&tp, &tq, &tc), ad, s, &mut len, &mut on).unwrap();
            assert!(
                on.iter().any(|e| *e) && on.iter().any(|e| !*e),
                "the sweep both engages and releases"
            );
            for k in 0..tp.len() {
                let (l, e) = pin_length(tp[k], tq[k], tc[k], ad, Dual2_64::from_re(0.0), s).unwrap();
                assert_eq!(e, on[k]);
                assert_relative_eq!(l.re, len[k].re, epsilon = 1e-12);
                assert_relative_eq!(l.v1, len[k].v1, epsilon = 1e-9);
                assert_relative_eq!(l.v2, len[k].v2, epsilon = 1e-9);
            }
            // Plain numbers take the vectorised square roots.
            let re = |t: &[V3<Dual2_64>]| t.iter().map(|v| v.map(|x| x.re)).collect::<Vec<_>>();
            let (mut lf, mut onf) = (Vec::new(), Vec::new());
            thin_pin_lengths((&re(&tp), &re(&tq), &re(&tc)), a, s, &mut lf, &mut onf).unwrap();
            assert_eq!(onf, on);
            assert!(lf.iter().zip(&len).all(|(x, y)| (x - y.re).abs() < 1e-12));
        }
        // Both ends on the pin's axis: no path; the failing position is named.
        let (mut p_axis, mut q_axis) = (tp.clone(), tq.clone());
        let z = Z.map(Dual2_64::from_re);
        p_axis[40] = tc[40] + z * Dual2_64::from_re(2.0);
        q_axis[40] = tc[40] - z * Dual2_64::from_re(3.0);
        let (mut len, mut on) = (Vec::new(), Vec::new());
        let r = thin_pin_lengths((&p_axis, &q_axis, &tc), z, 1.0, &mut len, &mut on);
        assert_eq!(r, Err(40));
        assert!(pin_length(p_axis[40], q_axis[40], tc[40], z, Dual2_64::from_re(0.0), 1.0).is_none());
    }

    #[test]
    fn thread_wrapping_a_roller_half_way_round() {
        // Roller radius 2 at the origin, thread coming from far left along
        // y = -2 and leaving to the far left along y = +2: a U-turn, θ = π.
        let (p, q) = (V3::new(-10.0, -2.0, 0.0), V3::new(-10.0, 2.0, 0.0));
        let w = pin_wrap(p, q, V3::zeros(), Z, 2.0, 1.0).unwrap();
        assert!(w.engaged);
        assert_relative_eq!(w.length, 20.0 + 2.0 * std::f64::consts::PI, epsilon = 1e-12);
        assert_relative_eq!(w.wrap_rad, std::f64::consts::PI, epsilon = 1e-12);
        // An end inside the roller is impossible.
        assert!(pin_wrap(V3::new(1.0, 0.0, 0.0), q, V3::zeros(), Z, 2.0, 1.0).is_none());
    }
}
