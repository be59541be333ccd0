//! Checking and compiling a `cam_follower` group: the cam, its follower and
//! the follower's lift.

use std::sync::Arc;

use super::{LoadResult, Loader};
use crate::mechanism::cam_follower::{Closure, Law, Spring};
use crate::model::file::{CamFollowerGroup, ClosureKind, ContactKind, FollowerKind, LiftFile, Value};
use crate::model::spans::KeyPath;
use crate::model::{QuantityId, StepDef};
use crate::numeric::PeriodicCubic;

/// The largest pressure angles allowed by default, deg: 30° for a
/// translating follower (its guide binds beyond), 45° for a rocking one
/// (Norton, *Design of Machinery*; Shigley & Uicker, *Theory of Machines
/// and Mechanisms*: the usual design limits).
pub const MAX_PRESSURE_TRANSLATING_DEG: f64 = 30.0;
pub const MAX_PRESSURE_ROCKING_DEG: f64 = 45.0;

/// A `cam_follower` group, its numbers still quantities of the parameters.
#[derive(Debug, Clone)]
pub(crate) struct CamFollowerDef {
    /// The group's name, or its output point's.
    pub name: String,
    pub center: usize,
    pub marker: usize,
    /// A rocking follower's pivot.
    pub pivot: Option<usize>,
    pub zero: QuantityId,
    pub base: QuantityId,
    pub contact: ContactKind,
    pub roller: Option<QuantityId>,
    pub motion: MotionDef,
    pub lift: LiftDef,
    pub closure: Closure,
    pub max_pressure_deg: f64,
    pub plane: usize,
    pub out: usize,
}

#[derive(Debug, Clone)]
pub(crate) enum MotionDef {
    /// Direction (deg) and offset (mm) of the axis.
    Translating { direction: QuantityId, offset: QuantityId },
    /// Arm (mm), side (+1 left) and a flat face's distance from the pivot
    /// (mm; zero for a roller or knife edge).
    Rocking {
        arm: QuantityId,
        sign: f64,
        face_offset: QuantityId,
    },
}

/// A lift: a table (in mm, or rad for a rocking follower) or segments
/// `(from rad, to rad, lift at the end, law)`, the lift in the file's unit
/// (mm, or deg for a rocking follower).
#[derive(Debug, Clone)]
pub(crate) enum LiftDef {
    Table(Arc<PeriodicCubic>),
    Segments(Vec<(f64, f64, QuantityId, Law)>),
}

impl Loader<'_> {
    pub(super) fn cam_follower_group(&mut self, g: &CamFollowerGroup, path: &KeyPath) -> LoadResult<StepDef> {
        let center = self.point(&g.center, &path.key("center"))?;
        let marker = self.point(&g.marker, &path.key("marker"))?;
        let zero = match &g.zero_deg {
            Some(v) => self.angle(v, path.key("zero_deg"))?,
            None => self.zero(),
        };
        let base = self.positive_length(&g.base_radius, path.key("base_radius"), "the cam's base circle radius")?;
        let roller = match (g.contact, &g.roller_radius) {
            (ContactKind::Roller, Some(r)) => {
                Some(self.positive_length(r, path.key("roller_radius"), "the roller's radius")?)
            }
            (ContactKind::Roller, None) => {
                return Err(self.err(
                    &path.key("contact"),
                    "a roller follower needs its roller's radius",
                    Some("add roller_radius = … (mm)".into()),
                ));
            }
            (_, Some(_)) => {
                return Err(self.err(
                    &path.key("roller_radius"),
                    "only a roller follower has a roller",
                    Some("write contact = \"roller\", or remove roller_radius".into()),
                ));
            }
            (_, None) => None,
        };
        let rocking = g.follower == FollowerKind::Rocking;
        let motion = self.follower_motion(g, path)?;
        let pivot = match (&g.pivot, rocking) {
            (Some(p), true) => Some(self.point(p, &path.key("pivot"))?),
            (None, true) => {
                return Err(self.err(
                    path,
                    "a rocking follower needs its pivot",
                    Some("add pivot = \"POINT\"".into()),
                ));
            }
            _ => None,
        };
        let lift = self.lift(&g.lift, rocking, &path.key("lift"))?;
        let closure = self.closure(g, path)?;
        let max_pressure_deg = match g.max_pressure_deg {
            Some(a) if a.is_finite() && a > 0.0 && a < 90.0 => a,
            Some(a) => {
                return Err(self.err(
                    &path.key("max_pressure_deg"),
                    format!("a pressure angle limit of {a}° is out of range"),
                    Some(
                        "give 0 < max_pressure_deg < 90 (30 is usual for a translating follower, 45 for a rocking one)"
                            .into(),
                    ),
                ));
            }
            None if rocking => MAX_PRESSURE_ROCKING_DEG,
            None => MAX_PRESSURE_TRANSLATING_DEG,
        };
        let plane = self.opt_frame(&g.plane, path.key("plane"))?;
        Ok(StepDef::CamFollower(Box::new(CamFollowerDef {
            name: g.name.clone().unwrap_or_else(|| g.out.clone()),
            center,
            marker,
            pivot,
            zero,
            base,
            contact: g.contact,
            roller,
            motion,
            lift,
            closure,
            max_pressure_deg,
            plane,
            out: self.point_index[&g.out],
        })))
    }

    /// How the follower moves: a translating one's axis or a rocking one's
    /// arm and side.
    fn follower_motion(&mut self, g: &CamFollowerGroup, path: &KeyPath) -> LoadResult<MotionDef> {
        let rocking = g.follower == FollowerKind::Rocking;
        Ok(if rocking {
            let flat = g.contact == ContactKind::Flat;
            for (key, given, help) in [
                (
                    "direction_deg",
                    g.direction_deg.is_some(),
                    "a rocking follower is placed by pivot, arm and branch",
                ),
                (
                    "offset",
                    g.offset.is_some() && !flat,
                    "a rocking follower is placed by pivot, arm and branch (offset places a flat face from its pivot)",
                ),
            ] {
                if given {
                    return Err(self.err(
                        &path.key(key),
                        format!("`{key}` places a translating follower's axis"),
                        Some(help.into()),
                    ));
                }
            }
            let (Some(arm), Some(branch)) = (&g.arm, g.branch) else {
                return Err(self.err(
                    path,
                    "a rocking follower needs its arm and the side its roller sits on",
                    Some("add arm = … (mm, pivot to roller centre) and branch = \"left\" or \"right\"".into()),
                ));
            };
            let arm = self.positive_length(arm, path.key("arm"), "the follower's arm")?;
            let face_offset = match &g.offset {
                Some(v) => self.length(v, path.key("offset"))?,
                None => self.zero(),
            };
            MotionDef::Rocking {
                arm,
                sign: self.side(branch, &path.key("branch"))?,
                face_offset,
            }
        } else {
            for (key, given) in [
                ("pivot", g.pivot.is_some()),
                ("arm", g.arm.is_some()),
                ("branch", g.branch.is_some()),
            ] {
                if given {
                    return Err(self.err(
                        &path.key(key),
                        format!("`{key}` belongs to a rocking follower"),
                        Some("a translating follower is placed by direction_deg and offset".into()),
                    ));
                }
            }
            let Some(direction) = &g.direction_deg else {
                return Err(self.err(
                    path,
                    "a translating follower needs the direction it lifts in",
                    Some("add direction_deg = … (deg in the plane)".into()),
                ));
            };
            let direction = self.angle(direction, path.key("direction_deg"))?;
            let offset = match &g.offset {
                Some(v) => self.length(v, path.key("offset"))?,
                None => self.zero(),
            };
            MotionDef::Translating { direction, offset }
        })
    }

    /// How the follower is kept on the cam, with a spring's figures checked.
    fn closure(&self, g: &CamFollowerGroup, path: &KeyPath) -> LoadResult<Closure> {
        Ok(match g.closure.unwrap_or(ClosureKind::Spring) {
            ClosureKind::Groove => {
                if g.spring.is_some() {
                    return Err(self.err(
                        &path.key("spring"),
                        "a follower held in a groove has no spring to check",
                        Some("remove spring, or write closure = \"spring\"".into()),
                    ));
                }
                Closure::Groove
            }
            ClosureKind::Spring => Closure::Spring(match &g.spring {
                None => None,
                Some(s) => {
                    let sp = path.key("spring");
                    for (key, v, lowest) in [
                        ("preload_n", s.preload_n, 0.0),
                        ("rate_n_per_mm", s.rate_n_per_mm, 0.0),
                        ("mass_kg", s.mass_kg, f64::MIN_POSITIVE),
                    ] {
                        if !(v.is_finite() && v >= lowest) {
                            return Err(self.err(
                                &sp.key(key),
                                format!("`{key}` = {v} must be a finite number, at least {}", lowest.max(0.0)),
                                Some(
                                    "give the spring's preload (N), rate (N/mm) and the follower's mass (kg, > 0)"
                                        .into(),
                                ),
                            ));
                        }
                    }
                    Some(Spring {
                        preload_n: s.preload_n,
                        rate_n_per_mm: s.rate_n_per_mm,
                        mass_kg: s.mass_kg,
                    })
                }
            }),
        })
    }

    fn lift(&mut self, l: &LiftFile, rocking: bool, path: &KeyPath) -> LoadResult<LiftDef> {
        let (unit, other) = if rocking { ("deg", "mm") } else { ("mm", "deg") };
        let values = if rocking { &l.deg } else { &l.mm };
        let wrong = if rocking { &l.mm } else { &l.deg };
        if wrong.is_some() {
            return Err(self.err(
                &path.key(other),
                format!(
                    "a {} follower's lift is in {unit}",
                    if rocking { "rocking" } else { "translating" }
                ),
                Some(format!("write the lift as `{unit} = [...]`")),
            ));
        }
        match (&l.angle_deg, values, &l.segments) {
            (Some(angle), Some(values), None) => {
                let ok_len = angle.len() == values.len() && angle.len() >= 4;
                let finite = angle.iter().chain(values).all(|v| v.is_finite());
                let increasing = angle.windows(2).all(|w| w[1] > w[0]);
                let one_turn = angle.first().zip(angle.last()).is_some_and(|(a, b)| b - a < 360.0);
                if !(ok_len && finite && increasing && one_turn) {
                    return Err(self.err(
                        path,
                        "a lift table is at least 4 finite points, cam angles increasing within one turn",
                        Some(format!("give angle_deg = [...] and {unit} = [...] of the same length")),
                    ));
                }
                if let Some(k) = values.iter().position(|&v| v < 0.0) {
                    return Err(self.err(
                        &path.key(unit).index(k),
                        format!("the lift {} {unit} is below the base circle", values[k]),
                        Some("measure the lift from the base circle (the cam's least radius), so it is never negative".into()),
                    ));
                }
                let scale = if rocking { std::f64::consts::PI / 180.0 } else { 1.0 };
                let rad: Vec<f64> = angle.iter().map(|a| a.to_radians()).collect();
                let s: Vec<f64> = values.iter().map(|v| v * scale).collect();
                Ok(LiftDef::Table(Arc::new(PeriodicCubic::new(&rad, &s, std::f64::consts::TAU))))
            }
            (None, None, Some(segs)) if !segs.is_empty() => {
                let mut out = Vec::with_capacity(segs.len());
                let mut from = 0.0;
                for (k, seg) in segs.iter().enumerate() {
                    let sp = path.key("segments").index(k);
                    let last = k + 1 == segs.len();
                    if !(seg.end_deg.is_finite() && seg.end_deg > from && seg.end_deg <= 360.0)
                        || (last && seg.end_deg != 360.0)
                    {
                        return Err(self.err(
                            &sp.key("end_deg"),
                            format!("segment {} ends at {}°", k + 1, seg.end_deg),
                            Some(format!(
                                "segments cover one turn in order: each ends after {from}°, the last at 360°"
                            )),
                        ));
                    }
                    let (value, key): (&Option<Value>, &str) =
                        if rocking { (&seg.lift_deg, "lift_deg") } else { (&seg.lift_mm, "lift_mm") };
                    let wrong_key = if rocking { "lift_mm" } else { "lift_deg" };
                    let wrong_given = if rocking { seg.lift_mm.is_some() } else { seg.lift_deg.is_some() };
                    if wrong_given {
                        return Err(self.err(
                            &sp.key(wrong_key),
                            format!("this follower's lift is in {unit}"),
                            Some(format!("write `{key}`")),
                        ));
                    }
                    let Some(value) = value else {
                        return Err(self.err(&sp, format!("segment {} has no lift", k + 1), Some(format!("add {key} = …"))));
                    };
                    if let Value::Number(v) = value
                        && *v < 0.0
                    {
                        return Err(self.err(
                            &sp.key(key),
                            format!("the lift {v} {unit} is below the base circle"),
                            Some("measure the lift from the base circle (the cam's least radius), so it is never negative".into()),
                        ));
                    }
                    let q = if rocking {
                        self.angle(value, sp.key(key))?
                    } else {
                        self.length(value, sp.key(key))?
                    };
                    let law = match &seg.law {
                        None => Law::Cycloidal,
                        Some(name) => Law::from_name(name).ok_or_else(|| {
                            self.err(
                                &sp.key("law"),
                                format!("unknown motion law `{name}`"),
                                Some(format!("write one of {}", Law::NAMES.join(", "))),
                            )
                        })?,
                    };
                    out.push((from.to_radians(), seg.end_deg.to_radians(), q, law));
                    from = seg.end_deg;
                }
                Ok(LiftDef::Segments(out))
            }
            _ => Err(self.err(
                path,
                "a lift is a table or segments",
                Some(format!(
                    "write lift = {{ angle_deg = [...], {unit} = [...] }} or lift = {{ segments = [{{ end_deg = …, lift_{unit} = …, law = \"cycloidal\" }}, …] }}"
                )),
            )),
        }
    }
}
