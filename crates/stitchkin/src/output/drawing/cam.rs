//! A synthesised cam's profile as drawings to scale: SVG (1 user unit =
//! 1 mm) and an R12 DXF for CAD (`stitchkin cam`). Beside the mechanism
//! drawing, not among the charts: both are pictures of parts to scale.

use crate::format::fmt_num;
use crate::output::svg::escape;
use crate::study::cam_synthesis::CamSynthesis;

/// The profile drawn to scale (1 user unit = 1 mm) with its centre, the
/// marker direction (θ = 0) and a scale bar, seen from the tip of the
/// shaft axis (profile angles counter-clockwise).
pub fn svg(cam: &CamSynthesis) -> String {
    let pts = cam.outline();
    let r = pts.iter().map(|(x, y)| x.hypot(*y)).fold(1.0f64, f64::max);
    let margin = 0.25 * r + 4.0;
    let half = r + margin;
    let bar = nice_length(0.5 * r);
    let (w, h) = (2.0 * half, 2.0 * half + 12.0);
    let f = |x: f64| format!("{x:.4}");
    let mut d = String::new();
    for (i, (x, y)) in pts.iter().enumerate() {
        d += &format!("{}{} {} ", if i == 0 { "M" } else { "L" }, f(*x), f(-*y));
    }
    d += "Z";
    let font = (0.06 * r).clamp(1.5, 6.0);
    let mut s = String::new();
    s += "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n";
    s += &format!(
        "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{}mm\" height=\"{}mm\" viewBox=\"{} {} {} {}\">\n",
        f(w),
        f(h),
        f(-half),
        f(-half),
        f(w),
        f(h)
    );
    s += &format!(
        "  <title>cam {} for thread path {}: {} (stitchkin cam); 1 unit = 1 mm, seen from the tip of the shaft axis</title>\n",
        escape(&cam.cam),
        escape(&cam.path),
        escape(&cam.target)
    );
    s += &format!(
        "  <path id=\"profile\" d=\"{d}\" fill=\"none\" stroke=\"black\" stroke-width=\"{}\"/>\n",
        f(0.01 * r)
    );
    let c = 0.06 * r;
    s += &format!(
        "  <g id=\"centre\" stroke=\"black\" stroke-width=\"{}\"><line x1=\"{}\" y1=\"0\" x2=\"{}\" y2=\"0\"/><line x1=\"0\" y1=\"{}\" x2=\"0\" y2=\"{}\"/><circle cx=\"0\" cy=\"0\" r=\"{}\" fill=\"none\"/></g>\n",
        f(0.004 * r),
        f(-c),
        f(c),
        f(-c),
        f(c),
        f(0.4 * c)
    );
    s += &format!(
        "  <g id=\"marker\" stroke=\"blue\" stroke-width=\"{}\" stroke-dasharray=\"{} {}\"><line x1=\"0\" y1=\"0\" x2=\"{}\" y2=\"0\"/></g>\n",
        f(0.006 * r),
        f(0.04 * r),
        f(0.02 * r),
        f(r + 0.5 * margin)
    );
    s += &format!(
        "  <text x=\"{}\" y=\"{}\" font-size=\"{}\" fill=\"blue\" text-anchor=\"end\">θ = 0 (toward {})</text>\n",
        f(r + 0.5 * margin),
        f(-0.4 * font),
        f(font),
        escape(&cam.marker)
    );
    let (y0, x0) = (half + 4.0, -half + 2.0);
    s += &format!(
        "  <g id=\"scale\" stroke=\"black\" stroke-width=\"{}\"><line x1=\"{}\" y1=\"{}\" x2=\"{}\" y2=\"{}\"/><line x1=\"{}\" y1=\"{}\" x2=\"{}\" y2=\"{}\"/><line x1=\"{}\" y1=\"{}\" x2=\"{}\" y2=\"{}\"/></g>\n",
        f(0.3),
        f(x0),
        f(y0),
        f(x0 + bar),
        f(y0),
        f(x0),
        f(y0 - 1.0),
        f(x0),
        f(y0 + 1.0),
        f(x0 + bar),
        f(y0 - 1.0),
        f(x0 + bar),
        f(y0 + 1.0)
    );
    s += &format!(
        "  <text x=\"{}\" y=\"{}\" font-size=\"{}\">{} mm</text>\n",
        f(x0 + bar + 1.5),
        f(y0 + 1.2),
        f(3.0),
        fmt_num(bar)
    );
    s += &format!(
        "  <text x=\"{}\" y=\"{}\" font-size=\"{}\">cam {} (centre {}), radius {:.2}…{:.2} mm</text>\n",
        f(x0),
        f(y0 + 6.0),
        f(3.0),
        escape(&cam.cam),
        escape(&cam.center),
        cam.radius_mm[0],
        cam.radius_mm[1]
    );
    s += "</svg>\n";
    s
}

/// The profile as an R12 ASCII DXF (units mm): a closed POLYLINE on
/// layer PROFILE, the centre as a POINT and the marker direction as a
/// LINE on layer MARKER.
pub fn dxf(cam: &CamSynthesis) -> String {
    dxf_outline(
        &format!("stitchkin cam: cam {} for thread path {}; units mm", cam.cam, cam.path),
        &cam.outline(),
    )
}

/// A closed outline `pts` (mm, about the cam's centre, x toward angle 0)
/// as an R12 ASCII DXF with the `comment` first: a closed POLYLINE on
/// layer PROFILE, the centre as a POINT and the angle-0 direction as a
/// LINE on layer MARKER.
pub fn dxf_outline(comment: &str, pts: &[(f64, f64)]) -> String {
    let mut s = String::new();
    let mut g = |code: i32, v: &str| {
        s += &format!("{code}\n{v}\n");
    };
    g(999, comment);
    for (c, v) in [
        (0, "SECTION"),
        (2, "HEADER"),
        (9, "$ACADVER"),
        (1, "AC1009"),
        (9, "$INSUNITS"),
        (70, "4"),
        (0, "ENDSEC"),
    ] {
        g(c, v);
    }
    for (c, v) in [
        (0, "SECTION"),
        (2, "ENTITIES"),
        (0, "POLYLINE"),
        (8, "PROFILE"),
        (66, "1"),
        (70, "1"),
        (10, "0.0"),
        (20, "0.0"),
        (30, "0.0"),
    ] {
        g(c, v);
    }
    for (x, y) in pts {
        for (c, v) in [
            (0, "VERTEX".to_string()),
            (8, "PROFILE".into()),
            (10, format!("{x:.6}")),
            (20, format!("{y:.6}")),
            (30, "0.0".into()),
        ] {
            g(c, &v);
        }
    }
    let r = pts.iter().map(|(x, y)| x.hypot(*y)).fold(0.0f64, f64::max);
    for (c, v) in [
        (0, "SEQEND".to_string()),
        (8, "PROFILE".into()),
        (0, "POINT".into()),
        (8, "CENTER".into()),
        (10, "0.0".into()),
        (20, "0.0".into()),
        (30, "0.0".into()),
    ] {
        g(c, &v);
    }
    for (c, v) in [
        (0, "LINE".to_string()),
        (8, "MARKER".into()),
        (10, "0.0".into()),
        (20, "0.0".into()),
        (30, "0.0".into()),
        (11, format!("{:.6}", 1.15 * r)),
        (21, "0.0".into()),
        (31, "0.0".into()),
        (0, "ENDSEC".into()),
        (0, "EOF".into()),
    ] {
        g(c, &v);
    }
    s
}

/// 1, 2 or 5 × 10^k, at most `x` (at least 1 mm).
fn nice_length(x: f64) -> f64 {
    let x = x.max(1.0);
    let p = 10f64.powf(x.log10().floor());
    [5.0, 2.0, 1.0]
        .into_iter()
        .map(|m| m * p)
        .find(|&v| v <= x)
        .unwrap_or(p)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn nice_scale_bars() {
        assert_eq!(nice_length(8.6), 5.0);
        assert_eq!(nice_length(23.0), 20.0);
        assert_eq!(nice_length(0.3), 1.0);
    }
}
