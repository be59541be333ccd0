//! What each parameter is on the machine (`kind`, `label`, `what`,
//! `increase`, `decrease`): the defaults, the checks on load, the presets'
//! settings, the tuning that adjusts only machine settings and says in shop
//! terms what to do.

use stitchkin::error::Error;
use stitchkin::eval::{CycleOptions, run_cycle};
use stitchkin::model::{Model, ParamKind};
use stitchkin::study::tune::{Adjustment, KindRefusal, TuneOptions, tune};

/// A small model with a stitch: a needle bar on a crank, a fixed guide, a
/// looper law; `params` is its [parameters] table.
fn model_with(params: &str) -> Result<Model, String> {
    let text = format!(
        r#"
[model]
name = "kinds"
phi_start_deg = 90

[parameters]
{params}

[points]
O = [0, 0]
G = [30, 20, 25]

[[drivers]]
type = "crank"
center = "O"
out = "A"
radius = "r"

[[groups]]
type = "rrp"
name = "rod"
from = "A"
length = 40
through = "O"
direction_deg = 90
out = "E"
branch = "backward"

[[groups]]
type = "offset"
name = "eye"
from = "E"
by = [0, -60]
out = "N"

[thread]
phi0_deg = 90

[thread.physics]
ea_n = "ea"
breaking_n = "breaking"
regulator_n = 0.5

[[thread.paths]]
name = "needle"
nodes = ["G", "N"]

[stitch]
type = "401"
m_mm = "m"
t_mm = "t"
cyclogram_zero_deg = 270
feed = {{ law = "harmonic", start_deg = 130, duration_deg = 100 }}

[[stitch.needles]]
name = "n1"
eye = "N"
path = "needle"

[stitch.looper]
law = {{ stroke_mm = 17, far_deg = 180, catch_deg = 30, depth_mm = 5.5 }}
k_mm = 4
a_mm = 1
b_mm = 2.5
gamma_max_deg = 23
"#
    );
    Model::from_toml_str(&text, "kinds.toml").map_err(|e| {
        let mut s = e.to_string();
        if let Some(h) = &e.help {
            s += &format!(" / help: {h}");
        }
        s
    })
}

const BASE: &str = r#"r = { value = 12, unit = "mm", range = [10, 14] }
m = { value = 2, unit = "mm", range = [0.5, 4] }
t = { value = 2.5, unit = "mm", range = [1, 4] }
ea = { value = 85, unit = "N", range = [20, 300] }
breaking = { value = 10.5, unit = "N" }
"#;

fn kind(m: &Model, name: &str) -> ParamKind {
    m.params()[m.param_index(name).unwrap()].kind
}

#[test]
fn kinds_default_to_what_the_model_does_with_each_parameter() {
    let m = model_with(&format!(
        "{BASE}w = {{ value = 3, unit = \"mm\" }}\nfixed = {{ value = 20, unit = \"deg\", range = [20, 20] }}\n\
         twice = {{ expr = \"2*r\", unit = \"mm\" }}\n"
    ))
    .unwrap();
    // The stitch's thickness and length, the thread's stiffness and
    // breaking force: job inputs, ranged or not.
    for n in ["m", "t", "ea", "breaking"] {
        assert_eq!(kind(&m, n), ParamKind::Input, "{n}");
    }
    // A range with room to move: a machine setting (old files keep tuning
    // what they tuned); none, a single value or derived: a fixed dimension.
    assert_eq!(kind(&m, "r"), ParamKind::Setting);
    for n in ["w", "fixed", "twice"] {
        assert_eq!(kind(&m, n), ParamKind::Dimension, "{n}");
    }
    assert!(m.params().iter().all(|p| !p.kind_declared));
    assert_eq!(m.machine_settings(), ["r"]);
    assert_eq!(m.default_adjustables(&m.defaults()).unwrap(), ["r"]);
    // A declared kind wins where the model allows it.
    let m = model_with(&format!(
        "{BASE}w = {{ value = 3, unit = \"mm\", range = [2, 4], kind = \"dimension\" }}\n"
    ))
    .unwrap();
    assert_eq!(kind(&m, "w"), ParamKind::Dimension);
    assert!(m.params()[m.param_index("w").unwrap()].kind_declared);
    assert_eq!(m.default_adjustables(&m.defaults()).unwrap(), ["r"]);
}

#[test]
fn kinds_and_words_are_checked_on_load() {
    for (extra, says, fix) in [
        (
            "w = { value = 3, unit = \"mm\", kind = \"setting\" }",
            "`w` is a machine setting but has no range",
            "range = [lo, hi]",
        ),
        (
            "w = { value = 3, unit = \"mm\", range = [3, 3], kind = \"setting\" }",
            "no range to be set in",
            "lo < hi",
        ),
        (
            "w = { expr = \"2*r\", unit = \"mm\", kind = \"setting\" }",
            "derived (with `expr`), so nothing sets it",
            "kind = \"dimension\"",
        ),
        (
            "w = { value = 3, unit = \"mm\", kind = \"knob\" }",
            "unknown variant `knob`",
            "",
        ),
        (
            "w = { value = 3, unit = \"mm\", label = \"  \" }",
            "`label` is empty",
            "leave `label` out",
        ),
        (
            "w = { value = 3, unit = \"mm\", label = \"two\\nlines\" }",
            "a label is one line",
            "`what`",
        ),
        (
            "w = { value = 3, unit = \"mm\", increase = \"raise it\" }",
            "`increase` is given without `decrease`",
            "give both",
        ),
        (
            "w = { expr = \"2*r\", unit = \"mm\", increase = \"a\", decrease = \"b\" }",
            "a derived parameter (with `expr`) is not set",
            "parameters it is derived from",
        ),
    ] {
        let e = model_with(&format!("{BASE}{extra}\n")).unwrap_err();
        assert!(e.contains(says), "{extra}: {e}");
        assert!(e.contains(fix), "{extra} gives no fix: {e}");
        assert!(e.contains("kinds.toml"), "{extra}: no place: {e}");
    }
    // The stitch's thickness is a job input whatever the file says.
    let e = model_with(&BASE.replace(
        "m = { value = 2, unit = \"mm\", range = [0.5, 4] }",
        "m = { value = 2, unit = \"mm\", range = [0.5, 4], kind = \"setting\" }",
    ))
    .unwrap_err();
    assert!(
        e.contains("the stitch's material thickness ([stitch] m_mm), a job input") && e.contains("kind = \"input\""),
        "{e}"
    );
}

/// Every preset says what each parameter is: its kind written out, a label
/// and a sentence; every machine setting has a range to move in and the
/// two ways a technician moves it; the stitch's thickness and length are
/// job inputs.
#[test]
fn every_preset_parameter_says_what_it_is() {
    for preset in stitchkin::presets::ALL {
        let m = Model::preset(preset.name).unwrap();
        for p in m.params() {
            let at = format!("{}: {}", preset.name, p.name);
            assert!(p.kind_declared, "{at}: no kind");
            let label = p.label.as_deref().unwrap_or_else(|| panic!("{at}: no label"));
            let what = p.what.as_deref().unwrap_or_else(|| panic!("{at}: no what"));
            assert!(label.len() < 90 && !label.ends_with('.'), "{at}: label `{label}`");
            assert!(what.ends_with('.') && what.len() < 300, "{at}: what `{what}`");
            for word in ["session", "issue", "developer", "TODO"] {
                assert!(!label.contains(word) && !what.contains(word), "{at}: says `{word}`");
            }
            if p.kind == ParamKind::Setting {
                assert!(p.is_adjustable_setting(), "{at}: a setting without room to move");
                assert!(p.increase.is_some() && p.decrease.is_some(), "{at}: no way to move it");
            } else {
                assert!(p.increase.is_none(), "{at}: a way to move what is not set");
            }
        }
        for which in ["m", "t"] {
            if let Some(n) = m.stitch_param(which) {
                assert_eq!(
                    m.params()[m.param_index(n).unwrap()].kind,
                    ParamKind::Input,
                    "{}: {n}",
                    preset.name
                );
            }
        }
        // A machine with a stitch has settings to tune.
        if m.has_stitch() {
            assert!(
                !m.default_adjustables(&m.defaults()).unwrap().is_empty(),
                "{}",
                preset.name
            );
        }
    }
}

#[test]
fn the_presets_expose_their_machines_settings() {
    let settings = |name: &str| {
        Model::preset(name)
            .unwrap()
            .machine_settings()
            .into_iter()
            .map(str::to_string)
            .collect::<Vec<_>>()
    };
    // Seed 000: Table 3, R and alpha0 (section 4.2), the guides G3 along Y
    // per needle, the thread's regulator and clamp.
    assert_eq!(
        settings("mf7923d"),
        [
            "r1",
            "l_o2b",
            "z",
            "r2",
            "R",
            "psi",
            "regulator",
            "clamp",
            "dphi",
            "g3_1",
            "g3_2",
            "g3_3"
        ]
    );
    let mf = Model::preset("mf7923d").unwrap();
    assert_eq!(
        mf.default_adjustables(&mf.defaults()).unwrap(),
        ["r1", "l_o2b", "z", "r2", "R", "psi", "dphi", "g3_1", "g3_2", "g3_3"]
    );
    // The Altin: the lower looper's timing, height and gap to the needle,
    // and the regulators.
    let a = Model::preset("altin504").unwrap();
    assert_eq!(
        a.default_adjustables(&a.defaults()).unwrap(),
        ["timing_l", "height_l", "gap_l"]
    );
    assert_eq!(
        settings("altin504"),
        ["regulator_needle", "regulator_looper", "timing_l", "height_l", "gap_l"]
    );
    // The lockstitch: the hook's timing, the needle bar's height, the
    // regulator and the check spring; the lever's pivot is a dimension.
    assert_eq!(
        settings("lockstitch"),
        [
            "catch_rise",
            "s_b",
            "regulator",
            "spring_take_up",
            "spring_start",
            "spring_end"
        ]
    );
    assert_eq!(settings("needle876"), ["alpha"]);
    assert_eq!(settings("overlock500"), ["l19_20", "phi02"]);
    assert!(settings("altin-needle").is_empty() && settings("takeup-lever").is_empty());
}

fn quick(adjust: &[&str], samples: usize, step_deg: f64) -> TuneOptions {
    TuneOptions {
        objective: Default::default(),
        adjust: adjust.iter().map(|s| s.to_string()).collect(),
        samples,
        seed: 1,
        step_deg,
    }
}

#[test]
fn tuning_refuses_job_inputs_and_fixed_dimensions_unless_allowed() {
    let mut m = Model::preset("mf7923d").unwrap();
    let p = m.defaults();
    for (name, says, instead) in [
        (
            "m",
            "`m` (compressed material thickness m) is a job input",
            "allow job inputs",
        ),
        ("stitch", "is a job input", "a nomogram tunes them over the job's range"),
        ("ea", "is a job input", "allow job inputs"),
        (
            "l_ab",
            "`l_ab` (rod AB with ball ends) is a fixed dimension",
            "allow fixed dimensions",
        ),
        ("t1_phase", "is a fixed dimension", "change to the machine's design"),
    ] {
        let Err(Error::Param(e)) = tune(&m, &p, &quick(&[name], 8, 10.0)) else {
            panic!("{name} tuned");
        };
        assert!(e.message.contains(says), "{name}: {e:?}");
        let help = e.help.unwrap_or_default();
        assert!(
            help.contains(instead) && help.contains("r1, l_o2b, z"),
            "{name}: {help}"
        );
    }
    assert!(KindRefusal::of(&m, "z").is_none() && KindRefusal::of(&m, "zz").is_none());
    // Allowed, the job input is searched like a setting.
    m.allow_adjusting(ParamKind::Input);
    assert!(KindRefusal::of(&m, "m").is_none() && KindRefusal::of(&m, "l_ab").is_some());
    let r = tune(&m, &p, &quick(&["m"], 8, 10.0)).unwrap();
    assert_eq!(r.adjustments[0].kind, ParamKind::Input);
    m.allow_adjusting(ParamKind::Dimension);
    assert!(KindRefusal::of(&m, "l_ab").is_none());
}

#[test]
fn advice_names_the_part_the_way_and_how_far() {
    let m = Model::preset("mf7923d").unwrap();
    let def = |n: &str| &m.params()[m.param_index(n).unwrap()];
    let a = Adjustment::new(def("z"), 0.0, -0.3249);
    assert_eq!(
        a.advice,
        "ball arm O2B along the take-up shaft: slide it away from the take-up eyelets T1 by 0.32 mm (z: 0 → -0.32 mm)"
    );
    assert_eq!(
        (a.label.as_str(), a.unit, a.kind),
        ("ball arm O2B along the take-up shaft", "mm", ParamKind::Setting)
    );
    assert!(a.what.as_deref().unwrap().contains("take-up shaft"));
    let a = Adjustment::new(def("dphi"), 0.0, 8.694);
    assert_eq!(
        a.advice,
        "eccentric O1A's timing on the main shaft: turn it forward on the shaft (T1 earlier) by 8.69 deg (dphi: 0 → 8.69 deg)"
    );
    // The change between the printed values, and none below a hundredth.
    assert!(
        Adjustment::new(def("r1"), 4.0, 4.776)
            .advice
            .contains("by 0.78 mm (r1: 4 → 4.78 mm)")
    );
    assert_eq!(
        Adjustment::new(def("z"), 0.0, 0.004).advice,
        "ball arm O2B along the take-up shaft: leave it as it is (z = 0 mm)"
    );
    // Without words in the file: the name, and which way the number goes.
    let bare = model_with(BASE).unwrap();
    let r = &bare.params()[bare.param_index("r").unwrap()];
    assert_eq!(
        Adjustment::new(r, 12.0, 11.5).advice,
        "r: decrease it by 0.5 mm (r: 12 → 11.5 mm)"
    );
}

/// The Altin's lower looper, set by its timing, height and gap: tuning
/// adjusts them by default and never loses match or a check.
#[test]
fn altin504_tunes_its_looper_settings() {
    let m = Model::preset("altin504").unwrap();
    let p = m.defaults();
    let adjust = m.default_adjustables(&p).unwrap();
    let mut opts = quick(&[], 24, 4.0);
    opts.adjust = adjust;
    let r = tune(&m, &p, &opts).unwrap();
    assert_eq!(
        r.names.iter().map(|n| n.0.as_str()).collect::<Vec<_>>(),
        ["timing_l", "height_l", "gap_l"]
    );
    assert!(r.after_figures.objective <= r.before_figures.objective + 1e-12, "{r:?}");
    assert!(r.after_figures.feasible && r.before_figures.feasible, "{r:?}");
    assert!(
        r.adjustments[0].advice.starts_with("lower-looper timing: "),
        "{:?}",
        r.adjustments
    );
}

/// The looper's settings at 0 are the preset as it was laid out; each moves
/// what it says: the timing the catch and the drop, the height the point's
/// clearance above the eye.
#[test]
fn altin504_looper_settings_move_what_they_say() {
    let m = Model::preset("altin504").unwrap();
    let text = m.text();
    // The file without the settings: the same table, number for number.
    let laid_out = [
        ("\"ph_l + timing_l\"", "\"ph_l\""),
        ("\"rl_l + height_l\"", "\"rl_l\""),
        ("catch_deg = \"30 - timing_l\"", "catch_deg = 30"),
        ("drop_deg = \"300 - timing_l\"", "drop_deg = 300"),
        ("k_mm = \"k_l - height_l\"", "k_mm = \"k_l\""),
        (
            "\"(k_l - height_l + b_l)*tan(alpha) + gap_l\"",
            "\"(k_l + b_l)*tan(alpha)\"",
        ),
    ]
    .iter()
    .fold(text.to_string(), |t, (from, to)| {
        assert!(t.contains(from), "{from}");
        t.replace(from, to)
    });
    let before = Model::from_toml_str(&laid_out, "altin504.toml").unwrap();
    let opts = CycleOptions::default();
    let a = run_cycle(&m, &m.defaults(), &opts).unwrap();
    let b = run_cycle(&before, &before.defaults(), &opts).unwrap();
    assert_eq!(a.columns, b.columns);
    assert_eq!(a.stitch, b.stitch);
    // Timing: the catch and the drop come earlier by the advance.
    let setup = |set: &[(&str, f64)]| {
        let mut p = m.defaults();
        for (n, v) in set {
            m.set(&mut p, n, *v).unwrap();
        }
        m.stitch_setup(&p).unwrap().unwrap()
    };
    let early = setup(&[("timing_l", 4.0)]);
    assert_eq!(early.spec.needles[0].catch_deg, Some(26.0));
    assert_eq!(early.spec.needles[0].drop_deg, Some(296.0));
    // Height: the looper's upper face comes up with it.
    let raised = setup(&[("height_l", 1.0)]);
    assert!((raised.spec.looper.as_ref().unwrap().k_mm - 3.0).abs() < 1e-12);
    let clearance = |set: &[(&str, f64)]| {
        let mut p = m.defaults();
        for (n, v) in set {
            m.set(&mut p, n, *v).unwrap();
        }
        let t = run_cycle(&m, &p, &opts).unwrap();
        let st = t.stitch.unwrap();
        st.checks.iter().find(|c| c.name == "catch_clearance").unwrap().value
    };
    let c0 = clearance(&[]);
    let c1 = clearance(&[("height_l", 0.5)]);
    assert!((c1 - c0 - 0.5).abs() < 0.05, "{c0} -> {c1}");
}

/// Seed 000's guides G3 as settings: at Table 2's heights the machine is
/// exactly as before (literal coordinates), every check passes, and each
/// guide moves its own needle's thread only.
#[test]
fn mf7923d_guides_g3_are_settings_that_change_nothing_at_their_defaults() {
    let m = Model::preset("mf7923d").unwrap();
    let literal = [("\"g3_1\"", "0"), ("\"g3_2\"", "12"), ("\"g3_3\"", "24")].iter().fold(
        m.text().to_string(),
        |t, (from, to)| {
            assert!(t.contains(&format!("at = [-29, {from},")), "{from}");
            t.replace(&format!("at = [-29, {from},"), &format!("at = [-29, {to},"))
        },
    );
    let fixed = Model::from_toml_str(&literal, "mf7923d.toml").unwrap();
    let opts = CycleOptions::default();
    let a = run_cycle(&m, &m.defaults(), &opts).unwrap();
    let b = run_cycle(&fixed, &fixed.defaults(), &opts).unwrap();
    assert_eq!(a.columns, b.columns);
    assert_eq!(a.stitch, b.stitch);
    assert!(a.stitch.as_ref().unwrap().checks_ok());
    let mut p = m.defaults();
    m.set(&mut p, "g3_1", 6.0).unwrap();
    let c = run_cycle(&m, &p, &opts).unwrap();
    let col = |t: &stitchkin::eval::CycleTable, n: &str| t.columns.iter().find(|c| c.name == n).unwrap().values.clone();
    assert_ne!(col(&a, "n1_A.P_B_mm"), col(&c, "n1_A.P_B_mm"));
    assert_eq!(col(&a, "n2_A.P_B_mm"), col(&c, "n2_A.P_B_mm"));
    // Out of its range, refused.
    assert!(m.set(&mut p, "g3_1", 7.0).unwrap_err().to_string().contains("-6…6 mm"));
}
