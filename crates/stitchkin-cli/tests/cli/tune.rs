//! `stitchkin tune` adjusts machine settings and says how in shop terms;
//! the stitch's thickness and length are `--thickness` and `--stitch` in
//! every command, within the parameter's range.

use super::{fails, ok};

#[test]
fn tune_says_which_part_which_way_and_how_far() {
    let (out, _) = ok(&["tune", "--adjust", "z,dphi", "--step", "4", "--samples", "16"]);
    let mut lines = out.lines();
    assert!(lines.next().unwrap().starts_with("Recommended setting: z = "), "{out}");
    assert!(
        lines.next().unwrap().starts_with("(from z = 0 mm, dphi = 0 deg)"),
        "{out}"
    );
    assert_eq!(lines.next(), Some("On the machine:"), "{out}");
    let z = lines.next().unwrap();
    assert!(
        z.starts_with("  ball arm O2B along the take-up shaft: slide it ")
            && (z.contains("toward the take-up eyelets T1 by ") || z.contains("away from the take-up eyelets T1 by "))
            && z.contains(" mm (z: 0 → ")
            && z.ends_with(" mm)"),
        "{z}"
    );
    let dphi = lines.next().unwrap();
    assert!(
        dphi.starts_with("  eccentric O1A's timing on the main shaft: ") && dphi.contains(" deg (dphi: 0 → "),
        "{dphi}"
    );
    // The same in JSON, with the label and the sentence.
    let (json, _) = ok(&[
        "tune",
        "--adjust",
        "z",
        "--step",
        "6",
        "--samples",
        "8",
        "--format",
        "json",
    ]);
    let v: serde_json::Value = serde_json::from_str(&json).unwrap();
    let a = &v["adjustments"][0];
    assert_eq!(a["name"], "z");
    assert_eq!(a["kind"], "setting");
    assert_eq!(a["label"], "ball arm O2B along the take-up shaft");
    assert!(a["what"].as_str().unwrap().contains("take-up shaft"), "{a}");
    assert!(a["advice"].as_str().unwrap().contains("(z: 0 → "), "{a}");
}

#[test]
fn tune_adjusts_machine_settings_and_refuses_the_job_unless_allowed() {
    // altin504: the lower looper's timing, height and gap, by default.
    let (out, _) = ok(&["tune", "--preset", "altin504", "--step", "4", "--samples", "24"]);
    assert!(out.starts_with("Recommended setting: timing_l = "), "{out}");
    for part in [
        "  lower-looper timing: ",
        "  lower-looper height: ",
        "  lower-looper gap to the needle: ",
    ] {
        assert!(out.contains(part), "{part} missing:\n{out}");
    }
    assert!(
        out.contains("physical checks: before all pass, after all pass"),
        "{out}"
    );
    // The material is the job's: refused, with what to do and how to
    // search it anyway.
    let e = fails(&["tune", "--adjust", "m"]);
    assert!(
        e.contains("`m` (compressed material thickness m) is a job input, not a machine setting")
            && e.contains("(in --adjust)")
            && e.contains("--allow-inputs"),
        "{e}"
    );
    let e = fails(&["tune", "--adjust", "z,l_ab"]);
    assert!(
        e.contains("`l_ab` (rod AB with ball ends) is a fixed dimension") && e.contains("--allow-dimensions"),
        "{e}"
    );
    // Allowed, it is searched, and said to be what it is.
    let (json, _) = ok(&[
        "tune",
        "--adjust",
        "m",
        "--allow-inputs",
        "--step",
        "6",
        "--samples",
        "8",
        "--format",
        "json",
    ]);
    let v: serde_json::Value = serde_json::from_str(&json).unwrap();
    assert_eq!(v["adjustments"][0]["kind"], "input");
    // The nomogram refuses its own axis in its words, a dimension in these.
    let e = fails(&["nomogram", "--thickness", "3", "--adjust", "z,m"]);
    assert!(
        e.contains("`m` is the material thickness the nomogram is drawn over"),
        "{e}"
    );
}

#[test]
fn the_thickness_is_one_option_everywhere_within_its_range() {
    // `match --thickness` is `match --set m=`.
    let (a, _) = ok(&["match", "--thickness", "4", "--stitch", "2.5", "--format", "json"]);
    let (b, _) = ok(&["match", "--set", "m=4", "--set", "stitch=2.5", "--format", "json"]);
    assert_eq!(a, b);
    let v: serde_json::Value = serde_json::from_str(&a).unwrap();
    assert_eq!(v["m_mm"], 4.0, "{v}");
    // The parameter's range holds wherever the thickness is given.
    for args in [
        &["match", "--thickness", "0.3"][..],
        &["tune", "--thickness", "0.3", "--adjust", "z"],
        &["run", "--thickness", "0.3"],
        &["nomogram", "--thickness", "0.3:2:2", "--adjust", "z"],
    ] {
        let e = fails(args);
        assert!(
            e.contains("m = 0.3 mm is outside its adjustable range 0.5…5 mm") && e.contains("(in --thickness)"),
            "{args:?}: {e}"
        );
    }
    let e = fails(&["match", "--thickness", "4", "--set", "m=3"]);
    assert!(
        e.contains("`m` is given twice") && e.contains("give it once, with --thickness"),
        "{e}"
    );
    let e = fails(&["run", "--thickness", "1:3:3"]);
    assert!(
        e.contains("is a range, and this command takes one thickness") && e.contains("nomogram"),
        "{e}"
    );
    let e = fails(&["run", "--preset", "needle876", "--thickness", "3"]);
    assert!(e.contains("no [stitch]"), "{e}");
    // Without a model, the stitch still needs material.
    let e = fails(&["consumption", "--type", "401", "--thickness", "0", "--stitch", "3"]);
    assert!(
        e.contains("the material thickness = 0 is out of range") && e.contains("m > 0 mm"),
        "{e}"
    );
    ok(&["consumption", "--type", "401", "--thickness", "0.2", "--stitch", "3"]);
}

#[test]
fn check_says_what_each_parameter_is() {
    let (out, _) = ok(&["check", "--preset", "mf7923d"]);
    for line in [
        "  z          0 mm  range -10…10 mm  machine setting — ball arm O2B along the take-up shaft  [published]",
        "  m          3 mm  range 0.5…5 mm  job input — compressed material thickness m  [published]",
        "  l_ab       32 mm  fixed dimension — rod AB with ball ends  [published]",
        "  g3_1       0 mm  range -6…6 mm  machine setting — thread guide G3 of needle 1 (its height)  [published]",
    ] {
        assert!(out.contains(line), "`{line}` missing:\n{out}");
    }
}
