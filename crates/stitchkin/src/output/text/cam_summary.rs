//! A synthesised thread feed cam ([`crate::study::cam_synthesis`]): the
//! summary of its profile, verification and checks.

use crate::format::{dec4_or_sci, fmt_num};
use crate::study::cam_synthesis::{CamSynthesis, Verification};

/// The smoothing line of a synthesis summary: the moving average over
/// `smooth_deg` of `angle` ("profile angle", "cam angle"), or none.
pub(crate) fn smoothing_line(smooth_deg: f64, angle: &str) -> String {
    if smooth_deg > 0.0 {
        format!(
            "# smoothing: moving average over {}° of {angle}, applied twice\n",
            fmt_num(smooth_deg)
        )
    } else {
        "# smoothing: none\n".to_string()
    }
}

/// The verification's error line: the largest |P − target| at the knots
/// and between them, beside the model's `own` cam or lift.
pub(crate) fn max_error_line(v: &Verification, own: &str) -> String {
    format!(
        "#   max |P − target| {} mm at the knots (φ = {:.1}°), {} mm between them (φ = {:.1}°); the model's own {own}: {} mm\n",
        dec4_or_sci(v.max_err_knots_mm),
        v.max_err_knots_at_deg,
        dec4_or_sci(v.max_err_between_mm),
        v.max_err_between_at_deg,
        dec4_or_sci(v.max_err_before_mm)
    )
}

/// The summary of a synthesised cam, `# `-lines: the path and cam, the
/// knots and radii, the anchor, the smoothing, the verification (the model
/// evaluated again with the new profile), the checks, the notes and the
/// files `written`.
pub fn summary(s: &CamSynthesis) -> String {
    let v = &s.verify;
    let c = &s.checks;
    let n = s.knots.len();
    let mut r = format!(
        "# cam synthesis: thread path `{}`, cam `{}` (contact = \"offset\", γ = {:.2}°, {} §2.5)\n# target: {}\n",
        s.path,
        s.cam,
        s.gamma_deg,
        crate::references::cite(4),
        s.target
    );
    r += &format!(
        "# {n} knots: the contact angles at φ = {}° + k·{}°; radius {:.3}…{:.3} mm (the model's profile: {:.3}…{:.3} mm)\n",
        fmt_num(s.phi0_deg),
        fmt_num(360.0 / n as f64),
        s.radius_mm[0],
        s.radius_mm[1],
        s.reference_radius_mm[0],
        s.reference_radius_mm[1]
    );
    r += &format!(
        "# anchor: ρ = {:.4} mm at θ = {:.2}°, the contact at φ0 = {}° where P is fixed by its convention\n",
        s.anchor_radius_mm,
        s.anchor_theta_deg,
        fmt_num(s.phi0_deg)
    );
    r += &smoothing_line(s.smooth_deg, "profile angle");
    r += "# verify (the model evaluated again with the new profile as a polar cam):\n";
    r += &max_error_line(v, "cam");
    if let (Some(t), Some(b), Some(a), Some(f)) = (&s.thread, &v.match_before, &v.match_after, &v.match_after_all) {
        let sc = |x: Option<f64>| x.map_or("—".to_string(), |x| format!("{x:.1}"));
        r += &format!(
            "#   match of thread `{t}` (docs/stitch-formation.md §8, on the knots' φ): score {} → {}, RMS(P − P') {:.4} → {:.4} mm; with the midpoints: score {}, RMS {:.4} mm\n",
            sc(b.score),
            sc(a.score),
            b.rms_d_mm,
            a.rms_d_mm,
            sc(f.score),
            f.rms_d_mm
        );
    }
    r += "# checks (reported, not fixed):\n";
    r += &format!(
        "#   min radius     {:.3} mm at θ = {:.1}° (limit {} mm): {}\n",
        c.min_radius_mm,
        c.min_radius_at_theta_deg,
        fmt_num(c.min_radius_limit_mm),
        if c.min_radius_ok { "ok" } else { "TOO SMALL" }
    );
    if c.convex {
        r += "#   convex         yes (what contact = \"exact\" would need)\n";
    } else {
        let total: f64 = c.not_convex_deg.iter().map(|i| i[1] - i[0]).sum();
        let list: Vec<String> = c
            .not_convex_deg
            .iter()
            .take(4)
            .map(|i| format!("{:.1}°…{:.1}°", i[0], i[1].rem_euclid(360.0)))
            .collect();
        r += &format!(
            "#   convex         NO: {} stretch(es) of θ, {:.1}° in all ({}{}); the offset contact does not need it, a taut thread (contact = \"exact\") would bridge them\n",
            c.not_convex_deg.len(),
            total,
            list.join(", "),
            if c.not_convex_deg.len() > 4 { ", …" } else { "" }
        );
    }
    r += &format!(
        "#   profile slope  max {:.1}° at θ = {:.1}° (atan(|ρ'|/ρ): the angle between the radius and the profile normal)\n",
        c.max_slope_deg, c.max_slope_at_theta_deg
    );
    r += &format!(
        "#   contact angle  max {:.1}° at φ = {:.1}° (limit {}°): {}  (profile normal against the thread's pull on the cam; large: the thread slides along the profile)\n",
        c.max_contact_angle_deg,
        c.max_contact_angle_at_phi_deg,
        fmt_num(c.contact_angle_limit_deg),
        if c.contact_angle_ok { "ok" } else { "TOO STEEP" }
    );
    for note in &s.notes {
        r += &format!("# note: {note}\n");
    }
    if !(c.min_radius_ok && c.contact_angle_ok) && s.smooth_deg == 0.0 {
        r += "# hint: --smooth DEG rounds off steps of the target (such as the thread drawn in at a lock) at the cost of the match\n";
    }
    r
}
