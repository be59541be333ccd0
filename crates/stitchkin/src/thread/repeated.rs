//! Repeated readings of a take-up, reduced to their mean curve with its
//! uncertainty as seed 004 §3.4 processes its bench measurements (ten
//! readings of the thread every 10° of the main shaft).
//!
//! For each φ with readings x_1 … x_n (n ≥ 2), at the confidence P
//! (default 0.95) and the instrument's resolution Δ_s (its largest error,
//! seed 004 §3.4 takes ± 0.05 mm for its scale with vernier):
//!
//! 1. the mean x̄ = Σ x_i / n;
//! 2. the standard deviation s = √(Σ (x_i − x̄)² / (n − 1));
//! 3. the standard deviation of the mean s_x̄ = s / √n;
//! 4. Student's coefficient t = t_{(1+P)/2, n−1};
//! 5. the random error Δ_r = t · s_x̄;
//! 6. the total error Δ = √(Δ_r² + Δ_s²), the systematic error Δ_s being
//!    the instrument's resolution;
//! 7. the relative error ε = Δ / |x̄| · 100 % (none where |x̄| ≤ Δ: a mean
//!    not told apart from zero has no relative error);
//! 8. the result x = x̄ ± Δ, the interval [x̄ − Δ, x̄ + Δ].
//!
//! The standard uncertainty carried by the mean curve (the weight of a fit
//! is 1/σ²) is u = √(s_x̄² + Δ_s²/3): the random part of the mean and the
//! resolution as a systematic error spread evenly over ± Δ_s (a
//! rectangular distribution, whose standard deviation is Δ_s/√3).
//!
//! Outliers are flagged, never removed, by Grubbs' test at the
//! significance α = 1 − P: the reading farthest from the mean is an outlier
//! when G = max |x_i − x̄| / s exceeds
//! G_crit = (n − 1)/√n · √(t² / (n − 2 + t²)), t = t_{1 − α/(2n), n−2}
//! (n ≥ 3; one test per φ).
//!
//! ```
//! use stitchkin::thread::repeated::{process_point, student_t_quantile};
//!
//! assert!((student_t_quantile(0.975, 9.0) - 2.262_157).abs() < 1e-6);
//! let p = process_point(30.0, &[1.0, 1.2, 1.1, 1.1], 0.05, 0.95);
//! assert!((p.mean_mm - 1.1).abs() < 1e-12);
//! assert!(p.ci_low_mm < p.mean_mm && p.mean_mm < p.ci_high_mm);
//! ```

use serde::Serialize;

/// The confidence of the interval when none is given (seed 004 §3.4: α = 95 %).
pub const DEFAULT_CONFIDENCE: f64 = 0.95;

/// The processed readings of one φ (seed 004 §3.4, steps 1–8).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct PointStats {
    pub phi_deg: f64,
    /// The number of readings n.
    pub n: usize,
    /// The mean x̄, mm.
    pub mean_mm: f64,
    /// The standard deviation s of one reading, mm.
    pub s_mm: f64,
    /// The standard deviation of the mean s/√n, mm.
    pub s_mean_mm: f64,
    /// Student's coefficient t_{(1+P)/2, n−1}.
    pub t: f64,
    /// The interval x̄ ∓ Δ, mm.
    pub ci_low_mm: f64,
    pub ci_high_mm: f64,
    /// The random error Δ_r = t·s/√n, mm.
    pub random_mm: f64,
    /// The systematic error Δ_s (the instrument's resolution), mm.
    pub systematic_mm: f64,
    /// The total error Δ = √(Δ_r² + Δ_s²), mm.
    pub total_mm: f64,
    /// The relative error Δ/|x̄|, %; `None` where |x̄| ≤ Δ.
    pub relative_pct: Option<f64>,
    /// The standard uncertainty of the mean √(s²/n + Δ_s²/3), mm.
    pub sigma_mm: f64,
    /// The readings Grubbs' test flags (1-based, in the order given).
    pub outliers: Vec<usize>,
}

/// Every φ's readings processed, and how.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Processed {
    /// The confidence P of the intervals.
    pub confidence: f64,
    /// The instrument's resolution, mm: the systematic error.
    pub resolution_mm: f64,
    pub points: Vec<PointStats>,
}

impl Processed {
    /// The readings of every φ (`phis_deg[k]` with `readings[k]`, n ≥ 2 each)
    /// processed at `confidence` (0 < P < 1) with the instrument's
    /// resolution `resolution_mm` (> 0).
    pub fn new(phis_deg: &[f64], readings: &[Vec<f64>], resolution_mm: f64, confidence: f64) -> Self {
        Processed {
            confidence,
            resolution_mm,
            points: phis_deg
                .iter()
                .zip(readings)
                .map(|(&phi, x)| process_point(phi, x, resolution_mm, confidence))
                .collect(),
        }
    }

    /// The largest number of readings at any φ.
    pub fn max_n(&self) -> usize {
        self.points.iter().map(|p| p.n).max().unwrap_or(0)
    }

    /// The number of flagged readings.
    pub fn outlier_count(&self) -> usize {
        self.points.iter().map(|p| p.outliers.len()).sum()
    }
}

/// The readings `x` (n ≥ 2, finite) of one φ processed as seed 004 §3.4
/// does, with the instrument's resolution `resolution_mm` (> 0) at
/// `confidence` (0 < P < 1).
pub fn process_point(phi_deg: f64, x: &[f64], resolution_mm: f64, confidence: f64) -> PointStats {
    let n = x.len();
    let nf = n as f64;
    // Steps 1–3.
    let mean = x.iter().sum::<f64>() / nf;
    let s = if n > 1 {
        (x.iter().map(|xi| (xi - mean).powi(2)).sum::<f64>() / (nf - 1.0)).sqrt()
    } else {
        0.0
    };
    let s_mean = s / nf.sqrt();
    // Step 4: two-sided, so the quantile (1 + P)/2.
    let t = if n > 1 {
        student_t_quantile((1.0 + confidence) / 2.0, nf - 1.0)
    } else {
        0.0
    };
    // Steps 5–7.
    let random = t * s_mean;
    let systematic = resolution_mm;
    let total = random.hypot(systematic);
    let relative_pct = (mean.abs() > total).then(|| total / mean.abs() * 100.0);
    let sigma = (s_mean * s_mean + systematic * systematic / 3.0).sqrt();
    PointStats {
        phi_deg,
        n,
        mean_mm: mean,
        s_mm: s,
        s_mean_mm: s_mean,
        t,
        ci_low_mm: mean - total,
        ci_high_mm: mean + total,
        random_mm: random,
        systematic_mm: systematic,
        total_mm: total,
        relative_pct,
        sigma_mm: sigma,
        outliers: grubbs_outlier(x, 1.0 - confidence).into_iter().map(|i| i + 1).collect(),
    }
}

/// Grubbs' test at significance `alpha` (0 < α < 1): the index of the
/// reading farthest from the mean when G = max |x_i − x̄| / s exceeds
/// G_crit = (n − 1)/√n · √(t² / (n − 2 + t²)), t = t_{1 − α/(2n), n−2};
/// `None` for n < 3, all readings equal or no outlier.
pub fn grubbs_outlier(x: &[f64], alpha: f64) -> Option<usize> {
    let n = x.len();
    if n < 3 {
        return None;
    }
    let nf = n as f64;
    let mean = x.iter().sum::<f64>() / nf;
    let s = (x.iter().map(|xi| (xi - mean).powi(2)).sum::<f64>() / (nf - 1.0)).sqrt();
    if s.is_nan() || s <= 0.0 {
        return None;
    }
    let (far, dev) = x
        .iter()
        .enumerate()
        .map(|(i, xi)| (i, (xi - mean).abs()))
        .fold((0, -1.0), |best, d| if d.1 > best.1 { d } else { best });
    let g = dev / s;
    (g > grubbs_critical(n, alpha)).then_some(far)
}

/// Grubbs' two-sided critical value for `n` (≥ 3) readings at significance
/// `alpha`: G_crit = (n − 1)/√n · √(t² / (n − 2 + t²)),
/// t = t_{1 − α/(2n), n−2}.
pub fn grubbs_critical(n: usize, alpha: f64) -> f64 {
    let nf = n as f64;
    let t = student_t_quantile(1.0 - alpha / (2.0 * nf), nf - 2.0);
    (nf - 1.0) / nf.sqrt() * (t * t / (nf - 2.0 + t * t)).sqrt()
}

/// The quantile t_{p, ν} of Student's t distribution with ν > 0 degrees of
/// freedom, 0 < p < 1: the t with F_ν(t) = p, found by bisection on the
/// distribution function [`student_t_cdf`] to the last bits.
pub fn student_t_quantile(p: f64, dof: f64) -> f64 {
    if p == 0.5 {
        return 0.0;
    }
    if p < 0.5 {
        return -student_t_quantile(1.0 - p, dof);
    }
    // Bracket [0, hi] with F(hi) ≥ p, then halve.
    let mut hi = 1.0;
    while student_t_cdf(hi, dof) < p && hi < 1e300 {
        hi *= 2.0;
    }
    let mut lo = 0.0;
    for _ in 0..200 {
        let mid = 0.5 * (lo + hi);
        if mid <= lo || mid >= hi {
            break;
        }
        if student_t_cdf(mid, dof) < p {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    0.5 * (lo + hi)
}

/// Student's t distribution function F_ν(t) with ν > 0 degrees of freedom:
/// for t ≥ 0, F = 1 − ½ I_{ν/(ν+t²)}(ν/2, ½), I the regularized incomplete
/// beta function; F(−t) = 1 − F(t).
pub fn student_t_cdf(t: f64, dof: f64) -> f64 {
    let tail = 0.5 * incomplete_beta(dof / (dof + t * t), dof / 2.0, 0.5);
    if t >= 0.0 { 1.0 - tail } else { tail }
}

/// The regularized incomplete beta function I_x(a, b), 0 ≤ x ≤ 1, a, b > 0:
/// I_x = x^a (1−x)^b / (a B(a,b)) · 1/(1+ d_1/(1+ d_2/(1+ …))), the
/// continued fraction evaluated by the modified Lentz method, and
/// I_x(a,b) = 1 − I_{1−x}(b,a) where the fraction converges slowly
/// (x > (a+1)/(a+b+2)) (Press et al., Numerical Recipes §6.4).
pub fn incomplete_beta(x: f64, a: f64, b: f64) -> f64 {
    if x <= 0.0 {
        return 0.0;
    }
    if x >= 1.0 {
        return 1.0;
    }
    let ln_front = ln_gamma(a + b) - ln_gamma(a) - ln_gamma(b) + a * x.ln() + b * (1.0 - x).ln();
    if x < (a + 1.0) / (a + b + 2.0) {
        ln_front.exp() * beta_fraction(x, a, b) / a
    } else {
        1.0 - ln_front.exp() * beta_fraction(1.0 - x, b, a) / b
    }
}

/// The continued fraction of I_x(a, b): d_{2m+1} = −(a+m)(a+b+m)x / ((a+2m)(a+2m+1)),
/// d_{2m} = m(b−m)x / ((a+2m−1)(a+2m)).
fn beta_fraction(x: f64, a: f64, b: f64) -> f64 {
    const TINY: f64 = 1e-300;
    let mut c = 1.0;
    let mut d = 1.0 - (a + b) * x / (a + 1.0);
    if d.abs() < TINY {
        d = TINY;
    }
    d = 1.0 / d;
    let mut h = d;
    for m in 1..=1000 {
        let m = m as f64;
        for coefficient in [
            m * (b - m) * x / ((a + 2.0 * m - 1.0) * (a + 2.0 * m)),
            -(a + m) * (a + b + m) * x / ((a + 2.0 * m) * (a + 2.0 * m + 1.0)),
        ] {
            d = 1.0 + coefficient * d;
            if d.abs() < TINY {
                d = TINY;
            }
            c = 1.0 + coefficient / c;
            if c.abs() < TINY {
                c = TINY;
            }
            d = 1.0 / d;
            h *= d * c;
        }
        // The last factor d·c of the pair ≈ 1: converged.
        if (d * c - 1.0).abs() < 1e-16 {
            break;
        }
    }
    h
}

/// ln Γ(x), x > 0: the Lanczos approximation (g = 7, 9 terms; relative
/// error below 1e-15), Γ(x) = Γ(x+1)/x for x < ½.
pub fn ln_gamma(x: f64) -> f64 {
    const G: f64 = 7.0;
    const C: [f64; 9] = [
        0.999_999_999_999_809_9,
        676.520_368_121_885_1,
        -1_259.139_216_722_402_8,
        771.323_428_777_653_1,
        -176.615_029_162_140_6,
        12.507_343_278_686_905,
        -0.138_571_095_265_720_12,
        9.984_369_578_019_572e-6,
        1.505_632_735_149_311_6e-7,
    ];
    if x < 0.5 {
        // Reflection: Γ(x) Γ(1−x) = π / sin(πx).
        return (std::f64::consts::PI / (std::f64::consts::PI * x).sin()).ln() - ln_gamma(1.0 - x);
    }
    let x = x - 1.0;
    let mut sum = C[0];
    for (k, c) in C.iter().enumerate().skip(1) {
        sum += c / (x + k as f64);
    }
    let t = x + G + 0.5;
    0.5 * (2.0 * std::f64::consts::PI).ln() + (x + 0.5) * t.ln() - t + sum.ln()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ln_gamma_matches_factorials() {
        for (x, f) in [(1.0, 1.0), (2.0, 1.0), (5.0, 24.0), (11.0, 3_628_800.0)] {
            assert!((ln_gamma(x) - f64::ln(f)).abs() < 1e-12, "{x}");
        }
        // Γ(½) = √π.
        assert!((ln_gamma(0.5) - std::f64::consts::PI.sqrt().ln()).abs() < 1e-13);
        assert!((ln_gamma(0.1) - 2.252_712_651_734_206).abs() < 1e-12);
    }

    #[test]
    fn incomplete_beta_matches_closed_forms() {
        // I_x(1, 1) = x; I_x(a, 1) = x^a; I_x(1, b) = 1 − (1−x)^b.
        for x in [0.0, 0.1, 0.37, 0.5, 0.9, 1.0] {
            assert!((incomplete_beta(x, 1.0, 1.0) - x).abs() < 1e-14);
            assert!((incomplete_beta(x, 3.0, 1.0) - x.powi(3)).abs() < 1e-14);
            assert!((incomplete_beta(x, 1.0, 4.0) - (1.0 - (1.0 - x).powi(4))).abs() < 1e-14);
        }
    }

    /// Student's table (two-sided 95 %, 99 % and 90 %, e.g. any statistics
    /// handbook) to its printed digits.
    #[test]
    fn t_quantiles_match_the_table() {
        for (p, dof, t) in [
            (0.975, 1.0, 12.706),
            (0.975, 2.0, 4.303),
            (0.975, 4.0, 2.776),
            (0.975, 9.0, 2.262),
            (0.975, 10.0, 2.228),
            (0.975, 30.0, 2.042),
            (0.995, 9.0, 3.250),
            (0.995, 1.0, 63.657),
            (0.95, 9.0, 1.833),
            (0.95, 5.0, 2.015),
            (0.9995, 9.0, 4.781),
        ] {
            let got = student_t_quantile(p, dof);
            assert!((got - t).abs() < 6e-4, "t({p}, {dof}) = {got}, table {t}");
        }
        // t(0.975, 9) to more digits; symmetric; → the normal quantile for large ν.
        assert!((student_t_quantile(0.975, 9.0) - 2.262_157_162_740_991).abs() < 1e-9);
        assert!((student_t_quantile(0.025, 9.0) + student_t_quantile(0.975, 9.0)).abs() < 1e-12);
        assert!((student_t_quantile(0.975, 1e7) - 1.959_964).abs() < 1e-5);
        assert_eq!(student_t_quantile(0.5, 3.0), 0.0);
        // ν = 1 is the Cauchy distribution: t_p = tan(π(p − ½)).
        for p in [0.6, 0.9, 0.99, 0.99999] {
            let exact = (std::f64::consts::PI * (p - 0.5)).tan();
            assert!((student_t_quantile(p, 1.0) / exact - 1.0).abs() < 1e-9, "{p}");
        }
    }

    #[test]
    fn one_point_is_processed_by_hand() {
        // x = 2, 4, 4, 4, 5, 5, 7, 9: x̄ = 5, Σ(x−x̄)² = 32, s = √(32/7).
        let x = [2.0, 4.0, 4.0, 4.0, 5.0, 5.0, 7.0, 9.0];
        let p = process_point(90.0, &x, 0.05, 0.95);
        let s = (32.0f64 / 7.0).sqrt();
        let t = 2.364_624_251_592_785; // t(0.975, 7)
        assert_eq!(p.n, 8);
        assert!((p.mean_mm - 5.0).abs() < 1e-15);
        assert!((p.s_mm - s).abs() < 1e-14);
        assert!((p.s_mean_mm - s / 8f64.sqrt()).abs() < 1e-14);
        assert!((p.t - t).abs() < 1e-9);
        let random = t * s / 8f64.sqrt();
        assert!((p.random_mm - random).abs() < 1e-9);
        assert_eq!(p.systematic_mm, 0.05);
        let total = (random * random + 0.0025).sqrt();
        assert!((p.total_mm - total).abs() < 1e-9);
        assert!((p.ci_low_mm - (5.0 - total)).abs() < 1e-9 && (p.ci_high_mm - (5.0 + total)).abs() < 1e-9);
        assert!((p.relative_pct.unwrap() - total / 5.0 * 100.0).abs() < 1e-9);
        assert!((p.sigma_mm - (32.0 / 7.0 / 8.0 + 0.0025 / 3.0f64).sqrt()).abs() < 1e-14);
        assert!(p.outliers.is_empty());
    }

    #[test]
    fn equal_readings_leave_the_resolution_only() {
        let p = process_point(0.0, &[1.5; 10], 0.1, 0.95);
        assert_eq!((p.s_mm, p.random_mm), (0.0, 0.0));
        assert!((p.total_mm - 0.1).abs() < 1e-15);
        assert!((p.sigma_mm - 0.1 / 3f64.sqrt()).abs() < 1e-15);
        assert!(p.outliers.is_empty());
        // A mean within its error of zero has no relative error.
        let z = process_point(0.0, &[-0.02, 0.01, 0.03], 0.05, 0.95);
        assert_eq!(z.relative_pct, None);
    }

    #[test]
    fn grubbs_flags_the_far_reading_only() {
        // G_crit(10, 0.05) = 2.290 (Grubbs' table, two-sided).
        assert!(
            (grubbs_critical(10, 0.05) - 2.290).abs() < 1e-3,
            "{}",
            grubbs_critical(10, 0.05)
        );
        // G_crit(3, 0.05) = 1.155, G_crit(5, 0.05) = 1.715.
        assert!((grubbs_critical(3, 0.05) - 1.1543).abs() < 1e-3);
        assert!((grubbs_critical(5, 0.05) - 1.7150).abs() < 1e-3);
        let mut x = [5.0, 5.1, 4.9, 5.0, 5.05, 4.95, 5.0, 5.1, 4.9, 5.0];
        assert_eq!(grubbs_outlier(&x, 0.05), None);
        x[6] = 6.0;
        assert_eq!(grubbs_outlier(&x, 0.05), Some(6));
        assert_eq!(process_point(0.0, &x, 0.01, 0.95).outliers, vec![7]);
        // Two readings cannot be tested; nor equal ones.
        assert_eq!(grubbs_outlier(&[1.0, 9.0], 0.05), None);
        assert_eq!(grubbs_outlier(&[1.0; 5], 0.05), None);
    }

    #[test]
    fn the_interval_covers_the_mean_at_about_its_confidence() {
        // Draws of 10 readings from a known mean with a deterministic
        // generator: the random interval x̄ ± t s/√n covers it ≈ 95 % of the time.
        let mut state = 0x2545_f491_4f6c_dd1d_u64;
        let mut uniform = || {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            (state >> 11) as f64 / (1u64 << 53) as f64
        };
        let mut covered = 0;
        let draws = 4000;
        for _ in 0..draws {
            let x: Vec<f64> = (0..10)
                .map(|_| {
                    // Box–Muller.
                    let (u, v) = (uniform().max(1e-300), uniform());
                    3.0 + 0.2 * (-2.0 * u.ln()).sqrt() * (2.0 * std::f64::consts::PI * v).cos()
                })
                .collect();
            let p = process_point(0.0, &x, 1e-12, 0.95);
            if (p.mean_mm - 3.0).abs() <= p.random_mm {
                covered += 1;
            }
        }
        let rate = covered as f64 / draws as f64;
        assert!((0.935..=0.965).contains(&rate), "{rate}");
    }
}
