//! Numbers as text: the one place that decides how a figure is written in
//! CSV, tables, reports and pictures.

/// Formats a number with 12 significant digits, shortest form
/// (`175`, `-3.14159265359`; `1.5e-10` for tiny and huge magnitudes).
pub fn fmt_num(x: f64) -> String {
    if x == 0.0 {
        return "0".into();
    }
    let rounded: f64 = format!("{x:.11e}").parse().unwrap_or(x);
    let a = rounded.abs();
    if (1e-4..1e15).contains(&a) {
        format!("{rounded}")
    } else {
        format!("{rounded:e}")
    }
}
