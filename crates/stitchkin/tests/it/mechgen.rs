//! Random mechanisms written as model files, for property tests.

use proptest::prelude::*;
use stitchkin::model::Model;

/// A generated model and the facts a test needs about it.
#[derive(Debug, Clone)]
pub struct Generated {
    pub toml: String,
    /// (point, point, length): pairs whose distance the mechanism keeps.
    pub links: Vec<(&'static str, &'static str, f64)>,
}

impl Generated {
    pub fn load(&self) -> Model {
        Model::from_toml_str(&self.toml, "generated.toml").unwrap_or_else(|e| panic!("{e}\n{}", self.toml))
    }
}

fn branch(left: bool) -> &'static str {
    if left { "left" } else { "right" }
}

/// Grashof crank-rocker four-bars with a coupler point.
pub fn four_bar() -> impl Strategy<Value = Generated> {
    (
        5.0..15.0f64,
        40.0..80.0f64,
        30.0..90.0f64,
        30.0..90.0f64,
        5.0..40.0f64,
        -180.0..180.0f64,
        any::<bool>(),
        -180.0..180.0f64,
    )
        .prop_filter("Grashof crank-rocker with the crank shortest", |&(r, d, l, c, ..)| {
            let longest = d.max(l).max(c);
            let sum = r + d + l + c;
            // crank shortest by a margin; s + L < p + q with a margin
            r + 3.0 < d.min(l).min(c) && r + longest < sum - r - longest - 2.0
        })
        .prop_map(|(r, d, l, c, cp_d, cp_a, left, phase)| Generated {
            toml: format!(
                r#"[model]
name = "four-bar"
[parameters]
r = {{ value = {r}, unit = "mm" }}
l = {{ value = {l}, unit = "mm" }}
c = {{ value = {c}, unit = "mm" }}
[points]
O1 = [0, 0]
O2 = [{d}, 0]
[[drivers]]
type = "crank"
center = "O1"
out = "A"
radius = "r"
phase_deg = {phase}
[[groups]]
type = "rrr"
name = "bc"
joints = ["A", "O2"]
lengths = ["l", "c"]
out = "B"
branch = "{}"
[[groups]]
type = "rigid_point"
base = ["A", "B"]
distance = {cp_d}
angle_deg = {cp_a}
out = "P"
"#,
                branch(left)
            ),
            links: vec![("O1", "A", r), ("A", "B", l), ("O2", "B", c), ("A", "P", cp_d)],
        })
}

/// Offset slider-cranks on a guide line at any angle.
pub fn slider_crank() -> impl Strategy<Value = Generated> {
    (
        5.0..20.0f64,
        10.0..60.0f64,
        -8.0..8.0f64,
        -180.0..180.0f64,
        any::<bool>(),
        -20.0..20.0f64,
        -20.0..20.0f64,
    )
        .prop_map(|(r, extra, e, dir, fwd, hx, hy)| {
            // The rod must reach the guide line from everywhere on the crank circle.
            let dist = (hx * (dir.to_radians().sin()) - hy * (dir.to_radians().cos())).abs();
            let l = r + dist + e.abs() + extra;
            Generated {
                toml: format!(
                    r#"[model]
name = "slider-crank"
[points]
O = [0, 0]
H = [{hx}, {hy}]
[[drivers]]
type = "crank"
center = "O"
out = "A"
radius = {r}
[[groups]]
type = "rrp"
name = "slider"
from = "A"
length = {l}
through = "H"
direction_deg = {dir}
offset = {e}
out = "G"
branch = "{}"
"#,
                    if fwd { "forward" } else { "backward" }
                ),
                links: vec![("O", "A", r), ("A", "G", l)],
            }
        })
}

/// Spatial chains: a crank, an RSSR rocker on a tilted axis, a point rigid
/// to the rocker, and a slider on a spatial line driven from it.
pub fn rssr_chain() -> impl Strategy<Value = Generated> {
    (
        4.0..8.0f64,
        40.0..60.0f64,
        18.0..30.0f64,
        -0.3..0.3f64,
        -0.3..0.3f64,
        -10.0..10.0f64,
        any::<bool>(),
        20.0..30.0f64,
    )
        .prop_map(|(r, dist, arm, ay, az, zoff, left, rod2)| {
            // Rod length so the arm stands roughly across the rod at φ = 90°.
            let rod = (dist.powi(2) + arm.powi(2)).sqrt();
            Generated {
                toml: format!(
                    r#"[model]
name = "rssr-chain"
[frames.rocker]
origin = [0, {dist}, {zoff}]
rotate = [["y", {ay_deg}], ["z", {az_deg}]]
[points]
O = [0, 0, 0]
C = {{ at = [0, 0, 0], frame = "rocker" }}
Cx = {{ at = [10, 0, 0], frame = "rocker" }}
N1 = [30, {n1y}, 5]
N2 = [40, {n1y}, 40]
[[drivers]]
type = "eccentric"
center = "O"
out = "A"
radius = {r}
axis = "x"
[[groups]]
type = "rssr"
name = "rocker"
from = "A"
rod = {rod}
pivot = "C"
axis = "x"
frame = "rocker"
arm = {arm}
out = "B"
branch = "{}"
[[groups]]
type = "rigid_point_3d"
frame = ["C", "B", "Cx"]
at = [15, 5, 3]
out = "K"
[[groups]]
type = "point_on_line"
name = "slider"
from = "K"
length = {rod2}
through = "N1"
toward = "N2"
out = "S"
branch = "forward"
"#,
                    branch(left),
                    ay_deg = ay.to_degrees(),
                    az_deg = az.to_degrees(),
                    n1y = dist,
                ),
                links: vec![("O", "A", r), ("A", "B", rod), ("C", "B", arm), ("K", "S", rod2)],
            }
        })
}
