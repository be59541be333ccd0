//! The thread one finished stitch consumes
//! ([`crate::stitch::consumption`]) as a readable table or CSV.

use crate::format::fmt_num;
use crate::stitch::consumption::{Consumption, StitchGeometry};

/// A length to 4 decimals, or `—` where the contour is not derivable.
fn len(v: Option<f64>) -> String {
    v.map_or("—".to_string(), |x| format!("{x:.4}"))
}

/// The readable table: the stitch's geometry `g`, the derived lengths, one
/// row per thread (contour, mm per stitch, ratio to the seam, m for the
/// seam without and with waste, formula), the total and what the figures
/// leave out.
pub fn table(c: &Consumption, g: &StitchGeometry) -> String {
    // The inputs each family's formulas use: the overedge width and edge
    // split for class 500, the interlacing depth for the lockstitch.
    let overedge = (500..600).contains(&c.stitch_type);
    let mut s = format!(
        "stitch {}: m = {} mm, t = {} mm, β = {}°",
        c.stitch_type, g.thickness_mm, g.stitch_mm, g.incline_deg
    );
    if overedge {
        s += &format!(", a = {} mm, e = {}", g.width_mm, g.edge_fraction);
    }
    if c.stitch_type == 301 {
        s += &format!(", f = {}", g.interlace_fraction);
    }
    s += &format!("\nl_m = m/cos β = {:.4} mm", c.l_m_mm);
    if overedge {
        s += &format!(", l = √(a² + t²) = {:.4} mm", c.l_mm);
    }
    s += "\n";
    s += &format!(
        "seam {} mm = {:.1} stitches, waste allowance {} %\n\n",
        c.seam.length_mm, c.stitches, c.seam.waste_pct
    );
    s += &format!(
        "{:<14} {:>7}  {:>12}  {:>10}  {:>10}  {:>12}  formula\n",
        "thread", "contour", "mm/stitch", "mm/mm seam", "m for seam", "m with waste"
    );
    let row =
        |name: &str, contour: &str, length: Option<f64>, ratio: Option<f64>, seam: Option<f64>, waste: Option<f64>| {
            format!(
                "{name:<14} {contour:>7}  {:>12}  {:>10}  {:>10}  {:>12}",
                len(length),
                len(ratio),
                len(seam),
                len(waste)
            )
        };
    for t in &c.threads {
        let contour = t.contour.map_or("—".to_string(), |n| n.to_string());
        s += &row(&t.thread, &contour, t.length_mm, t.ratio, t.seam_m, t.seam_with_waste_m);
        s += &format!("  {}\n", t.formula);
    }
    s += &row(
        "total",
        "",
        c.total_mm,
        c.total_ratio,
        c.total_seam_m,
        c.total_seam_with_waste_m,
    );
    s += "\n";
    if c.total_mm.is_none() {
        s += "(no total: a thread's contour is not derivable)\n";
    }
    for note in &c.notes {
        s += &format!("note: {note}\n");
    }
    s
}

/// One row per thread and a `total` row: `thread,contour,formula,
/// length_mm,ratio_mm_per_mm,seam_m,seam_with_waste_m` (empty where there
/// is none).
pub fn csv(c: &Consumption) -> String {
    let mut s = String::from("thread,contour,formula,length_mm,ratio_mm_per_mm,seam_m,seam_with_waste_m\n");
    let num = |v: Option<f64>| v.map_or(String::new(), fmt_num);
    for t in &c.threads {
        let contour = t.contour.map_or(String::new(), |n| n.to_string());
        s += &format!(
            "{},{contour},\"{}\",{},{},{},{}\n",
            t.thread,
            t.formula,
            num(t.length_mm),
            num(t.ratio),
            num(t.seam_m),
            num(t.seam_with_waste_m)
        );
    }
    s += &format!(
        "total,,\"{}\",{},{},{},{}\n",
        if c.total_mm.is_some() {
            "sum of the threads"
        } else {
            "not derivable: a thread is not"
        },
        num(c.total_mm),
        num(c.total_ratio),
        num(c.total_seam_m),
        num(c.total_seam_with_waste_m)
    );
    s
}
