//! Engine speed, one core, one full cycle (360 positions) per iteration.
//! `cargo bench -p stitchkin --bench engine` prints time and heap
//! allocations per cycle. Targets: four-bar ≤ 2 µs positions,
//! ≤ 6 µs with first and second analogs; needle876 with analogs ≤ 10 µs;
//! no heap allocation per φ step.

use divan::{Bencher, black_box};
use num_dual::Dual2_64;
use stitchkin::eval::cycle_phis_deg;
use stitchkin::mechanism::analogs::PoseAnalogs;
use stitchkin::mechanism::{Mechanism, Phi};
use stitchkin::model::Model;
use stitchkin::scalar::Real;
use stitchkin::thread::ThreadWork;

#[global_allocator]
static ALLOC: divan::AllocProfiler = divan::AllocProfiler::system();

/// The benchmark four-bar: O1 = (0,0), O2 = (60,0), crank 15,
/// coupler 50, rocker 40, coupler point 20 mm from A at 30° to AB. One file,
/// which the Python peer benchmark (crates/stitchkin-py/bench/peers.py)
/// reads too.
const FOUR_BAR: &str = include_str!("four_bar.toml");

fn main() {
    divan::main();
}

fn cycle<T: Real>(model: &Model) -> (Mechanism<T>, Vec<Phi<T>>) {
    let mech = model.mechanism::<T>(&model.defaults()).unwrap();
    let phis = Phi::table(&cycle_phis_deg(model.phi_start_deg(), 1.0));
    (mech, phis)
}

fn bench_cycle<T: Real>(bencher: Bencher, model: &Model) {
    let (mech, phis) = cycle::<T>(model);
    let mut pose = mech.new_pose(phis.len());
    let p = mech.n_points() - 1;
    bencher.bench_local(|| {
        mech.solve(black_box(&phis), &mut pose).unwrap();
        black_box(pose.point(p, 180))
    });
}

#[divan::bench]
fn four_bar_positions(bencher: Bencher) {
    bench_cycle::<f64>(bencher, &Model::from_toml_str(FOUR_BAR, "bench").unwrap());
}

/// Positions in `f64`, then exact first and second analogs of every point
/// in closed form (mechanism::analogs), as `run` computes them.
fn bench_closed_form(bencher: Bencher, model: &Model) {
    let (mech, phis) = cycle::<f64>(model);
    assert!(mech.has_closed_form_analogs());
    let mut pose = mech.new_pose(phis.len());
    let mut an = PoseAnalogs::new(mech.n_points(), phis.len());
    let p = mech.n_points() - 1;
    bencher.bench_local(|| {
        mech.solve(black_box(&phis), &mut pose).unwrap();
        mech.analogs(&phis, &pose, &mut an).unwrap();
        black_box(an.acc(p, 180))
    });
}

#[divan::bench]
fn four_bar_with_analogs(bencher: Bencher) {
    bench_closed_form(bencher, &Model::from_toml_str(FOUR_BAR, "bench").unwrap());
}

/// The same analogs carried by second-order dual numbers through the
/// position formulas (the solve for groups without a closed form).
#[divan::bench]
fn four_bar_with_analogs_dual(bencher: Bencher) {
    bench_cycle::<Dual2_64>(bencher, &Model::from_toml_str(FOUR_BAR, "bench").unwrap());
}

#[divan::bench]
fn needle876_positions(bencher: Bencher) {
    bench_cycle::<f64>(bencher, &Model::preset("needle876").unwrap());
}

#[divan::bench]
fn needle876_with_analogs(bencher: Bencher) {
    bench_closed_form(bencher, &Model::preset("needle876").unwrap());
}

#[divan::bench]
fn needle876_with_analogs_dual(bencher: Bencher) {
    bench_cycle::<Dual2_64>(bencher, &Model::preset("needle876").unwrap());
}

#[divan::bench]
fn overlock500_with_analogs(bencher: Bencher) {
    bench_cycle::<Dual2_64>(bencher, &Model::preset("overlock500").unwrap());
}

/// The floor: the same four-bar written by hand over precomputed crank
/// angles (circle intersection, no engine), with one division and one
/// square root per position: `1/|AO2|²` and `h`; the coupler's length is
/// known, so the coupler point needs neither.
#[divan::bench]
fn four_bar_hand_written(bencher: Bencher) {
    let (cs, sn): (Vec<f64>, Vec<f64>) = (0..360)
        .map(|k| (k as f64).to_radians())
        .map(|p| (p.cos(), p.sin()))
        .unzip();
    let (r, l, c, ox) = (15.0f64, 50.0f64, 40.0f64, 60.0f64);
    let (dc, ds) = (20.0 * 30f64.to_radians().cos() / l, 20.0 * 30f64.to_radians().sin() / l);
    let mut px = vec![0.0; 360];
    let mut py = vec![0.0; 360];
    bencher.bench_local(|| {
        let (cs, sn) = (black_box(&cs), black_box(&sn));
        for k in 0..360 {
            let (ax, ay) = (r * cs[k], r * sn[k]);
            let (dx, dy) = (ox - ax, -ay);
            let inv_d2 = 1.0 / (dx * dx + dy * dy);
            let kk = 0.5 * (l * l - c * c) * inv_d2 + 0.5;
            let h = (l * l * inv_d2 - kk * kk).sqrt();
            let (ex, ey) = (kk * dx - h * dy, kk * dy + h * dx);
            px[k] = ax + ex * dc - ey * ds;
            py[k] = ay + ex * ds + ey * dc;
        }
        black_box((&px, &py));
    });
}

/// Load, check and compile a model file (not per φ: once per model).
#[divan::bench]
fn load_needle876(bencher: Bencher) {
    let text = stitchkin::presets::find("needle876").unwrap().toml;
    bencher.bench_local(|| Model::from_toml_str(black_box(text), "needle876").unwrap());
}

/// Targets: mf7923d, 3 needles × contours A and B, 360 steps: the
/// mechanism solve plus every path's ξ(φ) (P = ξ(φ0) − ξ(φ) is one
/// subtraction more) ≤ 15 µs per cycle, ≤ 40 µs with P's analogs.
fn bench_takeup<T: Real>(bencher: Bencher) {
    let model = Model::preset("mf7923d").unwrap();
    let (mech, phis) = cycle::<T>(&model);
    let mut pose = mech.new_pose(phis.len());
    let threads = model.machine::<T>(&model.defaults()).unwrap().threads.unwrap();
    let mut work = ThreadWork::default();
    bencher.bench_local(|| {
        mech.solve(black_box(&phis), &mut pose).unwrap();
        threads.evaluate_into(&pose, None, &mut work).unwrap();
        black_box(work.tracks[5].xi[90])
    });
}

#[divan::bench]
fn mf7923d_take_up(bencher: Bencher) {
    bench_takeup::<f64>(bencher);
}

/// P's analogs in closed form: the mechanism's (`Mechanism::analogs`),
/// then the thread paths' (`Threads::evaluate_analogs`), with no pose of
/// dual numbers.
#[divan::bench]
fn mf7923d_take_up_with_analogs(bencher: Bencher) {
    let model = Model::preset("mf7923d").unwrap();
    let (plain, phis) = cycle::<f64>(&model);
    let threads = model.machine::<f64>(&model.defaults()).unwrap().threads.unwrap();
    let mut pose = plain.new_pose(phis.len());
    let mut an = PoseAnalogs::new(plain.n_points(), phis.len());
    let mut work = ThreadWork::default();
    bencher.bench_local(|| {
        plain.solve(black_box(&phis), &mut pose).unwrap();
        plain.analogs(&phis, &pose, &mut an).unwrap();
        threads.evaluate_analogs(&pose, &an, &mut work).unwrap();
        black_box(work.tracks[5].xi[90])
    });
}

#[divan::bench]
fn mf7923d_take_up_with_analogs_dual(bencher: Bencher) {
    bench_takeup::<Dual2_64>(bencher);
}

/// One sweep setting of mf7923d (3 needles × contours A and B, 360
/// steps, the three match scores), P' shared as the sweep shares it. Target:
/// ≥ 100 000 settings per second on 2 cores, i.e. ≤ 20 µs per setting per core.
#[divan::bench]
fn sweep_setting_mf7923d(bencher: Bencher) {
    use stitchkin::eval::CycleOptions;
    use stitchkin::study::design::{Design, Sweep, Vary};
    use stitchkin::study::{figures, sweep};
    let model = Model::preset("mf7923d").unwrap();
    let base = model.defaults();
    let sw = Sweep::new(vec![Vary::parse(&model, "z=-10:10:101").unwrap()], Design::Grid).unwrap();
    let shared = figures::shared_stitch(&model, &base, &sw, 1.0).unwrap();
    let names = vec!["score.mean".to_string()];
    let opts = CycleOptions {
        step_deg: 1.0,
        rpm: None,
        analogs: false,
        points: Some(Vec::new()),
        lean: true,
    };
    // One worker's evaluator, as `sweep::run` keeps one per worker.
    let mut ev = sweep::Evaluator::new(sweep::SweepJob {
        model: &model,
        base: &base,
        sweep: &sw,
        names: &names,
        opts: &opts,
        shared: shared.as_ref(),
    });
    assert!(ev.is_fast());
    let mut i = 0;
    bencher.bench_local(|| {
        i = (i + 1) % 101;
        black_box(ev.evaluate(i))
    });
}

/// `stitchkin tune` of mf7923d over z and dphi (target: under a second).
#[divan::bench(sample_count = 5)]
fn tune_mf7923d(bencher: Bencher) {
    use stitchkin::study::tune::{TuneOptions, tune};
    let model = Model::preset("mf7923d").unwrap();
    let mut base = model.defaults();
    model.set(&mut base, "t1_phase", 180.0).unwrap();
    let opts = TuneOptions {
        objective: Default::default(),
        adjust: vec!["z".into(), "dphi".into()],
        samples: 0,
        seed: 1,
        step_deg: 1.0,
    };
    bencher.bench_local(|| black_box(tune(&model, &base, &opts).unwrap()));
}

/// The P–P′ mismatch with the best lag over a cycle of 360 000 positions
/// (a 0.001° step), a 60° regulator window left out: the lag search by
/// FFT (target: well under a second; the direct search took minutes).
#[divan::bench(sample_count = 10)]
fn mismatch_lag_360000(bencher: Bencher) {
    use stitchkin::stitch::mismatch::mismatch;
    let n = 360_000;
    let phi_deg: Vec<f64> = (0..n).map(|k| k as f64 * 0.001).collect();
    let p: Vec<f64> = phi_deg
        .iter()
        .map(|f| 9.0 - 9.0 * (f.to_radians()).cos() + 1.5 * (2.0 * f.to_radians()).sin())
        .collect();
    let pprime: Vec<f64> = phi_deg
        .iter()
        .map(|f| 10.0 - 10.0 * ((f - 12.0).to_radians()).cos())
        .collect();
    let compared: Vec<bool> = phi_deg.iter().map(|&f| f < 300.0).collect();
    bencher.bench_local(|| black_box(mismatch(&phi_deg, &p, &pprime, &compared, 0.5, true)));
}

/// The thread's tension of every thread of `preset` over one cycle at 1°,
/// from their courses (the path geometry and the stitch's contour,
/// computed once): the periodic steady state, every cycle run to reach it.
fn bench_thread_tension(bencher: Bencher, preset: &str, threads: usize) {
    let model = Model::preset(preset).unwrap();
    let courses = stitchkin::eval::tension::courses(&model, &model.defaults(), 1.0).unwrap();
    assert_eq!(courses.len(), threads);
    bencher.bench_local(|| {
        for (_, c) in &courses {
            black_box(stitchkin::thread::tension::solve(&c.chain, &c.course()).unwrap());
        }
    });
}

/// The tension of the MF-7923D's three needle threads.
#[divan::bench]
fn mf7923d_thread_tension(bencher: Bencher) {
    bench_thread_tension(bencher, "mf7923d", 3);
}

/// The tension of the lockstitch's needle thread (its last span goes slack
/// as the hook casts the loop off).
#[divan::bench]
fn lockstitch_thread_tension(bencher: Bencher) {
    bench_thread_tension(bencher, "lockstitch", 1);
}

/// P′ at 1° of `preset` with parameter `name` set to a new value from
/// `lo` in steps of `step` each iteration (40 values in turn).
fn bench_stitch_setup(bencher: Bencher, preset: &str, name: &str, lo: f64, step: f64) {
    use stitchkin::eval::stitch_process::prepare;
    let model = Model::preset(preset).unwrap();
    let mut params = model.defaults();
    let mut i = 0;
    bencher.bench_local(|| {
        i = (i + 1) % 40;
        model.set(&mut params, name, lo + step * i as f64).unwrap();
        black_box(prepare(&model, &params, 1.0).unwrap())
    });
}

/// P′ of the MF-7923D's three needle threads at 1° for a new material
/// thickness m each iteration: the organs' motions, the stitch's moments
/// and P′ on the cycle's φ steps (target: at most 200 µs).
#[divan::bench]
fn stitch_setup_mf7923d(bencher: Bencher) {
    bench_stitch_setup(bencher, "mf7923d", "m", 1.0, 0.1);
}

/// P′ of the lockstitch's needle thread at 1° for a new catch rise each
/// iteration: the hook's loop at every φ.
#[divan::bench]
fn stitch_setup_lockstitch(bencher: Bencher) {
    bench_stitch_setup(bencher, "lockstitch", "catch_rise", 1.8, 0.025);
}

/// `run` of the MF-7923D at its defaults: every column of the cycle at 1°
/// with analogs, the stitch process, the thread's tension and the checks
/// (what `Model.preset("mf7923d").run()` computes from Python).
#[divan::bench]
fn run_mf7923d(bencher: Bencher) {
    use stitchkin::eval::{CycleOptions, run_cycle};
    let model = Model::preset("mf7923d").unwrap();
    let params = model.defaults();
    let opts = CycleOptions::default();
    bencher.bench_local(|| black_box(run_cycle(&model, &params, &opts).unwrap()));
}

/// The two charts the live page draws for the default preset, from one
/// cycle at 1° (as `/api/evaluate` computes it): P and P′ beside each
/// other, and the thread's tension; rendered to SVG text.
#[divan::bench]
fn page_charts_mf7923d(bencher: Bencher) {
    use stitchkin::eval::{CycleOptions, run_cycle};
    use stitchkin::output::plots;
    let model = Model::preset("mf7923d").unwrap();
    let opts = CycleOptions {
        analogs: false,
        points: Some(Vec::new()),
        ..Default::default()
    };
    let table = run_cycle(&model, &model.defaults(), &opts).unwrap();
    bencher.bench_local(|| {
        let take_up = plots::take_up_with_measured(&model, &table, &[]).unwrap().render();
        let tension = plots::tension(&model, &table).unwrap().render();
        black_box((take_up, tension))
    });
}
