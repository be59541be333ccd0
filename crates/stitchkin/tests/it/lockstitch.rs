//! The `lockstitch` preset: seed 001's take-up lever with a needle bar and a
//! rotary hook, stitch 301 (docs/stitch-formation.md §13).

use stitchkin::eval::stitch_process::StitchSummary;
use stitchkin::eval::{CycleOptions, CycleTable, run_cycle};
use stitchkin::model::Model;
use stitchkin::study::tune::{TuneOptions, tune};
use stitchkin::{StitchGeometry, consumption};

/// A cycle at `set` with the regulator's window assumed (the stitch
/// process's and the kinematic match's own figures; the thread's tension
/// is solved all the same).
fn run_with(set: &[(&str, f64)]) -> CycleTable {
    let model = super::support::assumed_window("lockstitch");
    let mut params = model.defaults();
    for (k, v) in set {
        model.set(&mut params, k, *v).unwrap();
    }
    run_cycle(&model, &params, &CycleOptions::default()).unwrap()
}

fn stitch(t: &CycleTable) -> &StitchSummary {
    t.stitch.as_ref().expect("lockstitch has a [stitch]")
}

/// The preset's kinematic match, and what its thread's tension says of it:
/// the lever gives 41.3 mm where the hook takes 66.5 mm, so the hook draws
/// the difference from the slack the lever gave, the check spring and the
/// thread's stretch, and pulls the stitch's thread through the regulator
/// just before it sheds the loop (the thread's peak); the lever draws the
/// loop back up after TDC, before the needle enters the material again.
/// Every check passes.
#[test]
fn the_default_matches_and_its_lever_draws_the_loop_back_up() {
    let t = run_with(&[]);
    let s = stitch(&t);
    assert_eq!(s.stitch_type, 301);
    let names: Vec<&str> = s.checks.iter().map(|c| c.name).collect();
    assert_eq!(
        names,
        [
            "thread_bound",
            "takeup_gives",
            "hook_clearance",
            "tension_margin",
            "slack_loop",
            "stitch_set",
            "spring_before_slip"
        ]
    );
    assert!(s.checks_ok(), "{:?}", s.checks);
    // The check spring is at its end before thread slips (0.35 N < 0.7 N).
    assert!(s.checks[6].value < 1e-3 && s.checks[6].message.contains("pull test passes"));
    let beak = s.checks[2].value;
    assert!(
        (beak - 1.48).abs() < 0.005,
        "the beak {beak} mm above the eye at the catch"
    );
    assert!(s.warnings.is_empty(), "{:?}", s.warnings);
    assert!(s.transfers.iter().any(|w| w.contains("401")), "{:?}", s.transfers);
    let [needle] = &s.threads[..] else {
        panic!("one thread: {:?}", s.threads.len())
    };
    assert_eq!(needle.thread, "needle");
    // The thread locked per stitch is 301's needle thread, t + 2·f·l_m.
    let c = consumption(301, &StitchGeometry::new(2.0, 2.5)).unwrap();
    assert!((needle.per_stitch_mm - c.threads[0].length_mm.unwrap()).abs() < 1e-12);
    assert!((needle.locked_mm - needle.per_stitch_mm).abs() < 1e-9);
    // Golden: the match and the loop released where the beak sheds it
    // (φ = 282.5°).
    let mm = needle.mismatch.as_ref().unwrap();
    assert!((mm.score.unwrap() - 81.3).abs() < 0.05, "{mm:?}");
    assert!((mm.rms_d_mm - 13.290).abs() < 1e-3, "{mm:?}");
    assert!((needle.lock_phi_deg - 282.46).abs() < 0.05, "{}", needle.lock_phi_deg);
    assert!((needle.released_mm - 66.741).abs() < 1e-3, "{}", needle.released_mm);
    assert!((needle.max_pprime_mm - 70.943).abs() < 1e-3, "{}", needle.max_pprime_mm);
    // The thread: its peak while the hook pulls, below the stitch (N–stitch)
    // in the 20° before the loop is shed, where thread passes the regulator.
    let tn = needle.tension.as_ref().unwrap();
    assert!(
        tn.peak_span == "N–stitch" && (needle.lock_phi_deg - 20.0..needle.lock_phi_deg).contains(&tn.peak_at_deg),
        "{tn:?}"
    );
    assert!(
        tn.regulator_windows_deg
            .iter()
            .any(|w| w[0] <= tn.peak_at_deg + 1.0 && tn.peak_at_deg <= w[1]),
        "{tn:?}"
    );
    // Pulled taut after TDC and before the needle enters the material.
    assert!(
        tn.set_slack_mm < 0.05 && (10.0..60.0).contains(&tn.set_at_deg),
        "{tn:?}"
    );
    // P and P' at B are 0 at φ0 = TDC and finite everywhere.
    for name in ["needle.P_B_mm", "needle.Pprime_B_mm"] {
        let v = t.column(name).unwrap();
        assert!(v[0].abs() < 1e-12 && v.iter().all(|x| x.is_finite()), "{name}");
    }
}

/// The reading the thread physics decided against: a loop the beak holds
/// until it has passed the bottom of the case (270° of its turn) is shed
/// 17° before TDC, and the lever cannot draw it back up before the needle
/// enters the material again: `stitch_set` fails by most of the loop.
#[test]
fn a_loop_held_past_the_bottom_of_the_case_is_never_drawn_up() {
    let text = super::support::assumed_text("lockstitch");
    let from = "cast_off = { value = 148, unit = \"deg\", range = [130, 170]";
    assert!(text.contains(from), "the preset's cast_off line moved");
    let late = text.replace(from, "cast_off = { value = 270, unit = \"deg\", range = [240, 300]");
    let model = Model::from_toml_str(&late, "lockstitch-late.toml").unwrap();
    let t = run_cycle(&model, &model.defaults(), &CycleOptions::for_figures(2.0)).unwrap();
    let s = stitch(&t);
    let set = s.checks.iter().find(|c| c.name == "stitch_set").unwrap();
    assert!(
        !set.ok && set.value > 30.0 && set.message.contains("never pulls"),
        "{set:?}"
    );
    assert!(s.threads[0].lock_phi_deg > 340.0, "{}", s.threads[0].lock_phi_deg);
}

#[test]
fn the_hook_timing_moves_the_stitch() {
    // A later catch (more needle rise) finds a longer loop: P' grows.
    let base = stitch(&run_with(&[])).threads[0].max_pprime_mm;
    let late = stitch(&run_with(&[("catch_rise", 2.8)])).threads[0].max_pprime_mm;
    assert!(late != base);
    // The needle bar set 2 mm higher: the beak meets the needle below the
    // eye, where there is no loop; the check says so.
    let high = run_with(&[("s_b", 15.0)]);
    let clearance = stitch(&high)
        .checks
        .iter()
        .find(|c| c.name == "hook_clearance")
        .unwrap();
    assert!(
        !clearance.ok && clearance.value < 0.0 && clearance.message.contains("below"),
        "{clearance:?}"
    );
    // An earlier cast-off releases the loop before it has gone as far round.
    let early_run = run_with(&[("cast_off", 130.0)]);
    let early = &stitch(&early_run).threads[0];
    assert!(early.lock_phi_deg < 282.0 && early.released_mm < 66.7, "{early:?}");
}

#[test]
fn tune_adjusts_the_lever_and_the_hook_timing() {
    let mut model = Model::preset("lockstitch").unwrap();
    let base = model.defaults();
    // The technician's settings: the hook's timing and the needle bar's
    // height (the regulator and the check spring are tuned when named).
    let adjust = model.default_adjustables(&base).unwrap();
    assert_eq!(adjust, ["catch_rise", "s_b"]);
    // The lever's pivot is a fixed dimension: searched only as a change to
    // the design, when allowed.
    let opts = |adjust: &[&str], samples| TuneOptions {
        objective: Default::default(),
        adjust: adjust.iter().map(|s| s.to_string()).collect(),
        samples,
        seed: 1,
        step_deg: 6.0,
    };
    let Err(stitchkin::error::Error::Param(e)) = tune(&model, &base, &opts(&["x4"], 6)) else {
        panic!("x4 tuned without --allow-dimensions");
    };
    assert!(
        e.message.contains("`x4`") && e.message.contains("fixed dimension"),
        "{e:?}"
    );
    assert!(
        e.help.as_deref().unwrap_or("").contains("allow fixed dimensions"),
        "{e:?}"
    );
    model.allow_adjusting(stitchkin::model::ParamKind::Dimension);
    // The lever shares one P′ over its settings; the hook's timing changes
    // the stitch, so each of its settings recomputes P′: a few samples here
    // (the command line's default is 32 per setting).
    for (adjust, samples) in [(vec!["x4", "y4"], 64), (vec!["catch_rise"], 6)] {
        let r = tune(&model, &base, &opts(&adjust, samples)).unwrap();
        // The default passes every check, and so does the tuned setting.
        assert!(
            r.after_figures.failed_checks.is_empty(),
            "{adjust:?}: {:?}",
            r.after_figures.failed_checks
        );
        assert!(r.after_figures.mu_ok, "{adjust:?}");
        assert!(
            r.after_figures.score_mean >= r.before_figures.score_mean - 1e-9,
            "{adjust:?}"
        );
    }
}

#[test]
fn a_lockstitch_model_must_have_its_hook() {
    let text = Model::preset("lockstitch").unwrap().text().to_string();
    let hook_start = text.find("[stitch.hook]").unwrap();
    let err = |t: &str| Model::from_toml_str(t, "lockstitch.toml").unwrap_err().to_string();
    // No hook.
    let e = err(&text[..hook_start]);
    assert!(e.contains("needs its hook") && e.contains("lockstitch.toml"), "{e}");
    // A looper instead.
    let with_looper = format!(
        "{}\n[stitch.looper]\nlaw = {{ stroke_mm = 32, far_deg = 180, catch_deg = 30, depth_mm = 5.5 }}\nk_mm = 4\na_mm = 1\nb_mm = 2.5\ngamma_max_deg = 23\n",
        &text[..hook_start]
    );
    assert!(err(&with_looper).contains("has a hook, not a looper"));
    // The interlacing belongs to the lockstitch only.
    let chain = Model::preset("mf7923d")
        .unwrap()
        .text()
        .replace("type = \"407\"", "type = \"407\"\ninterlace = 0.5");
    assert!(err(&chain).contains("no interlacing depth"));
    // A hook that would stand above the plate is refused when run.
    let shallow = text.replace(r#"hook_depth = { value = 15.7"#, r#"hook_depth = { value = 12"#);
    let model = Model::from_toml_str(&shallow, "lockstitch.toml").unwrap();
    let e = run_cycle(&model, &model.defaults(), &CycleOptions::default())
        .unwrap_err()
        .to_string();
    assert!(e.contains("above the plate top"), "{e}");
    // A case that reaches across the needle line is refused when run.
    let wide = text.replace("case_radius_mm = 11", "case_radius_mm = 12.5");
    let model = Model::from_toml_str(&wide, "lockstitch.toml").unwrap();
    let e = run_cycle(&model, &model.defaults(), &CycleOptions::default())
        .unwrap_err()
        .to_string();
    assert!(e.contains("hook") && e.contains("beside the needle line"), "{e}");
}
