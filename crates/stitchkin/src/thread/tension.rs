//! The real thread over the cycle: an elastic thread held by friction on
//! every guide, drawn from a tension regulator that passes thread only when
//! pulled hard enough, with an optional check spring and thread clamps,
//! feeding a stitch that takes what it needs (`docs/thread-physics.md`).
//!
//! The thread from the regulator to the anchor of the newest finished
//! stitch is a chain of spans i = 0 … S−1 joined at nodes i = 0 … S−2 (node
//! i between span i and span i + 1: the guides, the eyelets, the eye); the
//! last span is the stitch's consumption contour, from the eye to the
//! anchor. The state is the unstretched thread m_i each span holds. With
//! ℓ_i(φ) its reach (the length the kinematics gives), a span's tension is
//!
//! ```text
//! T_i = EA·(ℓ_i/m_i − 1)   when taut (m_i < ℓ_i),   0 when slack
//! ```
//!
//! A node with the capstan factor E = e^{μθ} (θ its wrap at φ, μ the
//! friction) and an additive hold H (a closed clamp, else 0) holds the
//! thread while T_{i+1} ≤ E·T_i + H and T_i ≤ E·T_{i+1} + H; beyond that
//! the thread slides toward the larger tension with the bound met
//! (Euler–Eytelwein). The regulator passes thread into span 0 while T_0
//! reaches its passing tension, never back. The stitch's anchor holds; at
//! the moment the stitch is set the finished stitch leaves the last span
//! with the strain it has there.
//!
//! Friction is rate-independent, so each φ is an incremental problem: from
//! the state at the previous φ, find the thread moved across each node
//! (the fluxes) such that every node holds or slips by its law. Each step
//! is solved part by part: the nodes that hold split the chain into parts,
//! each balanced by one monotone equation in one span's thread; which nodes
//! hold starts as at the previous φ and is corrected until the answer
//! agrees with it. Where that does not settle, Newton's method on every
//! node's equation (a tridiagonal system) balances the step from the
//! previous φ's fluxes. Either answer meets the same laws to the same
//! tolerance. The cycle is
//! repeated until the state at its start repeats: the periodic steady
//! state.

use std::ops::RangeInclusive;

use serde::Serialize;

use crate::geometry::since_deg;

/// Cycles run at most to reach the periodic steady state.
pub const MAX_CYCLES: usize = 60;

/// The state has settled when no span's thread changes by more than this
/// over a cycle, mm.
pub const SETTLE_MM: f64 = 1e-5;

/// A thread path's real thread and the parts that hold it, in numbers
/// (the model file's `[thread.physics]`, resolved for one path).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ThreadPhysics {
    /// The thread, in words.
    pub thread: Option<String>,
    /// Where the numbers come from.
    pub source: Option<String>,
    /// Axial stiffness EA, N.
    pub ea_n: f64,
    /// Breaking force, N.
    pub breaking_n: f64,
    /// The tension past the regulator at which it passes thread, N.
    pub regulator_n: f64,
    pub spring: Option<SpringAt>,
    pub clamps: Vec<ClampAt>,
}

/// A check spring after the path's node `node` (it acts on the thread from
/// there to the next node).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct SpringAt {
    pub node: usize,
    pub take_up_mm: f64,
    /// [F₀, F₁], N.
    pub force_n: [f64; 2],
}

/// A thread clamp at the path's node `node`.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct ClampAt {
    pub node: usize,
    pub hold_n: f64,
    /// When it is closed, [from, to] in the model's φ, deg; `None`: always.
    pub closed_deg: Option<[f64; 2]>,
}

impl ClampAt {
    /// Its hold at model-φ `phi_deg`: `hold_n` while closed, else 0.
    pub fn hold_at(&self, phi_deg: f64) -> f64 {
        match self.closed_deg {
            None => self.hold_n,
            Some([from, to]) => {
                let (a, len) = (since_deg(from, 0.0), since_deg(to, from));
                let closed = len == 0.0 || since_deg(phi_deg, a) <= len;
                if closed { self.hold_n } else { 0.0 }
            }
        }
    }
}

/// A check spring (take-up spring) on one span: it holds thread out of the
/// path, lengthening the span's reach by `take_up_mm·(1 − x)`, where x, its
/// travel from rest (0) to its end (1), balances the thread's tension:
/// x = (T − F₀)/(F₁ − F₀) clamped to [0, 1].
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct CheckSpring {
    /// The span it acts on.
    pub span: usize,
    /// The thread it stores over its travel, mm.
    pub take_up_mm: f64,
    /// The thread tension that holds it at the start and at the end of its
    /// travel, [F₀, F₁] with 0 ≤ F₀ < F₁, N.
    pub force_n: [f64; 2],
}

/// The thread and the machine's parts that hold it, for one thread path.
#[derive(Debug, Clone, PartialEq)]
pub struct Chain {
    /// Axial stiffness EA of the thread, N (tension per unit strain).
    pub ea_n: f64,
    /// The tension past the regulator at which it passes thread, N.
    pub pass_n: f64,
    pub spring: Option<CheckSpring>,
}

/// What the chain meets over one cycle of a uniform φ grid of n positions:
/// every array is row-major, one row per φ.
#[derive(Debug, Clone, Copy)]
pub struct Course<'a> {
    /// The spans' reaches ℓ_i(φ_k), n × S, mm.
    pub len_mm: &'a [f64],
    /// The nodes' capstan factors e^{μθ}, n × (S − 1).
    pub factor: &'a [f64],
    /// The nodes' additive holds (closed clamps), n × (S − 1), N.
    pub hold_n: &'a [f64],
    /// The step at which the finished stitch leaves the last span: before
    /// solving φ_k for k = `set_k` the last span gives up `set_mm` of thread
    /// at the strain it has (its reach already drops by it at φ_k).
    pub set_k: usize,
    /// The finished stitch's length L_s, mm.
    pub set_mm: f64,
}

/// The periodic steady state of a thread over the cycle.
#[derive(Debug, Clone, PartialEq)]
pub struct Tensions {
    /// The number of spans S.
    pub spans: usize,
    /// Tension of every span at every φ, n × S, N (0 where slack).
    pub tension_n: Vec<f64>,
    /// Thread each span holds beyond its reach (slack that is not in a
    /// check spring's store), n × S, mm.
    pub slack_mm: Vec<f64>,
    /// Thread moved across each node in the step that ends at φ_k, toward
    /// the stitch positive, n × (S − 1), mm (unstretched).
    pub moved_mm: Vec<f64>,
    /// How each node passes thread at φ_k, n × (S − 1): 1 toward the
    /// stitch, −1 back toward the regulator, 0 holding.
    pub slip: Vec<i8>,
    /// Thread passed by the regulator in the step that ends at φ_k, mm
    /// (unstretched, ≥ 0).
    pub drawn_mm: Vec<f64>,
    /// The check spring's travel at each φ, as the thread it has given
    /// out of its store (0 at rest, its take-up at the end of its travel),
    /// mm; empty without a spring.
    pub spring_mm: Vec<f64>,
    /// Thread drawn past the regulator over the cycle, mm (unstretched).
    pub drawn_per_cycle_mm: f64,
    /// The strain the finished stitch keeps: the last span's where the
    /// stitch is set.
    pub lock_strain: f64,
    /// Cycles run from the start (the thread just drawn through every
    /// guide from the regulator at the end of the take-up's hardest pull,
    /// docs/thread-physics.md §1.7).
    pub cycles: usize,
    /// φ steps balanced in all those cycles.
    pub steps: usize,
    /// Of those, the steps the part-by-part balance left to Newton's
    /// method on the whole chain (each costs tens of ordinary steps).
    pub newton_steps: usize,
    /// Whether the state at a step repeated the last cycle's within
    /// [`SETTLE_MM`].
    pub settled: bool,
    /// The largest change of a span's thread over the last cycle, mm.
    pub change_mm: f64,
}

impl Tensions {
    /// The tension of span `i` at the `k`-th φ.
    pub fn tension(&self, k: usize, i: usize) -> f64 {
        self.tension_n[k * self.spans + i]
    }
}

/// A step the solver could not balance (a bug or a degenerate input).
#[derive(Debug, Clone, PartialEq)]
pub struct TensionError {
    /// The position in the cycle.
    pub k: usize,
    pub message: String,
}

/// A span's tension law.
#[derive(Debug, Clone, Copy)]
struct Law {
    ea: f64,
    /// A check spring's take-up and [F₀, F₁].
    spring: Option<(f64, f64, f64)>,
}

/// T = EA·(ℓ/m − 1) and dT/dm. Negative when the span is slack: a slack
/// span carries no tension (every law reads max(0, T) of it), but the
/// pulling side of a slipping node is solved on this smooth extension, so
/// Newton's method meets no kink where a span just goes taut; its roots
/// there have T ≥ 0, the same as the physical law's.
#[inline]
fn stretch_tension(ea: f64, l: f64, m: f64) -> (f64, f64) {
    (ea * (l / m - 1.0), -ea * l / (m * m))
}

/// A slack span gives thread to a taut neighbour pulling on it with this
/// fraction of its (negative) stretch tension as a push. A slack thread
/// carries no tension and gives thread freely; the push only decides, where
/// a taut span draws from two slack neighbours at once (friction cannot:
/// both carry nothing), that it draws from each in proportion to its slack,
/// and keeps Newton's matrix regular there. Slack does not move into a
/// slack neighbour (nothing pulls it; a loose loop stays where it forms
/// until a taut span draws it in), and a bound moves by no more than
/// 1e-6·EA times a giving span's slack over its reach.
const SLACK_PUSH: f64 = 1e-6;

/// How a span holds thread back at a guide that passes it on with the
/// capstan factor `e`: e·T when taut, [`SLACK_PUSH`]·T (a small push) when
/// slack; and its slope in T.
#[inline]
fn holding(t: f64, e: f64) -> (f64, f64) {
    if t >= 0.0 {
        (e * t, e)
    } else {
        (SLACK_PUSH * t, SLACK_PUSH)
    }
}

impl Law {
    /// The tension of `m` mm of thread over a reach of `l` mm, and dT/dm
    /// (negative when slack, [`stretch_tension`]).
    #[inline]
    fn tension(&self, l: f64, m: f64) -> (f64, f64) {
        let Some((s, f0, f1)) = self.spring else {
            return stretch_tension(self.ea, l, m);
        };
        // At rest the spring holds its whole store out: reach ℓ + s.
        let l_max = l + s;
        let at_rest = stretch_tension(self.ea, l_max, m);
        if at_rest.0 <= f0 {
            return at_rest;
        }
        // At the end of its travel: reach ℓ.
        let at_end = stretch_tension(self.ea, l, m);
        if at_end.0 >= f1 {
            return at_end;
        }
        // Between: the reach ℓ + s − c·(T − F₀), c = s/(F₁ − F₀), so
        // T = EA·(ℓ + s + c·F₀ − m)/(m + EA·c).
        let ea = self.ea;
        let c = s / (f1 - f0);
        let den = m + ea * c;
        let t = ea * (l_max + c * f0 - m) / den;
        (t, -ea * (ea * c + l_max + c * f0) / (den * den))
    }

    /// The thread a span holds at tension `t` ≥ 0 over a reach of `l`.
    fn thread_at(&self, l: f64, t: f64) -> f64 {
        let reach = match self.spring {
            None => l,
            Some((s, f0, f1)) => l + s * (1.0 - ((t - f0) / (f1 - f0)).clamp(0.0, 1.0)),
        };
        reach / (1.0 + t / self.ea)
    }

    /// The longest reach of a span: with a check spring at rest.
    fn max_reach(&self, l: f64) -> f64 {
        l + self.spring.map_or(0.0, |(s, ..)| s)
    }

    /// The thread a check spring has given out of its store at tension `t`.
    fn spring_travel(&self, t: f64) -> f64 {
        self.spring
            .map_or(0.0, |(s, f0, f1)| s * ((t - f0) / (f1 - f0)).clamp(0.0, 1.0))
    }
}

/// A step has balanced when every row's residual, as a force (its Φ over
/// its ρ), is below this, N…
const TOL_N: f64 = 1e-9;
/// …or, where the damped steps stall on a kink of the laws, below this.
const STALL_N: f64 = 1e-6;
/// Newton's iterations per step.
const MAX_NEWTON: usize = 200;
/// A Newton step is halved at most this many times before it counts as
/// stalled (even a short step that lowers |Φ| is cheaper than a relaxation).
const LINE_SEARCH_HALVINGS: usize = 50;
/// Gauss–Seidel sweeps at most where Newton's method stalls: enough to
/// leave the kink it stalled on, after which Newton's method goes on (30
/// sweeps gave the same balances at 2–3 times the cost on the MF-7923D).
const RELAX_SWEEPS: usize = 10;
/// A Newton step moves no flux by more than this, mm, before its line
/// search: where a slack span gives its thread with only the slack push
/// ([`SLACK_PUSH`]) against it, Newton's matrix is nearly singular and its
/// step runs to 10⁶ mm, which the line search would halve twenty times and
/// more (the lockstitch's residuals 110 000 → 44 000 a cycle; 0.3 mm and
/// 10 mm cost more).
const STEP_CAP_MM: f64 = 1.0;
/// Rounds of the part-by-part solve ([`Stepper::by_parts`]) before the
/// step is left to Newton's method, beyond twice the chain's spans: a
/// change of which guides hold travels about one guide a round, and a
/// guide may hold for a round before it slips the other way (the
/// MF-7923D's n3 at φ = 138°, where the released loop's thread is drawn
/// back through every guide, settles in 14 rounds).
const EXTRA_ROUNDS: usize = 8;
/// Iterations of a part's own balance, and the force its error may leave
/// on a span, N (a thousandth of the balance's tolerance).
const PART_ITERATIONS: usize = 100;
const PART_TOL_N: f64 = 1e-3 * TOL_N;
/// Newton's iterations at most of a taut part's balance
/// ([`Stepper::taut_part`]): it converges in a few from the last step's.
const TAUT_ITERATIONS: usize = 50;
/// A part's balance within this, N, is finished by one linear step
/// ([`Stepper::finish`]), which leaves its equation within `LINEAR_TOL_N`
/// (a hundredth of the balance's tolerance; the rounding of a span's thread
/// alone, 10⁻¹⁴ mm, is up to 5·10⁻¹² N of it).
const LINEAR_N: f64 = 1e-5;
const LINEAR_TOL_N: f64 = 1e-2 * TOL_N;
/// A step is halved at most this many times (2^−12 of it).
const MAX_HALVINGS: u32 = 12;

/// One φ's inputs: reaches, capstan factors, holds.
#[derive(Clone, Copy)]
struct At<'a> {
    l: &'a [f64],
    e: &'a [f64],
    h: &'a [f64],
}

/// One φ's inputs, owned (a position between two of the grid's).
#[derive(Clone)]
struct Inputs {
    l: Vec<f64>,
    e: Vec<f64>,
    h: Vec<f64>,
}

impl Inputs {
    fn of(at: At<'_>) -> Inputs {
        Inputs {
            l: at.l.to_vec(),
            e: at.e.to_vec(),
            h: at.h.to_vec(),
        }
    }

    fn at(&self) -> At<'_> {
        At {
            l: &self.l,
            e: &self.e,
            h: &self.h,
        }
    }

    /// The inputs a fraction `f` of the way to `to`.
    fn toward(&self, to: At<'_>, f: f64) -> Inputs {
        let lerp = |a: &[f64], b: &[f64]| a.iter().zip(b).map(|(a, b)| a + f * (b - a)).collect();
        Inputs {
            l: lerp(&self.l, to.l),
            e: lerp(&self.e, to.e),
            h: lerp(&self.h, to.h),
        }
    }
}

/// Across a guide with capstan factor `e` and hold `h` at its bound, from
/// the tension `t` on one side (and its derivative `dt` in a part's
/// pivot's): the tension on the other side, which pulls the thread through
/// (`pulls`: [`holding`] of `t`, plus `h`) or gives it (the inverse), and
/// its derivative.
#[inline]
fn across(t: f64, dt: f64, e: f64, h: f64, pulls: bool) -> (f64, f64) {
    if pulls {
        let (g, dg) = holding(t, e);
        (g + h, dt * dg)
    } else {
        let slope = if t - h >= 0.0 { e } else { SLACK_PUSH };
        ((t - h) / slope, dt / slope)
    }
}

/// A part's spans placed from its pivot's tension ([`Stepper::spread`]).
struct Spread {
    /// The thread the other spans hold, mm, and its derivative in the
    /// pivot's tension, mm/N.
    others: f64,
    d_others: f64,
    /// The first span's tension, N, and its derivative in the pivot's.
    t_first: f64,
    dt_first: f64,
}

/// Which of a row's two slip laws act at the current fluxes.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
struct Branch {
    forward: bool,
    backward: bool,
}

/// How a step is balanced first; each falls back as [`Stepper::balance`]
/// says.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum First {
    /// Part by part ([`Stepper::by_parts`]), a part whose spans stay taut
    /// in closed form ([`Stepper::taut_part`]), as [`solve`] does.
    Parts,
    /// Part by part, every part by its search (what the closed form is
    /// checked against).
    #[cfg(test)]
    PartsSearched,
    /// Newton's method on the whole chain.
    Newton,
}

/// The balance of one step and its buffers.
///
/// The unknowns are x[0], the thread the regulator passes, and x[i + 1],
/// the thread moved across node i (toward the stitch positive). Each node's
/// law is written as one equation (a complementarity function), with
/// r = T_{i+1} − G_i − H its forward and b = T_i − G_{i+1} − H its backward
/// excess (T the pulling span's stretch tension, negative when slack; G the
/// giving span's hold, E·T when taut, [`holding`]):
///
/// ```text
/// Φ = x − max(0, x + ρ·r) − min(0, x − ρ·b) = 0
/// ```
///
/// which holds exactly when x > 0 with r = 0, x < 0 with b = 0, or x = 0
/// with r ≤ 0 and b ≤ 0 (ρ, mm/N, scales tensions to thread). The
/// regulator's is Φ = x − max(0, x + ρ·(T_0 − T_pass)). Newton's method on
/// Φ (semismooth: the Jacobian of the branch that acts) needs no guess of
/// which guides hold: a frictionless guide slips either way with one
/// equation, and a span pulled from both ends takes its thread from the end
/// that gives it more easily.
struct Stepper {
    laws: Vec<Law>,
    pass: f64,
    x: Vec<f64>,
    trial: Vec<f64>,
    dx: Vec<f64>,
    g: Vec<f64>,
    sub: Vec<f64>,
    diag: Vec<f64>,
    sup: Vec<f64>,
    t: Vec<f64>,
    dt: Vec<f64>,
    /// ρ of each row, mm/N: the compliance of the spans it joins.
    rho: Vec<f64>,
    branch: Vec<Branch>,
    /// The step's fluxes so far (its halves add up): `moved[0]` passed by
    /// the regulator, `moved[i + 1]` across node i.
    moved: Vec<f64>,
    /// How each node is taken to pass thread in the part-by-part solve
    /// ([`Self::by_parts`]): 1 toward the stitch, −1 back, 0 holding.
    dir: Vec<i8>,
    /// Whether the regulator is taken to pass thread there.
    passing: bool,
    /// The regulator's and the nodes' choices of each round of the
    /// part-by-part solve so far, `passing` then `dir`, round after round.
    chosen: Vec<i8>,
    /// The thread each span holds in the part-by-part solve, mm.
    held: Vec<f64>,
    /// The derivatives of each span's thread and tension in the part's
    /// pivot's tension, mm/N and N/N ([`Self::spread`]).
    d_held: Vec<f64>,
    d_t: Vec<f64>,
    /// The fluxes the step started from (Newton's warm start).
    x_start: Vec<f64>,
    /// The thread of each span whose tension picks a part's pivot.
    pivot_from: Vec<f64>,
    /// A taut part's spans' tensions as affine functions of its pivot's,
    /// T_j = α_j·T_k + β_j ([`Self::taut_part`]): α_j, and β_j in N.
    alpha: Vec<f64>,
    beta: Vec<f64>,
    /// How a step is balanced first.
    first: First,
    /// The node across which the last [`Self::spread`] that found no
    /// balance met a span that would take endless thread.
    endless: Option<usize>,
    /// Steps balanced by Newton's method on the whole chain so far.
    newton_steps: usize,
}

impl Stepper {
    fn new(chain: &Chain, spans: usize) -> Stepper {
        let laws = (0..spans)
            .map(|i| Law {
                ea: chain.ea_n,
                spring: chain
                    .spring
                    .filter(|s| s.span == i)
                    .map(|s| (s.take_up_mm, s.force_n[0], s.force_n[1])),
            })
            .collect();
        let zeros = vec![0.0; spans];
        Stepper {
            laws,
            pass: chain.pass_n,
            x: zeros.clone(),
            trial: zeros.clone(),
            dx: zeros.clone(),
            g: zeros.clone(),
            sub: zeros.clone(),
            diag: zeros.clone(),
            sup: zeros.clone(),
            t: zeros.clone(),
            dt: zeros.clone(),
            rho: zeros.clone(),
            branch: vec![Branch::default(); spans],
            moved: zeros.clone(),
            dir: vec![0; spans - 1],
            passing: false,
            chosen: Vec::with_capacity((2 * spans + EXTRA_ROUNDS) * spans),
            held: zeros.clone(),
            d_held: zeros.clone(),
            d_t: zeros.clone(),
            pivot_from: zeros.clone(),
            alpha: zeros.clone(),
            beta: zeros.clone(),
            x_start: zeros,
            first: First::Parts,
            endless: None,
            newton_steps: 0,
        }
    }

    /// Tensions at the fluxes `x` (into `t`, `dt`), each row's residual Φ
    /// (into `g`) and branch; the sum of squares of Φ, or `None` when a
    /// span would hold no thread.
    fn residual(&mut self, m: &[f64], x: &[f64], at: At<'_>) -> Option<f64> {
        let s = m.len();
        for i in 0..s {
            let out = if i + 1 < s { x[i + 1] } else { 0.0 };
            let mi = m[i] + x[i] - out;
            if mi.is_nan() || mi <= 0.0 {
                return None;
            }
            (self.t[i], self.dt[i]) = self.laws[i].tension(at.l[i], mi);
        }
        let t = &self.t;
        // The pulling side pulls with its stretch tension (negative: a
        // slack span pulls nothing); the giving side holds ([`holding`]).
        let f = x[0] + self.rho[0] * (t[0] - self.pass);
        self.branch[0] = Branch {
            forward: f > 0.0,
            backward: false,
        };
        self.g[0] = x[0] - f.max(0.0);
        for i in 0..s - 1 {
            let (e, h, rho, xi) = (at.e[i], at.h[i], self.rho[i + 1], x[i + 1]);
            let r = t[i + 1] - holding(t[i], e).0 - h;
            let b = t[i] - holding(t[i + 1], e).0 - h;
            let (fwd, bwd) = (xi + rho * r, xi - rho * b);
            self.branch[i + 1] = Branch {
                forward: fwd > 0.0,
                backward: bwd < 0.0,
            };
            self.g[i + 1] = xi - fwd.max(0.0) - bwd.min(0.0);
        }
        Some(self.g.iter().map(|g| g * g).sum())
    }

    /// The derivative of Φ in the unknowns on the acting branches
    /// (tridiagonal), from the tensions' slopes of the last
    /// [`Self::residual`].
    fn jacobian(&mut self, at: At<'_>) {
        let s = self.t.len();
        let (t, dt) = (&self.t, &self.dt);
        let rho0 = self.rho[0];
        (self.sub[0], self.diag[0], self.sup[0]) = if self.branch[0].forward {
            (0.0, -rho0 * dt[0], rho0 * dt[0])
        } else {
            (0.0, 1.0, 0.0)
        };
        for i in 0..s - 1 {
            let (row, e, rho) = (i + 1, at.e[i], self.rho[i + 1]);
            // ∂r and ∂b over x_i, x_{i+1}, x_{i+2} (span i holds
            // m_i + x_i − x_{i+1}, span i + 1 holds m_{i+1} + x_{i+1} − x_{i+2}).
            let (hi, hj) = (holding(t[i], e).1 * dt[i], holding(t[i + 1], e).1 * dt[i + 1]);
            let (ri, rj) = (-hi, dt[i + 1]);
            let (bi, bj) = (dt[i], -hj);
            let dr = [ri, rj - ri, -rj];
            let db = [bi, bj - bi, -bj];
            let mut j = [0.0, 1.0, 0.0];
            let br = self.branch[row];
            for c in 0..3 {
                if br.forward {
                    j[c] -= rho * dr[c] + if c == 1 { 1.0 } else { 0.0 };
                }
                if br.backward {
                    j[c] -= -rho * db[c] + if c == 1 { 1.0 } else { 0.0 };
                }
            }
            self.sub[row] = j[0];
            self.diag[row] = j[1];
            self.sup[row] = if row + 1 < s { j[2] } else { 0.0 };
        }
    }

    /// Balances the step to `at`: moves thread in `m` and adds the fluxes
    /// to `moved`. Starts from the previous step's fluxes; when Newton's
    /// method stalls from there, starts again from none; false when that
    /// stalls too (`m` untouched).
    fn balance(&mut self, m: &mut [f64], at: At<'_>) -> bool {
        let s = m.len();
        // ρ: the compliance of the spans a row joins, mm/N.
        let ea = self.laws[0].ea;
        self.rho[0] = m[0] / ea;
        for i in 0..s - 1 {
            self.rho[i + 1] = 0.5 * (m[i] + m[i + 1]) / ea;
        }
        self.x_start.copy_from_slice(&self.x);
        if !(self.first != First::Newton && self.by_parts(m, at)) {
            self.newton_steps += 1;
            self.x.copy_from_slice(&self.x_start);
            if !self.newton(m, at) {
                self.x.fill(0.0);
                if !self.newton(m, at) {
                    return false;
                }
            }
        }
        for i in 0..s {
            let out = if i + 1 < s { self.x[i + 1] } else { 0.0 };
            m[i] += self.x[i] - out;
            self.moved[i] += self.x[i];
        }
        true
    }

    /// Balances the step part by part: the nodes taken to hold split the
    /// chain into parts that keep their thread (or, the first, take it from
    /// the passing regulator); within a part every node slips its way, so
    /// each span's tension follows from one span's by the capstan law and
    /// the part's thread fixes it ([`Self::solve_part`]). Which nodes hold
    /// starts as at the last step and is corrected where the answer
    /// contradicts it (a holding node beyond its bound slips, a slipping
    /// node whose flux turned holds, a slipping node across which a part
    /// would give endless thread holds) until nothing does, at most
    /// 2·S + [`EXTRA_ROUNDS`] times. True with `self.x` the step's fluxes
    /// and every row balanced within [`TOL_N`] ([`Self::residual`]); false
    /// leaves the step to Newton's method.
    fn by_parts(&mut self, m: &[f64], at: At<'_>) -> bool {
        let s = m.len();
        self.passing = self.branch[0].forward;
        for (d, b) in self.dir.iter_mut().zip(&self.branch[1..]) {
            *d = b.forward as i8 - b.backward as i8;
        }
        // A law counts as broken beyond a tenth of the balance's tolerance.
        let eps = 0.1 * TOL_N;
        self.pivot_from.copy_from_slice(m);
        self.chosen.clear();
        let mut one_at_a_time = false;
        let mut retried = false;
        'rounds: for _ in 0..2 * s + EXTRA_ROUNDS {
            let mut a = 0;
            while a < s {
                let mut b = a;
                while b + 1 < s && self.dir[b] != 0 {
                    b += 1;
                }
                self.endless = None;
                if !self.solve_part(m, at, a, b) {
                    // A guide whose pulling side cannot overcome its hold
                    // (a slack span, or a clamp's hold above the pull)
                    // would leave the giving side endless thread: it holds.
                    let Some(j) = self.endless else { return false };
                    self.dir[j] = 0;
                    continue 'rounds;
                }
                a = b + 1;
            }
            // Each span's tension is as its part left it in `t`.
            let mut changed = false;
            let t0 = self.t[0];
            if self.passing && self.x[0] < 0.0 {
                self.passing = false;
                changed = true;
            } else if !self.passing && t0 > self.pass + eps {
                self.passing = true;
                changed = true;
            }
            let mut t_i = t0;
            for i in 0..s - 1 {
                let t_j = self.t[i + 1];
                let (e, h, x) = (at.e[i], at.h[i], self.x[i + 1]);
                let d = match self.dir[i] {
                    1 if x < 0.0 => 0,
                    -1 if x > 0.0 => 0,
                    0 if t_j - holding(t_i, e).0 - h > eps => 1,
                    0 if t_i - holding(t_j, e).0 - h > eps => -1,
                    d => d,
                };
                t_i = t_j;
                if d != self.dir[i] {
                    if one_at_a_time && changed {
                        continue;
                    }
                    changed = true;
                    self.dir[i] = d;
                }
            }
            if changed && !one_at_a_time {
                // Every contradiction corrected at once can cycle (a slack
                // chain whose guides turn each other, four rounds round):
                // once a round's choice repeats an earlier round's, one
                // correction a round, the first along the chain.
                let passing = self.passing as i8;
                one_at_a_time = self
                    .chosen
                    .chunks_exact(self.dir.len() + 1)
                    .any(|c| c[0] == passing && c[1..] == self.dir[..]);
                self.chosen.push(passing);
                self.chosen.extend_from_slice(&self.dir);
            }
            if !changed {
                let x = std::mem::take(&mut self.x);
                let balanced = self.residual(m, &x, at).is_some() && self.within(TOL_N);
                self.x = x;
                if !balanced && !retried {
                    // Pivots chosen from the answer's tensions instead.
                    retried = true;
                    self.pivot_from.copy_from_slice(&self.held);
                    continue;
                }
                return balanced;
            }
        }
        false
    }

    /// Solves the part of spans `a..=b` (every node between them slipping
    /// as `dir` says, none across its ends but the regulator's passing
    /// thread) into `held` and the fluxes `x[a..=b]`; false where it has no
    /// balance (a span with no thread).
    ///
    /// The part is solved in the thread h of one span, its pivot: every
    /// other span's tension follows from the pivot's across the slipping
    /// nodes, and what they hold then rises with h (Newton's method kept
    /// within a bracket). The pivot is the slackest of the part's sources
    /// (spans that give thread on both sides) at the step's start (or,
    /// tried again, in the answer found): from a source outward every
    /// guide is crossed toward the span that pulls, so the slack push only
    /// shrinks tensions ([`SLACK_PUSH`]); crossed toward the span that
    /// gives, it would multiply the rounding of one by 10⁶ at every slack
    /// span passed (a slack span that is not a source, the slackest at the
    /// step's start, is one the answer drains or a guide beside it holds).
    /// Where the regulator passes and none of the part's sources is slack,
    /// T_0 at its passing tension fixes the part without a search.
    fn solve_part(&mut self, m: &[f64], at: At<'_>, a: usize, b: usize) -> bool {
        let total: f64 = m[a..=b].iter().sum();
        let regulated = a == 0 && self.passing;
        let mut k = a;
        let mut t_min = f64::INFINITY;
        for j in a..=b {
            // A source: the span gives thread on both sides (or meets the
            // part's end).
            let gives_left = j == a || self.dir[j - 1] < 0;
            let gives_right = j == b || self.dir[j] > 0;
            if !(gives_left && gives_right) {
                continue;
            }
            let t = self.laws[j].tension(at.l[j], self.pivot_from[j]).0;
            if t < t_min {
                (k, t_min) = (j, t);
            }
        }
        if regulated && t_min >= 0.0 {
            // A taut part from the passing regulator: T_0 at its passing
            // tension fixes every span's.
            k = 0;
        }
        let law = self.laws[k];
        if regulated && k == 0 {
            self.held[0] = law.thread_at(at.l[0], self.pass);
            if self.spread(at, a, b, 0, self.pass).is_none() {
                return false;
            }
        } else if a == b {
            self.held[a] = m[a];
        } else {
            // Passing regulator: T_0 at its tension; else the part's thread.
            let (mut lo, mut hi) = (0.0, if regulated { f64::INFINITY } else { total });
            // From the pivot's thread moved as in the last step.
            let out = if k + 1 < m.len() { self.x_start[k + 1] } else { 0.0 };
            let mut m_k = m[k] + self.x_start[k] - out;
            if !(m_k > lo && m_k < hi) {
                m_k = m[k];
            }
            if !regulated
                && self.first == First::Parts
                && self.taut_part(at, a, b, k, total, law.tension(at.l[k], m_k).0)
            {
                return self.part_fluxes(m, at, a, b, k, false);
            }
            let mut solved = false;
            for _ in 0..PART_ITERATIONS {
                let (t_k, dt_k) = law.tension(at.l[k], m_k);
                let spread = self.spread(at, a, b, k, t_k);
                let feasible = spread.is_some();
                let next = match spread {
                    None => {
                        hi = m_k;
                        0.5 * (lo + hi)
                    }
                    Some(spread) => {
                        // f rises with m_k; its error as a force on the
                        // pivot (where conservation puts it) is `f_n`.
                        let (f, df, f_n) = if regulated {
                            let f = self.pass - spread.t_first;
                            (f, -spread.dt_first * dt_k, f)
                        } else {
                            let f = m_k + spread.others - total;
                            (f, 1.0 + spread.d_others * dt_k, f * dt_k)
                        };
                        if f_n.abs() <= PART_TOL_N {
                            solved = true;
                            break;
                        }
                        if f > 0.0 {
                            hi = m_k;
                        } else {
                            lo = m_k;
                        }
                        let next = m_k - f / df;
                        if next > lo && next < hi {
                            if f_n.abs() <= LINEAR_N && self.finish(at, a..=b, k, next, t_k, total) {
                                m_k = next;
                                solved = true;
                                break;
                            }
                            next
                        } else if hi.is_finite() {
                            0.5 * (lo + hi)
                        } else {
                            2.0 * m_k
                        }
                    }
                };
                if next == m_k {
                    // Rounding-bound: the answer where `held` is whole.
                    solved = feasible;
                    break;
                }
                m_k = next;
            }
            // `held` is that of the last m_k tried, the answer.
            if !solved {
                return false;
            }
            self.held[k] = m_k;
        }
        self.part_fluxes(m, at, a, b, k, regulated)
    }

    /// The fluxes of the part of spans `a..=b` with pivot `k`, each span
    /// holding `held`: into the part from the left (the regulator's, where
    /// it passes: all the part holds beyond its thread), and none out at
    /// its right; the pivot keeps what conservation leaves it, and its
    /// tension follows. False where that leaves it no thread.
    fn part_fluxes(&mut self, m: &[f64], at: At<'_>, a: usize, b: usize, k: usize, regulated: bool) -> bool {
        self.x[a] = if regulated {
            (a..=b).map(|j| self.held[j] - m[j]).sum()
        } else {
            0.0
        };
        for j in a..k {
            self.x[j + 1] = self.x[j] + m[j] - self.held[j];
        }
        let mut out = 0.0;
        for j in (k + 1..=b).rev() {
            self.x[j] = out + self.held[j] - m[j];
            out = self.x[j];
        }
        self.held[k] = m[k] + self.x[k] - out;
        self.t[k] = self.laws[k].tension(at.l[k], self.held[k]).0;
        self.held[k] > 0.0
    }

    /// The balance of the part of spans `a..=b` (none of them with a check
    /// spring) where every span of it is taut, from the pivot `k`'s tension
    /// `t_guess`, N: into `t` and `held`; false where the part has a spring
    /// or its balance lies where a span is slack (the search of
    /// [`Self::solve_part`] then).
    ///
    /// With every guide crossed from a taut side, each span's tension is
    /// affine in the pivot's, T_j = α_j·T_k + β_j: across a guide toward the
    /// side that pulls, T' = E·T + H; toward the side that gives,
    /// T' = (T − H)/E (the capstan bound, [`across`]). That holds for T_k ≥
    /// T_min, where every tension crossed from is at least 0 (or H). There
    /// the part's thread, G(T_k) = Σ_j ℓ_j·EA/(EA + T_j) − its thread in
    /// all, falls and is convex in T_k, so its root is the part's balance
    /// and Newton's method from below it climbs to it without overshoot
    /// (a step from above lands below, or at T_min). The same equation as
    /// the search's, the spans' tensions written out once instead of
    /// spread afresh at every iteration.
    fn taut_part(&mut self, at: At<'_>, a: usize, b: usize, k: usize, total: f64, t_guess: f64) -> bool {
        if self.laws[a..=b].iter().any(|law| law.spring.is_some()) {
            return false;
        }
        let mut t_min = f64::NEG_INFINITY;
        // Across node j from a side at α·T + β: the other side's (α, β),
        // and the least T_k where that crossing is from a taut side.
        let cross = |(alpha, beta): (f64, f64), e: f64, h: f64, pulls: bool, t_min: &mut f64| {
            if pulls {
                *t_min = t_min.max(-beta / alpha);
                (e * alpha, e * beta + h)
            } else {
                *t_min = t_min.max((h - beta) / alpha);
                (alpha / e, (beta - h) / e)
            }
        };
        (self.alpha[k], self.beta[k]) = (1.0, 0.0);
        let mut ab = (1.0, 0.0);
        for j in k..b {
            ab = cross(ab, at.e[j], at.h[j], self.dir[j] > 0, &mut t_min);
            (self.alpha[j + 1], self.beta[j + 1]) = ab;
        }
        ab = (1.0, 0.0);
        for j in (a..k).rev() {
            ab = cross(ab, at.e[j], at.h[j], self.dir[j] < 0, &mut t_min);
            (self.alpha[j], self.beta[j]) = ab;
        }
        // G(T_k) and its slope (the chain has one EA); the balance's error
        // as a force on the pivot is G·dT_k/dm_k.
        let ea = self.laws[k].ea;
        let part = a..=b;
        let g = |t: f64| {
            let (mut g, mut dg) = (-total, 0.0);
            for j in part.clone() {
                let inv = 1.0 / (ea + self.alpha[j] * t + self.beta[j]);
                let held = at.l[j] * ea * inv;
                g += held;
                dg -= held * inv * self.alpha[j];
            }
            (g, dg)
        };
        let mut t = if t_guess.is_finite() { t_guess.max(t_min) } else { t_min };
        let mut solved = false;
        for _ in 0..TAUT_ITERATIONS {
            let (g_t, dg_t) = g(t);
            let f_n = g_t * (ea + t) * (ea + t) / (ea * at.l[k]);
            if f_n.abs() <= PART_TOL_N {
                solved = true;
                break;
            }
            let mut next = t - g_t / dg_t;
            if next.is_nan() || next < t_min {
                if t == t_min {
                    // The root lies below T_min: a span goes slack.
                    return false;
                }
                next = t_min;
            }
            if (next - t).abs() <= PART_TOL_N {
                // The rounding of G alone moves T_k by more than the
                // balance's error once it is this close.
                t = next;
                solved = true;
                break;
            }
            t = next;
        }
        if !(solved && t.is_finite()) {
            return false;
        }
        for j in a..=b {
            let t_j = self.alpha[j] * t + self.beta[j];
            self.t[j] = t_j;
            self.held[j] = at.l[j] * ea / (ea + t_j);
        }
        true
    }

    /// The last Newton step of the balance of the part of spans `part`
    /// ([`Self::solve_part`]), the pivot `k`'s thread from the last tried
    /// (at tension `t_k`) to `m_k`, taken without another
    /// [`Self::spread`]: every other span's tension and thread follow the
    /// pivot's tension by their derivatives there. So near the balance
    /// (within [`LINEAR_N`]) what this leaves out is second order in the
    /// step, about 10⁻¹³ mm on the MF-7923D, where one more spread is a
    /// third of the part's work. True where the part's equation then holds
    /// within [`LINEAR_TOL_N`], the pivot's own law taken exact; a step
    /// across a kink of a law (a span going slack, a check spring at the end
    /// of its travel) leaves it off, and `held` and `t` go to the next
    /// spread (0.4 % of the finishes over 23 settings of three presets).
    fn finish(&mut self, at: At<'_>, part: RangeInclusive<usize>, k: usize, m_k: f64, t_k: f64, total: f64) -> bool {
        let (t_now, dt_now) = self.laws[k].tension(at.l[k], m_k);
        let dt = t_now - t_k;
        let a = *part.start();
        let mut others = 0.0;
        for j in part.filter(|&j| j != k) {
            self.held[j] += self.d_held[j] * dt;
            self.t[j] += self.d_t[j] * dt;
            others += self.held[j];
        }
        let f_n = if a == 0 && self.passing {
            self.pass - if k == a { t_now } else { self.t[a] }
        } else {
            (m_k + others - total) * dt_now
        };
        f_n.abs() <= LINEAR_TOL_N
    }

    /// Every span of the part `a..=b` but the pivot `k` at the tension that
    /// follows from the pivot's `t_k` across the slipping nodes between
    /// (each at its capstan bound as `dir` says, [`holding`] on a slack
    /// side), into `t`, and the thread each holds, into `held`; `None` where a span
    /// would take endless thread (its tension at or below −EA), with the
    /// node crossed to it in `endless`.
    fn spread(&mut self, at: At<'_>, a: usize, b: usize, k: usize, t_k: f64) -> Option<Spread> {
        let mut spread = Spread {
            others: 0.0,
            d_others: 0.0,
            t_first: t_k,
            dt_first: 1.0,
        };
        // Rightward: span j + 1 from span j across node j (span j + 1
        // pulls where the thread moves toward the stitch).
        let (mut t, mut dt) = (t_k, 1.0);
        for j in k..b {
            (t, dt) = across(t, dt, at.e[j], at.h[j], self.dir[j] > 0);
            if self.hold_at(at, j + 1, t, dt, &mut spread).is_none() {
                self.endless = Some(j);
                return None;
            }
        }
        // Leftward: span j from span j + 1.
        let (mut t, mut dt) = (t_k, 1.0);
        for j in (a..k).rev() {
            (t, dt) = across(t, dt, at.e[j], at.h[j], self.dir[j] < 0);
            if self.hold_at(at, j, t, dt, &mut spread).is_none() {
                self.endless = Some(j);
                return None;
            }
            (spread.t_first, spread.dt_first) = (t, dt);
        }
        Some(spread)
    }

    /// Span `j` at tension `t` (whose derivative in the pivot's is `dt`):
    /// its tension into `t`, the thread it holds into `held` and `spread`.
    #[inline]
    fn hold_at(&mut self, at: At<'_>, j: usize, t: f64, dt: f64, spread: &mut Spread) -> Option<()> {
        let law = &self.laws[j];
        if t <= -law.ea || t.is_nan() {
            return None;
        }
        let (held, d_held) = if law.spring.is_none() {
            // m = ℓ/(1 + T/EA), dm/dT = −m/(EA + T).
            let inv = 1.0 / (law.ea + t);
            let held = at.l[j] * law.ea * inv;
            (held, -held * inv)
        } else {
            let held = law.thread_at(at.l[j], t);
            (held, 1.0 / law.tension(at.l[j], held).1)
        };
        self.held[j] = held;
        self.t[j] = t;
        self.d_held[j] = dt * d_held;
        self.d_t[j] = dt;
        spread.others += held;
        spread.d_others += dt * d_held;
        Some(())
    }

    /// Balances the step from `from` to `to`; where Newton's method stalls
    /// (a sudden change turns several guides at once), in halves, down to
    /// 2^−`depth` of the step, the inputs interpolated linearly: the path
    /// the thread follows between the two positions.
    fn advance(&mut self, m: &mut [f64], from: &Inputs, to: At<'_>, depth: u32) -> Result<(), String> {
        if self.balance(m, to) {
            return Ok(());
        }
        if depth == 0 {
            return Err(
                "the thread's balance does not converge (a span with no thread, or holds that cannot be met)".into(),
            );
        }
        let mid = from.toward(to, 0.5);
        self.x.fill(0.0);
        self.advance(m, from, mid.at(), depth - 1)?;
        self.advance(m, &mid, to, depth - 1)
    }

    /// Semismooth Newton on Φ from `self.x`, damped so that |Φ|² falls;
    /// false when it stalls.
    fn newton(&mut self, m: &[f64], at: At<'_>) -> bool {
        let s = m.len();
        let x = std::mem::take(&mut self.x);
        let merit = self.residual(m, &x, at);
        self.x = x;
        let Some(mut merit) = merit else { return false };
        for _ in 0..MAX_NEWTON {
            if self.within(TOL_N) {
                return true;
            }
            self.jacobian(at);
            solve_tridiagonal(&self.sub, &mut self.diag, &self.sup, &mut self.g, &mut self.dx);
            let dx_max = self.dx.iter().fold(0.0f64, |a, d| a.max(d.abs()));
            let mut alpha = (STEP_CAP_MM / dx_max).min(1.0);
            let mut accepted = false;
            for _ in 0..LINE_SEARCH_HALVINGS {
                for j in 0..s {
                    self.trial[j] = self.x[j] - alpha * self.dx[j];
                }
                let trial = std::mem::take(&mut self.trial);
                let r = self.residual(m, &trial, at);
                self.trial = trial;
                if let Some(r) = r
                    && r <= (1.0 - 1e-4 * alpha) * merit
                {
                    merit = r;
                    std::mem::swap(&mut self.x, &mut self.trial);
                    accepted = true;
                    break;
                }
                alpha *= 0.5;
            }
            if !accepted {
                // Stalled on a kink of the laws (a span squeezed between
                // two guides at their bounds): relax row by row, then go on.
                if !self.relax(m, at) {
                    return false;
                }
                let x = std::mem::take(&mut self.x);
                let r = self.residual(m, &x, at);
                self.x = x;
                match r {
                    Some(r) if r < merit => merit = r,
                    _ => return self.within(STALL_N),
                }
            }
        }
        self.within(TOL_N)
    }

    /// Gauss–Seidel sweeps over the rows, each row's law solved exactly in
    /// its own flux with its neighbours' held ([`root`]): slow, but every
    /// sweep brings a monotone system like this one closer to its
    /// solution, kinks or not. False when a span would hold no thread.
    fn relax(&mut self, m: &[f64], at: At<'_>) -> bool {
        let s = m.len();
        for sweep in 0..RELAX_SWEEPS {
            for jj in 0..s {
                let j = if sweep % 2 == 0 { jj } else { s - 1 - jj };
                self.x[j] = self.row_solution(m, at, j);
            }
            let x = std::mem::take(&mut self.x);
            let ok = self.residual(m, &x, at).is_some();
            self.x = x;
            if !ok {
                return false;
            }
            if self.within(TOL_N) {
                break;
            }
        }
        true
    }

    /// The flux of row `j` that meets its law with the other fluxes held.
    fn row_solution(&self, m: &[f64], at: At<'_>, j: usize) -> f64 {
        let s = m.len();
        let x = &self.x;
        let next = |j: usize| if j < s { x[j] } else { 0.0 };
        // The thread span i holds with row j's flux at `v`.
        let held = |i: usize, v: f64| {
            let inflow = if i == j { v } else { x[i] };
            let out = if i + 1 == j { v } else { next(i + 1) };
            m[i] + inflow - out
        };
        let t_of = |i: usize, v: f64| self.laws[i].tension(at.l[i], held(i, v)).0;
        // Where span i keeps some thread.
        let eps = 1e-12;
        if j == 0 {
            // The regulator: passes while span 0 is above its tension.
            let excess = |v: f64| t_of(0, v) - self.pass;
            if excess(0.0) <= 0.0 {
                return 0.0;
            }
            let hi = self.laws[0].max_reach(at.l[0]) + next(1) - m[0] + 1.0;
            return root(excess, 0.0, hi);
        }
        let i = j - 1;
        let (e, h) = (at.e[i], at.h[i]);
        let r = |v: f64| t_of(j, v) - holding(t_of(i, v), e).0 - h;
        let b = |v: f64| t_of(i, v) - holding(t_of(j, v), e).0 - h;
        if r(0.0) > 0.0 {
            // Forward, until span i (which gives) would be empty.
            root(r, 0.0, m[i] + x[i] - eps)
        } else if b(0.0) > 0.0 {
            // Backward, until span j would be empty; b rises with the flux.
            root(|v| -b(v), next(j + 1) - m[j] + eps, 0.0)
        } else {
            0.0
        }
    }

    /// The step to φ_k into `out`: what the regulator passed, the thread
    /// moved across each node and how, each span's tension and slack, the
    /// check spring's travel.
    fn record(&self, out: &mut Tensions, k: usize, m: &[f64], at: At<'_>) {
        let s = m.len();
        let nodes = s - 1;
        out.drawn_mm[k] = self.moved[0].max(0.0);
        out.moved_mm[k * nodes..(k + 1) * nodes].copy_from_slice(&self.moved[1..]);
        for (slip, b) in out.slip[k * nodes..(k + 1) * nodes].iter_mut().zip(&self.branch[1..]) {
            *slip = b.forward as i8 - b.backward as i8;
        }
        for i in 0..s {
            let law = &self.laws[i];
            let t = self.t[i].max(0.0);
            out.tension_n[k * s + i] = t;
            // A span carrying tension has no slack, though rounding may
            // leave its thread a hair over its reach.
            out.slack_mm[k * s + i] = if t > 0.0 {
                0.0
            } else {
                (m[i] - law.max_reach(at.l[i])).max(0.0)
            };
            if law.spring.is_some() {
                out.spring_mm[k] = law.spring_travel(t);
            }
        }
    }

    /// Whether every row's residual, as a force, is within `tol_n`.
    fn within(&self, tol_n: f64) -> bool {
        self.g.iter().zip(&self.rho).all(|(g, rho)| g.abs() <= rho * tol_n)
    }
}

/// A row's law is met by [`root`] when its excess is within this, N: a
/// hundredth of the balance's tolerance.
const ROW_TOL_N: f64 = 1e-2 * TOL_N;

/// The root of `f`, decreasing from f(lo) > 0 to f(hi) < 0 (or the end it
/// does not cross): regula falsi with the Illinois rule (the end that stays
/// has its value halved, so both ends move), which converges superlinearly
/// on these piecewise-smooth laws and never leaves the bracket; until
/// |f| ≤ [`ROW_TOL_N`] or the bracket closes to the last bit.
fn root(f: impl Fn(f64) -> f64, mut lo: f64, mut hi: f64) -> f64 {
    let (mut f_lo, mut f_hi) = (f(lo), f(hi));
    if f_hi >= 0.0 {
        return hi;
    }
    if f_lo <= 0.0 {
        return lo;
    }
    // Which end stayed the last time (−1 lo, +1 hi): the Illinois rule.
    let mut kept = 0i8;
    for _ in 0..200 {
        let width = hi - lo;
        let mut mid = lo + width * f_lo / (f_lo - f_hi);
        if !(mid > lo && mid < hi) {
            mid = 0.5 * (lo + hi);
        }
        if mid <= lo || mid >= hi {
            break;
        }
        let f_mid = f(mid);
        if f_mid.abs() <= ROW_TOL_N {
            return mid;
        }
        if f_mid > 0.0 {
            lo = mid;
            f_lo = f_mid;
            if kept == 1 {
                f_hi *= 0.5;
            }
            kept = 1;
        } else {
            hi = mid;
            f_hi = f_mid;
            if kept == -1 {
                f_lo *= 0.5;
            }
            kept = -1;
        }
    }
    0.5 * (lo + hi)
}

/// Solves `a·x = d` for a tridiagonal `a` (sub-, main and super-diagonal;
/// `sub[0]` and the last `sup` unused), Thomas's algorithm; overwrites
/// `diag` and `d`.
fn solve_tridiagonal(sub: &[f64], diag: &mut [f64], sup: &[f64], d: &mut [f64], x: &mut [f64]) {
    let n = diag.len();
    // diag becomes the reciprocal of each eliminated pivot.
    diag[0] = 1.0 / diag[0];
    for i in 1..n {
        let w = sub[i] * diag[i - 1];
        diag[i] = 1.0 / (diag[i] - w * sup[i - 1]);
        d[i] -= w * d[i - 1];
    }
    x[n - 1] = d[n - 1] * diag[n - 1];
    for i in (0..n - 1).rev() {
        x[i] = (d[i] - sup[i] * x[i + 1]) * diag[i];
    }
}

/// The periodic steady state of `chain` over `course`: the thread starts,
/// at the end of the take-up's hardest pull (docs/thread-physics.md §1.7),
/// as if just drawn through every guide from the regulator, and whole
/// cycles are run until the state at a step repeats the last cycle's (at
/// most [`MAX_CYCLES`]).
pub fn solve(chain: &Chain, course: &Course<'_>) -> Result<Tensions, TensionError> {
    solve_steps(chain, course, First::Parts, None)
}

/// The φ over which [`start_step`] weighs how hard a draw ends, deg.
const DRAW_END_DEG: f64 = 10.0;

/// The thread just drawn through every guide from the regulator at φ_k,
/// into `m`: T_0 at the passing tension and each next span at the capstan
/// bound of the guide before it (T_{i+1} = E_i·T_i + H_i); the last span's
/// tension, N.
fn drawn_state(chain: &Chain, laws: &[Law], course: &Course<'_>, k: usize, m: &mut [f64]) -> f64 {
    let s = m.len();
    let nodes = s - 1;
    let mut t = chain.pass_n;
    for (i, (m_i, law)) in m.iter_mut().zip(laws).enumerate() {
        if i > 0 {
            t = course.factor[k * nodes + i - 1] * t + course.hold_n[k * nodes + i - 1];
        }
        *m_i = law.thread_at(course.len_mm[k * s + i], t);
    }
    t
}

/// The step the cycles start at: where the take-up has just drawn the
/// thread through every guide from the regulator, so that the state there
/// is the drawn one whatever the cycle before left, and the first cycle is
/// already the periodic one.
///
/// From the geometry alone: a step continues a draw through every guide
/// when, the thread drawn at the step before, the drawn state at this step
/// takes thread across every node toward the stitch and from the
/// regulator (each span from node i on holds more of it in all, the
/// finished stitch's thread counted as leaving the last span at the set).
/// Such steps form runs; the run that ends in the hardest pull (the most
/// thread drawn over its last [`DRAW_END_DEG`], the thread the finished
/// stitch takes away at the set not counted) has drawn the thread taut
/// through every guide, where a run that fades out has usually lost it to
/// a slack loop on the needle's side, and a shorter run may not have
/// taken up the slack it met. The start is that run's last step, or the
/// set where no run is that long. The periodic state does not depend on the
/// start; a start that misses only takes more cycles (the lockstitch's
/// needle thread: 361 steps from the end of its take-up's pull against
/// 635 from the set; docs/thread-physics.md §1.7). `laws` are the chain's
/// spans', `n` the course's positions.
fn start_step(chain: &Chain, laws: &[Law], course: &Course<'_>, n: usize) -> usize {
    let s = laws.len();
    let (mut before, mut now) = (vec![0.0; s], vec![0.0; s]);
    let mut t_before = drawn_state(chain, laws, course, n - 1, &mut before);
    // Per step: whether it continues a draw, and the thread the regulator
    // passes into it, mm.
    let mut draws = vec![false; n];
    let mut pull_mm = vec![0.0; n];
    for k in 0..n {
        let t_now = drawn_state(chain, laws, course, k, &mut now);
        let set_mm = if k == course.set_k {
            course.set_mm / (1.0 + t_before / chain.ea_n)
        } else {
            0.0
        };
        // Σ_{j ≥ i} Δm_j: the thread across node i − 1 (i = 0: from the
        // regulator).
        let mut across = set_mm;
        let mut every = true;
        for i in (0..s).rev() {
            across += now[i] - before[i];
            every &= across > 0.0;
        }
        draws[k] = every;
        pull_mm[k] = across - set_mm;
        std::mem::swap(&mut before, &mut now);
        t_before = t_now;
    }
    // The runs' last steps, each with the thread drawn over its last
    // DRAW_END_DEG; a run shorter than that (a step or a few of pull
    // between slack) cannot be told to have drawn every span taut.
    let end_steps = ((DRAW_END_DEG * n as f64 / 360.0).round() as usize).clamp(1, n);
    let mut start = (f64::NEG_INFINITY, course.set_k);
    for k in (0..n).filter(|&k| draws[k] && !draws[(k + 1) % n]) {
        let end = (0..end_steps).map(|back| (k + n - back) % n);
        if end.clone().all(|j| draws[j]) {
            let end_pull_mm: f64 = end.map(|j| pull_mm[j]).sum();
            if end_pull_mm > start.0 {
                start = (end_pull_mm, k);
            }
        }
    }
    start.1
}

/// [`solve`] with the cycles started at step `k_s` (`None`: where
/// [`start_step`] picks), each step balanced first as `first` says.
fn solve_steps(chain: &Chain, course: &Course<'_>, first: First, k_s: Option<usize>) -> Result<Tensions, TensionError> {
    let n = rows(course)?;
    let s = course.len_mm.len() / n;
    let nodes = s - 1;
    let mut st = Stepper::new(chain, s);
    st.first = first;
    let k_s = k_s.map_or_else(|| start_step(chain, &st.laws, course, n), |k| k % n);
    // The start: the thread just drawn through every guide from the
    // regulator at φ_{k_s}. Where the take-up has really drawn it so there
    // ([`start_step`]), the first cycle is already the periodic one;
    // elsewhere the cycles forget the start as they would from any other
    // step (docs/thread-physics.md §1.7).
    let mut m = vec![0.0; s];
    drawn_state(chain, &st.laws, course, k_s, &mut m);
    let mut out = Tensions {
        spans: s,
        tension_n: vec![0.0; n * s],
        slack_mm: vec![0.0; n * s],
        moved_mm: vec![0.0; n * nodes],
        slip: vec![0; n * nodes],
        drawn_mm: vec![0.0; n],
        spring_mm: if chain.spring.is_some() {
            vec![0.0; n]
        } else {
            Vec::new()
        },
        drawn_per_cycle_mm: 0.0,
        lock_strain: 0.0,
        cycles: 0,
        steps: 0,
        newton_steps: 0,
        settled: false,
        change_mm: f64::INFINITY,
    };
    let last = s - 1;
    // The state after each step of the last cycle: where this cycle's state
    // meets it again, the rest of the cycle repeats it (the same state and
    // the same inputs give the same steps), and the steady state is reached.
    let mut after = vec![f64::NAN; n * s];
    for cycle in 0..MAX_CYCLES {
        out.cycles = cycle + 1;
        let mut drawn = 0.0;
        // The cycle's steps from the start: j-th after it, at φ_k.
        for j in 0..n {
            let k = (k_s + j) % n;
            let at = At {
                l: &course.len_mm[k * s..(k + 1) * s],
                e: &course.factor[k * nodes..(k + 1) * nodes],
                h: &course.hold_n[k * nodes..(k + 1) * nodes],
            };
            // The finished stitch leaves with the strain it has (the first
            // cycle starts just after the set).
            if k == course.set_k && !(cycle == 0 && j == 0) {
                let prev = if k == 0 { n - 1 } else { k - 1 };
                let l_prev = course.len_mm[prev * s + last];
                let t = st.laws[last].tension(l_prev, m[last]).0.max(0.0);
                let strain = t / chain.ea_n;
                out.lock_strain = strain;
                m[last] -= course.set_mm / (1.0 + strain);
                if m[last].is_nan() || m[last] <= 0.0 {
                    return Err(TensionError {
                        k,
                        message: format!(
                            "the stitch's contour holds less thread than the finished stitch takes ({:.3} mm)",
                            course.set_mm
                        ),
                    });
                }
            }
            st.moved.fill(0.0);
            out.steps += 1;
            if !st.balance(&mut m, at) {
                // In halves from the previous position (the finished
                // stitch's length already gone from the last span's reach).
                let prev = if k == 0 { n - 1 } else { k - 1 };
                let mut from = Inputs::of(At {
                    l: &course.len_mm[prev * s..(prev + 1) * s],
                    e: &course.factor[prev * nodes..(prev + 1) * nodes],
                    h: &course.hold_n[prev * nodes..(prev + 1) * nodes],
                });
                if k == course.set_k {
                    from.l[last] -= course.set_mm;
                }
                st.x.fill(0.0);
                st.advance(&mut m, &from, at, MAX_HALVINGS)
                    .map_err(|message| TensionError { k, message })?;
            }
            out.newton_steps = st.newton_steps;
            let passed = st.moved[0].max(0.0);
            drawn += passed;
            st.record(&mut out, k, &m, at);
            let before = &mut after[k * s..(k + 1) * s];
            let change = m
                .iter()
                .zip(before.iter())
                .map(|(a, b)| (a - b).abs())
                .fold(0.0, f64::max);
            before.copy_from_slice(&m);
            if cycle > 0 && change <= SETTLE_MM {
                // The rest of the cycle is the last one's, already recorded.
                out.drawn_per_cycle_mm = drawn + (j + 1..n).map(|j| out.drawn_mm[(k_s + j) % n]).sum::<f64>();
                out.change_mm = change;
                out.settled = true;
                return Ok(out);
            }
            if j + 1 == n {
                out.change_mm = change;
            }
        }
        out.drawn_per_cycle_mm = drawn;
    }
    Ok(out)
}

/// The number of positions of a course, checked against its arrays.
fn rows(course: &Course<'_>) -> Result<usize, TensionError> {
    let bad = |message: String| Err(TensionError { k: 0, message });
    let (nl, nf) = (course.len_mm.len(), course.factor.len());
    if nl == 0 {
        return bad("the course has no positions".into());
    }
    // n·S reaches and n·(S − 1) factors: n = nl − nf.
    let n = nl - nf.min(nl);
    if n == 0 || nl % n != 0 || nf != n * (nl / n - 1) || course.hold_n.len() != nf || course.set_k >= n {
        return bad(format!(
            "the course's arrays do not fit one grid ({nl} reaches, {nf} factors, {} holds, set at {})",
            course.hold_n.len(),
            course.set_k
        ));
    }
    Ok(n)
}

/// The laws of the thread checked on a solution, at every φ: the regulator
/// never passes thread back and never lets the tension past it exceed its
/// hold; every node within its capstan bound, and a slipping node at it
/// with the larger tension on the side the thread goes; a slack span
/// without tension; and, where the cycle settled, the thread drawn per
/// cycle times (1 + lock strain) equal to the finished stitch. The first
/// law broken, in words; tolerances 1e-4 N and [`SETTLE_MM`] per span.
pub fn verify(chain: &Chain, course: &Course<'_>, t: &Tensions) -> Result<(), String> {
    let s = t.spans;
    let n = t.drawn_mm.len();
    let tol = 1e-4;
    for k in 0..n {
        if t.drawn_mm[k] < -1e-9 {
            return Err(format!("thread went back through the regulator at k = {k}"));
        }
        if t.tension(k, 0) > chain.pass_n + tol {
            return Err(format!(
                "the tension past the regulator, {} N, exceeds its hold {} N at k = {k}",
                t.tension(k, 0),
                chain.pass_n
            ));
        }
        for i in 0..s {
            if t.slack_mm[k * s + i] > 0.0 && t.tension(k, i) != 0.0 {
                return Err(format!("slack span {i} carries {} N at k = {k}", t.tension(k, i)));
            }
        }
        for i in 0..s - 1 {
            let (e, h) = (course.factor[k * (s - 1) + i], course.hold_n[k * (s - 1) + i]);
            let (ta, tb) = (t.tension(k, i), t.tension(k, i + 1));
            // A slack neighbour's push (SLACK_PUSH) moves a bound by up to
            // 1e-6·EA times its slack strain.
            let strain = |j: usize| t.slack_mm[k * s + j] / course.len_mm[k * s + j].max(1e-9);
            let tol = tol + 2.0 * SLACK_PUSH * chain.ea_n * (strain(i) + strain(i + 1));
            if tb > e * ta + h + tol || ta > e * tb + h + tol {
                return Err(format!(
                    "node {i} outside its capstan bound at k = {k}: {ta} N and {tb} N"
                ));
            }
            let at_bound = match t.slip[k * (s - 1) + i] {
                1 => (tb - (e * ta + h)).abs() < tol || tb == 0.0,
                -1 => (ta - (e * tb + h)).abs() < tol || ta == 0.0,
                _ => true,
            };
            if !at_bound {
                return Err(format!(
                    "node {i} slips against the larger pull at k = {k}: {ta} N and {tb} N"
                ));
            }
        }
    }
    if t.settled {
        // Thread is conserved: over the cycle that ends where the state
        // repeats, the thread drawn differs from the stitch's by the
        // change in what the spans hold, at most SETTLE_MM each, scaled
        // like the drawn thread by the stitch's strain.
        let balance = t.drawn_per_cycle_mm * (1.0 + t.lock_strain);
        if (balance - course.set_mm).abs() > s as f64 * SETTLE_MM * (1.0 + t.lock_strain) {
            return Err(format!(
                "drawn {balance} mm per cycle against the stitch's {} mm",
                course.set_mm
            ));
        }
    } else if t.change_mm <= SETTLE_MM {
        return Err("not settled, yet the last cycle repeated".into());
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::numeric::uniform;
    use proptest::prelude::*;

    /// A course of `n` positions over φ = 2πk/n: `reach(i, φ)` for each of
    /// `s` spans, `factor(i, φ)` and `hold(i, φ)` for each node.
    struct Built {
        len: Vec<f64>,
        factor: Vec<f64>,
        hold: Vec<f64>,
    }

    fn build(
        n: usize,
        s: usize,
        reach: impl Fn(usize, f64) -> f64,
        factor: impl Fn(usize, f64) -> f64,
        hold: impl Fn(usize, f64) -> f64,
    ) -> Built {
        let mut b = Built {
            len: Vec::new(),
            factor: Vec::new(),
            hold: Vec::new(),
        };
        for k in 0..n {
            let phi = std::f64::consts::TAU * k as f64 / n as f64;
            b.len.extend((0..s).map(|i| reach(i, phi)));
            b.factor.extend((0..s - 1).map(|i| factor(i, phi)));
            b.hold.extend((0..s - 1).map(|i| hold(i, phi)));
        }
        b
    }

    fn course(b: &Built, set_k: usize, set_mm: f64) -> Course<'_> {
        Course {
            len_mm: &b.len,
            factor: &b.factor,
            hold_n: &b.hold,
            set_k,
            set_mm,
        }
    }

    /// A take-up eyelet between two fixed guides, three path spans and the
    /// stitch: the eyelet swings the middle span, the stitch draws 20 mm
    /// over the turn and lets 6 mm go again before it is set at φ = 0 with
    /// 9 mm of thread.
    fn takeup(n: usize, mu_theta: f64) -> Built {
        build(
            n,
            4,
            |i, phi| match i {
                0 => 80.0,
                1 => 60.0 + 12.0 * (1.0 - phi.cos()),
                2 => 40.0 + 6.0 * phi.sin(),
                _ => 30.0 + 20.0 * (phi / std::f64::consts::TAU) - 6.0 * (phi > 4.0) as u8 as f64,
            },
            |_, _| mu_theta.exp(),
            |_, _| 0.0,
        )
    }

    const EA: f64 = 85.0;

    fn chain(pass_n: f64) -> Chain {
        Chain {
            ea_n: EA,
            pass_n,
            spring: None,
        }
    }

    /// Every law of [`verify`], and an unsettled cycle said plainly.
    fn check_laws(b: &Built, c: &Chain, t: &Tensions, set_mm: f64) {
        // `verify` reads the factors, holds, reaches and the stitch's
        // length; where the stitch is set does not enter the laws.
        verify(c, &course(b, 0, set_mm), t).unwrap_or_else(|e| panic!("{e}"));
        if !t.settled {
            assert!(t.change_mm > SETTLE_MM && t.cycles == MAX_CYCLES);
        }
    }

    /// A part's last Newton step taken by the derivatives ([`Stepper::finish`])
    /// leaves every span where one more pass over the part puts it, and is
    /// refused where the part's equation is not met there.
    #[test]
    fn a_parts_last_step_follows_its_pivot_by_the_derivatives() {
        let mut st = Stepper::new(&chain(0.4), 4);
        // One part, every guide slipping toward the stitch: span 0 gives.
        st.dir.fill(1);
        let (l, e, h) = ([80.0, 62.0, 41.0, 35.0], [1.3, 1.2, 1.25], [0.0, 0.05, 0.0]);
        let at = At { l: &l, e: &e, h: &h };
        let law = st.laws[0];
        // The balance: span 0 at 1 N less a last Newton step of thread (its
        // tension about 5·10⁻⁶ N above).
        let m_from = law.thread_at(l[0], 1.0);
        let m_k = m_from - 5e-6;
        let t_k = law.tension(l[0], m_k).0;
        let exact = st.spread(at, 0, 3, 0, t_k).unwrap();
        let total = m_k + exact.others;
        let (held, t) = (st.held.clone(), st.t.clone());
        // From the last tried, 1 N, to the balance, without another pass.
        st.spread(at, 0, 3, 0, 1.0).unwrap();
        assert!(st.finish(at, 0..=3, 0, m_k, 1.0, total));
        for j in 1..4 {
            assert!(
                (st.held[j] - held[j]).abs() < 1e-12,
                "span {j}: {} against {}",
                st.held[j],
                held[j]
            );
            assert!(
                (st.t[j] - t[j]).abs() < 1e-12,
                "span {j}: {} N against {} N",
                st.t[j],
                t[j]
            );
        }
        // Where the part would hold other thread, the step is not taken.
        st.spread(at, 0, 3, 0, 1.0).unwrap();
        assert!(!st.finish(at, 0..=3, 0, m_k, 1.0, total + 1e-6));
    }

    #[test]
    fn the_laws_hold_at_every_position() {
        let b = takeup(360, 0.3);
        let c = chain(0.8);
        let t = solve(&c, &course(&b, 0, 9.0)).unwrap();
        assert!(
            t.settled,
            "settles: change {} mm after {} cycles",
            t.change_mm, t.cycles
        );
        check_laws(&b, &c, &t, 9.0);
        assert!(t.drawn_per_cycle_mm > 8.8 && t.drawn_per_cycle_mm <= 9.0 + 1e-9);
        assert!(t.cycles <= 10, "settles in a few cycles: {}", t.cycles);
    }

    #[test]
    fn without_friction_a_taut_path_carries_one_tension() {
        let b = takeup(360, 0.0);
        let c = chain(0.8);
        let t = solve(&c, &course(&b, 0, 9.0)).unwrap();
        check_laws(&b, &c, &t, 9.0);
        for k in 0..360 {
            let row: Vec<f64> = (0..4).map(|i| t.tension(k, i)).collect();
            let hi = row.iter().cloned().fold(0.0, f64::max);
            let lo = row.iter().cloned().fold(f64::MAX, f64::min);
            assert!(
                hi - lo < 1e-6 || lo == 0.0 && hi < 1e-6,
                "one tension at k = {k}: {row:?}"
            );
        }
    }

    #[test]
    fn a_stronger_regulator_raises_the_peak() {
        let b = takeup(360, 0.3);
        let peak = |pass| {
            let t = solve(&chain(pass), &course(&b, 0, 9.0)).unwrap();
            t.tension_n.iter().cloned().fold(0.0, f64::max)
        };
        let (weak, strong) = (peak(0.5), peak(1.2));
        assert!(strong > weak + 0.5, "{weak} N → {strong} N");
    }

    #[test]
    fn a_check_spring_takes_up_the_slack_a_rigid_guide_leaves() {
        let b = takeup(360, 0.3);
        let slack = |spring: Option<CheckSpring>| {
            let c = Chain { spring, ..chain(0.8) };
            let t = solve(&c, &course(&b, 0, 9.0)).unwrap();
            check_laws(&b, &c, &t, 9.0);
            (0..360)
                .map(|k| (0..4).map(|i| t.slack_mm[k * 4 + i]).sum::<f64>())
                .fold(0.0, f64::max)
        };
        let rigid = slack(None);
        let sprung = slack(Some(CheckSpring {
            span: 0,
            take_up_mm: 8.0,
            force_n: [0.2, 0.5],
        }));
        assert!(rigid > 1.0, "the path goes slack without a spring: {rigid} mm");
        assert!(sprung < rigid - 1.0, "the spring stores it: {rigid} → {sprung} mm");
    }

    /// A closed clamp holds up to its force between its two sides.
    #[test]
    fn a_clamp_holds_its_force() {
        let b = build(
            360,
            3,
            |i, phi| if i == 1 { 50.0 + 10.0 * phi.sin() } else { 50.0 },
            |_, _| 1.0,
            |i, _| if i == 1 { 0.4 } else { 0.0 },
        );
        let c = chain(0.6);
        let t = solve(&c, &course(&b, 0, 1.0)).unwrap();
        check_laws(&b, &c, &t, 1.0);
        let jump = (0..360)
            .map(|k| (t.tension(k, 1) - t.tension(k, 2)).abs())
            .fold(0.0, f64::max);
        assert!(
            jump > 0.3 && jump < 0.4 + 1e-6,
            "the tensions across the clamp differ by up to its hold: {jump}"
        );
    }

    /// The largest difference between two arrays' entries.
    fn most_apart(a: &[f64], b: &[f64]) -> f64 {
        a.iter().zip(b).map(|(a, b)| (a - b).abs()).fold(0.0, f64::max)
    }

    /// The part-by-part balance settles the steps that once fell to
    /// Newton's method on the whole chain, each at tens of times an
    /// ordinary step's cost: where the released loop's thread is drawn
    /// back through every guide (the MF-7923D's n3 at φ = 138°: 14 rounds,
    /// with a guide whose clamp the slack side cannot overcome holding),
    /// and where the part's slackest span is not a source of its thread
    /// (n3 at φ = 197°). Before both, the default left 4 steps to Newton's
    /// method, m = 1.4 mm 14 and z = −8 mm 28; the laws hold on every
    /// answer.
    #[test]
    fn the_parts_settle_where_a_loop_is_drawn_back() {
        let model = crate::Model::preset("mf7923d").unwrap();
        for (set, most) in [(None, 0), (Some(("m", 1.4)), 6), (Some(("z", -8.0)), 2)] {
            let mut params = model.defaults();
            if let Some((name, value)) = set {
                model.set(&mut params, name, value).unwrap();
            }
            let mut newton_steps = 0;
            for (name, c) in crate::eval::tension::courses(&model, &params, 1.0).unwrap() {
                let t = solve(&c.chain, &c.course()).unwrap();
                assert!(t.settled, "{set:?} {name}");
                verify(&c.chain, &c.course(), &t).unwrap_or_else(|e| panic!("{set:?} {name}: {e}"));
                newton_steps += t.newton_steps;
            }
            assert!(newton_steps <= most, "{set:?}: {newton_steps} steps to Newton's method");
        }
    }

    /// Solved part by part or by Newton's method alone, every preset's
    /// threads meet the laws and carry the same tensions, within the
    /// balance's tolerance; the thread they draw agrees to 10⁻⁸ mm. Where
    /// the whole of a thread goes slack (the lockstitch after the hook
    /// casts its loop off) the balance holds for a range of slack splits
    /// (each span's slack within 10⁶ times its neighbour's), and the two
    /// land on states up to about 0.05 mm apart: bounded here at 0.1 mm,
    /// and to 10⁻⁴ mm where the thread stays taut somewhere (the MF-7923D).
    #[test]
    fn by_parts_and_by_newton_agree() {
        for (preset, params) in [
            ("mf7923d", vec![]),
            ("mf7923d", vec![("z", -8.0)]),
            ("mf7923d", vec![("z", 8.0)]),
            ("lockstitch", vec![]),
            ("lockstitch", vec![("catch_rise", 2.8)]),
            ("altin504", vec![]),
        ] {
            let model = crate::Model::preset(preset).unwrap();
            let mut p = model.defaults();
            for (name, v) in &params {
                model.set(&mut p, name, *v).unwrap();
            }
            let slack_bound = if preset == "mf7923d" { 1e-4 } else { 0.1 };
            for (name, c) in crate::eval::tension::courses(&model, &p, 1.0).unwrap() {
                let course = c.course();
                let parts = solve_steps(&c.chain, &course, First::Parts, Some(course.set_k)).unwrap();
                let newton = solve_steps(&c.chain, &course, First::Newton, Some(course.set_k)).unwrap();
                let at = format!("{preset} {params:?} {name}");
                verify(&c.chain, &course, &parts).unwrap_or_else(|e| panic!("{at}: {e}"));
                assert_eq!(parts.settled, newton.settled, "{at}");
                assert!(most_apart(&parts.tension_n, &newton.tension_n) < 1e-8, "{at}: tensions");
                assert!(
                    most_apart(&parts.slack_mm, &newton.slack_mm) < slack_bound,
                    "{at}: slack"
                );
                assert!(
                    most_apart(&parts.moved_mm, &newton.moved_mm) < slack_bound,
                    "{at}: moved"
                );
                let d_drawn = (parts.drawn_per_cycle_mm - newton.drawn_per_cycle_mm).abs();
                assert!(d_drawn < 1e-8, "{at}: drawn");
            }
        }
    }

    /// A chain slack from end to end whose guides, each correction of a
    /// round made at once, turn each other round in four rounds (the
    /// lockstitch with a catch rise of 1.8 mm, its needle thread at
    /// φ ≈ 55° of the first cycle) is balanced part by part, one correction
    /// a round once a round's choice repeats. It carries the tensions
    /// Newton's method finds, and its slack is split within the range the
    /// balance allows a chain slack throughout
    /// ([`by_parts_and_by_newton_agree`]).
    #[test]
    fn a_slack_chain_whose_guides_turn_each_other_is_balanced_part_by_part() {
        let chain = Chain {
            ea_n: 85.0,
            pass_n: 0.7,
            spring: Some(CheckSpring {
                span: 0,
                take_up_mm: 8.0,
                force_n: [0.25, 0.35],
            }),
        };
        let m0 = [
            50.712652923027896,
            21.231223056092986,
            10.296369556105514,
            47.08589444367569,
            63.798678661397815,
            39.98837601621525,
            7.984891941054592,
        ];
        let l = [
            42.62545405445439,
            21.30029898348718,
            10.308576716808577,
            46.964485105654994,
            63.9495580408018,
            40.0,
            7.842955050927766,
        ];
        let e = [
            1.146396840144705,
            1.6084075283992094,
            1.223833347820292,
            1.0689342179729784,
            1.1287471027225853,
            1.0,
        ];
        let h = [0.0; 6];
        // The fluxes and slips of the step before.
        let x_before = [
            0.0,
            0.034886048929237745,
            -0.042896823734892564,
            -0.054010591830660815,
            0.047948808640789764,
            -0.11714799394869146,
            -0.13799308416724898,
        ];
        let slips = [0, 1, -1, -1, 1, -1, -1];
        let at = At { l: &l, e: &e, h: &h };
        let balanced = |first: First| {
            let mut st = Stepper::new(&chain, m0.len());
            st.first = first;
            st.x.copy_from_slice(&x_before);
            for (b, d) in st.branch.iter_mut().zip(slips) {
                *b = Branch {
                    forward: d > 0,
                    backward: d < 0,
                };
            }
            let mut m = m0;
            assert!(st.balance(&mut m, at), "{first:?}: no balance");
            let t: Vec<f64> = (0..m.len())
                .map(|i| st.laws[i].tension(l[i], m[i]).0.max(0.0))
                .collect();
            (m, t, st.newton_steps)
        };
        let (parts, t_parts, newton_steps) = balanced(First::Parts);
        assert_eq!(newton_steps, 0, "left to Newton's method");
        let (newton, t_newton, _) = balanced(First::Newton);
        assert!(
            most_apart(&t_parts, &t_newton) < 1e-8,
            "{t_parts:?} against {t_newton:?}"
        );
        assert!(most_apart(&parts, &newton) < 0.1, "{parts:?} against {newton:?}");
    }

    /// A taut part's balance in closed form ([`Stepper::taut_part`]) is the
    /// search's: on random parts of 2–9 spans (capstan factors 1–4, clamps
    /// on some guides, each guide slipping either way, the pivot anywhere,
    /// the spans' threads from −0.3 to 2 N) the two give every span's
    /// thread within 10⁻¹⁰ mm and tension within 10⁻⁹ N, the closed form
    /// settles most of them, and where it declines the search's balance
    /// has a span slack.
    #[test]
    fn a_taut_part_in_closed_form_balances_as_the_search() {
        let mut uniform = uniform(11);
        let (mut closed, mut declined) = (0, 0);
        for case in 0..3000 {
            let s = 2 + case % 8;
            let ea = 20.0 + 400.0 * uniform();
            let chain = Chain {
                ea_n: ea,
                pass_n: 1.0,
                spring: None,
            };
            let l: Vec<f64> = (0..s).map(|_| 5.0 + 100.0 * uniform()).collect();
            let e: Vec<f64> = (0..s - 1).map(|_| 1.0 + 3.0 * uniform()).collect();
            let h: Vec<f64> = (0..s - 1)
                .map(|_| if uniform() < 0.3 { 0.2 * uniform() } else { 0.0 })
                .collect();
            let m: Vec<f64> = l.iter().map(|l| l / (1.0 + (-0.3 + 2.3 * uniform()) / ea)).collect();
            let at = At { l: &l, e: &e, h: &h };
            let dir: Vec<i8> = (0..s - 1).map(|_| if uniform() < 0.5 { 1 } else { -1 }).collect();
            let solved = |first: First| {
                let mut st = Stepper::new(&chain, s);
                st.first = first;
                st.dir.copy_from_slice(&dir);
                st.pivot_from.copy_from_slice(&m);
                let ok = st.solve_part(&m, at, 0, s - 1);
                (ok, st.held.clone(), st.t.clone())
            };
            let (ok_c, held_c, t_c) = solved(First::Parts);
            let (ok_s, held_s, t_s) = solved(First::PartsSearched);
            // Whether the closed form took the part: the same call, kept.
            let mut st = Stepper::new(&chain, s);
            st.dir.copy_from_slice(&dir);
            let total: f64 = m.iter().sum();
            let took = st.taut_part(at, 0, s - 1, 0, total, 0.5);
            let at_case = format!("case {case}: {s} spans, dir {dir:?}");
            assert_eq!(ok_c, ok_s, "{at_case}");
            if took {
                closed += 1;
            } else {
                declined += 1;
                if ok_s {
                    assert!(
                        t_s.iter().any(|&t| t < 1e-6),
                        "{at_case}: declined a part the search finds taut: {t_s:?}"
                    );
                }
            }
            if ok_s {
                assert!(
                    most_apart(&held_c, &held_s) < 1e-10,
                    "{at_case}: threads {held_c:?} {held_s:?}"
                );
                assert!(most_apart(&t_c, &t_s) < 1e-9, "{at_case}: tensions {t_c:?} {t_s:?}");
            }
        }
        assert!(closed > 2 * declined, "closed {closed}, declined {declined}");
    }

    /// The periodic state is the cycle's, not the start's: started where
    /// [`start_step`] picks (as [`solve`] starts), at the set or at φ_0,
    /// every thread of the presets whose set is not at φ_0 (the Altin's)
    /// and of two at φ_0 settles to the same tensions (10⁻⁹ N), slack and
    /// thread moved (10⁻⁸ mm), each guide slipping the same way wherever it
    /// passes more than rounding (10⁻⁸ mm). Where the picked start ends a
    /// draw through every guide the first cycle is already the periodic
    /// one (361 steps at 1°): the Altin's three threads, the lockstitch's
    /// and the MF-7923D's n1 and n2, which take 467 to 635 steps from the
    /// set but for the Altin's loopers (their set draws the thread through
    /// every guide too).
    #[test]
    fn the_periodic_state_does_not_depend_on_where_the_cycles_start() {
        let mut in_one_cycle = Vec::new();
        for preset in ["altin504", "mf7923d", "lockstitch"] {
            let model = crate::Model::preset(preset).unwrap();
            for (name, c) in crate::eval::tension::courses(&model, &model.defaults(), 1.0).unwrap() {
                let course = c.course();
                let picked = solve(&c.chain, &course).unwrap();
                let set = solve_steps(&c.chain, &course, First::Parts, Some(course.set_k)).unwrap();
                let zero = solve_steps(&c.chain, &course, First::Parts, Some(0)).unwrap();
                let at = format!("{preset} {name} (set at step {})", course.set_k);
                for (other, from) in [(&set, "set"), (&zero, "φ_0")] {
                    let at = format!("{at}, picked start against {from}");
                    assert!(picked.settled && other.settled, "{at}");
                    assert!(most_apart(&picked.tension_n, &other.tension_n) < 1e-9, "{at}: tensions");
                    assert!(most_apart(&picked.slack_mm, &other.slack_mm) < 1e-8, "{at}: slack");
                    assert!(most_apart(&picked.moved_mm, &other.moved_mm) < 1e-8, "{at}: moved");
                    assert!(
                        (picked.drawn_per_cycle_mm - other.drawn_per_cycle_mm).abs() < 1e-8,
                        "{at}: drawn"
                    );
                    // A guide passing no more than rounding may read as
                    // holding in one and slipping in the other.
                    for (q, (a, b)) in picked.slip.iter().zip(&other.slip).enumerate() {
                        let moved = picked.moved_mm[q].abs().max(other.moved_mm[q].abs());
                        assert!(a == b || moved < 1e-8, "{at}: slip {a} against {b} at {q}, {moved} mm");
                    }
                }
                if picked.steps == 361 {
                    in_one_cycle.push(format!("{preset} {name}"));
                    if preset != "altin504" {
                        assert!(set.steps > 361, "{at}: from the set {} steps", set.steps);
                    }
                }
            }
        }
        assert_eq!(
            in_one_cycle,
            [
                "altin504 needle",
                "altin504 lower",
                "altin504 upper",
                "mf7923d n1",
                "mf7923d n2",
                "lockstitch needle"
            ]
        );
    }

    /// Where the state forgets its start slowly, the cycles stop once a
    /// step's state moves by at most [`SETTLE_MM`] over a cycle, so two
    /// starts land within a few times that of each other: the MF-7923D at
    /// m = 1.3 to 1.5 mm (n2 takes 1 300 to 1 480 steps), where a `sweep`'s
    /// score moved by up to 5·10⁻⁵ when the start moved from the set to the
    /// end of the hardest pull. Slack, thread moved and drawn within
    /// 10·[`SETTLE_MM`], tensions within 10⁻⁴ N (measured: 4.6·10⁻⁵ mm and
    /// 1.8·10⁻⁵ N at most).
    #[test]
    fn a_slowly_settling_state_is_known_to_the_settle_tolerance() {
        let model = crate::Model::preset("mf7923d").unwrap();
        let mut apart = 0.0f64;
        for m in [1.3, 1.378, 1.4436, 1.5] {
            let mut params = model.defaults();
            model.set(&mut params, "m", m).unwrap();
            for (name, c) in crate::eval::tension::courses(&model, &params, 1.0).unwrap() {
                let course = c.course();
                let picked = solve(&c.chain, &course).unwrap();
                let set = solve_steps(&c.chain, &course, First::Parts, Some(course.set_k)).unwrap();
                let at = format!("m = {m} mm, {name}");
                assert!(picked.settled && set.settled, "{at}");
                let thread = most_apart(&picked.slack_mm, &set.slack_mm)
                    .max(most_apart(&picked.moved_mm, &set.moved_mm))
                    .max((picked.drawn_per_cycle_mm - set.drawn_per_cycle_mm).abs());
                assert!(thread <= 10.0 * SETTLE_MM, "{at}: thread {thread} mm apart");
                let tension = most_apart(&picked.tension_n, &set.tension_n);
                assert!(tension <= 1e-4, "{at}: tensions {tension} N apart");
                apart = apart.max(thread);
            }
        }
        // The two starts do differ here (else this bounds nothing).
        assert!(apart > SETTLE_MM, "{apart} mm");
    }

    /// The stitch's span goes slack while the head stays taut: the loop
    /// is released (its reach drops by 8 mm at φ = π) while a clamp holds
    /// the head's thread, and an eyelet draws the loop back up over the
    /// rest of the turn. These steps are the ones where the branch Newton's
    /// method starts on has no solution near (docs/benchmarks.md, "Studies
    /// over the stitch"): the laws hold there (docs/thread-physics.md §1.2,
    /// §1.5), tension and slack are complementary (a span carries tension
    /// or holds slack, never both), and the eyelet draws the loop back
    /// from the stitch, not from the regulator, while the stitch is slack.
    #[test]
    fn a_released_loop_goes_slack_below_a_taut_head() {
        let tau = std::f64::consts::TAU;
        let b = build(
            360,
            3,
            |i, phi| match i {
                0 => 50.0,
                1 => 40.0 + 6.0 * phi.cos(),
                _ => 30.0 + 10.0 * (phi / tau) - 8.0 * (phi > std::f64::consts::PI) as u8 as f64,
            },
            |_, _| 0.3f64.exp(),
            |i, _| if i == 0 { 0.3 } else { 0.0 },
        );
        let c = chain(0.8);
        let t = solve(&c, &course(&b, 0, 2.0)).unwrap();
        assert!(t.settled, "settles: change {} mm", t.change_mm);
        check_laws(&b, &c, &t, 2.0);
        let mut slack_below_taut = 0;
        for k in 0..360 {
            for i in 0..3 {
                let (tension, slack) = (t.tension(k, i), t.slack_mm[k * 3 + i]);
                assert!(tension >= 0.0 && slack >= 0.0, "k = {k}, span {i}");
                assert!(
                    tension * slack == 0.0,
                    "complementary at k = {k}, span {i}: {tension} N, {slack} mm"
                );
            }
            if t.slack_mm[k * 3 + 2] > 1.0 && t.tension(k, 0) > 0.1 {
                slack_below_taut += 1;
                // While the stitch gives thread freely the regulator passes none.
                assert_eq!(t.drawn_mm[k], 0.0, "k = {k}");
            }
        }
        assert!(
            slack_below_taut > 20,
            "the stitch slack below a taut head at {slack_below_taut} positions"
        );
        // The eyelet takes the loop back: the stitch's slack falls as the
        // middle span's reach grows after the release.
        let loop_at = |k: usize| t.slack_mm[k * 3 + 2];
        assert!(
            loop_at(185) > 7.0 && loop_at(260) < loop_at(185) - 2.0,
            "{} → {} mm",
            loop_at(185),
            loop_at(260)
        );
    }

    #[test]
    fn the_spring_law_is_continuous_and_falls_with_thread() {
        let law = Law {
            ea: EA,
            spring: Some((8.0, 0.2, 0.5)),
        };
        let l = 40.0;
        let mut prev = f64::INFINITY;
        for j in 0..4000 {
            let m = 38.0 + j as f64 * 0.003;
            let (t, d) = law.tension(l, m);
            assert!(t < prev + 1e-12 && d < 0.0, "falls at m = {m}");
            if j > 0 {
                assert!(prev - t < 0.01, "continuous at m = {m}: {prev} → {t}");
            }
            let h = 1e-7;
            let fd = (law.tension(l, m + h).0 - law.tension(l, m - h).0) / (2.0 * h);
            assert!(
                (fd - d).abs() < 1e-4 * d.abs().max(1e-3),
                "slope at m = {m}: {fd} vs {d}"
            );
            if t >= 0.0 {
                assert!(
                    (law.thread_at(l, t) - m).abs() < 1e-9,
                    "thread_at inverts it at m = {m}"
                );
            }
            prev = t;
        }
    }

    #[test]
    fn a_course_that_does_not_fit_is_refused() {
        let b = takeup(10, 0.3);
        let mut c = course(&b, 0, 9.0);
        c.factor = &b.factor[1..];
        assert!(solve(&chain(0.8), &c).is_err());
        let c = course(&b, 10, 9.0);
        assert!(solve(&chain(0.8), &c).is_err());
    }

    /// A random chain of `s` spans ([`random_chains_keep_the_laws`]).
    #[allow(clippy::too_many_arguments)]
    fn check_random(
        s: usize,
        base: &[f64],
        swing: &[f64],
        lag: &[f64],
        mu_theta: &[f64],
        clamp: &[f64],
        pass: f64,
        ea: f64,
        set_k: usize,
        set_mm: f64,
    ) {
        let mut b = build(
            72,
            s,
            |i, phi| base[i] + swing[i] * (phi + lag[i]).sin(),
            |i, phi| (mu_theta[i] * (1.0 + 0.5 * (phi + lag[i]).cos())).exp(),
            |i, phi| if (phi + lag[i]).sin() > 0.5 { clamp[i] } else { 0.0 },
        );
        // The stitch's reach drops by its length where it is set.
        for k in 0..set_k {
            b.len[k * s + s - 1] += set_mm;
        }
        let c = Chain {
            ea_n: ea,
            pass_n: pass,
            spring: None,
        };
        let t = solve(&c, &course(&b, set_k, set_mm)).unwrap();
        check_laws(&b, &c, &t, set_mm);
    }

    proptest! {
        #![proptest_config(ProptestConfig { cases: 96, ..ProptestConfig::default() })]
        /// Random chains of 2–9 spans with swinging reaches, wraps and
        /// clamps: the laws hold at every position.
        #[test]
        fn random_chains_keep_the_laws(
            s in 2usize..9,
            base in proptest::collection::vec(10.0f64..120.0, 9),
            swing in proptest::collection::vec(-8.0f64..8.0, 9),
            lag in proptest::collection::vec(0.0f64..6.3, 9),
            mu_theta in proptest::collection::vec(0.0f64..1.5, 9),
            clamp in proptest::collection::vec(0.0f64..0.5, 9),
            pass in 0.2f64..2.0,
            ea in 20.0f64..2000.0,
            set_k in 0usize..72,
            set_mm in 0.5f64..12.0,
        ) {
            check_random(s, &base, &swing, &lag, &mu_theta, &clamp, pass, ea, set_k, set_mm);
        }
    }
}
