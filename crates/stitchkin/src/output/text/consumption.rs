//! The thread one finished stitch consumes
//! ([`crate::stitch::consumption`]) as a readable table or CSV.

use crate::format::fmt_num;
use crate::stitch::consumption::{Consumption, StitchGeometry};

/// A length to 4 decimals, or `—` where the contour is not derivable.
fn len(v: Option<f64>) -> String {
    v.map_or("—".to_string(), |x| format!("{x:.4}"))
}

/// The readable table: the stitch's geometry `g`, the derived lengths, one
/// row per thread (contour, mm per stitch, formula) and the total.
pub fn table(c: &Consumption, g: &StitchGeometry) -> String {
    let mut s = format!(
        "stitch {}: m = {} mm, t = {} mm, a = {} mm, β = {}°, e = {}\n",
        c.stitch_type, g.thickness_mm, g.stitch_mm, g.width_mm, g.incline_deg, g.edge_fraction
    );
    s += &format!(
        "l_m = m/cos β = {:.4} mm, l = √(a² + t²) = {:.4} mm\n\n",
        c.l_m_mm, c.l_mm
    );
    s += &format!("{:<14} {:>7}  {:>12}  formula\n", "thread", "contour", "mm/stitch");
    for t in &c.threads {
        let contour = t.contour.map_or("—".to_string(), |n| n.to_string());
        s += &format!(
            "{:<14} {:>7}  {:>12}  {}\n",
            t.thread,
            contour,
            len(t.length_mm),
            t.formula
        );
    }
    s += &format!("{:<14} {:>7}  {:>12}\n", "total", "", len(c.total_mm));
    if c.total_mm.is_none() {
        s += "(no total: a thread's contour is not derivable from the seeds)\n";
    }
    s
}

/// One row per thread: `thread,contour,formula,length_mm` (empty where
/// there is none).
pub fn csv(c: &Consumption) -> String {
    let mut s = String::from("thread,contour,formula,length_mm\n");
    for t in &c.threads {
        let contour = t.contour.map_or(String::new(), |n| n.to_string());
        let value = t.length_mm.map_or(String::new(), fmt_num);
        s += &format!("{},{contour},\"{}\",{value}\n", t.thread, t.formula);
    }
    s
}
