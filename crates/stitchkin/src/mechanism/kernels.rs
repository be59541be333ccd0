//! Whole-cycle loops of the groups that cannot fail at any φ (offsets,
//! rigid points on a link of known length, cranks on a fixed shaft),
//! written without branches and compiled per vector unit
//! ([`crate::scalar::widest_fn!`]), so 4 or 8 positions go through each
//! instruction. The groups that can fail (dyads, guides) keep their checked
//! loops in [`super::Mechanism::solve`].

use super::{Phi, line, rigid, rssr};
use crate::geometry::{PlaneMap, V3};
use crate::scalar::{Real, widest_fn};

widest_fn! {
    /// `o[k] = a[k] + by` for every k.
    pub(super) fn offset<T: Real>(o: &mut [V3<T>], a: &[V3<T>], by: V3<T>) => offset_in
}

#[inline(always)]
fn offset_in<T: Real>(o: &mut [V3<T>], a: &[V3<T>], by: V3<T>) {
    for (o, a) in o.iter_mut().zip(a) {
        *o = *a + by;
    }
}

widest_fn! {
    /// A rigid point on the link `a → b` of known length, in the plane
    /// `pl`, `lift` above it (see [`rigid::rigid_point_on_link`]).
    pub(super) fn rigid_on_link<T: Real, P: PlaneMap<T>>(o: &mut [V3<T>], a: &[V3<T>], b: &[V3<T>], pl: P, dcl: T, dsl: T, lift: T) => rigid_on_link_in
}

#[inline(always)]
fn rigid_on_link_in<T: Real, P: PlaneMap<T>>(
    o: &mut [V3<T>],
    a: &[V3<T>],
    b: &[V3<T>],
    pl: P,
    dcl: T,
    dsl: T,
    lift: T,
) {
    for ((o, a), b) in o.iter_mut().zip(a).zip(b) {
        *o = pl.lift(rigid::rigid_point_on_link(pl.project(a), pl.project(b), dcl, dsl), lift);
    }
}

widest_fn! {
    /// A crank on a fixed shaft along z through `c0`: `o = c0 + cos φ·(cx, cy) + sin φ·(sx, sy)`.
    pub(super) fn planar_crank<T: Real>(o: &mut [V3<T>], phis: &[Phi<T>], c0: V3<T>, cs: [T; 4]) => planar_crank_in
}

#[inline(always)]
fn planar_crank_in<T: Real>(o: &mut [V3<T>], phis: &[Phi<T>], c0: V3<T>, [cx, cy, sx, sy]: [T; 4]) {
    for (o, phi) in o.iter_mut().zip(phis) {
        let (c, s) = (phi.cos, phi.sin);
        *o = V3::new(
            c0.x + c.times_k(cx) + s.times_k(sx),
            c0.y + c.times_k(cy) + s.times_k(sy),
            c0.z,
        );
    }
}

widest_fn! {
    /// A crank on a fixed shaft through `c0`, at angle φ + ph:
    /// `o = c0 + cos(φ + ph)·ru + sin(φ + ph)·rv`.
    pub(super) fn crank<T: Real>(o: &mut [V3<T>], phis: &[Phi<T>], c0: V3<T>, r: [V3<T>; 2], ph: [T; 2]) => crank_in
}

#[inline(always)]
fn crank_in<T: Real>(o: &mut [V3<T>], phis: &[Phi<T>], c0: V3<T>, [ru, rv]: [V3<T>; 2], [cos_ph, sin_ph]: [T; 2]) {
    for (o, phi) in o.iter_mut().zip(phis) {
        let (c, s) = (phi.cos * cos_ph - phi.sin * sin_ph, phi.sin * cos_ph + phi.cos * sin_ph);
        *o = c0 + ru.map(|x| c.times_k(x)) + rv.map(|x| s.times_k(x));
    }
}

widest_fn! {
    /// RSSR ball ends for every position of the driving point `a`
    /// ([`rssr::rssr_unchecked`]); `false` when some position has none
    /// (the caller then finds which, with its message).
    pub(super) fn rssr<T: Real>(o: &mut [V3<T>], a: &[V3<T>], rod: &rssr::RockerRod<T>, sign: f64) -> bool => rssr_in
}

#[inline(always)]
fn rssr_in<T: Real>(o: &mut [V3<T>], a: &[V3<T>], rod: &rssr::RockerRod<T>, sign: f64) -> bool {
    let mut ok = true;
    for (o, a) in o.iter_mut().zip(a) {
        let (b, fine) = rssr::rssr_unchecked(rod, *a, sign);
        *o = b;
        ok &= fine;
    }
    ok
}

widest_fn! {
    /// Points on a guide of fixed direction `u` through `h[k]` at `l` from
    /// `a[k]` ([`line::point_on_line_unchecked`]); `false` when some
    /// position has none.
    pub(super) fn point_on_line<T: Real>(o: &mut [V3<T>], h: &[V3<T>], a: &[V3<T>], u: V3<T>, l_sq: T, sign: f64) -> bool => point_on_line_in
}

#[inline(always)]
fn point_on_line_in<T: Real>(o: &mut [V3<T>], h: &[V3<T>], a: &[V3<T>], u: V3<T>, l_sq: T, sign: f64) -> bool {
    let mut ok = true;
    for ((o, h), a) in o.iter_mut().zip(h).zip(a) {
        let (p, fine) = line::point_on_line_unchecked(*h, u, *a, l_sq, sign);
        *o = p;
        ok &= fine;
    }
    ok
}
