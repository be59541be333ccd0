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

/// `x` with at most `decimals` decimals, trailing zeros and a bare point
/// dropped, never `-0` (`12.5`, `3`, `-0.25`): lengths and angles written
/// into pictures. Callers keep `x` finite.
pub fn fmt_decimals(x: f64, decimals: usize) -> String {
    let s = format!("{x:.decimals$}");
    let s = if s.contains('.') {
        s.trim_end_matches('0').trim_end_matches('.')
    } else {
        s.as_str()
    };
    if s == "-0" || s.is_empty() {
        "0".into()
    } else {
        s.to_string()
    }
}

/// A coordinate in an SVG picture: two decimals at most (a hundredth of a
/// pixel), as [`fmt_decimals`] writes it.
pub fn svg_num(x: f64) -> String {
    fmt_decimals(x, 2)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn shortest_form_with_twelve_digits() {
        assert_eq!(fmt_num(0.0), "0");
        assert_eq!(fmt_num(175.0), "175");
        assert_eq!(fmt_num(-std::f64::consts::PI), "-3.14159265359");
        assert_eq!(fmt_num(1.5e-10), "1.5e-10");
        assert_eq!(fmt_num(2.0e15), "2e15");
    }

    #[test]
    fn decimals_are_trimmed_and_never_minus_zero() {
        assert_eq!(svg_num(12.5), "12.5");
        assert_eq!(svg_num(100.0), "100");
        assert_eq!(svg_num(-0.25), "-0.25");
        assert_eq!(svg_num(0.004), "0");
        assert_eq!(svg_num(-0.004), "0");
        assert_eq!(svg_num(1.005), "1");
        assert_eq!(svg_num(2.999), "3");
        assert_eq!(fmt_decimals(1.2345, 3), "1.234");
        assert_eq!(fmt_decimals(-0.0004, 3), "0");
        assert_eq!(fmt_decimals(40.0, 0), "40");
        assert_eq!(fmt_decimals(-0.4, 0), "0");
    }
}
