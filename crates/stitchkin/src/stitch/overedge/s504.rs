//! Stitch 504: the lower- and upper-looper threads around the material edge
//! (`docs/stitch-formation.md` §4.5, §4.6, §5.3, §5.4), on the seam of
//! [`super::EdgeSeam`].
//!
//! Lower thread (contour 13, anchor H̄_{c−1}^b, tail 2em + a_e):
//!
//! | piece | φ_c | η |
//! |---|---|---|
//! | L1 | [0, φ_UC) | W(LE, K_{c−1}) + tail |
//! | L2 | [φ_UC, φ_UD) | W(LE, Q_U) + W(Q_U, K_{c−1}) + tail |
//! | L3 | [φ_UD, φ4) | W(LE, E_c(φ)) + W(E_c(φ), K_{c−1}) + tail |
//! | L4 | [φ4, φ5) | W(LE, E_c) + W(E_c, Q_N(φ)) + W(Q_N(φ), K_{c−1}) + tail |
//! | L5 | [φ5, 360) | W(LE, K_c) + tail |
//!
//! Upper thread (contour 10, anchor H̄_c^t):
//!
//! | piece | φ_c | η |
//! |---|---|---|
//! | U1 | [0, φ3) | W(UE, H̄_c^t) |
//! | U2 | [φ3, φ_UD) | W(UE, G) + W(G, H̄_c^t) |
//! | U3 | [φ_UD, φ5) | W(UE, G) + W(G, E_c(φ)) + W(E_c(φ), H̄_c^t) |
//! | U4 | [φ5, 360) | W(UE, H̄_{c+1}^t) |

use super::{EdgeSeam, HOOK_OFFSET_WARN_MM, inside_scan};
use crate::Error;
use crate::error::StitchError;
use crate::geometry::V3;
use crate::stitch::material::WPath;
use crate::stitch::needle_thread::{NeedleThread, Side, piece_at};
use crate::stitch::spec::{EventKind, Motion, StitchSpec, polyline_at};

/// Piece of the lower-looper thread's contour (§5.3).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum LowerPiece {
    L1,
    L2,
    L3,
    L4,
    L5,
}

/// Piece of the upper-looper thread's contour (§5.4).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum UpperPiece {
    U1,
    U2,
    U3,
    U4,
}

impl LowerPiece {
    pub fn id(self) -> &'static str {
        match self {
            LowerPiece::L1 => "L1",
            LowerPiece::L2 => "L2",
            LowerPiece::L3 => "L3",
            LowerPiece::L4 => "L4",
            LowerPiece::L5 => "L5",
        }
    }
}

impl UpperPiece {
    pub fn id(self) -> &'static str {
        match self {
            UpperPiece::U1 => "U1",
            UpperPiece::U2 => "U2",
            UpperPiece::U3 => "U3",
            UpperPiece::U4 => "U4",
        }
    }
}

/// The two looper threads of stitch 504.
#[derive(Debug, Clone)]
pub struct Overedge {
    /// The material points and W.
    pub seam: EdgeSeam,
    /// φ3 (stab), φ_UD (upper looper releases), φ4 (needle loop drops), φ5
    /// (drawn in: the lock), deg.
    pub phi_stab: f64,
    pub phi_release: f64,
    pub phi_drop: f64,
    pub phi_draw_in: f64,
    /// φ_UC: the upper looper picks the lower thread (closest approach, §4.5), deg.
    pub phi_pick: f64,
    /// Distance of the upper looper's eye from the thread at φ_UC, mm.
    pub hook_offset_mm: f64,
    /// Validity warnings found while building.
    pub warnings: Vec<String>,
    /// Q_U − UE: the catching point, fixed to the upper looper.
    qu_off: V3<f64>,
    /// W(Q_U(φ_UD), E_c): the path on which the released bight settles (§4.6).
    settle: WPath,
    lower_eye: Motion,
    upper_eye: Motion,
}

impl Overedge {
    /// The looper threads of `spec` (stitch 504), around needle 1 `needle`.
    pub fn new(spec: &StitchSpec, needle: &NeedleThread) -> Result<Overedge, Error> {
        let stitch_err = |msg: String| Err(Error::Stitch(StitchError::new("stitch 504", msg)));
        let Some(upper) = spec.upper_looper.as_ref() else {
            return stitch_err("the upper looper is missing; give [stitch.upper_looper]".into());
        };
        let seam = EdgeSeam::new(spec, needle)?;
        let mo = spec.moments;
        let (phi_stab, phi_release, phi_draw_in) = (mo.stab_deg, mo.upper_release_deg, mo.draw_in_deg);
        let phi_drop = needle.phi_drop;
        seam.check_moments(
            phi_stab,
            ("upper_release φ_UD", phi_release),
            (&needle.name, phi_drop),
            phi_draw_in,
        )?;
        let mut ov = Overedge {
            seam,
            phi_stab,
            phi_release,
            phi_drop,
            phi_draw_in,
            phi_pick: f64::NAN,
            hook_offset_mm: f64::NAN,
            warnings: Vec::new(),
            qu_off: V3::zeros(),
            settle: WPath::default(),
            lower_eye: spec.the_looper()?.eye.clone(),
            upper_eye: upper.eye.clone(),
        };
        let seam = &ov.seam;

        // No looper eye inside the material, anywhere in the cycle (§4.3).
        for phi in inside_scan() {
            seam.check_outside("the lower looper eye LE", &ov.lower_eye.at(phi), phi)?;
            seam.check_outside("the upper looper eye UE", &ov.upper_eye.at(phi), phi)?;
        }

        // Pick-up φ_UC (§4.5): closest approach of UE to the lower thread's
        // path W(LE, K_{c−1}).
        let pick = seam.pick_up(
            &ov.upper_eye,
            upper.pick_window_deg,
            "the lower thread LE → K_{c−1}",
            |phi| (ov.lower_eye.at(phi), seam.k_pt(-1, phi)),
        )?;
        let (phi_pick, hook) = (pick.phi, pick.hook_offset_mm);
        if phi_pick >= phi_release {
            return stitch_err(format!(
                "the upper looper picks the lower thread at φ_UC = {phi_pick:.2}°, not before it releases it \
                 (upper_release φ_UD = {phi_release}°); move the pick-up window or φ_UD"
            ));
        }
        ov.phi_pick = phi_pick;
        ov.hook_offset_mm = hook;
        ov.qu_off = pick.offset;
        if hook > HOOK_OFFSET_WARN_MM {
            ov.warnings.push(format!(
                "upper looper: its eye passes {hook:.3} mm from the lower thread at the pick-up φ_UC = \
                 {phi_pick:.2}° (hook offset > {HOOK_OFFSET_WARN_MM} mm): the stand-in motions may not really cross \
                 the thread (§4.5)"
            ));
        }
        for phi in inside_scan().filter(|&phi| phi_pick <= phi && phi <= phi_release) {
            ov.seam.check_outside(
                "the upper looper's hook Q_U (the lower thread's bight)",
                &ov.q_u(phi),
                phi,
            )?;
        }
        // The released bight settles along W to its final place E_c (§4.6).
        let from = ov.q_u(phi_release);
        let to = ov.seam.e_pt(0, phi_draw_in);
        ov.settle = ov.seam.path(&from, &to, phi_release, "the released bight Q_U → E_c")?;
        Ok(ov)
    }

    /// W(P, Q) (§4.3), with an error naming the thread and φ.
    fn w(&self, p: &V3<f64>, q: &V3<f64>, phi: f64, what: &str) -> Result<f64, Error> {
        self.seam.w(p, q, phi, what)
    }

    /// LE(φ): the lower looper's eye.
    pub fn le(&self, phi: f64) -> V3<f64> {
        self.lower_eye.at(phi)
    }

    /// UE(φ): the upper looper's eye.
    pub fn ue(&self, phi: f64) -> V3<f64> {
        self.upper_eye.at(phi)
    }

    /// Q_U(φ): the upper looper's catching point (§4.5).
    pub fn q_u(&self, phi: f64) -> V3<f64> {
        self.ue(phi) + self.qu_off
    }

    /// E_c(φ): the lower thread's new bight. On the upper looper until φ_UD,
    /// then along W to its final place E_c, uniformly in φ until φ5 (§4.6).
    pub fn e_c(&self, phi: f64) -> V3<f64> {
        if phi <= self.phi_release {
            return self.q_u(phi);
        }
        let lam = ((phi - self.phi_release) / (self.phi_draw_in - self.phi_release)).min(1.0);
        polyline_at(self.settle.nodes(), lam)
    }

    /// Q_N(φ) (§4.6): the dropped needle loop draws the lower thread from
    /// K_{c−1} to H̄_c^b on the bottom face, uniformly over [φ4, φ5].
    pub fn q_n(&self, phi: f64) -> V3<f64> {
        let mu = (phi - self.phi_drop) / (self.phi_draw_in - self.phi_drop);
        let (k, h) = (self.seam.k_pt(-1, phi), self.seam.hb(0, phi));
        k + (h - k) * mu
    }

    pub fn lower_piece(&self, phi: f64, side: Side) -> LowerPiece {
        use LowerPiece::*;
        let ends = [
            (self.phi_pick, L1),
            (self.phi_release, L2),
            (self.phi_drop, L3),
            (self.phi_draw_in, L4),
        ];
        piece_at(phi, side, &ends, L5)
    }

    pub fn upper_piece(&self, phi: f64, side: Side) -> UpperPiece {
        use UpperPiece::*;
        piece_at(
            phi,
            side,
            &[(self.phi_stab, U1), (self.phi_release, U2), (self.phi_draw_in, U3)],
            U4,
        )
    }

    /// η of the lower-looper thread: from its eye LE to the anchor
    /// H̄_{c−1}^b, mm (§5.3).
    pub fn eta_lower(&self, phi: f64, side: Side) -> Result<f64, Error> {
        let le = self.le(phi);
        self.seam.check_outside("the lower looper eye LE", &le, phi)?;
        let w = |p: &V3<f64>, q: &V3<f64>| self.w(p, q, phi, "the lower-looper thread");
        // K_{c−1} → E_{c−1} → K_{c−1} → H̄_{c−1}^b, in final position.
        let tail = 2.0 * self.seam.e * self.seam.m + self.seam.a_e;
        let k_prev = self.seam.k_pt(-1, phi);
        let body = match self.lower_piece(phi, side) {
            LowerPiece::L1 => w(&le, &k_prev)?,
            LowerPiece::L2 => {
                let q = self.q_u(phi);
                self.seam.check_outside("the upper looper's hook Q_U", &q, phi)?;
                w(&le, &q)? + w(&q, &k_prev)?
            }
            LowerPiece::L3 => {
                let ec = self.e_c(phi);
                w(&le, &ec)? + w(&ec, &k_prev)?
            }
            LowerPiece::L4 => {
                let (ec, qn) = (self.e_c(phi), self.q_n(phi));
                w(&le, &ec)? + w(&ec, &qn)? + w(&qn, &k_prev)?
            }
            // Locked: the anchor is H̄_c^b.
            LowerPiece::L5 => w(&le, &self.seam.k_pt(0, phi))?,
        };
        Ok(body + tail)
    }

    /// η of the upper-looper thread: from its eye UE to the anchor H̄_c^t,
    /// mm (§5.4).
    pub fn eta_upper(&self, phi: f64, side: Side) -> Result<f64, Error> {
        let ue = self.ue(phi);
        self.seam.check_outside("the upper looper eye UE", &ue, phi)?;
        let w = |p: &V3<f64>, q: &V3<f64>| self.w(p, q, phi, "the upper-looper thread");
        let h_t = self.seam.ht(0, phi);
        Ok(match self.upper_piece(phi, side) {
            UpperPiece::U1 => w(&ue, &h_t)?,
            UpperPiece::U2 => {
                let g = self.seam.g(phi);
                w(&ue, &g)? + w(&g, &h_t)?
            }
            UpperPiece::U3 => {
                let (g, ec) = (self.seam.g(phi), self.e_c(phi));
                w(&ue, &g)? + w(&g, &ec)? + w(&ec, &h_t)?
            }
            // Locked: the anchor is H̄_{c+1}^t.
            UpperPiece::U4 => w(&ue, &self.seam.ht(1, phi))?,
        })
    }

    /// The lower thread cut at the lock φ5, from the final nodes:
    /// H̄_c^b → K_{c−1} (l) → E_{c−1} → K_{c−1} (2em) → H̄_{c−1}^b (a_e) —
    /// contour 13 (§5.3, §7).
    pub fn lower_cut(&self) -> f64 {
        let phi = self.phi_draw_in;
        let k = self.seam.k_pt(-1, phi);
        (self.seam.hb(0, phi) - k).norm()
            + 2.0 * (k - self.seam.e_pt(-1, phi)).norm()
            + (k - self.seam.hb(-1, phi)).norm()
    }

    /// The upper thread cut at the lock φ5, from the final nodes:
    /// H̄_{c+1}^t → K'_c (l) → E_c → K'_c (2(1−e)m) → H̄_c^t (a_e) —
    /// contour 10 (§5.4, §7).
    pub fn upper_cut(&self) -> f64 {
        self.seam.top_face_cut(self.phi_draw_in)
    }

    /// The lower thread's moments in φ_c order (§5.6).
    pub fn lower_events(&self) -> Vec<(String, f64, EventKind)> {
        let mut ev = vec![
            ("transport start".to_string(), self.seam.feed.start_deg, EventKind::Cont),
            (
                "upper looper picks lower thread (φ_UC, derived)".to_string(),
                self.phi_pick,
                EventKind::Cont,
            ),
            ("transport end".to_string(), self.seam.feed.end_deg(), EventKind::Cont),
            (
                "upper looper releases bight (φ_UD)".to_string(),
                self.phi_release,
                EventKind::Cont,
            ),
            (
                "needle loop drops (φ4): draw-in starts".to_string(),
                self.phi_drop,
                EventKind::Cont,
            ),
            ("drawn in = lock (φ5)".to_string(), self.phi_draw_in, EventKind::Lock),
        ];
        ev.sort_by(|a, b| a.1.total_cmp(&b.1));
        ev
    }

    /// The upper thread's moments in φ_c order (§5.6).
    pub fn upper_events(&self) -> Vec<(String, f64, EventKind)> {
        let mut ev = vec![
            ("transport start".to_string(), self.seam.feed.start_deg, EventKind::Cont),
            ("transport end".to_string(), self.seam.feed.end_deg(), EventKind::Cont),
            (
                "stab: needle takes the upper thread (φ3)".to_string(),
                self.phi_stab,
                EventKind::Jump,
            ),
            (
                "lower bight joins the upper thread (φ_UD)".to_string(),
                self.phi_release,
                EventKind::Jump,
            ),
            ("lock (φ5)".to_string(), self.phi_draw_in, EventKind::Lock),
        ];
        ev.sort_by(|a, b| a.1.total_cmp(&b.1));
        ev
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::stitch::feed::Feed;
    fn altin504() -> StitchSpec {
        crate::stitch::reference::altin504(2.5, 2.8)
    }
    use approx::assert_relative_eq;

    fn altin() -> (Overedge, NeedleThread) {
        let s = altin504();
        let feed = Feed::new(&s.feed, s.t_mm).unwrap();
        let n = NeedleThread::new(&s.needles[0], s.looper.as_ref().unwrap(), s.m_mm, s.tilt_deg, feed).unwrap();
        (Overedge::new(&s, &n).unwrap(), n)
    }

    #[test]
    fn pick_up_is_the_closest_approach() {
        let (ov, _) = altin();
        // README: the upper looper picks the lower thread at 126.60° (hook offset 0.81 mm).
        assert_relative_eq!(ov.phi_pick, 126.6, epsilon = 1e-9);
        assert!((ov.hook_offset_mm - 0.81).abs() < 0.005, "{}", ov.hook_offset_mm);
        assert!(ov.warnings.is_empty());
        // The catching point lies on the lower thread at φ_UC: L2 starts continuously.
        let left = ov.eta_lower(ov.phi_pick, Side::Left).unwrap();
        let right = ov.eta_lower(ov.phi_pick, Side::Right).unwrap();
        assert!((right - left).abs() < 1e-9);
    }

    #[test]
    fn cuts_are_the_contour_formulas() {
        let (ov, _) = altin();
        let l = 4f64.hypot(2.8);
        assert_relative_eq!(ov.lower_cut(), 4.0 + l + 2.0 * 0.5 * 2.5, epsilon = 1e-12); // contour 13
        assert_relative_eq!(ov.upper_cut(), 4.0 + l + 2.0 * 0.5 * 2.5, epsilon = 1e-12); // contour 10
    }

    #[test]
    fn lock_jumps_and_snaps() {
        let (ov, _) = altin();
        let phi5 = ov.phi_draw_in;
        // Lower: the snap is small (the bight is in its final place at φ5;
        // W(LE, K_c) + em − W(LE, E_c) = 4.0e-5 mm in the reference) and ≥ 0.
        let jl = ov.eta_lower(phi5, Side::Right).unwrap() - ov.eta_lower(phi5, Side::Left).unwrap();
        assert_relative_eq!(jl, -11.382582250412547, epsilon = 1e-9);
        let snap = jl + ov.lower_cut();
        assert!((0.0..1e-4).contains(&snap), "{snap}");
        // Upper: jump −11.2 mm, snap = l + (1−e)m − W(H̄_{c+1}^t, E_c) = 0.183 mm (§5.4).
        let ju = ov.eta_upper(phi5, Side::Right).unwrap() - ov.eta_upper(phi5, Side::Left).unwrap();
        assert_relative_eq!(ju, -11.2, epsilon = 1e-6);
        let snap = ju + ov.upper_cut();
        let geodesic = ov.seam.slab.w(&ov.seam.ht(1, phi5), &ov.seam.e_pt(0, phi5)).unwrap();
        assert_relative_eq!(snap, 4f64.hypot(2.8) + 1.25 - geodesic, epsilon = 1e-9);
        assert!((snap - 0.183).abs() < 0.001);
    }

    #[test]
    fn nodes_settle_continuously() {
        let (ov, _) = altin();
        // E_c leaves Q_U at φ_UD and reaches its final place at φ5.
        assert_relative_eq!(ov.e_c(ov.phi_release + 1e-9), ov.q_u(ov.phi_release), epsilon = 1e-6);
        assert_relative_eq!(ov.e_c(ov.phi_draw_in), ov.seam.e_pt(0, ov.phi_draw_in), epsilon = 1e-12);
        // Q_N goes from K_{c−1} at φ4 to H̄_c^b at φ5.
        assert_relative_eq!(ov.q_n(ov.phi_drop), ov.seam.k_pt(-1, ov.phi_drop), epsilon = 1e-12);
        assert_relative_eq!(ov.q_n(ov.phi_draw_in), ov.seam.hb(0, ov.phi_draw_in), epsilon = 1e-12);
        // G: the material top while the point is in it, the point above.
        assert_eq!(ov.seam.g(0.0).z, 2.5);
        assert!(ov.seam.g(180.0).z > 2.5);
    }
}
