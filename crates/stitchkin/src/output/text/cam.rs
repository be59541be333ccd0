//! A synthesised cam as text: its knots as CSV and the `[[cams]]` entry to
//! paste into a model file (`stitchkin cam`).

use crate::format::fmt_num;
use crate::study::cam_synthesis::CamSynthesis;

/// Every knot as `theta_deg,radius_mm`.
pub fn csv(cam: &CamSynthesis) -> String {
    let mut s = String::from("theta_deg,radius_mm\n");
    for k in &cam.knots {
        s += &format!("{},{}\n", fmt_num(k.theta_deg), fmt_num(k.radius_mm));
    }
    s
}

/// A `[[cams]]` entry with the polar profile, to paste over the model's.
pub fn toml_snippet(cam: &CamSynthesis) -> String {
    let list = |v: Vec<f64>| {
        let items: Vec<String> = v.iter().map(|x| fmt_num(*x)).collect();
        let rows: Vec<String> = items.chunks(8).map(|c| format!("    {}", c.join(", "))).collect();
        format!("[\n{},\n  ]", rows.join(",\n"))
    };
    let mut s = format!(
        "# Cam `{}` synthesised by `stitchkin cam` for thread path `{}`: {}.\n\
         # {} knots, radius {:.3}…{:.3} mm; replace the [[cams]] entry named `{}` with this one.\n",
        cam.cam,
        cam.path,
        cam.target,
        cam.knots.len(),
        cam.radius_mm[0],
        cam.radius_mm[1],
        cam.cam
    );
    s += "[[cams]]\n";
    s += &format!(
        "name = {:?}\ncenter = {:?}\nmarker = {:?}\n",
        cam.cam, cam.center, cam.marker
    );
    if let Some(a) = &cam.axis_toml {
        s += &format!("axis = {a}\n");
    }
    if let Some(f) = &cam.frame {
        s += &format!("frame = {f:?}\n");
    }
    s += &format!(
        "polar = {{ angle_deg = {}, radius_mm = {} }}\n",
        list(cam.knots.iter().map(|k| k.theta_deg).collect()),
        list(cam.knots.iter().map(|k| k.radius_mm).collect())
    );
    s
}
