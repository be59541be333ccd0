//! The error of a planar model of a spatial thread path
//! ([`crate::study::compare_2d3d`]) as CSV and a summary.

use crate::format::fmt_num;
use crate::study::compare_2d3d::Comparison;

/// `phi_deg`, then per path `PATH.P3D_mm`, `PATH.P2D_mm`, `PATH.dP_mm`,
/// one row per φ.
pub fn csv(c: &Comparison) -> String {
    let mut names = vec!["phi_deg".to_string()];
    let mut columns = vec![&c.phi_deg];
    for p in &c.paths {
        for (suffix, v) in [("P3D_mm", &p.p3d_mm), ("P2D_mm", &p.p2d_mm), ("dP_mm", &p.dp_mm)] {
            names.push(format!("{}.{suffix}", p.path));
            columns.push(v);
        }
    }
    let mut s = names.join(",") + "\n";
    for r in 0..c.phi_deg.len() {
        let row: Vec<String> = columns.iter().map(|v| fmt_num(v[r])).collect();
        s += &(row.join(",") + "\n");
    }
    s
}

/// The largest |ΔP| of each path and where, `# `-lines.
pub fn summary(c: &Comparison) -> String {
    let w = super::name_width(c.paths.iter().map(|p| p.path.len()), 1);
    let mut s = format!(
        "# 2D model: every node projected onto the xy-plane of `{}`; ΔP = P3D − P2D\n",
        c.plane
    );
    for p in &c.paths {
        s += &format!(
            "# {:<w$} max |ΔP| {:.4} mm at φ = {:.1}° ({:.2} % of max P)\n",
            p.path, p.max_abs_dp_mm, p.phi_at_max_deg, p.max_rel_percent
        );
    }
    s
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::study::compare_2d3d::PathComparison;

    #[test]
    fn csv_has_three_columns_per_path_and_the_summary_its_largest_error() {
        let c = Comparison {
            plane: "uvw".into(),
            phi_deg: vec![0.0, 180.0],
            paths: vec![PathComparison {
                path: "n1".into(),
                p3d_mm: vec![1.0, 2.5],
                p2d_mm: vec![1.0, 2.0],
                dp_mm: vec![0.0, 0.5],
                max_abs_dp_mm: 0.5,
                phi_at_max_deg: 180.0,
                max_rel_percent: 20.0,
            }],
        };
        assert_eq!(
            csv(&c),
            "phi_deg,n1.P3D_mm,n1.P2D_mm,n1.dP_mm\n0,1,1,0\n180,2.5,2,0.5\n"
        );
        assert_eq!(
            summary(&c),
            "# 2D model: every node projected onto the xy-plane of `uvw`; ΔP = P3D − P2D\n\
             # n1 max |ΔP| 0.5000 mm at φ = 180.0° (20.00 % of max P)\n"
        );
    }
}
