//! The design of a study: what varies and how it is sampled.
//!
//! A [`Sweep`] is a [`Design`] over one or more [`Vary`] ranges: a full
//! grid, or `n` random or Latin-hypercube samples drawn from a seed.
//! Settings are numbered 0…len−1 and each one's values depend only on its
//! number and the seed, so a sweep split into shards ([`Sweep::shard`]) and
//! concatenated is the same sweep.

use crate::error::{Error, Input, ParamError};
use crate::model::Model;

/// One swept parameter: `NAME=LO:HI:N` (N values from LO to HI, both
/// included; for sampled designs only LO and HI matter).
#[derive(Debug, Clone, PartialEq)]
pub struct Vary {
    pub name: String,
    pub lo: f64,
    pub hi: f64,
    pub n: usize,
}

impl Vary {
    /// Parses `NAME=LO:HI:N` (or `NAME=LO:HI`, N = 11) and checks it against
    /// the model: a settable parameter, both ends inside its adjustable range.
    pub fn parse(model: &Model, spec: &str) -> Result<Vary, Error> {
        const HELP: &str = "write NAME=LO:HI:N, e.g. z=-10:10:41 (N values, ends included)";
        let bad = |message: String| Error::Param(ParamError::new(Input::Vary, message, Some(HELP.into())));
        let (name, range) = spec
            .split_once('=')
            .ok_or_else(|| bad(format!("`{spec}` is not NAME=LO:HI:N")))?;
        let (lo, hi, n) = parse_lo_hi_n(spec, range, Input::Vary, HELP, |lo| {
            format!(
                "give N ≥ 2 for values from LO to HI, or {}={lo}:{lo}:1 for the one value {lo}",
                name.trim()
            )
        })?;
        let name = name.trim().to_string();
        // Both ends must be accepted by the parameter (existence, range).
        let mut p = model.defaults();
        model.set(&mut p, &name, lo).map_err(|e| e.in_input(Input::Vary))?;
        model.set(&mut p, &name, hi).map_err(|e| e.in_input(Input::Vary))?;
        Ok(Vary { name, lo, hi, n })
    }

    /// The k-th of the N grid values.
    pub fn grid_value(&self, k: usize) -> f64 {
        if self.n == 1 {
            self.lo
        } else {
            self.lo + (self.hi - self.lo) * k as f64 / (self.n - 1) as f64
        }
    }
}

/// The ends and the number of values of `range`, `LO:HI:N` (or `LO:HI`,
/// N = 11), the part of `spec` given in `input`: finite ends, a whole
/// N ≥ 1, LO = HI only for N = 1 and N = 1 only for LO = HI. `help` says
/// how to write it; `one_value(lo)` how to ask for the one value LO
/// instead of one value between two ends.
pub(crate) fn parse_lo_hi_n(
    spec: &str,
    range: &str,
    input: Input,
    help: &str,
    one_value: impl Fn(f64) -> String,
) -> Result<(f64, f64, usize), Error> {
    let bad = |message: String| Error::Param(ParamError::new(input, message, Some(help.into())));
    let what = if spec == range {
        format!("`{spec}`")
    } else {
        format!("`{spec}`: `{range}`")
    };
    let parts: Vec<&str> = range.split(':').collect();
    if !(2..=3).contains(&parts.len()) {
        return Err(bad(format!("{what} is not LO:HI:N")));
    }
    let num = |s: &str| s.trim().parse::<f64>().ok().filter(|x| x.is_finite());
    let (Some(lo), Some(hi)) = (num(parts[0]), num(parts[1])) else {
        return Err(bad(format!("{what}: the ends must be numbers")));
    };
    let n = match parts.get(2) {
        Some(s) => s
            .trim()
            .parse::<usize>()
            .ok()
            .filter(|&n| n >= 1)
            .ok_or_else(|| bad(format!("`{spec}`: N = `{s}` must be a whole number ≥ 1")))?,
        None => 11,
    };
    if n > 1 && lo == hi {
        return Err(bad(format!(
            "`{spec}`: LO = HI gives {n} equal values; use N = 1 or widen the range"
        )));
    }
    if n == 1 && lo != hi {
        // One value from a range: LO, HI or between? Every study refuses it.
        return Err(Error::Param(ParamError::new(
            input,
            format!("`{spec}` asks for 1 value between two different ends; a range needs at least 2"),
            Some(one_value(lo)),
        )));
    }
    Ok((lo, hi, n))
}

/// How settings are chosen.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Design {
    /// Every combination of the grid values; the last `--vary` changes fastest.
    Grid,
    /// `samples` independent uniform draws in the box LO…HI of every parameter.
    Random { samples: usize, seed: u64 },
    /// `samples` Latin-hypercube draws: each parameter's range cut into
    /// `samples` equal strata, each stratum used exactly once.
    Lhs { samples: usize, seed: u64 },
}

/// A sweep: what varies and how.
#[derive(Debug, Clone)]
pub struct Sweep {
    pub vary: Vec<Vary>,
    pub design: Design,
    /// Latin-hypercube strata: `perm[d][i]` is the stratum of setting i in
    /// parameter d.
    perm: Vec<Vec<u32>>,
}

/// SplitMix64 (Steele, Lea & Flood 2014): a tiny, well-studied generator whose
/// stream is fixed forever, so a seed gives the same samples in every
/// stitchkin version (general-purpose RNG crates do not promise that).
fn splitmix64(x: u64) -> u64 {
    let mut z = x.wrapping_add(0x9E37_79B9_7F4A_7C15);
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^ (z >> 31)
}

/// A uniform number in [0, 1) from the seed, the setting and the parameter.
fn uniform(seed: u64, setting: usize, dim: usize) -> f64 {
    let h = splitmix64(splitmix64(seed ^ 0x5151_5151) ^ splitmix64((setting as u64) << 8 | dim as u64));
    (h >> 11) as f64 / (1u64 << 53) as f64
}

/// The most settings a sweep may have, checked before any is drawn (a
/// Latin hypercube's strata take 4 bytes per setting and parameter).
pub const MAX_SETTINGS: usize = 100_000_000;
// The strata are numbered in `u32`.
const _: () = assert!(MAX_SETTINGS <= u32::MAX as usize);

/// Number of settings of `design` over `vary`.
fn settings(vary: &[Vary], design: Design) -> usize {
    match design {
        Design::Grid => vary.iter().map(|v| v.n).fold(1usize, |a, n| a.saturating_mul(n)),
        Design::Random { samples, .. } | Design::Lhs { samples, .. } => samples,
    }
}

impl Sweep {
    pub fn new(vary: Vec<Vary>, design: Design) -> Result<Sweep, Error> {
        if vary.is_empty() {
            return Err(Error::Param(ParamError::new(
                Input::Vary,
                "a sweep needs at least one varied parameter",
                Some("vary one, e.g. z=-10:10:41".into()),
            )));
        }
        if let Some(d) = vary
            .iter()
            .position(|v| vary.iter().filter(|w| w.name == v.name).count() > 1)
        {
            return Err(Error::Param(ParamError::new(
                Input::Vary,
                format!("`{}` is varied twice", vary[d].name),
                None,
            )));
        }
        let len = settings(&vary, design);
        if len == 0 || len > MAX_SETTINGS {
            return Err(Error::Param(ParamError::general(
                format!("the sweep has {len} settings"),
                Some("between 1 and 100 million settings: fewer grid points, or a random sample of settings".into()),
            )));
        }
        let perm = match design {
            Design::Lhs { samples, seed } => (0..vary.len())
                .map(|d| {
                    // Fisher–Yates with the seeded generator; samples ≤
                    // MAX_SETTINGS fit in u32.
                    let mut p: Vec<u32> = (0..samples as u32).collect();
                    for i in (1..samples).rev() {
                        let j = (splitmix64(seed.wrapping_mul(31).wrapping_add((d as u64) << 40 | i as u64))
                            % (i as u64 + 1)) as usize;
                        p.swap(i, j);
                    }
                    p
                })
                .collect(),
            _ => Vec::new(),
        };
        Ok(Sweep { vary, design, perm })
    }

    /// Number of settings.
    pub fn len(&self) -> usize {
        settings(&self.vary, self.design)
    }

    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// The values of the varied parameters at setting `i`, in `vary` order.
    pub fn setting(&self, i: usize) -> Vec<f64> {
        match self.design {
            Design::Grid => {
                let mut rest = i;
                let mut out = vec![0.0; self.vary.len()];
                for (d, v) in self.vary.iter().enumerate().rev() {
                    out[d] = v.grid_value(rest % v.n);
                    rest /= v.n;
                }
                out
            }
            Design::Random { seed, .. } => self
                .vary
                .iter()
                .enumerate()
                .map(|(d, v)| v.lo + (v.hi - v.lo) * uniform(seed, i, d))
                .collect(),
            Design::Lhs { samples, seed } => self
                .vary
                .iter()
                .enumerate()
                .map(|(d, v)| v.lo + (v.hi - v.lo) * (self.perm[d][i] as f64 + uniform(seed, i, d)) / samples as f64)
                .collect(),
        }
    }

    /// The settings of shard `k` of `n` (1-based): a contiguous block, so
    /// the shards' outputs concatenated in order are the whole sweep.
    pub fn shard(&self, k: usize, n: usize) -> std::ops::Range<usize> {
        let len = self.len();
        (len * (k - 1) / n)..(len * k / n)
    }
}
#[cfg(test)]
mod tests {
    use super::*;

    fn vary(name: &str, lo: f64, hi: f64, n: usize) -> Vary {
        Vary {
            name: name.into(),
            lo,
            hi,
            n,
        }
    }

    #[test]
    fn grid_runs_the_last_parameter_fastest() {
        let s = Sweep::new(vec![vary("a", 0.0, 1.0, 2), vary("b", 10.0, 30.0, 3)], Design::Grid).unwrap();
        assert_eq!(s.len(), 6);
        let all: Vec<Vec<f64>> = (0..6).map(|i| s.setting(i)).collect();
        assert_eq!(all[0], vec![0.0, 10.0]);
        assert_eq!(all[1], vec![0.0, 20.0]);
        assert_eq!(all[3], vec![1.0, 10.0]);
        assert_eq!(all[5], vec![1.0, 30.0]);
    }

    #[test]
    fn latin_hypercube_uses_every_stratum_once() {
        let n = 50;
        let s = Sweep::new(
            vec![vary("a", 0.0, 1.0, 2), vary("b", -5.0, 5.0, 2)],
            Design::Lhs { samples: n, seed: 7 },
        )
        .unwrap();
        for (d, (lo, hi)) in [(0.0, 1.0), (-5.0, 5.0)].into_iter().enumerate() {
            let mut strata: Vec<usize> = (0..n)
                .map(|i| ((s.setting(i)[d] - lo) / (hi - lo) * n as f64) as usize)
                .collect();
            strata.sort();
            assert_eq!(strata, (0..n).collect::<Vec<_>>());
        }
        // The same seed gives the same samples; another seed others.
        let again = Sweep::new(s.vary.clone(), Design::Lhs { samples: n, seed: 7 }).unwrap();
        let other = Sweep::new(s.vary.clone(), Design::Lhs { samples: n, seed: 8 }).unwrap();
        assert_eq!(s.setting(13), again.setting(13));
        assert_ne!(s.setting(13), other.setting(13));
    }

    #[test]
    fn random_samples_stay_in_the_box_and_look_uniform() {
        let s = Sweep::new(
            vec![vary("a", 2.0, 4.0, 2)],
            Design::Random {
                samples: 20_000,
                seed: 1,
            },
        )
        .unwrap();
        let xs: Vec<f64> = (0..20_000).map(|i| s.setting(i)[0]).collect();
        assert!(xs.iter().all(|x| (2.0..4.0).contains(x)));
        let mean = xs.iter().sum::<f64>() / xs.len() as f64;
        assert!((mean - 3.0).abs() < 0.02, "{mean}");
        let below = xs.iter().filter(|x| **x < 2.5).count() as f64 / xs.len() as f64;
        assert!((below - 0.25).abs() < 0.02, "{below}");
    }

    #[test]
    fn too_many_samples_are_refused_before_they_are_drawn() {
        // 2³² samples once wrapped to no strata and panicked; 10⁹ held 4 GB
        // of strata before the limit was checked.
        for samples in [1usize << 32, 1_000_000_000, MAX_SETTINGS + 1] {
            for design in [Design::Lhs { samples, seed: 1 }, Design::Random { samples, seed: 1 }] {
                let e = Sweep::new(vec![vary("a", 0.0, 1.0, 2)], design).unwrap_err();
                assert!(e.to_string().contains(&format!("{samples} settings")), "{e}");
                assert!(e.help().is_some_and(|h| h.contains("100 million")), "{e:?}");
            }
        }
        assert_eq!(
            Sweep::new(
                vec![vary("a", 0.0, 1.0, 2)],
                Design::Random {
                    samples: MAX_SETTINGS,
                    seed: 1
                }
            )
            .unwrap()
            .len(),
            MAX_SETTINGS
        );
    }

    #[test]
    fn shards_tile_the_sweep() {
        let s = Sweep::new(vec![vary("a", 0.0, 1.0, 7), vary("b", 0.0, 1.0, 3)], Design::Grid).unwrap();
        let parts: Vec<std::ops::Range<usize>> = (1..=4).map(|k| s.shard(k, 4)).collect();
        assert_eq!(parts[0].start, 0);
        assert_eq!(parts[3].end, 21);
        for w in parts.windows(2) {
            assert_eq!(w[0].end, w[1].start);
        }
    }
}
