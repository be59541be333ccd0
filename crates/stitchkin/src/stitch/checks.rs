//! Physical checks of a needle thread: what no real machine can do
//! (`docs/stitch-formation.md` §8.4).
//!
//! - `thread_bound`: the thread the take-up passes through B, P_B(φ),
//!   never exceeds what the needle can take through B: twice its deepest
//!   travel below B so far in the cycle (the branch from B down to the eye
//!   and the branch back up to the material) plus the loop on the looper
//!   (or a lockstitch's hook).
//!   More than that can only hang slack. Judged where P_B comes closest to
//!   the bound among the positions where the take-up has given thread
//!   ([`bound_margin`]); its value is the thread to spare there.
//! - `takeup_gives`: while the stitch draws its thread (φ0 to P′'s peak)
//!   the take-up gives at least a quarter of it ([`TAKEUP_SHARE`]): a take-up
//!   that never rises, or runs against P′, leaves the stitch to draw its
//!   loop through the regulator.
//! - `catch_clearance`: at the catch φ1 the looper's point passes 1–3 mm
//!   above the needle eye, where the loop forms (seed 004 §2.1: the eye
//!   1.5–2 mm below the looper nose).
//! - `hook_clearance` (lockstitch): at the catch the hook's beak passes
//!   0.5–2.4 mm above the eye, as the makers' timing gauges set it.
//! - `stab_before_drop`: when the needle loop drops off the looper (φ4) the
//!   needle point is already below the looper's upper face, inside the
//!   triangle of the looper thread (seed 004 Table 2: the stab φ3 comes
//!   before the drop φ4); its value is how far below the face, mm.

use serde::Serialize;

use crate::geometry::since_deg;

/// The catch clearance a looper point must keep above the eye, mm.
pub const CATCH_CLEARANCE_MM: [f64; 2] = [1.0, 3.0];

/// One check of one thread.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Check {
    /// `thread_bound`, `takeup_gives`, `catch_clearance`, `hook_clearance`,
    /// `stab_before_drop`, or from the thread's tension `tension_margin`,
    /// `slack_loop` and `spring_before_slip`.
    pub name: &'static str,
    /// The thread checked (`n1`, `needle`).
    pub thread: String,
    pub ok: bool,
    /// The quantity checked, in `unit`.
    pub value: f64,
    /// Its bounds [lowest, highest] allowed (`None`: no bound that side).
    pub limit: [Option<f64>; 2],
    /// The unit of `value` and `limit`: `mm`, or `1` for a ratio.
    pub unit: &'static str,
    /// The model φ where it is checked (the worst φ of a bound over the
    /// cycle), deg.
    pub at_deg: f64,
    /// What the value means for the machine, and what to change if it fails.
    pub message: String,
}

impl Check {
    /// `value` with its unit, as tables print it: `2.35 mm`, `3.10×` for a
    /// ratio, `n/a` for a check that does not apply (no bounds).
    pub fn value_words(&self) -> String {
        match (self.limit, self.unit) {
            ([None, None], _) => "n/a".into(),
            (_, "1") => format!("{:.2}×", self.value),
            (_, u) => format!("{:.2} {u}", self.value),
        }
    }

    /// How far the value lies beyond its allowed range, in its unit (0
    /// within it).
    pub fn excess(&self) -> f64 {
        let [lo, hi] = self.limit;
        lo.map_or(0.0, |lo| lo - self.value)
            .max(hi.map_or(0.0, |hi| self.value - hi))
            .max(0.0)
    }

    /// The allowed range with its unit: `1…3 mm`, `≤ -4.00 mm`, `≥ 3.00×`,
    /// or `—` without bounds.
    pub fn limit_words(&self) -> String {
        let u = |x: f64| match self.unit {
            "1" => format!("{x:.2}×"),
            u => format!("{x:.2} {u}"),
        };
        match self.limit {
            [Some(a), Some(b)] if self.unit == "1" => format!("{a}…{b}×"),
            [Some(a), Some(b)] => format!("{a}…{b} {}", self.unit),
            [None, Some(b)] => format!("≤ {}", u(b)),
            [Some(a), None] => format!("≥ {}", u(a)),
            [None, None] => "—".into(),
        }
    }
}

/// The geometry of a needle thread's catch and drop that the checks need,
/// from the stitch process (cyclogram angles φ_c, stitch frame).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct NeedleMoments {
    /// The catch φ1, deg.
    pub catch_deg: f64,
    /// Height of the looper's catching point above the needle eye at the
    /// catch, mm.
    pub looper_above_eye_mm: f64,
    /// The drop φ4, deg.
    pub drop_deg: f64,
    /// Height of the needle point above the plate top at the drop, mm.
    pub point_z_at_drop_mm: f64,
    /// Height of the looper's upper face above the plate top, −k, mm.
    pub looper_top_z_mm: f64,
}

/// The beak's height above the needle eye at a lockstitch's catch that the
/// hook makers' timing gauges set, mm (Brother S-7000DD 0.5–0.7, Juki
/// LU-2210N-7 1.4 ± 0.2, Consew 255RB-3 2.4; docs/references.md).
pub const HOOK_CLEARANCE_MM: [f64; 2] = [0.5, 2.4];

/// The catch of a lockstitch's hook, for `hook_clearance`.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct HookMoments {
    /// The catch φ1, deg (cyclogram).
    pub catch_deg: f64,
    /// The beak point above the eye there, along the needle, mm.
    pub beak_above_eye_mm: f64,
}

/// `hook_clearance`: at the catch the beak passes within the makers' range
/// above the eye, where the loop has formed.
pub fn hook_clearance(thread: &str, m: &HookMoments, from_c: impl Fn(f64) -> f64) -> Check {
    let [lo, hi] = HOOK_CLEARANCE_MM;
    let (h, at) = (m.beak_above_eye_mm, from_c(m.catch_deg));
    let ok = (lo..=hi).contains(&h);
    let message = if ok {
        format!(
            "at the catch (φ = {at:.1}°) the hook's beak passes {h:.2} mm above the eye, within {lo}–{hi} mm: it enters the loop"
        )
    } else if h < lo {
        format!(
            "at the catch (φ = {at:.1}°) the hook's beak passes {} the eye ({h:+.2} mm; {lo}–{hi} mm above it wanted): it can \
             miss the loop and skip stitches; set the needle bar lower, or time the hook later",
            if h < 0.0 { "below" } else { "too close above" }
        )
    } else {
        format!(
            "at the catch (φ = {at:.1}°) the hook's beak passes {h:.2} mm above the eye ({lo}–{hi} mm wanted), above the loop: it can \
             miss it and skip stitches; set the needle bar higher, or time the hook earlier"
        )
    };
    Check {
        name: "hook_clearance",
        thread: thread.into(),
        ok,
        value: h,
        limit: [Some(lo), Some(hi)],
        unit: "mm",
        at_deg: at,
        message,
    }
}

/// The most thread the needle can take through B at each φ of the model
/// grid `phis_deg`, mm: 2·S_deepest(φ) + Λ(φ), with S the needle's travel
/// below B (`travel`), S_deepest its largest value since φ0 (where P = 0:
/// the taut state at the needle's TDC) in the cycle's order, and Λ the loop
/// on the looper (`loop_mm`).
pub fn bound_curve(phis_deg: &[f64], travel: &[f64], loop_mm: &[f64], phi0_deg: f64) -> Vec<f64> {
    let n = phis_deg.len().min(travel.len()).min(loop_mm.len());
    let since = |k: usize| (phis_deg[k] - phi0_deg).rem_euclid(360.0);
    let mut order: Vec<usize> = (0..n).collect();
    order.sort_by(|&a, &b| since(a).total_cmp(&since(b)));
    let mut bound = vec![0.0; n];
    let mut deepest = 0.0f64;
    for k in order {
        deepest = deepest.max(travel[k]);
        bound[k] = 2.0 * deepest + loop_mm[k];
    }
    bound
}

/// Thread given below this, mm, counts as none for `thread_bound`: a tenth
/// of a millimetre forms no loop that could hang slack, and a scale on the
/// take-up reads no finer. P_B is 0 at φ0 by its definition and rises from
/// it as the square of the angle, so a smaller figure (1 µm) let a position
/// 2° from φ0 stand for the check on the Altin 504 (0.004 mm given, the
/// margin the loop on the looper there, as at φ0).
pub const GIVEN_MM: f64 = 0.1;

/// Where `thread_bound` is judged: the position k, of the cycle's grid,
/// where the thread given through B comes closest to the bound (or goes
/// furthest past it) among those where it can bind, and the margin
/// bound − P_B there, mm.
///
/// The bound can bind only where the take-up has given thread (P_B >
/// [`GIVEN_MM`]): where it has drawn thread back, none can hang slack. Of
/// those positions the check takes the margin's local minima (each the
/// closest approach of one stretch of the cycle, neighbours taken round
/// the cycle), not the ends of a stretch that begins at φ0: there P_B is 0
/// by its definition and the margin is the loop already on the looper, the
/// same at every setting. Where no local minimum lies in such a stretch,
/// the least margin of the stretch; `None` where the take-up gives no
/// thread at all.
pub fn bound_margin(p_b: &[f64], bound: &[f64]) -> Option<(usize, f64)> {
    let n = p_b.len().min(bound.len());
    let margin = |k: usize| bound[k] - p_b[k];
    // The least margin (the first of equals) where the take-up gives
    // thread at a local minimum of the margin, and anywhere it gives thread.
    let mut at_local: Option<(usize, f64)> = None;
    let mut anywhere: Option<(usize, f64)> = None;
    let lower = |best: Option<(usize, f64)>, m: f64| best.is_none_or(|(_, b)| m.total_cmp(&b).is_lt());
    for k in 0..n {
        if p_b[k] <= GIVEN_MM || p_b[k].is_nan() {
            continue;
        }
        let m = margin(k);
        if lower(anywhere, m) {
            anywhere = Some((k, m));
        }
        let (before, after) = (if k == 0 { n - 1 } else { k - 1 }, if k + 1 == n { 0 } else { k + 1 });
        if m <= margin(before) && m <= margin(after) && lower(at_local, m) {
            at_local = Some((k, m));
        }
    }
    at_local.or(anywhere)
}

/// The figure `THR.bound_margin_mm`, mm: the margin where the take-up comes
/// closest to the bound ([`bound_margin`]), or where it gives no thread the
/// least margin over the cycle (0 for no positions).
pub fn bound_margin_mm(p_b: &[f64], bound: &[f64]) -> f64 {
    bound_margin(p_b, bound).map_or_else(
        || {
            let least = bound.iter().zip(p_b).map(|(b, p)| b - p).fold(f64::INFINITY, f64::min);
            if least.is_finite() { least } else { 0.0 }
        },
        |(_, m)| m,
    )
}

/// `thread_bound` over a cycle: the take-up at B `p_b` against `bound`
/// ([`bound_curve`]) at each φ of `phis_deg`; `loop_mm` as for the bound.
/// Its value is the thread to spare, bound − P_B, where the take-up comes
/// closest to the bound ([`bound_margin`]; the sweep figure
/// `THR.bound_margin_mm`), at least 0 allowed; the message also names P_B's
/// peak, the thread given at its most.
pub fn thread_bound(thread: &str, phis_deg: &[f64], p_b: &[f64], bound: &[f64], loop_mm: &[f64]) -> Check {
    let n = phis_deg.len().min(p_b.len()).min(bound.len()).min(loop_mm.len());
    let (p_b, bound, loop_mm) = (&p_b[..n], &bound[..n], &loop_mm[..n]);
    let check = |ok: bool, value: f64, limit: [Option<f64>; 2], at_deg: f64, message: String| Check {
        name: "thread_bound",
        thread: thread.into(),
        ok,
        value,
        limit,
        unit: "mm",
        at_deg,
        message,
    };
    let Some((k, spare)) = bound_margin(p_b, bound) else {
        return check(
            true,
            bound_margin_mm(p_b, bound),
            [None, None],
            phis_deg.first().copied().unwrap_or(0.0),
            "the take-up never gives thread through B past its state at φ0 (P_B ≤ 0 over the whole cycle), so none can \
             hang slack; whether it gives the stitch enough is `takeup_gives`"
                .into(),
        );
    };
    let peak = (0..n)
        .max_by(|&a, &b| p_b[a].total_cmp(&p_b[b]).then(b.cmp(&a)))
        .unwrap_or(k);
    let at = phis_deg[k].rem_euclid(360.0);
    let ok = spare >= -1e-9;
    let parts = |k: usize| {
        format!(
            "twice the needle's {:.1} mm deepest travel below B so far plus {:.1} mm of loop on the looper or hook",
            0.5 * (bound[k] - loop_mm[k]),
            loop_mm[k]
        )
    };
    let message = if ok {
        format!(
            "P_B comes closest to what the needle can take through B at φ = {at:.1}°: {:.2} mm given of {:.2} mm ({}), \
             {spare:.2} mm to spare; P_B peaks at {:.2} mm at φ = {:.1}° (of {:.2} mm there)",
            p_b[k],
            bound[k],
            parts(k),
            p_b[peak],
            phis_deg[peak].rem_euclid(360.0),
            bound[peak]
        )
    } else {
        format!(
            "P_B reaches {:.2} mm at φ = {at:.1}°, {:.2} mm more than the needle can take through B ({:.2} mm: {}): \
             the take-up gives thread the stitch can never use, and it hangs slack; the take-up releases while it should draw back \
             (check its phase against the needle)",
            p_b[k],
            -spare,
            bound[k],
            parts(k)
        )
    };
    check(ok, spare, [Some(0.0), None], at, message)
}

/// The least share of the stitch's peak need, P′'s largest value, that a
/// take-up must give while the stitch draws its thread (`takeup_gives`).
///
/// Below it the stitch takes nearly all of its loop through the
/// regulator's discs against their hold, while the loop forms: the loop
/// comes out tight and short and the looper can miss it, and the thread's
/// tension rises. The quarter is stitchkin's decision, no source gives one:
/// every preset's default gives 62–97 %, each of O2B, z, Δφ and r2 at the
/// ends of seed 000's Table 3 ranges 26 % and more, and a take-up that
/// gives next to nothing (the MF-7923D at r1 = 5 mm: 5 % to needle 3; at
/// 6 mm: 0–2 %) fails. Half would also fail z = 10 mm (27 and 32 %).
pub const TAKEUP_SHARE: f64 = 0.25;

/// What a take-up gives while the stitch draws its thread
/// ([`takeup_gives`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Given {
    /// Where P′ peaks (the end of the drawing phase), and its value, mm.
    pub k_need: usize,
    pub need_mm: f64,
    /// Where P is largest in the drawing phase, and the thread it gives
    /// there (P, not below 0), mm.
    pub k_give: usize,
    pub given_mm: f64,
}

impl Given {
    /// The stitch's drawing phase runs from φ0 (`phi0_deg`, where P = P′ =
    /// 0) to P′'s peak in the cycle's order; `None` for no positions.
    pub fn of(phis_deg: &[f64], p: &[f64], pprime: &[f64], phi0_deg: f64) -> Option<Given> {
        let n = phis_deg.len().min(p.len()).min(pprime.len());
        let since = |k: usize| since_deg(phis_deg[k], phi0_deg);
        // The largest of `key` over `ks`, the earliest after φ0 among equals
        // (read only where the key ties).
        let first_max = |ks: &mut dyn Iterator<Item = usize>, key: &[f64]| {
            let mut best: Option<usize> = None;
            for k in ks {
                best = match best {
                    None => Some(k),
                    Some(b) => match key[k].total_cmp(&key[b]) {
                        std::cmp::Ordering::Greater => Some(k),
                        std::cmp::Ordering::Equal if since(k) <= since(b) => Some(k),
                        _ => Some(b),
                    },
                };
            }
            best
        };
        let k_need = first_max(&mut (0..n), pprime)?;
        let until = since(k_need);
        let k_give = first_max(&mut (0..n).filter(|&k| since(k) <= until), p).unwrap_or(k_need);
        Some(Given {
            k_need,
            need_mm: pprime[k_need],
            k_give,
            given_mm: p[k_give].max(0.0),
        })
    }

    /// The least the take-up must give, mm.
    pub fn wanted_mm(&self) -> f64 {
        TAKEUP_SHARE * self.need_mm
    }

    pub fn ok(&self) -> bool {
        self.need_mm <= 0.0 || self.given_mm >= self.wanted_mm()
    }
}

/// `takeup_gives`: the take-up gives thread while the stitch draws it. The
/// value is the most thread the take-up gives in the stitch's drawing
/// phase ([`Given`]), mm, against at least [`TAKEUP_SHARE`] of P′'s peak.
/// A P that never rises, or that rises only after the stitch has drawn its
/// thread, fails.
pub fn takeup_gives(thread: &str, phis_deg: &[f64], p: &[f64], pprime: &[f64], phi0_deg: f64) -> Check {
    let Some(g) = Given::of(phis_deg, p, pprime, phi0_deg) else {
        return Check {
            name: "takeup_gives",
            thread: thread.into(),
            ok: true,
            value: 0.0,
            limit: [None, None],
            unit: "mm",
            at_deg: phi0_deg,
            message: "no positions to check".into(),
        };
    };
    let (need, given, ok) = (g.need_mm, g.given_mm, g.ok());
    let share = if need > 0.0 { 100.0 * given / need } else { 100.0 };
    let (from, peak_at, at) = (
        phi0_deg.rem_euclid(360.0),
        phis_deg[g.k_need].rem_euclid(360.0),
        phis_deg[g.k_give].rem_euclid(360.0),
    );
    let wanted = 100.0 * TAKEUP_SHARE;
    let message = if ok {
        format!(
            "while the stitch draws its thread (φ = {from:.1}° to P′'s peak of {need:.2} mm at φ = {peak_at:.1}°) the take-up \
             gives up to {given:.2} mm (at φ = {at:.1}°), {share:.0} % of it (at least {wanted:.0} % wanted)"
        )
    } else {
        format!(
            "while the stitch draws its thread (φ = {from:.1}° to P′'s peak of {need:.2} mm at φ = {peak_at:.1}°) the take-up \
             gives at most {given:.2} mm, {share:.0} % of it (at least {wanted:.0} % wanted; P is {:.2} mm at the peak): the \
             stitch draws nearly all its loop through the regulator against its hold, so the loop forms tight and short, the \
             looper can miss it (skipped stitches) and the tension rises; check the take-up's stroke and its phase against the \
             needle's: it should release thread as the needle goes down",
            p[g.k_need]
        )
    };
    Check {
        name: "takeup_gives",
        thread: thread.into(),
        ok,
        value: given,
        limit: [Some(g.wanted_mm()), None],
        unit: "mm",
        at_deg: at,
        message,
    }
}

/// `catch_clearance` and `stab_before_drop` of one needle thread;
/// `from_c` turns a cyclogram angle into the model's φ.
pub fn catch_and_stab(thread: &str, m: &NeedleMoments, from_c: impl Fn(f64) -> f64) -> [Check; 2] {
    let [lo, hi] = CATCH_CLEARANCE_MM;
    let h = m.looper_above_eye_mm;
    let at = from_c(m.catch_deg);
    let catch_ok = (lo..=hi).contains(&h);
    let message = if catch_ok {
        format!(
            "at the catch (φ = {at:.1}°) the looper point passes {h:.2} mm above the eye, within {lo}–{hi} mm: it enters the loop"
        )
    } else if h < lo {
        format!(
            "at the catch (φ = {at:.1}°) the looper point passes {} the eye ({h:+.2} mm; {lo}–{hi} mm above it wanted): it can miss \
             the loop, which forms above the eye, and skip stitches; set the needle lower in its bar, or catch earlier",
            if h < 0.0 { "below" } else { "too close above" }
        )
    } else {
        format!(
            "at the catch (φ = {at:.1}°) the looper point passes {h:.2} mm above the eye ({lo}–{hi} mm wanted), above where the loop \
             has formed: it can miss it and skip stitches; set the needle higher in its bar, or catch later"
        )
    };
    let catch = Check {
        name: "catch_clearance",
        thread: thread.into(),
        ok: catch_ok,
        value: h,
        limit: [Some(lo), Some(hi)],
        unit: "mm",
        at_deg: at,
        message,
    };
    let (z, top) = (m.point_z_at_drop_mm, m.looper_top_z_mm);
    let at = from_c(m.drop_deg);
    let stab_ok = top - z >= -1e-9;
    let message = if stab_ok {
        format!(
            "when its loop drops (φ = {at:.1}°) the needle point is {:.2} mm below the looper's upper face: the needle has entered \
             the looper thread's triangle first",
            top - z
        )
    } else {
        format!(
            "when its loop drops (φ = {at:.1}°) the needle point is still {:.2} mm above the looper's upper face: the loop leaves the \
             looper before the needle has entered the looper thread's triangle, so the chain breaks (skipped stitch); set the needle \
             lower, or let the looper hold the loop longer",
            z - top
        )
    };
    let stab = Check {
        name: "stab_before_drop",
        thread: thread.into(),
        ok: stab_ok,
        value: top - z,
        limit: [Some(0.0), None],
        unit: "mm",
        at_deg: at,
        message,
    };
    [catch, stab]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_bound_margin_is_the_least_local_minimum_of_a_given_stretch() {
        // The reference, written as the words of `bound_margin` read.
        let reference = |p_b: &[f64], bound: &[f64]| {
            let n = p_b.len();
            let margin = |k: usize| bound[k] - p_b[k];
            let least = |ks: Vec<usize>| {
                ks.into_iter()
                    .map(|k| (k, margin(k)))
                    .min_by(|a, b| a.1.total_cmp(&b.1).then(a.0.cmp(&b.0)))
            };
            let given: Vec<usize> = (0..n).filter(|&k| p_b[k] > GIVEN_MM).collect();
            let local = given
                .iter()
                .copied()
                .filter(|&k| margin(k) <= margin((k + n - 1) % n) && margin(k) <= margin((k + 1) % n))
                .collect();
            least(local).or_else(|| least(given))
        };
        let mut seed = 11u64;
        let mut draw = || {
            seed = seed.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
            ((seed >> 33) % 7) as f64 - 2.0
        };
        for n in [1usize, 2, 3, 5, 12, 36] {
            for _ in 0..300 {
                let p_b: Vec<f64> = (0..n).map(|_| draw()).collect();
                let bound: Vec<f64> = (0..n).map(|_| draw() + 3.0).collect();
                assert_eq!(bound_margin(&p_b, &bound), reference(&p_b, &bound), "{p_b:?} {bound:?}");
            }
        }
    }

    #[test]
    fn the_drawing_phase_takes_the_first_of_equal_peaks() {
        // The reference: `max_by` with the ties broken toward φ0, as
        // written in words on `Given::of`.
        let reference = |phis: &[f64], key: &[f64], ks: &[usize], phi0: f64| {
            let since = |k: usize| (phis[k] - phi0).rem_euclid(360.0);
            ks.iter()
                .copied()
                .max_by(|&a, &b| key[a].total_cmp(&key[b]).then(since(b).total_cmp(&since(a))))
        };
        let phis: Vec<f64> = (0..72).map(|k| 5.0 * k as f64).collect();
        let mut seed = 7u64;
        for round in 0..400 {
            // Values on a coarse ladder, so peaks tie often.
            let mut draw = || {
                seed = seed.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
                ((seed >> 33) % 6) as f64
            };
            let p: Vec<f64> = (0..72).map(|_| draw()).collect();
            let pprime: Vec<f64> = (0..72).map(|_| draw()).collect();
            let phi0 = (round % 72) as f64 * 5.0 + if round % 3 == 0 { 2.5 } else { 0.0 };
            let g = Given::of(&phis, &p, &pprime, phi0).unwrap();
            let all: Vec<usize> = (0..72).collect();
            let k_need = reference(&phis, &pprime, &all, phi0).unwrap();
            let until = (phis[k_need] - phi0).rem_euclid(360.0);
            let drawing: Vec<usize> = all
                .iter()
                .copied()
                .filter(|&k| (phis[k] - phi0).rem_euclid(360.0) <= until)
                .collect();
            let k_give = reference(&phis, &p, &drawing, phi0).unwrap_or(k_need);
            assert_eq!((g.k_need, g.k_give), (k_need, k_give), "round {round}");
        }
    }

    #[test]
    fn the_bound_is_twice_the_deepest_travel_plus_the_loop() {
        // A needle 10 mm deep at BDC (φ = 180) on a cosine law; the loop of
        // 3 mm is on the looper from 210 to 300.
        let phis: Vec<f64> = (0..360).map(f64::from).collect();
        let s: Vec<f64> = phis.iter().map(|p| 5.0 * (1.0 - p.to_radians().cos())).collect();
        let lp: Vec<f64> = phis
            .iter()
            .map(|&p| if (210.0..300.0).contains(&p) { 3.0 } else { 0.0 })
            .collect();
        // Exactly the bound: ok, nothing to spare where it binds.
        let p: Vec<f64> = (0..360)
            .map(|k| 2.0 * if k <= 180 { s[k] } else { 10.0 } + lp[k])
            .collect();
        let bound = bound_curve(&phis, &s, &lp, 0.0);
        let c = thread_bound("n1", &phis, &p, &bound, &lp);
        assert!(c.ok && c.value.abs() < 1e-12 && c.limit == [Some(0.0), None], "{c:?}");
        assert!(
            c.message.contains("0.00 mm to spare") && c.message.contains("P_B peaks at 23.00 mm at φ = 210.0°"),
            "{}",
            c.message
        );
        // 1 mm too much while the needle descends: fails there, by 1 mm.
        let mut q = p.clone();
        q[90] += 1.0;
        let c = thread_bound("n1", &phis, &q, &bound, &lp);
        assert!(!c.ok && c.at_deg == 90.0 && (c.value + 1.0).abs() < 1e-12, "{c:?}");
        assert!(
            c.message.contains("slack") && c.message.contains("phase"),
            "{}",
            c.message
        );
        // After BDC the loop held below the material counts: 2·10 mm stay
        // allowed while the needle rises.
        let c = thread_bound("n1", &phis, &vec![19.0; 360], &bound, &lp);
        assert!(!c.ok && c.at_deg == 0.0, "near TDC 19 mm is too much: {c:?}");
        let mut r = vec![0.0; 360];
        r[200] = 19.0;
        assert!(thread_bound("n1", &phis, &r, &bound, &lp).ok);
        // Counted from φ0: with φ0 = 180 the deepest travel is 10 at once.
        let from_bdc = bound_curve(&phis, &s, &lp, 180.0);
        assert_eq!(from_bdc[90], 20.0);
        assert!(thread_bound("n1", &phis, &vec![20.0; 360], &from_bdc, &lp).ok);
        assert!(!thread_bound("n1", &phis, &vec![20.0; 360], &bound, &lp).ok);
    }

    /// The margin is judged where the take-up gives thread, away from φ0,
    /// where P_B = 0 and the margin is the loop already on the looper.
    #[test]
    fn the_bound_is_judged_where_the_take_up_gives_thread() {
        let phis: Vec<f64> = (0..360).map(f64::from).collect();
        // 18 mm of loop on the looper at φ0, a bound that grows to 40 mm by
        // 60° and stays; the take-up gives a hump of 11 mm at 120°.
        let bound: Vec<f64> = phis
            .iter()
            .map(|&f| 18.0 + 22.0 * (f.min(360.0 - f) / 60.0).min(1.0))
            .collect();
        let p: Vec<f64> = phis
            .iter()
            .map(|&f| 11.0 * (-((f - 120.0) / 30.0).powi(2)).exp())
            .collect();
        let (k, spare) = bound_margin(&p, &bound).unwrap();
        let c = thread_bound("n1", &phis, &p, &bound, &vec![0.0; 360]);
        assert!(c.ok && c.value == spare && c.at_deg == phis[k], "{c:?}");
        // Not the 18 mm at φ0: the closest approach while thread is given.
        assert!(k == 120 && (spare - 29.0).abs() < 1e-12, "{k} {spare}");
        assert!(c.message.contains(&format!("{spare:.2} mm to spare")), "{}", c.message);
        // A take-up that gives nothing cannot overfill: n/a, passes.
        let none = vec![-1.0; 360];
        assert_eq!(bound_margin(&none, &bound), None);
        let c = thread_bound("n1", &phis, &none, &bound, &vec![0.0; 360]);
        assert!(
            c.ok && c.limit == [None, None] && c.message.contains("never gives thread"),
            "{c:?}"
        );
    }

    #[test]
    fn a_take_up_must_give_thread_while_the_stitch_draws_it() {
        let phis: Vec<f64> = (0..360).map(f64::from).collect();
        // P′ rises to 12 mm at 150°, then falls back.
        let pprime: Vec<f64> = phis
            .iter()
            .map(|&f| 12.0 * (std::f64::consts::PI * f / 300.0).sin().max(0.0))
            .collect();
        let follows: Vec<f64> = pprime.iter().map(|v| 0.9 * v).collect();
        let c = takeup_gives("n2", &phis, &follows, &pprime, 0.0);
        assert!(
            c.ok && (c.value - 10.8).abs() < 1e-9 && c.limit == [Some(3.0), None],
            "{c:?}"
        );
        assert!(
            c.message.contains("90 %") && c.message.contains("at least 25 % wanted"),
            "{}",
            c.message
        );
        // A take-up that never rises: fails, value 0.
        let never: Vec<f64> = pprime.iter().map(|v| -v).collect();
        let c = takeup_gives("n2", &phis, &never, &pprime, 0.0);
        assert!(!c.ok && c.value == 0.0 && c.message.contains("regulator"), "{c:?}");
        // One that gives its thread only after the stitch has drawn it
        // (runs against P′ while it rises): fails too.
        let late: Vec<f64> = phis
            .iter()
            .map(|&f| if f > 200.0 { 12.0 } else { -0.5 * f / 200.0 })
            .collect();
        let c = takeup_gives("n2", &phis, &late, &pprime, 0.0);
        assert!(!c.ok, "{c:?}");
        // The drawing phase is counted from φ0 round the cycle.
        let shifted: Vec<f64> = (0..360).map(|k| pprime[(k + 180) % 360]).collect();
        let p_shifted: Vec<f64> = (0..360).map(|k| follows[(k + 180) % 360]).collect();
        assert!(takeup_gives("n2", &phis, &p_shifted, &shifted, 180.0).ok);
    }

    #[test]
    fn catch_and_stab_limits() {
        let m = NeedleMoments {
            catch_deg: 30.0,
            looper_above_eye_mm: 2.0,
            drop_deg: 300.0,
            point_z_at_drop_mm: -6.0,
            looper_top_z_mm: -4.0,
        };
        let from_c = |p: f64| p + 180.0;
        let [c, s] = catch_and_stab("n1", &m, from_c);
        assert!(c.ok && s.ok && c.at_deg == 210.0 && s.at_deg == 480.0);
        // The value is the figure of the message: 2 mm below the face.
        assert!(
            s.value == 2.0 && s.limit == [Some(0.0), None] && s.message.contains("2.00 mm below"),
            "{s:?}"
        );
        assert_eq!(c.limit, [Some(1.0), Some(3.0)]);
        let [c, s] = catch_and_stab(
            "n1",
            &NeedleMoments {
                looper_above_eye_mm: -0.8,
                point_z_at_drop_mm: -1.3,
                ..m
            },
            from_c,
        );
        assert!(!c.ok && c.message.contains("below the eye"), "{}", c.message);
        assert!(
            !s.ok && s.message.contains("2.70 mm above") && (s.value + 2.7).abs() < 1e-12,
            "{s:?}"
        );
        let [c, _] = catch_and_stab(
            "n1",
            &NeedleMoments {
                looper_above_eye_mm: 6.0,
                ..m
            },
            from_c,
        );
        assert!(!c.ok && c.message.contains("higher"), "{}", c.message);
    }
}
