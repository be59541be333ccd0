//! The needle thread of a lockstitch 301 whose loop a rotary hook takes
//! around the bobbin case (`docs/stitch-formation.md` §13).
//!
//! η_K(φ_c) is the thread from the moving eye N to the anchor I_{c−1}, the
//! interlacing of the previous stitch, f·l_m down hole c−1. The pieces:
//!
//! | piece | φ_c | η_K |
//! |---|---|---|
//! | K1 loop forming | [0, φ1) | (S_max − S) + (S_max − s_B) + l_m + t + f·l_m |
//! | K2a on the hook, needle in hole c | [φ1, φ_out) | e + Λ_h(R1, H_c^b) + l_m + t + f·l_m |
//! | K2b on the hook, needle out | [φ_out, φ_K) | \|N − H_c^t\| + l_m + Λ_h(H_c^b, H_c^b) + l_m + t + f·l_m |
//! | K3a cast off, eye out | [φ_K, φ_in) | \|N − H_c^t\| + f·l_m |
//! | K3b cast off, needle c+1 in | [φ_in, 360) | (S − S_top) + \|P_top − H_c^t\| + f·l_m |
//!
//! Λ_h is the taut loop in the hook's plane (the plane through the needle
//! line across the hook axis): the shortest thread from its root R1 (the
//! eye, or the bottom of hole c) around the beak and the part of the bobbin
//! case's outline the beak has carried it over, back to the bottom of hole
//! c: the perimeter of their convex hull less the chord R1–H_c^b. The beak
//! turns twice per stitch; the loop leaves the hook (is cast off) after
//! the beak's turn `cast_off_deg` from the catch, and the take-up pulls the
//! stitch tight: the lock, at which the thread of one stitch, t + 2·f·l_m,
//! is cut off (§6, G7) and the loop is released.

use crate::Error;
use crate::error::StitchError;
use crate::geometry::{V3, by_x_then_y, convex_hull, convex_hull_sorted};

use super::feed::Feed;
use super::needle_thread::{NeedleLine, Side, before, needle_line};
use super::search::first_crossing;
use super::spec::{EventKind, HookSpec, NeedleSpec};

/// The largest step of the bobbin case's outline in the loop's hull, deg:
/// the hull's perimeter is then within r·Θ·(Δ²/24) ≈ 2·10⁻⁴ mm of the arc's
/// for a case of radius 11 mm wrapped a full turn.
const ARC_STEP_DEG: f64 = 0.5;

/// The most steps of the outline a hull from its deciding points takes:
/// a turn short of a full one.
const MAX_ARC_STEPS: usize = (360.0 / ARC_STEP_DEG) as usize;

/// ⌊x⌋ and ⌈x⌉ as integers (for the few arc indices a hull decides).
fn floor_i(x: f64) -> isize {
    let t = x as isize;
    if t as f64 > x { t - 1 } else { t }
}

fn ceil_i(x: f64) -> isize {
    let t = x as isize;
    if (t as f64) < x { t + 1 } else { t }
}

/// The steps of the case's outline over a turn of `turn_rad`.
fn arc_steps(turn_rad: f64) -> usize {
    (turn_rad.to_degrees() / ARC_STEP_DEG).ceil().max(1.0) as usize
}

/// Perimeter of the convex hull of points in a plane (y, z), mm; fewer
/// than two distinct points have perimeter 0.
pub fn hull_perimeter(points: &mut [[f64; 2]]) -> f64 {
    perimeter(&convex_hull(points))
}

/// Perimeter of a closed polygon, mm.
fn perimeter(polygon: &[[f64; 2]]) -> f64 {
    let n = polygon.len();
    (0..n)
        .map(|i| {
            let (a, b) = (polygon[i], polygon[(i + 1) % n]);
            (b[0] - a[0]).hypot(b[1] - a[1])
        })
        .sum()
}

/// Into `out`: the points of `arc` (consecutive points of a circle's arc,
/// in its order) and of `extra` (sorted), in [`by_x_then_y`] order. The
/// arc falls into runs along which x only rises or only falls (it turns
/// at most at every half turn); the runs, each already ordered, and the
/// extra points are merged, not sorted.
fn merge_arc_runs(arc: &[[f64; 2]], extra: &[[f64; 2]], out: &mut Vec<[f64; 2]>) {
    out.clear();
    out.extend_from_slice(extra);
    let mut merged = Vec::with_capacity(arc.len() + extra.len());
    let mut start = 0;
    while start < arc.len() {
        // The longest run from `start` that is strictly ordered one way.
        let mut end = start + 1;
        if end < arc.len() {
            let rising = by_x_then_y(&arc[start], &arc[end]).is_lt();
            while end < arc.len() && by_x_then_y(&arc[end - 1], &arc[end]).is_lt() == rising && arc[end - 1] != arc[end]
            {
                end += 1;
            }
            if !rising {
                // A falling run, read backwards.
                merge_into(out, arc[start..end].iter().rev(), &mut merged);
                start = end;
                continue;
            }
        }
        merge_into(out, arc[start..end].iter(), &mut merged);
        start = end;
    }
}

/// `sorted` merged with the ordered `run` (both in [`by_x_then_y`] order),
/// back into `sorted`; `scratch` is reused.
fn merge_into<'a>(sorted: &mut Vec<[f64; 2]>, run: impl Iterator<Item = &'a [f64; 2]>, scratch: &mut Vec<[f64; 2]>) {
    scratch.clear();
    let mut run = run.peekable();
    let mut i = 0;
    while i < sorted.len() {
        match run.peek() {
            Some(p) if by_x_then_y(p, &sorted[i]).is_lt() => scratch.push(*run.next().expect("peeked")),
            _ => {
                scratch.push(sorted[i]);
                i += 1;
            }
        }
    }
    scratch.extend(run.copied());
    std::mem::swap(sorted, scratch);
}

/// The hook in the stitch frame: its centre, where the beak meets the
/// needle, and which way it turns.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct HookGeometry {
    /// The hook axis's point in the hook plane (y, z), mm.
    pub centre: [f64; 2],
    /// The beak's radius, mm.
    pub beak_radius: f64,
    /// The bobbin case's radius in the hook plane, mm.
    pub case_radius: f64,
    /// The beak's angle in the hook plane at the catch (from +y toward +z), rad.
    pub psi_catch: f64,
    /// +1 when the beak turns from +y toward +z, −1 the other way.
    pub sense: f64,
}

impl HookGeometry {
    /// The beak's angle after turning `turn_rad` from the catch, rad.
    pub fn psi(&self, turn_rad: f64) -> f64 {
        self.psi_catch + self.sense * turn_rad
    }

    /// A point of the hook plane at radius `r` and angle ψ from the centre.
    pub fn at(&self, r: f64, psi: f64) -> [f64; 2] {
        [self.centre[0] + r * psi.cos(), self.centre[1] + r * psi.sin()]
    }

    /// The case's outline from the catch's angle over `turn_rad`, at
    /// `steps` + 1 evenly spaced points: each the last turned by the step
    /// (a rotation, not a sine and cosine per point).
    fn case_arc(&self, turn_rad: f64, steps: usize) -> Vec<[f64; 2]> {
        let (sd, cd) = (self.sense * turn_rad / steps as f64).sin_cos();
        let (mut s, mut c) = self.psi_catch.sin_cos();
        let r = self.case_radius;
        (0..=steps)
            .map(|_| {
                let p = [self.centre[0] + r * c, self.centre[1] + r * s];
                (c, s) = (c * cd - s * sd, s * cd + c * sd);
                p
            })
            .collect()
    }

    /// Λ_h: the taut loop from root `r1` around the beak (turned `turn_rad`
    /// from the catch) and the case outline it has swept, back to root `r2`
    /// (both roots in the hook plane), mm.
    pub fn loop_length(&self, turn_rad: f64, r1: [f64; 2], r2: [f64; 2], buf: &mut Vec<[f64; 2]>) -> f64 {
        let steps = arc_steps(turn_rad);
        let extra = [r1, r2, self.at(self.beak_radius, self.psi(turn_rad))];
        let hull = self
            .pruned_hull_perimeter(turn_rad, steps, extra, buf)
            .unwrap_or_else(|| self.full_hull_perimeter(turn_rad, steps, extra, buf));
        hull - (r2[0] - r1[0]).hypot(r2[1] - r1[1])
    }

    /// The perimeter of the hull of the case's arc (`steps` + 1 points
    /// over `turn_rad`) and the `extra` points, every point of the arc
    /// taken: its x-monotone runs merged with the extra points.
    fn full_hull_perimeter(&self, turn_rad: f64, steps: usize, extra: [[f64; 2]; 3], buf: &mut Vec<[f64; 2]>) -> f64 {
        // The swept outline, in the order the beak passes it.
        let arc = self.case_arc(turn_rad, steps);
        let mut extra = extra;
        extra.sort_by(by_x_then_y);
        merge_arc_runs(&arc, &extra, buf);
        perimeter(&convex_hull_sorted(buf))
    }

    /// [`Self::full_hull_perimeter`] from the few points of the arc that
    /// decide the hull (docs/stitch-formation.md §4.7). The arc's points
    /// lie on the case's circle (centre C, radius R, spacing Δ), so an
    /// extra point p at distance d from C and angle θ_p can only hide the
    /// points within acos(R/d) of θ_p (its cap: past them p lies behind
    /// the circle's tangent), and surely hides those within
    /// acos(R·cos(Δ/2)/d) − Δ/2 of it (p lies past both edges at the
    /// point), so also those within acos(R/d) − Δ/2, a few less. The points
    /// outside every cap stay on the hull, one after the other: a run of
    /// them counts as its chain, k·2R·sin(Δ/2) for k steps, and enters the
    /// hull by its two ends. The points at the caps' edges, on either side
    /// of each extra point's angle and at the arc's ends go to the hull as
    /// they are; the hidden ones are left out. A run spans at most 60°, and
    /// no extra point's angle falls inside it, so nothing but its own chain
    /// lies past its chord. `None` where the arc is too short for this to
    /// pay or turns nearly a full turn (the arc would meet itself).
    fn pruned_hull_perimeter(
        &self,
        turn_rad: f64,
        steps: usize,
        extra: [[f64; 2]; 3],
        buf: &mut Vec<[f64; 2]>,
    ) -> Option<f64> {
        use std::f64::consts::{FRAC_PI_3, TAU};
        const KEPT: u8 = 0;
        const EDGE: u8 = 1;
        const HIDDEN: u8 = 2;
        let delta = turn_rad / steps as f64;
        // (A turn that is not a number has one step.)
        if !(16..=MAX_ARC_STEPS).contains(&steps) || turn_rad >= TAU - 4.0 * delta {
            return None;
        }
        let (c, r) = (self.centre, self.case_radius);
        // Where each arc point stands: kept, at an edge (to the hull as it
        // is) or hidden. Bounds are widened (edges) or narrowed (hidden) by
        // `EPS` of a step, far above the angles' rounding.
        const EPS: f64 = 1e-6;
        let mut states = [KEPT; MAX_ARC_STEPS + 1];
        let state = &mut states[..=steps];
        let mut mark = |lo: isize, hi: isize, to: u8, within: (isize, isize)| {
            let (lo, hi) = (lo.max(within.0), hi.min(within.1));
            if lo <= hi {
                for s in &mut state[lo as usize..=hi as usize] {
                    *s = (*s).max(to);
                }
            }
        };
        let last = steps as isize;
        // Each extra point's hidden points, at each of three turns of its angle.
        let mut hidden = [(1, 0); 9];
        for (p, hidden) in extra.iter().zip(hidden.chunks_exact_mut(3)) {
            let w = [p[0] - c[0], p[1] - c[1]];
            let d = w[0].hypot(w[1]);
            // The point's angle from the catch in the beak's sense, and its
            // cap's half width, in steps. The points it surely hides lie
            // within acos(R·cos(Δ/2)/d) − Δ/2 of it; acos(R/d) − Δ/2 is
            // less (both acos fall with their argument), so it hides no
            // more than p does.
            let sigma = self.sense * (w[1].atan2(w[0]) - self.psi_catch);
            let sigma = sigma - TAU * floor_i(sigma / TAU) as f64;
            let cap = if d > r { Some((r / d).acos() / delta) } else { None };
            for (s, hidden) in [sigma - TAU, sigma, sigma + TAU].into_iter().zip(hidden) {
                let at = s / delta;
                // The points on either side of its own angle (also where it
                // lies inside the circle).
                mark(floor_i(at - EPS), ceil_i(at + EPS), EDGE, (0, last));
                if let Some(alpha) = cap {
                    mark(ceil_i(at - alpha - EPS), floor_i(at + alpha + EPS), EDGE, (0, last));
                    let h = alpha - 0.5;
                    *hidden = (ceil_i(at - h + EPS), floor_i(at + h - EPS));
                }
            }
        }
        for (lo, hi) in hidden {
            mark(lo, hi, HIDDEN, (1, last - 1));
        }
        state[0] = EDGE;
        state[steps] = EDGE;
        let point = |j: usize| {
            let (s, co) = (self.psi_catch + self.sense * j as f64 * delta).sin_cos();
            [c[0] + r * co, c[1] + r * s]
        };
        let link = 2.0 * r * (0.5 * delta).sin();
        let longest = ((FRAC_PI_3 / delta) as usize).max(2);
        buf.clear();
        buf.reserve(64);
        buf.extend_from_slice(&extra);
        let mut chains = 0.0;
        let mut j = 0;
        while j <= steps {
            match state[j] {
                HIDDEN => j += 1,
                EDGE => {
                    buf.push(point(j));
                    j += 1;
                }
                _ => {
                    // A run of kept points, j..=end, as runs of at most `longest` steps.
                    let mut end = j;
                    while end < steps && state[end + 1] == KEPT {
                        end += 1;
                    }
                    let mut a = j;
                    let mut pa = point(a);
                    buf.push(pa);
                    while a < end {
                        let b = (a + longest).min(end);
                        let pb = point(b);
                        if b - a > 1 {
                            chains += (b - a) as f64 * link - (pb[0] - pa[0]).hypot(pb[1] - pa[1]);
                        }
                        buf.push(pb);
                        (a, pa) = (b, pb);
                    }
                    j = end + 1;
                }
            }
        }
        buf.sort_by(by_x_then_y);
        Some(perimeter(&convex_hull_sorted(buf)) + chains)
    }
}

/// Piece of the lockstitch needle-thread contour.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum LockPiece {
    K1,
    K2a,
    K2b,
    K3a,
    K3b,
}

impl LockPiece {
    pub fn id(self) -> &'static str {
        match self {
            LockPiece::K1 => "K1",
            LockPiece::K2a => "K2a",
            LockPiece::K2b => "K2b",
            LockPiece::K3a => "K3a",
            LockPiece::K3b => "K3b",
        }
    }
}

fn hook_err<T>(name: &str, msg: String) -> Result<T, Error> {
    Err(Error::Stitch(StitchError::new(
        format!("needle {name} and the hook"),
        msg,
    )))
}

/// The needle thread of a lockstitch: its needle, the hook, the moments.
#[derive(Debug, Clone)]
pub struct LockstitchThread {
    pub name: String,
    pub line: NeedleLine,
    pub hook: HookGeometry,
    pub feed: Feed,
    /// f: the interlacing's depth below the top face, a fraction of m.
    pub interlace: f64,
    /// φ1: the beak takes the loop, deg.
    pub phi_catch: f64,
    /// φ_K: the loop leaves the hook (the lock), deg.
    pub phi_cast: f64,
    /// φ_out, φ_in: the eye leaves / reaches the material top, deg.
    pub phi_out: f64,
    pub phi_in: f64,
    /// The beak point above the eye at the catch, along the needle, mm.
    pub beak_above_eye: f64,
    pub warnings: Vec<String>,
}

impl LockstitchThread {
    /// Needle `needle` with the hook `hook`, material thickness m, needle
    /// tilt β (deg), interlacing depth f (fraction of m) and the feed.
    pub fn new(
        needle: &NeedleSpec,
        hook: &HookSpec,
        m: f64,
        tilt_deg: f64,
        interlace: f64,
        feed: Feed,
    ) -> Result<LockstitchThread, Error> {
        let name = &needle.name;
        hook.check().or_else(|e| hook_err(name, e))?;
        if !(0.0..=1.0).contains(&interlace) {
            return hook_err(
                name,
                format!("the interlacing depth f = {interlace} must be in [0, 1] (0.5: the balanced stitch)"),
            );
        }
        let mut warnings = Vec::new();
        let (line, phi_out, phi_in) = needle_line(needle, tilt_deg, m, &mut warnings)?;
        // The catch: the needle has risen `catch_rise_mm` from its BDC
        // (φ_c = 0), as the makers' timing gauges set it.
        let rise = |phi: f64| line.s_max - line.travel(phi) - hook.catch_rise_mm;
        // The first half turn from the BDC.
        let Some(phi_catch) = first_crossing(rise, 0.0, 180.0, true) else {
            return hook_err(
                name,
                format!(
                    "the needle never rises {} mm from its BDC in the first half turn; give a smaller catch_rise_mm",
                    hook.catch_rise_mm
                ),
            );
        };
        let eye = line.eye_at_travel(line.travel(phi_catch));
        if eye.z >= 0.0 {
            return hook_err(
                name,
                format!(
                    "the eye is {:.3} mm above the plate top at the catch φ1 = {phi_catch:.2}°, so the hook finds \
                     no loop below the plate; lower the needle",
                    eye.z
                ),
            );
        }
        // The hook's centre: `offset_mm` along the seam from the needle line,
        // `depth_mm` below the plate. The beak meets the needle where its
        // circle crosses the needle line on the way up, N1 + s·u_n with
        // |N1 + s·u_n − C| = R_h, the larger root: s is the beak's height
        // above the eye at the catch.
        let (r_h, d) = (hook.beak_radius_mm, hook.offset_mm);
        let centre = [eye.y + d, -hook.depth_mm];
        let w = [eye.y - centre[0], eye.z - centre[1]];
        let (uy, uz) = (line.u_n.y, line.u_n.z);
        let half_b = w[0] * uy + w[1] * uz;
        let c = w[0] * w[0] + w[1] * w[1] - r_h * r_h;
        let disc = half_b * half_b - c;
        if disc.is_nan() || disc < 0.0 {
            return hook_err(
                name,
                "the beak's circle does not reach the needle line; give a smaller offset_mm or a larger beak_radius_mm"
                    .into(),
            );
        }
        let beak_above_eye = -half_b + disc.sqrt();
        let beak = eye + line.u_n * beak_above_eye;
        let psi_catch = (beak.z - centre[1]).atan2(beak.y - centre[0]);
        // The beak crosses the needle line toward the hook's side (+y when
        // the centre is at +y): clockwise seen along +x for offset > 0.
        let sense = -d.signum();
        let hook_geo = HookGeometry {
            centre,
            beak_radius: r_h,
            case_radius: hook.case_radius_mm,
            psi_catch,
            sense,
        };
        let phi_cast = phi_catch + 0.5 * hook.cast_off_deg;
        if phi_cast >= 360.0 {
            return hook_err(
                name,
                format!(
                    "the loop leaves the hook at φ_c = {phi_cast:.2}°, after the cycle ends; give a smaller cast_off_deg"
                ),
            );
        }
        if phi_cast <= phi_out {
            return hook_err(
                name,
                format!(
                    "the loop leaves the hook (φ_c = {phi_cast:.2}°) before the eye has left the material (φ_out = \
                     {phi_out:.2}°): the loop must hang from hole c when it is pulled up; give a larger cast_off_deg"
                ),
            );
        }
        if phi_cast >= phi_in {
            return hook_err(
                name,
                format!(
                    "the loop leaves the hook (φ_c = {phi_cast:.2}°) after the needle has entered the material again \
                     (φ_in = {phi_in:.2}°); give a smaller cast_off_deg"
                ),
            );
        }
        Ok(LockstitchThread {
            name: name.clone(),
            line,
            hook: hook_geo,
            feed,
            interlace,
            phi_catch,
            phi_cast,
            phi_out,
            phi_in,
            beak_above_eye,
            warnings,
        })
    }

    /// S(φ_c), mm.
    pub fn travel(&self, phi_c: f64) -> f64 {
        self.line.travel(phi_c)
    }

    /// (H_c^t, H_c^b): the ends of hole c, moving with the material by T(φ).
    pub fn hole_c(&self, phi_c: f64) -> (V3<f64>, V3<f64>) {
        let shift = V3::new(0.0, self.feed.at(phi_c), 0.0);
        (self.line.p_top() + shift, self.line.n0 + shift)
    }

    /// The hook's turn since the catch at φ_c, rad (two turns per stitch).
    fn turn(&self, phi_c: f64) -> f64 {
        2.0 * (phi_c - self.phi_catch).to_radians()
    }

    /// Λ_h(φ_c, R1, R2): the loop on the hook, mm.
    pub fn lam(&self, phi_c: f64, r1: &V3<f64>, r2: &V3<f64>) -> f64 {
        let mut buf = Vec::new();
        self.hook
            .loop_length(self.turn(phi_c), [r1.y, r1.z], [r2.y, r2.z], &mut buf)
    }

    /// The loop on the hook with both roots at the bottom of hole c from the
    /// catch to the cast-off, 0 otherwise, mm.
    pub fn loop_on_hook(&self, phi_c: f64) -> f64 {
        if phi_c < self.phi_catch || phi_c >= self.phi_cast {
            return 0.0;
        }
        let (_, h_b) = self.hole_c(phi_c);
        self.lam(phi_c, &h_b, &h_b)
    }

    /// The piece at φ_c (the left one at a moment when `side` is Left).
    pub fn piece(&self, phi_c: f64, side: Side) -> LockPiece {
        let before = |at| before(phi_c, at, side);
        if before(self.phi_catch) {
            LockPiece::K1
        } else if before(self.phi_cast) {
            if before(self.phi_out) {
                LockPiece::K2a
            } else {
                LockPiece::K2b
            }
        } else if before(self.phi_in) {
            LockPiece::K3a
        } else {
            LockPiece::K3b
        }
    }

    /// η_K(φ_c): thread from the eye to the anchor I_{c−1}, mm.
    pub fn eta(&self, phi_c: f64, side: Side) -> f64 {
        self.eta_with(phi_c, side, None)
    }

    /// Per φ_c of `phis`: η (the right limit), the travel S and the loop
    /// on the hook, the loop's hull taken once where η holds the same loop.
    pub fn series(&self, phis: &[f64]) -> (Vec<f64>, Vec<f64>, Vec<f64>) {
        let n = phis.len();
        let (mut eta, mut travel, mut on_hook) = (Vec::with_capacity(n), Vec::with_capacity(n), Vec::with_capacity(n));
        for &phi in phis {
            let lp = self.loop_on_hook(phi);
            let shared = (self.piece(phi, Side::Right) == LockPiece::K2b).then_some(lp);
            eta.push(self.eta_with(phi, Side::Right, shared));
            travel.push(self.travel(phi));
            on_hook.push(lp);
        }
        (eta, travel, on_hook)
    }

    /// [`Self::eta`], with Λ_h(H_c^b, H_c^b) at φ_c when it is known.
    fn eta_with(&self, phi_c: f64, side: Side, loop_hb: Option<f64>) -> f64 {
        let (t, l_m, s_b) = (self.feed.t_mm, self.line.l_m, self.line.s_b);
        let anchor = self.interlace * l_m;
        let s = self.travel(phi_c);
        let n = self.line.eye_at_travel(s);
        let (h_t, h_b) = self.hole_c(phi_c);
        // Up hole c, along the top face to hole c−1 and down to I_{c−1}.
        let tail = l_m + t + anchor;
        match self.piece(phi_c, side) {
            // The eye slides along the loop the needle leaves below the
            // material: η_B = S + η_K stays constant (as N1 of §5.1).
            LockPiece::K1 => (self.line.s_max - s) + (self.line.s_max - s_b) + tail,
            LockPiece::K2a => {
                let (e, r1) = if n.z < 0.0 { (0.0, n) } else { (s_b - s, self.line.n0) };
                e + self.lam(phi_c, &r1, &h_b) + tail
            }
            LockPiece::K2b => (n - h_t).norm() + l_m + loop_hb.unwrap_or_else(|| self.lam(phi_c, &h_b, &h_b)) + tail,
            LockPiece::K3a => (n - h_t).norm() + anchor,
            LockPiece::K3b => (s - self.line.s_top) + (self.line.p_top() - h_t).norm() + anchor,
        }
    }

    /// The thread cut at the lock, from the final nodes: up hole c−1 from
    /// I_{c−1} (f·l_m), along the top face (t), down hole c to I_c (f·l_m).
    pub fn lock_cut(&self) -> f64 {
        let (h_t, h_b) = self.hole_c(self.phi_cast);
        let interlacing = h_t + (h_b - h_t) * self.interlace;
        let h_t_prev = h_t + V3::new(0.0, self.feed.t_mm, 0.0);
        let i_prev = interlacing + V3::new(0.0, self.feed.t_mm, 0.0);
        (i_prev - h_t_prev).norm() + (h_t_prev - h_t).norm() + (h_t - interlacing).norm()
    }

    /// ρ: what the lock releases besides the stitch's thread: the loop on
    /// the hook and the thread below the interlacing in hole c,
    /// Λ_h(φ_K⁻) + 2·(1 − f)·l_m, mm.
    pub fn released(&self) -> f64 {
        let (_, h_b) = self.hole_c(self.phi_cast);
        self.lam(self.phi_cast, &h_b, &h_b) + 2.0 * (1.0 - self.interlace) * self.line.l_m
    }

    /// The moments of this thread in φ_c order.
    pub fn events(&self) -> Vec<(String, f64, EventKind)> {
        let mut ev = vec![
            ("catch by the hook (φ1)".to_string(), self.phi_catch, EventKind::Jump),
            ("eye leaves material (φ_out)".to_string(), self.phi_out, EventKind::Cont),
            ("transport start".to_string(), self.feed.start_deg, EventKind::Cont),
            ("transport end".to_string(), self.feed.end_deg(), EventKind::Cont),
            ("eye enters material (φ_in)".to_string(), self.phi_in, EventKind::Cont),
            (
                "cast off the hook = needle-thread lock (φ_K)".to_string(),
                self.phi_cast,
                EventKind::Lock,
            ),
        ];
        ev.sort_by(|a, b| a.1.total_cmp(&b.1));
        ev
    }

    /// The catch the `hook_clearance` check judges.
    pub fn moments_for_checks(&self) -> super::checks::HookMoments {
        super::checks::HookMoments {
            catch_deg: self.phi_catch,
            beak_above_eye_mm: self.beak_above_eye,
        }
    }

    /// Derived moments of this needle (name, φ_c deg).
    pub fn moments(&self) -> Vec<(String, f64)> {
        let n = &self.name;
        vec![
            (format!("{n}: needle TDC"), self.line.phi_tdc),
            (format!("{n}: catch by the hook"), self.phi_catch),
            (format!("{n}: eye leaves material (φ_out)"), self.phi_out),
            (format!("{n}: cast off the hook = lock"), self.phi_cast),
            (format!("{n}: eye enters material (φ_in)"), self.phi_in),
        ]
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::numeric::uniform;
    use approx::assert_relative_eq;

    #[test]
    fn hull_of_a_square_and_inner_points() {
        let mut pts = vec![[0.0, 0.0], [2.0, 0.0], [2.0, 2.0], [0.0, 2.0], [1.0, 1.0], [0.5, 1.5]];
        assert_relative_eq!(hull_perimeter(&mut pts), 8.0, epsilon = 1e-12);
        let mut two = vec![[0.0, 0.0], [3.0, 4.0]];
        assert_relative_eq!(hull_perimeter(&mut two), 10.0, epsilon = 1e-12);
        let mut one = vec![[1.0, 1.0], [1.0, 1.0]];
        assert_eq!(hull_perimeter(&mut one), 0.0);
    }

    /// The merged runs give the hull the sort gives, to the bit, for arcs
    /// of every length either way round and roots anywhere.
    #[test]
    fn merging_the_arc_runs_is_sorting_them() {
        let mut rnd = uniform(12345u64);
        for _ in 0..200 {
            let hook = HookGeometry {
                centre: [10.0 * rnd() - 5.0, -10.0 * rnd()],
                beak_radius: 8.0 + 4.0 * rnd(),
                case_radius: 6.0 + 2.0 * rnd(),
                psi_catch: 6.0 * rnd(),
                sense: if rnd() < 0.5 { 1.0 } else { -1.0 },
            };
            let turn = 12.0 * rnd();
            let (r1, r2) = ([8.0 * rnd() - 4.0, 4.0 * rnd()], [8.0 * rnd() - 4.0, 4.0 * rnd()]);
            let mut buf = Vec::new();
            let steps = arc_steps(turn);
            let beak = hook.at(hook.beak_radius, hook.psi(turn));
            let merged = hook.full_hull_perimeter(turn, steps, [r1, r2, beak], &mut buf);
            let mut all = vec![r1, r2, beak];
            all.extend(hook.case_arc(turn, steps));
            let sorted = hull_perimeter(&mut all);
            assert_eq!(merged, sorted, "turn {turn}");
            // The turned points stay on the case's circle at their angles.
            let arc = hook.case_arc(turn, steps);
            let exact = hook.at(hook.case_radius, hook.psi(turn));
            assert!((arc[steps][0] - exact[0]).hypot(arc[steps][1] - exact[1]) < 1e-11);
        }
    }

    /// The hull from the arc's deciding points is the hull of every point
    /// of the arc, for arcs up to nearly a full turn either way round, the
    /// roots inside, on and outside the case, near it and far from it.
    /// The two differ only in rounding: the arc's points placed by sine and
    /// cosine instead of by rotation, and a run's chain summed as k equal
    /// links.
    #[test]
    fn the_hull_from_the_deciding_points_is_the_hull_of_the_whole_arc() {
        let mut rnd = uniform(987654321u64);
        let mut pruned = 0;
        let mut worst: f64 = 0.0;
        for case in 0..4000 {
            let hook = HookGeometry {
                centre: [10.0 * rnd() - 5.0, -10.0 * rnd()],
                beak_radius: 6.0 + 8.0 * rnd(),
                case_radius: 6.0 + 2.0 * rnd(),
                psi_catch: 7.0 * rnd() - 0.5,
                sense: if rnd() < 0.5 { 1.0 } else { -1.0 },
            };
            let turn = 6.3 * rnd();
            // A root anywhere in a box around the case, or on its circle,
            // or just outside it.
            let mut root = |k: usize| -> [f64; 2] {
                let a = 7.0 * rnd();
                let radius = match (case + k) % 4 {
                    0 => hook.case_radius,
                    1 => hook.case_radius * (1.0 + 1e-4 * rnd()),
                    2 => hook.case_radius * rnd(),
                    _ => hook.case_radius * (1.0 + 3.0 * rnd()),
                };
                [hook.centre[0] + radius * a.cos(), hook.centre[1] + radius * a.sin()]
            };
            let (r1, r2) = (root(0), root(1));
            let steps = arc_steps(turn);
            let extra = [r1, r2, hook.at(hook.beak_radius, hook.psi(turn))];
            let mut buf = Vec::new();
            let full = hook.full_hull_perimeter(turn, steps, extra, &mut buf);
            if let Some(fast) = hook.pruned_hull_perimeter(turn, steps, extra, &mut buf) {
                pruned += 1;
                worst = worst.max((fast - full).abs());
                assert!((fast - full).abs() < 1e-9, "turn {turn}: {fast} against {full}");
                // It takes far fewer points than the whole arc.
                assert!(buf.len() < steps / 2 + 40, "{} points of {steps}", buf.len());
            }
        }
        assert!(pruned > 3000, "{pruned}");
        assert!(worst < 1e-9, "{worst}");
        // A root inside the case but outside the arc's polygon, between two
        // of its points in the middle of a run: it is on the hull.
        let hook = HookGeometry {
            centre: [0.0, 0.0],
            beak_radius: 13.5,
            case_radius: 11.0,
            psi_catch: 0.0,
            sense: 1.0,
        };
        let turn = 2.5;
        let steps = arc_steps(turn);
        let delta = turn / steps as f64;
        // Beside the catch, away from the far root's cap (21.5°…158.5°).
        let a = 15.5 * delta;
        let rho = 11.0 * (1.0 + (0.5 * delta).cos()) / 2.0;
        let extra = [[rho * a.cos(), rho * a.sin()], [0.0, 30.0], hook.at(13.5, turn)];
        let mut buf = Vec::new();
        let full = hook.full_hull_perimeter(turn, steps, extra, &mut buf);
        let fast = hook
            .pruned_hull_perimeter(turn, steps, extra, &mut buf)
            .expect("a long arc");
        assert!((fast - full).abs() < 1e-9, "{fast} against {full}");
        let inner = [8.0 * 1.25f64.cos(), 8.0 * 1.25f64.sin()];
        let without = hook.full_hull_perimeter(turn, steps, [inner, extra[1], extra[2]], &mut buf);
        assert!(full > without + 1e-8, "{full} {without}");
    }

    #[test]
    fn a_loop_around_the_whole_case_is_the_belt_around_a_point_and_a_disc() {
        // Root 10 mm above the centre of a case of radius 6: the belt is two
        // tangents √(10² − 6²) = 8 and the arc 6·(2π − 2·acos(6/10)).
        let hook = HookGeometry {
            centre: [0.0, 0.0],
            beak_radius: 6.0,
            case_radius: 6.0,
            psi_catch: std::f64::consts::FRAC_PI_2,
            sense: 1.0,
        };
        let mut buf = Vec::new();
        let lam = hook.loop_length(2.0 * std::f64::consts::PI, [0.0, 10.0], [0.0, 10.0], &mut buf);
        let belt = 2.0 * 8.0 + 6.0 * (2.0 * std::f64::consts::PI - 2.0 * (0.6f64).acos());
        assert!((lam - belt).abs() < 1e-3 && lam <= belt, "{lam} {belt}");
        // Before the beak turns, the loop is the thread to the beak and back.
        let lam0 = hook.loop_length(0.0, [0.0, 10.0], [0.0, 10.0], &mut buf);
        assert_relative_eq!(lam0, 8.0, epsilon = 1e-12);
    }

    fn stand_in() -> (crate::stitch::spec::StitchSpec, Vec<f64>) {
        let spec = crate::stitch::reference::lockstitch301(2.0, 2.5);
        (spec, (0..36_000).map(|k| k as f64 * 0.01).collect())
    }

    #[test]
    fn the_lock_cuts_one_stitch_and_the_contour_closes() {
        use crate::stitch::required_take_up::required_take_up;
        let (spec, phis) = stand_in();
        let req = required_take_up(&spec, &phis, 180.0).unwrap();
        let th = &req.threads[0];
        // The thread locked is t + 2·f·l_m = 2.5 + 2·0.5·2 (§6, G7); the
        // contour on its final nodes is the contour just before the lock.
        assert_relative_eq!(th.per_stitch_mm, 4.5, epsilon = 1e-12);
        assert_relative_eq!(th.cut_mm, 4.5, epsilon = 1e-9);
        assert!(th.snap_mm.abs() < 1e-9, "{}", th.snap_mm);
        // η closes over the cycle: the anchor moved on by one stitch.
        let eta = &th.eta_mm;
        assert!(
            (eta[eta.len() - 1] - eta[0]).abs() < 0.01,
            "{} {}",
            eta[0],
            eta[eta.len() - 1]
        );
        // Before the catch the eye slides along the loop: S + η constant.
        let travel = th.travel_mm.as_ref().unwrap();
        for k in (0..2900).step_by(100) {
            assert_relative_eq!(travel[k] + eta[k], travel[0] + eta[0], epsilon = 1e-9);
        }
        // No jump but at the catch and the lock.
        let lock = th.lock_deg;
        let catch = th
            .events
            .iter()
            .find(|e| e.name.starts_with("catch"))
            .unwrap()
            .phi_c_deg;
        for k in 1..eta.len() {
            let near = |at: f64| (phis[k] - at).abs() < 0.02 || (phis[k - 1] - at).abs() < 0.02;
            if !near(catch) && !near(lock) {
                assert!(
                    (eta[k] - eta[k - 1]).abs() < 0.05,
                    "a step at {}: {} → {}",
                    phis[k],
                    eta[k - 1],
                    eta[k]
                );
            }
        }
    }

    /// Union Special's *301 Stitch* manual: about 8.9 cm of needle thread is
    /// carried below the material and around the bobbin for each stitch.
    /// The stand-in's industrial-size hook draws a loop of that size.
    #[test]
    fn the_loop_around_the_bobbin_is_of_the_published_size() {
        use crate::stitch::required_take_up::required_take_up;
        let (spec, phis) = stand_in();
        let th = &required_take_up(&spec, &phis, 180.0).unwrap().threads[0];
        let max_loop = th.loop_mm.as_ref().unwrap().iter().cloned().fold(0.0, f64::max);
        assert!((75.0..100.0).contains(&max_loop), "{max_loop}");
        assert_relative_eq!(max_loop, 83.878, epsilon = 1e-3);
    }

    #[test]
    fn a_hook_that_cannot_work_is_refused() {
        use crate::stitch::required_take_up::required_take_up;
        let (spec, phis) = stand_in();
        let with_hook = |f: &dyn Fn(&mut HookSpec)| {
            let mut s = spec.clone();
            f(s.hook.as_mut().unwrap());
            required_take_up(&s, &phis[..10], 180.0).unwrap_err().to_string()
        };
        assert!(with_hook(&|h| h.offset_mm = 5.0).contains("beside the needle line"));
        assert!(with_hook(&|h| h.cast_off_deg = 90.0).contains("before the eye has left the material"));
        assert!(with_hook(&|h| h.cast_off_deg = 300.0).contains("crosses the needle line again"));
        assert!(with_hook(&|h| h.catch_rise_mm = 40.0).contains("never rises"));
        let mut no_hook = spec.clone();
        no_hook.hook = None;
        assert!(
            required_take_up(&no_hook, &phis[..10], 180.0)
                .unwrap_err()
                .to_string()
                .contains("no hook")
        );
    }
}
