//! `[thread.physics]`: the thread sewn and the parts that hold it (its
//! stiffness and strength, the regulator's hold, a check spring, thread
//! clamps), checked on load and resolved with the parameters into
//! [`ThreadPhysics`] per path (`docs/thread-physics.md`).

use super::expr::Dim;
use super::file::{self, ThreadPhysicsFile, Value};
use super::load::{LoadResult, Loader};
use super::spans::KeyPath;
use super::{Model, Params, PathDef, QuantityId};
use crate::error::Error;
use crate::thread::tension::{ClampAt, SpringAt, ThreadPhysics};

/// A path's thread physics as loaded: quantities still expressions.
#[derive(Debug, Clone)]
pub(crate) struct PhysicsDef {
    pub thread: Option<String>,
    pub source: Option<String>,
    pub ea: (QuantityId, KeyPath),
    pub breaking: (QuantityId, KeyPath),
    pub regulator: (QuantityId, KeyPath),
    pub spring: Option<SpringDef>,
    pub clamps: Vec<ClampDef>,
}

#[derive(Debug, Clone)]
pub(crate) struct SpringDef {
    pub node: usize,
    pub take_up: QuantityId,
    pub force: SpringForce,
    pub path: KeyPath,
}

#[derive(Debug, Clone)]
pub(crate) enum SpringForce {
    Ends([QuantityId; 2]),
    Rate { preload: QuantityId, rate: QuantityId },
}

impl SpringForce {
    /// The two quantities the force is written with: its ends, or its
    /// preload and rate.
    fn quantities(&self) -> [QuantityId; 2] {
        match *self {
            SpringForce::Ends(ends) => ends,
            SpringForce::Rate { preload, rate } => [preload, rate],
        }
    }
}

#[derive(Debug, Clone)]
pub(crate) struct ClampDef {
    pub node: usize,
    pub hold: QuantityId,
    pub closed_deg: Option<[f64; 2]>,
    pub path: KeyPath,
}

/// N/mm, the unit of a check spring's rate.
const FORCE_PER_LENGTH: Dim = Dim {
    length: -1,
    angle: 0,
    force: 1,
};

impl Loader<'_> {
    /// Each path's thread physics (`None` for every path without
    /// `[thread.physics]` or a path `physics`). Every field must be given
    /// for each path that has physics, at either level; a spring or clamp
    /// must name a node of a path.
    pub(super) fn thread_physics(
        &mut self,
        t: &file::ThreadSpec,
        paths: &[PathDef],
        has_stitch: bool,
    ) -> LoadResult<Vec<Option<PhysicsDef>>> {
        let root = KeyPath::root().key("thread");
        let any_path = t.paths.iter().any(|p| p.physics.is_some());
        if t.physics.is_none() && !any_path {
            return Ok(vec![None; paths.len()]);
        }
        let top_path = root.key("physics");
        if t.tension_n.is_some() {
            return Err(self.err(
                &root.key("tension_n"),
                "`tension_n` estimates the tension by the capstan law alone; with thread physics the tension is solved",
                Some("remove `tension_n`: the regulator's hold is `regulator_n` in [thread.physics]".into()),
            ));
        }
        if !has_stitch {
            let at = if t.physics.is_some() {
                top_path.clone()
            } else {
                root.key("paths")
            };
            return Err(self.err(
                &at,
                "the thread's tension is solved against the stitch it feeds, and this model has no [stitch]",
                Some("add a [stitch] table whose threads name these paths, or remove the thread physics".into()),
            ));
        }
        let top = t.physics.clone().unwrap_or_default();
        // Clamps and a spring given at the top must each find a path.
        self.placed_somewhere(&top, &top_path, paths)?;
        let mut out = Vec::with_capacity(paths.len());
        for (k, (tp, def)) in t.paths.iter().zip(paths).enumerate() {
            let own_path = root.key("paths").index(k).key("physics");
            if tp.physics.is_none() && t.physics.is_none() {
                out.push(None);
                continue;
            }
            let own = tp.physics.clone().unwrap_or_default();
            out.push(Some(self.path_physics(&top, &top_path, &own, &own_path, def)?));
        }
        Ok(out)
    }

    /// Every top-level clamp and spring names a node some path passes.
    fn placed_somewhere(&self, top: &ThreadPhysicsFile, at: &KeyPath, paths: &[PathDef]) -> LoadResult<()> {
        let inner = |name: &str| {
            paths.iter().any(|p| {
                p.node_names[1..p.node_names.len().saturating_sub(1)]
                    .iter()
                    .any(|n| n == name)
            })
        };
        for (i, c) in top.clamps.iter().enumerate() {
            if !inner(&c.at) {
                return Err(self.err(
                    &at.key("clamps").index(i).key("at"),
                    format!(
                        "the clamp's guide `{}` is not between the regulator and the eye of any path",
                        c.at
                    ),
                    Some("name a guide the thread passes (a node of a path other than its first and last)".into()),
                ));
            }
        }
        if let Some(s) = &top.check_spring
            && !paths.iter().any(|p| {
                p.node_names[..p.node_names.len().saturating_sub(1)]
                    .iter()
                    .any(|n| n == &s.after)
            })
        {
            return Err(self.err(
                &at.key("check_spring").key("after"),
                format!(
                    "the check spring's node `{}` is on no path (or only as its eye)",
                    s.after
                ),
                Some("name the node the spring follows, e.g. the regulator's (the path's first node)".into()),
            ));
        }
        Ok(())
    }

    /// One path's physics: its own fields over the top-level ones.
    fn path_physics(
        &mut self,
        top: &ThreadPhysicsFile,
        top_path: &KeyPath,
        own: &ThreadPhysicsFile,
        own_path: &KeyPath,
        path: &PathDef,
    ) -> LoadResult<PhysicsDef> {
        let pick = |own_v: &Option<Value>, top_v: &Option<Value>, key: &str| match (own_v, top_v) {
            (Some(v), _) => Some((v.clone(), own_path.key(key))),
            (None, Some(v)) => Some((v.clone(), top_path.key(key))),
            (None, None) => None,
        };
        let force = |ld: &mut Loader<'_>, key: &str, what: &str, example: &str| -> LoadResult<(QuantityId, KeyPath)> {
            let (own_v, top_v) = match key {
                "ea_n" => (&own.ea_n, &top.ea_n),
                "breaking_n" => (&own.breaking_n, &top.breaking_n),
                _ => (&own.regulator_n, &top.regulator_n),
            };
            let Some((v, p)) = pick(own_v, top_v, key) else {
                return Err(ld.err(
                    top_path,
                    format!("the thread physics of path `{}` has no {what} (`{key}`)", path.name),
                    Some(format!(
                        "give `{key}` in [thread.physics] or in the path's `physics`, e.g. {example}"
                    )),
                ));
            };
            Ok((ld.qty(&v, Some(Dim::FORCE), p.clone())?, p))
        };
        let ea = force(self, "ea_n", "stiffness EA", "ea_n = 85 (tex 30 spun polyester)")?;
        let breaking = force(self, "breaking_n", "breaking force", "breaking_n = 10.5")?;
        let regulator = force(self, "regulator_n", "regulator hold", "regulator_n = 0.9")?;
        let spring = match (&own.check_spring, &top.check_spring) {
            (Some(s), _) => self.spring(s, &own_path.key("check_spring"), path, true)?,
            (None, Some(s)) => self.spring(s, &top_path.key("check_spring"), path, false)?,
            (None, None) => None,
        };
        let mut clamps = Vec::new();
        for (list, at, is_own) in [(&top.clamps, top_path, false), (&own.clamps, own_path, true)] {
            for (i, c) in list.iter().enumerate() {
                let cp = at.key("clamps").index(i);
                let inner = 1..path.node_names.len().saturating_sub(1);
                let Some(node) = inner.clone().find(|&n| path.node_names[n] == c.at) else {
                    // A top-level clamp holds on the paths that pass its guide.
                    if is_own {
                        return Err(self.err(
                            &cp.key("at"),
                            format!(
                                "the clamp's guide `{}` is not between the regulator and the eye of path `{}`",
                                c.at, path.name
                            ),
                            Some(format!("name one of its guides: {}", path.node_names[inner].join(", "))),
                        ));
                    }
                    continue;
                };
                let hold = self.qty(&c.hold_n, Some(Dim::FORCE), cp.key("hold_n"))?;
                if let Some([a, b]) = c.closed_deg
                    && !(a.is_finite() && b.is_finite() && b > a && b - a <= 360.0)
                {
                    return Err(self.err(
                        &cp.key("closed_deg"),
                        format!("the clamp is closed over [{a}, {b}]°, not a stretch of one turn"),
                        Some("give [from, to] in the model's φ with from < to ≤ from + 360, e.g. [300, 420]".into()),
                    ));
                }
                clamps.push(ClampDef {
                    node,
                    hold,
                    closed_deg: c.closed_deg,
                    path: cp,
                });
            }
        }
        Ok(PhysicsDef {
            thread: own.thread.clone().or_else(|| top.thread.clone()),
            source: own.source.clone().or_else(|| top.source.clone()),
            ea,
            breaking,
            regulator,
            spring,
            clamps,
        })
    }

    /// A check spring on `path`: `None` when the path does not pass its
    /// node (a top-level spring), an error when the path's own spring names
    /// a node it lacks.
    fn spring(
        &mut self,
        s: &file::CheckSpringFile,
        at: &KeyPath,
        path: &PathDef,
        own: bool,
    ) -> LoadResult<Option<SpringDef>> {
        let last = path.node_names.len().saturating_sub(1);
        let Some(node) = (0..last).find(|&n| path.node_names[n] == s.after) else {
            if own {
                return Err(self.err(
                    &at.key("after"),
                    format!(
                        "the check spring's node `{}` is not a node of path `{}` before its eye",
                        s.after, path.name
                    ),
                    Some(format!("name one of: {}", path.node_names[..last].join(", "))),
                ));
            }
            return Ok(None);
        };
        let take_up = self.qty(&s.take_up_mm, Some(Dim::LENGTH), at.key("take_up_mm"))?;
        let force = match (&s.force_n, &s.preload_n, &s.rate_n_per_mm) {
            (Some([a, b]), None, None) => SpringForce::Ends([
                self.qty(a, Some(Dim::FORCE), at.key("force_n").index(0))?,
                self.qty(b, Some(Dim::FORCE), at.key("force_n").index(1))?,
            ]),
            (None, Some(p), Some(r)) => SpringForce::Rate {
                preload: self.qty(p, Some(Dim::FORCE), at.key("preload_n"))?,
                rate: self.qty(r, Some(FORCE_PER_LENGTH), at.key("rate_n_per_mm"))?,
            },
            _ => {
                return Err(self.err(
                    at,
                    "a check spring's force is given one way: `force_n = [start, end]`, or `preload_n` with `rate_n_per_mm`",
                    Some("e.g. force_n = [0.25, 0.45] (N of thread tension at the start and the end of its travel)".into()),
                ));
            }
        };
        Ok(Some(SpringDef {
            node,
            take_up,
            force,
            path: at.clone(),
        }))
    }
}

impl Model {
    /// Whether the model's thread paths carry thread physics.
    pub fn has_thread_physics(&self) -> bool {
        self.threads
            .as_ref()
            .is_some_and(|t| t.physics.iter().any(Option::is_some))
    }

    /// Whether parameter `name` sets the thread or the parts that hold it
    /// (it appears in `[thread.physics]`): a thread setting, which a tuning
    /// adjusts only when named.
    pub fn is_thread_setting(&self, name: &str) -> bool {
        let Some(i) = self.param_index(name) else { return false };
        let Some(t) = &self.threads else { return false };
        let mut used = Vec::new();
        for d in t.physics.iter().flatten() {
            let mut qs = vec![d.ea.0, d.breaking.0, d.regulator.0];
            if let Some(sp) = &d.spring {
                qs.push(sp.take_up);
                qs.extend(sp.force.quantities());
            }
            qs.extend(d.clamps.iter().map(|c| c.hold));
            for q in qs {
                self.exprs[q].params(&mut used);
            }
        }
        used.contains(&i)
    }

    /// Each thread path's physics resolved with `params` (in path order;
    /// `None` for a path without), every value checked in range with its
    /// place in the file.
    pub fn thread_physics(&self, params: &Params) -> Result<Vec<Option<ThreadPhysics>>, Error> {
        let Some(t) = &self.threads else { return Ok(Vec::new()) };
        if !self.has_thread_physics() {
            return Ok(vec![None; t.physics.len()]);
        }
        let q = self.quantities(&params.values)?;
        t.physics
            .iter()
            .map(|d| {
                d.as_ref()
                    .map(|d| self.resolve_physics(d, &q, &params.values))
                    .transpose()
            })
            .collect()
    }

    /// One path's physics from the quantities `q`; `values` are the
    /// parameters they were evaluated with (named in an error).
    fn resolve_physics(&self, d: &PhysicsDef, q: &[f64], values: &[f64]) -> Result<ThreadPhysics, Error> {
        let positive = |(i, p): &(QuantityId, KeyPath), what: &str, help: &str| {
            let v = q[*i];
            if v > 0.0 {
                Ok(v)
            } else {
                Err(self.error_at(p, format!("{what} must be positive, got {v} N"), Some(help.into())))
            }
        };
        let ea_n = positive(
            &d.ea,
            "the thread's stiffness EA",
            "EA is the tension per unit strain, e.g. 85 N for tex 30 spun polyester (docs/thread-physics.md)",
        )?;
        let breaking_n = positive(
            &d.breaking,
            "the breaking force",
            "e.g. 10.5 N for tex 30 spun polyester",
        )?;
        let regulator_n = positive(
            &d.regulator,
            "the regulator's hold",
            "the tension past the discs at which thread passes, e.g. 0.9 N",
        )?;
        let spring = d
            .spring
            .as_ref()
            .map(|s| self.resolve_spring(s, q, values))
            .transpose()?;
        let clamps = d
            .clamps
            .iter()
            .map(|c| {
                let hold_n = q[c.hold];
                if hold_n < 0.0 {
                    return Err(self.error_at(
                        &c.path.key("hold_n"),
                        format!("a clamp's hold must not be negative, got {hold_n} N"),
                        Some("give the force it holds the thread with, e.g. 0.3 N (Juki MH-481: 0.69–0.98 N)".into()),
                    ));
                }
                Ok(ClampAt {
                    node: c.node,
                    hold_n,
                    closed_deg: c.closed_deg,
                })
            })
            .collect::<Result<_, Box<_>>>()?;
        Ok(ThreadPhysics {
            thread: d.thread.clone(),
            source: d.source.clone(),
            ea_n,
            breaking_n,
            regulator_n,
            spring,
            clamps,
        })
    }

    fn resolve_spring(
        &self,
        s: &SpringDef,
        q: &[f64],
        values: &[f64],
    ) -> Result<SpringAt, Box<crate::error::ModelError>> {
        let take_up_mm = q[s.take_up];
        if take_up_mm <= 0.0 {
            return Err(self.error_at(
                &s.path.key("take_up_mm"),
                format!("the check spring's take-up must be positive, got {take_up_mm} mm"),
                Some("give the thread it stores over its travel, e.g. 8 mm (Juki SC-916: 6–10 mm)".into()),
            ));
        }
        let force_n = match s.force {
            SpringForce::Ends([a, b]) => [q[a], q[b]],
            SpringForce::Rate { preload, rate } => [q[preload], q[preload] + q[rate] * take_up_mm],
        };
        if !(force_n[0] >= 0.0 && force_n[1] > force_n[0]) {
            // The parameters the two ends are written with, where the file
            // sets them by name: what a user moved to get here.
            let mut used = Vec::new();
            for q in s.force.quantities() {
                self.exprs[q].params(&mut used);
            }
            used.sort_unstable();
            used.dedup();
            let names: Vec<String> = used
                .iter()
                .map(|&i| match (&self.params[i], values.get(i)) {
                    (p, Some(&v)) if !p.is_derived() => {
                        format!("{} = {} {}", p.name, crate::format::fmt_decimals(v, 3), p.unit.as_str())
                    }
                    (p, _) => p.name.clone(),
                })
                .collect();
            let from = if names.is_empty() {
                String::new()
            } else {
                format!(" (from {})", names.join(", "))
            };
            return Err(self.error_at(
                &s.path,
                format!(
                    "the check spring's force runs {} → {} N over its travel{from}; it must start at 0 N or more and rise",
                    crate::format::fmt_decimals(force_n[0], 3),
                    crate::format::fmt_decimals(force_n[1], 3)
                ),
                Some(
                    "the force at the end of its travel above the one at its start, e.g. force_n = [0.25, 0.45] \
                     (the makers' 0.25–0.5 N), or preload_n ≥ 0 with rate_n_per_mm > 0"
                        .into(),
                ),
            ));
        }
        Ok(SpringAt {
            node: s.node,
            take_up_mm,
            force_n,
        })
    }
}
