//! Nomograms: tune over a grid of material thickness and stitch length.

use stitchkin::model::{Model, Params};
use stitchkin::output::text;
use stitchkin::study::nomogram::{Axis, Nomogram, NomogramOptions, nomogram};
use stitchkin::study::tune::{TuneOptions, set_stitch_value, tune};

fn mf7923d(t1_phase: f64) -> (Model, Params) {
    let m = Model::preset("mf7923d").unwrap();
    let mut p = m.defaults();
    m.set(&mut p, "t1_phase", t1_phase).unwrap();
    (m, p)
}

fn opts(thickness: &str, stitch: Option<&str>, adjust: &[&str], step_deg: f64) -> NomogramOptions {
    NomogramOptions {
        thickness: Axis::parse(thickness, stitchkin::Input::Thickness).unwrap(),
        stitch: stitch.map(|s| Axis::parse(s, stitchkin::Input::StitchLength).unwrap()),
        tune: TuneOptions {
            objective: Default::default(),
            adjust: adjust.iter().map(|s| s.to_string()).collect(),
            samples: 0,
            seed: 1,
            step_deg,
        },
    }
}

/// Tuning never makes the match worse: the nominal setting competes.
fn assert_never_worse(n: &Nomogram) {
    for (p, r) in n.tuned() {
        let (b, a) = (&r.before_figures, &r.after_figures);
        assert!(
            a.objective <= b.objective + 1e-12,
            "m = {}, t = {}: J {} -> {}",
            p.m_mm,
            p.t_mm,
            b.objective,
            a.objective
        );
        assert!(
            a.score_mean >= b.score_mean - 1e-9,
            "m = {}, t = {}: score {} -> {}",
            p.m_mm,
            p.t_mm,
            b.score_mean,
            a.score_mean
        );
    }
}

#[test]
fn axes_parse_with_clear_errors() {
    assert_eq!(
        Axis::parse("0.5:5:10", stitchkin::Input::Thickness).unwrap(),
        Axis {
            lo: 0.5,
            hi: 5.0,
            n: 10
        }
    );
    assert_eq!(
        Axis::parse("4", stitchkin::Input::Thickness).unwrap(),
        Axis { lo: 4.0, hi: 4.0, n: 1 }
    );
    assert_eq!(Axis::parse("1:3", stitchkin::Input::StitchLength).unwrap().n, 11);
    let a = Axis::parse("1:4.5:8", stitchkin::Input::StitchLength).unwrap();
    assert_eq!((a.value(0), a.value(7)), (1.0, 4.5));
    for (spec, says) in [
        ("a:5:3", "must be numbers"),
        ("1:5:0", "whole number ≥ 1"),
        ("3:3:4", "LO = HI"),
        ("1:2:3:4", "not LO:HI:N"),
        ("nan", "not a number"),
        ("inf:5:2", "must be numbers"),
    ] {
        let e = Axis::parse(spec, stitchkin::Input::Thickness).unwrap_err();
        assert!(e.to_string().contains(says), "{spec}: {e}");
        let stitchkin::error::Error::Param(p) = e else {
            panic!("{spec}: not a parameter error")
        };
        assert_eq!(p.input, Some(stitchkin::Input::Thickness), "{spec}");
        assert!(p.help.unwrap().contains("LO:HI:N"), "{spec}");
    }
}

#[test]
fn bad_input_is_refused_before_anything_runs() {
    let (m, p) = mf7923d(180.0);
    let run = |o: NomogramOptions| nomogram(&m, &p, &o, || {}).unwrap_err().to_string();
    assert!(run(opts("0.5:9:3", None, &["z"], 10.0)).contains("outside its adjustable range"));
    assert!(run(opts("3", Some("0:3:2"), &["z"], 10.0)).contains("outside its adjustable range"));
    assert!(run(opts("3", None, &["z", "m"], 10.0)).contains("`m` is the material thickness"));
    assert!(run(opts("3", Some("1:3:2"), &["stitch"], 10.0)).contains("`stitch` is the stitch length"));
    assert!(run(opts("3", None, &["zz"], 10.0)).contains("no parameter `zz`"));
    assert!(run(opts("3", None, &["z"], 0.0)).contains("step 0 deg is out of range"));
    assert!(run(opts("0.5:5:200", Some("1:4.5:200"), &["z"], 10.0)).contains("40000 grid points"));
    let n = Model::preset("needle876").unwrap();
    let e = nomogram(&n, &n.defaults(), &opts("3", None, &["alpha"], 10.0), || {})
        .unwrap_err()
        .to_string();
    assert!(e.contains("no [stitch]"), "{e}");
    // A fixed dimension is refused before anything runs.
    assert!(run(opts("3", None, &["z", "l_ab"], 10.0)).contains("`l_ab` (rod AB with ball ends) is a fixed dimension"));
    // A model without machine settings has nothing to tune by default, and
    // says so: altin504 with its looper settings made fixed dimensions.
    let text = Model::preset("altin504")
        .unwrap()
        .text()
        .replace("kind = \"setting\"", "kind = \"dimension\"");
    let a = Model::from_toml_str(&text, "altin504.toml").unwrap();
    let Err(stitchkin::error::Error::Param(e)) = nomogram(&a, &a.defaults(), &opts("1:2.5:2", None, &[], 10.0), || {})
    else {
        panic!("a model without machine settings tuned");
    };
    assert!(e.message.contains("nothing to adjust"), "{e:?}");
    assert!(e.help.as_deref().unwrap_or("").contains("no machine setting"), "{e:?}");
}

/// Seed 000: "z = −2…−5 mm suits 3–5 mm material". At the default setting
/// (T1 up at the needle's TDC, the regulator's window computed from each
/// needle thread's tension) z tuned alone goes deep, near −9 mm for m = 3,
/// 4 and 5 mm, the paper's direction past its depth, with a large gain in
/// the match (docs/published-facts.md MF11); with the window assumed, the
/// last 60° before TDC, it sat near +2.4 mm.
#[test]
fn seed000_z_finding_at_the_default_setting() {
    let (m, p) = mf7923d(180.0);
    let calls = std::sync::atomic::AtomicUsize::new(0);
    let o = opts("3:5:3", None, &["z"], 5.0);
    let n = nomogram(&m, &p, &o, || {
        calls.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
    })
    .unwrap();
    assert_eq!(calls.into_inner(), 3, "progress once per grid point");
    assert_eq!(n.points.len(), 3);
    assert_eq!(n.adjust, vec![("z".to_string(), "mm")]);
    assert_eq!(n.threads, ["n1", "n2", "n3"]);
    assert_eq!(n.points.iter().map(|p| p.m_mm).collect::<Vec<_>>(), [3.0, 4.0, 5.0]);
    assert!(
        n.points.iter().all(|p| p.t_mm == 3.0 && p.error.is_none()),
        "t stays the preset's 3 mm"
    );
    assert_never_worse(&n);
    let z: Vec<f64> = n.tuned().map(|(_, r)| r.after[0]).collect();
    for (k, z) in z.iter().enumerate() {
        assert!((-10.0..=-7.0).contains(z), "m = {}: z = {z}", 3 + k);
    }
    for (_, r) in n.tuned() {
        let (b, a) = (r.before_figures.score_mean, r.after_figures.score_mean);
        assert!(a > b + 10.0 && a > 70.0, "a large gain: {b} -> {a}");
        assert!(
            r.after_figures.failed_checks.is_empty(),
            "{:?}",
            r.after_figures.failed_checks
        );
        let f = &r.flatness[0];
        assert!(f.lo <= -8.5 && f.hi <= -5.0, "the optimum is deep: {f:?}");
    }
    // No setting sits on a range end, so the nomogram has nothing to warn of.
    assert!(n.notes().is_empty(), "{:?}", n.notes());
    // The same seed gives the same nomogram, however the grid points are
    // scheduled (here: all on one thread).
    let pool = rayon::ThreadPoolBuilder::new().num_threads(1).build().unwrap();
    assert_eq!(pool.install(|| nomogram(&m, &p, &o, || {})).unwrap(), n);
    // A row is `tune` at that grid point with the same seed.
    let mut q = p.clone();
    set_stitch_value(&m, &mut q, "m", 4.0).unwrap();
    assert_eq!(&tune(&m, &q, &o.tune).unwrap(), n.points[1].tuned.as_ref().unwrap());
    assert!(!n.all_scores_zero());
    assert!(
        text::nomogram::table(&n).contains("z within 1 pt"),
        "{}",
        text::nomogram::table(&n)
    );
}

/// A grid over m and t, with the other reading of the take-up phase
/// (t1_phase = 0, T1 down at the needle's TDC). P then peaks near the
/// needle's BDC, far beyond what the needle can take: every score is 0
/// before and after, the thread bound fails everywhere, and the nomogram
/// says so.
#[test]
fn a_grid_over_thickness_and_stitch_runs_stitch_fastest() {
    let (m, p) = mf7923d(0.0);
    let n = nomogram(&m, &p, &opts("1:5:2", Some("1:4:2"), &["z"], 10.0), || {}).unwrap();
    let grid: Vec<(f64, f64)> = n.points.iter().map(|p| (p.m_mm, p.t_mm)).collect();
    assert_eq!(grid, [(1.0, 1.0), (1.0, 4.0), (5.0, 1.0), (5.0, 4.0)]);
    assert_never_worse(&n);
    for (_, r) in n.tuned() {
        for f in [&r.before_figures, &r.after_figures] {
            assert!(f.threads.iter().all(|t| t.1 == Some(0.0)), "{:?}", f.threads);
            assert!(f.objective > 1.4, "J = {}", f.objective);
        }
    }
    assert!(n.all_scores_zero());
    assert!(
        n.notes().iter().any(|t| t.contains("passes every physical check")),
        "{:?}",
        n.notes()
    );
    // Each point's stitch really has that m and t: the per-stitch thread
    // of stitch 407 is t + 2m, so P' differs between the points.
    let before: Vec<f64> = n.tuned().map(|(_, r)| r.before_figures.threads[0].2).collect();
    assert!(before.windows(2).all(|w| w[0] != w[1]), "{before:?}");
    let csv = text::nomogram::csv(&n);
    let lines: Vec<&str> = csv.lines().collect();
    assert_eq!(lines.len(), 5);
    let header: Vec<&str> = lines[0].split(',').collect();
    assert_eq!(&header[..5], ["m_mm", "t_mm", "z_mm", "z_lo_mm", "z_hi_mm"]);
    for col in [
        "score_mean_before",
        "score_mean_after",
        "J_after",
        "n1.score_after",
        "n3.rms_D_after_mm",
        "mu_max_after_deg",
        "status",
    ] {
        assert!(header.contains(&col), "{col} missing: {header:?}");
    }
    for l in &lines[1..] {
        assert_eq!(l.split(',').count(), header.len(), "{l}");
        assert!(l.ends_with(",ok") && !l.contains("NaN") && !l.contains("inf"), "{l}");
    }
    assert!(lines[2].starts_with("1,4,"), "{}", lines[2]);
    // Both axes varied: the table adds the matrix of each setting.
    let t = text::nomogram::table(&n);
    assert!(t.contains("recommended z (mm): rows m (mm), columns t (mm)"), "{t}");
    assert!(t.contains("Every match score is 0"), "{t}");
}
