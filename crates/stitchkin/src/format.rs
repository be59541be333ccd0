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

/// `x` to `decimals` places, without a negative zero: `decimals(-0.00001,
/// 3)` is `0.000`, not `-0.000`.
pub fn decimals(x: f64, decimals: usize) -> String {
    let s = format!("{x:.decimals$}");
    if s.trim_start_matches('-').chars().all(|c| c == '0' || c == '.') {
        s.trim_start_matches('-').to_string()
    } else {
        s
    }
}

/// `x` with `digits` significant digits, always in fixed-point notation
/// (`0.000123`, `123457`): never an exponent, and never fewer than zero
/// decimals, so a large `x` keeps all its integer digits. Zero, a
/// non-finite `x` and |x| < 1e-9 are written by [`fmt_num`].
pub fn sig_fixed(x: f64, digits: usize) -> String {
    if x == 0.0 || !x.is_finite() || x.abs() < 1e-9 {
        return fmt_num(x);
    }
    let d = (digits as i32 - 1 - x.abs().log10().floor() as i32).max(0) as usize;
    format!("{x:.d$}")
}

/// `x` with `digits` significant digits: fixed point for everyday
/// magnitudes (10⁻⁴ ≤ |x| < 10⁷), scientific outside them (`1.2346e-5`).
/// Zero is `0`; a non-finite `x` is written as Rust writes it (`NaN`, `inf`).
pub fn sig_sci(x: f64, digits: usize) -> String {
    if x == 0.0 || !x.is_finite() {
        return if x == 0.0 { "0".into() } else { format!("{x}") };
    }
    let mag = x.abs().log10().floor() as i32;
    if !(-4..=6).contains(&mag) {
        return format!("{x:.*e}", digits.saturating_sub(1));
    }
    let decimals = (digits as i32 - 1 - mag).max(0) as usize;
    format!("{x:.decimals$}")
}

/// `x` to 4 decimals (`0.0123`), or, when it is not zero and |x| < 10⁻³,
/// with 2 significant digits in scientific notation (`3.2e-5`), so a small
/// error does not read as `0.0000`.
pub fn dec4_or_sci(x: f64) -> String {
    if x != 0.0 && x.abs() < 1e-3 {
        format!("{x:.1e}")
    } else {
        format!("{x:.4}")
    }
}

/// A length to 5 decimals with its unit: `0.01234 mm`.
pub fn mm5(x: f64) -> String {
    format!("{x:.5} mm")
}

/// A signed length to 5 decimals with its sign and unit: `+0.01234 mm`,
/// `-0.00500 mm`.
pub fn mm5_signed(x: f64) -> String {
    format!("{x:+.5} mm")
}

/// `x` rounded to hundredths and written in its shortest form (`2.5`,
/// `-3.14`, `0`; never `-0`).
pub fn hundredths(x: f64) -> String {
    let r = (x * 100.0).round() / 100.0;
    if r == 0.0 { "0".to_string() } else { format!("{r}") }
}

/// A match score, points of 0…100, to one decimal, or `—` when there is
/// none (a flat P′ has no score).
pub fn score(s: Option<f64>) -> String {
    s.map_or("—".into(), |x| format!("{x:.1}"))
}

/// The unit of a derivative or any ratio: `numerator/denominator`
/// (`mm/deg`).
pub fn per_unit(numerator: &str, denominator: &str) -> String {
    format!("{numerator}/{denominator}")
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

    #[test]
    fn decimals_drops_a_negative_zero() {
        assert_eq!(decimals(-0.00001, 3), "0.000");
        assert_eq!(decimals(-0.0, 2), "0.00");
        assert_eq!(decimals(-0.0015, 3), "-0.002");
        assert_eq!(decimals(174.99871, 4), "174.9987");
    }

    #[test]
    fn sig_fixed_never_writes_an_exponent() {
        assert_eq!(sig_fixed(0.036789, 2), "0.037");
        assert_eq!(sig_fixed(123456.7, 2), "123457");
        assert_eq!(sig_fixed(-2.0, 4), "-2.000");
        assert_eq!(sig_fixed(1.2345e-7, 2), "0.00000012");
        // Below 1e-9, zero and non-finite values: fmt_num.
        assert_eq!(sig_fixed(5e-10, 2), "5e-10");
        assert_eq!(sig_fixed(0.0, 3), "0");
    }

    #[test]
    fn sig_sci_switches_to_an_exponent_outside_everyday_magnitudes() {
        assert_eq!(sig_sci(52.290948, 6), "52.2909");
        assert_eq!(sig_sci(-0.5, 5), "-0.50000");
        assert_eq!(sig_sci(1234567.0, 3), "1234567");
        assert_eq!(sig_sci(12345678.0, 3), "1.23e7");
        assert_eq!(sig_sci(0.0001234, 3), "0.000123");
        assert_eq!(sig_sci(0.00001234, 3), "1.23e-5");
        assert_eq!(sig_sci(0.0, 5), "0");
        assert_eq!(sig_sci(f64::NAN, 5), "NaN");
    }

    #[test]
    fn dec4_or_sci_keeps_small_errors_visible() {
        assert_eq!(dec4_or_sci(0.0), "0.0000");
        assert_eq!(dec4_or_sci(0.0123456), "0.0123");
        assert_eq!(dec4_or_sci(0.001), "0.0010");
        assert_eq!(dec4_or_sci(0.0000321), "3.2e-5");
        assert_eq!(dec4_or_sci(-0.0009), "-9.0e-4");
    }

    #[test]
    fn lengths_to_five_decimals() {
        assert_eq!(mm5(0.0123456), "0.01235 mm");
        assert_eq!(mm5_signed(0.0123456), "+0.01235 mm");
        assert_eq!(mm5_signed(-0.005), "-0.00500 mm");
    }

    #[test]
    fn hundredths_score_and_units() {
        assert_eq!(hundredths(2.499), "2.5");
        assert_eq!(hundredths(-0.001), "0");
        assert_eq!(hundredths(-1.23456), "-1.23");
        assert_eq!(score(Some(87.26)), "87.3");
        assert_eq!(score(None), "—");
        assert_eq!(per_unit("mm", "deg"), "mm/deg");
    }
}
