//! The `[stitch]` table: checked on load into a stitch definition, resolved with
//! parameter values into a [`StitchSpec`] whose organ motions are sampled
//! from the solved mechanism (`docs/stitch-formation.md` §9).

use std::sync::Arc;

use super::expr::Dim;
use super::file::{ModelFile, PolylineLawFile, StitchFile, StitchHook, StitchLooper, Value};
use super::load::{LoadResult, Loader};
use super::spans::KeyPath;
use super::{Model, Params, QuantityId, ThreadsDef};
use crate::error::Error;
use crate::geometry::{Placement, V3};
use crate::mechanism::analogs::PoseAnalogs;
use crate::mechanism::{Mechanism, Phi, Pose};
use crate::stitch::search::max_on_cycle;
use crate::stitch::spec::{
    DEFAULT_REGULATOR_WIDTH_DEG, FeedLaw, HookSpec, LooperSpec, Moments, Motion, NeedleSpec, Regulator, SpreaderSpec,
    StitchSpec, StitchType, UpperLooperSpec,
};
use num_dual::Dual64;

/// ε of the match metrics (D within ± ε counts as matched), mm, when
/// `[stitch]` gives no `tolerance_mm`.
pub const DEFAULT_TOLERANCE_MM: f64 = 0.5;

/// The upper looper of a 504: its organ, its window (deg) and the thread path it feeds.
type UpperLooper = (OrganDef, [f64; 2], Option<String>);

/// Step at which mechanism points are sampled for the stitch process, with
/// their exact first analogs, degrees of φ. Cubic Hermite segments between
/// the samples are within about 10⁻⁸ mm of the mechanism for the presets'
/// organs (a test holds every preset's organs to 10⁻⁶ mm at the midpoints).
pub const ORGAN_STEP_DEG: f64 = 1.0;

/// Where an organ's motion comes from.
#[derive(Debug, Clone)]
pub(crate) enum OrganDef {
    /// A mechanism point (slot).
    Point(usize),
    NeedleLaw {
        x: QuantityId,
        s_b: QuantityId,
        stroke: QuantityId,
        bdc: Option<QuantityId>,
    },
    LooperLaw {
        stroke: QuantityId,
        far: QuantityId,
        catch: QuantityId,
        catch_x: Option<QuantityId>,
        y0: Option<QuantityId>,
        avoid: Option<QuantityId>,
        depth: QuantityId,
    },
    Polyline {
        points: Vec<[f64; 3]>,
        low: f64,
        high: f64,
    },
}

#[derive(Debug, Clone)]
pub(crate) struct NeedleDef {
    pub name: String,
    pub eye: OrganDef,
    pub eye_above_plate: Option<QuantityId>,
    pub point_below_eye: Option<QuantityId>,
    pub path: Option<String>,
    pub catch_deg: Option<QuantityId>,
    pub drop_deg: Option<QuantityId>,
}

/// Where the stitch's thread passes the regulator: a model-φ window, the
/// last degrees (a quantity) before each thread is pulled tight, or at the
/// lock.
#[derive(Debug, Clone)]
pub(crate) enum RegulatorDef {
    Window([f64; 2]),
    BeforeTightening(Option<QuantityId>),
    AtLock,
    Computed,
}

/// The material feed: harmonic (start, duration) or a feed-dog tooth point.
#[derive(Debug, Clone)]
pub(crate) enum FeedDef {
    Harmonic(QuantityId, QuantityId),
    Point(usize),
}

/// The checked `[stitch]` table, values as quantity indices.
#[derive(Debug, Clone)]
pub(crate) struct StitchDef {
    pub stitch_type: StitchType,
    pub m: QuantityId,
    pub t: QuantityId,
    pub tilt: Option<QuantityId>,
    pub a_e: Option<QuantityId>,
    pub edge_split: f64,
    pub frame: usize,
    pub cyclogram_zero_deg: f64,
    pub tolerance_mm: f64,
    pub regulator: RegulatorDef,
    pub feed: FeedDef,
    pub needles: Vec<NeedleDef>,
    /// Every type but 301: the looper's organ, body (k, a, b, γmax) and path.
    pub looper: Option<(OrganDef, [QuantityId; 4], Option<String>)>,
    /// 301: the hook (beak radius, case radius, offset, depth, catch rise,
    /// cast-off turn) and the interlacing depth f.
    pub hook: Option<([QuantityId; 6], QuantityId)>,
    pub upper: Option<(OrganDef, [f64; 2], Option<String>)>,
    /// 503: the spreader and its pick-up window.
    pub spreader: Option<(OrganDef, [f64; 2])>,
    pub moments: Option<Moments>,
}

/// How the stitch process of a model is compared with its take-up: what
/// `run` and `match` need besides the [`StitchSpec`].
#[derive(Debug, Clone, PartialEq)]
pub struct StitchSetup {
    pub spec: StitchSpec,
    /// The model's φ of φ_c = 0.
    pub cyclogram_zero_deg: f64,
    /// ε of the excess/deficit intervals, mm.
    pub tolerance_mm: f64,
    /// For each thread of the spec (needles in order, then the looper
    /// threads: `lower`, `upper` for 504, `looper` for 503), the thread path
    /// it is compared with.
    pub paths: Vec<Option<String>>,
}

fn finite_deg(ld: &Loader, v: f64, path: &KeyPath) -> LoadResult<f64> {
    if v.is_finite() {
        Ok(v)
    } else {
        Err(ld.err(path, "the angle must be a finite number of degrees", None))
    }
}

impl Loader<'_> {
    /// An organ is a mechanism point (`eye`) or a stand-in `law`, never
    /// both: the point's slot, or `None` for the law.
    fn organ_point(
        &self,
        eye: &Option<String>,
        has_law: bool,
        path: &KeyPath,
        what: &str,
    ) -> LoadResult<Option<usize>> {
        match (eye, has_law) {
            (Some(p), false) => Ok(Some(self.point(p, &path.key("eye"))?)),
            (None, true) => Ok(None),
            _ => Err(self.err(
                path,
                format!("the {what} needs exactly one of `eye` (a mechanism point) or `law` (a stand-in motion)"),
                Some("e.g. `eye = \"N_1\"`".into()),
            )),
        }
    }

    fn opt_length(&mut self, v: &Option<Value>, path: KeyPath) -> LoadResult<Option<QuantityId>> {
        v.as_ref().map(|v| self.length(v, path)).transpose()
    }

    /// An organ that moves along a polyline stand-in (the upper looper, the
    /// spreader): a mechanism point `eye` or a polyline `law`.
    fn polyline_organ(
        &self,
        eye: &Option<String>,
        law: &Option<PolylineLawFile>,
        at: &KeyPath,
        what: &str,
    ) -> LoadResult<OrganDef> {
        match (self.organ_point(eye, law.is_some(), at, what)?, law) {
            (Some(slot), _) => Ok(OrganDef::Point(slot)),
            (None, Some(w)) => {
                let p = at.key("law");
                if w.polyline_mm.len() < 2 || w.polyline_mm.iter().flatten().any(|x| !x.is_finite()) {
                    return Err(self.err(
                        &p.key("polyline_mm"),
                        "the polyline needs at least 2 finite points",
                        Some("e.g. [[13, 1, -6], [5.5, 0, 4]]".into()),
                    ));
                }
                let (low, high) = (
                    finite_deg(self, w.low_deg, &p.key("low_deg"))?,
                    finite_deg(self, w.high_deg, &p.key("high_deg"))?,
                );
                Ok(OrganDef::Polyline {
                    points: w.polyline_mm.clone(),
                    low,
                    high,
                })
            }
            (None, None) => unreachable!("organ_point checked"),
        }
    }

    /// A pick-up window [from, to], from < to (φ_c degrees).
    fn pick_window(&self, w: [f64; 2], at: &KeyPath) -> LoadResult<[f64; 2]> {
        if !(w[0].is_finite() && w[1].is_finite() && w[1] > w[0]) {
            return Err(self.err(at, "the pick-up window is [from, to] with from < to", None));
        }
        Ok(w)
    }

    pub(super) fn stitch(&mut self, f: &ModelFile, threads: Option<&ThreadsDef>) -> LoadResult<Option<StitchDef>> {
        let Some(s) = &f.stitch else { return Ok(None) };
        let path = KeyPath::root().key("stitch");
        let stitch_type = self.stitch_type(s, &path)?;
        let m = self.positive_length(&s.m_mm, path.key("m_mm"), "the material thickness m")?;
        let t = self.positive_length(&s.t_mm, path.key("t_mm"), "the stitch length t")?;
        let tilt = s
            .tilt_deg
            .as_ref()
            .map(|v| self.angle_within(v, path.key("tilt_deg"), "the needle tilt β", 80.0))
            .transpose()?;
        let a_e = match &s.overedge_width_mm {
            Some(v) => Some(self.positive_length(v, path.key("overedge_width_mm"), "the overedge width a_e")?),
            None => None,
        };
        if matches!(stitch_type, StitchType::S503 | StitchType::S504) && a_e.is_none() {
            return Err(self.err(
                &path,
                format!("stitch {} needs the overedge width", s.stitch_type),
                Some("add `overedge_width_mm = 4`".into()),
            ));
        }
        let edge_split = s.edge_split.unwrap_or(0.5);
        if !(0.0..=1.0).contains(&edge_split) {
            return Err(self.err(
                &path.key("edge_split"),
                format!("edge_split = {edge_split} is outside 0…1"),
                Some("0.5 puts the looper threads' meeting point mid-edge".into()),
            ));
        }
        let frame = self.opt_frame(&s.frame, path.key("frame"))?;
        let cyclogram_zero_deg = finite_deg(self, s.cyclogram_zero_deg, &path.key("cyclogram_zero_deg"))?;
        let tolerance_mm = s.tolerance_mm.unwrap_or(DEFAULT_TOLERANCE_MM);
        if !(tolerance_mm.is_finite() && tolerance_mm > 0.0) {
            return Err(self.err(
                &path.key("tolerance_mm"),
                "the tolerance must be a positive number of mm",
                None,
            ));
        }
        let regulator = self.regulator(f, s, &path)?;
        let feed = self.feed(s, &path)?;
        let needles = self.needles(s, stitch_type, &path, threads)?;
        let (looper, hook) = match (stitch_type, &s.looper, &s.hook) {
            (StitchType::S301, None, Some(h)) => (None, Some(self.hook(h, s, &path)?)),
            (StitchType::S301, Some(_), _) => {
                return Err(self.err(
                    &path.key("looper"),
                    "a lockstitch (301) has a hook, not a looper",
                    Some(
                        "replace [stitch.looper] with [stitch.hook] (docs/model-format.md, \"Stitch process\")".into(),
                    ),
                ));
            }
            (StitchType::S301, None, None) => {
                return Err(self.err(
                    &path,
                    "a lockstitch (301) needs its hook",
                    Some(
                        "add [stitch.hook] with beak_radius_mm, case_radius_mm, offset_mm and cast_off_deg \
                         (docs/model-format.md, \"Stitch process\")"
                            .into(),
                    ),
                ));
            }
            (_, _, Some(_)) => {
                return Err(self.err(
                    &path.key("hook"),
                    format!("stitch {} has a looper, not a hook", s.stitch_type),
                    Some("remove [stitch.hook]; only a lockstitch (type \"301\") has one".into()),
                ));
            }
            (_, Some(l), None) => (Some(self.looper(l, &path, threads)?), None),
            (_, None, None) => {
                return Err(self.err(
                    &path,
                    format!(
                        "stitch {} needs the looper that catches the needle loops",
                        s.stitch_type
                    ),
                    Some("add [stitch.looper] (docs/model-format.md, \"Stitch process\")".into()),
                ));
            }
        };
        if let (Some(_), false) = (&s.interlace, stitch_type == StitchType::S301) {
            return Err(self.err(
                &path.key("interlace"),
                format!("stitch {} has no interlacing depth", s.stitch_type),
                Some("remove `interlace`; only a lockstitch (type \"301\") has one".into()),
            ));
        }
        let upper = self.upper_looper(s, stitch_type, &path, threads)?;
        let spreader = self.spreader(s, stitch_type, &path)?;
        let moments = self.moments(s, stitch_type, &path)?;
        Ok(Some(StitchDef {
            stitch_type,
            m,
            t,
            tilt,
            a_e,
            edge_split,
            frame,
            cyclogram_zero_deg,
            tolerance_mm,
            regulator,
            feed,
            needles,
            looper,
            hook,
            upper,
            spreader,
            moments,
        }))
    }

    /// The stitch type: 301, 401, 406, 407, 503 or 504.
    fn stitch_type(&self, s: &StitchFile, path: &KeyPath) -> LoadResult<StitchType> {
        Ok(match s.stitch_type.as_str() {
            "301" => StitchType::S301,
            "401" => StitchType::S401,
            "406" => StitchType::S406,
            "407" => StitchType::S407,
            "503" => StitchType::S503,
            "504" => StitchType::S504,
            other => {
                return Err(self.err(
                    &path.key("type"),
                    format!("unknown or unsupported stitch type `{other}`"),
                    Some("write \"301\", \"401\", \"406\", \"407\", \"503\" or \"504\"".into()),
                ));
            }
        })
    }

    /// Where the thread passes the regulator: a window of φ (that must not
    /// hold φ0, where P' = 0), the last degrees before tightening, or at
    /// the lock.
    fn regulator(&mut self, f: &ModelFile, s: &StitchFile, path: &KeyPath) -> LoadResult<RegulatorDef> {
        let rp = path.key("regulator");
        // Thread physics on every compared path computes the window.
        let physics = compared_paths_have_physics(f, s);
        Ok(match &s.regulator {
            None if physics.is_ok() => RegulatorDef::Computed,
            None => RegulatorDef::BeforeTightening(None),
            Some(r) if r.computed == Some(true) => {
                if r.window_deg.is_some() || r.width_deg.is_some() || r.at_lock == Some(true) {
                    return Err(self.err(
                        &rp,
                        "give exactly one of `computed = true`, `window_deg`, `width_deg` or `at_lock = true`",
                        None,
                    ));
                }
                if let Err(missing) = physics {
                    return Err(self.err(
                        &rp.key("computed"),
                        format!("the regulator's window is computed from the thread's tension, and {missing}"),
                        Some("give [thread.physics] (or the path's own `physics`), or assume a window: regulator = { width_deg = 60 }".into()),
                    ));
                }
                RegulatorDef::Computed
            }
            Some(r) => match (r.window_deg, &r.width_deg, r.at_lock) {
                (Some(w), None, None | Some(false)) => {
                    let width = w[1] - w[0];
                    if !(w[0].is_finite() && w[1].is_finite() && width > 0.0 && width < 360.0) {
                        return Err(self.err(&rp.key("window_deg"), format!("the window [{}, {}] must run forward by less than a turn", w[0], w[1]), Some("give [from, to] in the model's φ, degrees, with from < to < from + 360, e.g. [300, 360]".into())));
                    }
                    // P' = 0 at φ0 (the taut state): each stitch's thread
                    // is drawn between one φ0 and the next.
                    let phi0 = f
                        .thread
                        .as_ref()
                        .and_then(|t| t.phi0_deg)
                        .unwrap_or(f.model.phi_start_deg.unwrap_or(0.0));
                    let inside = (phi0 - w[0]).rem_euclid(360.0);
                    if inside > 1e-9 && inside < width - 1e-9 {
                        // The same width ending at φ0.
                        let end = phi0.rem_euclid(360.0) + if phi0.rem_euclid(360.0) < width { 360.0 } else { 0.0 };
                        return Err(self.err(
                            &rp.key("window_deg"),
                            format!(
                                "the window [{}, {}] contains φ0 = {}°, where P' = 0 (the taut state): the thread must be drawn through the \
                                 regulator within one stitch, between one φ0 and the next",
                                w[0],
                                w[1],
                                phi0.rem_euclid(360.0)
                            ),
                            Some(format!("end the window at φ0 or start it there, e.g. window_deg = [{}, {end}]", end - width)),
                        ));
                    }
                    RegulatorDef::Window(w)
                }
                (None, Some(v), None | Some(false)) => {
                    RegulatorDef::BeforeTightening(Some(self.angle(v, rp.key("width_deg"))?))
                }
                (None, None, Some(true)) => RegulatorDef::AtLock,
                _ => {
                    return Err(self.err(&rp, "give exactly one of `computed = true`, `window_deg`, `width_deg` or `at_lock = true`", Some("e.g. regulator = { width_deg = 60 } (the default without thread physics), or regulator = { window_deg = [300, 360] }".into())));
                }
            },
        })
    }

    /// The material feed: harmonic, or a feed-dog tooth of the mechanism.
    fn feed(&mut self, s: &StitchFile, path: &KeyPath) -> LoadResult<FeedDef> {
        let fp = path.key("feed");
        Ok(
            match (
                s.feed.law.as_str(),
                &s.feed.start_deg,
                &s.feed.duration_deg,
                &s.feed.point,
            ) {
                ("harmonic", Some(a), Some(d), None) => FeedDef::Harmonic(
                    self.angle(a, fp.key("start_deg"))?,
                    self.angle(d, fp.key("duration_deg"))?,
                ),
                ("harmonic", ..) => {
                    return Err(self.err(
                        &fp,
                        "the harmonic feed takes `start_deg` and `duration_deg` (and no `point`)",
                        Some("e.g. feed = { law = \"harmonic\", start_deg = 134, duration_deg = 100 }".into()),
                    ));
                }
                ("point", None, None, Some(p)) => FeedDef::Point(self.point(p, &fp.key("point"))?),
                ("point", ..) => {
                    return Err(self.err(
                    &fp,
                    "the point feed takes `point`, the feed dog's tooth (and no angles: they follow from its motion)",
                    Some("e.g. feed = { law = \"point\", point = \"DOG\" }".into()),
                ));
                }
                (other, ..) => {
                    return Err(self.err(&fp.key("law"), format!("unknown feed law `{other}`"), Some(format!("write law = \"harmonic\" ({} §2.2.3) or law = \"point\" (a feed-dog tooth of the mechanism)", crate::references::cite(4)))));
                }
            },
        )
    }

    /// The needles: as many as the stitch type has, each with a unique
    /// thread name, its eye (a point or a law) and its thread path.
    fn needles(
        &mut self,
        s: &StitchFile,
        stitch_type: StitchType,
        path: &KeyPath,
        threads: Option<&ThreadsDef>,
    ) -> LoadResult<Vec<NeedleDef>> {
        let want = stitch_type.needles();
        if s.needles.len() != want {
            return Err(self.err(
                &path.key("needles"),
                format!(
                    "stitch {} has {want} needle(s), {} given",
                    s.stitch_type,
                    s.needles.len()
                ),
                Some(format!("give {want} [[stitch.needles]] tables")),
            ));
        }
        let mut names: Vec<String> = Vec::new();
        let mut needles = Vec::new();
        for (k, n) in s.needles.iter().enumerate() {
            let np = path.key("needles").index(k);
            if !super::load::is_ident(&n.name)
                || names.contains(&n.name)
                || ["lower", "upper", "looper"].contains(&n.name.as_str())
            {
                return Err(self.err(
                    &np.key("name"),
                    format!("`{}` is not a valid, unique thread name", n.name),
                    Some(
                        "use letters, digits and `_`, e.g. `n1`; `lower`, `upper` and `looper` are the looper threads"
                            .into(),
                    ),
                ));
            }
            names.push(n.name.clone());
            let eye = match (self.organ_point(&n.eye, n.law.is_some(), &np, "needle")?, &n.law) {
                (Some(slot), _) => OrganDef::Point(slot),
                (None, Some(l)) => {
                    let lp = np.key("law");
                    OrganDef::NeedleLaw {
                        x: self.length(&l.x_mm, lp.key("x_mm"))?,
                        s_b: self.length(&l.eye_above_plate_mm, lp.key("eye_above_plate_mm"))?,
                        stroke: self.positive_length(&l.stroke_mm, lp.key("stroke_mm"), "the needle stroke")?,
                        bdc: l
                            .bdc_deg
                            .as_ref()
                            .map(|v| self.angle(v, lp.key("bdc_deg")))
                            .transpose()?,
                    }
                }
                (None, None) => unreachable!("organ_point checked"),
            };
            if n.law.is_some() && n.eye_above_plate_mm.is_some() {
                return Err(self.err(
                    &np.key("eye_above_plate_mm"),
                    "with a `law`, the eye height is the law's `eye_above_plate_mm`",
                    Some("remove this line".into()),
                ));
            }
            let eye_above_plate = self.opt_length(&n.eye_above_plate_mm, np.key("eye_above_plate_mm"))?;
            let point_below_eye = self.opt_length(&n.point_below_eye_mm, np.key("point_below_eye_mm"))?;
            let catch_deg = n
                .catch_deg
                .as_ref()
                .map(|v| self.angle(v, np.key("catch_deg")))
                .transpose()?;
            let drop_deg = n
                .drop_deg
                .as_ref()
                .map(|v| self.angle(v, np.key("drop_deg")))
                .transpose()?;
            needles.push(NeedleDef {
                name: n.name.clone(),
                eye,
                eye_above_plate,
                point_below_eye,
                path: self.thread_path(&n.path, np.key("path"), threads)?,
                catch_deg,
                drop_deg,
            });
        }
        Ok(needles)
    }

    /// The hook of a lockstitch (five lengths and an angle) and the
    /// interlacing depth f, checked when the parameters change.
    fn hook(&mut self, h: &StitchHook, s: &StitchFile, path: &KeyPath) -> LoadResult<([QuantityId; 6], QuantityId)> {
        let hp = path.key("hook");
        let default = |v: &Option<Value>, x: f64| v.clone().unwrap_or(Value::Number(x));
        let q = [
            self.positive_length(&h.beak_radius_mm, hp.key("beak_radius_mm"), "the beak radius")?,
            self.positive_length(&h.case_radius_mm, hp.key("case_radius_mm"), "the bobbin case radius")?,
            self.length(&h.offset_mm, hp.key("offset_mm"))?,
            self.positive_length(&h.depth_mm, hp.key("depth_mm"), "the hook axis's depth below the plate")?,
            self.positive_length(
                &default(&h.catch_rise_mm, 2.0),
                hp.key("catch_rise_mm"),
                "the needle rise at the catch",
            )?,
            self.angle(&h.cast_off_deg, hp.key("cast_off_deg"))?,
        ];
        let f = self.qty(&default(&s.interlace, 0.5), Some(Dim::ONE), path.key("interlace"))?;
        Ok((q, f))
    }

    /// The looper: its eye (a point or a law), body and thread path.
    fn looper(
        &mut self,
        l: &StitchLooper,
        path: &KeyPath,
        threads: Option<&ThreadsDef>,
    ) -> LoadResult<(OrganDef, [QuantityId; 4], Option<String>)> {
        let lp = path.key("looper");
        let looper_eye = match (self.organ_point(&l.eye, l.law.is_some(), &lp, "looper")?, &l.law) {
            (Some(slot), _) => OrganDef::Point(slot),
            (None, Some(w)) => {
                let p = lp.key("law");
                OrganDef::LooperLaw {
                    stroke: self.positive_length(&w.stroke_mm, p.key("stroke_mm"), "the looper stroke")?,
                    far: self.angle(&w.far_deg, p.key("far_deg"))?,
                    catch: self.angle(&w.catch_deg, p.key("catch_deg"))?,
                    catch_x: self.opt_length(&w.catch_x_mm, p.key("catch_x_mm"))?,
                    y0: self.opt_length(&w.y0_mm, p.key("y0_mm"))?,
                    avoid: self.opt_length(&w.avoid_mm, p.key("avoid_mm"))?,
                    depth: self.length(&w.depth_mm, p.key("depth_mm"))?,
                }
            }
            (None, None) => unreachable!("organ_point checked"),
        };
        let body = [
            self.length(&l.k_mm, lp.key("k_mm"))?,
            self.positive_length(&l.a_mm, lp.key("a_mm"), "the looper's half-cylinder radius a")?,
            self.length(&l.b_mm, lp.key("b_mm"))?,
            self.angle(&l.gamma_max_deg, lp.key("gamma_max_deg"))?,
        ];
        Ok((looper_eye, body, self.thread_path(&l.path, lp.key("path"), threads)?))
    }

    /// The upper looper, which 504 has and no other stitch.
    fn upper_looper(
        &mut self,
        s: &StitchFile,
        stitch_type: StitchType,
        path: &KeyPath,
        threads: Option<&ThreadsDef>,
    ) -> LoadResult<Option<UpperLooper>> {
        Ok(match (&s.upper_looper, stitch_type) {
            (Some(u), StitchType::S504) => {
                let up = path.key("upper_looper");
                let eye = self.polyline_organ(&u.eye, &u.law, &up, "upper looper")?;
                let w = self.pick_window(u.pick_window_deg, &up.key("pick_window_deg"))?;
                Some((eye, w, self.thread_path(&u.path, up.key("path"), threads)?))
            }
            (None, StitchType::S504) => {
                return Err(self.err(
                    path,
                    "stitch 504 needs an upper looper",
                    Some("add a [stitch.upper_looper] table".into()),
                ));
            }
            (Some(_), StitchType::S503) => {
                return Err(self.err(&path.key("upper_looper"), "stitch 503 has no upper looper", Some("remove [stitch.upper_looper]; the organ that carries 503's looper thread over the edge is [stitch.spreader]".into())));
            }
            (Some(_), _) => {
                return Err(self.err(
                    &path.key("upper_looper"),
                    format!("stitch {} has no upper looper", s.stitch_type),
                    Some("remove [stitch.upper_looper]".into()),
                ));
            }
            (None, _) => None,
        })
    }

    /// The spreader, which 503 has and no other stitch.
    fn spreader(
        &mut self,
        s: &StitchFile,
        stitch_type: StitchType,
        path: &KeyPath,
    ) -> LoadResult<Option<(OrganDef, [f64; 2])>> {
        Ok(match (&s.spreader, stitch_type) {
            (Some(sp), StitchType::S503) => {
                let at = path.key("spreader");
                let eye = self.polyline_organ(&sp.eye, &sp.law, &at, "spreader")?;
                Some((eye, self.pick_window(sp.pick_window_deg, &at.key("pick_window_deg"))?))
            }
            (None, StitchType::S503) => {
                return Err(self.err(
                    path,
                    "stitch 503 needs a spreader, the organ that carries the looper thread over the edge to the needle",
                    Some("add a [stitch.spreader] table with `eye` (or `law`) and `pick_window_deg`".into()),
                ));
            }
            (Some(_), _) => {
                return Err(self.err(
                    &path.key("spreader"),
                    format!("stitch {} has no spreader", s.stitch_type),
                    Some("remove [stitch.spreader] (only 503 has one)".into()),
                ));
            }
            (None, _) => None,
        })
    }

    /// The cyclogram moments of an overedge stitch (503, 504), in order.
    fn moments(&mut self, s: &StitchFile, stitch_type: StitchType, path: &KeyPath) -> LoadResult<Option<Moments>> {
        Ok(match (&s.moments, stitch_type) {
            (Some(mo), StitchType::S503 | StitchType::S504) => {
                let mp = path.key("moments");
                // 504: the upper looper lets go of the lower thread's bight;
                // 503: the spreader lets go of the looper thread (§5.5).
                let ((key, release), (other_key, other)) = if stitch_type == StitchType::S504 {
                    (
                        ("upper_release_deg", mo.upper_release_deg),
                        ("spreader_release_deg", mo.spreader_release_deg),
                    )
                } else {
                    (
                        ("spreader_release_deg", mo.spreader_release_deg),
                        ("upper_release_deg", mo.upper_release_deg),
                    )
                };
                if other.is_some() {
                    return Err(self.err(
                        &mp.key(other_key),
                        format!("stitch {} has no `{other_key}`", s.stitch_type),
                        Some(format!("write `{key}` instead")),
                    ));
                }
                let Some(release) = release else {
                    return Err(self.err(
                        &mp,
                        format!("stitch {} needs `{key}`", s.stitch_type),
                        Some(format!("add `{key} = 290` (φ_c, degrees, between stab and draw-in)")),
                    ));
                };
                for (v, k) in [
                    (mo.stab_deg, "stab_deg"),
                    (release, key),
                    (mo.draw_in_deg, "draw_in_deg"),
                ] {
                    finite_deg(self, v, &mp.key(k))?;
                }
                if !(mo.stab_deg < release && release < mo.draw_in_deg && mo.draw_in_deg < 360.0) {
                    let name = key.trim_end_matches("_deg");
                    return Err(self.err(
                        &mp,
                        format!("the moments must come in the order stab < {name} < draw_in < 360 (φ_c, degrees)"),
                        Some(format!("{} Table 2: stab 270, draw-in 330", crate::references::cite(4))),
                    ));
                }
                Some(Moments {
                    stab_deg: mo.stab_deg,
                    upper_release_deg: release,
                    draw_in_deg: mo.draw_in_deg,
                })
            }
            (None, StitchType::S503 | StitchType::S504) => {
                let key = if stitch_type == StitchType::S504 {
                    "upper_release_deg"
                } else {
                    "spreader_release_deg"
                };
                return Err(self.err(
                    path,
                    format!("stitch {} needs its cyclogram moments", s.stitch_type),
                    Some(format!("add [stitch.moments] with stab_deg, {key}, draw_in_deg")),
                ));
            }
            (_, _) => None,
        })
    }

    /// A `path` naming one of the model's thread paths.
    fn thread_path(&self, p: &Option<String>, at: KeyPath, threads: Option<&ThreadsDef>) -> LoadResult<Option<String>> {
        let path_names: Vec<&str> = threads
            .map(|t| t.paths.iter().map(|p| p.name.as_str()).collect())
            .unwrap_or_default();
        match p {
            Some(name) if !path_names.contains(&name.as_str()) => Err(self.err(
                &at,
                format!("unknown thread path `{name}`"),
                Some(match crate::error::did_you_mean(name, path_names.iter().copied()) {
                    Some(s) => format!("did you mean `{s}`? Paths are the [[thread.paths]] names"),
                    None if path_names.is_empty() => {
                        "the model has no [[thread.paths]]; add one or remove `path`".into()
                    }
                    None => format!("paths are: {}", path_names.join(", ")),
                }),
            )),
            _ => Ok(p.clone()),
        }
    }
}

/// One point's samples: positions (mm) and first analogs.
type PointSamples = (Vec<V3<f64>>, Vec<V3<f64>>);

/// Mechanism points sampled over one cycle from φ_c = 0 in steps of
/// [`ORGAN_STEP_DEG`] with their first analogs, in the stitch frame: the
/// organs' motions.
struct OrganSamples {
    /// Per point, for the organs': positions and first analogs d/dφ
    /// (mm/rad) in the world.
    tracks: Vec<Option<PointSamples>>,
    /// The stitch frame's placement (`None`: the world).
    placement: Option<Placement<f64>>,
}

impl OrganSamples {
    /// The track of point `slot` in the stitch frame: positions (mm) and
    /// first analogs (mm/deg).
    fn track(&self, slot: usize) -> (Vec<V3<f64>>, Vec<V3<f64>>) {
        let (x, v) = self.tracks[slot].as_ref().expect("sampled when a point is used");
        let per_deg = std::f64::consts::PI / 180.0;
        match self.placement {
            Some(pl) => (
                x.iter().map(|p| pl.to_local(*p)).collect(),
                v.iter().map(|d| pl.rot.tr_mul(d) * per_deg).collect(),
            ),
            None => (x.clone(), v.iter().map(|d| d * per_deg).collect()),
        }
    }

    /// Point `slot`'s motion over the cycle.
    fn motion(&self, slot: usize) -> Motion {
        let (points, slopes) = self.track(slot);
        sampled_motion(points, slopes)
    }
}

/// The buffers of one organ sampling, kept by each thread from one setting
/// to the next (a study samples the organs at every setting that moves
/// them): the pose, its analogs and the φ table of a cyclogram zero.
struct OrganScratch {
    pose: Pose<f64>,
    analogs: PoseAnalogs,
    zero_deg: f64,
    phis: Vec<Phi<f64>>,
    /// The fixed points whose analogs are zero in `analogs`.
    fixed: Vec<usize>,
    /// The last sampling: a setting that leaves the mechanism as it was
    /// (a study over the stitch alone: the material, the hook's timing)
    /// takes its samples as they are.
    last: Option<LastSampling>,
}

/// The mechanism, cyclogram zero and points of the last organ sampling, and
/// its samples.
struct LastSampling {
    mech: Mechanism<f64>,
    zero_deg: f64,
    slots: Vec<usize>,
    tracks: Vec<Option<PointSamples>>,
}

thread_local! {
    static ORGAN_SCRATCH: std::cell::RefCell<Option<OrganScratch>> = const { std::cell::RefCell::new(None) };
}

/// The φ of the organ samples for cyclogram zero `zero_deg`, deg.
fn organ_phis_deg(zero_deg: f64) -> Vec<f64> {
    let n = (360.0 / ORGAN_STEP_DEG).round() as usize;
    (0..n).map(|k| zero_deg + k as f64 * ORGAN_STEP_DEG).collect()
}

/// Positions and first analogs (mm/rad) of the points `slots` of `mech`
/// at the organ samples from `zero_deg`; `mech_dual` gives the analogs when
/// they have no closed form.
fn sample_points(
    mech: &Mechanism<f64>,
    mech_dual: impl FnOnce() -> Result<Mechanism<Dual64>, Error>,
    zero_deg: f64,
    slots: &[usize],
) -> Result<Vec<Option<PointSamples>>, Error> {
    // The same mechanism moves the same points the same way.
    let kept = ORGAN_SCRATCH.with_borrow(|scratch| {
        let last = scratch.as_ref()?.last.as_ref()?;
        (last.zero_deg == zero_deg && last.slots == slots && last.mech == *mech).then(|| last.tracks.clone())
    });
    if let Some(tracks) = kept {
        return Ok(tracks);
    }
    let phis_deg = organ_phis_deg(zero_deg);
    let n = phis_deg.len();
    let mut tracks = vec![None; mech.n_points()];
    let closed = ORGAN_SCRATCH.with_borrow_mut(|scratch| -> Result<bool, Error> {
        let s = scratch.get_or_insert_with(|| OrganScratch {
            pose: mech.new_pose(n),
            analogs: PoseAnalogs::new(mech.n_points(), n),
            zero_deg,
            phis: Phi::table(&phis_deg),
            fixed: Vec::new(),
            last: None,
        });
        s.last = None;
        if s.zero_deg != zero_deg || s.phis.len() != n {
            (s.zero_deg, s.phis) = (zero_deg, Phi::table(&phis_deg));
        }
        mech.reset_pose(&mut s.pose, n);
        mech.solve(&s.phis, &mut s.pose)?;
        // Fixed points' analogs stay zero: reset when they are others.
        let fixed = mech.fixed_slots();
        if !s.analogs.fits(mech.n_points(), n) || s.fixed != fixed {
            s.analogs.reset_for(mech, n);
            s.fixed = fixed;
        }
        let closed = mech.analogs(&s.phis, &s.pose, &mut s.analogs).is_some();
        for &slot in slots {
            let v = if closed {
                s.analogs.vel_track(slot).to_vec()
            } else {
                Vec::new()
            };
            tracks[slot] = Some((s.pose.track(slot).to_vec(), v));
        }
        Ok(closed)
    })?;
    if !closed {
        // No closed form: the analogs by dual numbers.
        let md = mech_dual()?;
        let mut pd = md.new_pose(n);
        md.solve(&Phi::table(&phis_deg), &mut pd)?;
        for &slot in slots {
            if let Some((_, v)) = tracks[slot].as_mut() {
                *v = pd.track(slot).iter().map(|p| p.map(|c| c.eps)).collect();
            }
        }
    }
    ORGAN_SCRATCH.with_borrow_mut(|scratch| {
        if let Some(s) = scratch {
            s.last = Some(LastSampling {
                mech: mech.clone(),
                zero_deg,
                slots: slots.to_vec(),
                tracks: tracks.clone(),
            });
        }
    });
    Ok(tracks)
}

fn sampled_motion(points: Vec<V3<f64>>, slopes: Vec<V3<f64>>) -> Motion {
    Motion::Table {
        start_deg: 0.0,
        step_deg: ORGAN_STEP_DEG,
        points: Arc::from(points),
        slopes: Some(Arc::from(slopes)),
    }
}

impl Model {
    /// For each thread of the stitch (needles in order, then the looper
    /// threads), the thread path it is compared with; empty without a
    /// `[stitch]`. It does not depend on the parameters.
    pub fn stitch_paths(&self) -> Vec<Option<String>> {
        self.stitch.as_ref().map_or(Vec::new(), compared_paths)
    }

    /// The names the stitch's threads may take, which prefix their columns:
    /// the needles' own, and `needle`, `looper`, `lower` and `upper` (the
    /// lockstitch's needle thread, the looper threads of 503 and 504);
    /// empty without a `[stitch]`.
    pub fn stitch_thread_names(&self) -> Vec<String> {
        let Some(d) = &self.stitch else { return Vec::new() };
        let mut names: Vec<String> = d.needles.iter().map(|n| n.name.clone()).collect();
        names.extend(["needle", "looper", "lower", "upper"].map(String::from));
        names
    }

    /// The model's stitch process resolved with `params`, organ motions
    /// sampled from the solved mechanism; `None` when the model has no
    /// `[stitch]`.
    pub fn stitch_setup(&self, params: &Params) -> Result<Option<StitchSetup>, Error> {
        let Some(d) = &self.stitch else { return Ok(None) };
        let base: Vec<f64> = params.values.clone();
        let q = self.quantities(&base)?;
        let tilt_deg = d.tilt.map_or(0.0, |i| q[i]);
        let samples = self.sample_organs(d, &q)?;
        let needles = d
            .needles
            .iter()
            .map(|nd| needle_spec(nd, &q, &samples, tilt_deg))
            .collect();
        let looper = d.looper.as_ref().map(|l| looper_spec(l, &q, &samples, tilt_deg));
        let hook = d.hook.as_ref().map(|(h, _)| HookSpec {
            beak_radius_mm: q[h[0]],
            case_radius_mm: q[h[1]],
            offset_mm: q[h[2]],
            depth_mm: q[h[3]],
            catch_rise_mm: q[h[4]],
            cast_off_deg: q[h[5]],
        });
        let interlace = d.hook.as_ref().map_or(0.5, |(_, f)| q[*f]);
        let upper_looper = d.upper.as_ref().map(|(o, w, _)| UpperLooperSpec {
            eye: polyline_motion(o, &samples),
            pick_window_deg: *w,
        });
        let spreader = d.spreader.as_ref().map(|(o, w)| SpreaderSpec {
            eye: polyline_motion(o, &samples),
            pick_window_deg: *w,
        });
        let spec = StitchSpec {
            stitch_type: d.stitch_type,
            m_mm: q[d.m],
            t_mm: q[d.t],
            tilt_deg,
            a_e_mm: d.a_e.map_or(0.0, |i| q[i]),
            edge_split: d.edge_split,
            feed: match d.feed {
                FeedDef::Harmonic(start, duration) => FeedLaw::Harmonic {
                    start_deg: q[start],
                    duration_deg: q[duration],
                },
                FeedDef::Point(slot) => FeedLaw::Point {
                    dog: samples.motion(slot),
                },
            },
            needles,
            looper,
            hook,
            interlace,
            upper_looper,
            spreader,
            // Chain stitches have no looper-thread moments.
            moments: d.moments.unwrap_or(Moments::NONE),
            regulator: match d.regulator {
                RegulatorDef::Window([from, to]) => Regulator::Window {
                    from_deg: from - d.cyclogram_zero_deg,
                    to_deg: to - d.cyclogram_zero_deg,
                },
                RegulatorDef::BeforeTightening(w) => Regulator::BeforeTightening {
                    width_deg: w.map_or(DEFAULT_REGULATOR_WIDTH_DEG, |i| q[i]),
                },
                RegulatorDef::AtLock => Regulator::AtLock,
                RegulatorDef::Computed => Regulator::Computed,
            },
        };
        Ok(Some(StitchSetup {
            spec,
            cyclogram_zero_deg: d.cyclogram_zero_deg,
            tolerance_mm: d.tolerance_mm,
            paths: compared_paths(d),
        }))
    }

    /// The organs that are mechanism points, sampled over the cycle; the
    /// mechanism is solved only when some organ is a point.
    fn sample_organs(&self, d: &StitchDef, q: &[f64]) -> Result<OrganSamples, Error> {
        let needs_mechanism = d.needles.iter().any(|n| matches!(n.eye, OrganDef::Point(_)))
            || matches!(&d.looper, Some((OrganDef::Point(_), ..)))
            || matches!(&d.upper, Some((OrganDef::Point(_), ..)))
            || matches!(&d.spreader, Some((OrganDef::Point(_), _)))
            || matches!(d.feed, FeedDef::Point(_));
        // One mechanism, from the quantities already resolved, gives both the
        // samples and the stitch frame's placement.
        let mech = if needs_mechanism || d.frame != 0 {
            Some(super::resolve::machine(self, q, false)?.mechanism)
        } else {
            None
        };
        let tracks = match &mech {
            Some(mech) if needs_mechanism => {
                let dual = || -> Result<Mechanism<Dual64>, Error> {
                    let qd: Vec<Dual64> = q.iter().map(|&v| Dual64::from_re(v)).collect();
                    Ok(super::resolve::machine(self, &qd, false)?.mechanism)
                };
                sample_points(mech, dual, d.cyclogram_zero_deg, &organ_slots(d))?
            }
            _ => Vec::new(),
        };
        let placement = mech.as_ref().filter(|_| d.frame != 0).map(|m| m.frames[d.frame]);
        Ok(OrganSamples { tracks, placement })
    }
}

/// The mechanism points the stitch's organs move with.
fn organ_slots(d: &StitchDef) -> Vec<usize> {
    let point = |o: &OrganDef| match o {
        OrganDef::Point(s) => Some(*s),
        _ => None,
    };
    let mut slots: Vec<usize> = d.needles.iter().filter_map(|n| point(&n.eye)).collect();
    slots.extend(d.looper.as_ref().and_then(|l| point(&l.0)));
    slots.extend(d.upper.as_ref().and_then(|u| point(&u.0)));
    slots.extend(d.spreader.as_ref().and_then(|s| point(&s.0)));
    if let FeedDef::Point(s) = d.feed {
        slots.push(s);
    }
    slots
}

/// A needle's motion: its eye point set in the bar so that it stands s_B
/// above the plate at TDC (when given), or its law.
fn needle_spec(nd: &NeedleDef, q: &[f64], samples: &OrganSamples, tilt_deg: f64) -> NeedleSpec {
    let b = tilt_deg.to_radians();
    let eye = match &nd.eye {
        OrganDef::Point(slot) => {
            let (points, slopes) = samples.track(*slot);
            match nd.eye_above_plate {
                // Set the needle in its bar: shift the eye along the
                // needle so that it stands s_B above the plate at TDC.
                Some(sb) => {
                    let u_n = V3::new(0.0, -b.sin(), b.cos());
                    let eye = sampled_motion(points.clone(), slopes.clone());
                    let s_b_now = max_on_cycle(|phi| eye.at(phi).z).1 / b.cos();
                    let shift = u_n * (q[sb] - s_b_now);
                    sampled_motion(points.iter().map(|p| p + shift).collect(), slopes)
                }
                None => sampled_motion(points, slopes),
            }
        }
        OrganDef::NeedleLaw { x, s_b, stroke, bdc } => Motion::NeedleLaw {
            x_mm: q[*x],
            eye_above_plate_mm: q[*s_b],
            stroke_mm: q[*stroke],
            bdc_deg: bdc.map_or(0.0, |i| q[i]),
            tilt_deg,
        },
        _ => unreachable!("needles take a point or a needle law"),
    };
    NeedleSpec {
        name: nd.name.clone(),
        eye,
        point_below_eye_mm: nd.point_below_eye.map_or(2.0, |i| q[i]),
        catch_deg: nd.catch_deg.map(|i| q[i]),
        drop_deg: nd.drop_deg.map(|i| q[i]),
    }
}

/// The looper: its catching point (a mechanism point or its law) and body.
fn looper_spec(
    (organ, body, _): &(OrganDef, [QuantityId; 4], Option<String>),
    q: &[f64],
    samples: &OrganSamples,
    tilt_deg: f64,
) -> LooperSpec {
    let (k, a, bb, gmax) = (q[body[0]], q[body[1]], q[body[2]], q[body[3]]);
    let eye = match organ {
        OrganDef::Point(slot) => samples.motion(*slot),
        OrganDef::LooperLaw {
            stroke,
            far,
            catch,
            catch_x,
            y0,
            avoid,
            depth,
        } => Motion::LooperLaw {
            stroke_mm: q[*stroke],
            far_deg: q[*far],
            catch_deg: q[*catch],
            catch_x_mm: catch_x.map_or(0.0, |i| q[i]),
            y0_mm: y0.map_or((k + bb) * tilt_deg.to_radians().tan(), |i| q[i]),
            avoid_mm: avoid.map_or(0.0, |i| q[i]),
            depth_mm: q[*depth],
        },
        _ => unreachable!("the looper takes a point or a looper law"),
    };
    LooperSpec {
        eye,
        k_mm: k,
        a_mm: a,
        b_mm: bb,
        gamma_max_rad: gmax.to_radians(),
    }
}

/// The upper looper and the spreader: a point or a polyline law.
fn polyline_motion(o: &OrganDef, samples: &OrganSamples) -> Motion {
    match o {
        OrganDef::Point(slot) => samples.motion(*slot),
        OrganDef::Polyline { points, low, high } => Motion::PolylineLaw {
            points: points
                .iter()
                .map(|p| V3::new(p[0], p[1], p[2]))
                .collect::<Vec<_>>()
                .into(),
            low_deg: *low,
            high_deg: *high,
        },
        _ => unreachable!("the upper looper and the spreader take a point or a polyline law"),
    }
}

/// `Ok` when every thread path the stitch compares carries thread physics
/// (and there is at least one); otherwise which path does not, in words.
fn compared_paths_have_physics(f: &ModelFile, s: &StitchFile) -> Result<(), String> {
    let Some(t) = &f.thread else {
        return Err("the model has no thread paths".into());
    };
    let mut names: Vec<&str> = s.needles.iter().filter_map(|n| n.path.as_deref()).collect();
    names.extend(s.looper.as_ref().and_then(|l| l.path.as_deref()));
    names.extend(s.upper_looper.as_ref().and_then(|u| u.path.as_deref()));
    if names.is_empty() {
        return Err("the stitch compares no thread path".into());
    }
    for name in names {
        let own = t
            .paths
            .iter()
            .find(|p| p.name == name)
            .is_some_and(|p| p.physics.is_some());
        if !(own || t.physics.is_some()) {
            return Err(format!("path `{name}` has no thread physics"));
        }
    }
    Ok(())
}

/// For each thread of the spec (needles in order, then the looper threads:
/// `lower` and `upper` for 504, `looper` for 503), the thread path it is
/// compared with.
fn compared_paths(d: &StitchDef) -> Vec<Option<String>> {
    let mut paths: Vec<Option<String>> = d.needles.iter().map(|n| n.path.clone()).collect();
    if matches!(d.stitch_type, StitchType::S503 | StitchType::S504) {
        paths.push(d.looper.as_ref().and_then(|l| l.2.clone()));
    }
    if d.stitch_type == StitchType::S504 {
        paths.push(d.upper.as_ref().and_then(|u| u.2.clone()));
    }
    paths
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The organs' samples kept from the last setting are taken again only
    /// where the mechanism is the same: a setting that moves it (the
    /// MF-7923D's needle crank r2) samples afresh, and a return to the
    /// first setting, or a setting over the stitch alone (m), gives what a
    /// thread that sampled nothing before gives.
    #[test]
    fn kept_organ_samples_follow_the_mechanism() {
        let model = Model::preset("mf7923d").unwrap();
        let with = |name: &str, value: f64| {
            let mut p = model.defaults();
            model.set(&mut p, name, value).unwrap();
            p
        };
        let (base, moved, thin) = (model.defaults(), with("r2", 16.5), with("m", 1.5));
        let fresh = |p: &Params| {
            let (model, p) = (model.clone(), p.clone());
            std::thread::spawn(move || model.stitch_setup(&p).unwrap().unwrap())
                .join()
                .unwrap()
        };
        let (base_fresh, moved_fresh, thin_fresh) = (fresh(&base), fresh(&moved), fresh(&thin));
        assert_ne!(base_fresh, moved_fresh, "r2 moves the needles");
        let setup = |p: &Params| model.stitch_setup(p).unwrap().unwrap();
        assert_eq!(setup(&base), base_fresh);
        assert_eq!(setup(&moved), moved_fresh, "a moved mechanism is sampled afresh");
        assert_eq!(setup(&base), base_fresh, "and back");
        assert_eq!(setup(&thin), thin_fresh, "the stitch alone: the samples kept");
    }

    /// Every preset organ that is a mechanism point, sampled at
    /// ORGAN_STEP_DEG and joined by Hermite segments, against the mechanism
    /// solved halfway between the samples: within 10⁻⁶ mm (a linear table
    /// would need a 0.02° step for 3·10⁻⁷ mm).
    #[test]
    fn sampled_organs_follow_the_mechanism_between_their_samples() {
        let mut checked = 0;
        for preset in crate::presets::ALL {
            let model = Model::preset(preset.name).unwrap();
            let Some(d) = &model.stitch else { continue };
            let q = model.quantities(&model.defaults().values).unwrap();
            let samples = model.sample_organs(d, &q).unwrap();
            let mut slots: Vec<usize> = d
                .needles
                .iter()
                .map(|n| &n.eye)
                .chain(d.looper.as_ref().map(|l| &l.0))
                .filter_map(|o| match o {
                    OrganDef::Point(s) => Some(*s),
                    _ => None,
                })
                .collect();
            if let FeedDef::Point(s) = d.feed {
                slots.push(s);
            }
            if slots.is_empty() {
                continue;
            }
            let mech = super::super::resolve::machine::<f64>(&model, &q, false)
                .unwrap()
                .mechanism;
            let mids: Vec<f64> = (0..360).map(|k| k as f64 + 0.5).collect();
            let phis: Vec<f64> = mids.iter().map(|m| m + d.cyclogram_zero_deg).collect();
            let mut pose = mech.new_pose(phis.len());
            mech.solve(&Phi::table(&phis), &mut pose).unwrap();
            let placement = (d.frame != 0).then(|| mech.frames[d.frame]);
            for slot in slots {
                let motion = samples.motion(slot);
                let worst = mids
                    .iter()
                    .enumerate()
                    .map(|(k, &m)| {
                        let exact = placement.map_or(pose.point(slot, k), |pl| pl.to_local(pose.point(slot, k)));
                        (motion.at(m) - exact).norm()
                    })
                    .fold(0.0, f64::max);
                assert!(worst < 1e-6, "{}: point {slot} is {worst:e} mm off", preset.name);
                checked += 1;
            }
        }
        assert!(checked >= 4, "{checked} organs checked");
    }
}
