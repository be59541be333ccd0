//! How well the actual take-up P(φ) matches the required P'(φ)
//! (`docs/stitch-formation.md` §8).
//!
//! With D(φ) = P(φ) − P'(φ), D > 0 is thread given but not needed (slack, a
//! loose stitch) and D < 0 thread needed but not given (strain). Every metric
//! is taken over the compared positions of a uniform φ grid covering one
//! cycle (the cycle minus the regulator windows, where thread passes the
//! tension regulator and the two need not agree).

use rustfft::num_complex::Complex64;
use rustfft::{Fft, FftPlanner};
use serde::Serialize;

/// The mismatch of one thread.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Mismatch {
    /// max |D| and where, mm and deg.
    pub max_abs_d_mm: f64,
    pub max_abs_d_at_deg: f64,
    /// Largest excess (max D) and largest deficit (min D), mm.
    pub max_d_mm: f64,
    pub min_d_mm: f64,
    /// √(mean D²), mm.
    pub rms_d_mm: f64,
    /// Standard deviation of D (RMS with the mean offset removed), mm.
    pub std_d_mm: f64,
    /// ∫ max(D, 0) dφ and ∫ max(−D, 0) dφ, mm·deg.
    pub excess_area_mm_deg: f64,
    pub deficit_area_mm_deg: f64,
    /// Maximal φ intervals [from, to] (deg) with D > ε and with D < −ε, in
    /// grid order; one that runs through the end of the grid into its start
    /// is a single interval whose `to` is 360° more than its last φ.
    pub excess_intervals_deg: Vec<[f64; 2]>,
    pub deficit_intervals_deg: Vec<[f64; 2]>,
    /// φ(max P) − φ(max P'), wrapped to (−180°, 180°].
    pub phase_shift_max_deg: f64,
    /// The circular shift λ (deg, wrapped) that minimizes std(P(φ + λ) −
    /// P'(φ)); `None` when not asked for.
    pub best_lag_deg: Option<f64>,
    /// Swing of P', max P' − min P', mm.
    pub range_pprime_mm: f64,
    /// The match score s = 100·max(0, 1 − RMS(D)/range(P')), 0…100: 100 is
    /// a perfect match, 0 an RMS error as large as P' swings. What tuning
    /// maximizes. `None` when P' does not vary.
    pub score: Option<f64>,
    /// s₀: the same with std(D) (offset-free), a diagnostic.
    pub score_offset_free: Option<f64>,
}

/// Wraps an angle difference to (−180°, 180°].
fn wrap180(x: f64) -> f64 {
    let w = (x + 180.0).rem_euclid(360.0) - 180.0;
    if w == -180.0 { 180.0 } else { w }
}

/// `Σ_k w_k·(p_k − p'_k)²` with w the 0/1 weight of the compared
/// positions: the sum of squares of the mismatch D over them, in four
/// partial sums (so a cycle's loop runs on the vector unit). The match
/// score's RMS; sweeps compute it with this same function, so their score
/// is bit for bit the cycle table's.
#[inline]
pub fn sum_sq_diff(p: &[f64], pprime: &[f64], w: &[f64]) -> f64 {
    let n = p.len().min(pprime.len()).min(w.len());
    let (p, pprime, w) = (&p[..n], &pprime[..n], &w[..n]);
    let mut s = [0.0f64; 4];
    let full = n / 4 * 4;
    for k in (0..full).step_by(4) {
        for j in 0..4 {
            let d = (p[k + j] - pprime[k + j]) * w[k + j];
            s[j] += d * d;
        }
    }
    for k in full..n {
        let d = (p[k] - pprime[k]) * w[k];
        s[k - full] += d * d;
    }
    (s[0] + s[1]) + (s[2] + s[3])
}

/// Values of a curve within this of its largest, mm, count as its largest
/// ([`mismatch`]'s phase of the maxima): far above the rounding of P'
/// (10⁻¹¹ mm) and far below anything measured.
const PLATEAU_MM: f64 = 1e-9;

/// The mismatch of `p` against `pprime` on the uniform grid `phi_deg` (one
/// cycle, step `phi_deg[1] − phi_deg[0]`). `compared[k]` is false inside a
/// regulator window; `eps_mm` is the tolerance ε of the intervals; `lag`
/// asks for the best lag (O(n log n), [`best_lag_index`]). `None` when
/// nothing is compared.
pub fn mismatch(
    phi_deg: &[f64],
    p: &[f64],
    pprime: &[f64],
    compared: &[bool],
    eps_mm: f64,
    lag: bool,
) -> Option<Mismatch> {
    let n = phi_deg.len();
    assert!(
        p.len() == n && pprime.len() == n && compared.len() == n,
        "one value per φ"
    );
    let ks: Vec<usize> = (0..n).filter(|&k| compared[k]).collect();
    if ks.is_empty() {
        return None;
    }
    let dphi = if n > 1 { phi_deg[1] - phi_deg[0] } else { 360.0 };
    let d: Vec<f64> = (0..n).map(|k| p[k] - pprime[k]).collect();
    let count = ks.len() as f64;
    let mean = ks.iter().map(|&k| d[k]).sum::<f64>() / count;
    let weight: Vec<f64> = compared.iter().map(|&c| if c { 1.0 } else { 0.0 }).collect();
    let rms = (sum_sq_diff(p, pprime, &weight) / count).sqrt();
    let std = (ks.iter().map(|&k| (d[k] - mean).powi(2)).sum::<f64>() / count).sqrt();
    let k_abs = *ks
        .iter()
        .max_by(|&&a, &&b| d[a].abs().total_cmp(&d[b].abs()).then(b.cmp(&a)))
        .unwrap();
    // Where a curve is largest: the first compared position within
    // [`PLATEAU_MM`] of its largest value. P' can be level over a stretch
    // of the cycle (the MF-7923D's n2 over 180–225°), equal along it only
    // to the rounding of the thread's balance; the first of the level is
    // where its largest value is reached.
    let argmax = |v: &[f64]| {
        let top = ks.iter().map(|&k| v[k]).fold(f64::MIN, f64::max);
        *ks.iter().find(|&&k| v[k] >= top - PLATEAU_MM).unwrap()
    };
    let (pp_max, pp_min) = ks.iter().fold((f64::MIN, f64::MAX), |(hi, lo), &k| {
        (hi.max(pprime[k]), lo.min(pprime[k]))
    });
    let range = pp_max - pp_min;
    let best_lag = lag.then(|| wrap180(best_lag_index(p, pprime, compared) as f64 * dphi));
    let intervals = |sel: &dyn Fn(f64) -> bool| {
        let mut out = Vec::new();
        let mut start: Option<usize> = None;
        for k in 0..n {
            let on = compared[k] && sel(d[k]);
            match (on, start) {
                (true, None) => start = Some(k),
                (false, Some(s)) => {
                    out.push([phi_deg[s], phi_deg[k - 1]]);
                    start = None;
                }
                _ => {}
            }
        }
        if let Some(s) = start {
            // The grid is one cycle: a run through its end goes on at its
            // start, so the two pieces are one interval.
            if out.first().is_some_and(|f| f[0] == phi_deg[0]) && s > 0 {
                let first = out.remove(0);
                out.push([phi_deg[s], first[1] + 360.0]);
            } else {
                out.push([phi_deg[s], phi_deg[n - 1]]);
            }
        }
        out
    };
    let score = |e: f64| (range > 1e-12).then(|| 100.0 * (1.0 - e / range).max(0.0));
    Some(Mismatch {
        max_abs_d_mm: d[k_abs].abs(),
        max_abs_d_at_deg: phi_deg[k_abs],
        max_d_mm: ks.iter().map(|&k| d[k]).fold(f64::MIN, f64::max),
        min_d_mm: ks.iter().map(|&k| d[k]).fold(f64::MAX, f64::min),
        rms_d_mm: rms,
        std_d_mm: std,
        excess_area_mm_deg: ks.iter().map(|&k| d[k].max(0.0)).sum::<f64>() * dphi,
        deficit_area_mm_deg: ks.iter().map(|&k| (-d[k]).max(0.0)).sum::<f64>() * dphi,
        excess_intervals_deg: intervals(&|x| x > eps_mm),
        deficit_intervals_deg: intervals(&|x| x < -eps_mm),
        phase_shift_max_deg: wrap180(phi_deg[argmax(p)] - phi_deg[argmax(pprime)]),
        best_lag_deg: best_lag,
        range_pprime_mm: range,
        score: score(rms),
        score_offset_free: score(std),
    })
}

/// The best circular lag of `p` against `pprime`: the shift j (λ = j·dφ)
/// that minimizes the variance of P(φ_k + λ) − P'(φ_k) over the compared
/// k. Scanning j = 0, 1, …, n − 1, a lag replaces the best so far only when
/// its variance is lower by more than 1e-12 mm², so of (nearly) equal
/// minima the first wins and equal curves give 0.
pub fn best_lag_index(p: &[f64], pprime: &[f64], compared: &[bool]) -> usize {
    let mut best = (f64::INFINITY, 0usize);
    for (j, v) in lag_variances(p, pprime, compared).into_iter().enumerate() {
        if v < best.0 - 1e-12 {
            best = (v, j);
        }
    }
    best.1
}

/// For every lag j, the variance (mm²) of p_{k+j} − p'_k over the compared
/// k (indices mod n), in O(n log n). With w the 0/1 weight of the compared
/// positions:
///
/// Σ_k w_k (p_{k+j} − p'_k)  = (w ⋆ p)(j) − Σ_k w_k p'_k,
/// Σ_k w_k (p_{k+j} − p'_k)² = (w ⋆ p²)(j) − 2 (w·p' ⋆ p)(j) + Σ_k w_k p'_k²,
///
/// where (a ⋆ b)(j) = Σ_k a_k b_{k+j} is the circular cross-correlation,
/// IDFT(conj(DFT a)·DFT b) (the correlation theorem: Press et al.,
/// Numerical Recipes, 3rd ed., §13.2).
fn lag_variances(p: &[f64], pprime: &[f64], compared: &[bool]) -> Vec<f64> {
    let n = p.len();
    let count = compared.iter().filter(|&&c| c).count() as f64;
    // A constant added to P or to P' leaves every variance alone; centred,
    // the sums are small, and so are the transforms' rounding errors.
    let p_mean_mm = p.iter().sum::<f64>() / n as f64;
    let q_mean_mm = (0..n).filter(|&k| compared[k]).map(|k| pprime[k]).sum::<f64>() / count;
    let pc: Vec<f64> = p.iter().map(|x| x - p_mean_mm).collect();
    let w: Vec<f64> = compared.iter().map(|&c| if c { 1.0 } else { 0.0 }).collect();
    let wq: Vec<f64> = (0..n).map(|k| w[k] * (pprime[k] - q_mean_mm)).collect();
    let sum_wq: f64 = wq.iter().sum();
    let sum_wq2: f64 = wq.iter().map(|x| x * x).sum();
    let mut planner = FftPlanner::new();
    let forward = planner.plan_fft_forward(n);
    let (fp, fp2) = two_real_dfts(&*forward, &pc, &pc.iter().map(|x| x * x).collect::<Vec<_>>());
    let (fw, fwq) = two_real_dfts(&*forward, &w, &wq);
    // Both sums are real for every j: one inverse transform carries the
    // first as its real part and the second as its imaginary part.
    let mut z: Vec<Complex64> = (0..n)
        .map(|m| {
            let s1 = fw[m].conj() * fp[m];
            let s2 = fw[m].conj() * fp2[m] - 2.0 * fwq[m].conj() * fp[m];
            s1 + Complex64::i() * s2
        })
        .collect();
    planner.plan_fft_inverse(n).process(&mut z);
    z.iter()
        .map(|c| {
            let s1 = c.re / n as f64 - sum_wq;
            let s2 = c.im / n as f64 + sum_wq2;
            (s2 / count - (s1 / count).powi(2)).max(0.0)
        })
        .collect()
}

/// The DFTs of two real sequences from one complex transform of a + i·b:
/// A_m = (X_m + conj X_{n−m})/2, B_m = (X_m − conj X_{n−m})/(2i)
/// (Numerical Recipes, 3rd ed., §12.3).
fn two_real_dfts(fft: &dyn Fft<f64>, a: &[f64], b: &[f64]) -> (Vec<Complex64>, Vec<Complex64>) {
    let n = a.len();
    let mut x: Vec<Complex64> = a.iter().zip(b).map(|(&re, &im)| Complex64::new(re, im)).collect();
    fft.process(&mut x);
    (0..n)
        .map(|m| {
            let (xm, xc) = (x[m], x[(n - m) % n].conj());
            ((xm + xc) * 0.5, (xm - xc) * Complex64::new(0.0, -0.5))
        })
        .unzip()
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    /// The direct search [`best_lag_index`] replaced, n sums of n terms:
    /// the reference it must agree with.
    fn best_lag_index_direct(p: &[f64], pprime: &[f64], compared: &[bool]) -> usize {
        let n = p.len();
        let ks: Vec<usize> = (0..n).filter(|&k| compared[k]).collect();
        let count = ks.len() as f64;
        let p2: Vec<f64> = p.iter().chain(p).copied().collect();
        let mut best = (f64::INFINITY, 0usize);
        for j in 0..n {
            let var = variance_direct(&p2[j..j + n], pprime, &ks, count);
            if var < best.0 - 1e-12 {
                best = (var, j);
            }
        }
        best.1
    }

    /// The variance of `shifted − pprime` over `ks`, summed directly.
    fn variance_direct(shifted: &[f64], pprime: &[f64], ks: &[usize], count: f64) -> f64 {
        let (mut s1, mut s2) = (0.0, 0.0);
        for &k in ks {
            let x = shifted[k] - pprime[k];
            s1 += x;
            s2 += x * x;
        }
        (s2 / count - (s1 / count).powi(2)).max(0.0)
    }

    /// A random test case: n positions, P and P' (a few harmonics, an
    /// offset, noise, or a constant) and a compared mask (all, a regulator
    /// window that may wrap, or random).
    fn case() -> impl Strategy<Value = (Vec<f64>, Vec<f64>, Vec<bool>)> {
        let curve = |n: usize| {
            (
                prop::collection::vec((-20.0..20.0f64, 0.0..std::f64::consts::TAU), 1..4),
                -30.0..30.0f64,
                0.0..0.5f64,
                prop::collection::vec(-1.0..1.0f64, n),
                prop::bool::weighted(0.15),
            )
                .prop_map(move |(harmonics, offset, noise, rnd, flat)| {
                    (0..n)
                        .map(|k| {
                            if flat {
                                return offset;
                            }
                            let phi = std::f64::consts::TAU * k as f64 / n as f64;
                            let h: f64 = harmonics
                                .iter()
                                .enumerate()
                                .map(|(i, (a, ph))| a * ((i + 1) as f64 * phi + ph).sin())
                                .sum();
                            offset + h + noise * rnd[k]
                        })
                        .collect::<Vec<f64>>()
                })
        };
        (1usize..300).prop_flat_map(move |n| {
            let mask = prop_oneof![
                Just(vec![true; n]),
                (0..n, 0..n).prop_map(move |(start, len)| {
                    (0..n)
                        .map(|k| (k + n - start) % n >= len.min(n - 1))
                        .collect::<Vec<bool>>()
                }),
                prop::collection::vec(prop::bool::weighted(0.7), n)
                    .prop_map(|m| { if m.iter().any(|&c| c) { m } else { vec![true; m.len()] } }),
            ];
            (curve(n), curve(n), mask)
        })
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(300))]

        /// The transform gives the direct search's variances up to
        /// rounding, and its lag, or one whose variance equals the direct
        /// minimum up to rounding (a tie the rounding decides).
        #[test]
        fn fast_lag_matches_the_direct_search((p, pprime, compared) in case()) {
            let n = p.len();
            let ks: Vec<usize> = (0..n).filter(|&k| compared[k]).collect();
            let p2: Vec<f64> = p.iter().chain(&p).copied().collect();
            let direct: Vec<f64> =
                (0..n).map(|j| variance_direct(&p2[j..j + n], &pprime, &ks, ks.len() as f64)).collect();
            let fast = lag_variances(&p, &pprime, &compared);
            let scale = 1.0 + direct.iter().cloned().fold(0.0, f64::max);
            for j in 0..n {
                prop_assert!((fast[j] - direct[j]).abs() <= 1e-10 * scale, "j = {j}: {} vs {}", fast[j], direct[j]);
            }
            let (jf, jd) = (best_lag_index(&p, &pprime, &compared), best_lag_index_direct(&p, &pprime, &compared));
            prop_assert!(
                jf == jd || (direct[jf] - direct[jd]).abs() <= 1e-10 * scale,
                "lag {jf} vs {jd}: {} vs {}", direct[jf], direct[jd]
            );
        }
    }

    #[test]
    fn long_grids_match_the_direct_search() {
        // A prime length (no fast radix) and the 0.1° grid, with a window.
        for n in [2003usize, 3600] {
            let phi = |k: usize| std::f64::consts::TAU * k as f64 / n as f64;
            let pp: Vec<f64> = (0..n)
                .map(|k| 12.0 * phi(k).sin() + 3.0 * (3.0 * phi(k)).cos())
                .collect();
            let p: Vec<f64> = (0..n).map(|k| 11.0 * (phi(k) - 0.4).sin() + 20.0).collect();
            let compared: Vec<bool> = (0..n).map(|k| k < n * 5 / 6).collect();
            assert_eq!(
                best_lag_index(&p, &pp, &compared),
                best_lag_index_direct(&p, &pp, &compared),
                "n = {n}"
            );
        }
    }

    #[test]
    fn equal_minima_keep_the_first_lag() {
        // P' of period 180°: P lagging it by 30° matches at 30° and 210°.
        let n = 360;
        let pp: Vec<f64> = (0..n).map(|k| (2.0 * (k as f64).to_radians()).sin()).collect();
        let p: Vec<f64> = (0..n)
            .map(|k| (2.0 * (k as f64 - 30.0).to_radians()).sin() + 3.0)
            .collect();
        let all = vec![true; n];
        assert_eq!(best_lag_index(&p, &pp, &all), 30);
        assert_eq!(best_lag_index_direct(&p, &pp, &all), 30);
        // Constant curves: every lag ties, the first wins.
        assert_eq!(best_lag_index(&[2.5; 7], &[1.0; 7], &[true; 7]), 0);
        assert_eq!(best_lag_index(&[4.0], &[1.0], &[true]), 0);
    }

    fn grid(step: f64) -> Vec<f64> {
        (0..(360.0 / step) as usize).map(|k| k as f64 * step).collect()
    }

    #[test]
    fn identical_curves_score_100() {
        let phi = grid(1.0);
        let pp: Vec<f64> = phi.iter().map(|f| 10.0 * f.to_radians().sin()).collect();
        let m = mismatch(&phi, &pp, &pp, &vec![true; phi.len()], 0.5, true).unwrap();
        assert_eq!(m.rms_d_mm, 0.0);
        assert_eq!(m.score, Some(100.0));
        assert!(m.excess_intervals_deg.is_empty() && m.deficit_intervals_deg.is_empty());
        assert_eq!(m.best_lag_deg, Some(0.0));
    }

    #[test]
    fn offset_and_shift_are_measured() {
        let phi = grid(1.0);
        let pp: Vec<f64> = phi.iter().map(|f| 10.0 * f.to_radians().sin()).collect();
        // P lags P' by 30°: P(φ) = P'(φ − 30°), plus 1 mm of slack.
        let p: Vec<f64> = phi.iter().map(|f| 10.0 * (f - 30.0).to_radians().sin() + 1.0).collect();
        let m = mismatch(&phi, &p, &pp, &vec![true; phi.len()], 0.5, true).unwrap();
        assert!((m.phase_shift_max_deg - 30.0).abs() < 1e-9, "{m:?}");
        // P' level at its top from 60° to 120° with rounding along it: its
        // largest value is reached at 60°, wherever the rounding peaks.
        let level: Vec<f64> = phi
            .iter()
            .enumerate()
            .map(|(k, f)| {
                if (60.0..=120.0).contains(f) {
                    10.0 + 1e-12 * ((k * 7) % 5) as f64
                } else {
                    10.0 * f.to_radians().sin()
                }
            })
            .collect();
        let on_level = mismatch(&phi, &p, &level, &vec![true; phi.len()], 0.5, false).unwrap();
        assert!((on_level.phase_shift_max_deg - 60.0).abs() < 1e-9, "{on_level:?}");
        // P(φ + 30°) = P'(φ): the best lag is +30°.
        assert!((m.best_lag_deg.unwrap() - 30.0).abs() < 1e-9, "{m:?}");
        assert!((m.range_pprime_mm - 20.0).abs() < 1e-9);
        // D = 1 + 10(sin(φ−30°) − sin φ) = 1 − 2·10·sin15°·cos(φ − 15°):
        // mean 1, std 20 sin15°/√2.
        let std = 20.0 * 15f64.to_radians().sin() / 2f64.sqrt();
        assert!((m.std_d_mm - std).abs() < 1e-9);
        assert!((m.rms_d_mm - (1.0 + std * std).sqrt()).abs() < 1e-9);
        assert!((m.score.unwrap() - 100.0 * (1.0 - m.rms_d_mm / 20.0)).abs() < 1e-12);
        assert!(m.score_offset_free.unwrap() > m.score.unwrap());
        // Areas: the excess minus the deficit is the mean times 360°.
        assert!((m.excess_area_mm_deg - m.deficit_area_mm_deg - 360.0).abs() < 1e-6);
        assert!(!m.excess_intervals_deg.is_empty() && !m.deficit_intervals_deg.is_empty());
    }

    #[test]
    fn regulator_window_is_left_out() {
        let phi = grid(1.0);
        let pp = vec![0.0; 360];
        let mut pp2 = pp.clone();
        pp2[10] = 5.0;
        let mut p = pp2.clone();
        p[200] = 100.0; // a spike inside the window
        let compared: Vec<bool> = (0..360).map(|k| !(190..=210).contains(&k)).collect();
        let m = mismatch(&phi, &p, &pp2, &compared, 0.5, true).unwrap();
        assert_eq!(m.max_abs_d_mm, 0.0);
        assert!(mismatch(&phi, &p, &pp2, &[false; 360], 0.5, true).is_none());
        // A flat P' has no score.
        assert_eq!(mismatch(&phi, &p, &pp, &compared, 0.5, true).unwrap().score, None);
    }

    #[test]
    fn intervals_are_maximal_runs() {
        let phi = grid(10.0);
        let pp = vec![0.0; 36];
        let p: Vec<f64> = (0..36)
            .map(|k| {
                if (3..=6).contains(&k) {
                    1.0
                } else if k >= 30 {
                    -1.0
                } else {
                    0.0
                }
            })
            .collect();
        let m = mismatch(&phi, &p, &pp, &[true; 36], 0.5, true).unwrap();
        assert_eq!(m.excess_intervals_deg, vec![[30.0, 60.0]]);
        assert_eq!(m.deficit_intervals_deg, vec![[300.0, 350.0]]);
        assert!((m.excess_area_mm_deg - 40.0).abs() < 1e-12);
        // A run through the end of the cycle continues at its start.
        let p: Vec<f64> = (0..36).map(|k| if k <= 2 || k >= 33 { 1.0 } else { 0.0 }).collect();
        let m = mismatch(&phi, &p, &pp, &[true; 36], 0.5, true).unwrap();
        assert_eq!(m.excess_intervals_deg, vec![[330.0, 380.0]]);
    }
}
