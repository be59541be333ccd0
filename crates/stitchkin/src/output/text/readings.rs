//! Repeated readings processed as seed 004 §3.4
//! ([`crate::thread::repeated`]) as a readable table or CSV.

use crate::format::fmt_num;
use crate::references::cite;
use crate::thread::repeated::Processed;

/// The CSV header: one row per φ.
pub const CSV_HEADER: &str = "phi_deg,n,mean_mm,s_mm,s_mean_mm,t,ci_low_mm,ci_high_mm,random_mm,systematic_mm,total_mm,relative_pct,sigma_mm,outliers";

/// One row per φ (`CSV_HEADER`): `relative_pct` empty where the mean is
/// within its error of zero, `outliers` the flagged readings' numbers
/// (1-based) separated by spaces.
pub fn csv(p: &Processed) -> String {
    let mut s = format!("{CSV_HEADER}\n");
    for r in &p.points {
        s += &format!(
            "{},{},{},{},{},{},{},{},{},{},{},{},{},{}\n",
            fmt_num(r.phi_deg),
            r.n,
            r.mean_mm,
            r.s_mm,
            r.s_mean_mm,
            r.t,
            r.ci_low_mm,
            r.ci_high_mm,
            r.random_mm,
            r.systematic_mm,
            r.total_mm,
            r.relative_pct.map_or(String::new(), |v| v.to_string()),
            r.sigma_mm,
            r.outliers.iter().map(usize::to_string).collect::<Vec<_>>().join(" ")
        );
    }
    s
}

/// The readable table of `source`'s readings: how they are processed, one
/// row per φ, and the flagged outliers.
pub fn table(p: &Processed, source: &str) -> String {
    let mut s = format!(
        "{source}: repeated readings processed as {} §3.4\n\
         confidence {} %, resolution (systematic error) {} mm; \
         Δ = √(Δ_r² + Δ_s²), Δ_r = t·s/√n; result x̄ ± Δ\n\n",
        cite(4),
        fmt_num(p.confidence * 100.0),
        fmt_num(p.resolution_mm)
    );
    s += &format!(
        "{:>7} {:>3} {:>9} {:>8} {:>6} {:>9} {:>9} {:>8} {:>8} {:>8} {:>7}  outliers\n",
        "φ deg", "n", "mean mm", "s mm", "t", "low mm", "high mm", "Δr mm", "Δs mm", "Δ mm", "ε %"
    );
    for r in &p.points {
        s += &format!(
            "{:>7} {:>3} {:>9.4} {:>8.4} {:>6.3} {:>9.4} {:>9.4} {:>8.4} {:>8.4} {:>8.4} {:>7}  {}\n",
            fmt_num(r.phi_deg),
            r.n,
            r.mean_mm,
            r.s_mm,
            r.t,
            r.ci_low_mm,
            r.ci_high_mm,
            r.random_mm,
            r.systematic_mm,
            r.total_mm,
            r.relative_pct.map_or("—".to_string(), |v| format!("{v:.1}")),
            r.outliers.iter().map(|k| format!("#{k}")).collect::<Vec<_>>().join(" ")
        );
    }
    let flagged = p.outlier_count();
    s += &format!(
        "\n{} reading(s) flagged by Grubbs' test at α = {} (flagged, not removed); ε: — where |x̄| ≤ Δ\n",
        flagged,
        fmt_num(1.0 - p.confidence)
    );
    s
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn csv_has_one_row_per_phi_and_no_nan() {
        let p = Processed::new(&[0.0, 10.0], &[vec![0.0, 0.01, -0.01], vec![1.0, 1.1, 1.2]], 0.05, 0.95);
        let text = csv(&p);
        let lines: Vec<&str> = text.lines().collect();
        assert_eq!(lines.len(), 3);
        assert!(
            lines[1].starts_with("0,3,0,") && lines[1].contains(",,"),
            "{}",
            lines[1]
        );
        assert!(lines[2].starts_with("10,3,1.0999"), "{}", lines[2]);
        assert!(!text.contains("NaN") && !text.contains("inf"));
        let t = table(&p, "b.csv");
        assert!(
            t.contains("Polyakov (2022) §3.4") && t.contains("0 reading(s) flagged"),
            "{t}"
        );
    }
}
