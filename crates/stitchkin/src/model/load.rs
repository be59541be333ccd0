//! Checking a [`ModelFile`] and compiling it into a [`Model`]: names resolved
//! to slots, expressions parsed and unit-checked, groups put in solve order.

use std::collections::{BTreeMap, HashMap};
use std::sync::Arc;

use super::expr::{Dim, Dimension, Expr, ExprError};
use super::file::{self, Axis, Branch, FixedPoint, Group, ModelFile, ModelUnits, ParamKind, Unit, Value};
use super::spans::{KeyPath, SpanIndex};
use super::{
    AxisDef, CamContactDef, CamDef, ClosureDef, FrameDef, MeasureDef, ParamDef, PathDef, PointKind, ProfileDef,
    QuantityId, SpanDef, StepDef, ThreadsDef,
};
use crate::error::{ModelError, did_you_mean};

pub(crate) mod cam_follower;

/// Reserved words that cannot name a parameter.
const RESERVED: &[&str] = &[
    "pi", "sin", "cos", "tan", "asin", "acos", "atan", "atan2", "sqrt", "abs", "hypot", "min", "max",
];

pub(super) struct Loader<'a> {
    file_name: String,
    text: Arc<str>,
    spans: SpanIndex<'a>,
    pub(super) params: Vec<ParamDef>,
    param_index: HashMap<String, usize>,
    pub(super) exprs: Vec<Expr>,
    /// Quantities that must come out positive: (quantity, path, what).
    pub(super) positive: Vec<(QuantityId, KeyPath, &'static str)>,
    /// Angles that must stay within ± a bound, deg (the bound excluded).
    pub(super) within: Vec<(QuantityId, KeyPath, &'static str, f64)>,
    pub(super) expr_paths: Vec<KeyPath>,
    pub(super) frames: Vec<FrameDef>,
    frame_index: HashMap<String, usize>,
    pub(super) points: Vec<(String, PointKind)>,
    point_index: HashMap<String, usize>,
    /// The units the file's parameters and expressions are written in.
    pub(super) units: ModelUnits,
    /// The one quantity 0 every omitted coordinate, offset or radius reads
    /// (so two pieces of thread around one pin are one piece).
    zero: Option<QuantityId>,
}

/// What loading a part of the model gives: the part, or the place in the file
/// that is wrong.
pub(super) type LoadResult<T> = Result<T, Box<ModelError>>;

impl<'a> Loader<'a> {
    pub(super) fn new(file_name: &str, text: &'a str) -> Self {
        Loader {
            file_name: file_name.to_string(),
            text: Arc::from(text),
            spans: SpanIndex::new(text),
            params: Vec::new(),
            param_index: HashMap::new(),
            exprs: Vec::new(),
            positive: Vec::new(),
            within: Vec::new(),
            expr_paths: Vec::new(),
            frames: Vec::new(),
            frame_index: HashMap::new(),
            points: Vec::new(),
            point_index: HashMap::new(),
            units: ModelUnits::default(),
            zero: None,
        }
    }

    pub(super) fn err(&self, path: &KeyPath, message: impl Into<String>, help: Option<String>) -> Box<ModelError> {
        Box::new(ModelError {
            file: self.file_name.clone(),
            text: self.text.clone(),
            span: self.spans.find(path),
            path: path.to_string(),
            message: message.into(),
            help,
        })
    }

    fn toml_err(&self, e: toml::de::Error) -> Box<ModelError> {
        let mut msg = e.message().trim().to_string();
        // serde's words for a value of none of an untagged enum's forms, and
        // the parser's for nesting, said in the file's terms.
        let untagged = [
            ("untagged enum FixedPoint", "a fixed point"),
            ("untagged enum Node", "a thread-path node"),
            ("untagged enum Axis", "an axis"),
            ("untagged enum Value", "a value"),
        ]
        .into_iter()
        .find(|(serde_name, _)| msg.contains(serde_name));
        if let Some((_, what)) = untagged {
            msg = format!("this is not {what} in any of the forms it can take");
        }
        if msg.contains("recursion limit") || msg.contains("max recursion depth") {
            msg = "the file nests tables or arrays too deeply to read".into();
        }
        let help = if msg.contains("too deeply") {
            Some("a model file nests a few levels at most; look for a run of `[` or `{` that is never closed".into())
        } else if msg.contains("a fixed point") {
            Some(
                "a fixed point is `[x, y]` or `[x, y, z]` in mm (numbers or expressions in quotes), or \
                  `{ frame = \"F\", at = [x, y, z] }`; a missing table header can also put a point's line under \
                  the wrong table"
                    .to_string(),
            )
        } else if msg.contains("an axis") {
            Some(
                "an axis is `\"x\"`, `\"y\"`, `\"z\"`, a frame's axis such as `\"guide.y\"`, or a direction \
                  `[x, y, z]`"
                    .to_string(),
            )
        } else if msg.contains("unknown field") {
            Some("check the spelling against docs/model-format.md or `stitchkin schema`".to_string())
        } else if msg.contains("missing field") {
            Some("add the field; docs/model-format.md lists what each table needs".to_string())
        } else if msg.contains("unknown variant") {
            Some(unknown_variant_help(&msg))
        } else if msg.contains("a thread-path node") {
            Some("a node is a point name or a table: { at = \"G\" }, { pin = \"G\", axis = \"z\", wrap = \"cw\" } or { cam = \"C\", contact = \"exact\" | \"offset\", … }; check its keys and word values".to_string())
        } else if msg.contains("did not match any variant") || msg.contains("not a value") {
            Some("write a number, an expression in quotes, or a list of coordinates".to_string())
        } else {
            // The TOML itself does not parse here.
            Some(
                "a model file is TOML: table headers `[name]` or `[[name]]`, lines `key = value`, words in \
                 quotes, lists in `[ ]`, inline tables in `{ }` on one line; docs/model-format.md §2 shows a \
                 whole first model"
                    .to_string(),
            )
        };
        Box::new(ModelError {
            file: self.file_name.clone(),
            text: self.text.clone(),
            span: e.span(),
            path: String::new(),
            message: msg,
            help,
        })
    }

    pub(super) fn parse(&self, text: &str) -> LoadResult<ModelFile> {
        toml::from_str::<ModelFile>(text).map_err(|e| self.toml_err(e))
    }

    // ---- parameters -------------------------------------------------------

    pub(super) fn parameters(&mut self, f: &ModelFile) -> LoadResult<Vec<usize>> {
        self.units = f.model.units.unwrap_or_default();
        for (name, p) in &f.parameters {
            let path = KeyPath::root().key("parameters").key(name);
            self.param_unit(p.unit, &path)?;
            if !is_ident(name) {
                return Err(self.err(
                    &path,
                    format!("`{name}` is not a valid parameter name"),
                    Some("names start with a letter or `_` and use letters, digits and `_`".into()),
                ));
            }
            if RESERVED.contains(&name.as_str()) {
                return Err(self.err(
                    &path,
                    format!("`{name}` is a reserved word"),
                    Some("choose another name".into()),
                ));
            }
            match (p.value, &p.expr) {
                (Some(_), Some(_)) => {
                    return Err(self.err(
                        &path,
                        "a parameter has either `value` or `expr`, not both",
                        Some("keep `value` for a settable number, `expr` for a derived one".into()),
                    ));
                }
                (None, None) => {
                    return Err(self.err(
                        &path,
                        "the parameter has no `value`",
                        Some(format!("write e.g. `{name} = {{ value = 10, unit = \"mm\" }}`")),
                    ));
                }
                _ => {}
            }
            if let Some(v) = p.value
                && !v.is_finite()
            {
                return Err(self.err(&path.key("value"), "the value must be a finite number", None));
            }
            if let Some([lo, hi]) = p.range {
                let rp = path.key("range");
                if !(lo.is_finite() && hi.is_finite() && lo <= hi) {
                    return Err(self.err(&rp, "the range must be [min, max] with min ≤ max", None));
                }
                if p.expr.is_some() {
                    return Err(self.err(
                        &rp,
                        "a derived parameter (with `expr`) cannot have a range",
                        Some("put the range on the parameters it is derived from".into()),
                    ));
                }
                if let Some(v) = p.value
                    && (v < lo || v > hi)
                {
                    return Err(self.err(
                        &path.key("value"),
                        format!("the value {v} is outside the parameter's range [{lo}, {hi}]"),
                        Some("widen the range or correct the value".into()),
                    ));
                }
            }
            self.describing_words(name, p, &path)?;
            self.param_index.insert(name.clone(), self.params.len());
            self.params.push(ParamDef {
                name: name.clone(),
                unit: p.unit,
                value: p.value,
                expr: None,
                range: p.range,
                source: p.source.clone(),
                provenance: p.provenance,
                // Resolved once the stitch and the thread are read
                // (`Loader::param_kinds`).
                kind: p.kind.unwrap_or(ParamKind::Dimension),
                kind_declared: p.kind.is_some(),
                label: p.label.clone(),
                what: p.what.clone(),
                increase: p.increase.clone(),
                decrease: p.decrease.clone(),
            });
        }
        // Derived parameters: parse, check units, order.
        for (name, p) in &f.parameters {
            if let Some(src) = &p.expr {
                let path = KeyPath::root().key("parameters").key(name).key("expr");
                let e = self.parse_expr(src, &path)?;
                let want = unit_dim(p.unit);
                self.check_dim(&e, want, &path, src)?;
                let i = self.param_index[name];
                self.params[i].expr = Some(e);
            }
        }
        self.param_order()
    }

    /// A parameter's length or angle unit is the model's (`[model] units`).
    fn param_unit(&self, unit: Unit, path: &KeyPath) -> LoadResult<()> {
        let (model_unit, key, what) = match unit_dim(unit) {
            Some(Dim::LENGTH) => (self.units.length.unit(), "length", "lengths"),
            Some(Dim::ANGLE) => (self.units.angle.unit(), "angle", "angles"),
            _ => return Ok(()),
        };
        if unit == model_unit {
            return Ok(());
        }
        let declared = if self.units == ModelUnits::default() {
            "the model declares no `units`, so its".to_string()
        } else {
            "the model's".to_string()
        };
        Err(self.err(
            &path.key("unit"),
            format!(
                "the parameter is in {} but {declared} {what} are in {} ([model] units.{key})",
                unit.as_str(),
                model_unit.as_str()
            ),
            Some(format!(
                "a model is written in one length unit and one angle unit: write `unit = \"{}\"` with the value in \
                 {}, or set `units = {{ {key} = \"{}\" }}` in [model] and write every {} of the model in it",
                model_unit.as_str(),
                model_unit.as_str(),
                unit.as_str(),
                &what[..what.len() - 1]
            )),
        ))
    }

    /// A parameter's `label`, `what`, `increase` and `decrease`: words, not
    /// blanks; `increase` and `decrease` together, on a value parameter.
    fn describing_words(&self, name: &str, p: &file::Parameter, path: &KeyPath) -> LoadResult<()> {
        for (key, text) in [
            ("label", &p.label),
            ("what", &p.what),
            ("increase", &p.increase),
            ("decrease", &p.decrease),
        ] {
            if let Some(t) = text
                && t.trim().is_empty()
            {
                return Err(self.err(
                    &path.key(key),
                    format!("`{key}` is empty"),
                    Some(format!("write the words, or leave `{key}` out")),
                ));
            }
        }
        if let Some(l) = &p.label
            && l.contains('\n')
        {
            return Err(self.err(
                &path.key("label"),
                "a label is one line",
                Some("keep the label short (the part's name) and put the sentence in `what`".into()),
            ));
        }
        match (&p.increase, &p.decrease) {
            (Some(_), None) | (None, Some(_)) => {
                let (given, missing) = if p.increase.is_some() {
                    ("increase", "decrease")
                } else {
                    ("decrease", "increase")
                };
                return Err(self.err(
                    &path.key(given),
                    format!("`{given}` is given without `{missing}`"),
                    Some(format!(
                        "give both: what a technician does to raise `{name}` and to lower it"
                    )),
                ));
            }
            (Some(_), Some(_)) if p.expr.is_some() => {
                return Err(self.err(
                    &path.key("increase"),
                    "a derived parameter (with `expr`) is not set, so it has no `increase` or `decrease`",
                    Some("put them on the parameters it is derived from".into()),
                ));
            }
            _ => {}
        }
        Ok(())
    }

    /// Every parameter's kind: as declared, checked against what the model
    /// does with it, or the default (`docs/model-format.md` §4). Runs once
    /// the stitch and the thread are read.
    pub(super) fn param_kinds(&mut self, f: &ModelFile, threads: Option<&ThreadsDef>) -> LoadResult<()> {
        // The stitch's thickness and length, by the names its values give.
        let mut stitch_inputs: Vec<(usize, &'static str, &'static str)> = Vec::new();
        if let Some(st) = &f.stitch {
            for (v, key, what) in [
                (&st.m_mm, "m_mm", "material thickness"),
                (&st.t_mm, "t_mm", "stitch length"),
            ] {
                if let Value::Expr(e) = v
                    && let Some(&i) = self.param_index.get(e.trim())
                {
                    stitch_inputs.push((i, key, what));
                }
            }
        }
        // The thread's own properties: its stiffness and breaking force.
        let mut thread_inputs = Vec::new();
        for d in threads.iter().flat_map(|t| t.physics.iter().flatten()) {
            for q in [d.ea.0, d.breaking.0] {
                self.exprs[q].params(&mut thread_inputs);
            }
        }
        let declared: Vec<Option<ParamKind>> = f.parameters.values().map(|p| p.kind).collect();
        for (i, kind) in declared.into_iter().enumerate() {
            let p = &self.params[i];
            let path = KeyPath::root().key("parameters").key(&p.name);
            let stitch_input = stitch_inputs.iter().find(|s| s.0 == i);
            let ranged = p.range.is_some_and(|[lo, hi]| lo < hi);
            let resolved = match kind {
                None if stitch_input.is_some() || thread_inputs.contains(&i) => ParamKind::Input,
                None if p.is_derived() => ParamKind::Dimension,
                None if ranged => ParamKind::Setting,
                None => ParamKind::Dimension,
                Some(k) => {
                    let at = path.key("kind");
                    if p.is_derived() && k != ParamKind::Dimension {
                        return Err(self.err(
                            &at,
                            format!(
                                "`{}` is derived (with `expr`), so nothing sets it: it cannot be a {}",
                                p.name,
                                k.describe()
                            ),
                            Some("write kind = \"dimension\" or leave `kind` out".into()),
                        ));
                    }
                    if let Some((_, key, what)) = stitch_input
                        && k != ParamKind::Input
                    {
                        return Err(self.err(
                            &at,
                            format!(
                                "`{}` is the stitch's {what} ([stitch] {key}), a job input, not a {}",
                                p.name,
                                k.describe()
                            ),
                            Some("write kind = \"input\" or leave `kind` out".into()),
                        ));
                    }
                    if k == ParamKind::Setting && !ranged {
                        return Err(self.err(
                            &at,
                            format!("`{}` is a machine setting but has no range to be set in", p.name),
                            Some(
                                "give `range = [lo, hi]` (lo < hi), the travel the machine allows, or write kind = \"dimension\""
                                    .into(),
                            ),
                        ));
                    }
                    k
                }
            };
            self.params[i].kind = resolved;
        }
        Ok(())
    }

    fn param_order(&self) -> LoadResult<Vec<usize>> {
        // Kahn's algorithm over "derived parameter reads parameter" edges.
        let n = self.params.len();
        let mut deps: Vec<Vec<usize>> = vec![Vec::new(); n];
        for (i, p) in self.params.iter().enumerate() {
            if let Some(e) = &p.expr {
                e.params(&mut deps[i]);
            }
        }
        let mut done = vec![false; n];
        let mut order = Vec::with_capacity(n);
        loop {
            let before = order.len();
            for i in 0..n {
                if !done[i] && deps[i].iter().all(|&d| done[d]) {
                    done[i] = true;
                    order.push(i);
                }
            }
            if order.len() == n {
                return Ok(order);
            }
            if order.len() == before {
                let cyc: Vec<&str> = (0..n)
                    .filter(|&i| !done[i])
                    .map(|i| self.params[i].name.as_str())
                    .collect();
                let path = KeyPath::root().key("parameters").key(cyc[0]).key("expr");
                return Err(self.err(
                    &path,
                    format!("derived parameters depend on each other in a loop: {}", cyc.join(", ")),
                    Some("give one of them a plain `value`".into()),
                ));
            }
        }
    }

    /// Parses an expression; its trigonometric functions take and give
    /// the model's angle unit.
    fn parse_expr(&self, src: &str, path: &KeyPath) -> LoadResult<Expr> {
        let lookup = |n: &str| self.param_index.get(n).copied();
        let e = Expr::parse(src, &lookup).map_err(|e| self.expr_err(e, src, path))?;
        Ok(e.with_angle_unit(self.units.angle.deg()))
    }

    /// The names of the model's length and angle units, for messages.
    fn unit_names(&self) -> (&'static str, &'static str) {
        (self.units.length.unit().as_str(), self.units.angle.unit().as_str())
    }

    fn expr_err(&self, e: ExprError, src: &str, path: &KeyPath) -> Box<ModelError> {
        let mut help = e.help.clone();
        if e.message.starts_with("unknown parameter") {
            let name = &src[e.at.clone()];
            help = Some(match did_you_mean(name, self.param_index.keys().map(String::as_str)) {
                Some(s) => format!("did you mean `{s}`? Parameters are defined in [parameters]"),
                None => "define it in [parameters], e.g. `NAME = { value = 10, unit = \"mm\" }`".into(),
            });
        }
        let mut err = self.err(path, format!("in `{src}`: {}", e.message), help);
        // Narrow the span to the offending token inside a plain string.
        if let Some(span) = &err.span {
            let raw = &self.text[span.clone()];
            if (raw.starts_with('"') || raw.starts_with('\'')) && raw.len() >= 2 && &raw[1..raw.len() - 1] == src {
                let start = span.start + 1 + e.at.start;
                err.span = Some(start..(span.start + 1 + e.at.end).max(start + 1));
            }
        }
        err
    }

    fn check_dim(&self, e: &Expr, want: Option<Dim>, path: &KeyPath, src: &str) -> LoadResult<()> {
        let pd = |i: usize| unit_dim(self.params[i].unit).unwrap_or(Dim::ONE);
        let names = self.unit_names();
        match e.dimension_in(&pd, names) {
            Err(m) => Err(self.err(
                path,
                format!("in `{src}`: {m}"),
                Some("check the units of the parameters used".into()),
            )),
            Ok(Dimension::Is(d)) if want.is_some_and(|w| w != d) => {
                let w = want.unwrap_or(Dim::ONE);
                Err(self.err(
                    path,
                    format!(
                        "`{src}` is in {} but {} is expected here",
                        d.unit_in(names),
                        w.unit_in(names)
                    ),
                    Some(format!("use a quantity in {}", w.unit_in(names))),
                ))
            }
            Ok(_) => Ok(()),
        }
    }

    /// Compiles a value expected in dimension `want` (`None`: any), in
    /// the unit results are computed in (mm, deg, N): an expression of
    /// parameters is in the model's units and converted; a number, or an
    /// expression of numbers alone, is in the unit the field's name
    /// carries (`*_mm`, `*_deg`, …), else in the model's and converted.
    pub(super) fn qty(&mut self, v: &Value, want: Option<Dim>, path: KeyPath) -> LoadResult<QuantityId> {
        let (e, of_params) = match v {
            Value::Number(x) => {
                if !x.is_finite() {
                    return Err(self.err(&path, "the value must be a finite number", None));
                }
                (Expr::Num(*x), false)
            }
            Value::Expr(src) => {
                let e = self.parse_expr(src, &path)?;
                self.check_dim(&e, want, &path, src)?;
                let pd = |i: usize| unit_dim(self.params[i].unit).unwrap_or(Dim::ONE);
                let of_params = matches!(e.dimension(&pd), Ok(Dimension::Is(_)));
                (e, of_params)
            }
        };
        let factor = match want {
            Some(d) if of_params || !path.names_its_unit() => self.to_result_unit(d),
            _ => 1.0,
        };
        let e = if factor == 1.0 {
            e
        } else {
            Expr::Mul(Box::new(e), Box::new(Expr::Num(factor)))
        };
        self.exprs.push(e);
        self.expr_paths.push(path);
        Ok(self.exprs.len() - 1)
    }

    /// How many mm, deg and N one of the model's units of dimension `d` is.
    fn to_result_unit(&self, d: Dim) -> f64 {
        self.units.length.mm().powi(d.length.into()) * self.units.angle.deg().powi(d.angle.into())
    }

    pub(super) fn length(&mut self, v: &Value, path: KeyPath) -> LoadResult<QuantityId> {
        self.qty(v, Some(Dim::LENGTH), path)
    }

    pub(super) fn positive_length(&mut self, v: &Value, path: KeyPath, what: &'static str) -> LoadResult<QuantityId> {
        let q = self.qty(v, Some(Dim::LENGTH), path.clone())?;
        self.positive.push((q, path, what));
        Ok(q)
    }

    /// An angle that must stay strictly within ±`max_deg`, checked (with
    /// its place in the file) whenever the parameters change.
    pub(super) fn angle_within(
        &mut self,
        v: &Value,
        path: KeyPath,
        what: &'static str,
        max_deg: f64,
    ) -> LoadResult<QuantityId> {
        let q = self.angle(v, path.clone())?;
        self.within.push((q, path, what, max_deg));
        Ok(q)
    }

    pub(super) fn angle(&mut self, v: &Value, path: KeyPath) -> LoadResult<QuantityId> {
        self.qty(v, Some(Dim::ANGLE), path)
    }

    fn zero(&mut self) -> QuantityId {
        if let Some(id) = self.zero {
            return id;
        }
        self.exprs.push(Expr::Num(0.0));
        self.expr_paths.push(KeyPath::root());
        let id = self.exprs.len() - 1;
        self.zero = Some(id);
        id
    }

    fn coords(
        &mut self,
        v: &[Value],
        path: &KeyPath,
        dims: std::ops::RangeInclusive<usize>,
    ) -> LoadResult<[QuantityId; 3]> {
        if !dims.contains(&v.len()) {
            let want = if dims.start() == dims.end() {
                format!("{}", dims.start())
            } else {
                format!("{} or {}", dims.start(), dims.end())
            };
            return Err(self.err(
                path,
                format!("expected {want} coordinates, got {}", v.len()),
                Some("write `[x, y]` or `[x, y, z]` in mm".into()),
            ));
        }
        let x = self.length(&v[0], path.index(0))?;
        let y = self.length(&v[1], path.index(1))?;
        let z = if v.len() > 2 {
            self.length(&v[2], path.index(2))?
        } else {
            self.zero()
        };
        Ok([x, y, z])
    }

    // ---- frames and axes ----------------------------------------------------

    pub(super) fn frames(&mut self, f: &ModelFile) -> LoadResult<()> {
        self.frames.push(FrameDef {
            name: "world".into(),
            parent: None,
            origin: None,
            rotate: Vec::new(),
        });
        self.frame_index.insert("world".into(), 0);
        if f.frames.contains_key("world") {
            return Err(self.err(
                &KeyPath::root().key("frames").key("world"),
                "`world` is built in and cannot be redefined",
                Some("choose another frame name".into()),
            ));
        }
        for name in f.frames.keys() {
            self.frame_index.insert(name.clone(), self.frames.len());
            self.frames.push(FrameDef {
                name: name.clone(),
                parent: None,
                origin: None,
                rotate: Vec::new(),
            });
        }
        for (name, fr) in &f.frames {
            let path = KeyPath::root().key("frames").key(name);
            let i = self.frame_index[name];
            let parent = match &fr.parent {
                Some(p) => Some(self.frame_ref(p, &path.key("parent"))?),
                None => Some(0),
            };
            let origin = match &fr.origin {
                Some(o) => Some(self.coords(o, &path.key("origin"), 2..=3)?),
                None => None,
            };
            let mut rotate = Vec::new();
            for (k, file::Rotation(axis, ang)) in fr.rotate.iter().enumerate() {
                let rp = path.key("rotate").index(k);
                let a = match axis.as_str() {
                    "x" => 0,
                    "y" => 1,
                    "z" => 2,
                    _ => {
                        return Err(self.err(
                            &rp.index(0),
                            format!("unknown rotation axis `{axis}`"),
                            Some("write \"x\", \"y\" or \"z\"".into()),
                        ));
                    }
                };
                rotate.push((a, self.angle(ang, rp.index(1))?));
            }
            self.frames[i] = FrameDef {
                name: name.clone(),
                parent,
                origin,
                rotate,
            };
        }
        // Parent chains must end at the world.
        for i in 1..self.frames.len() {
            let mut seen = vec![i];
            let mut j = i;
            while let Some(p) = self.frames[j].parent {
                if p == 0 {
                    break;
                }
                if seen.contains(&p) {
                    let name = self.frames[i].name.clone();
                    return Err(self.err(
                        &KeyPath::root().key("frames").key(&name).key("parent"),
                        "frames are each other's parents in a loop",
                        Some("one frame of the loop must have `world` as parent".into()),
                    ));
                }
                seen.push(p);
                j = p;
            }
        }
        Ok(())
    }

    fn frame_ref(&self, name: &str, path: &KeyPath) -> LoadResult<usize> {
        self.frame_index.get(name).copied().ok_or_else(|| {
            let help = match did_you_mean(name, self.frame_index.keys().map(String::as_str)) {
                Some(s) => format!("did you mean `{s}`?"),
                None => format!("define it as [frames.{name}] or use `world`"),
            };
            self.err(path, format!("unknown frame `{name}`"), Some(help))
        })
    }

    pub(super) fn opt_frame(&self, name: &Option<String>, path: KeyPath) -> LoadResult<usize> {
        match name {
            Some(n) => self.frame_ref(n, &path),
            None => Ok(0),
        }
    }

    /// The zero direction of a turning axis. Two named axes are constants,
    /// so a zero direction along the axis is refused here, at its key; a
    /// vector that turns out parallel is caught when the setting is solved.
    fn zero_dir(&mut self, axis: &AxisDef, zero: Option<&Axis>, path: KeyPath) -> LoadResult<Option<AxisDef>> {
        let Some(a) = zero else { return Ok(None) };
        let zero = self.axis(a, path.clone())?;
        if let (AxisDef::Named(i, _), AxisDef::Named(j, _)) = (axis, &zero)
            && i == j
        {
            return Err(self.err(
                &path,
                "the zero direction is parallel to the axis",
                Some("give a `zero_dir` perpendicular to the axis".into()),
            ));
        }
        Ok(Some(zero))
    }

    fn axis(&mut self, a: &Axis, path: KeyPath) -> LoadResult<AxisDef> {
        match a {
            Axis::Named(s) => {
                let (sign, n) = match s.strip_prefix('-') {
                    Some(rest) => (-1.0, rest),
                    None => (1.0, s.strip_prefix('+').unwrap_or(s)),
                };
                let i = match n {
                    "x" => 0,
                    "y" => 1,
                    "z" => 2,
                    _ => {
                        return Err(self.err(
                            &path,
                            format!("unknown axis `{s}`"),
                            Some(
                                "write \"x\", \"y\", \"z\" (optionally with a sign, \"-y\") or a vector [x, y, z]"
                                    .into(),
                            ),
                        ));
                    }
                };
                Ok(AxisDef::Named(i, sign))
            }
            Axis::Vector(v) => {
                if v.len() != 3 && v.len() != 2 {
                    return Err(self.err(
                        &path,
                        format!("a direction has 2 or 3 components, got {}", v.len()),
                        None,
                    ));
                }
                let mut c = [0; 3];
                for (k, x) in v.iter().enumerate() {
                    c[k] = self.qty(x, None, path.index(k))?;
                }
                if v.len() == 2 {
                    c[2] = self.zero();
                }
                Ok(AxisDef::Vector(c, path))
            }
        }
    }

    // ---- points -------------------------------------------------------------

    pub(super) fn fixed_points(&mut self, f: &ModelFile) -> LoadResult<()> {
        for (name, p) in &f.points {
            let path = KeyPath::root().key("points").key(name);
            self.check_point_name(name, &path)?;
            let (frame, coords) = match p {
                FixedPoint::Coords(c) => (0, self.coords(c, &path, 2..=3)?),
                FixedPoint::InFrame(fp) => (
                    self.opt_frame(&fp.frame, path.key("frame"))?,
                    self.coords(&fp.at, &path.key("at"), 2..=3)?,
                ),
            };
            self.add_point(name, PointKind::Fixed { frame, coords }, &path)?;
        }
        Ok(())
    }

    fn check_point_name(&self, name: &str, path: &KeyPath) -> LoadResult<()> {
        if name.is_empty() || !name.chars().all(|c| c.is_ascii_alphanumeric() || c == '_') {
            return Err(self.err(
                path,
                format!("`{name}` is not a valid point name"),
                Some("point names use letters, digits and `_` (they become column names like `E.x_mm`)".into()),
            ));
        }
        Ok(())
    }

    fn add_point(&mut self, name: &str, kind: PointKind, path: &KeyPath) -> LoadResult<usize> {
        self.check_point_name(name, path)?;
        if self.point_index.contains_key(name) {
            return Err(self.err(
                path,
                format!("point `{name}` is defined twice"),
                Some("every point is created once: by [points], a driver or a group".into()),
            ));
        }
        self.point_index.insert(name.to_string(), self.points.len());
        self.points.push((name.to_string(), kind));
        Ok(self.points.len() - 1)
    }

    /// Declares every moving point first so groups may refer to points
    /// created later in the file.
    pub(super) fn declare_moving(&mut self, f: &ModelFile) -> LoadResult<()> {
        for (k, d) in f.drivers.iter().enumerate() {
            self.add_point(
                &d.out,
                PointKind::Moving,
                &KeyPath::root().key("drivers").index(k).key("out"),
            )?;
        }
        for (k, g) in f.groups.iter().enumerate() {
            let path = KeyPath::root().key("groups").index(k);
            match g {
                Group::Newton { unknowns, .. } => {
                    for name in unknowns.keys() {
                        self.add_point(name, PointKind::Moving, &path.key("unknowns").key(name))?;
                    }
                }
                _ => {
                    let out = group_out(g);
                    self.add_point(out, PointKind::Moving, &path.key("out"))?;
                }
            }
        }
        Ok(())
    }

    pub(super) fn point(&self, name: &str, path: &KeyPath) -> LoadResult<usize> {
        self.point_index.get(name).copied().ok_or_else(|| {
            let help = match did_you_mean(name, self.point_index.keys().map(String::as_str)) {
                Some(s) => format!("did you mean `{s}`?"),
                None => "points are defined in [points], by a driver's `out` or by a group's `out`".into(),
            };
            self.err(path, format!("unknown point `{name}`"), Some(help))
        })
    }

    fn fixed_point(&self, name: &str, path: &KeyPath) -> LoadResult<usize> {
        let i = self.point(name, path)?;
        if !matches!(self.points[i].1, PointKind::Fixed { .. }) {
            return Err(self.err(
                path,
                format!("`{name}` moves, but a fixed point is needed here"),
                Some("use a point from [points]".into()),
            ));
        }
        Ok(i)
    }

    // ---- drivers and groups ---------------------------------------------------

    pub(super) fn drivers(&mut self, f: &ModelFile) -> LoadResult<Vec<(StepDef, String)>> {
        let mut out = Vec::new();
        for (k, d) in f.drivers.iter().enumerate() {
            let path = KeyPath::root().key("drivers").index(k);
            let center = self.fixed_point(&d.center, &path.key("center"))?;
            let frame = self.opt_frame(&d.frame, path.key("frame"))?;
            let axis = match &d.axis {
                Some(a) => self.axis(a, path.key("axis"))?,
                None => AxisDef::Named(2, 1.0),
            };
            let zero_dir = self.zero_dir(&axis, d.zero_dir.as_ref(), path.key("zero_dir"))?;
            let radius = self.positive_length(&d.radius, path.key("radius"), "the crank radius")?;
            let phase = match &d.phase_deg {
                Some(v) => self.angle(v, path.key("phase_deg"))?,
                None => self.zero(),
            };
            let speed = d.speed.unwrap_or(1.0);
            if !speed.is_finite() || speed == 0.0 {
                return Err(self.err(
                    &path.key("speed"),
                    "the speed must be a non-zero number of turns per main-shaft turn",
                    None,
                ));
            }
            let outp = self.point_index[&d.out];
            let label = format!("driver {}", d.name.as_deref().unwrap_or(&d.out));
            out.push((
                StepDef::Crank {
                    center,
                    out: outp,
                    frame,
                    axis,
                    zero_dir,
                    radius,
                    phase,
                    speed,
                },
                label,
            ));
        }
        Ok(out)
    }

    pub(super) fn groups(&mut self, f: &ModelFile) -> LoadResult<Vec<(StepDef, String, KeyPath)>> {
        let mut out = Vec::new();
        let mut names: Vec<&str> = Vec::new();
        for (k, g) in f.groups.iter().enumerate() {
            let path = KeyPath::root().key("groups").index(k);
            if let Some(n) = group_name(g) {
                if n.is_empty() || !n.chars().all(|c| c.is_ascii_alphanumeric() || c == '_') {
                    return Err(self.err(
                        &path.key("name"),
                        format!("`{n}` is not a valid group name"),
                        Some(
                            "group names use letters, digits and `_` (they become column names like `mu_45_deg`)"
                                .into(),
                        ),
                    ));
                }
                if names.contains(&n) {
                    return Err(self.err(
                        &path.key("name"),
                        format!("two groups are named `{n}`"),
                        Some("give every group its own name".into()),
                    ));
                }
                names.push(n);
            }
            let (step, label) = self.group(g, &path)?;
            out.push((step, label, path));
        }
        Ok(out)
    }

    fn group(&mut self, g: &Group, path: &KeyPath) -> LoadResult<(StepDef, String)> {
        let kind = group_kind(g);
        let label = match group_name(g) {
            Some(n) => format!("{kind} group \"{n}\""),
            None => format!("{kind} group → {}", group_out(g)),
        };
        let step = match g {
            Group::RigidPoint {
                base,
                distance,
                angle_deg,
                lift,
                out,
                plane,
                ..
            } => {
                let a = self.point(&base[0], &path.key("base").index(0))?;
                let b = self.point(&base[1], &path.key("base").index(1))?;
                let d = self.length(distance, path.key("distance"))?;
                let angle = match angle_deg {
                    Some(v) => self.angle(v, path.key("angle_deg"))?,
                    None => self.zero(),
                };
                let lift = match lift {
                    Some(v) => self.length(v, path.key("lift"))?,
                    None => self.zero(),
                };
                let plane = self.opt_frame(plane, path.key("plane"))?;
                StepDef::Rigid {
                    base: [a, b],
                    d,
                    angle,
                    lift,
                    plane,
                    out: self.point_index[out],
                }
            }
            Group::Offset {
                from, by, frame, out, ..
            } => {
                let from = self.point(from, &path.key("from"))?;
                let frame = self.opt_frame(frame, path.key("frame"))?;
                let by = self.coords(by, &path.key("by"), 2..=3)?;
                StepDef::Offset {
                    from,
                    by,
                    frame,
                    out: self.point_index[out],
                }
            }
            Group::RigidPoint3d { frame, at, out, .. } => {
                let mut fr = [0; 3];
                for (k, n) in frame.iter().enumerate() {
                    fr[k] = self.point(n, &path.key("frame").index(k))?;
                }
                let at = self.coords(at, &path.key("at"), 3..=3)?;
                StepDef::Rigid3 {
                    frame: fr,
                    at,
                    out: self.point_index[out],
                }
            }
            Group::Newton {
                unknowns,
                constraints,
                plane,
                planar,
                ..
            } => self.newton_group(unknowns, constraints, plane, *planar, path)?,
            Group::CamFollower(c) => self.cam_follower_group(c, path)?,
            dyad => self.dyad_group(dyad, path)?,
        };
        Ok((step, label))
    }

    /// A planar dyad: RRR, RRP or RPR; the spatial ones go on to
    /// [`Self::spatial_group`].
    fn dyad_group(&mut self, g: &Group, path: &KeyPath) -> LoadResult<StepDef> {
        Ok(match g {
            Group::Rrr {
                joints,
                lengths,
                out,
                branch,
                plane,
                ..
            } => {
                let p1 = self.point(&joints[0], &path.key("joints").index(0))?;
                let p2 = self.point(&joints[1], &path.key("joints").index(1))?;
                let l1 = self.positive_length(&lengths[0], path.key("lengths").index(0), "a link length")?;
                let l2 = self.positive_length(&lengths[1], path.key("lengths").index(1), "a link length")?;
                let sign = self.side(*branch, &path.key("branch"))?;
                let plane = self.opt_frame(plane, path.key("plane"))?;
                StepDef::Rrr {
                    p1,
                    p2,
                    l1,
                    l2,
                    sign,
                    plane,
                    out: self.point_index[out],
                }
            }
            Group::Rrp {
                from,
                length,
                through,
                toward,
                direction_deg,
                offset,
                out,
                branch,
                plane,
                ..
            } => {
                let from = self.point(from, &path.key("from"))?;
                let l = self.positive_length(length, path.key("length"), "the rod length")?;
                let through = self.point(through, &path.key("through"))?;
                let (toward, dir) = match (toward, direction_deg) {
                    (Some(t), None) => (Some(self.point(t, &path.key("toward"))?), None),
                    (None, Some(d)) => (None, Some(self.angle(d, path.key("direction_deg"))?)),
                    _ => {
                        return Err(self.err(
                            path,
                            "the guide line needs exactly one of `toward` (a point) or `direction_deg`",
                            Some("e.g. `through = \"H\", direction_deg = 90`".into()),
                        ));
                    }
                };
                let offset = match offset {
                    Some(v) => self.length(v, path.key("offset"))?,
                    None => self.zero(),
                };
                let sign = self.along(*branch, &path.key("branch"))?;
                let plane = self.opt_frame(plane, path.key("plane"))?;
                StepDef::Rrp {
                    from,
                    through,
                    toward,
                    dir,
                    offset,
                    l,
                    sign,
                    plane,
                    out: self.point_index[out],
                }
            }
            Group::Rpr {
                from,
                pivot,
                offset,
                out,
                distance,
                plane,
                ..
            } => {
                let from = self.point(from, &path.key("from"))?;
                let pivot = self.point(pivot, &path.key("pivot"))?;
                let e = match offset {
                    Some(v) => self.length(v, path.key("offset"))?,
                    None => self.zero(),
                };
                let d = self.length(distance, path.key("distance"))?;
                let plane = self.opt_frame(plane, path.key("plane"))?;
                StepDef::Rpr {
                    from,
                    pivot,
                    e,
                    d,
                    plane,
                    out: self.point_index[out],
                }
            }
            spatial => self.spatial_group(spatial, path)?,
        })
    }

    /// A spatial dyad: RSSR or a point on a line.
    fn spatial_group(&mut self, g: &Group, path: &KeyPath) -> LoadResult<StepDef> {
        Ok(match g {
            Group::Rssr {
                from,
                rod,
                pivot,
                axis,
                arm,
                offset,
                out,
                branch,
                frame,
                zero_dir,
                ..
            } => {
                let from = self.point(from, &path.key("from"))?;
                let l = self.positive_length(rod, path.key("rod"), "the rod length")?;
                let pivot = self.fixed_point(pivot, &path.key("pivot"))?;
                let frame = self.opt_frame(frame, path.key("frame"))?;
                let axis = self.axis(axis, path.key("axis"))?;
                let r = self.positive_length(arm, path.key("arm"), "the rocker arm")?;
                let offset = match offset {
                    Some(v) => self.length(v, path.key("offset"))?,
                    None => self.zero(),
                };
                let zero_dir = self.zero_dir(&axis, zero_dir.as_ref(), path.key("zero_dir"))?;
                let sign = self.side(*branch, &path.key("branch"))?;
                StepDef::Rssr {
                    from,
                    l,
                    pivot,
                    frame,
                    axis,
                    r,
                    offset,
                    zero_dir,
                    sign,
                    out: self.point_index[out],
                }
            }
            Group::PointOnLine {
                from,
                length,
                through,
                toward,
                direction,
                frame,
                out,
                branch,
                ..
            } => {
                let from = self.point(from, &path.key("from"))?;
                let l = self.positive_length(length, path.key("length"), "the rod length")?;
                let through = self.point(through, &path.key("through"))?;
                let frame = self.opt_frame(frame, path.key("frame"))?;
                let (toward, dir) = match (toward, direction) {
                    (Some(t), None) => (Some(self.point(t, &path.key("toward"))?), None),
                    (None, Some(d)) => (None, Some(self.axis(d, path.key("direction"))?)),
                    _ => {
                        return Err(self.err(
                            path,
                            "the line needs exactly one of `toward` (a point) or `direction`",
                            Some("e.g. `through = \"N1\", toward = \"N2\"`".into()),
                        ));
                    }
                };
                let sign = self.along(*branch, &path.key("branch"))?;
                StepDef::PointOnLine {
                    from,
                    through,
                    toward,
                    dir,
                    frame,
                    l,
                    sign,
                    out: self.point_index[out],
                }
            }
            _ => unreachable!("read by group and dyad_group"),
        })
    }

    /// A numerical (Newton) group: its unknowns with their guesses, and as
    /// many closure equations as unknown coordinates.
    fn newton_group(
        &mut self,
        unknowns: &indexmap::IndexMap<String, Vec<Value>>,
        constraints: &[file::Constraint],
        plane: &Option<String>,
        planar: Option<bool>,
        path: &KeyPath,
    ) -> LoadResult<StepDef> {
        let dims: Vec<usize> = unknowns.values().map(Vec::len).collect();
        let dim = match planar {
            Some(true) => 2,
            Some(false) => 3,
            None => dims.first().copied().unwrap_or(2),
        };
        if unknowns.is_empty() {
            return Err(self.err(
                &path.key("unknowns"),
                "a newton group needs at least one unknown point",
                Some("e.g. `unknowns = { B = [10, 20] }`".into()),
            ));
        }
        let mut outs = Vec::new();
        let mut guess = Vec::new();
        let mut local: BTreeMap<&str, usize> = BTreeMap::new();
        for (i, (name, g)) in unknowns.iter().enumerate() {
            let gp = path.key("unknowns").key(name);
            if g.len() != dim {
                return Err(self.err(
                    &gp,
                    format!("expected {dim} coordinates for the guess, got {}", g.len()),
                    Some(if dim == 2 {
                        "a planar group's guesses are [x, y] in its plane".into()
                    } else {
                        "a spatial group's guesses are [x, y, z]".into()
                    }),
                ));
            }
            for (k, v) in g.iter().enumerate() {
                guess.push(self.length(v, gp.index(k))?);
            }
            outs.push(self.point_index[name.as_str()]);
            local.insert(name, i);
        }
        let mut closures = Vec::new();
        let mut equations = 0;
        for (k, c) in constraints.iter().enumerate() {
            let (closure, n) = self.constraint(c, &path.key("constraints").index(k), &local, dim)?;
            closures.push(closure);
            equations += n;
        }
        let n = outs.len() * dim;
        if equations != n {
            return Err(self.err(
                &path.key("constraints"),
                format!("{equations} closure equation(s) for {n} unknown coordinates"),
                Some(if equations < n {
                    "add constraints: the group can still move".into()
                } else {
                    "remove a redundant constraint (keep its length as a `distance` measure to watch it)".into()
                }),
            ));
        }
        if dim == 3 && plane.is_some() {
            return Err(self.err(
                &path.key("plane"),
                "a spatial newton group (3 coordinates per unknown) has no plane",
                Some("remove `plane`, or give 2-coordinate guesses for a planar group".into()),
            ));
        }
        let plane = self.opt_frame(plane, path.key("plane"))?;
        Ok(StepDef::Newton {
            dim,
            plane,
            outs,
            guess,
            closures,
        })
    }

    /// One closure of a newton group and the equations it gives: a distance
    /// (one) or a point held on a line (one per coordinate across it).
    fn constraint(
        &mut self,
        c: &file::Constraint,
        cp: &KeyPath,
        local: &BTreeMap<&str, usize>,
        dim: usize,
    ) -> LoadResult<(ClosureDef, usize)> {
        match c {
            file::Constraint {
                distance: Some(distance),
                length: Some(length),
                on_line: None,
                through: None,
                toward: None,
            } => {
                let mut r = [ClosureRef::Known(0); 2];
                for j in 0..2 {
                    let n = &distance[j];
                    r[j] = match local.get(n.as_str()) {
                        Some(&u) => ClosureRef::Unknown(u),
                        None => ClosureRef::Known(self.point(n, &cp.key("distance").index(j))?),
                    };
                }
                let l = self.positive_length(length, cp.key("length"), "a distance")?;
                Ok((ClosureDef::Distance { a: r[0], b: r[1], l }, 1))
            }
            file::Constraint {
                distance: None,
                length: None,
                on_line: Some(on_line),
                through: Some(through),
                toward: Some(toward),
            } => {
                let Some(&p) = local.get(on_line.as_str()) else {
                    return Err(self.err(
                        &cp.key("on_line"),
                        format!("`{on_line}` is not an unknown of this group"),
                        Some("the point on the line must be one of the group's unknowns".into()),
                    ));
                };
                let h = self.point(through, &cp.key("through"))?;
                let t = self.point(toward, &cp.key("toward"))?;
                for n in [through, toward] {
                    if local.contains_key(n.as_str()) {
                        return Err(self.err(
                            cp,
                            format!(
                                "the line's points must be solved before this group, but `{n}` is one of its unknowns"
                            ),
                            Some("define the line by points solved earlier".into()),
                        ));
                    }
                }
                Ok((ClosureDef::OnLine { p, h, t }, dim - 1))
            }
            _ => {
                Err(self.err(
                    cp,
                    "a constraint is either a distance or a point on a line",
                    Some("write `{ distance = [\"A\", \"B\"], length = 20 }` or `{ on_line = \"P\", through = \"H\", toward = \"T\" }`".into()),
                ))
            }
        }
    }

    fn side(&self, b: Branch, path: &KeyPath) -> LoadResult<f64> {
        match b {
            Branch::Left => Ok(1.0),
            Branch::Right => Ok(-1.0),
            _ => Err(self.err(
                path,
                "this group's assembly is `left` or `right` of its base line",
                Some("write branch = \"left\" or branch = \"right\"".into()),
            )),
        }
    }

    fn along(&self, b: Branch, path: &KeyPath) -> LoadResult<f64> {
        match b {
            Branch::Forward => Ok(1.0),
            Branch::Backward => Ok(-1.0),
            _ => Err(self.err(
                path,
                "a slider's assembly is `forward` or `backward` along its line",
                Some("write branch = \"forward\" or branch = \"backward\"".into()),
            )),
        }
    }

    // ---- measures and output ------------------------------------------------------

    pub(super) fn measures(&mut self, f: &ModelFile) -> LoadResult<Vec<(String, MeasureDef)>> {
        let mut out: Vec<(String, MeasureDef)> = Vec::new();
        for (k, m) in f.measures.iter().enumerate() {
            let path = KeyPath::root().key("measures").index(k);
            let (name, def) = match m {
                file::Measure::Distance { name, points } => {
                    let a = self.point(&points[0], &path.key("points").index(0))?;
                    let b = self.point(&points[1], &path.key("points").index(1))?;
                    (name, MeasureDef::Distance { a, b })
                }
                file::Measure::LineDeviation {
                    name,
                    point,
                    through,
                    toward,
                    plane,
                } => {
                    let p = self.point(point, &path.key("point"))?;
                    let h = self.point(through, &path.key("through"))?;
                    let t = self.point(toward, &path.key("toward"))?;
                    let plane = match plane.as_deref() {
                        Some("none") => None,
                        Some(n) => Some(self.frame_ref(n, &path.key("plane"))?),
                        None => Some(0),
                    };
                    (name, MeasureDef::LineDeviation { p, h, t, plane })
                }
                file::Measure::Coordinate {
                    name,
                    point,
                    axis,
                    frame,
                    from,
                } => {
                    let p = self.point(point, &path.key("point"))?;
                    let frame = self.opt_frame(frame, path.key("frame"))?;
                    let axis = self.axis(axis, path.key("axis"))?;
                    let from = match from {
                        Some(n) => Some(self.point(n, &path.key("from"))?),
                        None => None,
                    };
                    (name, MeasureDef::Coordinate { p, from, frame, axis })
                }
            };
            if !is_ident(name) {
                return Err(self.err(
                    &path.key("name"),
                    format!("`{name}` is not a valid measure name"),
                    Some("use letters, digits and `_`".into()),
                ));
            }
            if out.iter().any(|(n, _)| n == name) || self.point_index.contains_key(name) {
                return Err(self.err(
                    &path.key("name"),
                    format!("the name `{name}` is already used"),
                    Some("give every measure its own name, distinct from point names".into()),
                ));
            }
            out.push((name.clone(), def));
        }
        Ok(out)
    }

    pub(super) fn output_points(&self, f: &ModelFile) -> LoadResult<Vec<usize>> {
        match f.output.as_ref().and_then(|o| o.points.as_ref()) {
            Some(names) => names
                .iter()
                .enumerate()
                .map(|(k, n)| self.point(n, &KeyPath::root().key("output").key("points").index(k)))
                .collect(),
            None => Ok((0..self.points.len())
                .filter(|&i| matches!(self.points[i].1, PointKind::Moving))
                .collect()),
        }
    }

    /// Orders drivers and groups so every step's inputs are solved before it
    /// (file order where possible).
    pub(super) fn order(&self, steps: Vec<(StepDef, String, KeyPath)>) -> LoadResult<Vec<(StepDef, String)>> {
        let mut known: Vec<bool> = self
            .points
            .iter()
            .map(|(_, k)| matches!(k, PointKind::Fixed { .. }))
            .collect();
        let mut left: Vec<Option<(StepDef, String, KeyPath)>> = steps.into_iter().map(Some).collect();
        let mut out = Vec::with_capacity(left.len());
        loop {
            let mut progressed = false;
            for slot in left.iter_mut() {
                let ready = slot
                    .as_ref()
                    .is_some_and(|(s, _, _)| s.inputs().iter().all(|&i| known[i]));
                if ready {
                    let (s, label, _) = slot.take().expect("checked above");
                    for o in s.outputs() {
                        known[o] = true;
                    }
                    out.push((s, label));
                    progressed = true;
                }
            }
            if left.iter().all(Option::is_none) {
                return Ok(out);
            }
            if !progressed {
                let stuck: Vec<&(StepDef, String, KeyPath)> = left.iter().flatten().collect();
                let names: Vec<&str> = stuck.iter().map(|(_, l, _)| l.as_str()).collect();
                let (s, _, path) = stuck[0];
                let missing: Vec<&str> = s
                    .inputs()
                    .iter()
                    .filter(|&&i| !known[i])
                    .map(|&i| self.points[i].0.as_str())
                    .collect();
                return Err(self.err(
                    path,
                    format!(
                        "these groups need each other's points, so none can be solved first: {} (waiting for {})",
                        names.join("; "),
                        missing.join(", ")
                    ),
                    Some("a loop of groups has no closed form: solve its points together in one `newton` group".into()),
                ));
            }
        }
    }

    // ---- thread paths ---------------------------------------------------------

    pub(super) fn threads(
        &mut self,
        f: &ModelFile,
        same_body: &impl Fn(usize, usize) -> bool,
    ) -> LoadResult<Option<ThreadsDef>> {
        let Some(t) = &f.thread else {
            if !f.cams.is_empty() {
                return Err(self.err(
                    &KeyPath::root().key("cams"),
                    "[[cams]] are only used by thread paths",
                    Some("add a [thread] table with paths that bear on the cam, or remove the cam".into()),
                ));
            }
            return Ok(None);
        };
        let cams = self.cams(f)?;
        let path = KeyPath::root().key("thread");
        let default_mu = self.friction(t.friction, path.key("friction"))?.unwrap_or(0.0);
        if let Some(tn) = t.tension_n
            && !(tn.is_finite() && tn > 0.0)
        {
            return Err(self.err(
                &path.key("tension_n"),
                format!("the regulator tension {tn} N must be positive"),
                None,
            ));
        }
        if let Some(p0) = t.phi0_deg
            && !p0.is_finite()
        {
            return Err(self.err(&path.key("phi0_deg"), "phi0_deg must be a finite angle", None));
        }
        let convention = t.convention.unwrap_or(file::TakeUpConvention::Release);
        let elongation = match &t.elongation_mm {
            Some(_) if convention == file::TakeUpConvention::Release => {
                return Err(self.err(
                    &path.key("elongation_mm"),
                    "the elongation allowance ΔP belongs to the `feed` convention",
                    Some(format!(
                        "write convention = \"feed\" (P = ξ(φ) − ξ(φ0) + ΔP, {}), or remove elongation_mm",
                        crate::references::cite(1)
                    )),
                ));
            }
            Some(v) => Some(self.length(v, path.key("elongation_mm"))?),
            None => None,
        };
        if t.paths.is_empty() {
            return Err(self.err(
                &path.key("paths"),
                "[thread] has no paths",
                Some("add [[thread.paths]] with `name` and `nodes`".into()),
            ));
        }
        let mut paths: Vec<PathDef> = Vec::new();
        for (k, tp) in t.paths.iter().enumerate() {
            let pp = path.key("paths").index(k);
            if paths.iter().any(|p| p.name == tp.name) && is_ident(&tp.name) {
                return Err(self.err(
                    &pp.key("name"),
                    format!("two thread paths are named `{}`", tp.name),
                    Some("give every path its own name".into()),
                ));
            }
            let def = self.path_def(tp, &pp, default_mu, &cams, same_body)?;
            paths.push(def);
        }
        let layout = Arc::new(super::ThreadLayout::new(&paths, |slot| {
            matches!(self.points.get(slot), Some((_, PointKind::Fixed { .. })))
        }));
        let physics = self.thread_physics(t, &paths, f.stitch.is_some())?;
        Ok(Some(ThreadsDef {
            convention,
            elongation,
            phi0_deg: t.phi0_deg,
            tension_n: t.tension_n,
            paths,
            cams,
            layout,
            physics,
        }))
    }

    /// A friction coefficient μ, when given, within 0…5.
    fn friction(&self, mu: Option<f64>, p: KeyPath) -> LoadResult<Option<f64>> {
        match mu {
            Some(m) if !(m.is_finite() && (0.0..=5.0).contains(&m)) => Err(self.err(
                &p,
                format!("friction coefficient {m} is out of range"),
                Some("give μ between 0 and 5 (thread on steel is about 0.1–0.3)".into()),
            )),
            m => Ok(m),
        }
    }

    /// One thread path: its nodes from the regulator to the eye, each
    /// passed once, pins and cams between eyelets, and the spans between.
    fn path_def(
        &mut self,
        tp: &file::ThreadPath,
        pp: &KeyPath,
        default_mu: f64,
        cams: &[CamDef],
        same_body: &impl Fn(usize, usize) -> bool,
    ) -> LoadResult<PathDef> {
        if !is_ident(&tp.name) {
            return Err(self.err(
                &pp.key("name"),
                format!("`{}` is not a valid path name", tp.name),
                Some("path names use letters, digits and `_` (they prefix column names like `n1_A.P_mm`)".into()),
            ));
        }
        let path_mu = self.friction(tp.friction, pp.key("friction"))?.unwrap_or(default_mu);
        if tp.nodes.len() < 2 {
            return Err(self.err(
                &pp.key("nodes"),
                "a thread path needs at least two nodes",
                Some("list the nodes from the tension regulator to the eye".into()),
            ));
        }
        let mut nodes = Vec::new();
        let mut names = Vec::new();
        let mut friction = Vec::new();
        // Guides between two eyelets: (node index, span).
        let mut pins: Vec<(usize, SpanDef)> = Vec::new();
        for (i, node) in tp.nodes.iter().enumerate() {
            let np = pp.key("nodes").index(i);
            let (name, mu, guide) = match node {
                file::Node::Point(name) => (name.clone(), path_mu, None),
                file::Node::Guide(g) => self.guide_node(g, i, &np, path_mu, cams)?,
            };
            let slot = match &guide {
                // A cam node names the cam, not a point: its slot is the cam centre.
                Some(SpanDef::Cam { cam, .. }) => cams[*cam].center,
                _ => self.point(
                    &name,
                    &if matches!(node, file::Node::Point(_)) {
                        np.clone()
                    } else {
                        np.key("at")
                    },
                )?,
            };
            if let Some(span) = guide {
                if i == 0 || i + 1 == tp.nodes.len() {
                    return Err(self.err(
                        &np,
                        "a path starts and ends at an eyelet, not at a pin or cam",
                        Some("put the guide between two eyelets".into()),
                    ));
                }
                if pins.last().is_some_and(|p| p.0 + 1 == i) {
                    return Err(self.err(
                        &np,
                        "two pins or cams follow each other",
                        Some("put an eyelet or guide between them".into()),
                    ));
                }
                pins.push((i, span));
            }
            if names.contains(&name) {
                return Err(self.err(
                    &np,
                    format!("`{name}` appears twice in path `{}`", tp.name),
                    Some("a path passes each guide once (its columns are named after the nodes)".into()),
                ));
            }
            nodes.push(slot);
            names.push(name);
            friction.push(mu);
        }
        let spans = spans_between(&nodes, &pins, same_body);
        Ok(PathDef {
            name: tp.name.clone(),
            label: tp.thread.clone(),
            nodes,
            node_names: names,
            friction,
            spans,
        })
    }

    /// A guide table's node: an eyelet (`at`), a pin or a cam, with its
    /// name, friction and (for a pin or cam) its span, ends filled in later.
    fn guide_node(
        &mut self,
        g: &file::GuideNode,
        i: usize,
        np: &KeyPath,
        path_mu: f64,
        cams: &[CamDef],
    ) -> LoadResult<(String, f64, Option<SpanDef>)> {
        let mu = self.friction(g.friction, np.key("friction"))?.unwrap_or(path_mu);
        let cam_fields = g.contact.is_some() || g.gamma_deg.is_some();
        let (name, span) = match (&g.at, &g.pin, &g.cam) {
            (Some(at), None, None) => {
                if g.axis.is_some() || g.wrap.is_some() || g.radius.is_some() || g.frame.is_some() || cam_fields {
                    return Err(self.err(
                        np,
                        "an eyelet (`at`) has no axis, wrap, radius, frame or cam contact",
                        Some("for a one-sided guide write `pin = \"NAME\"` instead of `at`".into()),
                    ));
                }
                (at.clone(), None)
            }
            (None, Some(pin), None) => {
                if cam_fields {
                    return Err(self.err(np, "`contact` and `gamma_deg` belong to cams, not pins", None));
                }
                self.pin_guide(g, pin, i, np)?
            }
            (None, None, Some(cam)) => self.cam_guide(g, cam, i, np, cams)?,
            _ => {
                return Err(self.err(np, "a guide table has one of `at` (an eyelet), `pin` (a one-sided guide) or `cam`", Some("e.g. `{ at = \"G1\", friction = 0.2 }`, `{ pin = \"G4\", axis = \"z\", wrap = \"ccw\" }` or `{ cam = \"C\", wrap = \"cw\" }`".into())));
            }
        };
        Ok((name, mu, span))
    }

    /// A one-sided guide: a pin the thread wraps in a given sense.
    fn pin_guide(
        &mut self,
        g: &file::GuideNode,
        pin: &str,
        i: usize,
        np: &KeyPath,
    ) -> LoadResult<(String, Option<SpanDef>)> {
        let Some(axis) = &g.axis else {
            return Err(self.err(
                np,
                "a pin needs its `axis`",
                Some("e.g. `axis = \"z\"`: the direction of the pin".into()),
            ));
        };
        let Some(wrap) = g.wrap else {
            return Err(self.err(
                np,
                "a pin needs `wrap`: the sense the thread turns around it",
                Some("write wrap = \"ccw\" or wrap = \"cw\" (about the axis, right-hand rule)".into()),
            ));
        };
        let frame = self.opt_frame(&g.frame, np.key("frame"))?;
        let axis = self.axis(axis, np.key("axis"))?;
        let r = match &g.radius {
            Some(v) => self.length(v, np.key("radius"))?,
            None => self.zero(),
        };
        let sense = if wrap == file::Wrap::Ccw { 1.0 } else { -1.0 };
        let c = self.point(pin, &np.key("pin"))?;
        Ok((
            pin.to_string(),
            Some(SpanDef::Pin {
                a: 0,
                b: 0,
                c,
                axis,
                frame,
                r,
                sense,
                node: i,
            }),
        ))
    }

    /// A cam node: a `[[cams]]` cam with an exact or an offset contact.
    fn cam_guide(
        &mut self,
        g: &file::GuideNode,
        cam: &str,
        i: usize,
        np: &KeyPath,
        cams: &[CamDef],
    ) -> LoadResult<(String, Option<SpanDef>)> {
        if g.axis.is_some() || g.radius.is_some() || g.frame.is_some() {
            return Err(self.err(
                np,
                "a cam node takes its axis and profile from [[cams]]",
                Some("remove `axis`, `radius` and `frame` here".into()),
            ));
        }
        let Some(ci) = cams.iter().position(|c| c.name == cam) else {
            let names: Vec<&str> = cams.iter().map(|c| c.name.as_str()).collect();
            let help = match did_you_mean(cam, names.iter().copied()) {
                Some(n) => format!("did you mean `{n}`?"),
                None => "define it in [[cams]]".into(),
            };
            return Err(self.err(&np.key("cam"), format!("unknown cam `{cam}`"), Some(help)));
        };
        let contact = match g.contact.unwrap_or(file::CamContactModel::Exact) {
            file::CamContactModel::Exact => {
                if g.gamma_deg.is_some() {
                    return Err(self.err(
                        &np.key("gamma_deg"),
                        "`gamma_deg` belongs to `contact = \"offset\"`",
                        None,
                    ));
                }
                let Some(wrap) = g.wrap else {
                    return Err(self.err(
                        np,
                        "an exact cam contact needs `wrap`: the sense the thread turns around the cam",
                        Some("write wrap = \"ccw\" or wrap = \"cw\" (about the cam's axis)".into()),
                    ));
                };
                if cams[ci].convex_min <= 0.0 {
                    return Err(self.err(
                        &np.key("cam"),
                        format!("cam `{cam}` is not convex, so a taut thread does not follow its profile"),
                        Some("use contact = \"offset\" or smooth the profile".into()),
                    ));
                }
                CamContactDef::Exact {
                    sense: if wrap == file::Wrap::Ccw { 1.0 } else { -1.0 },
                }
            }
            file::CamContactModel::Offset => {
                if g.wrap.is_some() {
                    return Err(self.err(
                        &np.key("wrap"),
                        "an offset cam contact has no wrap sense",
                        Some("remove `wrap`, or use contact = \"exact\"".into()),
                    ));
                }
                let Some(gamma) = &g.gamma_deg else {
                    return Err(self.err(
                        np,
                        "an offset cam contact needs `gamma_deg`",
                        Some(format!(
                            "{} uses γ = 0.4–0.8 rad, i.e. 23–46 degrees",
                            crate::references::cite(4)
                        )),
                    ));
                };
                CamContactDef::Offset {
                    gamma: self.angle(gamma, np.key("gamma_deg"))?,
                }
            }
        };
        Ok((
            cam.to_string(),
            Some(SpanDef::Cam {
                a: 0,
                b: 0,
                cam: ci,
                contact,
                node: i,
            }),
        ))
    }

    fn cams(&mut self, f: &ModelFile) -> LoadResult<Vec<CamDef>> {
        let mut out: Vec<CamDef> = Vec::new();
        for (k, c) in f.cams.iter().enumerate() {
            let path = KeyPath::root().key("cams").index(k);
            if !is_ident(&c.name) || out.iter().any(|o| o.name == c.name) || self.point_index.contains_key(&c.name) {
                return Err(self.err(
                    &path.key("name"),
                    format!("`{}` is not a valid, unique cam name", c.name),
                    Some(
                        "cam names use letters, digits and `_`, and differ from each other and from point names".into(),
                    ),
                ));
            }
            let center = self.point(&c.center, &path.key("center"))?;
            let marker = self.point(&c.marker, &path.key("marker"))?;
            let frame = self.opt_frame(&c.frame, path.key("frame"))?;
            let axis = match &c.axis {
                Some(a) => self.axis(a, path.key("axis"))?,
                None => AxisDef::Named(2, 1.0),
            };
            let profile = match (&c.disc, &c.polar) {
                (Some(d), None) => {
                    let r = self.positive_length(&d.radius_mm, path.key("disc").key("radius_mm"), "the disc radius")?;
                    let e = self.length(&d.eccentricity_mm, path.key("disc").key("eccentricity_mm"))?;
                    ProfileDef::Disc { r, e }
                }
                (None, Some(p)) => {
                    let pp = path.key("polar");
                    if p.angle_deg.len() != p.radius_mm.len() || p.angle_deg.len() < 4 {
                        return Err(self.err(
                            &pp,
                            "a polar profile needs at least 4 points, as many angles as radii",
                            Some("give `angle_deg` and `radius_mm` of equal length".into()),
                        ));
                    }
                    let ok = p.angle_deg.iter().all(|a| a.is_finite())
                        && p.angle_deg.windows(2).all(|w| w[1] > w[0])
                        && p.angle_deg[p.angle_deg.len() - 1] - p.angle_deg[0] < 360.0;
                    if !ok {
                        return Err(self.err(
                            &pp.key("angle_deg"),
                            "profile angles must increase and stay within one turn",
                            Some("list angles in degrees, e.g. 0, 30, …, 330".into()),
                        ));
                    }
                    if let Some(r) = p.radius_mm.iter().find(|r| !(r.is_finite() && **r > 0.0)) {
                        return Err(self.err(
                            &pp.key("radius_mm"),
                            format!("profile radius {r} must be a positive number of mm"),
                            None,
                        ));
                    }
                    ProfileDef::Polar {
                        theta: p.angle_deg.iter().map(|a| a.to_radians()).collect(),
                        rho: p.radius_mm.clone(),
                    }
                }
                _ => {
                    return Err(self.err(
                        &path,
                        "a cam has exactly one profile: `disc` or `polar`",
                        Some("e.g. `disc = { radius_mm = 12, eccentricity_mm = 3 }`".into()),
                    ));
                }
            };
            // Convexity, for the exact contact model (disc profiles are convex;
            // polar ones are checked on their spline).
            let convex_min = match &profile {
                ProfileDef::Disc { .. } => 1.0,
                ProfileDef::Polar { theta, rho } => crate::thread::cam::Profile::spline(theta, rho).convexity(),
            };
            out.push(CamDef {
                name: c.name.clone(),
                center,
                marker,
                axis,
                frame,
                profile,
                convex_min,
                path,
            });
        }
        Ok(out)
    }

    pub(super) fn into_parts(self) -> (String, Arc<str>, SpanIndex<'a>) {
        (self.file_name, self.text, self.spans)
    }

    pub(super) fn point_names(&self) -> Vec<String> {
        self.points.iter().map(|(n, _)| n.clone()).collect()
    }
}

use super::ClosureRef;

/// The spans between consecutive contact nodes of a path: straight between
/// eyelets (constant when both ride on one body), or over the pin or cam
/// between two eyelets.
fn spans_between(
    nodes: &[usize],
    pins: &[(usize, SpanDef)],
    same_body: &impl Fn(usize, usize) -> bool,
) -> Vec<SpanDef> {
    let mut spans = Vec::new();
    let mut i = 0;
    while i + 1 < nodes.len() {
        if let Some((_, guide)) = pins.iter().find(|p| p.0 == i + 1) {
            let (a0, b0) = (nodes[i], nodes[i + 2]);
            spans.push(match guide.clone() {
                SpanDef::Pin {
                    c,
                    axis,
                    frame,
                    r,
                    sense,
                    node,
                    ..
                } => SpanDef::Pin {
                    a: a0,
                    b: b0,
                    c,
                    axis,
                    frame,
                    r,
                    sense,
                    node,
                },
                SpanDef::Cam { cam, contact, node, .. } => SpanDef::Cam {
                    a: a0,
                    b: b0,
                    cam,
                    contact,
                    node,
                },
                s => s,
            });
            i += 2;
        } else {
            let (a, b) = (nodes[i], nodes[i + 1]);
            spans.push(SpanDef::Straight {
                a,
                b,
                constant: same_body(a, b),
            });
            i += 1;
        }
    }
    spans
}

/// Help for serde's "unknown variant `x`, expected one of `a`, `b`": the
/// listed value nearest the one written (a unit's spelled-out name too:
/// `inch` is `in`), else the list.
fn unknown_variant_help(msg: &str) -> String {
    let quoted: Vec<&str> = msg.split('`').skip(1).step_by(2).collect();
    let (Some(given), allowed) = (quoted.first(), quoted.get(1..).unwrap_or_default()) else {
        return "use one of the listed values".to_string();
    };
    let spelled = |g: &str| -> Option<&'static str> {
        let g = g.trim().to_lowercase();
        let g = g.strip_suffix("es").filter(|s| s.ends_with("ch")).unwrap_or(&g);
        let g = g.trim_end_matches('s');
        Some(match g {
            "inch" | "\"" | "''" => "in",
            "millimeter" | "millimetre" => "mm",
            "centimeter" | "centimetre" | "cm" => "cm",
            "degree" | "°" => "deg",
            "radian" => "rad",
            "newton" => "N",
            _ => return None,
        })
    };
    let nearest = spelled(given)
        .filter(|s| allowed.contains(s))
        .or_else(|| did_you_mean(given, allowed.iter().copied()));
    match nearest {
        Some(s) => format!("did you mean `{s}`? The values are: {}", allowed.join(", ")),
        None => "use one of the listed values".to_string(),
    }
}

pub(super) fn is_ident(s: &str) -> bool {
    let mut c = s.chars();
    matches!(c.next(), Some(ch) if ch.is_ascii_alphabetic() || ch == '_')
        && c.all(|ch| ch.is_ascii_alphanumeric() || ch == '_')
}

fn unit_dim(u: Unit) -> Option<Dim> {
    Some(match u {
        Unit::Mm | Unit::Cm | Unit::In => Dim::LENGTH,
        Unit::Deg | Unit::Rad => Dim::ANGLE,
        Unit::One => Dim::ONE,
        Unit::N => Dim::FORCE,
    })
}

pub(super) fn group_out(g: &Group) -> &str {
    match g {
        Group::Rrr { out, .. }
        | Group::Rrp { out, .. }
        | Group::Rpr { out, .. }
        | Group::Rssr { out, .. }
        | Group::PointOnLine { out, .. }
        | Group::RigidPoint { out, .. }
        | Group::RigidPoint3d { out, .. }
        | Group::Offset { out, .. } => out,
        Group::CamFollower(c) => &c.out,
        Group::Newton { name, .. } => name,
    }
}

fn group_name(g: &Group) -> Option<&str> {
    match g {
        Group::Rrr { name, .. }
        | Group::Rrp { name, .. }
        | Group::Rpr { name, .. }
        | Group::Rssr { name, .. }
        | Group::PointOnLine { name, .. }
        | Group::RigidPoint { name, .. }
        | Group::RigidPoint3d { name, .. }
        | Group::Offset { name, .. } => name.as_deref(),
        Group::CamFollower(c) => c.name.as_deref(),
        Group::Newton { name, .. } => Some(name),
    }
}

pub(super) fn group_kind(g: &Group) -> &'static str {
    match g {
        Group::Rrr { .. } => "rrr",
        Group::Rrp { .. } => "rrp",
        Group::Rpr { .. } => "rpr",
        Group::Rssr { .. } => "rssr",
        Group::PointOnLine { .. } => "point_on_line",
        Group::RigidPoint { .. } => "rigid_point",
        Group::RigidPoint3d { .. } => "rigid_point_3d",
        Group::Offset { .. } => "offset",
        Group::Newton { .. } => "newton",
        Group::CamFollower(_) => "cam_follower",
    }
}

pub(super) fn group_key(g: &Group) -> String {
    group_name(g).unwrap_or_else(|| group_out(g)).to_string()
}
