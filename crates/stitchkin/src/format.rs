//! Numbers as text: the one place that decides how a figure is written in
//! CSV, tables, reports and pictures.

/// Formats a number with 12 significant digits, shortest form
/// (`175`, `-3.14159265359`; `1.5e-10` for tiny and huge magnitudes).
pub fn fmt_num(x: f64) -> String {
    let mut s = Vec::new();
    push_num(&mut s, x);
    String::from_utf8(s).expect("numbers are written in ASCII")
}

/// Appends [`fmt_num`]`(x)` to `out`, in ASCII: what a CSV of millions of
/// numbers writes, without a heap allocation or a decimal conversion of
/// its own for nearly every number.
pub fn push_num(out: &mut Vec<u8>, x: f64) {
    if x == 0.0 {
        out.push(b'0');
    } else if let Some((digits, exp10)) = twelve_digits(x) {
        if x < 0.0 {
            out.push(b'-');
        }
        push_fixed(out, digits, exp10);
    } else {
        // Rounded to 12 significant digits, then written in the shortest
        // form that reads back as the rounded value.
        let rounded: f64 = format!("{x:.11e}").parse().unwrap_or(x);
        let text = if (1e-4..1e15).contains(&rounded.abs()) {
            format!("{rounded}")
        } else {
            format!("{rounded:e}")
        };
        out.extend_from_slice(text.as_bytes());
    }
}

/// |x| rounded to 12 significant digits, as the integer d (10¹¹ ≤ d < 10¹²)
/// and the exponent e of |x| ≈ d·10^(e−11), for 10⁻⁴ ≤ |x| < 10¹⁵, where
/// [`fmt_num`] writes no exponent; `None` where this cannot be sure of the
/// rounding (the caller then asks the exact decimal conversion).
///
/// y = |x|·10^(11−e) is one correctly rounded product or quotient (10^k is
/// exact in `f64` for k ≤ 22), so it is within half an ulp of the exact
/// value, under 2⁻¹³ for y < 10¹²: when the fraction of y is not within
/// 10⁻³ of ½ it rounds as the exact value does.
fn twelve_digits(x: f64) -> Option<(u64, i32)> {
    const POW10: [f64; 17] = [
        1e0, 1e1, 1e2, 1e3, 1e4, 1e5, 1e6, 1e7, 1e8, 1e9, 1e10, 1e11, 1e12, 1e13, 1e14, 1e15, 1e16,
    ];
    let a = x.abs();
    if !(1e-4..1e15).contains(&a) {
        return None;
    }
    let scaled = |e: i32| {
        let k = 11 - e;
        if k >= 0 {
            a * POW10[k as usize]
        } else {
            a / POW10[(-k) as usize]
        }
    };
    // floor(e₂·log₁₀2) from the binary exponent e₂ (78913/2¹⁸ ≈ log₁₀2, as
    // in Ryu, Adams 2018): the decimal exponent or one less.
    let e2 = ((a.to_bits() >> 52) & 0x7ff) as i32 - 1023;
    let mut e = (e2 * 78913) >> 18;
    let mut y = scaled(e);
    if y < 1e11 {
        e -= 1;
        y = scaled(e);
    } else if y >= 1e12 {
        e += 1;
        y = scaled(e);
    }
    if !(1e11..1e12).contains(&y) {
        return None;
    }
    let whole = y as u64;
    let frac = y - whole as f64;
    if (frac - 0.5).abs() < 1e-3 {
        return None;
    }
    let mut d = whole + u64::from(frac > 0.5);
    if d == 1_000_000_000_000 {
        d = 100_000_000_000;
        e += 1;
    }
    (-4..=14).contains(&e).then_some((d, e))
}

/// Writes d·10^(e−11) (12 digits in d) in fixed notation without trailing
/// zeros, as Rust writes the `f64` nearest to it: a decimal of at most 15
/// significant digits is the shortest form of that `f64`.
///
/// The digits are laid out in one 128-bit register, the first digit in the
/// lowest byte, and stored 16 bytes at a time; the text's end is then cut.
/// (Built byte by byte on the stack and copied, the text made the copy wait
/// for the bytes' stores: a fifth of the time of a table's output.)
fn push_fixed(out: &mut Vec<u8>, d: u64, e: i32) {
    const ZEROS: u128 = u128::from_le_bytes([b'0'; 16]);
    // d < 10¹²: four digits, then eight.
    let raw =
        u128::from(four_digits((d / 100_000_000) as u32)) | (u128::from(eight_digits((d % 100_000_000) as u32)) << 32);
    // The last digit that is not 0 (d ≥ 10¹¹, so raw ≠ 0).
    let len = ((127 - raw.leading_zeros()) / 8 + 1) as usize;
    let ascii = raw | ZEROS;
    let start = out.len();
    if e < 0 {
        // 0.000ddd: one to four zeros before the digits.
        let zeros = (-e - 1) as usize;
        out.extend_from_slice(b"0.000");
        out.truncate(start + 2 + zeros);
        out.extend_from_slice(&ascii.to_le_bytes());
        out.truncate(start + 2 + zeros + len);
    } else {
        let int_len = e as usize + 1;
        if len <= int_len {
            // Bytes 12 to 15 are zeros too: up to 15 integer digits.
            out.extend_from_slice(&ascii.to_le_bytes());
            out.truncate(start + int_len);
        } else {
            // The integer digits, the point, then the rest one byte on
            // (int_len < len ≤ 12, so the text is at most 13 bytes).
            let low = ascii & ((1u128 << (8 * int_len)) - 1);
            let high = (ascii >> (8 * int_len)) << (8 * (int_len + 1));
            let text = low | (u128::from(b'.') << (8 * int_len)) | high;
            out.extend_from_slice(&text.to_le_bytes());
            out.truncate(start + len + 1);
        }
    }
}

/// The four decimal digits of `v` < 10⁴, each a byte 0–9, the first in the
/// lowest byte.
fn four_digits(v: u32) -> u32 {
    // Two digits per 16-bit lane: v/100 low, v%100 high.
    let hi = (v * 5243) >> 19; // v/100 for v < 10⁴ (5243/2¹⁹ ≈ 1/100)
    let pairs = hi | ((v - hi * 100) << 16);
    // One digit per byte: tens low, ones high.
    let tens = ((pairs * 103) >> 10) & 0x000f_000f; // m/10 for m < 100
    tens | ((pairs - tens * 10) << 8)
}

/// The eight decimal digits of `v` < 10⁸, each a byte 0–9, the first in
/// the lowest byte; every lane of the arithmetic stays within its bits.
fn eight_digits(v: u32) -> u64 {
    let x = u64::from(v / 10_000) | (u64::from(v % 10_000) << 32);
    // Each 32-bit lane n < 10⁴ → n/100 low, n%100 high (10486/2²⁰ ≈ 1/100).
    let hi = ((x * 10486) >> 20) & 0x0000_007f_0000_007f;
    let pairs = hi | ((x - hi * 100) << 16);
    // Each 16-bit lane m < 100 → m/10 low, m%10 high (103/2¹⁰ ≈ 1/10).
    let tens = ((pairs * 103) >> 10) & 0x000f_000f_000f_000f;
    tens | ((pairs - tens * 10) << 8)
}

/// `x` with at most `decimals` decimals, trailing zeros and a bare point
/// dropped, never `-0` (`12.5`, `3`, `-0.25`): lengths and angles written
/// into pictures. Callers keep `x` finite.
pub fn fmt_decimals(x: f64, decimals: usize) -> String {
    let mut s = String::new();
    push_decimals(&mut s, x, decimals);
    s
}

/// Appends [`fmt_decimals`]`(x, decimals)` to `out` without a heap
/// allocation of its own where the rounding is sure (the digits fit an
/// integer and no tie is near): a
/// chart's polylines write thousands of coordinates.
pub fn push_decimals(out: &mut String, x: f64, decimals: usize) {
    let Some((negative, digits)) = rounded(x, decimals) else {
        let s = format!("{x:.decimals$}");
        let s = if s.contains('.') {
            s.trim_end_matches('0').trim_end_matches('.')
        } else {
            s.as_str()
        };
        out.push_str(if s == "-0" || s.is_empty() { "0" } else { s });
        return;
    };
    let unit = POW10_U64[decimals];
    let (int, mut frac, mut places) = (digits / unit, digits % unit, decimals);
    // Trailing zeros dropped, and the point with them.
    while places > 0 && frac % 10 == 0 {
        frac /= 10;
        places -= 1;
    }
    // What rounds to zero is written `0`, never `-0`.
    if negative && (int != 0 || places > 0) {
        out.push('-');
    }
    push_point_digits(out, int, frac, places);
}

/// Appends `int`, then, with `places` > 0, a point and `frac` zero-padded to
/// `places` digits.
fn push_point_digits(out: &mut String, int: u64, frac: u64, places: usize) {
    push_digits(out, int, 1);
    if places > 0 {
        out.push('.');
        push_digits(out, frac, places);
    }
}

/// 10^k for k ≤ 6, the decimals [`rounded`] is sure of.
const POW10_U64: [u64; 7] = [1, 10, 100, 1_000, 10_000, 100_000, 1_000_000];

/// Appends the decimal digits of `v`, zero-padded to at least `width`
/// (≤ 20) digits.
fn push_digits(out: &mut String, mut v: u64, width: usize) {
    let mut buf = [b'0'; 20];
    let mut start = buf.len();
    while v > 0 {
        start -= 1;
        buf[start] = b'0' + (v % 10) as u8;
        v /= 10;
    }
    start = start.min(buf.len() - width);
    out.push_str(std::str::from_utf8(&buf[start..]).expect("decimal digits are ASCII"));
}

/// |x| scaled by 10^`decimals` and rounded half to even as the exact
/// decimal value of `x` rounds (what `format!` writes), with the sign of
/// `x`: where that scaled value is surely not within 10⁻⁶ of a rounding
/// tie, for at most 6 decimals and |x|·10^decimals < 10¹⁵; else `None`.
fn rounded(x: f64, decimals: usize) -> Option<(bool, u64)> {
    const SURE: f64 = 1e-6;
    if decimals >= POW10_U64.len() {
        return None;
    }
    let scale = POW10_U64[decimals] as f64;
    let y = x * scale;
    // NaN, infinities and 10¹⁵ or more go to the exact conversion.
    if y.is_nan() || y.abs() >= 1e15 {
        return None;
    }
    // x·scale exactly = y + err; its part past the integer below y.
    let err = x.mul_add(scale, -y);
    // ⌊y⌋ through an integer (|y| < 10¹⁵ < 2⁶³; the library's floor is a
    // call on the baseline x86-64 target).
    let truncated = y as i64 as f64;
    let below = if truncated > y { truncated - 1.0 } else { truncated };
    let frac = (y - below) + err;
    if (frac - 0.5).abs() <= SURE {
        return None;
    }
    let r = if frac > 0.5 { below + 1.0 } else { below };
    Some((x.is_sign_negative(), r.abs() as u64))
}

/// `format!("{x:.decimals$}")`, the same text: where [`rounded`] is sure,
/// rounded in integers (a chart writes thousands of coordinates; the exact
/// decimal conversion was an eighth of a page request), else by `format!`.
fn fixed(x: f64, decimals: usize) -> String {
    let Some((negative, digits)) = rounded(x, decimals) else {
        return format!("{x:.decimals$}");
    };
    let mut s = String::with_capacity(24);
    if negative {
        s.push('-');
    }
    let unit = POW10_U64[decimals];
    push_point_digits(&mut s, digits / unit, digits % unit, decimals);
    s
}

/// A coordinate in an SVG picture: two decimals at most (a hundredth of a
/// pixel), as [`fmt_decimals`] writes it.
pub fn svg_num(x: f64) -> String {
    fmt_decimals(x, 2)
}

/// Appends [`svg_num`]`(x)` to `out`.
pub fn push_svg_num(out: &mut String, x: f64) {
    push_decimals(out, x, 2);
}

/// `x` to `decimals` places, without a negative zero: `decimals(-0.00001,
/// 3)` is `0.000`, not `-0.000`.
pub fn decimals(x: f64, decimals: usize) -> String {
    let s = fixed(x, decimals);
    if s.trim_start_matches('-').chars().all(|c| c == '0' || c == '.') {
        s.trim_start_matches('-').to_string()
    } else {
        s
    }
}

/// `text` with every number that rounds to zero written without its minus
/// sign: `-0.00` becomes `0.00`, `-0` becomes `0`, `+0.0` is kept as it is,
/// `-0.001` and `x-0.00` (a minus inside a word or after a digit) are kept.
/// In an aligned column (the minus after two spaces or at a line's start
/// after a space) the minus becomes a space, so the column stays aligned.
/// The last pass over text printed for people, whatever formatted its
/// numbers (`{:.2}` writes `-0.00` for −0.001).
pub fn without_negative_zeros(text: &str) -> std::borrow::Cow<'_, str> {
    let bytes = text.as_bytes();
    let negative_zero_at = |i: usize| -> bool {
        // A minus at a number's start: not after a letter, a digit, a point
        // or an underscore.
        if bytes[i] != b'-' || i > 0 && (bytes[i - 1].is_ascii_alphanumeric() || matches!(bytes[i - 1], b'.' | b'_')) {
            return false;
        }
        let mut j = i + 1;
        if bytes.get(j) != Some(&b'0') {
            return false;
        }
        j += 1;
        if bytes.get(j) == Some(&b'.') && bytes.get(j + 1).is_some_and(u8::is_ascii_digit) {
            j += 1;
            while bytes.get(j) == Some(&b'0') {
                j += 1;
            }
        }
        // The number ends here: no other digit, and no exponent.
        !bytes
            .get(j)
            .is_some_and(|b| b.is_ascii_digit() || matches!(b, b'e' | b'E' | b'.'))
    };
    if !(0..bytes.len()).any(negative_zero_at) {
        return std::borrow::Cow::Borrowed(text);
    }
    let padded = |i: usize| i >= 1 && bytes[i - 1] == b' ' && (i == 1 || matches!(bytes[i - 2], b' ' | b'\n'));
    let mut out = String::with_capacity(text.len());
    let mut from = 0;
    for i in 0..bytes.len() {
        if negative_zero_at(i) {
            out.push_str(&text[from..i]);
            if padded(i) {
                out.push(' ');
            }
            from = i + 1;
        }
    }
    out.push_str(&text[from..]);
    std::borrow::Cow::Owned(out)
}

/// A rate for people: a whole number with a space every three digits
/// and its unit, `12 652 settings/s` (never `12,651.6851/s`); under 10 with
/// one decimal (`2.5 settings/s`).
pub fn rate(per_second: f64, what: &str) -> String {
    format!("{} {what}/s", rate_number(per_second))
}

/// The number of [`rate`]: `12 652`, `950`, `2.5`; `–` for no rate.
pub fn rate_number(per_second: f64) -> String {
    if !per_second.is_finite() || per_second < 0.0 {
        "–".into()
    } else if per_second < 10.0 {
        decimals(per_second, 1)
    } else {
        grouped(per_second.round() as u64)
    }
}

/// A whole number with a space every three digits: `12 652`, `950`.
pub fn grouped(n: u64) -> String {
    let digits = n.to_string();
    let mut out = String::with_capacity(digits.len() + digits.len() / 3);
    for (k, c) in digits.chars().enumerate() {
        if k > 0 && (digits.len() - k).is_multiple_of(3) {
            out.push(' ');
        }
        out.push(c);
    }
    out
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

    /// Finite numbers to write: ties at every number of decimals and their
    /// neighbours, awkward ones, then 20 000 coordinates (hundreds of
    /// pixels), lengths and doubles of any size.
    fn numbers() -> Vec<f64> {
        let mut seed = 3u64;
        let mut next = || {
            seed = seed.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
            seed
        };
        let mut xs = vec![
            0.0,
            -0.0,
            0.125,
            2.675,
            -0.001,
            -0.005,
            0.005,
            1.005,
            999.995,
            -2.5,
            0.5,
            1e14,
            -1e16,
            1.0 / 3.0,
            -0.004,
            10.0,
            -100.0,
        ];
        for d in 0..=6 {
            let t = 0.5 / 10f64.powi(d);
            xs.extend([t, -t, 3.0 + t, t.next_up(), t.next_down()]);
        }
        for _ in 0..20_000 {
            let bits = next();
            let x = match bits % 3 {
                0 => ((bits >> 11) as f64 / (1u64 << 53) as f64 - 0.5) * 2000.0,
                1 => ((bits >> 20) % 2_000_000) as f64 / 1000.0 - 1000.0,
                _ => f64::from_bits(bits >> 2),
            };
            if x.is_finite() {
                xs.push(x);
            }
        }
        xs
    }

    #[test]
    fn fixed_writes_what_format_writes() {
        let xs = numbers();
        for d in 0..=8usize {
            for &x in &xs {
                assert_eq!(fixed(x, d), format!("{x:.d$}"), "{x:e} to {d}");
            }
        }
    }

    /// What the pictures wrote before their numbers were appended in
    /// place: `format!`, trailing zeros and the point trimmed, `-0` as `0`.
    #[test]
    fn decimals_appended_are_the_trimmed_format() {
        let trimmed = |x: f64, d: usize| {
            let s = format!("{x:.d$}");
            let s = if s.contains('.') {
                s.trim_end_matches('0').trim_end_matches('.').to_string()
            } else {
                s
            };
            if s == "-0" { "0".to_string() } else { s }
        };
        let xs = numbers();
        for d in 0..=8usize {
            let mut out = String::from("x=");
            for &x in &xs {
                assert_eq!(fmt_decimals(x, d), trimmed(x, d), "{x:e} to {d}");
                out.truncate(2);
                push_decimals(&mut out, x, d);
                assert_eq!(out[2..], trimmed(x, d), "{x:e} to {d}");
            }
        }
        assert_eq!(fmt_decimals(-0.004, 2), "0");
        assert_eq!(fmt_decimals(12.50, 2), "12.5");
        assert_eq!(fmt_decimals(-100.0, 2), "-100");
    }

    #[test]
    fn negative_zeros_lose_their_sign_and_nothing_else_does() {
        for (text, tidy) in [
            ("-0.00", "0.00"),
            ("max -0.000 mm, min -0 mm", "max 0.000 mm, min 0 mm"),
            ("(-0.0°)", "(0.0°)"),
            ("a,-0.00\n", "a,0.00\n"),
            ("-0.001", "-0.001"),
            ("-0.50", "-0.50"),
            ("-0e-5", "-0e-5"),
            ("-0.0e3", "-0.0e3"),
            ("-05", "-05"),
            ("x-0.00", "x-0.00"),
            ("1-0.00", "1-0.00"),
            ("+0.00 and -12.00", "+0.00 and -12.00"),
            ("Δ −0.00", "Δ −0.00"),
            ("x    -0.00\n -0.0 mm", "x     0.00\n  0.0 mm"),
            ("", ""),
        ] {
            assert_eq!(without_negative_zeros(text), tidy, "{text}");
        }
        assert!(matches!(
            without_negative_zeros("1.00 mm"),
            std::borrow::Cow::Borrowed(_)
        ));
        for x in [-0.0, -1e-9, -0.004, -0.0049] {
            assert_eq!(without_negative_zeros(&format!("{x:.2}")), "0.00", "{x}");
            assert_eq!(without_negative_zeros(&format!("{x:8.2}")), "    0.00", "{x}");
        }
        assert_eq!(without_negative_zeros(&format!("{:.2}", -0.005_1)), "-0.01");
    }

    #[test]
    fn rates_are_whole_numbers_grouped_by_thousands() {
        assert_eq!(rate(12_651.685_1, "settings"), "12 652 settings/s");
        assert_eq!(rate(950.4, "settings"), "950 settings/s");
        assert_eq!(rate(2.46, "settings"), "2.5 settings/s");
        assert_eq!(rate(0.0, "cycles"), "0.0 cycles/s");
        assert_eq!(rate(f64::NAN, "cycles"), "– cycles/s");
        assert_eq!(rate(1_234_567.0, "rows"), "1 234 567 rows/s");
        assert_eq!(rate_number(12_651.685_1), "12 652");
        assert_eq!(grouped(0), "0");
        assert_eq!(grouped(100), "100");
        assert_eq!(grouped(1000), "1 000");
    }

    /// What [`fmt_num`] wrote before [`push_num`]: the exact decimal
    /// conversion for every number.
    fn fmt_num_exact(x: f64) -> String {
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

    proptest::proptest! {
        #![proptest_config(proptest::prelude::ProptestConfig::with_cases(20_000))]

        /// The fast path writes what the exact conversion writes: any bit
        /// pattern, and numbers of every everyday magnitude.
        #[test]
        fn fast_digits_equal_the_exact_conversion(bits in proptest::prelude::any::<u64>(),
                                                  m in -1.0..1.0f64, e in -6i32..17) {
            let x = f64::from_bits(bits);
            proptest::prop_assert_eq!(fmt_num(x), fmt_num_exact(x));
            let y = m * 10f64.powi(e);
            proptest::prop_assert_eq!(fmt_num(y), fmt_num_exact(y));
        }
    }

    #[test]
    fn fast_digits_at_the_edges() {
        let mut xs = vec![
            1e-4,
            9.99999999999e-5,
            9.999999999995e-5,
            0.000099999999999949,
            1e15,
            999999999999999.9,
            1e14,
            999999999999.5,
            99999999999.95,
            123456789012.5,
            0.5,
            1.5,
            2.5,
            1.0000000000005,
            1.0000000000015,
            175.0,
            0.1,
            0.2,
            0.3,
            1.0 / 3.0,
            2.0 / 3.0,
            f64::NAN,
            f64::INFINITY,
            f64::MIN_POSITIVE,
            5e-324,
            f64::MAX,
        ];
        // Every power of ten and its neighbours, and halves at the 12th digit.
        for k in -6..17 {
            let p = 10f64.powi(k);
            xs.extend([
                p,
                p.next_up(),
                p.next_down(),
                5.0 * p,
                1.000000000005 * p,
                9.999999999995 * p,
            ]);
        }
        for x in xs {
            for x in [x, -x] {
                assert_eq!(fmt_num(x), fmt_num_exact(x), "{x:e}");
            }
        }
        // The grid angles and take-ups of a cycle of 0.001° steps, nearly
        // all on the fast path.
        let mut fast = 0;
        for k in 1..360_000 {
            let phi = k as f64 * 0.001;
            let p = 12.5 * phi.to_radians().sin() - 3.0;
            assert_eq!(fmt_num(phi), fmt_num_exact(phi));
            assert_eq!(fmt_num(p), fmt_num_exact(p));
            fast += usize::from(twelve_digits(phi).is_some()) + usize::from(twelve_digits(p).is_some());
        }
        assert!(fast > 2 * 359_999 * 99 / 100, "{fast}");
    }

    #[test]
    fn digits_in_lanes_equal_division() {
        let bytes = |v: u64, n: usize| -> Vec<u8> { (0..n).map(|i| ((v >> (8 * i)) & 0xff) as u8).collect() };
        let decimal = |v: u32, n: usize| -> Vec<u8> { format!("{v:0n$}").bytes().map(|b| b - b'0').collect() };
        for v in 0..10_000 {
            assert_eq!(bytes(u64::from(four_digits(v)), 4), decimal(v, 4), "{v}");
        }
        for v in (0..100_000_000)
            .step_by(9_973)
            .chain([99_999_999, 10_000_000, 1, 12_345_678])
        {
            assert_eq!(bytes(eight_digits(v), 8), decimal(v, 8), "{v}");
        }
    }

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
