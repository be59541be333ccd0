//! The model fitted to a measured take-up (study::fit_measured): a known
//! setting recovered from noisy synthetic data within its interval, the
//! interval's coverage over many draws, and the warning for parameters the
//! data cannot tell apart.
//!
//! The synthetic measurement: P of needle thread n1 at B from the preset
//! mf7923d at z = −3 mm, Δφ = 5° (the rest as shipped), every 10° of φ
//! (36 samples), plus independent Gaussian noise of σ = 0.05 mm drawn by a
//! fixed-seed splitmix64 generator (Steele et al. 2014) through Box–Muller.

use stitchkin::eval::{CycleOptions, run_cycle};
use stitchkin::model::{Model, Params};
use stitchkin::study::fit_measured::{CurveInput, FitMeasuredOptions, fit_measured};
use stitchkin::thread::measured::parse_curve_csv;

/// splitmix64: a 64-bit state advanced by the golden-ratio increment and
/// mixed (Steele, Lea & Flood 2014).
struct SplitMix(u64);

impl SplitMix {
    fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }

    /// Uniform on (0, 1): the top 53 bits, shifted off 0.
    fn uniform(&mut self) -> f64 {
        ((self.next_u64() >> 11) as f64 + 0.5) / (1u64 << 53) as f64
    }

    /// Standard normal (Box–Muller): √(−2 ln u1) cos(2π u2).
    fn normal(&mut self) -> f64 {
        let (u1, u2) = (self.uniform(), self.uniform());
        (-2.0 * u1.ln()).sqrt() * (2.0 * std::f64::consts::PI * u2).cos()
    }
}

const TRUE_Z: f64 = -3.0;
const TRUE_DPHI: f64 = 5.0;
const NOISE_MM: f64 = 0.05;
const STEP: f64 = 10.0;

fn model() -> Model {
    Model::preset("mf7923d").unwrap()
}

fn at(m: &Model, pairs: &[(&str, f64)]) -> Params {
    let mut p = m.defaults();
    for (k, v) in pairs {
        m.set(&mut p, k, *v).unwrap();
    }
    p
}

/// The cycle of `m` at `p` every 10°, without analogs or points.
fn cycle(m: &Model, p: &Params) -> stitchkin::eval::CycleTable {
    run_cycle(
        m,
        p,
        &CycleOptions {
            step_deg: STEP,
            rpm: None,
            analogs: false,
            points: Some(Vec::new()),
            lean: false,
        },
    )
    .unwrap()
}

/// φ and P of n1 at B at the true setting, every 10°.
fn truth(m: &Model) -> (Vec<f64>, Vec<f64>) {
    let t = cycle(m, &at(m, &[("z", TRUE_Z), ("dphi", TRUE_DPHI)]));
    (
        t.column("phi_deg").unwrap().to_vec(),
        t.column("n1_A.P_B_mm").unwrap().to_vec(),
    )
}

fn noisy_curve(phi: &[f64], p: &[f64], rng: &mut SplitMix, sigma: Option<f64>) -> CurveInput {
    let mut csv = String::from("phi_deg,n1.P_B_mm\n");
    for (f, v) in phi.iter().zip(p) {
        csv += &format!("{f},{}\n", v + NOISE_MM * rng.normal());
    }
    let mut curve = parse_curve_csv(&csv, "synthetic.csv").unwrap();
    if let Some(s) = sigma {
        curve = curve.with_sigma_mm(vec![s; phi.len()]).unwrap();
    }
    CurveInput { thread: None, curve }
}

fn opts(adjust: &[&str]) -> FitMeasuredOptions {
    FitMeasuredOptions {
        adjust: adjust.iter().map(|s| s.to_string()).collect(),
        step_deg: Some(STEP),
        ..Default::default()
    }
}

#[test]
fn a_noisy_measurement_gives_back_z_and_dphi_within_their_intervals() {
    let m = model();
    let (phi, p) = truth(&m);
    let mut rng = SplitMix(4);
    let curve = noisy_curve(&phi, &p, &mut rng, None);
    // From the shipped setting z = 0, Δφ = 0.
    let f = fit_measured(&m, &m.defaults(), &[curve], &opts(&["z", "dphi"])).unwrap();
    assert!(f.converged, "{}", f.stop);
    assert!(!f.sigma_known);
    assert_eq!((f.samples, f.dof), (36, 34));
    for (v, truth) in f.params.iter().zip([TRUE_Z, TRUE_DPHI]) {
        let [lo, hi] = v.interval.unwrap();
        eprintln!(
            "{} = {:.4} ± {:.4} {}, 95 % {lo:.4}…{hi:.4} (true {truth})",
            v.name,
            v.fitted,
            v.std_error.unwrap(),
            v.unit
        );
        assert!(lo <= truth && truth <= hi, "{} not in its interval", v.name);
    }
    // s estimates the noise.
    let s = f.sigma_estimated_mm.unwrap();
    assert!((s - NOISE_MM).abs() < 0.4 * NOISE_MM, "s = {s}");
    assert!(f.quantile_from.contains("Student"));
    assert!((f.quantile - 2.032).abs() < 1e-3, "t(0.975, 34) = {}", f.quantile);
    assert_eq!(f.correlation.len(), 2);
    assert!(f.curves[0].exact_jacobian);
    assert!(f.warnings.is_empty(), "{:?}", f.warnings);
    assert_eq!(f.curves[0].residual_mm.len(), 36);
}

#[test]
fn a_known_uncertainty_weighs_the_fit_and_gives_normal_intervals() {
    let m = model();
    let (phi, p) = truth(&m);
    let mut rng = SplitMix(7);
    let curve = noisy_curve(&phi, &p, &mut rng, Some(NOISE_MM));
    let f = fit_measured(&m, &m.defaults(), &[curve], &opts(&["z", "dphi"])).unwrap();
    assert!(f.sigma_known && f.sigma_estimated_mm.is_none());
    assert!((f.quantile - 1.959_964).abs() < 1e-5);
    // χ²/dof about 1 when σ is the noise.
    assert!(f.chi2_per_dof > 0.4 && f.chi2_per_dof < 1.8, "{}", f.chi2_per_dof);
    for (v, truth) in f.params.iter().zip([TRUE_Z, TRUE_DPHI]) {
        let [lo, hi] = v.interval.unwrap();
        assert!(lo <= truth && truth <= hi, "{} = {} not in {lo}…{hi}", v.name, v.fitted);
    }
}

/// Over 200 noisy draws the 95 % intervals hold the true z and Δφ about 95 %
/// of the time (binomial: 0.95 ± 2·0.015; each fit starts at the shipped
/// setting).
#[test]
fn the_intervals_cover_the_truth_at_about_their_nominal_rate() {
    let m = model();
    let (phi, p) = truth(&m);
    let mut rng = SplitMix(2026);
    let draws = 200;
    let mut hits = [0usize; 2];
    let started = std::time::Instant::now();
    let curves: Vec<CurveInput> = (0..draws).map(|_| noisy_curve(&phi, &p, &mut rng, None)).collect();
    use rayon::prelude::*;
    let results: Vec<[bool; 2]> = curves
        .into_par_iter()
        .map(|c| {
            let f = fit_measured(&m, &m.defaults(), &[c], &opts(&["z", "dphi"])).unwrap();
            let inside = |j: usize, truth: f64| {
                let [lo, hi] = f.params[j].interval.unwrap();
                lo <= truth && truth <= hi
            };
            [inside(0, TRUE_Z), inside(1, TRUE_DPHI)]
        })
        .collect();
    for r in &results {
        for j in 0..2 {
            hits[j] += r[j] as usize;
        }
    }
    let rate = hits.map(|h| h as f64 / draws as f64);
    eprintln!(
        "coverage over {draws} draws: z {:.3}, dphi {:.3} ({:.1} s)",
        rate[0],
        rate[1],
        started.elapsed().as_secs_f64()
    );
    for r in rate {
        assert!((0.90..=0.99).contains(&r), "coverage {r}");
    }
}

/// The eccentric's throw r1 and the ball arm's length l_o2b set the
/// take-up arm's swing through their ratio: the data cannot tell them
/// apart.
#[test]
fn two_parameters_the_data_cannot_separate_are_named() {
    let m = model();
    let (phi, p) = truth(&m);
    let mut rng = SplitMix(11);
    let curve = noisy_curve(&phi, &p, &mut rng, None);
    let base = at(&m, &[("z", TRUE_Z), ("dphi", TRUE_DPHI), ("r1", 4.5)]);
    let f = fit_measured(&m, &base, &[curve], &opts(&["r1", "l_o2b"])).unwrap();
    eprintln!("{:?}\n{:#?}", f.correlation, f.warnings);
    assert!(f.correlation[0][1].abs() > 0.95, "{:?}", f.correlation);
    assert!(
        f.warnings
            .iter()
            .any(|w| w.contains("`r1`") && w.contains("`l_o2b`") && w.contains("cannot be told apart")),
        "{:?}",
        f.warnings
    );
}

#[test]
fn fitting_needs_samples_a_grid_and_known_parameters() {
    let m = model();
    let rows: String = (0..9).map(|k| format!("{},{}\n", 40 * k, k)).collect();
    let curve = parse_curve_csv(&format!("phi_deg,n1.P_B_mm\n{rows}"), "short.csv").unwrap();
    let c = || CurveInput {
        thread: None,
        curve: curve.clone(),
    };
    // Nine samples, nine parameters.
    let nine = ["z", "dphi", "r1", "R", "psi", "l_o2b", "r2", "g3_1", "g3_2"];
    let e = fit_measured(&m, &m.defaults(), &[c()], &opts(&nine))
        .unwrap_err()
        .to_string();
    assert!(e.contains("9 measured samples for 9 parameters"), "{e}");
    // A parameter the model lacks: its names.
    let e = fit_measured(&m, &m.defaults(), &[c()], &opts(&["zz"])).unwrap_err();
    assert!(format!("{e:?}").contains("dphi"), "{e:?}");
    let e = fit_measured(&m, &m.defaults(), &[c()], &opts(&["dphii"])).unwrap_err();
    assert!(format!("{e:?}").contains("did you mean `dphi`?"), "{e:?}");
    // A sample off the grid.
    let off = parse_curve_csv(
        "phi_deg,n1.P_B_mm\n0,0\n40,1\n85,7\n130,12\n175,17\n220,12\n265,5\n300,3\n340,2\n",
        "off.csv",
    )
    .unwrap();
    let e = fit_measured(
        &m,
        &m.defaults(),
        &[CurveInput {
            thread: None,
            curve: off,
        }],
        &opts(&["z"]),
    )
    .unwrap_err()
    .to_string();
    assert!(e.contains("φ = 85 deg") && e.contains("10 deg grid"), "{e}");
    // A thread the stitch lacks.
    let e = fit_measured(
        &m,
        &m.defaults(),
        &[CurveInput {
            thread: Some("n7".into()),
            curve: curve.clone(),
        }],
        &opts(&["z"]),
    )
    .unwrap_err();
    assert!(format!("{e:?}").contains("n1"), "{e:?}");
}

/// The advice from a fit: the tune starts at the fitted setting (its
/// "before" is the fitted machine's match, equal to `run_match` there) and
/// does not end worse; a fitted dimension is kept as fitted and said so.
#[test]
fn the_advice_tunes_from_the_fitted_setting() {
    use stitchkin::eval::run_match;
    use stitchkin::study::fit_measured::{advise, fitted_params};
    let m = model();
    let (phi, p) = truth(&m);
    let mut rng = SplitMix(5);
    let curve = noisy_curve(&phi, &p, &mut rng, Some(NOISE_MM));
    let f = fit_measured(&m, &m.defaults(), std::slice::from_ref(&curve), &opts(&["z", "dphi"])).unwrap();
    let a = advise(&m, &m.defaults(), &f, 64, 1, 2.0).unwrap();
    let t = a.tune.as_ref().expect("z and dphi are settings: a tune");
    let fitted = fitted_params(&m, &m.defaults(), &f).unwrap();
    assert_eq!(
        t.before,
        vec![
            fitted.values[m.param_index("z").unwrap()],
            fitted.values[m.param_index("dphi").unwrap()]
        ]
    );
    let table = run_match(&m, &fitted, 2.0).unwrap();
    let st = table.stitch.as_ref().unwrap();
    let n1 = st.threads.iter().find(|th| th.thread == "n1").unwrap();
    let before_n1 = t.before_figures.threads.iter().find(|th| th.0 == "n1").unwrap();
    let score = n1.mismatch.as_ref().unwrap().score.unwrap();
    assert!(
        (before_n1.1.unwrap() - score).abs() < 1e-9,
        "{:?} vs {score}",
        before_n1.1
    );
    assert!(t.after_figures.score_mean >= t.before_figures.score_mean - 1e-9);
    // A dimension fitted with a setting: kept as fitted, the setting tuned.
    let f = fit_measured(&m, &m.defaults(), &[curve], &opts(&["z", "h=30:34"])).unwrap();
    let a = advise(&m, &m.defaults(), &f, 64, 1, 2.0).unwrap();
    assert_eq!(
        a.tune
            .as_ref()
            .unwrap()
            .names
            .iter()
            .map(|n| n.0.as_str())
            .collect::<Vec<_>>(),
        ["z"]
    );
    assert!(
        a.notes
            .iter()
            .any(|n| n.contains("`h`") && n.contains("kept as fitted")),
        "{:?}",
        a.notes
    );
}

/// A feed mechanism without [stitch] (seed 004's variant 5, a rocking
/// roller follower): a measured P of its thread path fits its arm's length;
/// a required P′ cannot be fitted there, and the error says why.
#[test]
fn a_feed_mechanism_without_a_stitch_fits_its_paths_take_up() {
    let file = format!(
        "{}/../../examples/seed004-variants/variant5.toml",
        env!("CARGO_MANIFEST_DIR")
    );
    let m = Model::from_path(std::path::Path::new(&file)).unwrap();
    let t = cycle(&m, &at(&m, &[("l_arm", 36.0)]));
    let (phi, p) = (t.column("phi_deg").unwrap(), t.column("lower.P_mm").unwrap());
    let mut rng = SplitMix(9);
    let mut csv = String::from("phi_deg,lower.P_mm\n");
    for (f, v) in phi.iter().zip(p) {
        csv += &format!("{f},{}\n", v + 0.02 * rng.normal());
    }
    let curve = parse_curve_csv(&csv, "v5.csv").unwrap();
    let f = fit_measured(
        &m,
        &m.defaults(),
        &[CurveInput {
            thread: None,
            curve: curve.clone(),
        }],
        &opts(&["l_arm=30:40"]),
    )
    .unwrap();
    let [lo, hi] = f.params[0].interval.unwrap();
    assert!(
        lo <= 36.0 && 36.0 <= hi,
        "{} not around 36: {lo}…{hi}",
        f.params[0].fitted
    );
    assert!(f.curves[0].exact_jacobian && f.curves[0].path == "lower");
    let required = parse_curve_csv(&csv.replace("lower.P_mm", "lower.Pprime_mm"), "v5p.csv").unwrap();
    let e = fit_measured(
        &m,
        &m.defaults(),
        &[CurveInput {
            thread: None,
            curve: required,
        }],
        &opts(&["l_arm=30:40"]),
    )
    .unwrap_err()
    .to_string();
    assert!(e.contains("without [stitch]"), "{e}");
}
