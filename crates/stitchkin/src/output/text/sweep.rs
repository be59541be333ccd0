//! A sweep ([`crate::study::sweep`]) as streamed CSV, one row per setting,
//! and the summary of a finished sweep.

use crate::format::fmt_num;
use crate::model::Model;
use crate::study::design::Sweep;
use crate::study::sweep::Row;

/// The CSV header: `index`, each varied parameter with its unit, the
/// figures, `status`.
pub fn header(model: &Model, sweep: &Sweep, figures: &[String]) -> String {
    let mut header = String::from("index");
    for v in &sweep.vary {
        header += &format!(
            ",{}_{}",
            v.name,
            model.params[model.param_index(&v.name).unwrap_or(0)].unit_str()
        );
    }
    for f in figures {
        header += &format!(",{f}");
    }
    header + ",status\n"
}

/// One CSV row: the setting's number and values, its figures (empty where
/// it has none) and `ok`, or why it did not evaluate, quoted.
pub fn row(row: &Row) -> String {
    let mut line = row.index.to_string();
    for v in &row.values {
        line.push(',');
        line += &fmt_num(*v);
    }
    for f in &row.figures {
        line.push(',');
        if let Some(x) = f {
            line += &fmt_num(*x);
        }
    }
    match &row.error {
        None => line + ",ok\n",
        Some(e) => line + &format!(",\"{}\"\n", e.replace('"', "'")),
    }
}

/// The rows of a sweep counted as they stream past, with the settings of
/// the largest and smallest value of one figure: the mean match score
/// when there is one, else the first.
#[derive(Debug, Clone, Default)]
pub struct Tally {
    /// Index of the figure followed, in the sweep's figures.
    key: usize,
    evaluated: usize,
    failed: usize,
    lowest: Option<(f64, Vec<f64>)>,
    highest: Option<(f64, Vec<f64>)>,
}

impl Tally {
    /// A tally following `score.mean` among `figures`, or the first figure.
    pub fn new(figures: &[String]) -> Tally {
        Tally {
            key: figures.iter().position(|n| n == "score.mean").unwrap_or(0),
            ..Tally::default()
        }
    }

    /// Counts one row.
    pub fn add(&mut self, row: &Row) {
        if row.error.is_some() {
            self.failed += 1;
            return;
        }
        self.evaluated += 1;
        if let Some(Some(x)) = row.figures.get(self.key) {
            if self.lowest.as_ref().is_none_or(|(b, _)| x < b) {
                self.lowest = Some((*x, row.values.clone()));
            }
            if self.highest.as_ref().is_none_or(|(b, _)| x > b) {
                self.highest = Some((*x, row.values.clone()));
            }
        }
    }

    /// The summary, `# `-lines: how many of `total` settings evaluated, the
    /// shard `k` of `n` when the sweep is split, and the settings of the
    /// followed figure's extremes.
    pub fn summary(&self, sweep: &Sweep, figures: &[String], total: usize, (k, n): (usize, usize)) -> String {
        let mut s = format!(
            "# sweep: {total} settings ({} evaluated, {} without assembly or with errors)",
            self.evaluated, self.failed
        );
        if n > 1 {
            s += &format!(", shard {k}/{n} of {}", sweep.len());
        }
        s += "\n";
        for (word, ext) in [("largest", &self.highest), ("smallest", &self.lowest)] {
            if let (Some((x, values)), Some(f)) = (ext, figures.get(self.key)) {
                let setting: Vec<String> = sweep
                    .vary
                    .iter()
                    .zip(values)
                    .map(|(v, x)| format!("{} = {}", v.name, fmt_num(*x)))
                    .collect();
                s += &format!("# {word} {f} = {} at {}\n", fmt_num(*x), setting.join(", "));
            }
        }
        s
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::study::design::{Design, Vary};

    fn row(index: usize, values: Vec<f64>, figures: Vec<Option<f64>>, error: Option<&str>) -> Row {
        Row {
            index,
            values,
            figures,
            error: error.map(String::from),
        }
    }

    #[test]
    fn rows_leave_missing_figures_empty_and_quote_errors() {
        assert_eq!(
            super::row(&row(3, vec![1.5], vec![Some(2.0), None], None)),
            "3,1.5,2,,ok\n"
        );
        let failed = row(4, vec![-2.0], vec![None, None], Some("no \"assembly\""));
        assert_eq!(super::row(&failed), "4,-2,,,\"no 'assembly'\"\n");
    }

    #[test]
    fn the_tally_follows_the_mean_score_and_counts_failures() {
        let vary = Vary {
            name: "z".into(),
            lo: -1.0,
            hi: 1.0,
            n: 3,
        };
        let sweep = Sweep::new(vec![vary], Design::Grid).unwrap();
        let figures = ["mu.min_deg".to_string(), "score.mean".to_string()];
        let mut tally = Tally::new(&figures);
        tally.add(&row(0, vec![-1.0], vec![Some(40.0), Some(70.0)], None));
        tally.add(&row(1, vec![0.0], vec![Some(50.0), Some(90.0)], None));
        tally.add(&row(2, vec![1.0], vec![None, None], Some("no assembly")));
        assert_eq!(
            tally.summary(&sweep, &figures, 3, (1, 1)),
            "# sweep: 3 settings (2 evaluated, 1 without assembly or with errors)\n\
             # largest score.mean = 90 at z = 0\n\
             # smallest score.mean = 70 at z = -1\n"
        );
        assert!(
            tally
                .summary(&sweep, &figures, 2, (2, 2))
                .contains(", shard 2/2 of 3\n")
        );
    }
}
