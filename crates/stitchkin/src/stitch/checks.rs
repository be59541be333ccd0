//! Physical checks of a needle thread: what no real machine can do
//! (`docs/stitch-formation.md` §8.4).
//!
//! - `thread_bound`: the thread the take-up passes through B, P_B(φ),
//!   never exceeds what the needle can take through B: twice its deepest
//!   travel below B so far in the cycle (the branch from B down to the eye
//!   and the branch back up to the material) plus the loop on the looper
//!   (or a lockstitch's hook).
//!   More than that can only hang slack.
//! - `catch_clearance`: at the catch φ1 the looper's point passes 1–3 mm
//!   above the needle eye, where the loop forms (seed 004 §2.1: the eye
//!   1.5–2 mm below the looper nose).
//! - `hook_clearance` (lockstitch): at the catch the hook's beak passes
//!   0.5–2.4 mm above the eye, as the makers' timing gauges set it.
//! - `stab_before_drop`: when the needle loop drops off the looper (φ4) the
//!   needle point is already below the looper's upper face, inside the
//!   triangle of the looper thread (seed 004 Table 2: the stab φ3 comes
//!   before the drop φ4).

use serde::Serialize;

/// The catch clearance a looper point must keep above the eye, mm.
pub const CATCH_CLEARANCE_MM: [f64; 2] = [1.0, 3.0];

/// One check of one thread.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Check {
    /// `thread_bound`, `catch_clearance`, `hook_clearance`,
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

/// `thread_bound` over a cycle: the take-up at B `p_b` against `bound`
/// ([`bound_curve`]) at each φ of `phis_deg`; `loop_mm` as for the bound.
/// Judged where P_B comes closest to the bound (or goes furthest beyond it),
/// so `limit − value` is the sweep figure `THR.bound_margin_mm`; the
/// message also names P_B's peak, the thread given at its most.
pub fn thread_bound(thread: &str, phis_deg: &[f64], p_b: &[f64], bound: &[f64], loop_mm: &[f64]) -> Check {
    let n = phis_deg.len().min(p_b.len()).min(bound.len()).min(loop_mm.len());
    let bound_at = bound;
    let first_max = |key: &dyn Fn(usize) -> f64| (0..n).max_by(|&a, &b| key(a).total_cmp(&key(b)).then(b.cmp(&a)));
    let Some(worst) = first_max(&|k| p_b[k] - bound[k]) else {
        return Check {
            name: "thread_bound",
            thread: thread.into(),
            ok: true,
            value: 0.0,
            limit: [None, None],
            unit: "mm",
            at_deg: 0.0,
            message: "no positions to check".into(),
        };
    };
    let peak = first_max(&|k| p_b[k]).unwrap_or(worst);
    let (peak_mm, peak_at) = (p_b[peak], phis_deg[peak].rem_euclid(360.0));
    let k = worst;
    let (value, bound, lp) = (p_b[k], bound[k], loop_mm[k]);
    let at = phis_deg[k].rem_euclid(360.0);
    let ok = value <= bound + 1e-9;
    let parts = |bound: f64, lp: f64| {
        format!(
            "twice the needle's {:.1} mm deepest travel below B so far plus {lp:.1} mm of loop on the looper or hook",
            0.5 * (bound - lp)
        )
    };
    let message = if ok {
        format!(
            "P_B peaks at {peak_mm:.2} mm at φ = {peak_at:.1}°, within the {:.2} mm the needle can take through B there ({}); \
             the least to spare over the cycle is {:.2} mm, at φ = {at:.1}°",
            bound_at[peak],
            parts(bound_at[peak], loop_mm[peak]),
            bound - value
        )
    } else {
        format!(
            "P_B reaches {value:.2} mm at φ = {at:.1}°, {:.2} mm more than the needle can take through B ({bound:.2} mm: {}): \
             the take-up gives thread the stitch can never use, and it hangs slack; the take-up releases while it should draw back \
             (check its phase against the needle)",
            value - bound,
            parts(bound, lp)
        )
    };
    Check {
        name: "thread_bound",
        thread: thread.into(),
        ok,
        value,
        limit: [None, Some(bound)],
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
    let stab_ok = z <= top + 1e-9;
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
        value: z,
        limit: [None, Some(top)],
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
    fn the_bound_is_twice_the_deepest_travel_plus_the_loop() {
        // A needle 10 mm deep at BDC (φ = 180) on a cosine law; the loop of
        // 3 mm is on the looper from 210 to 300.
        let phis: Vec<f64> = (0..360).map(f64::from).collect();
        let s: Vec<f64> = phis.iter().map(|p| 5.0 * (1.0 - p.to_radians().cos())).collect();
        let lp: Vec<f64> = phis
            .iter()
            .map(|&p| if (210.0..300.0).contains(&p) { 3.0 } else { 0.0 })
            .collect();
        // Exactly the bound: ok, nothing to spare at the worst φ.
        let p: Vec<f64> = (0..360)
            .map(|k| 2.0 * if k <= 180 { s[k] } else { 10.0 } + lp[k])
            .collect();
        let bound = bound_curve(&phis, &s, &lp, 0.0);
        let c = thread_bound("n1", &phis, &p, &bound, &lp);
        assert!(c.ok, "{c:?}");
        // Nothing to spare; the peak, 2·10 + 3 mm while the loop is carried.
        assert!(c.limit[1].unwrap() - c.value < 1e-12, "{c:?}");
        assert!(
            c.message
                .starts_with("P_B peaks at 23.00 mm at φ = 210.0°, within the 23.00 mm")
                && c.message.contains("least to spare over the cycle is 0.00 mm"),
            "{}",
            c.message
        );
        // 1 mm too much while the needle descends: fails there, by 1 mm.
        let mut q = p.clone();
        q[90] += 1.0;
        let c = thread_bound("n1", &phis, &q, &bound, &lp);
        assert!(
            !c.ok && c.at_deg == 90.0 && (c.value - c.limit[1].unwrap() - 1.0).abs() < 1e-12,
            "{c:?}"
        );
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
        assert!(!s.ok && s.message.contains("2.70 mm above"), "{}", s.message);
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
