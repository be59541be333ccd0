//! Material transport T(φ_c) (`docs/stitch-formation.md` §4.2; seed 004
//! §2.2.3, reconstruction R1).
//!
//! A harmonic feed dog `x = 0.5·T_d·sin ψ` moves the material while its
//! teeth are up, ψ ∈ [−φ_tr/2, +φ_tr/2]. In the cyclogram angle:
//!
//! ```text
//! T(φ_c) = 0.5·T_d·[sin(φ_c − φ_mid) + sin(φ_tr/2)]   on [φ_s, φ_s + φ_tr]
//! T_d    = t / sin(φ_tr/2),   φ_mid = φ_s + φ_tr/2
//! ```
//!
//! 0 before the transport and t after it, so the material moves exactly one
//! stitch per cycle.
//!
//! Or, with a feed-dog tooth point of the mechanism (law `point`): the
//! transport lasts while the tooth is above the plate top (z > 0), and the
//! material follows the tooth along y,
//!
//! ```text
//! T(φ_c) = t · (y_dog(φ_c) − y_dog(φ_s)) / (y_dog(φ_e) − y_dog(φ_s))   on [φ_s, φ_e]
//! ```
//!
//! scaled so that the cycle's transport is exactly t; a tooth travel that
//! differs from t by more than 1 % is reported (the dog's stroke and the
//! stitch length disagree).

use crate::Error;
use crate::error::StitchError;

use super::search::crossing;
use super::spec::{FeedLaw, Motion};

/// Step of the scan that brackets the feed dog's rise and fall, deg (each
/// then found by root finding, `super::search`).
const DOG_GRID_DEG: f64 = super::search::SCAN_STEP_DEG;

/// The transport of one cycle, resolved to numbers.
#[derive(Debug, Clone)]
pub struct Feed {
    /// Stitch length t: the material's travel per cycle, mm.
    pub t_mm: f64,
    /// φ_s: start of the transport, φ_c deg.
    pub start_deg: f64,
    /// φ_tr: duration of the transport, deg.
    pub duration_deg: f64,
    /// Law `point`: the tooth, its y at φ_s and the scale t/Δy.
    dog: Option<(Motion, f64, f64)>,
    /// Law `point`: the tooth's travel differs from t by more than 1 %.
    pub warning: Option<String>,
    /// sin(φ_tr/2), once.
    sin_half_tr: f64,
}

impl Feed {
    /// The feed of `law` for stitch length `t_mm`. The transport must lie
    /// inside one cyclogram cycle (it never straddles φ_c = 0, §2).
    pub fn new(law: &FeedLaw, t_mm: f64) -> Result<Feed, Error> {
        if !(t_mm.is_finite() && t_mm > 0.0) {
            return Err(Error::Stitch(StitchError::new(
                "feed",
                format!("the stitch length t = {t_mm} mm is not positive; give t > 0"),
            )));
        }
        let (start_deg, duration_deg) = match law {
            FeedLaw::Harmonic {
                start_deg,
                duration_deg,
            } => (*start_deg, *duration_deg),
            FeedLaw::Point { dog } => return Feed::from_dog(dog, t_mm),
        };
        if !(duration_deg.is_finite() && duration_deg > 0.0 && duration_deg < 360.0) {
            return Err(Error::Stitch(StitchError::new(
                "feed",
                format!(
                    "the transport duration φ_tr = {duration_deg}° is out of range; give 0° < φ_tr < 360° \
                 ({}: 100°)",
                    crate::references::cite(4)
                ),
            )));
        }
        if !(start_deg.is_finite() && start_deg >= 0.0 && start_deg + duration_deg <= 360.0) {
            return Err(Error::Stitch(StitchError::new(
                "feed",
                format!(
                    "the transport [{start_deg}°, {}°] must lie inside the cyclogram cycle [0°, 360°] \
                 (φ_c = 0 is the needle BDC); move start_deg",
                    start_deg + duration_deg
                ),
            )));
        }
        Ok(Feed {
            t_mm,
            start_deg,
            duration_deg,
            dog: None,
            warning: None,
            sin_half_tr: (0.5 * duration_deg).to_radians().sin(),
        })
    }

    /// The feed of a tooth point: the transport is where it is above the
    /// plate; it must rise once and sink once inside one cyclogram cycle.
    fn from_dog(dog: &Motion, t_mm: f64) -> Result<Feed, Error> {
        let n = (360.0 / DOG_GRID_DEG).round() as usize;
        let z = |phi: f64| dog.at(phi).z;
        let (mut rises, mut sinks) = (Vec::new(), Vec::new());
        for k in 0..n {
            let (a, b) = (k as f64 * DOG_GRID_DEG, (k + 1) as f64 * DOG_GRID_DEG);
            let (za, zb) = (z(a), z(b));
            if !(za.is_finite() && zb.is_finite()) {
                return Err(Error::Stitch(StitchError::new(
                    "feed",
                    format!("the feed dog's tooth is not finite at φ_c = {a:.2}°"),
                )));
            }
            // The tooth is above the plate where z > 0: −z at or above zero
            // is below it.
            if za <= 0.0 && zb > 0.0 {
                rises.push(crossing(|phi| -z(phi), a, b));
            } else if za > 0.0 && zb <= 0.0 {
                sinks.push(crossing(|phi| -z(phi), a, b));
            }
        }
        let (start_deg, end_deg) = match (rises.as_slice(), sinks.as_slice()) {
            ([r], [s]) if r < s => (*r, *s),
            ([r], [s]) => {
                return Err(Error::Stitch(StitchError::new(
                    "feed",
                    format!(
                        "the feed dog's tooth is above the plate from φ_c = {r:.2}° through the needle's BDC to {s:.2}°; \
                     the transport must lie inside one cyclogram cycle (φ_c = 0 is the needle BDC): change the dog's phase"
                    ),
                )));
            }
            ([], []) => {
                return Err(StitchError::new(
                    "feed",
                    "the feed dog's tooth never rises above the plate top (z > 0 in the stitch frame); \
                     raise the dog or check the stitch frame",
                )
                .into());
            }
            _ => {
                return Err(Error::Stitch(StitchError::new(
                    "feed",
                    format!(
                        "the feed dog's tooth rises above the plate {} times in a cycle; it must rise once",
                        rises.len()
                    ),
                )));
            }
        };
        let (y_s, y_e) = (dog.at(start_deg).y, dog.at(end_deg).y);
        let travel = y_e - y_s;
        if travel.is_nan() || travel <= 1e-9 {
            return Err(Error::Stitch(StitchError::new(
                "feed",
                format!(
                    "while above the plate the feed dog's tooth moves {travel:.4} mm along the seam; it must move \
                 the material forward (+y of the stitch frame)"
                ),
            )));
        }
        let warning = ((travel - t_mm).abs() > 0.01 * t_mm).then(|| {
            format!(
                "feed: the feed dog's tooth travels {travel:.3} mm while above the plate but the stitch length is \
                 t = {t_mm} mm; the material is taken to move t (the dog's stroke and t disagree)"
            )
        });
        Ok(Feed {
            t_mm,
            start_deg,
            duration_deg: end_deg - start_deg,
            dog: Some((dog.clone(), y_s, t_mm / travel)),
            warning,
            sin_half_tr: (0.5 * (end_deg - start_deg)).to_radians().sin(),
        })
    }

    /// End of the transport φ_s + φ_tr, deg.
    pub fn end_deg(&self) -> f64 {
        self.start_deg + self.duration_deg
    }

    /// Feed-dog amplitude T_d = t / sin(φ_tr/2), mm (R1).
    pub fn t_d(&self) -> f64 {
        self.t_mm / self.sin_half_tr
    }

    /// T(φ_c), mm, for φ_c in [0°, 360°) of this cycle: 0 before the
    /// transport, t after it (R1).
    pub fn at(&self, phi_c: f64) -> f64 {
        if phi_c <= self.start_deg {
            return 0.0;
        }
        if phi_c >= self.end_deg() {
            return self.t_mm;
        }
        if let Some((dog, y_s, scale)) = &self.dog {
            return scale * (dog.at(phi_c).y - y_s);
        }
        let phi_mid = self.start_deg + 0.5 * self.duration_deg;
        0.5 * self.t_d() * ((phi_c - phi_mid).to_radians().sin() + self.sin_half_tr)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_relative_eq;

    fn altin() -> Feed {
        Feed::new(
            &FeedLaw::Harmonic {
                start_deg: 134.0,
                duration_deg: 100.0,
            },
            2.8,
        )
        .unwrap()
    }

    #[test]
    fn endpoints_total_and_amplitude() {
        let f = altin();
        // Seed 004 / docs §4.2: T_d = 2.8 / sin 50° = 3.655 mm.
        assert_relative_eq!(f.t_d(), 3.655, epsilon = 5e-4);
        assert_eq!(f.at(0.0), 0.0);
        assert_eq!(f.at(134.0), 0.0);
        assert_eq!(f.at(234.0), 2.8);
        assert_eq!(f.at(359.0), 2.8);
        // Continuous at both ends of the transport.
        assert!(f.at(134.0 + 1e-9).abs() < 1e-9);
        assert!((f.at(234.0 - 1e-9) - 2.8).abs() < 1e-9);
        // Half the stitch at mid-transport (the harmonic is odd about φ_mid).
        assert_relative_eq!(f.at(184.0), 1.4, epsilon = 1e-12);
        // Monotonic during the transport.
        let mut prev = 0.0;
        for k in 0..=1000 {
            let v = f.at(134.0 + 0.1 * k as f64);
            assert!(v >= prev - 1e-15);
            prev = v;
        }
    }

    #[test]
    fn bad_feeds_are_errors() {
        let h = |s, d| FeedLaw::Harmonic {
            start_deg: s,
            duration_deg: d,
        };
        assert!(Feed::new(&h(134.0, 100.0), 0.0).is_err());
        assert!(
            Feed::new(&h(300.0, 100.0), 2.8)
                .unwrap_err()
                .to_string()
                .contains("inside the cyclogram")
        );
        assert!(Feed::new(&h(0.0, 360.0), 2.8).is_err());
        assert!(Feed::new(&h(f64::NAN, 100.0), 2.8).is_err());
    }

    /// A tooth on a circle in the yz-plane, top at φ_c = `top`, above the
    /// plate for 100° (z0 = −r cos 50°).
    fn dog(top: f64, r: f64) -> FeedLaw {
        let pts: Vec<crate::geometry::V3<f64>> = (0..36000)
            .map(|k| {
                let th = (k as f64 * 0.01 - top).to_radians();
                crate::geometry::V3::new(0.0, r * th.sin(), r * (th.cos() - 50f64.to_radians().cos()))
            })
            .collect();
        FeedLaw::Point {
            dog: Motion::Table {
                start_deg: 0.0,
                step_deg: 0.01,
                points: pts.into(),
                slopes: None,
            },
        }
    }

    #[test]
    fn a_tooth_point_feeds_while_above_the_plate() {
        let t = 2.0 * 1.5 * 50f64.to_radians().sin();
        let f = Feed::new(&dog(184.0, 1.5), t).unwrap();
        assert_relative_eq!(f.start_deg, 134.0, epsilon = 1e-6);
        assert_relative_eq!(f.duration_deg, 100.0, epsilon = 1e-6);
        assert!(f.warning.is_none());
        let h = Feed::new(
            &FeedLaw::Harmonic {
                start_deg: 134.0,
                duration_deg: 100.0,
            },
            t,
        )
        .unwrap();
        for phi in [100.0, 134.0, 150.0, 184.0, 200.5, 234.0, 300.0] {
            assert_relative_eq!(f.at(phi), h.at(phi), epsilon = 1e-6);
        }
        // Through the needle's BDC (φ_c = 0): refused.
        let e = Feed::new(&dog(10.0, 1.5), t).unwrap_err().to_string();
        assert!(e.contains("through the needle's BDC"), "{e}");
        // A stroke 25 % longer than t is reported.
        assert!(
            Feed::new(&dog(184.0, 1.5), 0.8 * t)
                .unwrap()
                .warning
                .unwrap()
                .contains("disagree")
        );
    }
}
