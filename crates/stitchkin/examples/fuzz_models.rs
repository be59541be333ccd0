//! Fuzzes the model loader and `run_cycle` with mutants of the shipped
//! presets (`tests/fuzz/mutate.rs` says which edits and which checks):
//!
//! ```sh
//! cargo run --release -p stitchkin --example fuzz_models -- --runs 1000000
//! ```
//!
//! Options: `--runs N` (default 1 000 000), `--seed S` (default 1),
//! `--threads T` (default: every core), `--limit-s L` (a mutant slower than
//! L seconds is a finding; default 5). Prints what the mutants did and every
//! finding, writes each finding's input to `target/fuzz-findings/`, and
//! exits 1 when there is one (2 when a mutant runs 10 times the limit: a
//! hang). A slow mutant is checked again alone at the end: one that is fast
//! by itself was slowed by other work on the machine, and is listed but not
//! a finding.

#[path = "../tests/fuzz/mutate.rs"]
mod mutate;

use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

use mutate::{Finding, Rng, check, mutate, seeds};

struct Options {
    runs: usize,
    seed: u64,
    threads: usize,
    limit: Duration,
}

fn options() -> Result<Options, String> {
    let mut o = Options {
        runs: 1_000_000,
        seed: 1,
        threads: std::thread::available_parallelism().map_or(1, |n| n.get()),
        limit: Duration::from_secs(5),
    };
    let args: Vec<String> = std::env::args().skip(1).collect();
    for pair in args.chunks(2) {
        let value = pair.get(1).ok_or(format!("{} needs a value", pair[0]))?;
        let bad = |_| format!("{} {value}: not a whole number", pair[0]);
        match pair[0].as_str() {
            "--runs" => o.runs = value.parse().map_err(bad)?,
            "--seed" => o.seed = value.parse().map_err(bad)?,
            "--threads" => o.threads = value.parse::<usize>().map_err(bad)?.max(1),
            "--limit-s" => o.limit = Duration::from_secs(value.parse().map_err(bad)?),
            other => {
                return Err(format!(
                    "unknown option {other}: --runs N, --seed S, --threads T, --limit-s L"
                ));
            }
        }
    }
    Ok(o)
}

/// Per worker: when its current mutant started (`None` once it is done),
/// and the mutant.
type Current = Arc<Vec<Mutex<(Option<Instant>, Vec<u8>)>>>;

/// What the workers counted.
#[derive(Default)]
struct Tally {
    done: AtomicUsize,
    loaded: AtomicUsize,
    ran: AtomicUsize,
    slowest_us: AtomicUsize,
    findings: Mutex<Vec<(usize, Finding, Vec<u8>)>>,
}

fn main() {
    let o = match options() {
        Ok(o) => o,
        Err(e) => {
            eprintln!("fuzz_models: {e}");
            std::process::exit(2);
        }
    };
    // Panics are findings, counted and saved; their messages are not noise.
    std::panic::set_hook(Box::new(|_| {}));
    let seeds = seeds();
    let tally = Arc::new(Tally::default());
    let current: Current = Arc::new((0..o.threads).map(|_| Mutex::new((None, Vec::new()))).collect());
    watchdog(Arc::clone(&current), o.limit * 10);
    let started = Instant::now();
    std::thread::scope(|scope| {
        for t in 0..o.threads {
            let (tally, current, seeds, o) = (&tally, &current, &seeds, &o);
            scope.spawn(move || {
                let mut rng = Rng::new(o.seed.wrapping_add(t as u64 * 0x1000_0001));
                for i in (t..o.runs).step_by(o.threads) {
                    let (_, text) = seeds[i % seeds.len()];
                    let bytes = mutate(text, &mut rng);
                    if let Ok(mut c) = current[t].lock() {
                        *c = (Some(Instant::now()), bytes.clone());
                    }
                    let t0 = Instant::now();
                    match check(&bytes, o.limit) {
                        Ok(out) => {
                            tally.loaded.fetch_add(out.loaded as usize, Ordering::Relaxed);
                            tally.ran.fetch_add(out.ran as usize, Ordering::Relaxed);
                        }
                        Err(f) => tally.findings.lock().unwrap().push((i, f, bytes)),
                    }
                    let us = t0.elapsed().as_micros() as usize;
                    tally.slowest_us.fetch_max(us, Ordering::Relaxed);
                    let done = tally.done.fetch_add(1, Ordering::Relaxed) + 1;
                    if done % 50_000 == 0 {
                        eprintln!("fuzz_models: {done} mutants, {:.0} s", started.elapsed().as_secs_f64());
                    }
                }
                // Done: a worker with nothing left to do is not hanging.
                if let Ok(mut c) = current[t].lock() {
                    c.0 = None;
                }
            });
        }
    });
    let elapsed = started.elapsed();
    let slow_under_load = recheck_slow(&o, &tally);
    report(&o, &tally, elapsed, &slow_under_load);
}

/// Checks each slow mutant again, alone: on a machine busy with other work
/// (or with the other workers) a mutant can pass the limit of wall time
/// that it takes a fraction of by itself. Those that are fast alone leave
/// the findings; returns them with both times.
fn recheck_slow(o: &Options, tally: &Tally) -> Vec<(usize, Duration, Duration)> {
    let mut findings = tally.findings.lock().unwrap();
    let mut under_load = Vec::new();
    findings.retain(|(i, f, bytes)| {
        let Finding::Slow(in_run) = f else { return true };
        let t0 = Instant::now();
        match check(bytes, o.limit) {
            Ok(_) => {
                under_load.push((*i, *in_run, t0.elapsed()));
                false
            }
            Err(_) => true,
        }
    });
    under_load
}

/// Exits 2 with the input when a mutant runs past `hang`.
fn watchdog(current: Current, hang: Duration) {
    std::thread::spawn(move || {
        loop {
            std::thread::sleep(Duration::from_secs(1));
            for slot in current.iter() {
                let Ok(c) = slot.lock() else { continue };
                if c.0.is_some_and(|t| t.elapsed() > hang) {
                    let path = save("hang", 0, &c.1);
                    eprintln!("fuzz_models: a mutant ran over {} s: {path}", hang.as_secs());
                    std::process::exit(2);
                }
            }
        }
    });
}

fn save(kind: &str, i: usize, bytes: &[u8]) -> String {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../target/fuzz-findings");
    let _ = std::fs::create_dir_all(&dir);
    let path = dir.join(format!("{kind}-{i}.toml"));
    let _ = std::fs::write(&path, bytes);
    path.display().to_string()
}

fn report(o: &Options, tally: &Tally, elapsed: Duration, slow_under_load: &[(usize, Duration, Duration)]) {
    let done = tally.done.load(Ordering::Relaxed);
    let findings = tally.findings.lock().unwrap();
    println!(
        "{done} mutants of {} presets (seed {}), {} threads, {:.1} s ({:.0} per second)",
        seeds().len(),
        o.seed,
        o.threads,
        elapsed.as_secs_f64(),
        done as f64 / elapsed.as_secs_f64()
    );
    println!(
        "  loaded {}, ran a cycle {}, refused with line:column {}; slowest {:.1} ms",
        tally.loaded.load(Ordering::Relaxed),
        tally.ran.load(Ordering::Relaxed),
        done - tally.loaded.load(Ordering::Relaxed) - findings.len(),
        tally.slowest_us.load(Ordering::Relaxed) as f64 / 1000.0
    );
    for (i, in_run, alone) in slow_under_load {
        println!(
            "  #{i}: slow under load only: {:.1} s in the run, {:.2} s alone (not a finding)",
            in_run.as_secs_f64(),
            alone.as_secs_f64()
        );
    }
    println!("  findings: {}", findings.len());
    for (i, what, bytes) in findings.iter().take(50) {
        let path = save("finding", *i, bytes);
        println!("  #{i}: {what}  ({path})");
    }
    if !findings.is_empty() {
        std::process::exit(1);
    }
}
