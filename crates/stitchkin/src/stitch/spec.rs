//! What the required take-up P'(φ) is computed from: the stitch, the organs'
//! motions in the stitch frame, and the cyclogram moments
//! (`docs/stitch-formation.md` §2, §4, §9).
//!
//! Every angle here is the **cyclogram angle** φ_c in degrees (0 = needle
//! BDC, seed 004 Table 2). Every position is in the **stitch frame**, mm:
//! x across the seam toward the material edge, y along the seam in the feed
//! direction, z up, z = 0 the needle-plate top, origin on the first needle's
//! line.

use std::f64::consts::PI;
use std::sync::Arc;

use crate::geometry::V3;

/// Stitch types whose required take-up stitchkin derives (§5).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum StitchType {
    /// Lockstitch: one needle, a rotary hook and a bobbin (§13).
    S301,
    /// Two-thread chain stitch: one needle, one looper.
    S401,
    /// Two-needle chain stitch.
    S406,
    /// Three-needle chain stitch (Juki MF-7923D, seed 000).
    S407,
    /// Two-thread overedge: needle thread (drawn to the edge) and looper
    /// thread (carried over the edge by a spreader), §5.5.
    S503,
    /// Three-thread overedge (Textima Altin, seed 004): needle, lower- and
    /// upper-looper threads.
    S504,
}

impl StitchType {
    pub fn number(self) -> u16 {
        match self {
            StitchType::S301 => 301,
            StitchType::S401 => 401,
            StitchType::S406 => 406,
            StitchType::S407 => 407,
            StitchType::S503 => 503,
            StitchType::S504 => 504,
        }
    }
    /// How many needles the type has.
    pub fn needles(self) -> usize {
        match self {
            StitchType::S406 => 2,
            StitchType::S407 => 3,
            _ => 1,
        }
    }
}

/// Material transport T(φ_c): displacement of the material along +y since
/// the start of this cycle's transport, 0 before, t after.
#[derive(Debug, Clone, PartialEq)]
pub enum FeedLaw {
    /// Seed 004 §2.2.3 (reconstruction R1): a harmonic feed dog,
    /// `T = 0.5·T_d·[sin(φ_c − φ_mid) + sin(φ_tr/2)]` on
    /// `[start, start + duration]`, `T_d = t / sin(φ_tr/2)`.
    Harmonic { start_deg: f64, duration_deg: f64 },
    /// A feed-dog tooth point of the mechanism (§4.2): the material moves
    /// with the tooth's y while the tooth is above the plate (z > 0), scaled
    /// so that one cycle's transport is exactly t.
    Point { dog: Motion },
}

/// A point moving with the main shaft, in the stitch frame (mm) as a
/// function of φ_c (deg). Laws are evaluated exactly; a mechanism point is
/// a table sampled from the solved mechanism with its exact first analogs.
#[derive(Clone)]
pub enum Motion {
    /// Samples at `start_deg + k·step_deg`, k = 0…n−1, covering one cycle
    /// (periodic: φ_c is wrapped into the table). With `slopes`, the exact
    /// first analogs dN/dφ_c (mm/deg) at the same angles, the samples are
    /// joined by cubic Hermite segments: within h⁴/384·|N⁗| of the motion
    /// (about 10⁻⁸ mm for a mechanism point at a 1° step,
    /// `model::stitch_setup`); without, linearly.
    Table {
        start_deg: f64,
        step_deg: f64,
        points: Arc<[V3<f64>]>,
        slopes: Option<Arc<[V3<f64>]>>,
    },
    /// Stand-in needle eye: `N = (x, 0, 0) + (s_B − S)·u_n` with
    /// `S = stroke/2·(1 + cos(φ_c − bdc))` and `u_n = (0, −sin β, cos β)`.
    NeedleLaw {
        x_mm: f64,
        eye_above_plate_mm: f64,
        stroke_mm: f64,
        bdc_deg: f64,
        tilt_deg: f64,
    },
    /// Stand-in looper eye (catching point):
    /// `x = x_c − stroke/2·cos(φ_c − far + 180°)`, with `x_c` such that
    /// x = `catch_x_mm` at `catch_deg`; `y = y0 − avoid·sin(φ_c)`; `z = −depth`.
    LooperLaw {
        stroke_mm: f64,
        far_deg: f64,
        catch_deg: f64,
        catch_x_mm: f64,
        y0_mm: f64,
        avoid_mm: f64,
        depth_mm: f64,
    },
    /// Stand-in upper looper or spreader: along a polyline, with harmonic
    /// progress from its first point at `low_deg` to its last at `high_deg`
    /// and back.
    PolylineLaw {
        points: Arc<[V3<f64>]>,
        low_deg: f64,
        high_deg: f64,
    },
}

impl std::fmt::Debug for Motion {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Motion::Table {
                start_deg,
                step_deg,
                points,
                slopes,
            } => {
                write!(
                    f,
                    "Table {{ start_deg: {start_deg}, step_deg: {step_deg}, n: {}, analogs: {} }}",
                    points.len(),
                    slopes.is_some()
                )
            }
            Motion::NeedleLaw { .. } | Motion::LooperLaw { .. } | Motion::PolylineLaw { .. } => {
                f.write_str(match self {
                    Motion::NeedleLaw { .. } => "NeedleLaw",
                    Motion::LooperLaw { .. } => "LooperLaw",
                    _ => "PolylineLaw",
                })
            }
        }
    }
}

/// Motions are equal when they give the same positions: same law and
/// numbers, or tables with the same samples.
impl PartialEq for Motion {
    fn eq(&self, other: &Self) -> bool {
        use Motion::*;
        match (self, other) {
            (
                Table {
                    start_deg: a,
                    step_deg: b,
                    points: p,
                    slopes: u,
                },
                Table {
                    start_deg: c,
                    step_deg: d,
                    points: q,
                    slopes: v,
                },
            ) => a == c && b == d && p[..] == q[..] && u.as_deref() == v.as_deref(),
            (
                NeedleLaw {
                    x_mm: a,
                    eye_above_plate_mm: b,
                    stroke_mm: c,
                    bdc_deg: d,
                    tilt_deg: e,
                },
                NeedleLaw {
                    x_mm: f,
                    eye_above_plate_mm: g,
                    stroke_mm: h,
                    bdc_deg: i,
                    tilt_deg: j,
                },
            ) => [a, b, c, d, e] == [f, g, h, i, j],
            (
                LooperLaw {
                    stroke_mm: a,
                    far_deg: b,
                    catch_deg: c,
                    catch_x_mm: d,
                    y0_mm: e,
                    avoid_mm: f,
                    depth_mm: g,
                },
                LooperLaw {
                    stroke_mm: h,
                    far_deg: i,
                    catch_deg: j,
                    catch_x_mm: k,
                    y0_mm: l,
                    avoid_mm: m,
                    depth_mm: n,
                },
            ) => [a, b, c, d, e, f, g] == [h, i, j, k, l, m, n],
            (
                PolylineLaw {
                    points: p,
                    low_deg: a,
                    high_deg: b,
                },
                PolylineLaw {
                    points: q,
                    low_deg: c,
                    high_deg: d,
                },
            ) => p[..] == q[..] && a == c && b == d,
            _ => false,
        }
    }
}

impl Motion {
    /// Position at φ_c (deg), mm.
    pub fn at(&self, phi_c_deg: f64) -> V3<f64> {
        match self {
            Motion::Table {
                start_deg,
                step_deg,
                points,
                slopes,
            } => {
                let n = points.len();
                let u = wrap_360(phi_c_deg - start_deg) / step_deg;
                let k = (u as usize).min(n - 1);
                let s = u - k as f64;
                let j = if k + 1 == n { 0 } else { k + 1 };
                match slopes {
                    // Cubic Hermite basis on [k, k + 1], slopes per step.
                    Some(m) => {
                        let (s2, s3) = (s * s, s * s * s);
                        let (h00, h10, h01, h11) = (
                            2.0 * s3 - 3.0 * s2 + 1.0,
                            s3 - 2.0 * s2 + s,
                            3.0 * s2 - 2.0 * s3,
                            s3 - s2,
                        );
                        points[k] * h00 + m[k] * (h10 * step_deg) + points[j] * h01 + m[j] * (h11 * step_deg)
                    }
                    None => points[k] + (points[j] - points[k]) * s,
                }
            }
            Motion::NeedleLaw {
                x_mm,
                eye_above_plate_mm,
                stroke_mm,
                bdc_deg,
                tilt_deg,
            } => {
                let s = 0.5 * stroke_mm * (1.0 + (phi_c_deg - bdc_deg).to_radians().cos());
                let b = tilt_deg.to_radians();
                let up = eye_above_plate_mm - s;
                V3::new(*x_mm, -b.sin() * up, b.cos() * up)
            }
            Motion::LooperLaw {
                stroke_mm,
                far_deg,
                catch_deg,
                catch_x_mm,
                y0_mm,
                avoid_mm,
                depth_mm,
            } => {
                let amp = 0.5 * stroke_mm;
                let x_c = catch_x_mm + amp * (catch_deg - far_deg + 180.0).to_radians().cos();
                let x = x_c - amp * (phi_c_deg - far_deg + 180.0).to_radians().cos();
                let y = if *avoid_mm == 0.0 {
                    *y0_mm
                } else {
                    y0_mm - avoid_mm * phi_c_deg.to_radians().sin()
                };
                V3::new(x, y, -depth_mm)
            }
            Motion::PolylineLaw {
                points,
                low_deg,
                high_deg,
            } => {
                let x = (phi_c_deg - low_deg).rem_euclid(360.0);
                let up = (high_deg - low_deg).rem_euclid(360.0);
                let s = if x <= up {
                    0.5 * (1.0 - (PI * x / up).cos())
                } else {
                    0.5 * (1.0 + (PI * (x - up) / (360.0 - up)).cos())
                };
                polyline_at(points, s)
            }
        }
    }
}

/// x wrapped into [0, 360): the common case (a value less than a turn
/// out) without a division.
#[inline]
fn wrap_360(x: f64) -> f64 {
    let w = if (0.0..360.0).contains(&x) {
        x
    } else if (-360.0..0.0).contains(&x) {
        x + 360.0
    } else if (360.0..720.0).contains(&x) {
        x - 360.0
    } else {
        x.rem_euclid(360.0)
    };
    // −1e-17 + 360 rounds to 360.
    if w >= 360.0 { 0.0 } else { w }
}

/// Point at arc-length fraction `s` ∈ [0, 1] of a polyline.
pub fn polyline_at(points: &[V3<f64>], s: f64) -> V3<f64> {
    let total: f64 = points.windows(2).map(|w| (w[1] - w[0]).norm()).sum();
    if total < 1e-15 {
        return points[0];
    }
    let mut target = s.clamp(0.0, 1.0) * total;
    for w in points.windows(2) {
        let l = (w[1] - w[0]).norm();
        if target <= l {
            return if l < 1e-15 {
                w[0]
            } else {
                w[0] + (w[1] - w[0]) * (target / l)
            };
        }
        target -= l;
    }
    points[points.len() - 1]
}

/// One needle and its thread.
#[derive(Debug, Clone, PartialEq)]
pub struct NeedleSpec {
    /// Thread name, the column prefix (`n1`, `needle`).
    pub name: String,
    /// The needle eye N(φ_c). The needle's travel S(φ_c) below TDC is
    /// `(N_TDC − N)·u_n`; the eye at TDC sits `s_B = z(N_TDC)/cos β` above
    /// the plate; the needle line is `x = x(N_TDC)`.
    pub eye: Motion,
    /// Needle point below the eye, along the needle, mm.
    pub point_below_eye_mm: f64,
    /// Catch φ1 (the looper's catching point reaches the needle line);
    /// `None` = derived.
    pub catch_deg: Option<f64>,
    /// Drop φ4 (the loop leaves the looper: the needle-thread lock);
    /// `None` = derived (§4.4).
    pub drop_deg: Option<f64>,
}

/// The looper that catches the needle loops (the lower looper of 503/504).
#[derive(Debug, Clone, PartialEq)]
pub struct LooperSpec {
    /// Its catching point, which is also its eye LE: L(φ) = x, loop
    /// position along the seam = y.
    pub eye: Motion,
    /// Plate top to the looper's upper face, mm (seed 004: k = 4).
    pub k_mm: f64,
    /// Half-cylinder radius a of the looper body, mm (seed 004: 1).
    pub a_mm: f64,
    /// Straight sides b of the looper body, mm (seed 004: 2.5).
    pub b_mm: f64,
    /// γmax, rad (seed 004: 0.4–0.8).
    pub gamma_max_rad: f64,
}

/// The rotary hook of a lockstitch 301 (`docs/stitch-formation.md` §13):
/// its axis across the seam (along x), the hook plane through the needle
/// line. Every length in mm.
#[derive(Debug, Clone, PartialEq)]
pub struct HookSpec {
    /// Radius of the beak point's circle.
    pub beak_radius_mm: f64,
    /// Radius of the bobbin case's outline in the hook plane.
    pub case_radius_mm: f64,
    /// The hook axis's distance from the needle line along the seam (+y:
    /// in the feed direction); the case's outline must lie beside the needle
    /// line, case radius < |offset| < beak radius.
    pub offset_mm: f64,
    /// The hook axis below the plate top.
    pub depth_mm: f64,
    /// The needle's rise from its BDC when the beak meets it: the hook's
    /// timing (the makers' gauges: 1.8–2.8 mm).
    pub catch_rise_mm: f64,
    /// The beak's turn from the catch to where the loop leaves the hook,
    /// deg (the hook turns twice per stitch, so φ_K = φ1 + turn/2).
    pub cast_off_deg: f64,
}

impl HookSpec {
    /// Each number in range, or what to give instead.
    pub fn check(&self) -> Result<(), String> {
        let positive = [
            ("beak_radius_mm", self.beak_radius_mm, "e.g. 14"),
            ("case_radius_mm", self.case_radius_mm, "e.g. 11"),
            ("depth_mm", self.depth_mm, "e.g. 16"),
            ("catch_rise_mm", self.catch_rise_mm, "the makers set 1.8–2.8 mm"),
            ("cast_off_deg", self.cast_off_deg, "e.g. 270"),
        ];
        for (name, v, hint) in positive {
            if !(v.is_finite() && v > 0.0) {
                return Err(format!("{name} = {v} must be > 0 ({hint})"));
            }
        }
        let d = self.offset_mm.abs();
        if !(self.offset_mm.is_finite() && self.case_radius_mm < d && d < self.beak_radius_mm) {
            return Err(format!(
                "offset_mm = {} must put the hook axis beside the needle line: farther than the case radius {} mm \
                 and nearer than the beak radius {} mm, so the beak crosses the needle line and the case does not",
                self.offset_mm, self.case_radius_mm, self.beak_radius_mm
            ));
        }
        if self.depth_mm <= self.beak_radius_mm {
            return Err(format!(
                "depth_mm = {} puts the hook's top {:.3} mm above the plate top: the hook axis must lie deeper than \
                 the beak radius {} mm",
                self.depth_mm,
                self.beak_radius_mm - self.depth_mm,
                self.beak_radius_mm
            ));
        }
        // The beak stays on the hook's side of the needle line for
        // 360° − 2·acos(|offset|/beak radius) after the catch; then it
        // crosses the needle line again, for the next stitch.
        let beside = 360.0 - 2.0 * (d / self.beak_radius_mm).acos().to_degrees();
        if self.cast_off_deg >= beside {
            return Err(format!(
                "cast_off_deg = {} must be less than {beside:.1}: the loop must leave the hook before the beak \
                 crosses the needle line again",
                self.cast_off_deg
            ));
        }
        Ok(())
    }
}

/// The upper looper of stitch 504.
#[derive(Debug, Clone, PartialEq)]
pub struct UpperLooperSpec {
    /// Its eye UE(φ_c).
    pub eye: Motion,
    /// φ_c window where the pick-up of the lower thread (closest approach) is
    /// searched, deg.
    pub pick_window_deg: [f64; 2],
}

/// The spreader of stitch 503 (§4.5, §5.5): it takes the looper thread
/// from the lower looper, carries it over the material edge and holds it
/// above the needle line until the needle has entered its triangle. It
/// carries no thread of its own, so it has no eye in the thread sense: `eye`
/// is its hook's reference point, and the catching point keeps the offset
/// it has from that point at the pick-up.
#[derive(Debug, Clone, PartialEq)]
pub struct SpreaderSpec {
    /// Its reference point S(φ_c).
    pub eye: Motion,
    /// φ_c window where the pick-up of the looper thread (closest approach)
    /// is searched, deg.
    pub pick_window_deg: [f64; 2],
}

/// Cyclogram moments, φ_c in degrees (seed 004 Table 2).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Moments {
    /// φ3: the looper thread touches the needle (stab).
    pub stab_deg: f64,
    /// 504: φ_UD, the upper looper releases the lower thread's bight.
    /// 503: φ_SD, the spreader releases the looper thread (§5.5).
    pub upper_release_deg: f64,
    /// φ5: the looper thread is drawn into the loop (looper-thread lock).
    pub draw_in_deg: f64,
}

impl Moments {
    /// The moments of a stitch without looper threads (chain stitches and
    /// the lockstitch), which nothing reads.
    pub const NONE: Moments = Moments {
        stab_deg: 0.0,
        upper_release_deg: 0.0,
        draw_in_deg: 0.0,
    };
}

/// Where the thread of one stitch, L_s, passes a thread's tension
/// regulator (`docs/stitch-formation.md` §3.3): P' gives back L_s at the
/// thread's lock and draws it over a window, which the mismatch metrics
/// leave out.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Regulator {
    /// Every thread over the window [from, to] of φ_c, deg (uniformly); it
    /// must not contain φ0, where P' = 0, inside it.
    Window { from_deg: f64, to_deg: f64 },
    /// Each thread over the last `width_deg` before its stitch is pulled
    /// tight: a needle thread before the needle's top dead centre (the
    /// take-up draws the next stitch's thread from the bobbin as the needle
    /// reaches TDC, seed 004 §2.1 period 2-3), a looper thread before its
    /// lock, the draw-in (period 7-8, the final tightening). The default,
    /// 60°.
    BeforeTightening { width_deg: f64 },
    /// All at once at the thread's lock, with nothing left out of the
    /// metrics: the accounting of the independent reference tables.
    AtLock,
    /// Where the thread's tension draws it, computed for each setting from
    /// the thread physics (`docs/thread-physics.md`): P' draws the stitch's
    /// thread in proportion to the thread passing the regulator, and those
    /// stretches are left out of the metrics. The default for a model whose
    /// stitch paths carry thread physics.
    Computed,
}

impl Default for Regulator {
    fn default() -> Self {
        Regulator::BeforeTightening {
            width_deg: DEFAULT_REGULATOR_WIDTH_DEG,
        }
    }
}

/// The default regulator window: the last 60° before a thread's stitch is
/// pulled tight, a choice (no seed gives its width; seed 004 §2.1 places
/// the needle thread's draw "at TDC").
pub const DEFAULT_REGULATOR_WIDTH_DEG: f64 = 60.0;

/// Everything P'(φ) needs, resolved to numbers.
#[derive(Debug, Clone, PartialEq)]
pub struct StitchSpec {
    pub stitch_type: StitchType,
    /// Compressed material thickness m, mm.
    pub m_mm: f64,
    /// Stitch length t, mm.
    pub t_mm: f64,
    /// Needle inclination β along the seam, deg (seed 004: 20°).
    pub tilt_deg: f64,
    /// Overedge width a_e, mm (class 500).
    pub a_e_mm: f64,
    /// Edge split e, 0…1.
    pub edge_split: f64,
    pub feed: FeedLaw,
    pub needles: Vec<NeedleSpec>,
    /// The looper that catches the needle loops (chain and overedge
    /// stitches).
    pub looper: Option<LooperSpec>,
    /// 301 only: the rotary hook.
    pub hook: Option<HookSpec>,
    /// 301 only: f, the interlacing's depth below the top face, a fraction
    /// of m (0.5: the balanced stitch).
    pub interlace: f64,
    /// 504 only.
    pub upper_looper: Option<UpperLooperSpec>,
    /// 503 only.
    pub spreader: Option<SpreaderSpec>,
    pub moments: Moments,
    /// Where each thread's per-stitch length passes the tension regulator.
    pub regulator: Regulator,
}

impl StitchSpec {
    /// The looper that catches the needle loops; an error for a stitch
    /// without one (301 has a hook).
    pub fn the_looper(&self) -> Result<&LooperSpec, crate::error::StitchError> {
        self.looper.as_ref().ok_or_else(|| {
            crate::error::StitchError::new(
                format!("stitch {}", self.stitch_type.number()),
                "it has no looper to catch the needle loops; give [stitch.looper]",
            )
        })
    }
}

/// Where η changes at a moment (§5.6).
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "lowercase")]
pub enum EventKind {
    /// Continuous (a kink at most).
    Cont,
    /// A documented discontinuity (catch, stab, …).
    Jump,
    /// The thread's lock: the anchor moves on by one stitch.
    Lock,
}

/// A moment of the cyclogram and η on both sides of it.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct Event {
    pub name: String,
    pub phi_c_deg: f64,
    pub kind: EventKind,
    pub eta_left_mm: f64,
    pub eta_right_mm: f64,
}

/// Which thread of the stitch.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum ThreadRole {
    Needle,
    /// The thread of the looper that catches the needle loops: 504's
    /// `lower`, 503's `looper`.
    LowerLooper,
    UpperLooper,
}

/// The consumption contour of one thread over the requested φ_c grid.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct RequiredThread {
    /// `n1`, `needle`, `lower`, `upper`, `looper`.
    pub name: String,
    pub role: ThreadRole,
    /// Contour number of seed 004 §2.6 (1, 3, 10, 13); 0 for the lockstitch,
    /// which seed 004 does not number.
    pub contour: u8,
    /// Per-stitch consumption by the contour formula, mm.
    pub per_stitch_mm: f64,
    /// The lock moment φ_L, deg.
    pub lock_deg: f64,
    /// The moment its stitch is pulled tight, deg: a needle thread's at the
    /// needle's TDC, a looper thread's at its lock (the draw-in). The
    /// finished stitch is complete there.
    pub tight_deg: f64,
    /// The thread cut at the lock, recomputed from the final nodes, mm (must
    /// equal `per_stitch_mm`).
    pub cut_mm: f64,
    /// Thread released at the lock (the needle loop leaving the looper, ρ), mm.
    pub released_mm: f64,
    /// σ_snap: the contour rewritten on its final nodes minus the contour
    /// just before the lock, mm (≥ 0).
    pub snap_mm: f64,
    /// η(φ_c) at each requested φ_c (right limits at events), mm.
    pub eta_mm: Vec<f64>,
    /// P'(φ_c) = η(φ_c) − η(φ0) + L_s·(H_L(φ_c) − w(φ_c)), mm: the change
    /// of the consumption contour, with the stitch's thread L_s given back at
    /// the lock (H_L: 0 before it, 1 after, counted from φ0) and drawn
    /// through the regulator over its window (w: 0 → 1 across it); §3.3.
    pub pprime_mm: Vec<f64>,
    /// Needle threads: S(φ_c), the needle's travel below TDC, mm (so that
    /// P'_B = P' + S − S(φ0), seed 004's split at B).
    pub travel_mm: Option<Vec<f64>>,
    /// Needle threads: γ(φ_c), the loop angle on the looper, deg.
    pub gamma_deg: Option<Vec<f64>>,
    /// Needle threads: the loop on the looper body at φ_c (0 outside the
    /// carry), mm.
    pub loop_mm: Option<Vec<f64>>,
    /// Needle threads: whether the eye is below the material's top face at
    /// each φ_c (between φ_in and φ_out), where the thread turns back up
    /// through the eye toward the stitch.
    pub eye_in_material: Option<Vec<bool>>,
    /// Needle threads: the catch and drop geometry of the physical checks.
    pub needle_moments: Option<super::checks::NeedleMoments>,
    /// A lockstitch's needle thread: the hook's catch for its check.
    pub hook_moments: Option<super::checks::HookMoments>,
    /// Where its per-stitch thread passes the regulator, φ_c [from, to] deg
    /// (`to` may exceed 360); `None` with [`Regulator::AtLock`].
    pub regulator_window_deg: Option<[f64; 2]>,
    /// Piece id at each φ_c (`N1`, `N2a`, …, `L3`, `U2`, `S3a`).
    pub piece: Vec<&'static str>,
    /// Every moment of this thread in φ_c order.
    pub events: Vec<Event>,
}

/// P'(φ) of every thread of a stitch process.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct RequiredTakeUp {
    pub threads: Vec<RequiredThread>,
    /// Derived moments (name, φ_c deg): eye leaves/enters the material,
    /// catches, drops, pick-up, looper far extreme.
    pub moments: Vec<(String, f64)>,
    /// Validity warnings (a declared drop far from the derived one, a large
    /// hook offset, …).
    pub warnings: Vec<String>,
}
