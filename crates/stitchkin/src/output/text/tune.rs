//! A tuning ([`crate::study::tune`]) as a readable table: the recommended
//! setting and how to make it on the machine, the match and the checks
//! before and after, and how far each setting may move.

use crate::format::{hundredths, score};
use crate::study::tune::{MatchFigures, TuneObjective, TuneResult};

/// The transmission angles' extremes, or `none`.
fn mu(f: &MatchFigures) -> String {
    match (f.mu_min_deg, f.mu_max_deg) {
        (Some(a), Some(b)) => format!("{a:.1}°…{b:.1}°{}", if f.mu_ok { "" } else { " (OUTSIDE 30°…150°)" }),
        _ => "none".into(),
    }
}

/// `all pass`, or the checks that fail.
fn checks(f: &MatchFigures) -> String {
    if f.failed_checks.is_empty() {
        "all pass".to_string()
    } else {
        format!("{} FAIL", f.failed_checks.join(", "))
    }
}

/// The readable result of a tuning: the recommended setting (and the one it
/// started from), each change in shop terms (which part, which way, how
/// far), score and RMS(D) per thread before and after, the
/// transmission angles and checks before and after, each setting's range
/// within one score point, the notes and the cycles evaluated.
pub fn table(r: &TuneResult) -> String {
    let setting = |xs: &[f64]| -> String {
        r.names
            .iter()
            .zip(xs)
            .map(|((n, u), x)| format!("{n} = {} {u}", hundredths(*x)))
            .collect::<Vec<_>>()
            .join(", ")
    };
    let mut s = match r.objective {
        TuneObjective::Match => String::new(),
        TuneObjective::PeakTension => {
            "Tuned for the lowest peak tension (as a share of each thread's breaking force), the checks kept:\n".into()
        }
    };
    s += &format!("Recommended setting: {}\n", setting(&r.after));
    s += &format!("(from {})\n", setting(&r.before));
    if !r.adjustments.is_empty() {
        s += "On the machine:\n";
        for a in &r.adjustments {
            s += &format!("  {}\n", a.advice);
        }
    }
    s += "\n";
    s += &format!(
        "{:<12} {:>14} {:>14} {:>16} {:>16}\n",
        "thread", "score before", "score after", "RMS(D) before", "RMS(D) after"
    );
    for (b, a) in r.before_figures.threads.iter().zip(&r.after_figures.threads) {
        s += &format!(
            "{:<12} {:>14} {:>14} {:>13.3} mm {:>13.3} mm\n",
            b.0,
            score(b.1),
            score(a.1),
            b.2,
            a.2
        );
    }
    s += &format!(
        "{:<12} {:>14.1} {:>14.1}\n",
        "mean", r.before_figures.score_mean, r.after_figures.score_mean
    );
    if let (Some(b), Some(a)) = (r.before_figures.peak_tension_n, r.after_figures.peak_tension_n) {
        s += &format!("{:<12} {:>12.2} N {:>12.2} N\n", "peak tension", b, a);
    }
    s += &format!(
        "\ntransmission angles: before {}, after {}\n",
        mu(&r.before_figures),
        mu(&r.after_figures)
    );
    s += &format!(
        "physical checks: before {}, after {}\n",
        checks(&r.before_figures),
        checks(&r.after_figures)
    );
    s += match r.objective {
        TuneObjective::Match => "within one score point of the optimum (each setting alone, the others held):\n",
        TuneObjective::PeakTension => {
            "within 1 % of the breaking force of the lowest peak (each setting alone, the others held):\n"
        }
    };
    for f in &r.flatness {
        let unit = r.names.iter().find(|n| n.0 == f.name).map_or("", |n| n.1);
        s += &format!(
            "  {} from {} to {} {unit}\n",
            f.name,
            hundredths(f.lo),
            hundredths(f.hi)
        );
    }
    for n in &r.notes {
        s += &format!("note: {n}\n");
    }
    s += &format!("({} cycles evaluated)\n", r.evaluations);
    s
}
