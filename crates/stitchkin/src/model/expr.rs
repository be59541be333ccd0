//! Arithmetic expressions of parameters: `"x_c + l_ef - l_ef*cos(alpha)"`.
//!
//! Grammar: numbers, parameter names, `+ - * / ^`, parentheses, unary minus,
//! the constant `pi` and the functions `sin cos tan` (argument in degrees),
//! `asin acos atan atan2` (result in degrees), `sqrt abs hypot min max`.
//! Every expression carries a [`Dim`]: lengths (mm), angles (deg), forces
//! (N), their products or pure numbers; mixing them wrongly (`l_ab +
//! alpha`, `sin(l_ab)`) is rejected when the model is loaded.

use crate::scalar::Real;

/// Physical dimension: powers of length (mm), angle (deg) and force (N).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Dim {
    pub length: i8,
    pub angle: i8,
    pub force: i8,
}

impl Dim {
    pub const ONE: Dim = Dim {
        length: 0,
        angle: 0,
        force: 0,
    };
    pub const LENGTH: Dim = Dim {
        length: 1,
        angle: 0,
        force: 0,
    };
    pub const ANGLE: Dim = Dim {
        length: 0,
        angle: 1,
        force: 0,
    };
    pub const FORCE: Dim = Dim {
        length: 0,
        angle: 0,
        force: 1,
    };

    /// Unit exponents beyond this are surely a mistake (and would overflow).
    const MAX_POWER: i32 = 12;

    fn checked(length: i32, angle: i32, force: i32) -> Result<Dim, String> {
        let max = Self::MAX_POWER;
        if length.abs() > max || angle.abs() > max || force.abs() > max {
            return Err(format!(
                "the units grow to mm^{length}·deg^{angle}·N^{force}, beyond any physical quantity"
            ));
        }
        Ok(Dim {
            length: length as i8,
            angle: angle as i8,
            force: force as i8,
        })
    }
    fn mul(self, o: Dim) -> Result<Dim, String> {
        Dim::checked(
            self.length as i32 + o.length as i32,
            self.angle as i32 + o.angle as i32,
            self.force as i32 + o.force as i32,
        )
    }
    fn div(self, o: Dim) -> Result<Dim, String> {
        Dim::checked(
            self.length as i32 - o.length as i32,
            self.angle as i32 - o.angle as i32,
            self.force as i32 - o.force as i32,
        )
    }

    /// The unit a quantity of this dimension is written in, e.g. `mm^2`.
    pub fn unit(self) -> String {
        self.unit_in(("mm", "deg"))
    }

    /// The unit a quantity of this dimension is written in, with lengths
    /// and angles in `names` (e.g. `("in", "rad")`): `in^2`.
    pub fn unit_in(self, names: (&str, &str)) -> String {
        let part = |name: &str, p: i8| match p {
            0 => String::new(),
            1 => name.to_string(),
            p => format!("{name}^{p}"),
        };
        let parts: Vec<String> = [
            part(names.0, self.length),
            part(names.1, self.angle),
            part("N", self.force),
        ]
        .into_iter()
        .filter(|p| !p.is_empty())
        .collect();
        if parts.is_empty() {
            "1 (a pure number)".to_string()
        } else {
            parts.join("·")
        }
    }
}

/// Inferred dimension: a bare number literal fits any dimension
/// (numbers in files are in mm and deg already).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Dimension {
    Free,
    Is(Dim),
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Func {
    Sin,
    Cos,
    Tan,
    Asin,
    Acos,
    Atan,
    Atan2,
    Sqrt,
    Abs,
    Hypot,
    Min,
    Max,
}

impl Func {
    fn lookup(name: &str) -> Option<(Func, usize)> {
        Some(match name {
            "sin" => (Func::Sin, 1),
            "cos" => (Func::Cos, 1),
            "tan" => (Func::Tan, 1),
            "asin" => (Func::Asin, 1),
            "acos" => (Func::Acos, 1),
            "atan" => (Func::Atan, 1),
            "atan2" => (Func::Atan2, 2),
            "sqrt" => (Func::Sqrt, 1),
            "abs" => (Func::Abs, 1),
            "hypot" => (Func::Hypot, 2),
            "min" => (Func::Min, 2),
            "max" => (Func::Max, 2),
            _ => return None,
        })
    }
    const NAMES: &'static str = "sin cos tan asin acos atan atan2 sqrt abs hypot min max";
}

/// Parsed expression. Parameters are referred to by index.
#[derive(Debug, Clone, PartialEq)]
pub enum Expr {
    Num(f64),
    Param(usize),
    Neg(Box<Expr>),
    Add(Box<Expr>, Box<Expr>),
    Sub(Box<Expr>, Box<Expr>),
    Mul(Box<Expr>, Box<Expr>),
    Div(Box<Expr>, Box<Expr>),
    /// Power with an integer literal exponent.
    Pow(Box<Expr>, i32),
    Call(Func, Vec<Expr>),
}

/// A problem in an expression, with the byte range inside the expression
/// text where it is.
#[derive(Debug, Clone, PartialEq)]
pub struct ExprError {
    pub message: String,
    pub help: Option<String>,
    pub at: std::ops::Range<usize>,
}

impl ExprError {
    fn new(message: impl Into<String>, at: std::ops::Range<usize>) -> Self {
        ExprError {
            message: message.into(),
            help: None,
            at,
        }
    }
    fn help(mut self, help: impl Into<String>) -> Self {
        self.help = Some(help.into());
        self
    }
}

#[derive(Debug, Clone, PartialEq)]
enum Tok {
    Num(f64),
    Ident(String),
    Op(char),
}

fn tokenize(src: &str) -> Result<Vec<(Tok, std::ops::Range<usize>)>, ExprError> {
    let bytes = src.as_bytes();
    let mut out = Vec::new();
    let mut i = 0;
    while i < bytes.len() {
        let c = bytes[i] as char;
        if c.is_ascii_whitespace() {
            i += 1;
        } else if c.is_ascii_digit() || c == '.' {
            let start = i;
            while i < bytes.len() && (bytes[i].is_ascii_digit() || bytes[i] == b'.') {
                i += 1;
            }
            if i < bytes.len() && (bytes[i] == b'e' || bytes[i] == b'E') {
                let save = i;
                i += 1;
                if i < bytes.len() && (bytes[i] == b'+' || bytes[i] == b'-') {
                    i += 1;
                }
                if i < bytes.len() && bytes[i].is_ascii_digit() {
                    while i < bytes.len() && bytes[i].is_ascii_digit() {
                        i += 1;
                    }
                } else {
                    i = save;
                }
            }
            let text = &src[start..i];
            let v: f64 = text
                .parse()
                .map_err(|_| ExprError::new(format!("`{text}` is not a number"), start..i))?;
            out.push((Tok::Num(v), start..i));
        } else if c.is_ascii_alphabetic() || c == '_' {
            let start = i;
            while i < bytes.len() && (bytes[i].is_ascii_alphanumeric() || bytes[i] == b'_') {
                i += 1;
            }
            out.push((Tok::Ident(src[start..i].to_string()), start..i));
        } else if "+-*/^(),".contains(c) {
            out.push((Tok::Op(c), i..i + 1));
            i += 1;
        } else {
            let len = src[i..].chars().next().map_or(1, char::len_utf8);
            return Err(
                ExprError::new(format!("unexpected character `{}`", &src[i..i + len]), i..i + len)
                    .help("expressions use numbers, parameter names, + - * / ^, parentheses and functions"),
            );
        }
    }
    Ok(out)
}

struct Parser<'a, F: Fn(&str) -> Option<usize>> {
    toks: Vec<(Tok, std::ops::Range<usize>)>,
    pos: usize,
    src_len: usize,
    lookup: &'a F,
    depth: usize,
}

const MAX_DEPTH: usize = 64;
/// Longest expression accepted, in tokens: keeps every expression tree
/// shallow enough to walk recursively.
const MAX_TOKENS: usize = 512;

impl<F: Fn(&str) -> Option<usize>> Parser<'_, F> {
    fn peek(&self) -> Option<&Tok> {
        self.toks.get(self.pos).map(|t| &t.0)
    }
    fn here(&self) -> std::ops::Range<usize> {
        self.toks
            .get(self.pos)
            .map_or(self.src_len..self.src_len, |t| t.1.clone())
    }
    fn eat(&mut self, c: char) -> bool {
        if self.peek() == Some(&Tok::Op(c)) {
            self.pos += 1;
            true
        } else {
            false
        }
    }
    fn enter(&mut self) -> Result<(), ExprError> {
        self.depth += 1;
        if self.depth > MAX_DEPTH {
            return Err(ExprError::new("expression nested too deeply", self.here()));
        }
        Ok(())
    }

    // sum := product (('+'|'-') product)*
    fn sum(&mut self) -> Result<Expr, ExprError> {
        self.enter()?;
        let mut lhs = self.product()?;
        loop {
            if self.eat('+') {
                lhs = Expr::Add(Box::new(lhs), Box::new(self.product()?));
            } else if self.eat('-') {
                lhs = Expr::Sub(Box::new(lhs), Box::new(self.product()?));
            } else {
                break;
            }
        }
        self.depth -= 1;
        Ok(lhs)
    }
    // product := unary (('*'|'/') unary)*
    fn product(&mut self) -> Result<Expr, ExprError> {
        let mut lhs = self.unary()?;
        loop {
            if self.eat('*') {
                lhs = Expr::Mul(Box::new(lhs), Box::new(self.unary()?));
            } else if self.eat('/') {
                lhs = Expr::Div(Box::new(lhs), Box::new(self.unary()?));
            } else {
                break;
            }
        }
        Ok(lhs)
    }
    // unary := '-' unary | '+' unary | power
    fn unary(&mut self) -> Result<Expr, ExprError> {
        self.enter()?;
        let e = if self.eat('-') {
            Expr::Neg(Box::new(self.unary()?))
        } else if self.eat('+') {
            self.unary()?
        } else {
            self.power()?
        };
        self.depth -= 1;
        Ok(e)
    }
    // power := atom ('^' ['-'] integer)?
    fn power(&mut self) -> Result<Expr, ExprError> {
        let base = self.atom()?;
        if self.eat('^') {
            let neg = self.eat('-');
            let at = self.here();
            match self.peek().cloned() {
                Some(Tok::Num(v)) if v.fract() == 0.0 && v.abs() <= 16.0 => {
                    self.pos += 1;
                    let n = v as i32;
                    return Ok(Expr::Pow(Box::new(base), if neg { -n } else { n }));
                }
                _ => {
                    return Err(ExprError::new("the exponent after `^` must be a whole number", at)
                        .help("write e.g. `l^2`; use sqrt() for square roots"));
                }
            }
        }
        Ok(base)
    }
    fn atom(&mut self) -> Result<Expr, ExprError> {
        let at = self.here();
        match self.peek().cloned() {
            Some(Tok::Num(v)) => {
                self.pos += 1;
                Ok(Expr::Num(v))
            }
            Some(Tok::Op('(')) => {
                self.pos += 1;
                let e = self.sum()?;
                if !self.eat(')') {
                    return Err(ExprError::new("missing `)`", self.here()));
                }
                Ok(e)
            }
            Some(Tok::Ident(name)) => {
                self.pos += 1;
                if self.peek() == Some(&Tok::Op('(')) {
                    let Some((func, arity)) = Func::lookup(&name) else {
                        return Err(ExprError::new(format!("unknown function `{name}`"), at)
                            .help(format!("functions are: {}", Func::NAMES)));
                    };
                    self.pos += 1;
                    let mut args = vec![self.sum()?];
                    while self.eat(',') {
                        args.push(self.sum()?);
                    }
                    if !self.eat(')') {
                        return Err(ExprError::new(
                            "missing `)` after the function's arguments",
                            self.here(),
                        ));
                    }
                    if args.len() != arity {
                        return Err(ExprError::new(
                            format!("`{name}` takes {arity} argument(s), got {}", args.len()),
                            at,
                        ));
                    }
                    return Ok(Expr::Call(func, args));
                }
                if name == "pi" {
                    return Ok(Expr::Num(std::f64::consts::PI));
                }
                match (self.lookup)(&name) {
                    Some(i) => Ok(Expr::Param(i)),
                    None => Err(ExprError::new(format!("unknown parameter `{name}`"), at)),
                }
            }
            Some(Tok::Op(c)) => Err(ExprError::new(format!("unexpected `{c}`"), at)
                .help("expected a number, a parameter name, a function call or `(`")),
            None => Err(ExprError::new("the expression ends too early", at)),
        }
    }
}

impl Expr {
    /// Parses `src`; `lookup` maps a parameter name to its index.
    pub fn parse(src: &str, lookup: &impl Fn(&str) -> Option<usize>) -> Result<Expr, ExprError> {
        let toks = tokenize(src)?;
        if toks.len() > MAX_TOKENS {
            return Err(ExprError::new(
                format!(
                    "the expression is too long ({} tokens, at most {MAX_TOKENS})",
                    toks.len()
                ),
                0..src.len(),
            )
            .help("split it into derived parameters (`expr = ...`)"));
        }
        if toks.is_empty() {
            return Err(ExprError::new("empty expression", 0..src.len()).help("write a number or an expression"));
        }
        let mut p = Parser {
            toks,
            pos: 0,
            src_len: src.len(),
            lookup,
            depth: 0,
        };
        let e = p.sum()?;
        if p.pos < p.toks.len() {
            return Err(
                ExprError::new("unexpected text after the expression", p.here()).help("is an operator missing?")
            );
        }
        Ok(e)
    }

    /// Parameters this expression reads.
    pub fn params(&self, out: &mut Vec<usize>) {
        match self {
            Expr::Num(_) => {}
            Expr::Param(i) => out.push(*i),
            Expr::Neg(a) | Expr::Pow(a, _) => a.params(out),
            Expr::Add(a, b) | Expr::Sub(a, b) | Expr::Mul(a, b) | Expr::Div(a, b) => {
                a.params(out);
                b.params(out);
            }
            Expr::Call(_, args) => args.iter().for_each(|a| a.params(out)),
        }
    }

    /// Infers the dimension given each parameter's; `Err` explains a clash.
    pub fn dimension(&self, param_dim: &impl Fn(usize) -> Dim) -> Result<Dimension, String> {
        self.dimension_in(param_dim, ("mm", "deg"))
    }

    /// [`Self::dimension`], a clash explained with lengths and angles in
    /// the units `names` (e.g. `("in", "rad")`).
    pub fn dimension_in(&self, param_dim: &impl Fn(usize) -> Dim, names: (&str, &str)) -> Result<Dimension, String> {
        self.dimension_impl(param_dim).map_err(|m| {
            if names == ("mm", "deg") {
                m
            } else {
                rename_units(&m, names)
            }
        })
    }

    fn dimension_impl(&self, param_dim: &impl Fn(usize) -> Dim) -> Result<Dimension, String> {
        use Dimension::{Free, Is};
        Ok(match self {
            Expr::Num(_) => Free,
            Expr::Param(i) => Is(param_dim(*i)),
            Expr::Neg(a) => a.dimension_impl(param_dim)?,
            Expr::Add(a, b) | Expr::Sub(a, b) => match (a.dimension_impl(param_dim)?, b.dimension_impl(param_dim)?) {
                (Free, d) | (d, Free) => d,
                (Is(x), Is(y)) if x == y => Is(x),
                (Is(x), Is(y)) => {
                    return Err(format!("cannot add or subtract {} and {}", x.unit(), y.unit()));
                }
            },
            Expr::Mul(a, b) | Expr::Div(a, b) => {
                let is_mul = matches!(self, Expr::Mul(..));
                match (a.dimension_impl(param_dim)?, b.dimension_impl(param_dim)?) {
                    (Free, Free) => Free,
                    (Is(x), Free) => Is(x),
                    (Free, Is(y)) => Is(if is_mul { y } else { Dim::ONE.div(y)? }),
                    (Is(x), Is(y)) => Is(if is_mul { x.mul(y)? } else { x.div(y)? }),
                }
            }
            Expr::Pow(a, n) => match a.dimension_impl(param_dim)? {
                Free => Free,
                Is(d) => Is(Dim::checked(
                    d.length as i32 * *n,
                    d.angle as i32 * *n,
                    d.force as i32 * *n,
                )?),
            },
            Expr::Call(f, args) => {
                let dims: Vec<Dimension> = args
                    .iter()
                    .map(|a| a.dimension_impl(param_dim))
                    .collect::<Result<_, _>>()?;
                let want = |d: Dimension, w: Dim, what: &str| match d {
                    Free => Ok(()),
                    Is(x) if x == w => Ok(()),
                    Is(x) => Err(format!("{what} needs {}, got {}", w.unit(), x.unit())),
                };
                match f {
                    Func::Sin | Func::Cos | Func::Tan => {
                        want(dims[0], Dim::ANGLE, "a trigonometric function's argument")?;
                        Is(Dim::ONE)
                    }
                    Func::Asin | Func::Acos | Func::Atan => {
                        want(dims[0], Dim::ONE, "an inverse trigonometric function's argument")?;
                        Is(Dim::ANGLE)
                    }
                    Func::Atan2 => {
                        match (dims[0], dims[1]) {
                            (Is(x), Is(y)) if x != y => {
                                return Err(format!(
                                    "atan2's two arguments must have one unit, got {} and {}",
                                    x.unit(),
                                    y.unit()
                                ));
                            }
                            _ => {}
                        }
                        Is(Dim::ANGLE)
                    }
                    Func::Sqrt => match dims[0] {
                        Free => Free,
                        Is(d) if d.length % 2 == 0 && d.angle % 2 == 0 && d.force % 2 == 0 => Is(Dim {
                            length: d.length / 2,
                            angle: d.angle / 2,
                            force: d.force / 2,
                        }),
                        Is(d) => return Err(format!("cannot take the square root of {}", d.unit())),
                    },
                    Func::Abs => dims[0],
                    Func::Hypot | Func::Min | Func::Max => match (dims[0], dims[1]) {
                        (Free, d) | (d, Free) => d,
                        (Is(x), Is(y)) if x == y => Is(x),
                        (Is(x), Is(y)) => {
                            return Err(format!("cannot compare or combine {} and {}", x.unit(), y.unit()));
                        }
                    },
                }
            }
        })
    }

    /// The expression for a model whose angles are in a unit of
    /// `deg_per_unit` degrees (180/π for radians): trigonometric functions
    /// take and give that unit. [`Self::eval`] works in degrees; this
    /// rewrites `sin(x)` as `sin(x·k)` and `asin(x)` as `asin(x)/k`.
    pub fn with_angle_unit(self, deg_per_unit: f64) -> Expr {
        if deg_per_unit == 1.0 {
            return self;
        }
        let k = || Box::new(Expr::Num(deg_per_unit));
        let r = |e: Box<Expr>| Box::new(e.with_angle_unit(deg_per_unit));
        match self {
            e @ (Expr::Num(_) | Expr::Param(_)) => e,
            Expr::Neg(a) => Expr::Neg(r(a)),
            Expr::Add(a, b) => Expr::Add(r(a), r(b)),
            Expr::Sub(a, b) => Expr::Sub(r(a), r(b)),
            Expr::Mul(a, b) => Expr::Mul(r(a), r(b)),
            Expr::Div(a, b) => Expr::Div(r(a), r(b)),
            Expr::Pow(a, n) => Expr::Pow(r(a), n),
            Expr::Call(f, args) => {
                let args: Vec<Expr> = args.into_iter().map(|a| a.with_angle_unit(deg_per_unit)).collect();
                match f {
                    Func::Sin | Func::Cos | Func::Tan => {
                        let x = args.into_iter().next().unwrap_or(Expr::Num(0.0));
                        Expr::Call(f, vec![Expr::Mul(Box::new(x), k())])
                    }
                    Func::Asin | Func::Acos | Func::Atan | Func::Atan2 => Expr::Div(Box::new(Expr::Call(f, args)), k()),
                    _ => Expr::Call(f, args),
                }
            }
        }
    }

    /// Evaluates with parameter values `p` (angles in degrees).
    pub fn eval<T: Real>(&self, p: &[T]) -> T {
        let deg = T::cst(std::f64::consts::PI / 180.0);
        match self {
            Expr::Num(v) => T::cst(*v),
            Expr::Param(i) => p[*i],
            Expr::Neg(a) => -a.eval(p),
            Expr::Add(a, b) => a.eval(p) + b.eval(p),
            Expr::Sub(a, b) => a.eval(p) - b.eval(p),
            Expr::Mul(a, b) => a.eval(p) * b.eval(p),
            Expr::Div(a, b) => a.eval(p) / b.eval(p),
            Expr::Pow(a, n) => a.eval(p).powi(*n),
            Expr::Call(f, args) => {
                let x = args[0].eval(p);
                let y = || args[1].eval(p);
                match f {
                    Func::Sin => (x * deg).sin(),
                    Func::Cos => (x * deg).cos(),
                    Func::Tan => (x * deg).tan(),
                    Func::Asin => x.asin() / deg,
                    Func::Acos => x.acos() / deg,
                    Func::Atan => x.atan() / deg,
                    Func::Atan2 => x.angle_of(y()) / deg,
                    Func::Sqrt => x.sqrt(),
                    Func::Abs => x.abs(),
                    Func::Hypot => x.hypot(y()),
                    Func::Min => x.min(y()),
                    Func::Max => x.max(y()),
                }
            }
        }
    }
}

/// `message` with the words `mm` and `deg` (alone or with a power) said
/// in the units `names`.
fn rename_units(message: &str, names: (&str, &str)) -> String {
    let mut out = String::with_capacity(message.len());
    let mut word = String::new();
    let flush = |word: &mut String, out: &mut String| {
        out.push_str(match word.as_str() {
            "mm" => names.0,
            "deg" => names.1,
            w => w,
        });
        word.clear();
    };
    for c in message.chars() {
        if c.is_alphanumeric() || c == '_' {
            word.push(c);
        } else {
            flush(&mut word, &mut out);
            out.push(c);
        }
    }
    flush(&mut word, &mut out);
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn names(n: &str) -> Option<usize> {
        ["l_ab", "alpha", "x_c", "k"].iter().position(|s| *s == n)
    }
    fn dim(i: usize) -> Dim {
        [Dim::LENGTH, Dim::ANGLE, Dim::LENGTH, Dim::ONE][i]
    }
    fn eval(s: &str) -> f64 {
        Expr::parse(s, &names).unwrap().eval(&[175.0, 30.0, 18.0, 2.0])
    }

    #[test]
    fn arithmetic_precedence_and_degrees() {
        assert_eq!(eval("1 + 2*3"), 7.0);
        assert_eq!(eval("-2^2"), -4.0);
        assert_eq!(eval("(1+2)*3"), 9.0);
        assert_eq!(eval("l_ab / k - x_c"), 175.0 / 2.0 - 18.0);
        assert!((eval("sin(alpha)") - 0.5).abs() < 1e-15);
        assert!((eval("acos(0.5)") - 60.0).abs() < 1e-12);
        assert!((eval("atan2(1, 1)") - 45.0).abs() < 1e-12);
        assert!((eval("2*pi") - std::f64::consts::TAU).abs() < 1e-15);
        assert_eq!(eval("1.5e2"), 150.0);
        assert_eq!(eval("hypot(3, 4)"), 5.0);
        assert_eq!(eval("max(3, min(4, 10))"), 4.0);
    }

    #[test]
    fn parse_errors_point_at_the_problem() {
        let e = Expr::parse("l_ab + bogus", &names).unwrap_err();
        assert_eq!(e.at, 7..12);
        assert!(e.message.contains("bogus"));
        let e = Expr::parse("sinn(alpha)", &names).unwrap_err();
        assert!(e.help.unwrap().contains("sin"));
        assert!(Expr::parse("1 +", &names).is_err());
        assert!(Expr::parse("(1", &names).is_err());
        assert!(Expr::parse("1 2", &names).is_err());
        assert!(Expr::parse("l_ab^0.5", &names).is_err());
        assert!(Expr::parse("", &names).is_err());
        assert!(Expr::parse("atan2(1)", &names).is_err());
        assert!(Expr::parse("1 $ 2", &names).is_err());
        let deep = "(".repeat(100) + "1" + &")".repeat(100);
        assert!(Expr::parse(&deep, &names).is_err());
        let long = vec!["1"; 1000].join("+");
        assert!(Expr::parse(&long, &names).unwrap_err().message.contains("too long"));
    }

    #[test]
    fn dimensions_are_checked() {
        let d = |s: &str| Expr::parse(s, &names).unwrap().dimension(&dim);
        assert_eq!(d("l_ab + 5").unwrap(), Dimension::Is(Dim::LENGTH));
        assert_eq!(d("x_c + l_ab*cos(alpha)").unwrap(), Dimension::Is(Dim::LENGTH));
        assert_eq!(d("sqrt(l_ab^2 + x_c^2)").unwrap(), Dimension::Is(Dim::LENGTH));
        assert_eq!(d("atan2(l_ab, x_c)").unwrap(), Dimension::Is(Dim::ANGLE));
        assert_eq!(d("3").unwrap(), Dimension::Free);
        assert!(d("l_ab + alpha").is_err());
        assert!(d("sin(l_ab)").is_err());
        assert!(d("acos(l_ab)").is_err());
        assert!(d("sqrt(l_ab)").is_err());
        assert_eq!(
            d("l_ab*l_ab").unwrap(),
            Dimension::Is(Dim {
                length: 2,
                angle: 0,
                force: 0
            })
        );
        assert_eq!(d("k*alpha").unwrap(), Dimension::Is(Dim::ANGLE));
        assert!(d("(l_ab^16)^16").unwrap_err().contains("beyond"));
        assert!(d(&vec!["l_ab"; 20].join("*")).is_err());
        assert!(d(&vec!["l_ab"; 20].join("/")).is_err());
    }
}
