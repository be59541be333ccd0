//! Input limits, checked before the work they limit: a request past one
//! fails at once, without a panic, naming the limit and the fix.

use super::{fails, ok};

#[test]
fn too_many_samples_are_refused_at_once() {
    // 2³² once wrapped in u32 and panicked; 10⁹ held 4 GB before the check.
    for n in ["4294967296", "1000000000"] {
        for method in ["lhs", "random"] {
            let e = fails(&["sweep", "--vary", "z=-10:10", "--samples", n, "--method", method]);
            assert!(e.contains(&format!("{n} settings")) && e.contains("100 million"), "{e}");
        }
        for args in [
            &["tune", "--adjust", "z"][..],
            &["nomogram", "--thickness", "1:3:2"],
            &["plot", "nomogram", "--thickness", "1:3:2"],
            &["report", "--tune"],
        ] {
            let e = fails(&[args, &["--samples", n]].concat());
            assert!(
                e.contains("samples are too many") && e.contains("at most 100000"),
                "{args:?}: {e}"
            );
        }
    }
}

#[test]
fn one_value_from_a_range_is_refused_by_sweeps_and_charts_alike() {
    for args in [
        &["sweep", "--vary", "z=-10:10:1"][..],
        &["plot", "family", "--vary", "z=-10:10:1"],
    ] {
        let e = fails(args);
        assert!(
            e.contains("1 value between two different ends") && e.contains("N ≥ 2"),
            "{args:?}: {e}"
        );
        assert!(e.contains("z=-10:-10:1"), "{args:?} gives no one-value form: {e}");
    }
    // LO:LO:1 is the one value: a sweep of one setting.
    let (csv, _) = ok(&["sweep", "--vary", "z=-10:-10:1"]);
    assert_eq!(csv.lines().filter(|l| !l.starts_with('#')).count(), 2, "{csv}");
}

#[test]
fn a_step_out_of_range_is_told_its_bounds() {
    let e = fails(&["run", "--step", "0"]);
    assert!(e.contains("greater than 0 and at most 360 degrees"), "{e}");
    let e = fails(&["stroke", "--preset", "needle876", "--point", "G", "--step", "0"]);
    assert!(e.contains("greater than 0 and at most 45 degrees"), "{e}");
}
