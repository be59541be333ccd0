//! A synthesised follower lift ([`crate::study::follower_synthesis`]) as
//! text: its summary, the lift and profiles as CSV, the `lift` to paste into
//! the group, and the profile as DXF.

use super::cam_summary::{max_error_line, smoothing_line};
use crate::format::fmt_num;
use crate::study::follower_synthesis::FollowerSynthesis;

/// The summary, `# `-lines: the group and path, the lift, the base circle,
/// the smoothing, the verification and the group's checks.
pub fn summary(s: &FollowerSynthesis) -> String {
    let v = &s.verify;
    let c = &s.checks;
    let u = s.lift_unit;
    let n = s.lift.len();
    let mut r = format!(
        "# cam synthesis for a follower: group `{}` ({} follower), thread path `{}`\n# target: {}\n",
        s.group, s.motion, s.path, s.target
    );
    r += &format!(
        "# {n} lift points: the cam angles at φ = {}° + k·{}°; lift 0…{:.4} {u} (solved {:.4}…{:.4} {u} from the model's zero lift)\n",
        fmt_num(s.phi0_deg),
        fmt_num(360.0 / n as f64),
        s.lift_range[1],
        s.least_lift,
        s.least_lift + s.lift_range[1]
    );
    let touching = match s.contact {
        "roller" => format!("roller {} mm", fmt_num(s.roller_mm)),
        "flat" => "a flat face".to_string(),
        _ => "a knife edge".to_string(),
    };
    r += &format!(
        "# base circle: {:.4} mm (the model's: {:.4} mm; {touching}): at zero lift the follower stands where the least lift put it\n",
        s.base_radius_mm, s.base_radius_model_mm
    );
    r += &smoothing_line(s.smooth_deg, "cam angle");
    r += "# verify (the model evaluated again with the new lift and base circle):\n";
    r += &max_error_line(v, "lift");
    let sc = |x: Option<f64>| x.map_or("—".to_string(), |x| format!("{x:.1}"));
    if let (Some(t), Some(b), Some(a)) = (&s.thread, &v.match_before, &v.match_after) {
        r += &format!(
            "#   match of thread `{t}` (docs/stitch-formation.md §8, on the knots' φ): score {} → {}, RMS(P − P') {:.4} → {:.4} mm\n",
            sc(b.score),
            sc(a.score),
            b.rms_d_mm,
            a.rms_d_mm
        );
    } else if let Some(m) = &s.match_target {
        r += &format!(
            "#   match with the target (docs/stitch-formation.md §8, on the knots' φ, every φ compared, tolerance 0.5 mm): score {}, RMS {:.4} mm\n",
            sc(m.score),
            m.rms_d_mm
        );
    }
    r += "# checks of the group (cam_pressure, cam_curvature):\n";
    r += &format!(
        "#   pressure angle  max {:.1}° at cam angle {:.1}° (limit {}°): {}\n",
        c.max_pressure_deg,
        c.max_pressure_at_cam_deg,
        fmt_num(c.pressure_limit_deg),
        if c.pressure_ok {
            "ok".to_string()
        } else {
            format!(
                "TOO STEEP by {:.1}°: a larger base circle (the follower working further out) or more smoothing",
                c.max_pressure_deg - c.pressure_limit_deg
            )
        }
    );
    r += &format!(
        "#   curvature       least radius {:.2} mm at cam angle {:.1}° (limit > 0): {}\n",
        c.min_curvature_radius_mm,
        c.min_curvature_at_cam_deg,
        match (c.curvature_ok, s.contact) {
            (true, _) => "ok",
            (false, "flat") =>
                "CONCAVE: a flat face cannot follow it; smooth the lift (a wider average) or enlarge the base circle",
            (false, _) => "UNDERCUT: smooth the lift (a wider average), or use a smaller roller",
        }
    );
    if let Some(b) = &s.base_circle_needed {
        let along = if s.motion == "translating" {
            "back along the follower's axis".to_string()
        } else {
            format!(
                "back by ({:.2}, {:.2}) mm, from the roller's rest point through the centre (a flat face: along its normal at rest)",
                b.move_mm[0], b.move_mm[1]
            )
        };
        r += &format!(
            "#   least base circle passing both: {:.1} mm, the cam's centre moved {:.2} mm {along} (away from the follower, so it keeps its positions): pressure {:.1}°, least radius {:.2} mm\n",
            b.base_radius_mm, b.move_back_mm, b.checks.max_pressure_deg, b.checks.min_curvature_radius_mm
        );
    } else if !(c.pressure_ok && c.curvature_ok) {
        r += if s.motion == "translating" {
            "#   no base circle up to 1000 mm passes both with this lift: smooth it\n"
        } else {
            "#   no base circle up to 1000 mm passes both with this lift: smooth it, or move the pivot (at rest the pressure angle is that of the line from the roller to the cam's centre against the roller's path, which no base circle changes)\n"
        };
    }
    for note in &s.notes {
        r += &format!("# note: {note}\n");
    }
    r
}

/// The lift table and the cam every half degree:
/// `cam_deg,lift_mm,pitch_x_mm,pitch_y_mm,profile_x_mm,profile_y_mm`
/// (a rocking follower's lift in deg), in the cam's frame.
pub fn csv(s: &FollowerSynthesis) -> String {
    let mut r = format!(
        "cam_deg,lift_{},pitch_x_mm,pitch_y_mm,profile_x_mm,profile_y_mm\n",
        s.lift_unit
    );
    for p in &s.profile {
        r += &format!(
            "{},{},{},{},{},{}\n",
            fmt_num(p.cam_deg),
            fmt_num(p.lift),
            fmt_num(p.pitch_mm[0]),
            fmt_num(p.pitch_mm[1]),
            fmt_num(p.profile_mm[0]),
            fmt_num(p.profile_mm[1])
        );
    }
    r
}

/// The `lift` and `base_radius` lines to paste into the group.
pub fn toml_snippet(s: &FollowerSynthesis) -> String {
    let list = |v: Vec<f64>| {
        let items: Vec<String> = v.iter().map(|x| fmt_num(*x)).collect();
        let rows: Vec<String> = items.chunks(8).map(|c| format!("    {}", c.join(", "))).collect();
        format!("[\n{},\n  ]", rows.join(",\n"))
    };
    let key = if s.lift_unit == "deg" { "deg" } else { "mm" };
    format!(
        "# The lift of group `{}` synthesised by `stitchkin cam` for thread path `{}`: {}.\n\
         # {} points, lift 0…{:.4} {}; replace the group's base_radius and lift with these.\n\
         base_radius = {}\n\
         lift = {{ angle_deg = {},\n  {key} = {} }}\n",
        s.group,
        s.path,
        s.target,
        s.lift.len(),
        s.lift_range[1],
        s.lift_unit,
        fmt_num(s.base_radius_mm),
        list(s.lift.iter().map(|k| k.theta_deg).collect()),
        list(s.lift.iter().map(|k| k.radius_mm).collect())
    )
}

/// The working profile as a closed R12 DXF polyline (mm, about the cam's
/// centre, x toward cam angle 0).
pub fn dxf(s: &FollowerSynthesis) -> String {
    let pts: Vec<(f64, f64)> = s.profile.iter().map(|p| (p.profile_mm[0], p.profile_mm[1])).collect();
    crate::output::drawing::cam::dxf_outline(
        &format!(
            "stitchkin cam: the cam of group {} for thread path {}; units mm",
            s.group, s.path
        ),
        &pts,
    )
}
