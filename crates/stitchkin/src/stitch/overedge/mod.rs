//! The seam both overedge stitches (503, 504) share: the material points of
//! cycle c, the thread around the edge W, and the pick-up of a thread by an
//! organ ([`EdgeSeam`]); the stitches themselves are [`s504`] (two looper
//! threads) and [`s503`] (needle and looper thread)
//! (`docs/stitch-formation.md` §4.5, §4.6, §5.3–§5.5).
//!
//! Material points of cycle c (they move with the feed T): hole j at
//! y_j = T − j·t (j = 0: hole c, −1: hole c−1, +1: hole c+1), its vertical
//! projections H̄_j^b = (x_1, y_j, 0) and H̄_j^t = (x_1, y_j, m), the edge
//! point E_j = (x_e, y_j, e·m) and the corners K_j = (x_e, y_j, 0),
//! K'_j = (x_e, y_j, m), with x_e = x_1 + a_e the edge. (x_1, y) are taken
//! from the needle line N0, so with the stitch frame's origin at N0 these are
//! the document's coordinates.

pub mod s503;
pub mod s504;

pub use s503::Overedge503;
pub use s504::Overedge;

use crate::Error;
use crate::error::StitchError;
use crate::geometry::V3;

use super::feed::Feed;
use super::material::{Slab, WPath, polyline_nearest};
use super::needle_thread::{NeedleLine, NeedleThread};
use super::spec::{Motion, StitchSpec};

/// Step of the pick-up search, deg (the reference's).
const PICK_STEP_DEG: f64 = 0.05;
/// Step of the scan for organ points inside the material, deg.
const INSIDE_SCAN_STEP_DEG: f64 = 0.25;
/// A hook offset above this is reported (§9, "checked while running"), mm.
pub const HOOK_OFFSET_WARN_MM: f64 = 3.0;

/// The φ_c of the scan for organ points inside the material: every 0.25°.
pub fn inside_scan() -> impl Iterator<Item = f64> + Clone {
    (0..(360.0 / INSIDE_SCAN_STEP_DEG) as usize).map(|k| k as f64 * INSIDE_SCAN_STEP_DEG)
}

fn fmt_p(p: &V3<f64>) -> String {
    format!("({:.3}, {:.3}, {:.3})", p.x, p.y, p.z)
}

/// The seam of an overedge stitch (503, 504) in cycle c: the material slab,
/// the material points on needle 1's line and at the edge, the thread
/// around the edge W (§4.3) with errors that name the thread and φ, and the
/// pick-up of a thread by an organ (§4.5).
#[derive(Debug, Clone)]
pub struct EdgeSeam {
    /// The stitch type, 503 or 504 (for messages).
    pub stitch: u16,
    /// Needle 1's line: H̄ and G lie on it.
    pub line: NeedleLine,
    pub slab: Slab,
    pub feed: Feed,
    /// m, t, e, a_e.
    pub m: f64,
    pub t: f64,
    pub e: f64,
    pub a_e: f64,
    /// d_p: needle point below the eye, mm.
    pub d_point: f64,
}

/// An organ's pick-up of a thread (§4.5).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PickUp {
    /// The moment of closest approach, φ_c deg.
    pub phi: f64,
    /// The organ's distance from the thread then (the hook offset), mm.
    pub hook_offset_mm: f64,
    /// Catching point − the organ's reference point: fixed to the organ
    /// from then on.
    pub offset: V3<f64>,
}

impl EdgeSeam {
    /// The seam of `spec` (503 or 504) around needle 1 `needle`; checks a_e
    /// and e.
    pub fn new(spec: &StitchSpec, needle: &NeedleThread) -> Result<EdgeSeam, Error> {
        let stitch = spec.stitch_type.number();
        let (m, t, e, a_e) = (spec.m_mm, spec.t_mm, spec.edge_split, spec.a_e_mm);
        let err = |msg: String| Err(Error::Stitch(StitchError::new(format!("stitch {stitch}"), msg)));
        if !(a_e.is_finite() && a_e > 0.0) {
            return err(format!("the overedge width a_e = {a_e} mm must be > 0 (e.g. 4)"));
        }
        if !(0.0..=1.0).contains(&e) {
            return err(format!(
                "the edge split e = {e} must be in [0, 1] (0.5: the threads meet mid-edge)"
            ));
        }
        let line = needle.line.clone();
        Ok(EdgeSeam {
            stitch,
            slab: Slab {
                x_edge: line.x_j + a_e,
                m,
            },
            line,
            feed: needle.feed.clone(),
            m,
            t,
            e,
            a_e,
            d_point: spec.needles[0].point_below_eye_mm,
        })
    }

    /// A stitch error of this type.
    pub fn err(&self, msg: String) -> Error {
        StitchError::new(format!("stitch {}", self.stitch), msg).into()
    }

    /// The looper-thread moments are in [0°, 360°) and ordered
    /// φ3 < `release` < φ4 < φ5; `release` is (its name, φ_c).
    pub fn check_moments(
        &self,
        phi_stab: f64,
        (release_name, phi_release): (&str, f64),
        (needle, phi_drop): (&str, f64),
        phi_draw_in: f64,
    ) -> Result<(), Error> {
        for (what, v) in [
            ("stab φ3", phi_stab),
            (release_name, phi_release),
            ("draw_in φ5", phi_draw_in),
        ] {
            if !(v.is_finite() && (0.0..360.0).contains(&v)) {
                return Err(self.err(format!("the moment {what} = {v}° is not in [0°, 360°)")));
            }
        }
        if !(phi_stab < phi_release && phi_release < phi_drop && phi_drop < phi_draw_in) {
            return Err(self.err(format!(
                "the moments must be ordered stab φ3 < {release_name} < drop φ4 < draw_in φ5, got \
                 {phi_stab}° , {phi_release}°, {phi_drop:.2}° (needle {needle}), {phi_draw_in}°; reorder them"
            )));
        }
        Ok(())
    }

    /// `p` of `organ` at φ_c is not inside the material (§4.3).
    pub fn check_outside(&self, organ: &str, p: &V3<f64>, phi: f64) -> Result<(), Error> {
        if self.slab.inside(p) {
            return Err(self.err(format!(
                "{organ} is inside the material at φ_c = {phi:.2}° (at {}; the material is x < {:.3}, \
                 0 < z < {} mm); move it below the plate, above the material or beyond the edge",
                fmt_p(p),
                self.slab.x_edge,
                self.m
            )));
        }
        Ok(())
    }

    /// W(P, Q) with its nodes (§4.3), with an error naming the thread and φ.
    pub fn path(&self, p: &V3<f64>, q: &V3<f64>, phi: f64, what: &str) -> Result<WPath, Error> {
        self.slab.path(p, q).ok_or_else(|| {
            self.err(format!(
                "no thread path around the material for {what} at φ_c = {phi:.2}° (from {} to {}); a point is \
                 inside the material",
                fmt_p(p),
                fmt_p(q)
            ))
        })
    }

    /// W(P, Q) (§4.3), with an error naming the thread and φ.
    pub fn w(&self, p: &V3<f64>, q: &V3<f64>, phi: f64, what: &str) -> Result<f64, Error> {
        self.path(p, q, phi, what).map(|w| w.length)
    }

    /// y of hole c + j: y(N0) + T(φ) − j·t (the material moves in +y, so
    /// older holes lie further on).
    fn y_hole(&self, j: i32, phi: f64) -> f64 {
        self.line.n0.y + self.feed.at(phi) - f64::from(j) * self.t
    }

    /// K_j: the corner below the edge point of stitch j.
    pub fn k_pt(&self, j: i32, phi: f64) -> V3<f64> {
        V3::new(self.slab.x_edge, self.y_hole(j, phi), 0.0)
    }

    /// K'_j: the corner above the edge point of stitch j.
    pub fn k_top(&self, j: i32, phi: f64) -> V3<f64> {
        V3::new(self.slab.x_edge, self.y_hole(j, phi), self.m)
    }

    /// E_j = (x_e, y_j, e·m): the edge interloop point of stitch j.
    pub fn e_pt(&self, j: i32, phi: f64) -> V3<f64> {
        V3::new(self.slab.x_edge, self.y_hole(j, phi), self.e * self.m)
    }

    /// H̄_j^b: hole j's bottom, projected vertically (G5).
    pub fn hb(&self, j: i32, phi: f64) -> V3<f64> {
        V3::new(self.line.x_j, self.y_hole(j, phi), 0.0)
    }

    /// H̄_j^t: hole j's top, projected vertically (G5).
    pub fn ht(&self, j: i32, phi: f64) -> V3<f64> {
        V3::new(self.line.x_j, self.y_hole(j, phi), self.m)
    }

    /// G(φ): the needle node for the looper threads, the needle line at the
    /// needle point's height or at the material top (§5.4).
    pub fn g(&self, phi: f64) -> V3<f64> {
        V3::new(
            self.line.x_j,
            self.line.n0.y,
            self.line.point_z(phi, self.d_point).max(self.m),
        )
    }

    /// The thread on the top face cut at a lock φ_L, from the final nodes:
    /// H̄_{c+1}^t → K'_c (l) → E_c → K'_c (2(1−e)m) → H̄_c^t (a_e) — contour
    /// 10 (504 upper looper §5.4, 503 looper §5.5; §7).
    pub fn top_face_cut(&self, phi_lock: f64) -> f64 {
        let k_top = self.k_top(0, phi_lock);
        (self.ht(1, phi_lock) - k_top).norm()
            + 2.0 * (k_top - self.e_pt(0, phi_lock)).norm()
            + (k_top - self.ht(0, phi_lock)).norm()
    }

    /// The pick-up (§4.5): the moment in `window` (φ_c deg) where `organ`
    /// comes closest to the thread W(from(φ), to(φ)) (`what` names it), on
    /// the reference's grid w0 + i·0.05°, and the catching point there, the
    /// nearest point of the thread.
    pub fn pick_up(
        &self,
        organ: &Motion,
        window: [f64; 2],
        what: &str,
        ends: impl Fn(f64) -> (V3<f64>, V3<f64>),
    ) -> Result<PickUp, Error> {
        let [w0, w1] = window;
        if !(w0.is_finite() && w1.is_finite() && 0.0 <= w0 && w0 < w1 && w1 <= 360.0) {
            return Err(self.err(format!(
                "the pick-up window [{w0}°, {w1}°] must satisfy 0° ≤ from < to ≤ 360°"
            )));
        }
        let delta = (w0 + PICK_STEP_DEG) - w0;
        let n = ((w1 - w0) / PICK_STEP_DEG).ceil() as usize;
        let mut best: Option<(f64, f64, V3<f64>)> = None;
        for i in 0..n {
            let phi = w0 + i as f64 * delta;
            let (from, to) = ends(phi);
            let path = self.path(&from, &to, phi, what)?;
            let Some((d, c)) = polyline_nearest(path.nodes(), &organ.at(phi)) else {
                continue;
            };
            if best.is_none_or(|(bd, _, _)| d < bd) {
                best = Some((d, phi, c));
            }
        }
        let Some((hook_offset_mm, phi, c)) = best else {
            return Err(self.err(format!("the pick-up window [{w0}°, {w1}°] is empty")));
        };
        Ok(PickUp {
            phi,
            hook_offset_mm,
            offset: c - organ.at(phi),
        })
    }
}
