//! A nomogram as text: the readable table a technician reads and the CSV
//! (`stitchkin nomogram`).

use crate::format::fmt_num;
use crate::study::nomogram::{Nomogram, thread_score};
use crate::study::tune::MatchFigures;

/// The CSV: `m_mm,t_mm`, per adjusted setting its recommended value and
/// the range within one score point (`z_mm,z_lo_mm,z_hi_mm`), the mean
/// score and objective before and after, per thread the score and RMS(D)
/// before and after, the transmission angles after, and `status` (`ok`
/// or why the point did not tune; its other cells are then empty).
pub fn csv(nomogram: &Nomogram) -> String {
    let mut s = String::from("m_mm,t_mm");
    for (n, u) in &nomogram.adjust {
        s += &format!(",{n}_{u},{n}_lo_{u},{n}_hi_{u}");
    }
    s += ",score_mean_before,score_mean_after,J_before,J_after";
    for t in &nomogram.threads {
        s += &format!(",{t}.score_before,{t}.score_after,{t}.rms_D_before_mm,{t}.rms_D_after_mm");
    }
    s += ",mu_min_after_deg,mu_max_after_deg,status\n";
    let cell = |x: Option<f64>| x.filter(|x| x.is_finite()).map(fmt_num).unwrap_or_default();
    let cols = 3 * nomogram.adjust.len() + 4 + 4 * nomogram.threads.len() + 2;
    for p in &nomogram.points {
        s += &format!("{},{}", fmt_num(p.m_mm), fmt_num(p.t_mm));
        match &p.tuned {
            Some(r) => {
                for (k, (name, _)) in nomogram.adjust.iter().enumerate() {
                    let f = r.flatness.iter().find(|f| &f.name == name);
                    s += &format!(
                        ",{},{},{}",
                        cell(r.after.get(k).copied()),
                        cell(f.map(|f| f.lo)),
                        cell(f.map(|f| f.hi))
                    );
                }
                let (b, a) = (&r.before_figures, &r.after_figures);
                s += &format!(
                    ",{},{},{},{}",
                    cell(Some(b.score_mean)),
                    cell(Some(a.score_mean)),
                    cell(Some(b.objective)),
                    cell(Some(a.objective))
                );
                for t in &nomogram.threads {
                    let rms = |f: &MatchFigures| f.threads.iter().find(|x| &x.0 == t).map(|x| x.2);
                    s += &format!(
                        ",{},{},{},{}",
                        cell(thread_score(r, t, false)),
                        cell(thread_score(r, t, true)),
                        cell(rms(b)),
                        cell(rms(a))
                    );
                }
                s += &format!(",{},{},ok\n", cell(a.mu_min_deg), cell(a.mu_max_deg));
            }
            None => {
                s += &",".repeat(cols);
                s += &format!(",\"{}\"\n", p.error.as_deref().unwrap_or("failed").replace('"', "'"));
            }
        }
    }
    s
}

/// The readable table: one row per grid point, then (when both m and t
/// vary) each recommended setting as a matrix over m and t.
pub fn table(nomogram: &Nomogram) -> String {
    let sc = |x: Option<f64>| x.map_or("—".to_string(), |x| format!("{x:.1}"));
    let mut s = format!(
        "Nomogram of `{}`: the tuned setting for each material thickness m and stitch length t\n",
        nomogram.model
    );
    let adj: Vec<String> = nomogram.adjust.iter().map(|(n, u)| format!("{n} ({u})")).collect();
    s += &format!(
        "adjusting {}; seed {}, φ step {}°\n",
        adj.join(", "),
        nomogram.seed,
        nomogram.step_deg
    );
    s += &format!(
        "score: the mean match score of {} (0…100); per thread after tuning; J: the objective tuned (J ≥ 1 gives score 0)\n",
        nomogram.threads.join(", ")
    );
    s += "within 1 pt: each setting alone may move this far with the match within one score point\n\n";
    // Columns: (header, width).
    let mut head: Vec<(String, usize)> = vec![("m mm".into(), 6), ("t mm".into(), 6)];
    for (n, u) in &nomogram.adjust {
        head.push((format!("{n} {u}"), 9.max(n.len() + u.len() + 1)));
        head.push((format!("{n} within 1 pt"), 15.max(n.len() + 12)));
    }
    for h in ["score before", "score after"] {
        head.push((h.into(), 12));
    }
    for t in &nomogram.threads {
        head.push((t.clone(), super::name_width([t.len()], 6)));
    }
    head.push(("J after".into(), 8));
    let line = |cells: &[String]| -> String {
        let mut l = String::new();
        for (k, (c, (_, w))) in cells.iter().zip(&head).enumerate() {
            if k > 0 {
                l += "  ";
            }
            l += &format!("{c:>w$}");
        }
        l.trim_end().to_string() + "\n"
    };
    s += &line(&head.iter().map(|h| h.0.clone()).collect::<Vec<_>>());
    let mut failures = Vec::new();
    for p in &nomogram.points {
        let mut cells = vec![r2(p.m_mm), r2(p.t_mm)];
        match &p.tuned {
            Some(r) => {
                for (k, (name, _)) in nomogram.adjust.iter().enumerate() {
                    cells.push(r2(r.after[k]));
                    cells.push(
                        r.flatness
                            .iter()
                            .find(|f| &f.name == name)
                            .map_or("—".into(), |f| format!("{} … {}", r2(f.lo), r2(f.hi))),
                    );
                }
                cells.push(format!("{:.1}", r.before_figures.score_mean));
                cells.push(format!("{:.1}", r.after_figures.score_mean));
                for t in &nomogram.threads {
                    cells.push(sc(thread_score(r, t, true)));
                }
                cells.push(format!("{:.3}", r.after_figures.objective));
            }
            None => {
                cells.push(format!("not tuned [{}]", failures.len() + 1));
                failures.push(p.error.clone().unwrap_or_default());
            }
        }
        s += &line(&cells);
    }
    for (k, e) in failures.iter().enumerate() {
        s += &format!("[{}] {e}\n", k + 1);
    }
    if nomogram.thickness.n > 1 && nomogram.stitch.n > 1 {
        s += &settings_matrices(nomogram);
    }
    let notes = nomogram.notes();
    if !notes.is_empty() {
        s += "\n";
    }
    for n in notes {
        s += &format!("note: {n}\n");
    }
    if nomogram.all_scores_zero() {
        s += "\nEvery match score is 0, before and after tuning, at every grid point: RMS(P − P') exceeds the\n\
              swing of P' (J ≥ 1) whatever the settings, so no setting in the ranges fits this stitch. The\n\
              recommendation only minimises J and should not be used. (For mf7923d this is the reading\n\
              t1_phase = 0, T1 down at the needle's TDC; see docs/stitch-formation.md §10.1.)\n";
    }
    s
}

/// Each recommended setting as a matrix over m (rows) and t (columns).
fn settings_matrices(nomogram: &Nomogram) -> String {
    let mut s = String::new();
    for (k, (name, unit)) in nomogram.adjust.iter().enumerate() {
        s += &format!("\nrecommended {name} ({unit}): rows m (mm), columns t (mm)\n");
        s += &format!("{:>6}", "m \\ t");
        for j in 0..nomogram.stitch.n {
            s += &format!("  {:>7}", r2(nomogram.stitch.value(j)));
        }
        s += "\n";
        for i in 0..nomogram.thickness.n {
            s += &format!("{:>6}", r2(nomogram.thickness.value(i)));
            for j in 0..nomogram.stitch.n {
                let v = nomogram.points[i * nomogram.stitch.n + j]
                    .tuned
                    .as_ref()
                    .map_or("—".into(), |r| r2(r.after[k]));
                s += &format!("  {v:>7}");
            }
            s += "\n";
        }
    }
    s
}

/// A setting or grid value rounded to hundredths, in its shortest form.
fn r2(x: f64) -> String {
    let r = (x * 100.0).round() / 100.0;
    if r == 0.0 { "0".to_string() } else { format!("{r}") }
}
