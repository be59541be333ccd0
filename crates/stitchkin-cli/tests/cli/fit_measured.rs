//! `stitchkin fit --measured`: the machine's setting from its measured
//! take-up, with intervals, the correlation of the fitted parameters, the
//! warning for parameters the data cannot tell apart, the residual chart and
//! the advice that follows.

use super::{fails, ok, scratch};

/// The illustrative bench file of examples/: the mf7923d preset's n1 take-up
/// at z = −3 mm, Δφ = 5° plus documented noise, ten readings every 10°.
fn bench() -> String {
    format!("{}/../../examples/mf7923d-bench-n1.csv", env!("CARGO_MANIFEST_DIR"))
}

/// `stitchkin fit --preset mf7923d --measured n1=BENCH` and `rest`.
fn fit_bench(rest: &[&str]) -> Vec<String> {
    let mut args: Vec<String> = ["fit", "--preset", "mf7923d", "--measured"]
        .iter()
        .map(|s| s.to_string())
        .collect();
    args.push(format!("n1={}", bench()));
    args.extend(rest.iter().map(|s| s.to_string()));
    args
}

/// [`ok`] and [`fails`] of owned arguments.
fn ok_with(args: &[String]) -> (String, String) {
    ok(&args.iter().map(String::as_str).collect::<Vec<_>>())
}
fn fails_with(args: &[String]) -> String {
    fails(&args.iter().map(String::as_str).collect::<Vec<_>>())
}

#[test]
fn fit_measured_recovers_z_and_dphi_within_their_intervals_and_advises() {
    let (json, _) = ok_with(&fit_bench(&["--adjust", "z,dphi", "--format", "json"]));
    let v: serde_json::Value = serde_json::from_str(&json).unwrap();
    let fit = &v["fit"];
    assert_eq!(fit["sigma_known"], true, "ten readings per φ carry their uncertainty");
    assert_eq!((fit["samples"].as_u64(), fit["dof"].as_u64()), (Some(36), Some(34)));
    for (p, truth) in fit["params"].as_array().unwrap().iter().zip([-3.0, 5.0]) {
        let iv: Vec<f64> = p["interval"]
            .as_array()
            .unwrap()
            .iter()
            .map(|x| x.as_f64().unwrap())
            .collect();
        assert!(
            iv[0] <= truth && truth <= iv[1],
            "{} = {} not in {iv:?}",
            p["name"],
            p["fitted"]
        );
        assert!(iv[1] - iv[0] < 0.5, "an interval that says something: {iv:?}");
    }
    assert_eq!(fit["correlation"].as_array().unwrap().len(), 2);
    assert!(fit["chi2_per_dof"].as_f64().unwrap() < 1.8);
    // The advice starts at the fitted setting.
    let tune = &v["advice"]["tune"];
    let fitted: Vec<f64> = fit["params"]
        .as_array()
        .unwrap()
        .iter()
        .map(|p| p["fitted"].as_f64().unwrap())
        .collect();
    let before: Vec<f64> = tune["before"]
        .as_array()
        .unwrap()
        .iter()
        .map(|x| x.as_f64().unwrap())
        .collect();
    assert_eq!(before, fitted);
    assert!(tune["after_figures"]["score_mean"].as_f64() >= tune["before_figures"]["score_mean"].as_f64());
    assert!(!json.contains("NaN"));
}

#[test]
fn fit_measured_prints_the_setting_the_residuals_and_the_advice_and_draws_the_chart() {
    let d = scratch("fit-measured-screen");
    let chart = d.join("residuals.svg");
    let (screen, err) = ok_with(&fit_bench(&["--adjust", "z,dphi", "--chart", chart.to_str().unwrap()]));
    for part in [
        "95 % interval",
        "ball arm O2B along the take-up shaft",
        "correlation ρ",
        "χ²/dof",
        "residuals (model − measured)",
        "The fitted machine against the stitch",
        "On the machine:",
        "Recommended setting:",
    ] {
        assert!(screen.contains(part), "missing `{part}`:\n{screen}");
    }
    assert!(err.contains("residuals.svg"), "{err}");
    let svg = std::fs::read_to_string(&chart).unwrap();
    assert!(svg.starts_with("<svg") || svg.starts_with("<?xml"), "{}", &svg[..80]);
    assert!(
        svg.contains("residuals of the fit") && svg.contains("φ = 350°"),
        "a dot per sample"
    );
    // Only the fit.
    let (bare, _) = ok_with(&fit_bench(&["--adjust", "z,dphi", "--no-advice"]));
    assert!(bare.contains("95 % interval") && !bare.contains("Recommended setting"));
    // Another confidence widens the intervals.
    let (wide, _) = ok_with(&fit_bench(&["--adjust", "z", "--no-advice", "--confidence", "0.99"]));
    assert!(wide.contains("99 % interval") && wide.contains("± 2.576"), "{wide}");
}

/// r1 (the eccentric's throw) and l_o2b (where B sits on the ball arm) set
/// T1's swing through their ratio: the warning names them.
#[test]
fn fit_measured_names_two_parameters_the_data_cannot_tell_apart() {
    let (screen, _) = ok_with(&fit_bench(&[
        "--set",
        "z=-3",
        "--set",
        "dphi=5",
        "--adjust",
        "r1,l_o2b",
        "--no-advice",
    ]));
    assert!(
        screen.contains("warning: `r1`") && screen.contains("cannot be told apart"),
        "{screen}"
    );
}

#[test]
fn fit_measured_refuses_what_it_cannot_do_with_the_fix() {
    let spec = format!("n1={}", bench());
    let e = fails_with(&fit_bench(&[]));
    assert!(e.contains("--adjust z,dphi"), "{e}");
    let e = fails(&[
        "fit",
        "--preset",
        "mf7923d",
        "--measured",
        "no-such-bench.csv",
        "--adjust",
        "z",
    ]);
    assert!(e.contains("no-such-bench.csv"), "{e}");
    let e = fails_with(&fit_bench(&["--adjust", "z", "--confidence", "1.5"]));
    assert!(e.contains("confidence") && e.contains("0.95"), "{e}");
    let e = fails_with(&fit_bench(&["--adjust", "z", "--chart", "r.pdf"]));
    assert!(e.contains("--chart") && e.contains(".svg"), "{e}");
    let e = fails(&["fit", "--preset", "mf7923d", "--adjust", "z"]);
    assert!(e.contains("--target") && e.contains("--measured"), "{e}");
    let e = fails(&["fit", "--preset", "mf7923d", "--adjust", "zz", "--measured", &spec]);
    assert!(e.contains("dphi"), "the model's parameters named: {e}");
}
