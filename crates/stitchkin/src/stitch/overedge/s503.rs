//! Stitch 503, the two-thread overedge: the needle thread whose loops are
//! drawn to the material edge (contour 3) and the looper thread that a
//! spreader carries over the edge (contour 10)
//! (`docs/stitch-formation.md` §4.5, §4.6, §5.5).
//!
//! Needle thread (split at the eye N, anchor H_{c−1}^t): N1 and N2a–N2c as
//! in §5.1 ([`NeedleThread`]), then
//!
//! | piece | φ_c | η_N |
//! |---|---|---|
//! | N2d the dropped loop drawn to the edge | [φ4, φ5) | head(φ) + l_m + 2·W(H_c^b, B_c(φ)) + l_m + t |
//! | N3a, N3b locked | [φ5, 360) | head(φ) |
//!
//! with head(φ) the N3 expression of §5.1 ([`NeedleThread::head`]) and B_c
//! the loop's bight, drawn along W from the looper's lowest point at φ4 to
//! E'_c = (x_e, y_c, e·m) at φ5 (§4.6). The lock at φ5 cuts
//! t + 2·l_m + 2·(a_e + e·m), contour 3.
//!
//! Looper thread (split at the lower-looper eye LE, anchor H̄_c^t):
//!
//! | piece | φ_c | η |
//! |---|---|---|
//! | S1 | [0, φ_SC) | W(LE, H̄_c^t) |
//! | S2 the spreader holds the thread | [φ_SC, φ3) | W(LE, Q_S) + W(Q_S, H̄_c^t) |
//! | S3a needle c+1 in the spreader's triangle | [φ3, φ_SD) | W(LE, Q_S) + W(Q_S, G) + W(G, H̄_c^t) |
//! | S3b the spreader has let go | [φ_SD, φ4) | W(LE, G) + W(G, H̄_c^t) |
//! | S4 the dropped needle loop draws the thread | [φ4, φ5) | W(LE, G) + W(G, B_c(φ)) + W(B_c(φ), H̄_c^t) |
//! | S5 locked | [φ5, 360) | W(LE, H̄_{c+1}^t) |
//!
//! The lock at φ5 cuts a_e + l + 2·(1 − e)·m, contour 10.

use crate::Error;
use crate::geometry::V3;

use super::{EdgeSeam, HOOK_OFFSET_WARN_MM, inside_scan};
use crate::stitch::material::WPath;
use crate::stitch::needle_thread::{NeedlePiece, NeedleThread, Side, before, piece_at};
use crate::stitch::spec::{EventKind, Motion, StitchSpec, polyline_at};

/// Piece of the 503 needle thread's contour (§5.5).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum NeedlePiece503 {
    /// N1, N2a–N2c before the drop, N3a/N3b after the lock: as in §5.1.
    AsIn51(NeedlePiece),
    /// N2d: the dropped loop is drawn to the edge.
    N2d,
}

impl NeedlePiece503 {
    pub fn id(self) -> &'static str {
        match self {
            NeedlePiece503::AsIn51(p) => p.id(),
            NeedlePiece503::N2d => "N2d",
        }
    }
}

/// Piece of the 503 looper thread's contour (§5.5).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum LooperPiece {
    S1,
    S2,
    S3a,
    S3b,
    S4,
    S5,
}

impl LooperPiece {
    pub fn id(self) -> &'static str {
        match self {
            LooperPiece::S1 => "S1",
            LooperPiece::S2 => "S2",
            LooperPiece::S3a => "S3a",
            LooperPiece::S3b => "S3b",
            LooperPiece::S4 => "S4",
            LooperPiece::S5 => "S5",
        }
    }
}

/// The two threads of stitch 503.
#[derive(Debug, Clone)]
pub struct Overedge503 {
    /// The material points and W.
    pub seam: EdgeSeam,
    /// The needle thread up to the drop (§5.1).
    pub needle: NeedleThread,
    /// φ3 (stab), φ_SD (the spreader lets go), φ4 (the needle loop drops),
    /// φ5 (drawn in: the lock of both threads), deg.
    pub phi_stab: f64,
    pub phi_release: f64,
    pub phi_drop: f64,
    pub phi_draw_in: f64,
    /// φ_SC: the spreader picks the looper thread (closest approach, §4.5), deg.
    pub phi_pick: f64,
    /// Distance of the spreader's reference point from the thread at φ_SC, mm.
    pub hook_offset_mm: f64,
    /// B_c(φ4): the looper's lowest point under the loop when it drops.
    pub bight_start: V3<f64>,
    /// Validity warnings found while building.
    pub warnings: Vec<String>,
    /// Q_S − S: the catching point, fixed to the spreader.
    qs_off: V3<f64>,
    /// W(B_c(φ4), E'_c): the path along which the loop's bight is drawn (§4.6).
    bight_path: WPath,
    lower_eye: Motion,
    spreader: Motion,
}

impl Overedge503 {
    /// The threads of `spec` (stitch 503) with needle 1 `needle` (its
    /// contour up to the drop).
    pub fn new(spec: &StitchSpec, needle: &NeedleThread) -> Result<Overedge503, Error> {
        let seam = EdgeSeam::new(spec, needle)?;
        let Some(spreader) = spec.spreader.as_ref() else {
            return Err(seam.err("the spreader is missing; give [stitch.spreader] (§5.5)".into()));
        };
        let mo = spec.moments;
        let (phi_stab, phi_release, phi_draw_in) = (mo.stab_deg, mo.upper_release_deg, mo.draw_in_deg);
        let phi_drop = needle.phi_drop;
        seam.check_moments(
            phi_stab,
            ("spreader_release φ_SD", phi_release),
            (&needle.name, phi_drop),
            phi_draw_in,
        )?;
        let lower_eye = spec.the_looper()?.eye.clone();
        let spreader_point = spreader.eye.clone();

        // No looper eye or spreader point inside the material (§4.3).
        for phi in inside_scan() {
            seam.check_outside("the lower looper eye LE", &lower_eye.at(phi), phi)?;
            seam.check_outside("the spreader", &spreader_point.at(phi), phi)?;
        }

        // Pick-up φ_SC (§4.5): closest approach of the spreader to the
        // looper thread W(LE, H̄_c^t).
        let pick = seam.pick_up(
            &spreader_point,
            spreader.pick_window_deg,
            "the looper thread LE → H̄_c^t",
            |phi| (lower_eye.at(phi), seam.ht(0, phi)),
        )?;
        let (phi_pick, hook) = (pick.phi, pick.hook_offset_mm);
        if phi_pick >= phi_stab {
            return Err(seam.err(format!(
                "the spreader picks the looper thread at φ_SC = {phi_pick:.2}°, not before the stab φ3 = \
                 {phi_stab}°; move the pick-up window or the stab"
            )));
        }
        let mut warnings = Vec::new();
        if hook > HOOK_OFFSET_WARN_MM {
            warnings.push(format!(
                "spreader: it passes {hook:.3} mm from the looper thread at the pick-up φ_SC = {phi_pick:.2}° (hook \
                 offset > {HOOK_OFFSET_WARN_MM} mm): the stand-in motions may not really cross the thread (§4.5)"
            ));
        }
        let q_s = |phi: f64| spreader_point.at(phi) + pick.offset;
        for phi in inside_scan().filter(|&phi| phi_pick <= phi && phi <= phi_release) {
            seam.check_outside("the spreader's hook Q_S (the looper thread)", &q_s(phi), phi)?;
        }
        // At the stab the needle enters the triangle LE–Q_S–H̄_c^t from
        // above: the spreader must hold the thread above the material and
        // past the needle line (§5.5).
        let q3 = q_s(phi_stab);
        if q3.z <= seam.m || q3.x >= seam.line.x_j {
            warnings.push(format!(
                "spreader: at the stab φ3 = {phi_stab}° its hook Q_S is at ({:.3}, {:.3}, {:.3}), not above the \
                 material (z > {}) and past the needle line (x < {:.3}): the needle cannot enter its triangle (§5.5)",
                q3.x, q3.y, q3.z, seam.m, seam.line.x_j
            ));
        }
        // The dropped loop's bight is drawn along W from the looper's lowest
        // point to E'_c (§4.6, §5.5).
        let bight_start = needle.loop_bottom(phi_drop);
        let bight_end = seam.e_pt(0, phi_draw_in);
        let bight_path = seam.path(&bight_start, &bight_end, phi_drop, "the needle loop's bight B_c → E'_c")?;
        Ok(Overedge503 {
            phi_stab,
            phi_release,
            phi_drop,
            phi_draw_in,
            phi_pick,
            hook_offset_mm: hook,
            bight_start,
            warnings,
            qs_off: pick.offset,
            bight_path,
            lower_eye,
            spreader: spreader_point,
            needle: needle.clone(),
            seam,
        })
    }

    /// LE(φ): the lower looper's eye, the looper thread's split point.
    pub fn le(&self, phi: f64) -> V3<f64> {
        self.lower_eye.at(phi)
    }

    /// Q_S(φ): the spreader's catching point (§4.5).
    pub fn q_s(&self, phi: f64) -> V3<f64> {
        self.spreader.at(phi) + self.qs_off
    }

    /// B_c(φ): the needle loop's bight, drawn along W from the looper's
    /// lowest point at φ4 to E'_c at φ5, uniformly in φ (§4.6, §5.5).
    pub fn b_c(&self, phi: f64) -> V3<f64> {
        let lam = ((phi - self.phi_drop) / (self.phi_draw_in - self.phi_drop)).clamp(0.0, 1.0);
        polyline_at(self.bight_path.nodes(), lam)
    }

    pub fn needle_piece(&self, phi: f64, side: Side) -> NeedlePiece503 {
        if before(phi, self.phi_drop, side) || !before(phi, self.phi_draw_in, side) {
            NeedlePiece503::AsIn51(self.needle.piece(phi, side))
        } else {
            NeedlePiece503::N2d
        }
    }

    pub fn looper_piece(&self, phi: f64, side: Side) -> LooperPiece {
        use LooperPiece::*;
        let ends = [
            (self.phi_pick, S1),
            (self.phi_stab, S2),
            (self.phi_release, S3a),
            (self.phi_drop, S3b),
            (self.phi_draw_in, S4),
        ];
        piece_at(phi, side, &ends, S5)
    }

    /// η_N of the needle thread: from the eye to the anchor H_{c−1}^t, mm
    /// (§5.1, §5.5).
    pub fn eta_needle(&self, phi: f64, side: Side) -> Result<f64, Error> {
        match self.needle_piece(phi, side) {
            NeedlePiece503::AsIn51(_) => Ok(self.needle.eta(phi, side)),
            NeedlePiece503::N2d => {
                // Down hole c, both legs of the loop to its bight, up hole c,
                // along the top face to hole c−1.
                let (l_m, t) = (self.needle.line.l_m, self.seam.t);
                let (_, h_b) = self.needle.hole_c(phi);
                let legs = self
                    .seam
                    .w(&h_b, &self.b_c(phi), phi, "the needle loop's legs H_c^b → B_c")?;
                Ok(self.needle.head(phi) + l_m + 2.0 * legs + l_m + t)
            }
        }
    }

    /// η of the looper thread: from the lower-looper eye LE to the anchor
    /// H̄_c^t, mm (§5.5).
    pub fn eta_looper(&self, phi: f64, side: Side) -> Result<f64, Error> {
        let le = self.le(phi);
        self.seam.check_outside("the lower looper eye LE", &le, phi)?;
        let w = |p: &V3<f64>, q: &V3<f64>| self.seam.w(p, q, phi, "the looper thread");
        let h_t = self.seam.ht(0, phi);
        Ok(match self.looper_piece(phi, side) {
            LooperPiece::S1 => w(&le, &h_t)?,
            LooperPiece::S2 => {
                let q = self.q_s(phi);
                w(&le, &q)? + w(&q, &h_t)?
            }
            LooperPiece::S3a => {
                let (q, g) = (self.q_s(phi), self.seam.g(phi));
                w(&le, &q)? + w(&q, &g)? + w(&g, &h_t)?
            }
            LooperPiece::S3b => {
                let g = self.seam.g(phi);
                w(&le, &g)? + w(&g, &h_t)?
            }
            LooperPiece::S4 => {
                let (g, b) = (self.seam.g(phi), self.b_c(phi));
                w(&le, &g)? + w(&g, &b)? + w(&b, &h_t)?
            }
            // Locked: the anchor is H̄_{c+1}^t.
            LooperPiece::S5 => w(&le, &self.seam.ht(1, phi))?,
        })
    }

    /// The needle thread cut at the lock φ5, from the final nodes: hole c−1
    /// top ← hole c top (t), down hole c (l_m), along the bottom face to K_c
    /// (a_e) and up the edge face to E'_c (e·m) and back, up hole c (l_m) —
    /// contour 3 (§5.5, §7).
    pub fn needle_cut(&self) -> f64 {
        let phi = self.phi_draw_in;
        let (h_t, h_b) = self.needle.hole_c(phi);
        let h_t_prev = h_t + V3::new(0.0, self.seam.t, 0.0);
        let k = self.seam.k_pt(0, phi);
        let leg = (k - h_b).norm() + (self.seam.e_pt(0, phi) - k).norm();
        (h_t - h_b).norm() + 2.0 * leg + (h_b - h_t).norm() + (h_t_prev - h_t).norm()
    }

    /// The looper thread cut at the lock φ5: contour 10 (§5.5, §7).
    pub fn looper_cut(&self) -> f64 {
        self.seam.top_face_cut(self.phi_draw_in)
    }

    /// The needle thread's moments in φ_c order (§5.6): those of §5.1, with
    /// the drop a jump and the lock at φ5.
    pub fn needle_events(&self) -> Vec<(String, f64, EventKind)> {
        let mut ev: Vec<_> = self
            .needle
            .events()
            .into_iter()
            .map(|e| match e.2 {
                EventKind::Lock => (
                    "drop (φ4): the loop slides onto the looper thread".to_string(),
                    e.1,
                    EventKind::Jump,
                ),
                _ => e,
            })
            .collect();
        ev.push((
            "drawn to the edge = lock (φ5)".to_string(),
            self.phi_draw_in,
            EventKind::Lock,
        ));
        ev.sort_by(|a, b| a.1.total_cmp(&b.1));
        ev
    }

    /// The looper thread's moments in φ_c order (§5.6).
    pub fn looper_events(&self) -> Vec<(String, f64, EventKind)> {
        let mut ev = vec![
            (
                "spreader picks the looper thread (φ_SC, derived)".to_string(),
                self.phi_pick,
                EventKind::Cont,
            ),
            ("transport start".to_string(), self.seam.feed.start_deg, EventKind::Cont),
            ("transport end".to_string(), self.seam.feed.end_deg(), EventKind::Cont),
            (
                "stab: needle enters the spreader's triangle (φ3)".to_string(),
                self.phi_stab,
                EventKind::Jump,
            ),
            (
                "spreader releases the looper thread (φ_SD)".to_string(),
                self.phi_release,
                EventKind::Jump,
            ),
            (
                "needle loop drops onto the looper thread (φ4)".to_string(),
                self.phi_drop,
                EventKind::Jump,
            ),
            ("drawn in = lock (φ5)".to_string(), self.phi_draw_in, EventKind::Lock),
        ];
        ev.sort_by(|a, b| a.1.total_cmp(&b.1));
        ev
    }

    /// Derived and used moments (name, φ_c deg): the needle's (§5.1), with
    /// its lock at φ5, and the spreader's pick-up.
    pub fn moments(&self) -> Vec<(String, f64)> {
        let n = &self.needle.name;
        let mut out: Vec<(String, f64)> = self
            .needle
            .moments()
            .into_iter()
            .map(|(name, phi)| (name.replace("drop = lock (used)", "drop (used)"), phi))
            .collect();
        out.push((format!("{n}: drawn to the edge = lock (φ5)"), self.phi_draw_in));
        out.push(("spreader picks the looper thread (φ_SC)".into(), self.phi_pick));
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::stitch::feed::Feed;
    fn altin503() -> StitchSpec {
        crate::stitch::reference::altin503(2.5, 2.8)
    }
    use approx::assert_relative_eq;

    fn altin() -> Overedge503 {
        let s = altin503();
        let feed = Feed::new(&s.feed, s.t_mm).unwrap();
        let n = NeedleThread::new(&s.needles[0], s.looper.as_ref().unwrap(), s.m_mm, s.tilt_deg, feed).unwrap();
        Overedge503::new(&s, &n).unwrap()
    }

    #[test]
    fn the_spreader_picks_the_thread_next_to_the_looper_and_holds_it_over_the_needle() {
        let o = altin();
        // README: the spreader picks the looper thread at 143.70° (hook offset 0.304 mm).
        assert_relative_eq!(o.phi_pick, 143.7, epsilon = 1e-9);
        assert!((o.hook_offset_mm - 0.304).abs() < 5e-4, "{}", o.hook_offset_mm);
        assert!(o.warnings.is_empty(), "{:?}", o.warnings);
        // The catching point lies on the thread at φ_SC: S2 starts continuously.
        let (l, r) = (
            o.eta_looper(o.phi_pick, Side::Left).unwrap(),
            o.eta_looper(o.phi_pick, Side::Right).unwrap(),
        );
        assert!((r - l).abs() < 1e-9, "{}", r - l);
        // At the stab the hook is above the material and past the needle line.
        let q = o.q_s(o.phi_stab);
        assert!(q.z > o.seam.m && q.x < 0.0, "{q:?}");
    }

    #[test]
    fn the_bight_is_drawn_from_the_looper_bottom_to_the_edge() {
        let o = altin();
        let d_l = 4.0 + 2.5 + 1.0;
        assert_relative_eq!(o.b_c(o.phi_drop), o.bight_start, epsilon = 1e-12);
        assert_relative_eq!(o.bight_start.z, -d_l);
        assert_relative_eq!(o.bight_start.x, o.needle.carry.x_loop(o.phi_drop), epsilon = 1e-15);
        let e_c = o.seam.e_pt(0, o.phi_draw_in);
        assert_relative_eq!(o.b_c(o.phi_draw_in), e_c, epsilon = 1e-12);
        // On the way it goes round the bottom corner line (below the plate, then the edge face).
        let mid = o.b_c(0.5 * (o.phi_drop + o.phi_draw_in));
        assert!(mid.x <= o.seam.slab.x_edge + 1e-12 && !o.seam.slab.inside(&mid));
        // W(H_c^b, E'_c) = a_e + e·m at equal y: the cut is exact.
        let (_, h_b) = o.needle.hole_c(o.phi_draw_in);
        assert_relative_eq!(o.seam.slab.w(&h_b, &e_c).unwrap(), 4.0 + 1.25, epsilon = 1e-12);
    }

    #[test]
    fn cuts_are_contours_3_and_10() {
        let o = altin();
        let l_m = 2.5 / 20f64.to_radians().cos();
        assert_relative_eq!(o.needle_cut(), 2.8 + 2.0 * l_m + 2.0 * (4.0 + 1.25), epsilon = 1e-12);
        assert_relative_eq!(o.looper_cut(), 4.0 + 4f64.hypot(2.8) + 2.0 * 0.5 * 2.5, epsilon = 1e-12);
    }

    #[test]
    fn jumps_have_the_signs_of_section_5_5() {
        let o = altin();
        let jn = |phi| o.eta_needle(phi, Side::Right).unwrap() - o.eta_needle(phi, Side::Left).unwrap();
        let jl = |phi| o.eta_looper(phi, Side::Right).unwrap() - o.eta_looper(phi, Side::Left).unwrap();
        // Needle: the wrap around the half-cylinder is lost at the drop,
        // 2·W(H_c^b, B_c(φ4)) − Λ(φ4⁻) ≤ 0; the lock cuts contour 3 exactly.
        let (_, h_b) = o.needle.hole_c(o.phi_drop);
        let want = 2.0 * (o.bight_start - h_b).norm() - o.needle.released();
        assert_relative_eq!(jn(o.phi_drop), want, epsilon = 1e-12);
        assert!(want < 0.0);
        assert_relative_eq!(jn(o.phi_draw_in), -o.needle_cut(), epsilon = 1e-12);
        // Looper: stab ≥ 0, release ≤ 0, drop ≥ 0 (triangle inequalities),
        // lock = −contour 10 + snap, snap = l + (1−e)m − W(H̄_{c+1}^t, E_c) ≥ 0.
        assert!(jl(o.phi_stab) > 0.0 && jl(o.phi_release) < 0.0 && jl(o.phi_drop) > 0.0);
        let phi5 = o.phi_draw_in;
        let snap = jl(phi5) + o.looper_cut();
        let geodesic = o.seam.slab.w(&o.seam.ht(1, phi5), &o.seam.e_pt(0, phi5)).unwrap();
        assert_relative_eq!(snap, 4f64.hypot(2.8) + 1.25 - geodesic, epsilon = 1e-9);
    }

    #[test]
    fn pieces_in_order() {
        let o = altin();
        let ids = |phi: f64, side| (o.needle_piece(phi, side).id(), o.looper_piece(phi, side).id());
        assert_eq!(ids(300.0, Side::Left), ("N2c", "S3b"));
        assert_eq!(ids(300.0, Side::Right), ("N2d", "S4"));
        assert_eq!(ids(330.0, Side::Left), ("N2d", "S4"));
        assert_eq!(ids(330.0, Side::Right), ("N3b", "S5"));
        assert_eq!(ids(280.0, Side::Right).1, "S3a");
        assert_eq!(ids(10.0, Side::Right), ("N1", "S1"));
    }

    #[test]
    fn missing_spreader_and_bad_moments_are_errors() {
        let mut s = altin503();
        let feed = Feed::new(&s.feed, s.t_mm).unwrap();
        let n = NeedleThread::new(&s.needles[0], s.looper.as_ref().unwrap(), s.m_mm, s.tilt_deg, feed).unwrap();
        s.moments.upper_release_deg = 310.0; // after the drop
        let err = Overedge503::new(&s, &n).unwrap_err().to_string();
        assert!(
            err.contains("stitch 503") && err.contains("spreader_release φ_SD") && err.contains("ordered"),
            "{err}"
        );
        s.spreader = None;
        let err = Overedge503::new(&s, &n).unwrap_err().to_string();
        assert!(err.contains("[stitch.spreader]"), "{err}");
    }
}
