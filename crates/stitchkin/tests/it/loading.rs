//! Bad model files and bad overrides get clear errors that name the place
//! and the fix; impossible positions name the group, φ and the defect.

use stitchkin::Error;
use stitchkin::error::ModelError;
use stitchkin::eval::{CycleOptions, run_cycle};
use stitchkin::model::Model;

/// A four-bar with a coupler point, parameters with and without a range
/// and a derived one (shared with the web tests).
const FOUR_BAR: &str = include_str!("../data/four-bar.toml");

fn load_err(text: &str) -> ModelError {
    match Model::from_toml_str(text, "bad.toml") {
        Ok(_) => panic!("expected an error for:\n{text}"),
        Err(e) => *e,
    }
}

/// The error's line and column, and the text it points at.
fn place(e: &ModelError) -> (usize, usize, String) {
    let (l, c) = e.line_col().expect("the error has a place");
    let span = e.span.clone().unwrap();
    (l, c, e.text[span].to_string())
}

#[test]
fn the_reference_model_loads() {
    let m = Model::from_toml_str(FOUR_BAR, "ok.toml").unwrap();
    assert!(m.is_planar());
    let t = run_cycle(&m, &m.defaults(), &CycleOptions::default()).unwrap();
    assert_eq!(t.rows(), 360);
    assert!(t.column("P.x_mm").is_some() && t.column("P.z_mm").is_none());
    assert!(t.column("mu_bc_deg").is_some());
}

#[test]
fn toml_syntax_error_has_line_and_column() {
    let e = load_err(&FOUR_BAR.replace("name = \"bc\"", "name = bc"));
    let (line, _, _) = place(&e);
    assert_eq!(line, 23);
    assert!(e.to_string().starts_with("bad.toml:23:"), "{e}");
    // A line that is not TOML says how TOML is written.
    let help = e.help.clone().unwrap_or_default();
    assert!(
        help.contains("a model file is TOML") && help.contains("in quotes"),
        "{help}"
    );
    let e = load_err(&FOUR_BAR.replace("[points]", "[points"));
    assert!(e.help.is_some_and(|h| h.contains("table headers")));
}

#[test]
fn unknown_point_suggests_the_closest_name() {
    let e = load_err(&FOUR_BAR.replace("joints = [\"A\", \"O2\"]", "joints = [\"A\", \"O3\"]"));
    assert!(e.message.contains("unknown point `O3`"), "{e}");
    assert!(e.help.as_deref().unwrap().contains("did you mean `O"), "{e}");
    let (line, col, text) = place(&e);
    assert_eq!((line, text.as_str()), (24, "\"O3\""));
    assert_eq!(col, 16);
    assert_eq!(e.path, "groups[0].joints[1]");
}

#[test]
fn unknown_parameter_in_an_expression_points_into_the_string() {
    let e = load_err(&FOUR_BAR.replace("radius = \"r\"", "radius = \"2*rr - 15\""));
    assert!(e.message.contains("unknown parameter `rr`"), "{e}");
    assert!(e.help.as_deref().unwrap().contains("`r`"));
    let (_, _, text) = place(&e);
    assert_eq!(text, "rr");
}

#[test]
fn unknown_field_and_group_type_are_rejected() {
    let e = load_err(&FOUR_BAR.replace("branch = \"left\"", "branch = \"left\"\nbranhc = 1"));
    assert!(e.message.contains("unknown field `branhc`"), "{e}");
    assert!(e.line_col().is_some());
    let e = load_err(&FOUR_BAR.replace("type = \"rrr\"", "type = \"rrrr\""));
    assert!(e.message.contains("rrrr"), "{e}");
    let e = load_err(&FOUR_BAR.replace("branch = \"left\"", "branch = \"up\""));
    assert!(e.message.contains("up"), "{e}");
}

#[test]
fn wrong_units_are_rejected() {
    // A length given an angle parameter.
    let e = load_err(&FOUR_BAR.replace("radius = \"r\"", "radius = \"gamma\""));
    assert!(e.message.contains("deg") && e.message.contains("mm"), "{e}");
    // Sum of a length and an angle.
    let e = load_err(&FOUR_BAR.replace("distance = 20", "distance = \"l + gamma\""));
    assert!(e.message.contains("cannot add"), "{e}");
    // Trigonometry of a length.
    let e = load_err(&FOUR_BAR.replace("distance = 20", "distance = \"l*sin(r)\""));
    assert!(e.message.contains("trigonometric"), "{e}");
    // A unit the format does not know.
    let e = load_err(&FOUR_BAR.replace("unit = \"deg\"", "unit = \"rad\""));
    assert!(e.message.contains("rad"), "{e}");
    // A derived parameter whose expression has the wrong unit.
    let e = load_err(&FOUR_BAR.replace("expr = \"2*r\", unit = \"mm\"", "expr = \"2*r\", unit = \"deg\""));
    assert!(e.message.contains("is in mm but deg is expected"), "{e}");
}

#[test]
fn groups_that_need_each_other_are_rejected() {
    let text = FOUR_BAR.replace("joints = [\"A\", \"O2\"]", "joints = [\"A\", \"P\"]");
    let e = load_err(&text);
    assert!(e.message.contains("need each other's points"), "{e}");
    assert!(e.help.as_deref().unwrap().contains("newton"));
}

#[test]
fn duplicate_points_and_bad_names() {
    let e = load_err(&FOUR_BAR.replace("out = \"P\"", "out = \"B\""));
    assert!(e.message.contains("defined twice"), "{e}");
    let e = load_err(&FOUR_BAR.replace("O2 = [60, 0]", "\"O-2\" = [60, 0]"));
    assert!(e.message.contains("not a valid point name"), "{e}");
    let e = load_err(&FOUR_BAR.replace("gamma = {", "sin = {"));
    assert!(e.message.contains("reserved"), "{e}");
}

#[test]
fn impossible_geometry_is_reported_at_load() {
    let e = load_err(&FOUR_BAR.replace("l = { value = 50", "l = { value = -50"));
    assert!(e.message.contains("must be positive"), "{e}");
    assert_eq!(place(&e).2, "\"l\"");
    let e = load_err(&FOUR_BAR.replace(
        "value = 15, unit = \"mm\", range = [10, 20]",
        "value = 25, unit = \"mm\", range = [10, 20]",
    ));
    assert!(e.message.contains("outside the parameter's range"), "{e}");
    let e = load_err(&FOUR_BAR.replace("distance = 20", "distance = \"r*r/(r - 15)\""));
    assert!(e.message.contains("evaluates to inf"), "{e}");
    let e = load_err(&FOUR_BAR.replace("twice_r = { expr = \"2*r\"", "twice_r = { expr = \"2*twice_r\""));
    assert!(e.message.contains("loop"), "{e}");
}

#[test]
fn overrides_are_checked() {
    let m = Model::from_toml_str(FOUR_BAR, "ok.toml").unwrap();
    let mut p = m.defaults();
    let e = m.set(&mut p, "r", 25.0).unwrap_err();
    assert!(e.message.contains("outside its adjustable range 10…20 mm"), "{e}");
    let e = m.set(&mut p, "twice_r", 25.0).unwrap_err();
    assert!(e.message.contains("derived"), "{e}");
    let e = m.set(&mut p, "gama", 25.0).unwrap_err();
    assert!(e.help.unwrap().contains("`gamma`"));
    let e = m.set_str(&mut p, "gamma=abc").unwrap_err();
    assert!(e.message.contains("not a number"), "{e}");
    let e = m.set_str(&mut p, "gamma").unwrap_err();
    assert!(e.message.contains("not an assignment"), "{e}");
    m.set_str(&mut p, "r = 12").unwrap();
    assert_eq!(p.values[m.param_index("r").unwrap()], 12.0);
}

#[test]
fn no_assembly_names_group_phi_and_defect() {
    // A rocker too short to reach: the crank pulls it apart on part of the cycle.
    let text = FOUR_BAR.replace("c = { value = 40", "c = { value = 24");
    let m = Model::from_toml_str(&text, "short.toml").unwrap();
    let err = run_cycle(&m, &m.defaults(), &CycleOptions::default()).unwrap_err();
    let Error::Assembly(a) = err else {
        panic!("expected an assembly error, got {err}")
    };
    assert!(a.group.contains("rrr group \"bc\""), "{a}");
    assert!(a.defect_mm > 0.0 && a.defect_mm < 20.0, "{a}");
    assert!((0.0..360.0).contains(&a.phi_deg), "{a}");
    let s = a.to_string();
    assert!(
        s.contains("no assembly at φ =") && s.contains("closure fails by"),
        "{s}"
    );
}

#[test]
fn missing_file_is_a_clear_error() {
    let e = Model::from_path(std::path::Path::new("/nonexistent/machine.toml")).unwrap_err();
    assert!(
        e.to_string()
            .contains("cannot read model file `/nonexistent/machine.toml`"),
        "{e}"
    );
}

#[test]
fn newton_group_counts_equations() {
    let text = r#"[model]
name = "triangle"
[points]
O = [0, 0]
Q = [5, 0]
[[groups]]
type = "newton"
name = "tri"
unknowns = { B = [2, 2] }
constraints = [ { distance = ["B", "O"], length = 3 } ]
"#;
    let e = load_err(text);
    assert!(
        e.message.contains("1 closure equation(s) for 2 unknown coordinates"),
        "{e}"
    );
    assert!(e.help.unwrap().contains("add constraints"));
}

#[test]
fn unknown_preset_suggests_one() {
    let e = Model::preset("needle867").unwrap_err();
    assert!(e.to_string().contains("did you mean `needle876`"), "{e}");
}

#[test]
fn group_names_must_be_column_safe_and_unique() {
    let e = load_err(&FOUR_BAR.replace("name = \"bc\"", "name = \"rod 4 / rocker\""));
    assert!(e.message.contains("not a valid group name"), "{e}");
    let text = FOUR_BAR.replace("type = \"rigid_point\"", "type = \"rigid_point\"\nname = \"bc\"");
    let e = load_err(&text);
    assert!(e.message.contains("two groups are named `bc`"), "{e}");
}

#[test]
fn newton_constraints_have_one_of_two_shapes() {
    let base = r#"[model]
name = "triangle"
[points]
O = [0, 0]
Q = [5, 0]
[[groups]]
type = "newton"
name = "tri"
unknowns = { B = [2, 2] }
constraints = [ { distance = ["B", "O"], length = 3 }, CONSTRAINT ]
"#;
    let ok = base.replace("CONSTRAINT", "{ distance = [\"B\", \"Q\"], length = 4 }");
    Model::from_toml_str(&ok, "ok.toml").unwrap();
    let e = load_err(&base.replace("CONSTRAINT", "{ distance = [\"B\", \"Q\"], lenght = 4 }"));
    assert!(e.message.contains("unknown field `lenght`"), "{e}");
    let e = load_err(&base.replace(
        "CONSTRAINT",
        "{ distance = [\"B\", \"Q\"], on_line = \"B\", length = 4 }",
    ));
    assert!(e.message.contains("either a distance or a point on a line"), "{e}");
    // A spatial group (3 coordinates per unknown) has no plane to name.
    let spatial = r#"[model]
name = "spatial"
[frames.p]
origin = [0, 0, 1]
[points]
O = [0, 0, 0]
Q = [5, 0, 0]
R = [0, 5, 0]
[[groups]]
type = "newton"
name = "tri"
plane = "p"
unknowns = { B = [2, 2, 2] }
constraints = [ { distance = ["B", "O"], length = 3 }, { distance = ["B", "Q"], length = 4 }, { distance = ["B", "R"], length = 4 } ]
"#;
    let e = load_err(spatial);
    assert!(e.message.contains("has no plane"), "{e}");
    Model::from_toml_str(&spatial.replace("plane = \"p\"\n", ""), "ok.toml").unwrap();
}

#[test]
fn vector_axis_in_a_rotated_frame_gets_a_perpendicular_zero() {
    // The frame turns x onto world y: the axis [1, 0, 0] is the world y axis.
    let text = r#"[model]
name = "turned"
[frames.t]
rotate = [["z", 90]]
[points]
O = [0, 0, 0]
[[drivers]]
type = "crank"
center = "O"
out = "A"
radius = 10
frame = "t"
axis = [1, 0, 0]
"#;
    let m = Model::from_toml_str(text, "turned.toml").unwrap();
    let t = run_cycle(
        &m,
        &m.defaults(),
        &CycleOptions {
            step_deg: 90.0,
            ..Default::default()
        },
    )
    .unwrap();
    // The pin circles in the world xz-plane: y stays 0.
    assert!(t.column("A.y_mm").unwrap().iter().all(|y| y.abs() < 1e-12));
    let r: Vec<f64> = (0..4)
        .map(|k| t.column("A.x_mm").unwrap()[k].hypot(t.column("A.z_mm").unwrap()[k]))
        .collect();
    assert!(r.iter().all(|r| (r - 10.0).abs() < 1e-12), "{r:?}");
}

#[test]
fn a_rotation_is_exactly_axis_and_angle() {
    let frame = |rot: &str| FOUR_BAR.replace("[points]", &format!("[frames.f]\nrotate = [{rot}]\n\n[points]"));
    Model::from_toml_str(&frame(r#"["x", 10]"#), "ok.toml").unwrap();
    let e = load_err(&frame(r#"["x", 10, 20]"#));
    assert!(e.message.contains("got 3 elements"), "{e}");
    let e = load_err(&frame(r#"[10, "x"]"#));
    assert!(e.message.contains("starts with its axis"), "{e}");
}

/// What a broken file says is in the file's terms, with its place: a byte
/// that is not UTF-8, a point whose table header went missing, tables
/// nested too deep, a length too large to compute with.
#[test]
fn broken_files_are_named_in_the_files_terms() {
    let mut bytes = FOUR_BAR.as_bytes().to_vec();
    let at = FOUR_BAR.find("O2 = [60, 0]").unwrap();
    bytes[at] = 0xE6;
    let e = *Model::from_toml_bytes(&bytes, "bad.toml").unwrap_err();
    assert_eq!(e.line_col(), Some((13, 1)), "{e}");
    assert!(e.message.contains("not UTF-8") && e.help.unwrap().contains("UTF-8"));

    let e = load_err(&FOUR_BAR.replace("O2 = [60, 0]", "O2 = { x = 60 }"));
    assert!(e.message.contains("not a fixed point in any of the forms"), "{e}");
    assert!(e.help.as_deref().unwrap().contains("[x, y]"), "{e}");
    assert_eq!(place(&e).0, 13);

    let deep = format!("{FOUR_BAR}\nx = {}1{}\n", "[".repeat(200), "]".repeat(200));
    let e = load_err(&deep);
    assert!(e.message.contains("too deeply") && e.line_col().is_some(), "{e}");

    let e = load_err(&FOUR_BAR.replace("O2 = [60, 0]", "O2 = [1e300, 0]"));
    assert!(
        e.message.contains("too large to compute with") && e.line_col().is_some(),
        "{e}"
    );
}

/// A [stitch] number out of range is refused where the file writes it.
#[test]
fn stitch_numbers_are_checked_where_they_are_written() {
    let altin = stitchkin::presets::find("altin504").unwrap().toml;
    for (from, to, says) in [
        (
            "tilt_deg = \"alpha\"",
            "tilt_deg = 85",
            "the needle tilt β = 85° is outside −80°…80°",
        ),
        (
            "overedge_width_mm = \"a_e\"",
            "overedge_width_mm = -4",
            "must be positive",
        ),
    ] {
        assert!(altin.contains(from), "{from}");
        let e = load_err(&altin.replacen(from, to, 1));
        assert!(e.to_string().contains(says) && e.line_col().is_some(), "{e}");
    }
}
