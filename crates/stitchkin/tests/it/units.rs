//! Models written in inches, centimetres and radians (`[model] units`,
//! docs/model-format.md "Units"): converted when loaded, they give the same
//! results, in mm and deg, as the same model in mm and degrees; their
//! parameters are read, set and advised in the model's units.

use stitchkin::eval::{CycleOptions, CycleTable, run_cycle};
use stitchkin::model::{Model, Params};
use stitchkin::study::tune::{Adjustment, set_stitch_value};

const TAKEUP_IN: &str = include_str!("../data/units/takeup-lever-in.toml");
const TAKEUP_CM_RAD: &str = include_str!("../data/units/takeup-lever-cm-rad.toml");

fn cycle(model: &Model, params: &Params) -> CycleTable {
    run_cycle(model, params, &CycleOptions::default()).unwrap()
}

/// Every column of `a` named `*_mm` or `*_deg` (positions, lengths, P, P′,
/// angles) whose name `keep` keeps equals `b`'s to `tol` at every φ.
fn same_columns(a: &CycleTable, b: &CycleTable, tol: f64, keep: impl Fn(&str) -> bool) -> usize {
    let mut compared = 0;
    for c in &a.columns {
        if !(c.name.ends_with("_mm") || c.name.ends_with("_deg")) || !keep(&c.name) {
            continue;
        }
        let other = b.column(&c.name).unwrap_or_else(|| panic!("{} missing", c.name));
        for (k, (x, y)) in c.values.iter().zip(other).enumerate() {
            let both_nan = x.is_nan() && y.is_nan();
            assert!(
                both_nan || (x - y).abs() <= tol,
                "{} at row {k}: {x} against {y}",
                c.name
            );
        }
        compared += 1;
    }
    compared
}

fn same_results(a: &CycleTable, b: &CycleTable, tol: f64) -> usize {
    same_columns(a, b, tol, |_| true)
}

/// The P column of a table's thread path `name`.
fn p_of<'a>(t: &'a CycleTable, name: &str) -> &'a [f64] {
    t.column(&format!("{name}.P_mm"))
        .or_else(|| t.column(&format!("{name}.P_B_mm")))
        .unwrap_or_else(|| panic!("no P column of {name}"))
}

#[test]
fn a_model_in_inches_gives_the_take_up_of_the_same_model_in_mm() {
    let mm = Model::preset("takeup-lever").unwrap();
    let inch = Model::from_toml_str(TAKEUP_IN, "takeup-lever-in.toml").unwrap();
    assert_eq!(inch.units().length.mm(), 25.4);
    let (a, b) = (cycle(&inch, &inch.defaults()), cycle(&mm, &mm.defaults()));
    let (pa, pb) = (p_of(&a, "lever"), p_of(&b, "lever"));
    assert_eq!(pa.len(), 360);
    let worst = pa.iter().zip(pb).map(|(x, y)| (x - y).abs()).fold(0.0, f64::max);
    assert!(worst < 1e-9, "P differs by {worst} mm");
    assert!(pb.iter().any(|p| p.abs() > 1.0), "P is not trivial");
    assert!(same_results(&a, &b, 1e-9) > 20);
}

#[test]
fn a_model_in_centimetres_and_radians_gives_the_same_results_in_mm_and_deg() {
    let mm = Model::preset("takeup-lever").unwrap();
    let cm = Model::from_toml_str(TAKEUP_CM_RAD, "takeup-lever-cm-rad.toml").unwrap();
    let (a, b) = (cycle(&cm, &cm.defaults()), cycle(&mm, &mm.defaults()));
    let worst = p_of(&a, "lever")
        .iter()
        .zip(p_of(&b, "lever"))
        .map(|(x, y)| (x - y).abs())
        .fold(0.0, f64::max);
    assert!(worst < 1e-9, "P differs by {worst} mm");
    assert!(same_results(&a, &b, 1e-9) > 20);
    let i = cm.param_index("U2_3_5").unwrap();
    assert_eq!(cm.params()[i].unit_str(), "rad");
}

/// A parameter of an inch model is set in inches and listed with `in`:
/// 0.9 in there is 22.86 mm in the mm model.
#[test]
fn an_inch_models_parameters_are_set_and_shown_in_inches() {
    let mm = Model::preset("takeup-lever").unwrap();
    let inch = Model::from_toml_str(TAKEUP_IN, "takeup-lever-in.toml").unwrap();
    let i = inch.param_index("l4_3").unwrap();
    assert_eq!(inch.params()[i].unit_str(), "in");
    let mut pi = inch.defaults();
    inch.set_str(&mut pi, "l4_3=0.9").unwrap();
    let mut pm = mm.defaults();
    mm.set(&mut pm, "l4_3", 22.86).unwrap();
    let (a, b) = (cycle(&inch, &pi), cycle(&mm, &pm));
    assert!(same_results(&a, &b, 1e-9) > 20);
    // Tuning advice speaks the parameter's unit.
    let adj = Adjustment::new(&inch.params()[i], 0.83, 0.9);
    assert!(adj.advice.contains("by 0.07 in"), "{}", adj.advice);
    assert!(adj.advice.contains("0.83 → 0.9 in"), "{}", adj.advice);
    // To the thousandth of an inch (0.0254 mm), as an inch machine is set.
    let adj = Adjustment::new(&inch.params()[i], 0.8268, 0.8312);
    assert!(
        adj.advice.contains("by 0.004 in (l4_3: 0.827 → 0.831 in)"),
        "{}",
        adj.advice
    );
}

/// `text` with every length parameter (and the plain numbers of fields
/// that do not name their unit) divided by `mm_per_unit`, in a model
/// declaring `units.length = unit`: the same machine in another unit.
fn in_length_unit(text: &str, unit: &str, mm_per_unit: f64) -> String {
    let mut doc: toml::Table = toml::from_str(text).unwrap();
    let model = doc["model"].as_table_mut().unwrap();
    let mut units = toml::Table::new();
    units.insert("length".into(), unit.into());
    model.insert("units".into(), units.into());
    for (_, p) in doc["parameters"].as_table_mut().unwrap().iter_mut() {
        let p = p.as_table_mut().unwrap();
        if p["unit"].as_str() != Some("mm") {
            continue;
        }
        p.insert("unit".into(), unit.into());
        if let Some(v) = p
            .get("value")
            .and_then(toml::Value::as_float)
            .or_else(|| p.get("value").and_then(toml::Value::as_integer).map(|i| i as f64))
        {
            p.insert("value".into(), (v / mm_per_unit).into());
        }
        if let Some(r) = p.get("range").and_then(toml::Value::as_array).cloned() {
            let r: Vec<toml::Value> = r
                .iter()
                .map(|x| (x.as_float().or(x.as_integer().map(|i| i as f64)).unwrap() / mm_per_unit).into())
                .collect();
            p.insert("range".into(), r.into());
        }
    }
    // Plain numbers in fields without a unit in their name: the model's.
    fn scale(v: &mut toml::Value, k: f64) {
        match v {
            toml::Value::Integer(i) => *v = (*i as f64 / k).into(),
            toml::Value::Float(x) => *x /= k,
            toml::Value::Array(a) => a.iter_mut().for_each(|x| scale(x, k)),
            _ => {}
        }
    }
    for (_, p) in doc
        .get_mut("points")
        .and_then(toml::Value::as_table_mut)
        .into_iter()
        .flatten()
    {
        match p {
            toml::Value::Table(t) => t.get_mut("at").into_iter().for_each(|x| scale(x, mm_per_unit)),
            other => scale(other, mm_per_unit),
        }
    }
    for g in doc
        .get_mut("groups")
        .and_then(toml::Value::as_array_mut)
        .into_iter()
        .flatten()
    {
        let g = g.as_table_mut().unwrap();
        for key in ["by", "lengths", "length", "distance", "lift", "offset", "rod", "arm"] {
            g.get_mut(key).into_iter().for_each(|x| scale(x, mm_per_unit));
        }
    }
    toml::to_string(&doc).unwrap()
}

/// The lockstitch preset in inches: the same P and P′, its thickness
/// set in mm through the stitch (converted to its inch parameter).
#[test]
fn the_lockstitch_in_inches_matches_and_takes_its_thickness_in_mm() {
    let mm = Model::preset("lockstitch").unwrap();
    let text = in_length_unit(mm.text(), "in", 25.4);
    let inch = Model::from_toml_str(&text, "lockstitch-in.toml").unwrap();
    let m = inch.stitch_param("m").unwrap();
    let i = inch.param_index(m).unwrap();
    assert_eq!(inch.params()[i].unit_str(), "in");
    let (mut pi, mut pm) = (inch.defaults(), mm.defaults());
    set_stitch_value(&inch, &mut pi, "m", 2.54).unwrap();
    set_stitch_value(&mm, &mut pm, "m", 2.54).unwrap();
    assert!((pi.values[i] - 0.1).abs() < 1e-15, "{}", pi.values[i]);
    let (a, b) = (cycle(&inch, &pi), cycle(&mm, &pm));
    let path = &inch.thread_path_names()[0].to_string();
    let worst = p_of(&a, path)
        .iter()
        .zip(p_of(&b, path))
        .map(|(x, y)| (x - y).abs())
        .fold(0.0, f64::max);
    assert!(worst < 1e-9, "P differs by {worst} mm");
    // The mechanism, P and P′ to rounding. The thread's tension is solved
    // by iteration to a tolerance, and the same mm model with its
    // parameters changed by 1e-15 already moves its slack by 0.02 mm, so
    // the tension's columns are left out.
    let kinematic = |n: &str| !(n.contains("_T_") || n.contains("slack") || n.contains(".T") || n.contains("tension"));
    assert!(same_columns(&a, &b, 1e-8, kinematic) > 20);
}

#[test]
fn trigonometry_takes_the_models_angle_unit() {
    let model = |angle: &str, a: f64| {
        Model::from_toml_str(
            &format!(
                r#"
[model]
name = "trig"
units = {{ angle = "{angle}" }}
[parameters]
a = {{ value = {a}, unit = "{angle}" }}
l = {{ value = 40, unit = "mm" }}
x = {{ expr = "l*cos(a)", unit = "mm" }}
b = {{ expr = "atan2(l, x)", unit = "{angle}" }}
[points]
O = [0, 0]
A = ["x", "l*sin(b)"]
[[drivers]]
type = "crank"
center = "O"
out = "P"
radius = 10
"#
            ),
            "trig.toml",
        )
        .unwrap()
    };
    let deg = model("deg", 30.0);
    let rad = model("rad", std::f64::consts::FRAC_PI_6);
    let q = |m: &Model| {
        let p = m.defaults();
        let t = cycle(m, &p);
        (t.column("P.x_mm").unwrap()[7], m.parameter_values(&p).unwrap())
    };
    let (a, b) = (q(&deg), q(&rad));
    assert!((a.0 - b.0).abs() < 1e-12);
    let xi = deg.param_index("x").unwrap();
    assert!((a.1[xi] - 40.0 * 3f64.sqrt() / 2.0).abs() < 1e-12);
    assert!((a.1[xi] - b.1[xi]).abs() < 1e-12);
    let bi = deg.param_index("b").unwrap();
    // b = atan2(40, 34.64) = 49.1° = 0.857 rad: each in its model's unit.
    assert!(
        (a.1[bi] - b.1[bi].to_degrees()).abs() < 1e-9,
        "{} deg, {} rad",
        a.1[bi],
        b.1[bi]
    );
}

#[test]
fn a_parameter_in_another_unit_than_the_models_is_refused_with_the_fix() {
    let text = TAKEUP_IN.replacen(
        r#"l4_3   = { value = 0.8267716535433072,  unit = "in""#,
        r#"l4_3   = { value = 21,  unit = "mm""#,
        1,
    );
    assert_ne!(text, TAKEUP_IN, "the test edits the file");
    let e = Model::from_toml_str(&text, "m.toml").unwrap_err();
    assert_eq!(e.path, "parameters.l4_3.unit");
    assert!(
        e.message.contains("in mm") && e.message.contains("in in"),
        "{}",
        e.message
    );
    let help = e.help.clone().unwrap();
    assert!(help.contains(r#"unit = "in""#) && help.contains("units"), "{help}");
    assert!(e.span.is_some());
    // And in a model that declares no units, an inch parameter.
    let e = Model::from_toml_str(
        "[model]\nname = \"x\"\n[parameters]\nr = { value = 1, unit = \"in\" }\n",
        "x.toml",
    )
    .unwrap_err();
    assert!(e.message.contains("declares no `units`"), "{}", e.message);
}

#[test]
fn an_unknown_unit_gets_the_nearest_and_the_list() {
    for (bad, want) in [
        ("inch", "`in`"),
        ("inches", "`in`"),
        ("radians", "`rad`"),
        ("cms", "`cm`"),
    ] {
        let text = format!("[model]\nname = \"x\"\nunits = {{ length = \"{bad}\" }}\n");
        let text = if bad == "radians" {
            text.replace("length", "angle")
        } else {
            text
        };
        let e = Model::from_toml_str(&text, "x.toml").unwrap_err();
        let help = e.help.clone().unwrap_or_default();
        assert!(
            help.contains(&format!("did you mean {want}")),
            "{bad}: {} / {help}",
            e.message
        );
        assert!(e.span.is_some());
    }
    let e = Model::from_toml_str(
        "[model]\nname = \"x\"\n[parameters]\nr = { value = 1, unit = \"millimetres\" }\n",
        "x.toml",
    )
    .unwrap_err();
    assert!(e.help.unwrap().contains("did you mean `mm`"));
}
