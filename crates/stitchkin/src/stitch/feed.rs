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

use crate::Error;

use super::spec::FeedLaw;

/// The transport of one cycle, resolved to numbers.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Feed {
    /// Stitch length t: the material's travel per cycle, mm.
    pub t_mm: f64,
    /// φ_s: start of the transport, φ_c deg.
    pub start_deg: f64,
    /// φ_tr: duration of the transport, deg.
    pub duration_deg: f64,
}

impl Feed {
    /// The feed of `law` for stitch length `t_mm`. The transport must lie
    /// inside one cyclogram cycle (it never straddles φ_c = 0, §2).
    pub fn new(law: &FeedLaw, t_mm: f64) -> Result<Feed, Error> {
        let FeedLaw::Harmonic { start_deg, duration_deg } = *law;
        if !(t_mm.is_finite() && t_mm > 0.0) {
            return Err(Error::Stitch(format!("feed: the stitch length t = {t_mm} mm is not positive; give t > 0")));
        }
        if !(duration_deg.is_finite() && duration_deg > 0.0 && duration_deg < 360.0) {
            return Err(Error::Stitch(format!(
                "feed: the transport duration φ_tr = {duration_deg}° is out of range; give 0° < φ_tr < 360° \
                 (seed 004: 100°)"
            )));
        }
        if !(start_deg.is_finite() && start_deg >= 0.0 && start_deg + duration_deg <= 360.0) {
            return Err(Error::Stitch(format!(
                "feed: the transport [{start_deg}°, {}°] must lie inside the cyclogram cycle [0°, 360°] \
                 (φ_c = 0 is the needle BDC); move start_deg",
                start_deg + duration_deg
            )));
        }
        Ok(Feed { t_mm, start_deg, duration_deg })
    }

    /// End of the transport φ_s + φ_tr, deg.
    pub fn end_deg(&self) -> f64 {
        self.start_deg + self.duration_deg
    }

    /// Feed-dog amplitude T_d = t / sin(φ_tr/2), mm (R1).
    pub fn t_d(&self) -> f64 {
        self.t_mm / (0.5 * self.duration_deg).to_radians().sin()
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
        let phi_mid = self.start_deg + 0.5 * self.duration_deg;
        let half_tr = (0.5 * self.duration_deg).to_radians();
        0.5 * self.t_d() * ((phi_c - phi_mid).to_radians().sin() + half_tr.sin())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_relative_eq;

    fn altin() -> Feed {
        Feed::new(&FeedLaw::Harmonic { start_deg: 134.0, duration_deg: 100.0 }, 2.8).unwrap()
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
        let h = |s, d| FeedLaw::Harmonic { start_deg: s, duration_deg: d };
        assert!(Feed::new(&h(134.0, 100.0), 0.0).is_err());
        assert!(Feed::new(&h(300.0, 100.0), 2.8).unwrap_err().to_string().contains("inside the cyclogram"));
        assert!(Feed::new(&h(0.0, 360.0), 2.8).is_err());
        assert!(Feed::new(&h(f64::NAN, 100.0), 2.8).is_err());
    }
}
