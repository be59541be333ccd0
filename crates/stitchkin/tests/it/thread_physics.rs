//! The real thread over the cycle on the presets (docs/thread-physics.md):
//! its laws at every φ, the balance of thread per stitch, the limits a
//! tension model must reach, and bad inputs refused at their place.

use stitchkin::eval::tension::courses;
use stitchkin::eval::{CycleOptions, CycleTable, run_cycle};
use stitchkin::model::Model;
use stitchkin::thread::tension::{solve, verify};

/// The presets whose stitch threads carry thread physics.
const WITH_PHYSICS: [&str; 3] = ["mf7923d", "altin504", "lockstitch"];

/// `text` with `from` replaced once; `from` must occur in it.
fn edit(text: &str, from: &str, to: &str) -> String {
    assert!(text.contains(from), "no `{from}` in the model");
    text.replacen(from, to, 1)
}

fn preset_text(name: &str) -> String {
    stitchkin::presets::find(name).unwrap().toml.to_string()
}

fn cycle(model: &Model, step: f64) -> CycleTable {
    run_cycle(model, &model.defaults(), &CycleOptions::for_figures(step)).unwrap()
}

fn col<'a>(t: &'a CycleTable, name: &str) -> &'a [f64] {
    t.column(name).unwrap_or_else(|| panic!("no column {name}"))
}

/// At every φ of every preset's thread: the regulator never passes thread
/// back and never lets the tension past it exceed its hold, every guide
/// stays within its capstan bound and slips the way the larger tension
/// pulls, a slack span carries nothing; and the cycle repeats.
#[test]
fn the_laws_hold_at_every_position_on_every_preset() {
    for name in WITH_PHYSICS {
        let model = Model::preset(name).unwrap();
        let cs = courses(&model, &model.defaults(), 1.0).unwrap();
        assert!(!cs.is_empty(), "{name} solves no thread");
        for (thread, tc) in &cs {
            let t = solve(&tc.chain, &tc.course()).unwrap();
            assert!(
                t.settled,
                "{name} {thread}: change {} mm after {} cycles",
                t.change_mm, t.cycles
            );
            verify(&tc.chain, &tc.course(), &t).unwrap_or_else(|e| panic!("{name} {thread}: {e}"));
        }
    }
}

/// The thread drawn past the regulator per cycle, unstretched, times
/// (1 + the strain the finished stitch keeps) is the thread one stitch
/// consumes, to 0.1 %, on every preset with a stitch.
#[test]
fn the_thread_balances_on_every_preset_with_a_stitch() {
    let mut seen = 0;
    for name in stitchkin::presets::ALL.iter().map(|p| p.name) {
        let model = Model::preset(name).unwrap();
        let t = cycle(&model, 1.0);
        let Some(st) = &t.stitch else { continue };
        for th in &st.threads {
            let tn = th
                .tension
                .as_ref()
                .unwrap_or_else(|| panic!("{name} {}: every preset's stitch carries physics", th.thread));
            let balance = tn.drawn_per_cycle_mm * (1.0 + tn.lock_strain);
            assert!(
                (balance / th.per_stitch_mm - 1.0).abs() < 1e-3,
                "{name} {}: {} × (1 + {}) against {}",
                th.thread,
                tn.drawn_per_cycle_mm,
                tn.lock_strain,
                th.per_stitch_mm
            );
            seen += 1;
        }
    }
    assert_eq!(
        seen, 7,
        "three MF-7923D needles, the Altin's three threads, the lockstitch's needle"
    );
}

/// A very stiff thread is the ideal thread: where the whole thread from the
/// regulator to the stitch is taut, its slack is none, and elsewhere the
/// slack it carries is the ideal thread's D = P − P′ above its least, while
/// the stitch neither waits to be pulled tight nor has been (outside the
/// lock-to-TDC stretch, where the stitch's contour and P′ count the
/// finished stitch differently).
#[test]
fn a_very_stiff_thread_gives_back_the_ideal_threads_d() {
    let text = edit(
        &preset_text("mf7923d"),
        "ea    = { value = 85,    unit = \"N\",   range = [20, 300]",
        "ea    = { value = 1000000, unit = \"N\", range = [20, 1000000]",
    );
    let model = Model::from_toml_str(&text, "mf7923d-stiff.toml").unwrap();
    let t = cycle(&model, 1.0);
    let st = t.stitch.as_ref().unwrap();
    let phis = col(&t, "phi_deg");
    for th in &st.threads {
        let n = th.thread.as_str();
        let d = col(&t, &format!("{n}.D_mm"));
        let (path, below) = (
            col(&t, &format!("{n}.slack_mm")),
            col(&t, &format!("{n}.slack_stitch_mm")),
        );
        let (lock, tdc) = (th.lock_phi_deg, 360.0);
        let counted = |k: usize| !(lock..tdc).contains(&phis[k]);
        let least = (0..phis.len())
            .filter(|&k| counted(k))
            .map(|k| d[k])
            .fold(f64::MAX, f64::min);
        for k in (0..phis.len()).filter(|&k| counted(k)) {
            let slack = path[k] + below[k];
            assert!(
                (slack - (d[k] - least)).abs() < 0.02,
                "{n} at φ = {}: slack {slack} mm against D − min D = {} mm",
                phis[k],
                d[k] - least
            );
        }
        assert!(th.tension.as_ref().unwrap().lock_strain < 1e-4);
    }
}

/// Without friction (μ = 0 on every guide and the eye) a taut path carries
/// one tension from the regulator to the eye.
#[test]
fn without_friction_a_taut_path_carries_one_tension() {
    let text = edit(&preset_text("lockstitch"), "friction = 0.2", "friction = 0");
    let model = Model::from_toml_str(&text, "lockstitch-frictionless.toml").unwrap();
    let cs = courses(&model, &model.defaults(), 2.0).unwrap();
    let (_, tc) = &cs[0];
    let t = solve(&tc.chain, &tc.course()).unwrap();
    let s = t.spans;
    let mut taut = 0;
    for k in 0..t.drawn_mm.len() {
        // The path's spans (not the stitch's), all taut.
        if (0..s - 1).all(|i| t.slack_mm[k * s + i] == 0.0 && t.tension(k, i) > 0.0) {
            let row: Vec<f64> = (0..s - 1).map(|i| t.tension(k, i)).collect();
            let (lo, hi) = row.iter().fold((f64::MAX, 0.0f64), |(a, b), &x| (a.min(x), b.max(x)));
            assert!(hi - lo < 1e-6, "k = {k}: {row:?}");
            taut += 1;
        }
    }
    assert!(taut > 10, "the path is taut somewhere: {taut} positions");
}

/// A stronger regulator raises the thread's peak.
#[test]
fn a_stronger_regulator_raises_the_peak() {
    let model = Model::preset("mf7923d").unwrap();
    let peak = |hold: f64| {
        let mut p = model.defaults();
        model.set(&mut p, "regulator", hold).unwrap();
        let t = run_cycle(&model, &p, &CycleOptions::for_figures(2.0)).unwrap();
        t.stitch
            .unwrap()
            .threads
            .iter()
            .map(|th| th.tension.as_ref().unwrap().peak_n)
            .fold(0.0, f64::max)
    };
    let (weak, strong) = (peak(0.3), peak(0.5));
    assert!(strong > weak + 0.5, "{weak} N at 0.3 N, {strong} N at 0.5 N");
}

/// A check spring that can move takes up slack that a rigid one (the same
/// path without it) leaves.
#[test]
fn a_check_spring_takes_up_slack_a_rigid_guide_leaves() {
    let text = preset_text("lockstitch");
    let spring = "check_spring = { after = \"N1\", take_up_mm = \"spring_take_up\", force_n = [\"spring_start\", \"spring_end\"] }\n";
    let rigid = Model::from_toml_str(&edit(&text, spring, ""), "lockstitch-rigid.toml").unwrap();
    let model = Model::preset("lockstitch").unwrap();
    let slack = |m: &Model| {
        let t = cycle(m, 1.0);
        t.stitch.unwrap().threads[0].tension.clone().unwrap()
    };
    let (with, without) = (slack(&model), slack(&rigid));
    let travel = with.spring.as_ref().unwrap().max_travel_mm;
    assert!(travel > 1.0, "the spring moves: {travel} mm");
    assert!(
        with.max_slack_mm < without.max_slack_mm - 1.0,
        "slack loop {} mm with the spring, {} mm without",
        with.max_slack_mm,
        without.max_slack_mm
    );
}

/// A check spring whose ends are settings, moved so that its force falls
/// over its travel, is refused at the spring, saying which settings gave
/// which force, rounded as a person reads them.
#[test]
fn a_check_spring_set_to_fall_names_the_settings_that_did_it() {
    let model = Model::preset("lockstitch").unwrap();
    let mut params = model.defaults();
    model.set(&mut params, "spring_start", 0.574_186_094_452_398_7).unwrap();
    model.set(&mut params, "spring_end", 0.414_116_219_341_611_47).unwrap();
    let e = run_cycle(&model, &params, &CycleOptions::for_figures(10.0))
        .expect_err("a falling spring force")
        .to_string();
    assert!(
        e.contains("thread.physics.check_spring")
            && e.contains("runs 0.574 → 0.414 N over its travel")
            && e.contains("spring_start = 0.574 N, spring_end = 0.414 N")
            && e.contains("the force at the end of its travel above the one at its start"),
        "{e}"
    );
}

/// Bad thread physics is refused at its place in the file, with what to
/// give instead: EA ≤ 0, a negative friction or hold, a check spring with
/// negative travel, a clamp outside the path.
#[test]
fn bad_thread_physics_is_refused_at_its_place() {
    let mf = preset_text("mf7923d");
    let ls = preset_text("lockstitch");
    let cases = [
        (
            &mf,
            "ea_n = \"ea\"",
            "ea_n = 0",
            "thread.physics.ea_n",
            "must be positive",
        ),
        (
            &mf,
            "ea_n = \"ea\"",
            "ea_n = -5",
            "thread.physics.ea_n",
            "must be positive",
        ),
        (
            &mf,
            "regulator_n = \"regulator\"",
            "regulator_n = -0.1",
            "thread.physics.regulator_n",
            "must be positive",
        ),
        (
            &mf,
            "{ at = \"G7_1\", hold_n = \"clamp\" }",
            "{ at = \"G7_1\", hold_n = -1 }",
            "thread.physics.clamps[0].hold_n",
            "must not be negative",
        ),
        (
            &mf,
            "{ at = \"G7_1\", hold_n = \"clamp\" }",
            "{ at = \"O1\", hold_n = 0.1 }",
            "thread.physics.clamps[0].at",
            "not between the regulator and the eye",
        ),
        (
            &ls,
            "take_up_mm = \"spring_take_up\"",
            "take_up_mm = -3",
            "thread.physics.check_spring.take_up_mm",
            "must be positive",
        ),
        (
            &ls,
            "friction = 0.2",
            "friction = -0.2",
            "thread.friction",
            "out of range",
        ),
    ];
    for (text, from, to, place, says) in cases {
        let bad = edit(text, from, to);
        let e = match Model::from_toml_str(&bad, "bad.toml") {
            Err(e) => e.to_string(),
            Ok(m) => run_cycle(&m, &m.defaults(), &CycleOptions::for_figures(10.0))
                .expect_err(to)
                .to_string(),
        };
        assert!(
            e.contains("bad.toml:") && e.contains(place) && e.contains(says),
            "{to}: {e}"
        );
    }
}
