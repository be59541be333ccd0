//! The needle thread whose loop one looper catches: 401, 406/407 per needle,
//! 504 (`docs/stitch-formation.md` §4.1, §4.4, §5.1, §5.2).
//!
//! η_N(φ_c) is the thread from the moving eye N to the anchor H_{c−1}^t, the
//! top of the previous hole. The pieces (§5.1):
//!
//! | piece | φ_c | η_N |
//! |---|---|---|
//! | N1 loop forming | [0, φ1) | (S_max − S) + (S_max − s_B) + l_m + t |
//! | N2a carried, needle in hole c | [φ1, φ_out) | e + Λ(R1, H_c^b) + l_m + t |
//! | N2b carried, needle out | [φ_out, φ_in) | \|N − H_c^t\| + l_m + Λ(H_c^b, H_c^b) + l_m + t |
//! | N2c carried, needle c+1 in | [φ_in, φ4) | (S − S_top) + \|P_top − H_c^t\| + l_m + Λ(H_c^b, H_c^b) + l_m + t |
//! | N3a locked, eye out | [φ4, φ_in) | \|N − H_c^t\| |
//! | N3b locked, needle c+1 in | [max(φ4, φ_in), 360) | (S − S_top) + \|P_top − H_c^t\| |

use crate::error::StitchError;
use std::f64::consts::PI;

use crate::Error;
use crate::geometry::V3;

use super::feed::Feed;
use super::search::{extremes_in, first_crossing, first_crossings_in, local_maxima, max_on_cycle, min_on, scan_angles};
use super::spec::{EventKind, LooperSpec, Motion, NeedleSpec};

/// Which limit of η at a moment: at an event both are evaluated (§5).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Side {
    Left,
    Right,
}

/// Is φ before the moment `at`? At the moment itself the piece to the right
/// applies, unless the left limit is asked for.
pub fn before(phi: f64, at: f64, side: Side) -> bool {
    phi < at || (side == Side::Left && (phi - at).abs() < 1e-12)
}

/// The piece of a cyclogram at φ: the first of `pieces` (each with the
/// moment it ends at, in order) whose end φ has not reached, else `last`.
pub fn piece_at<P: Copy>(phi: f64, side: Side, pieces: &[(f64, P)], last: P) -> P {
    pieces
        .iter()
        .find(|(end, _)| before(phi, *end, side))
        .map_or(last, |(_, p)| *p)
}

/// The needle's line and travel, from its eye motion (§2, §4.1).
#[derive(Debug, Clone)]
pub struct NeedleLine {
    /// β, rad (the inclination along the seam).
    pub beta: f64,
    /// u_n = (0, −sin β, cos β), up the needle.
    pub u_n: V3<f64>,
    /// φ_c of TDC (N·u_n largest), deg.
    pub phi_tdc: f64,
    /// The eye at TDC: the seed's split point B.
    pub n_tdc: V3<f64>,
    /// s_B = z(N_TDC)/cos β: the eye at TDC above the plate, along the needle, mm.
    pub s_b: f64,
    /// x_j: the needle line's x, mm.
    pub x_j: f64,
    /// N0: the needle line at the plate top.
    pub n0: V3<f64>,
    /// l_m = m/cos β: thread through the material along the needle, mm.
    pub l_m: f64,
    /// S_top = s_B − l_m: the travel at which the eye reaches the material top, mm.
    pub s_top: f64,
    /// S_max: the stroke, mm.
    pub s_max: f64,
    /// The largest distance of the eye from its line N0 + (s_B − S)·u_n, mm
    /// (0 for a law; a mechanism eye tilted otherwise than β shows here).
    pub off_line_mm: f64,
    eye: Motion,
    /// N·u_n at the scan angles ([`super::search`]), mm.
    heights: Vec<f64>,
}

impl NeedleLine {
    /// The line of the needle whose eye moves as `eye`, with tilt β (deg)
    /// and material thickness `m` (mm).
    pub fn new(eye: &Motion, tilt_deg: f64, m: f64) -> NeedleLine {
        let beta = tilt_deg.to_radians();
        let u_n = V3::new(0.0, -beta.sin(), beta.cos());
        // The eye at the scan angles, read by every search below.
        let knots: Vec<V3<f64>> = scan_angles().map(|phi| eye.at(phi)).collect();
        let heights: Vec<f64> = knots.iter().map(|p| p.dot(&u_n)).collect();
        // TDC: N·u_n largest; BDC (S_max): smallest.
        let ((phi_tdc, _), (_, lowest)) = extremes_in(&heights, |phi| eye.at(phi).dot(&u_n));
        let n_tdc = eye.at(phi_tdc);
        let s_b = n_tdc.z / beta.cos();
        let x_j = n_tdc.x;
        let n0 = V3::new(x_j, n_tdc.y + s_b * beta.sin(), 0.0);
        let l_m = m / beta.cos();
        let mut line = NeedleLine {
            beta,
            u_n,
            phi_tdc,
            n_tdc,
            s_b,
            x_j,
            n0,
            l_m,
            s_top: s_b - l_m,
            s_max: 0.0,
            off_line_mm: 0.0,
            eye: eye.clone(),
            heights,
        };
        line.s_max = n_tdc.dot(&u_n) - lowest;
        line.off_line_mm = knots
            .iter()
            .map(|n| (n - line.eye_at_travel((line.n_tdc - n).dot(&line.u_n))).norm())
            .fold(0.0, f64::max);
        line
    }

    /// S(φ_c) = (N_TDC − N(φ_c))·u_n: the travel below TDC along the needle, mm.
    pub fn travel(&self, phi_c: f64) -> f64 {
        (self.n_tdc - self.eye.at(phi_c)).dot(&self.u_n)
    }

    /// N = N0 + (s_B − S)·u_n: the eye on the needle line at travel `s`.
    pub fn eye_at_travel(&self, s: f64) -> V3<f64> {
        self.n0 + self.u_n * (self.s_b - s)
    }

    /// P_top = N0 + l_m·u_n: the needle line at the material top.
    pub fn p_top(&self) -> V3<f64> {
        self.n0 + self.u_n * self.l_m
    }

    /// Height of the needle point (d_p below the eye) above the plate at
    /// φ_c, mm.
    pub fn point_z(&self, phi_c: f64, d_point: f64) -> f64 {
        (self.s_b - self.travel(phi_c) - d_point) * self.u_n.z
    }

    /// (φ_out, φ_in): the eye leaves the material top going up, and reaches
    /// it going down, S(φ) = S_top (§4.1): the first crossings of the cycle
    /// ([`super::search`]). `None` if the eye never leaves the material.
    pub fn crossings(&self) -> Option<(f64, f64)> {
        // S − S_top falls below zero as the eye leaves, rises as it enters.
        let h_tdc = self.n_tdc.dot(&self.u_n);
        let scan: Vec<f64> = self.heights.iter().map(|h| h_tdc - h - self.s_top).collect();
        match first_crossings_in(&scan, |phi: f64| self.travel(phi) - self.s_top) {
            (Some(out), Some(inn)) => Some((out, inn)),
            _ => None,
        }
    }
}

/// The looper body's section (seed 004 §3 Table 1): plate top to its upper
/// face k, half-cylinder radius a, straight sides b, mm.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LooperSection {
    pub k: f64,
    pub a: f64,
    pub b: f64,
}

impl LooperSection {
    /// D_L = k + b + a: depth of the looper's lowest point (R2's AC), mm.
    pub fn d_l(&self) -> f64 {
        self.k + self.b + self.a
    }
}

/// Λ (§4.4): the loop on the looper body. Branch 1 from root `r1` to the
/// side P1, the half-cylinder (π·a), branch 2 from the side P2 to root
/// `r2`, with P1,2 = (x_loop_abs, y_loop ∓ a, −(k + b)).
pub fn loop_length(sec: &LooperSection, x_loop_abs: f64, y_loop: f64, r1: &V3<f64>, r2: &V3<f64>) -> f64 {
    let p1 = V3::new(x_loop_abs, y_loop - sec.a, -(sec.k + sec.b));
    let p2 = V3::new(x_loop_abs, y_loop + sec.a, -(sec.k + sec.b));
    (r1 - p1).norm() + PI * sec.a + (p2 - r2).norm()
}

/// The carry of needle j's loop on the looper (§4.4): it rides with the
/// catching point until γ reaches γmax, then slides; on the return stroke
/// it stays where the carrying stroke left it until the nose comes back.
#[derive(Debug, Clone)]
pub struct LoopCarry {
    /// x_j, the needle line, mm.
    pub x_j: f64,
    /// φ1j, the catch, deg.
    pub phi_catch: f64,
    /// φ_far: the far extreme of the catching point (end of the carrying
    /// stroke), deg.
    pub phi_far: f64,
    /// D_L = k + b + a, mm.
    pub d_l: f64,
    /// D_L·tan γmax: the most the loop is carried off the needle line, mm.
    pub hold_max: f64,
    looper: Motion,
    /// The running largest L from the catch: (φ, max L over [φ1, φ]) at
    /// the catch and at each local maximum of L up to φ_far that raises it.
    records: Vec<(f64, f64)>,
    /// L(φ_far), mm.
    l_far: f64,
}

impl LoopCarry {
    /// The carry for needle line `x_j`, catch φ1 and far extreme φ_far
    /// (φ1 < φ_far), looper catching point `looper` (L = its x).
    pub fn new(looper: &Motion, x_j: f64, phi_catch: f64, phi_far: f64, d_l: f64, gamma_max_rad: f64) -> LoopCarry {
        let l = |phi: f64| looper.at(phi).x;
        let mut records = vec![(phi_catch, l(phi_catch))];
        for (phi, v) in local_maxima(l, phi_catch, phi_far) {
            if v > records[records.len() - 1].1 {
                records.push((phi, v));
            }
        }
        LoopCarry {
            x_j,
            phi_catch,
            phi_far,
            d_l,
            hold_max: d_l * gamma_max_rad.tan(),
            looper: looper.clone(),
            records,
            l_far: l(phi_far),
        }
    }

    /// L(φ_c): the looper's catching point across the seam, mm.
    pub fn l(&self, phi_c: f64) -> f64 {
        self.looper.at(phi_c).x
    }

    /// x_hold(φ) = min(max_{φ1..min(φ, φ_far)} L − x_j, D_L·tan γmax): how
    /// far the carrying stroke has taken the loop (§4.4).
    pub fn x_hold(&self, phi_c: f64) -> f64 {
        self.x_hold_with(phi_c, self.l(phi_c))
    }

    /// [`Self::x_hold`] given L(φ_c) `l_phi`.
    fn x_hold_with(&self, phi_c: f64, l_phi: f64) -> f64 {
        let psi = phi_c.min(self.phi_far);
        let mut l_max = if psi == phi_c { l_phi } else { self.l_far };
        if psi >= self.phi_catch
            && let Some(&(_, r)) = self.records.iter().rev().find(|(at, _)| *at <= psi)
        {
            l_max = l_max.max(r);
        }
        (l_max - self.x_j).min(self.hold_max)
    }

    /// x_loop = max(0, min(x_hold, L − x_j)): the loop's offset from the
    /// needle line (the nose pushes it back on the return), mm.
    pub fn x_loop(&self, phi_c: f64) -> f64 {
        self.x_loop_with(phi_c, self.l(phi_c))
    }

    /// [`Self::x_loop`] given L(φ_c) `l_phi`.
    pub fn x_loop_with(&self, phi_c: f64, l_phi: f64) -> f64 {
        self.x_hold_with(phi_c, l_phi).min(l_phi - self.x_j).max(0.0)
    }

    /// γ = arctg(x_loop / D_L) (R2), rad.
    pub fn gamma(&self, phi_c: f64) -> f64 {
        (self.x_loop(phi_c) / self.d_l).atan()
    }

    /// The derived drop (§4.4): the first φ from the far extreme on where
    /// the nose is back at the held loop, L − x_j ≤ x_hold (at the far
    /// extreme itself when the loop was never held back). `None` if the
    /// nose does not come back within the cycle.
    pub fn derived_drop(&self) -> Option<f64> {
        // x_hold is constant from φ_far on: the loop is where the carry left it.
        let back = |phi: f64| self.x_hold(phi) + 1e-12 - (self.l(phi) - self.x_j);
        if back(self.phi_far) >= 0.0 {
            return Some(self.phi_far);
        }
        first_crossing(back, self.phi_far, 360.0, true)
    }
}

/// φ_far: where the looper's catching point is farthest along +x, the end
/// of its carrying stroke, deg.
pub fn looper_far(looper: &LooperSpec) -> f64 {
    max_on_cycle(|phi: f64| looper.eye.at(phi).x).0
}

/// The catch derived from the looper (§4.4): the first φ_c in [0, 360)
/// where the catching point L passes the needle line x_j going up (the
/// carrying direction is +x). The looper counts as there within 1e-9 mm, so
/// a catch that falls on a scan angle is not pushed past it by rounding.
/// `None` if it never gets there.
pub fn derived_catch(looper: &Motion, x_j: f64) -> Option<f64> {
    let f = |phi: f64| looper.at(phi).x - x_j + 1e-9;
    first_crossing(f, 0.0, 360.0, true).map(|phi| phi.rem_euclid(360.0))
}

/// The lowest the needle point gets during the transport: (φ_c, its height
/// above the plate, mm).
fn lowest_point_in_transport(line: &NeedleLine, d_point: f64, feed: &Feed) -> (f64, f64) {
    min_on(|phi| line.point_z(phi, d_point), feed.start_deg, feed.end_deg())
}

/// Piece of the needle-thread contour (§5.1).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum NeedlePiece {
    N1,
    N2a,
    N2b,
    N2c,
    N3a,
    N3b,
}

impl NeedlePiece {
    pub fn id(self) -> &'static str {
        match self {
            NeedlePiece::N1 => "N1",
            NeedlePiece::N2a => "N2a",
            NeedlePiece::N2b => "N2b",
            NeedlePiece::N2c => "N2c",
            NeedlePiece::N3a => "N3a",
            NeedlePiece::N3b => "N3b",
        }
    }
}

/// An error of needle `name`.
fn needle_err<T>(name: &str, msg: String) -> Result<T, Error> {
    Err(Error::Stitch(StitchError::new(format!("needle {name}"), msg)))
}

/// The needle's line and when its eye leaves and reaches the material top
/// (φ_out, φ_in), warning when φ_c = 0 is not the needle's BDC or the eye
/// leaves its line.
pub(super) fn needle_line(
    needle: &NeedleSpec,
    tilt_deg: f64,
    m: f64,
    warnings: &mut Vec<String>,
) -> Result<(NeedleLine, f64, f64), Error> {
    let name = &needle.name;
    let line = NeedleLine::new(&needle.eye, tilt_deg, m);
    if ![line.s_b, line.x_j, line.s_max, line.n0.y]
        .iter()
        .all(|v| v.is_finite())
    {
        return needle_err(name, "the eye motion gives non-finite positions".into());
    }
    let Some((phi_out, phi_in)) = line.crossings() else {
        return needle_err(
            name,
            format!(
                "the eye never leaves the material: at TDC it is {:.3} mm along the needle above the plate top \
                 (s_B), the material top is at {:.3} mm (l_m); raise the eye at TDC or give thinner material",
                line.s_b, line.l_m
            ),
        );
    };
    // φ_c = 0 is the needle's BDC (§2); N1 and the periodicity rely on it.
    let s0 = line.travel(0.0);
    if line.s_max - s0 > 1e-3 {
        warnings.push(format!(
            "needle {name}: φ_c = 0 is not the needle's BDC (S(0) = {s0:.3} mm, stroke {:.3} mm); set \
             cyclogram_zero_deg to the needle BDC",
            line.s_max
        ));
    }
    if line.off_line_mm > 0.01 {
        warnings.push(format!(
            "needle {name}: the eye leaves its line by up to {:.3} mm; the needle tilt β = {tilt_deg}° does not \
             match the eye's motion",
            line.off_line_mm
        ));
    }
    Ok((line, phi_out, phi_in))
}

/// The catch φ1, declared or derived (the looper's catching point crosses
/// the needle line x_j going up), and the derived one.
fn catch_angle(
    needle: &NeedleSpec,
    looper: &LooperSpec,
    x_j: f64,
    warnings: &mut Vec<String>,
) -> Result<(f64, Option<f64>), Error> {
    let name = &needle.name;
    let l = |phi: f64| looper.eye.at(phi).x;
    let phi_catch_derived = derived_catch(&looper.eye, x_j);
    let phi_catch = match (needle.catch_deg, phi_catch_derived) {
        (Some(c), _) if !(c.is_finite() && (0.0..360.0).contains(&c)) => {
            return needle_err(name, format!("the declared catch φ1 = {c}° is not in [0°, 360°)"));
        }
        (Some(c), _) => {
            let miss = l(c) - x_j;
            if miss.abs() > 0.5 {
                warnings.push(format!(
                    "needle {name}: at the declared catch φ1 = {c}° the looper's catching point is {miss:.3} mm \
                     from the needle line (x = {x_j:.3} mm)"
                ));
            }
            c
        }
        (None, Some(c)) => c,
        (None, None) => {
            let (lo, hi) = (-max_on_cycle(|phi| -l(phi)).1, max_on_cycle(l).1);
            return needle_err(
                name,
                format!(
                    "the looper never reaches the needle: its catching point moves in x = {lo:.3} … {hi:.3} mm and \
                     the needle line is at x = {x_j:.3} mm; move the looper or the needle, or declare catch_deg"
                ),
            );
        }
    };
    Ok((phi_catch, phi_catch_derived))
}

/// The drop φ4 (the lock): declared (checked against the derived one,
/// §4.4), or derived from the carry.
fn drop_angle(
    needle: &NeedleSpec,
    derived: Option<f64>,
    phi_far: f64,
    warnings: &mut Vec<String>,
) -> Result<f64, Error> {
    let name = &needle.name;
    match (needle.drop_deg, derived) {
        (Some(d), _) if !(d.is_finite() && (0.0..360.0).contains(&d)) => {
            needle_err(name, format!("the declared drop φ4 = {d}° is not in [0°, 360°)"))
        }
        (Some(d), derived) => {
            match derived {
                Some(dd) if (d - dd).abs() > 10.0 => warnings.push(format!(
                    "needle {name}: the declared drop φ4 = {d:.2}° differs from the derived drop {dd:.2}° by \
                     {:.2}° (§4.4)",
                    (d - dd).abs()
                )),
                None => warnings.push(format!(
                    "needle {name}: the looper's nose does not come back to the loop within the cycle; the \
                     declared drop φ4 = {d:.2}° cannot be checked (§4.4)"
                )),
                _ => {}
            }
            Ok(d)
        }
        (None, Some(d)) => Ok(d),
        (None, None) => needle_err(
            name,
            format!(
                "the looper's nose never comes back to the held loop after its far extreme (φ_c = {phi_far:.2}°), \
                 so the drop cannot be derived; declare drop_deg or raise γmax"
            ),
        ),
    }
}

/// The organs at one φ_c as the needle thread's contour reads them.
struct OrgansAt {
    phi_c: f64,
    /// S, mm.
    s: f64,
    /// H_c^t, H_c^b.
    h_t: V3<f64>,
    h_b: V3<f64>,
    /// x_loop and the looper's y, mm.
    x_loop: f64,
    y_loop: f64,
}

/// The organs the needles of one looper share, on a φ_c grid: the looper's
/// catching point and the feed T, mm.
#[derive(Debug, Clone)]
pub struct SharedOrgans {
    pub looper: Vec<V3<f64>>,
    pub feed_mm: Vec<f64>,
}

impl SharedOrgans {
    pub fn new(looper: &Motion, feed: &Feed, phis: &[f64]) -> SharedOrgans {
        SharedOrgans {
            looper: phis.iter().map(|&p| looper.at(p)).collect(),
            feed_mm: phis.iter().map(|&p| feed.at(p)).collect(),
        }
    }
}

/// A needle thread's contour over a φ grid ([`NeedleThread::series`]).
#[derive(Debug, Clone)]
pub struct NeedleSeries {
    pub eta_mm: Vec<f64>,
    pub travel_mm: Vec<f64>,
    pub gamma_deg: Vec<f64>,
    pub loop_mm: Vec<f64>,
}

/// One needle thread's consumption contour (§5.1, §5.2).
#[derive(Debug, Clone)]
pub struct NeedleThread {
    pub name: String,
    pub line: NeedleLine,
    pub carry: LoopCarry,
    pub section: LooperSection,
    pub feed: Feed,
    /// φ1: the catch used (declared or derived), deg.
    pub phi_catch: f64,
    /// The catch derived from the looper (L crosses x_j going up), deg.
    pub phi_catch_derived: Option<f64>,
    /// φ4: the drop used (declared or derived): the lock, deg.
    pub phi_drop: f64,
    /// The drop derived from the carry (§4.4), deg.
    pub phi_drop_derived: Option<f64>,
    /// φ_out, φ_in: the eye leaves / reaches the material top, deg.
    pub phi_out: f64,
    pub phi_in: f64,
    /// The needle point below the eye, along the needle, mm.
    pub point_below_eye_mm: f64,
    /// Validity warnings found while building.
    pub warnings: Vec<String>,
    looper_eye: Motion,
}

impl NeedleThread {
    /// Needle `needle` with the looper `looper`, material thickness m, needle
    /// tilt β (deg) and the feed.
    pub fn new(
        needle: &NeedleSpec,
        looper: &LooperSpec,
        m: f64,
        tilt_deg: f64,
        feed: Feed,
    ) -> Result<NeedleThread, Error> {
        Self::with_looper_far(needle, looper, looper_far(looper), m, tilt_deg, feed)
    }

    /// [`Self::new`] given the looper's far extreme φ_far ([`looper_far`]),
    /// which the needles of one looper share.
    pub fn with_looper_far(
        needle: &NeedleSpec,
        looper: &LooperSpec,
        phi_far: f64,
        m: f64,
        tilt_deg: f64,
        feed: Feed,
    ) -> Result<NeedleThread, Error> {
        let name = &needle.name;
        let section = LooperSection {
            k: looper.k_mm,
            a: looper.a_mm,
            b: looper.b_mm,
        };
        if ![section.k, section.a, section.b]
            .iter()
            .all(|v| v.is_finite() && *v >= 0.0)
            || section.d_l() <= 0.0
        {
            return needle_err(
                name,
                format!(
                    "the looper section k = {}, a = {}, b = {} mm must be ≥ 0 with k + b + a > 0 ({}: 4, 1, 2.5)",
                    section.k,
                    section.a,
                    section.b,
                    crate::references::cite(4)
                ),
            );
        }
        let gamma_max = looper.gamma_max_rad;
        if !(gamma_max.is_finite() && gamma_max > 0.0 && gamma_max < 0.5 * PI) {
            return needle_err(
                name,
                format!(
                    "γmax = {gamma_max} rad is out of range; give 0 < γmax < π/2 ({}: 0.4–0.8 rad)",
                    crate::references::cite(4)
                ),
            );
        }
        let mut warnings = Vec::new();
        let (line, phi_out, phi_in) = needle_line(needle, tilt_deg, m, &mut warnings)?;
        let x_j = line.x_j;
        let (phi_catch, phi_catch_derived) = catch_angle(needle, looper, x_j, &mut warnings)?;
        let z_catch = line.eye_at_travel(line.travel(phi_catch)).z;
        if z_catch >= 0.0 {
            return needle_err(
                name,
                format!(
                    "the eye is {z_catch:.3} mm above the plate top at the catch φ1 = {phi_catch:.2}°, so the looper \
                     finds no loop; catch earlier (before φ_out = {phi_out:.2}°) or lower the needle"
                ),
            );
        }
        if phi_catch >= phi_out {
            return needle_err(
                name,
                format!(
                    "the catch φ1 = {phi_catch:.2}° is not before the eye leaves the material (φ_out = \
                     {phi_out:.2}°); catch earlier"
                ),
            );
        }
        if phi_far <= phi_catch {
            return needle_err(
                name,
                format!(
                    "the looper reaches its far extreme (φ_c = {phi_far:.2}°) before it catches the loop \
                     (φ1 = {phi_catch:.2}°); the catch must be on the carrying stroke (+x)"
                ),
            );
        }
        let carry = LoopCarry::new(&looper.eye, x_j, phi_catch, phi_far, section.d_l(), gamma_max);
        let phi_drop_derived = carry.derived_drop();
        let phi_drop = drop_angle(needle, phi_drop_derived, phi_far, &mut warnings)?;
        if phi_drop <= phi_out {
            return needle_err(
                name,
                format!(
                    "the drop φ4 = {phi_drop:.2}° is not after the eye leaves the material (φ_out = {phi_out:.2}°): \
                     the loop must hang from hole c when it drops (§5.1); drop later"
                ),
            );
        }
        if phi_drop <= phi_catch {
            return needle_err(
                name,
                format!("the drop φ4 = {phi_drop:.2}° is not after the catch φ1 = {phi_catch:.2}°"),
            );
        }
        // The needle point must be out of the material while it is fed (§4.1).
        let d_p = needle.point_below_eye_mm;
        if !(d_p.is_finite() && d_p >= 0.0) {
            return needle_err(name, format!("point_below_eye_mm = {d_p} must be ≥ 0"));
        }
        let (phi, z) = lowest_point_in_transport(&line, d_p, &feed);
        if z <= m {
            warnings.push(format!(
                "needle {name}: the needle point is in the material during the transport (point {z:.3} mm above the \
                 plate at φ_c = {phi:.2}°, material top {m} mm); move the transport or raise the needle"
            ));
        }
        Ok(NeedleThread {
            name: name.clone(),
            line,
            carry,
            section,
            feed,
            phi_catch,
            phi_catch_derived,
            phi_drop,
            phi_drop_derived,
            phi_out,
            phi_in,
            point_below_eye_mm: d_p,
            warnings,
            looper_eye: looper.eye.clone(),
        })
    }

    /// The needle loop on the looper body at φ_c (§4.4): Λ with both roots
    /// at the bottom of hole c from the catch to the drop, 0 otherwise, mm.
    pub fn loop_on_looper(&self, phi_c: f64) -> f64 {
        self.loop_at(&self.organs_at(phi_c))
    }

    /// [`Self::loop_on_looper`] from the organs at φ_c.
    fn loop_at(&self, a: &OrgansAt) -> f64 {
        if a.phi_c < self.phi_catch || a.phi_c >= self.phi_drop {
            return 0.0;
        }
        self.lam_at(a, &a.h_b, &a.h_b)
    }

    /// The organs at φ_c, each evaluated once: what η, the loop and γ read.
    fn organs_at(&self, phi_c: f64) -> OrgansAt {
        self.organs_with(phi_c, self.looper_eye.at(phi_c), self.feed.at(phi_c))
    }

    /// [`Self::organs_at`] given the looper's catching point and the feed
    /// T at φ_c.
    fn organs_with(&self, phi_c: f64, looper: V3<f64>, feed_mm: f64) -> OrgansAt {
        let s = self.travel(phi_c);
        let shift = V3::new(0.0, feed_mm, 0.0);
        let (h_t, h_b) = (self.line.p_top() + shift, self.line.n0 + shift);
        OrgansAt {
            phi_c,
            s,
            h_t,
            h_b,
            x_loop: self.carry.x_loop_with(phi_c, looper.x),
            y_loop: looper.y,
        }
    }

    /// Per φ_c of `phis`: η (the right limit), the travel S, the carry
    /// angle γ (deg) and the loop on the looper, each organ evaluated once
    /// per φ (the looper and the feed in `shared`, for every needle).
    pub fn series(&self, phis: &[f64], shared: &SharedOrgans) -> NeedleSeries {
        let mut out = NeedleSeries {
            eta_mm: Vec::with_capacity(phis.len()),
            travel_mm: Vec::with_capacity(phis.len()),
            gamma_deg: Vec::with_capacity(phis.len()),
            loop_mm: Vec::with_capacity(phis.len()),
        };
        for (k, &phi) in phis.iter().enumerate() {
            let a = self.organs_with(phi, shared.looper[k], shared.feed_mm[k]);
            out.eta_mm.push(self.eta_at(&a, Side::Right));
            out.travel_mm.push(a.s);
            out.gamma_deg.push((a.x_loop / self.carry.d_l).atan().to_degrees());
            out.loop_mm.push(self.loop_at(&a));
        }
        out
    }

    /// The catch and drop geometry the physical checks judge
    /// ([`super::checks`]).
    pub fn moments_for_checks(&self) -> super::checks::NeedleMoments {
        let eye_at_catch = self.line.eye_at_travel(self.travel(self.phi_catch));
        super::checks::NeedleMoments {
            catch_deg: self.phi_catch,
            looper_above_eye_mm: self.looper_eye.at(self.phi_catch).z - eye_at_catch.z,
            drop_deg: self.phi_drop,
            point_z_at_drop_mm: self.line.point_z(self.phi_drop, self.point_below_eye_mm),
            looper_top_z_mm: -self.section.k,
        }
    }

    /// S(φ_c), mm.
    pub fn travel(&self, phi_c: f64) -> f64 {
        self.line.travel(phi_c)
    }

    /// (H_c^t, H_c^b): the ends of hole c, made in the previous cycle; they
    /// move with the material by T(φ).
    pub fn hole_c(&self, phi_c: f64) -> (V3<f64>, V3<f64>) {
        let shift = V3::new(0.0, self.feed.at(phi_c), 0.0);
        (self.line.p_top() + shift, self.line.n0 + shift)
    }

    /// Λ(φ, R1, R2) of §4.4 for this needle's loop.
    pub fn lam(&self, phi_c: f64, r1: &V3<f64>, r2: &V3<f64>) -> f64 {
        self.lam_at(&self.organs_at(phi_c), r1, r2)
    }

    /// [`Self::lam`] from the organs at φ_c.
    fn lam_at(&self, a: &OrgansAt, r1: &V3<f64>, r2: &V3<f64>) -> f64 {
        loop_length(&self.section, self.line.x_j + a.x_loop, a.y_loop, r1, r2)
    }

    /// The looper's lowest point under this needle's loop,
    /// (x_j + x_loop, y_loop, −D_L) (§4.4): where the loop's bight leaves
    /// the looper body when it drops (503, §5.5).
    pub fn loop_bottom(&self, phi_c: f64) -> V3<f64> {
        let l = self.looper_eye.at(phi_c);
        V3::new(
            self.line.x_j + self.carry.x_loop_with(phi_c, l.x),
            l.y,
            -self.section.d_l(),
        )
    }

    /// The head of the contour after the drop (§5.1 N3): the thread from the
    /// eye to the top of hole c, |N − H_c^t| while the eye is above the
    /// material (φ_c < φ_in), then (S − S_top) + |P_top − H_c^t| down needle
    /// c+1 and along the top face, mm.
    pub fn head(&self, phi_c: f64) -> f64 {
        self.head_at(&self.organs_at(phi_c))
    }

    /// [`Self::head`] from the organs at φ_c.
    fn head_at(&self, a: &OrgansAt) -> f64 {
        if before(a.phi_c, self.phi_in, Side::Right) {
            (self.line.eye_at_travel(a.s) - a.h_t).norm()
        } else {
            (a.s - self.line.s_top) + (self.line.p_top() - a.h_t).norm()
        }
    }

    /// The piece at φ_c (the left one at a moment when `side` is Left).
    pub fn piece(&self, phi_c: f64, side: Side) -> NeedlePiece {
        let before = |at| before(phi_c, at, side);
        if before(self.phi_catch) {
            NeedlePiece::N1
        } else if before(self.phi_drop) {
            if before(self.phi_out) {
                NeedlePiece::N2a
            } else if before(self.phi_in) {
                NeedlePiece::N2b
            } else {
                NeedlePiece::N2c
            }
        } else if before(self.phi_in) {
            NeedlePiece::N3a
        } else {
            NeedlePiece::N3b
        }
    }

    /// η_N(φ_c): thread from the eye to the anchor H_{c−1}^t, mm (§5.1).
    pub fn eta(&self, phi_c: f64, side: Side) -> f64 {
        self.eta_at(&self.organs_at(phi_c), side)
    }

    /// [`Self::eta`] from the organs at φ_c.
    fn eta_at(&self, a: &OrgansAt, side: Side) -> f64 {
        let (t, l_m, s_b) = (self.feed.t_mm, self.line.l_m, self.line.s_b);
        let (phi_c, s, h_t, h_b) = (a.phi_c, a.s, a.h_t, a.h_b);
        let n = self.line.eye_at_travel(s);
        // Through hole c and along the top face to hole c−1: branch 2's tail.
        let tail = l_m + t;
        // Needle c+1 in hole c+1: down the needle, along the top face to hole c.
        let via_next_needle = || (s - self.line.s_top) + (self.line.p_top() - h_t).norm();
        match self.piece(phi_c, side) {
            // The eye slides along the loop: η_B = S + η_N stays constant.
            NeedlePiece::N1 => (self.line.s_max - s) + (self.line.s_max - s_b) + tail,
            NeedlePiece::N2a => {
                // Eye below the plate: branch 1 starts at the eye; in the
                // material: down the needle to the plate.
                let (e, r1) = if n.z < 0.0 { (0.0, n) } else { (s_b - s, self.line.n0) };
                e + self.lam_at(a, &r1, &h_b) + tail
            }
            NeedlePiece::N2b => (n - h_t).norm() + l_m + self.lam_at(a, &h_b, &h_b) + tail,
            NeedlePiece::N2c => via_next_needle() + l_m + self.lam_at(a, &h_b, &h_b) + tail,
            NeedlePiece::N3a | NeedlePiece::N3b => self.head_at(a),
        }
    }

    /// The thread cut at the lock φ4, from the final nodes: hole c−1 top,
    /// down hole c (l_m), the collapsed loop (0), up (l_m), along the top
    /// face to hole c−1 (t) — contour 1 (§7).
    pub fn lock_cut(&self) -> f64 {
        let (h_t, h_b) = self.hole_c(self.phi_drop);
        let h_t_prev = h_t + V3::new(0.0, self.feed.t_mm, 0.0);
        (h_t - h_b).norm() + 0.0 + (h_b - h_t).norm() + (h_t_prev - h_t).norm()
    }

    /// ρ = Λ(φ4⁻): the loop released when it drops off the looper, mm.
    pub fn released(&self) -> f64 {
        let (_, h_b) = self.hole_c(self.phi_drop);
        self.lam(self.phi_drop, &h_b, &h_b)
    }

    /// The moments of this thread in φ_c order (§5.6).
    pub fn events(&self) -> Vec<(String, f64, EventKind)> {
        let mut ev = vec![
            ("catch (φ1)".to_string(), self.phi_catch, EventKind::Jump),
            ("eye leaves material (φ_out)".to_string(), self.phi_out, EventKind::Cont),
            ("transport start".to_string(), self.feed.start_deg, EventKind::Cont),
            ("transport end".to_string(), self.feed.end_deg(), EventKind::Cont),
            ("eye enters material (φ_in)".to_string(), self.phi_in, EventKind::Cont),
            (
                "drop = needle-thread lock (φ4)".to_string(),
                self.phi_drop,
                EventKind::Lock,
            ),
        ];
        ev.sort_by(|a, b| a.1.total_cmp(&b.1));
        ev
    }

    /// Derived moments of this needle (name, φ_c deg).
    pub fn moments(&self) -> Vec<(String, f64)> {
        let n = &self.name;
        let mut out = vec![
            (format!("{n}: needle TDC"), self.line.phi_tdc),
            (format!("{n}: eye leaves material (φ_out)"), self.phi_out),
            (format!("{n}: eye enters material (φ_in)"), self.phi_in),
            (format!("{n}: looper far extreme"), self.carry.phi_far),
        ];
        if let Some(c) = self.phi_catch_derived {
            out.push((format!("{n}: catch (derived)"), c));
        }
        out.push((format!("{n}: catch (used)"), self.phi_catch));
        if let Some(d) = self.phi_drop_derived {
            out.push((format!("{n}: drop (derived)"), d));
        }
        out.push((format!("{n}: drop = lock (used)"), self.phi_drop));
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    fn altin504() -> crate::stitch::spec::StitchSpec {
        crate::stitch::reference::altin504(2.5, 2.8)
    }
    fn mf7923d_407() -> crate::stitch::spec::StitchSpec {
        crate::stitch::reference::mf7923d_407(3.0, 3.0)
    }
    use approx::assert_relative_eq;

    fn altin_needle() -> NeedleThread {
        let s = altin504();
        let feed = Feed::new(&s.feed, s.t_mm).unwrap();
        NeedleThread::new(&s.needles[0], s.looper.as_ref().unwrap(), s.m_mm, s.tilt_deg, feed).unwrap()
    }

    #[test]
    fn needle_line_from_the_law() {
        let n = altin_needle();
        let l = &n.line;
        // S = stroke/2·(1 + cos φ_c), TDC at 180°, s_B = 11.5, N0 at the origin.
        assert_relative_eq!(l.phi_tdc, 180.0, epsilon = 1e-6);
        assert_relative_eq!(l.s_b, 11.5, epsilon = 1e-12);
        assert_relative_eq!(l.n0, V3::zeros(), epsilon = 1e-12);
        assert_relative_eq!(l.s_max, 25.44, epsilon = 1e-12);
        for phi in [0.0, 37.0, 180.0, 271.5] {
            assert_relative_eq!(
                l.travel(phi),
                12.72 * (1.0 + f64::to_radians(phi).cos()),
                epsilon = 1e-12
            );
        }
        assert!(l.off_line_mm < 1e-12);
        assert_relative_eq!(l.l_m, 2.5 / 20f64.to_radians().cos(), epsilon = 1e-15);
        // Crossings: S = S_top = s_B − l_m, symmetric about TDC (README: 107.76°, 252.24°).
        let phi_out = (2.0 * l.s_top / 25.44 - 1.0).acos().to_degrees();
        assert_relative_eq!(n.phi_out, phi_out, epsilon = 1e-9);
        assert_relative_eq!(n.phi_in, 360.0 - phi_out, epsilon = 1e-9);
        assert!((n.phi_out - 107.76).abs() < 0.005);
    }

    #[test]
    fn loop_length_by_hand() {
        let sec = LooperSection { k: 4.0, a: 1.0, b: 2.5 };
        assert_eq!(sec.d_l(), 7.5);
        // Both roots at the hole bottom (origin), loop straight below at y = 0:
        // two legs of √(1 + 6.5²) and the half circle π.
        let o = V3::zeros();
        assert_relative_eq!(
            loop_length(&sec, 0.0, 0.0, &o, &o),
            2.0 * 1f64.hypot(6.5) + PI,
            epsilon = 1e-12
        );
        // Carried 3 mm across and 0.5 along the seam; R1 at the eye below the plate.
        let r1 = V3::new(0.0, 0.0, -10.0);
        let want = 3f64.hypot(0.5 + 1.0).hypot(3.5) + PI + 3f64.hypot(0.5).hypot(6.5);
        assert_relative_eq!(loop_length(&sec, 3.0, -0.5, &r1, &o), want, epsilon = 1e-12);
    }

    #[test]
    fn carry_rides_saturates_holds_and_drops() {
        let n = altin_needle();
        let c = &n.carry;
        let hold_max = 7.5 * 0.4f64.tan();
        assert_relative_eq!(c.hold_max, hold_max, epsilon = 1e-15);
        assert_relative_eq!(c.phi_far, 180.0, epsilon = 1e-6);
        // Before the catch: no carry.
        assert_eq!(c.x_loop(10.0), 0.0);
        // Rides with the looper: x_loop = L − x_j, γ = arctg(x_loop/D_L).
        let l60 = 8.66 * (1.0 - 60f64.to_radians().cos()) - 8.66 * (1.0 - 30f64.to_radians().cos());
        assert_relative_eq!(c.x_loop(60.0), l60, epsilon = 1e-12);
        assert_relative_eq!(c.gamma(60.0), (l60 / 7.5).atan(), epsilon = 1e-12);
        // Slides at γmax, holds on the return stroke.
        assert_relative_eq!(c.gamma(150.0), 0.4, epsilon = 1e-12);
        assert_relative_eq!(c.x_loop(250.0), hold_max, epsilon = 1e-12);
        // The nose comes back just before 300° (docs §4.4: D_L·tan γmax ≈
        // 0.366·X_L/2): at 299.991°, which the reference's 0.01° grid
        // rounds up to 300.00°.
        let drop = c.derived_drop().unwrap();
        assert!(299.99 < drop && drop < 300.0, "{drop}");
        assert_relative_eq!(c.l(drop) - c.x_j, hold_max, epsilon = 1e-9);
        assert_relative_eq!(n.phi_drop, 300.0, epsilon = 0.0); // declared
        // Then the nose pushes the loop back.
        assert_relative_eq!(c.x_loop(320.0), c.l(320.0), epsilon = 1e-12);
        assert!(c.x_loop(320.0) < hold_max);
    }

    #[test]
    fn derived_catches_and_drops_of_the_407() {
        let s = mf7923d_407();
        let feed = Feed::new(&s.feed, s.t_mm).unwrap();
        let want = [(30.0, 311.91), (51.9735342, 294.7), (68.5292986, 279.67)];
        for (ns, (catch, drop)) in s.needles.iter().zip(want) {
            let n = NeedleThread::new(ns, s.looper.as_ref().unwrap(), s.m_mm, s.tilt_deg, feed.clone()).unwrap();
            assert!((n.phi_catch - catch).abs() < 1e-6, "{}: catch {}", ns.name, n.phi_catch);
            if ns.name == "n1" {
                assert!(n.phi_catch <= 30.0, "n1's catch falls on or before the grid angle 30°");
            }
            // The reference resolves the drop on its 0.01° grid, the first
            // grid angle at or after it; found by root finding it is there
            // or up to 0.01° before.
            assert!(
                n.phi_drop <= drop + 1e-9 && n.phi_drop > drop - 0.01,
                "{}: drop {}",
                ns.name,
                n.phi_drop
            );
        }
    }

    #[test]
    fn derived_catch_and_needle_point() {
        let s = altin504();
        // L = 8.66·(1 − cos φ) − L0 passes x = 0 going up at 30° (within the 1e-9 mm touch).
        let c = derived_catch(&s.looper.as_ref().unwrap().eye, 0.0).unwrap();
        assert!(c <= 30.0 && 30.0 - c < 1e-6, "{c}");
        assert!(derived_catch(&s.looper.as_ref().unwrap().eye, 40.0).is_none());
        // README: the point is 5.277 / 4.000 mm above the plate at the start / end of the transport.
        let n = altin_needle();
        let (phi, z) = lowest_point_in_transport(&n.line, 2.0, &n.feed);
        assert_relative_eq!(phi, 234.0);
        assert!((z - 4.000).abs() < 5e-4 && (n.line.point_z(134.0, 2.0) - 5.277).abs() < 5e-4);
    }

    #[test]
    fn piece_boundaries_and_limits() {
        let n = altin_needle();
        assert_eq!(n.piece(30.0, Side::Left), NeedlePiece::N1);
        assert_eq!(n.piece(30.0, Side::Right), NeedlePiece::N2a);
        assert_eq!(n.piece(200.0, Side::Right), NeedlePiece::N2b);
        assert_eq!(n.piece(280.0, Side::Right), NeedlePiece::N2c);
        assert_eq!(n.piece(300.0, Side::Left), NeedlePiece::N2c);
        assert_eq!(n.piece(300.0, Side::Right), NeedlePiece::N3b);
        // Lock jump = −(t + 2 l_m) − Λ(φ4⁻) (§5.1).
        let jump = n.eta(300.0, Side::Right) - n.eta(300.0, Side::Left);
        assert_relative_eq!(jump, -(n.lock_cut() + n.released()), epsilon = 1e-12);
        assert_relative_eq!(n.lock_cut(), 2.8 + 2.0 * n.line.l_m, epsilon = 1e-12);
    }
}
