//! `stitchkin`: the command line, a thin shell over the `stitchkin` library.

use std::io::Write;
use std::path::PathBuf;

use clap::{Args, Parser, Subcommand, ValueEnum};
use miette::{Diagnostic, LabeledSpan, NamedSource, SourceCode};
use stitchkin::error::{Error, ModelError};
use stitchkin::eval::{self, CycleOptions};
use stitchkin::model::{Model, Params};
use stitchkin::{output, presets};

mod cam;
mod draw;
mod fit;
mod image;
mod matching;
mod sensitivity;
mod straightness;
mod stroke;

mod nomogram;
mod plot;
mod report;
mod serve;

#[derive(Parser)]
#[command(
    name = "stitchkin",
    version,
    about = "Kinematics of sewing-machine mechanisms and the thread they move",
    long_about = "Kinematics of sewing-machine mechanisms and the thread they move.\n\n\
        Describe a machine in one TOML model file (docs/model-format.md) or pick a shipped preset, \
        and get every position, exact velocity/acceleration analog and transmission angle over a \
        main-shaft cycle.",
    after_help = "Examples:\n  stitchkin run                         # the default preset, CSV on stdout\n  \
        stitchkin run --preset needle876 --set alpha=30 --format json -o run.json\n  \
        stitchkin check my-machine.toml\n  stitchkin presets"
)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// List the shipped presets (name, machine, seed).
    #[command(after_help = "Example:\n  stitchkin presets")]
    Presets,
    /// Evaluate a model over one main-shaft cycle: positions, analogs,
    /// velocities, link and transmission angles, measures.
    #[command(after_help = "Examples:\n  stitchkin run\n  \
        stitchkin run --preset needle876 --set alpha=35 --step 0.5 --rpm 3000\n  \
        stitchkin run my-machine.toml --points G,E --format json -o out.json\n  \
        stitchkin run --columns '*.P_B_mm,*.G4_*_engaged'\n\n\
        Columns carry their units: phi_deg, G.y_mm, G.dy_dphi_mm_per_rad, G.d2y_dphi2_mm_per_rad2,\n\
        G.vy_mm_per_s (with --rpm), angle_A_B_deg, mu_23_deg, needle_y_mm, ...; a thread path's take-up\n\
        PATH.P_mm, or PATH.P_B_mm and PATH.P_eye_mm for a needle thread split at B (the eye's top position);\n\
        a stitch thread's THR.Pprime_B_mm (needle) or THR.Pprime_mm (looper) and THR.D_mm.\n\
        A summary (transmission angles, measure ranges, take-up, match, physical checks, notes, warnings)\n\
        goes to stderr; on a terminal without --format or -o, run shows the summary alone.")]
    Run(RunArgs),
    /// Check a model file: load, validate, solve a full cycle, and report
    /// its parameters, solve order, transmission angles and the stitch's
    /// physical checks (a failed one makes the command fail).
    #[command(
        after_help = "Examples:\n  stitchkin check my-machine.toml\n  stitchkin check --preset needle876 --set alpha=30 --cross-check"
    )]
    Check(CheckArgs),
    /// Compare each thread path with its planar model: project every node
    /// onto a plane, recompute P and report ΔP = P3D − P2D (seed 000 §4.6).
    #[command(
        name = "compare-2d3d",
        after_help = "Examples:\n  stitchkin compare-2d3d\n  stitchkin compare-2d3d --preset mf7923d --plane uvw --set z=-5 --format json -o dp.json\n\n\
        Columns: phi_deg, then per path PATH.P3D_mm, PATH.P2D_mm, PATH.dP_mm. The largest |ΔP| per path goes to stderr."
    )]
    Compare2d3d(CompareArgs),
    /// Thread consumed by one finished stitch, per thread, from the stitch's
    /// geometry (seed 004 §2.6; docs/stitch-formation.md §6).
    #[command(
        after_help = "Examples:\n  stitchkin consumption --type 504 --thickness 2.5 --stitch 2.8 --width 4 --incline 20\n  \
        stitchkin consumption --type 407 --thickness 3 --stitch 3 --format json\n\n\
        Types: 401, 406, 407 and 501–512, 514, 521. Contours whose drawings are lost in the thesis\n\
        are reported as not derivable, never guessed."
    )]
    Consumption(ConsumptionArgs),
    /// Compare the take-up P(φ) with the thread the stitch needs, P'(φ), for
    /// every thread of the model's `[stitch]`: per-stitch consumption, the
    /// mismatch D = P − P' and the match score.
    #[command(
        name = "match",
        after_help = "Examples:\n  stitchkin match\n  stitchkin match --preset mf7923d --set m=4 --set stitch=2.5\n  \
        stitchkin match --details\n  stitchkin match --measured n1=n1-measured.csv\n  \
        stitchkin match my-machine.toml --format json -o match.json\n\n\
        One screen: per thread the score, RMS(D), max P, max P', the thread per stitch and the physical checks\n\
        passed; P against P' as sparklines; the checks; the model's caveats. Needle threads are measured at B,\n\
        the eye's top position; each thread's regulator window is left out of the metrics.\n\
        D > 0 is thread given but not needed (slack), D < 0 thread needed but not given (strain).\n\
        Score s = 100·max(0, 1 − RMS(D)/range(P')): 100 is a perfect match (docs/stitch-formation.md §8).\n\
        The P' columns themselves come with `stitchkin run` (THR.Pprime_B_mm, THR.Pprime_mm, THR.D_mm, ...)."
    )]
    Match(matching::MatchArgs),
    /// Sweep adjustable parameters over a grid or random / Latin-hypercube
    /// samples, in parallel, and write figures of merit per setting (CSV,
    /// streamed).
    #[command(
        after_help = "Examples:\n  stitchkin sweep --vary z=-10:10:21 --vary dphi=-20:20:21\n  \
        stitchkin sweep --preset mf7923d --vary r1=4:6 --vary z=-10:10 --samples 1000 --method lhs --seed 7 -o lhs.csv\n  \
        stitchkin sweep --preset needle876 --vary alpha=0:35:36 --figures 'needle_y.range_mm,mu.*'\n  \
        stitchkin sweep --vary z=-10:10:101 --vary dphi=-20:20:101 --shard 2/4 -o part2.csv\n\n\
        Figures of merit (--figures, patterns with *): PATH.max_P_mm, PATH.min_P_mm (PATH.max_P_B_mm,\n\
        PATH.min_P_B_mm for a needle thread split at B), THREAD.score, THREAD.rms_D_mm, THREAD.max_abs_D_mm,\n\
        THREAD.max_Pprime_B_mm (needle) or THREAD.max_Pprime_mm (looper), THREAD.checks_ok,\n\
        THREAD.bound_margin_mm, checks.ok, score.mean, score.min, mu.min_deg,\n\
        mu.max_deg, mu.ok, mu_KEY.min_deg, MEASURE.range_mm, POINT.y_stroke_mm, ... (the first setting's\n\
        list is printed when a pattern matches nothing). By default: *.score, score.*, *.max_P_B_mm,\n\
        *.max_P_mm, checks.ok, mu.min_deg, mu.max_deg, *.range_mm, *_stroke_mm. Columns: index, the varied parameters, the\n\
        figures, status (ok, or why the setting did not evaluate; its figures are then empty).\n\
        Shards are contiguous blocks and only shard 1 writes the header: `cat part*.csv` is the sweep."
    )]
    Sweep(SweepArgs),
    /// Find the adjustable settings that make the take-up P match the
    /// stitch's required P' best, for every thread together, with every
    /// transmission angle inside 30°…150° and every physical check passing.
    #[command(
        after_help = "Examples:\n  stitchkin tune\n  stitchkin tune --thickness 4 --stitch 2.5\n  \
        stitchkin tune --preset mf7923d --adjust z,dphi --seed 3\n  \
        stitchkin tune --preset mf7923d --format json -o tuned.json\n\n\
        Default settings to adjust: every parameter with an adjustable range that leaves the stitch\n\
        alone. Constraints: the transmission angles inside 30°…150° and every physical check passing.\n\
        The search: a seeded Latin-hypercube sample (global) and Nelder-Mead (local); the same\n\
        seed gives the same answer. Prints the recommended setting, the match and the checks before and\n\
        after, how far each setting may move with the match within one score point of the optimum, and\n\
        notes: a setting on an end of its range, a match that does not improve, no setting that passes\n\
        the checks."
    )]
    Tune(TuneArgs),
    /// Tune at every point of a grid of material thickness (and stitch
    /// length): the recommended settings, their tolerance and the match
    /// before and after, as the nomogram a technician reads.
    #[command(after_help = "Examples:\n  stitchkin nomogram\n  \
        stitchkin nomogram --thickness 0.5:5:10 --adjust z\n  \
        stitchkin nomogram --thickness 1:5:5 --stitch 1:4.5:8 --adjust z,dphi --format csv -o nomogram.csv\n  \
        stitchkin nomogram --preset mf7923d --thickness 3:5:3 --adjust z --step 5 --format json\n\n\
        Without --thickness: 5 values over the range of the thickness parameter ([stitch] m_mm).\n\
        Each grid point is `stitchkin tune --thickness M --stitch T` with the same --seed, so the nomogram\n\
        is the same on every run. Table columns: m mm, t mm, each setting with its range within one score\n\
        point, the mean score before and after, each thread's score after, and the objective J after.\n\
        CSV columns: m_mm, t_mm, NAME_UNIT, NAME_lo_UNIT, NAME_hi_UNIT, score_mean_before, score_mean_after,\n\
        J_before, J_after, THREAD.score_before, THREAD.score_after, THREAD.rms_D_before_mm, ..., status.\n\
        Notes follow the table: a setting on an end of its range, a match that does not improve, a grid\n\
        point where no setting passes the physical checks.")]
    Nomogram(nomogram::NomogramArgs),
    /// Rank the adjustable parameters by their effect on each figure of
    /// merit: the exact derivative (dual numbers) times the range width, and
    /// the change over the whole range.
    #[command(after_help = "Examples:\n  stitchkin sensitivity\n  \
        stitchkin sensitivity --preset mf7923d --output 'n1_A.max_P_B_mm,mu.*' --params r1,z\n  \
        stitchkin sensitivity --preset needle876 --step 0.5 --format csv -o needle876-sensitivity.csv\n  \
        stitchkin sensitivity --output '*.score' --rank range --format json\n\n\
        Per figure (names as in `stitchkin sweep --figures`) and parameter: d/dp at the setting, exact by\n\
        dual numbers for smooth figures (take-up, measure, coordinate and transmission-angle extremes) and a\n\
        central difference (c) for the match figures; effect = d/dp × range width (figure unit); at lo, at hi\n\
        = the figure at the range's ends, the others nominal (seed 000 Fig. 7); span = its max − min over the\n\
        range (9 settings). Ranked by |effect| (by span for the match figures, or for all with --rank range).\n\
        Units: mm/mm, mm/deg, deg/mm, pts/mm (score points); CSV columns figure, figure_unit, nominal, rank,\n\
        parameter, parameter_unit, range_lo, range_hi, derivative, derivative_unit, method, ..., span, note.")]
    Sensitivity(sensitivity::SensitivityArgs),
    /// Fit model dimensions (figure-only, reconstructed ones) to stated
    /// results by weighted least squares within bounds, and report the
    /// fitted values, the residual per fact and the cost.
    #[command(
        after_help = "Examples:\n  stitchkin fit --preset needle876 --target examples/facts/needle876.toml --set y_c=170\n  \
        stitchkin fit --preset needle876 --target examples/facts/needle876.toml --set l_cf=41 --adjust l_cf=30:45\n  \
        stitchkin fit my-machine.toml --target facts.toml --adjust y_c=160:190,l_cf=30:45 --format json -o fit.json\n\n\
        facts.toml: [[fact]] figure = \"needle_y.range_mm\", value = 18, set = { alpha = 0 }, tolerance = 0.25\n\
        (or weight = W; relative_to = { alpha = 0 } fits the difference to that setting; top-level\n\
        adjust = [\"l_cf=30:45\"] names the default parameters). --adjust NAME uses the parameter's range,\n\
        NAME=LO:HI gives bounds. Levenberg-Marquardt with exact Jacobians (dual numbers) where the figure is\n\
        smooth; the start is the model with --set."
    )]
    Fit(fit::FitArgs),
    /// A point's stroke along an axis, both dead centres (refined below the
    /// φ step) and the range of every transmission angle, per setting, with
    /// where an angle leaves 30°…150° (seed 002 eq. 14, 15).
    #[command(
        after_help = "Examples:\n  stitchkin stroke --preset needle876 --point G --axis y\n  \
        stitchkin stroke --preset needle876 --point G --axis y --vary alpha=0:40:41\n  \
        stitchkin stroke --preset altin-needle --point E --axis guide.y --format json -o stroke.json\n  \
        stitchkin stroke my-machine.toml --point P --axis 0.34,0.94 --vary l_ef=20:30:11 --format csv\n\n\
        Axis: x, y, z (world), FRAME.x|y|z (from the frame's origin) or a world direction X,Y[,Z].\n\
        Dead centres: the zeros of the exact analog ds/dφ (dual numbers; Newton safeguarded by bisection).\n\
        Where an angle leaves the band between two settings, the setting is bisected to the crossing.\n\
        CSV columns: the varied parameters, P.AX_stroke_mm, P.AX_min_mm, P.AX_min_phi_deg, P.AX_max_mm,\n\
        P.AX_max_phi_deg, P.AX_min_to_max_deg, P_at_min.x_mm, ..., mu_KEY.min_deg, ..., mu_KEY.ok, status."
    )]
    Stroke(stroke::StrokeArgs),
    /// How far a point's path strays from a straight line (two model points,
    /// or the least-squares line): max and RMS deviation, minimum zone, over
    /// the cycle or the working stroke.
    #[command(
        after_help = "Examples:\n  stitchkin straightness --preset altin-needle --point E --line N1,N2\n  \
        stitchkin straightness --preset altin-needle --point E --fit --over down\n  \
        stitchkin straightness --preset altin-needle --point E --over 300:60 --step 0.25 --format csv -o dev.csv\n\n\
        Paths in the world xy-plane: the deviation is signed, + to the left of the line's direction (as\n\
        the line_deviation measure); spatial ones: the distance. --over down is the working stroke from the\n\
        far dead centre along the line to the near one. CSV: phi_deg, P.along_mm, P.dev_mm per sample."
    )]
    Straightness(straightness::StraightnessArgs),
    /// Which dimensional tolerances keep a path straight: each parameter
    /// alone at ± its tolerance, the largest tolerance each may have alone
    /// (bisection), and a seeded Monte Carlo over all at once.
    #[command(
        after_help = "Examples:\n  stitchkin tolerance --preset altin-needle --point E --limit 0.05\n  \
        stitchkin tolerance --preset altin-needle --point E --line N1,N2 --tol beta=0.1 --tol l_lm=0 --samples 200\n  \
        stitchkin tolerance --preset altin-needle --point E --length-tol 0 --tol l_ab=0.05 --tol l_be=0.05 --format json\n\n\
        Every length parameter without a --tol gets ±0.05 mm (--length-tol; seed 004); angles need an\n\
        explicit --tol NAME=±T in degrees, and T = 0 holds a parameter exact. The deviation is max |d| from\n\
        the line (--line H,T or the least-squares line, over --over). Monte Carlo: uniform in ±T, or\n\
        normal with σ = T/3 truncated at ±T; percentiles 50/90/99 %; the same --seed gives the same result."
    )]
    Tolerance(straightness::ToleranceArgs),
    /// Synthesise a thread feed cam: the polar profile ρ(θ) that makes a
    /// path's take-up P(φ) equal the stitch's required P'(φ) or a given
    /// curve (the inverse of seed 004 §2.5's cam feed, offset contact), with
    /// checks, and CSV, SVG, DXF and a [[cams]] snippet to paste.
    #[command(
        after_help = "Examples:\n  stitchkin cam --preset altin504 --path lower --target required -o lower-cam\n  \
        stitchkin cam --preset altin504 --path upper --target required --anchor-radius 21 --smooth 20 --format svg -o upper-cam.svg\n  \
        stitchkin cam my-machine.toml --path looper --target wanted.csv --points 72 --min-radius 5 --format toml\n\n\
        The profile: one radius per position φ = φ0 + k·360/N, solved from the target by seed 004 §2.5's\n\
        offset contact (a quadratic in ρ); the rest of the path from the solved mechanism. Checks (reported,\n\
        not fixed): minimum radius, convexity, profile slope and the thread's contact angle. Files: PREFIX.csv\n\
        (theta_deg,radius_mm), PREFIX.svg (to scale, mm), PREFIX.dxf (R12, mm), PREFIX.toml ([[cams]] entry).\n\
        Target CSV: columns phi_deg,P_mm. The summary goes to stderr."
    )]
    Cam(cam::CamArgs),
    /// Plot a cycle as SVG: the take-up P(φ) with the required P'(φ), the
    /// transmission angles, the trajectories of points, the motion law of
    /// any coordinate, angle or measure, and charts over varied parameters.
    #[command(after_help = "Examples:\n  stitchkin plot takeup -o mf7923d-takeup.svg\n  \
        stitchkin plot takeup --measured n1=n1-measured.csv -o measured.svg\n  \
        stitchkin plot takeup --preset altin504 --set m=2 --step 2 -o altin504.svg\n  \
        stitchkin plot mu --preset needle876 --set alpha=38 -o mu.svg\n  \
        stitchkin plot trajectory --preset needle876 --points G,E -o paths.svg\n  \
        stitchkin plot trajectory --preset altin-needle --points E --plane guide -o altin-guide.svg\n  \
        stitchkin plot motion --preset needle876 --series G.y,angle_C_B --vary alpha=0:35:6 -o motion.svg\n  \
        stitchkin plot surface --series angle_O2_B --vary r1=4:6:9 --wireframe -o psi-r1.svg\n\n\
        takeup: P of every thread path (solid) and P' of every stitch thread (dashed, its path's colour),\n\
        needle threads at B, where a one-sided guide bears on the thread shaded lightly; --measured adds a\n\
        measured curve. mu: every transmission angle, the band 30°…150° marked and the outside shaded.\n\
        trajectory: each point's path in the world xy-plane (or --plane FRAME's), equal scales, a dot at the\n\
        cycle's start. motion: each --series (a column of `stitchkin run`, the unit ending optional) against φ,\n\
        one panel per unit; with --vary one panel per series, a line per value. φ runs over one cycle from the\n\
        model's start (docs/plots.md).")]
    Plot(plot::PlotArgs),
    /// Draw the mechanism as SVG at a main-shaft angle, or animated over the cycle (docs/drawing.md).
    Draw(draw::DrawArgs),
    /// A local web page: a slider per adjustable parameter, thickness and
    /// stitch length inputs, and live P/P′, mismatch and mechanism drawing.
    #[command(
        after_help = "Examples:\n  stitchkin serve\n  stitchkin serve --preset altin504 --port 8081\n  \
        stitchkin serve my-machine.toml --set r1=5 --port 0\n\n\
        Open the address it prints in a browser; Ctrl-C stops it. It listens on 127.0.0.1 only, unless\n\
        --bind says otherwise, and answers requests for this machine's host names only (docs/web.md)."
    )]
    Serve(serve::ServeArgs),
    /// One self-contained HTML report: parameters, mechanism drawing (still
    /// and animated), P/P′ chart, mismatch, transmission angles and, when
    /// asked, the tuning result and a nomogram.
    #[command(after_help = "Examples:\n  stitchkin report -o report.html\n  \
        stitchkin report --preset altin504 --set m=2 -o altin504.html\n  \
        stitchkin report --tune --nomogram-thickness 1:5:3 -o tuned.html\n  \
        stitchkin report --measured n1=n1-measured.csv -o measured.html\n\n\
        The file holds everything (styles, every picture as inline SVG, no script) and opens in any browser (docs/report.md).")]
    Report(report::ReportArgs),
    /// Print the JSON Schema of the model file format.
    #[command(after_help = "Example:\n  stitchkin schema > stitchkin-model.schema.json")]
    Schema,
}

#[derive(Args)]
struct ModelArgs {
    /// Model file (TOML). Without it, --preset or the default preset is used.
    model: Option<PathBuf>,
    /// A shipped preset by name (see `stitchkin presets`).
    #[arg(long, conflicts_with = "model")]
    preset: Option<String>,
    /// Override a parameter: NAME=VALUE in the parameter's unit (mm or deg).
    /// Repeatable. Values outside the parameter's adjustable range are rejected.
    #[arg(long = "set", value_name = "NAME=VALUE")]
    set: Vec<String>,
}

#[derive(Args)]
struct RunArgs {
    #[command(flatten)]
    model: ModelArgs,
    /// Step of the main-shaft angle φ, degrees.
    #[arg(long, default_value_t = 1.0, value_name = "DEG", allow_negative_numbers = true)]
    step: f64,
    /// Main-shaft speed, rev/min: adds real velocities and accelerations
    /// (default: the model's `rpm`, if any).
    #[arg(long, value_name = "N", allow_negative_numbers = true)]
    rpm: Option<f64>,
    /// Points to tabulate, comma-separated (default: the model's output points).
    #[arg(long, value_delimiter = ',', value_name = "A,B,…")]
    points: Option<Vec<String>>,
    /// Columns to print, comma-separated patterns where `*` matches anything
    /// (e.g. `*.P_B_mm,mu_*`); phi_deg is always printed.
    #[arg(long, value_delimiter = ',', value_name = "PATTERN,…")]
    columns: Option<Vec<String>>,
    /// Positions only, without analogs.
    #[arg(long)]
    no_analogs: bool,
    /// Output format of the table (default CSV). On a terminal, without
    /// --format or -o, `run` shows its summary instead of the table.
    #[arg(long, value_enum)]
    format: Option<Format>,
    /// Write to FILE instead of stdout (written completely or not at all).
    #[arg(short, long, value_name = "FILE")]
    output: Option<PathBuf>,
}

#[derive(Args)]
struct CheckArgs {
    #[command(flatten)]
    model: ModelArgs,
    /// φ step of the assembly check, degrees.
    #[arg(long, default_value_t = 1.0, value_name = "DEG", allow_negative_numbers = true)]
    step: f64,
    /// Also solve the whole mechanism's closure equations with an
    /// independent Newton solver and report the largest disagreement with
    /// the closed-form groups.
    #[arg(long)]
    cross_check: bool,
}

#[derive(Args)]
struct CompareArgs {
    #[command(flatten)]
    model: ModelArgs,
    /// Frame whose xy-plane is the plane of the 2D model.
    #[arg(long, default_value = "world", value_name = "FRAME")]
    plane: String,
    /// Step of the main-shaft angle φ, degrees.
    #[arg(long, default_value_t = 1.0, value_name = "DEG", allow_negative_numbers = true)]
    step: f64,
    #[arg(long, value_enum, default_value_t = Format::Csv)]
    format: Format,
    /// Write to FILE instead of stdout (written completely or not at all).
    #[arg(short, long, value_name = "FILE")]
    output: Option<PathBuf>,
}

/// The search of `tune` and `nomogram`: what to adjust, how hard to look.
#[derive(Args)]
pub(crate) struct SearchArgs {
    /// Settings to adjust, comma-separated (default: every ranged parameter
    /// that leaves the stitch alone).
    #[arg(long, value_delimiter = ',', value_name = "NAME,…")]
    pub adjust: Option<Vec<String>>,
    /// Global samples of each tuning (default 32 per setting, at least 64).
    #[arg(long, default_value_t = 0, value_name = "N")]
    pub samples: usize,
    /// Seed of the global search (the same seed, the same answer).
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// Step of the main-shaft angle φ, degrees.
    #[arg(long, default_value_t = 1.0, value_name = "DEG", allow_negative_numbers = true)]
    pub step: f64,
}

impl SearchArgs {
    pub fn options(&self, adjust: Vec<String>) -> stitchkin::study::tune::TuneOptions {
        stitchkin::study::tune::TuneOptions {
            adjust,
            samples: self.samples,
            seed: self.seed,
            step_deg: self.step,
        }
    }
}

#[derive(Args)]
struct TuneArgs {
    #[command(flatten)]
    model: ModelArgs,
    /// Material thickness m, mm (sets the parameter [stitch] m_mm names).
    #[arg(long, value_name = "MM", allow_negative_numbers = true)]
    thickness: Option<f64>,
    /// Stitch length t, mm (sets the parameter [stitch] t_mm names).
    #[arg(long, value_name = "MM", allow_negative_numbers = true)]
    stitch: Option<f64>,
    #[command(flatten)]
    search: SearchArgs,
    #[arg(long, value_enum, default_value_t = MatchFormat::Table)]
    format: MatchFormat,
    /// Write to FILE instead of stdout (written completely or not at all).
    #[arg(short, long, value_name = "FILE")]
    output: Option<PathBuf>,
}

#[derive(Args)]
struct SweepArgs {
    #[command(flatten)]
    model: ModelArgs,
    /// A swept parameter: NAME=LO:HI:N (N values, ends included; default N
    /// 11). Repeatable: a grid over all of them, the last fastest.
    #[arg(long = "vary", value_name = "NAME=LO:HI:N", required = true)]
    vary: Vec<String>,
    /// Draw this many samples in the box instead of the grid.
    #[arg(long, value_name = "N")]
    samples: Option<usize>,
    /// How samples are drawn.
    #[arg(long, value_enum, default_value_t = Method::Lhs, requires = "samples")]
    method: Method,
    /// Seed of the samples (the same seed gives the same samples).
    #[arg(long, default_value_t = 1, requires = "samples")]
    seed: u64,
    /// Figures of merit, comma-separated patterns (default: every match
    /// score, the take-up extremes and the transmission-angle extremes).
    #[arg(long, value_delimiter = ',', value_name = "PATTERN,…")]
    figures: Option<Vec<String>>,
    /// Step of the main-shaft angle φ, degrees.
    #[arg(long, default_value_t = 1.0, value_name = "DEG", allow_negative_numbers = true)]
    step: f64,
    /// Evaluate only shard K of N (contiguous blocks, 1-based).
    #[arg(long, value_name = "K/N")]
    shard: Option<String>,
    /// Write to FILE instead of stdout (complete, or not at all).
    #[arg(short, long, value_name = "FILE")]
    output: Option<PathBuf>,
}

#[derive(Clone, Copy, ValueEnum)]
enum Method {
    Lhs,
    Random,
}

#[derive(Clone, Copy, ValueEnum)]
enum MatchFormat {
    Table,
    Json,
}

#[derive(Args)]
struct ConsumptionArgs {
    /// Stitch type (ISO 4915 number), e.g. 504.
    #[arg(long = "type", value_name = "N")]
    stitch_type: u16,
    /// Material thickness m (compressed), mm.
    #[arg(long, value_name = "MM", allow_negative_numbers = true)]
    thickness: f64,
    /// Stitch length t, mm.
    #[arg(long, value_name = "MM", allow_negative_numbers = true)]
    stitch: f64,
    /// Overedge width a (class 500), mm; required for class-500 types.
    #[arg(long, value_name = "MM", allow_negative_numbers = true)]
    width: Option<f64>,
    /// Needle inclination β from the normal to the material, degrees.
    #[arg(long, default_value_t = 0.0, value_name = "DEG", allow_negative_numbers = true)]
    incline: f64,
    /// Where the looper threads meet on the edge, as a fraction of m.
    #[arg(long, default_value_t = 0.5, value_name = "E", allow_negative_numbers = true)]
    edge: f64,
    /// Output format: a readable table, CSV or JSON.
    #[arg(long, value_enum, default_value_t = TableFormat::Table)]
    format: TableFormat,
}

#[derive(Clone, Copy, ValueEnum)]
enum TableFormat {
    Table,
    Csv,
    Json,
}

#[derive(Clone, Copy, ValueEnum)]
enum Format {
    Csv,
    Json,
}

/// A model-file error shown with its place in the file.
#[derive(Debug)]
struct FileDiagnostic {
    err: ModelError,
    src: NamedSource<String>,
}

impl std::fmt::Display for FileDiagnostic {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self.err.line_col() {
            Some((l, c)) => write!(f, "{}:{l}:{c}: ", self.err.file)?,
            None => write!(f, "{}: ", self.err.file)?,
        }
        if !self.err.path.is_empty() {
            write!(f, "{}: ", self.err.path)?;
        }
        write!(f, "{}", self.err.message)
    }
}

impl std::error::Error for FileDiagnostic {}

impl Diagnostic for FileDiagnostic {
    fn help<'a>(&'a self) -> Option<Box<dyn std::fmt::Display + 'a>> {
        self.err
            .help
            .as_ref()
            .map(|h| Box::new(h) as Box<dyn std::fmt::Display>)
    }
    fn source_code(&self) -> Option<&dyn SourceCode> {
        self.err.span.as_ref().map(|_| &self.src as &dyn SourceCode)
    }
    fn labels(&self) -> Option<Box<dyn Iterator<Item = LabeledSpan> + '_>> {
        let span = self.err.span.clone()?;
        let len = span.len().max(1);
        Some(Box::new(std::iter::once(LabeledSpan::new(
            Some("here".into()),
            span.start,
            len,
        ))))
    }
}

fn report(e: Error) -> miette::Report {
    match e {
        Error::Model(m) => {
            let src = NamedSource::new(m.file.clone(), m.text.to_string());
            miette::Report::new(FileDiagnostic { err: *m, src })
        }
        other => match other.help() {
            Some(h) => miette::miette!(help = h.to_string(), "{other}"),
            None => miette::miette!("{other}"),
        },
    }
}

fn load(args: &ModelArgs) -> Result<(Model, Params), Error> {
    let model = match (&args.model, &args.preset) {
        (Some(path), _) => Model::from_path(path)?,
        (None, Some(name)) => Model::preset(name)?,
        (None, None) => Model::preset(presets::DEFAULT)?,
    };
    let mut params = model.defaults();
    for s in &args.set {
        model.set_str(&mut params, s)?;
    }
    // Impossible geometry with the overrides is reported before evaluation.
    model.mechanism::<f64>(&params)?;
    Ok((model, params))
}

fn emit(bytes: &[u8], out: Option<&PathBuf>) -> Result<(), Error> {
    match out {
        Some(path) => output::write_atomic(path, bytes),
        None => {
            let mut stdout = std::io::stdout().lock();
            match stdout.write_all(bytes).and_then(|_| stdout.flush()) {
                Ok(()) => Ok(()),
                // A closed pipe (`| head`) is not an error.
                Err(e) if e.kind() == std::io::ErrorKind::BrokenPipe => Ok(()),
                Err(e) => Err(Error::Io(format!("cannot write to stdout: {e}"))),
            }
        }
    }
}

fn run(args: RunArgs) -> Result<(), Error> {
    let (model, params) = load(&args.model)?;
    let points = match &args.points {
        Some(names) => Some(
            names
                .iter()
                .map(|n| {
                    model.point_names.iter().position(|p| p == n).ok_or_else(|| {
                        Error::Param(stitchkin::error::ParamError {
                            message: format!("the model has no point `{n}` (in --points)"),
                            help: Some(format!("its points are: {}", model.point_names.join(", "))),
                        })
                    })
                })
                .collect::<Result<Vec<_>, _>>()?,
        ),
        None => None,
    };
    let opts = CycleOptions {
        step_deg: args.step,
        rpm: args.rpm.or(model.rpm()),
        analogs: !args.no_analogs,
        points,
        lean: false,
    };
    let mut table = eval::run_cycle(&model, &params, &opts)?;
    if let Some(patterns) = &args.columns {
        table.select(patterns)?;
    }
    // A person at a terminal gets the summary: 360 rows of a few hundred
    // columns read nowhere but in a file or a pipe.
    if args.format.is_none() && args.output.is_none() && std::io::IsTerminal::is_terminal(&std::io::stdout()) {
        let mut s = summary(&model, &table);
        s += &format!(
            "(the full table, {} rows × {} columns: `stitchkin run --format csv`, `-o FILE.csv`, or pipe it; how P matches P′: `stitchkin match`)\n",
            table.rows(),
            table.columns.len()
        );
        return emit(s.as_bytes(), None);
    }
    let format = args.format.unwrap_or(Format::Csv);
    let mut buf = Vec::new();
    match format {
        Format::Csv => output::write_csv(&table, &mut buf),
        Format::Json => output::write_json(&model, &params, &table, &mut buf),
    }
    .map_err(|e| Error::Io(e.to_string()))?;
    emit(&buf, args.output.as_ref())?;
    if matches!(format, Format::Csv) || args.output.is_some() {
        eprint!("{}", summary(&model, &table));
    }
    Ok(())
}

fn summary(model: &Model, table: &eval::CycleTable) -> String {
    let mut s = String::new();
    let m = &model.file.model;
    s += &format!(
        "# {} — {} rows, φ from {}° in steps of {}°{}\n",
        m.title.as_deref().unwrap_or(&m.name),
        table.rows(),
        model.phi_start_deg(),
        table.step_deg,
        table.rpm.map(|r| format!(", {r} rpm")).unwrap_or_default()
    );
    let w = table
        .transmission
        .iter()
        .map(|t| t.key.len() + 3)
        .chain(table.ranges.iter().map(|r| r.name.len()))
        .chain(table.paths.iter().map(|p| p.path.len()))
        .max()
        .unwrap_or(8);
    for t in &table.transmission {
        s += &format!(
            "# {:<w$} {:>7.2}° (φ = {:>6.1}°) … {:>7.2}° (φ = {:>6.1}°)  {}  [{}]\n",
            format!("mu_{}", t.key),
            t.min_deg,
            t.phi_at_min_deg,
            t.max_deg,
            t.phi_at_max_deg,
            if t.ok { "ok" } else { "OUTSIDE 30°…150°" },
            t.group
        );
    }
    for r in &table.ranges {
        s += &format!(
            "# {:<w$} {:.4} … {:.4} {} (range {:.4} {}; min at φ = {:.1}°, max at φ = {:.1}°)\n",
            r.name, r.min, r.max, r.unit, r.range, r.unit, r.phi_at_min_deg, r.phi_at_max_deg
        );
    }
    if let Some(conv) = &table.take_up {
        s += &format!("# take-up: {conv}\n");
    }
    for p in &table.paths {
        let pn = eval::take_up_name(p.split == stitchkin::thread::SplitPoint::B);
        s += &format!(
            "# {:<w$} max {pn} {:.3} mm at φ = {:.1}°, min {pn} {:.3} mm at φ = {:.1}°",
            p.path, p.max_p_mm, p.phi_at_max_deg, p.min_p_mm, p.phi_at_min_deg
        );
        if let Some(e) = p.max_p_eye_mm {
            s += &format!(" (max P_eye {e:.3} mm)");
        }
        for (pin, iv) in &p.engaged {
            s += &format!("; {pin} engaged {}", intervals(iv, "never"));
        }
        if !p.flat.is_empty() {
            s += &format!("; dwell {}", intervals(&p.flat, ""));
        }
        if let Some([lo, hi]) = p.eye_tension_n {
            s += &format!("; eye tension {lo:.3}…{hi:.3} N");
        }
        if let Some(t) = &p.thread {
            s += &format!("  [{t}]");
        }
        s += "\n";
    }
    if let Some(st) = &table.stitch {
        s += &format!(
            "# stitch {}: m = {} mm, t = {} mm; P' = 0 at φ = {}°, needle BDC at φ = {}°\n",
            st.stitch_type, st.m_mm, st.t_mm, st.phi0_deg, st.cyclogram_zero_deg
        );
        s += &format!("# regulator: {}\n", st.regulator);
        for t in &st.threads {
            let pn = if t.split == stitchkin::thread::SplitPoint::B {
                "P'_B"
            } else {
                "P'"
            };
            s += &format!(
                "# {:<w$} max {pn} {:.3} mm at φ = {:.1}°; {:.3} mm per stitch (cut at its lock, φ = {:.1}°: {:.3} mm)",
                t.thread, t.max_pprime_mm, t.phi_at_max_pprime_deg, t.per_stitch_mm, t.lock_phi_deg, t.locked_mm
            );
            if let (Some(p), Some(m)) = (&t.path, &t.mismatch) {
                s += &format!("; vs {p}: RMS(P − P') {:.3} mm, score {}", m.rms_d_mm, score(m.score));
            }
            s += "\n";
        }
        for c in &st.checks {
            s += &format!(
                "# check {:<4} {} {}: {}\n",
                if c.ok { "ok" } else { "FAIL" },
                c.thread,
                c.name,
                c.message
            );
        }
        for t in &st.transfers {
            s += &format!("# note: {t}\n");
        }
    }
    for c in model.caveats() {
        s += &format!("# note: {c}\n");
    }
    for w in &table.warnings {
        s += &format!("warning: {w}\n");
    }
    s
}

fn score(s: Option<f64>) -> String {
    s.map_or("—".into(), |x| format!("{x:.1}"))
}

fn tune_cmd(args: TuneArgs) -> Result<(), Error> {
    use stitchkin::study::tune::{set_stitch_value, tune};
    let (model, mut params) = load(&args.model)?;
    if let Some(m) = args.thickness {
        set_stitch_value(&model, &mut params, "m", m)?;
    }
    if let Some(t) = args.stitch {
        set_stitch_value(&model, &mut params, "t", t)?;
    }
    let adjust = match &args.search.adjust {
        Some(a) => a.clone(),
        None => model.default_adjustables(&params)?,
    };
    let r = tune(&model, &params, &args.search.options(adjust))?;
    let out = match args.format {
        MatchFormat::Json => serde_json::to_string_pretty(&r).map_err(|e| Error::Io(e.to_string()))? + "\n",
        MatchFormat::Table => {
            let fmt = |x: f64| {
                let r = (x * 100.0).round() / 100.0;
                if r == 0.0 { "0".to_string() } else { format!("{r}") }
            };
            let setting = |xs: &[f64]| -> String {
                r.names
                    .iter()
                    .zip(xs)
                    .map(|((n, u), x)| format!("{n} = {} {u}", fmt(*x)))
                    .collect::<Vec<_>>()
                    .join(", ")
            };
            let mut s = format!("Recommended setting: {}\n", setting(&r.after));
            s += &format!("(from {})\n\n", setting(&r.before));
            s += &format!(
                "{:<12} {:>14} {:>14} {:>16} {:>16}\n",
                "thread", "score before", "score after", "RMS(D) before", "RMS(D) after"
            );
            for (b, a) in r.before_figures.threads.iter().zip(&r.after_figures.threads) {
                s += &format!(
                    "{:<12} {:>14} {:>14} {:>13.3} mm {:>13.3} mm\n",
                    b.0,
                    score(b.1),
                    score(a.1),
                    b.2,
                    a.2
                );
            }
            s += &format!(
                "{:<12} {:>14.1} {:>14.1}\n",
                "mean", r.before_figures.score_mean, r.after_figures.score_mean
            );
            let mu = |f: &stitchkin::study::tune::MatchFigures| match (f.mu_min_deg, f.mu_max_deg) {
                (Some(a), Some(b)) => format!("{a:.1}°…{b:.1}°{}", if f.mu_ok { "" } else { " (OUTSIDE 30°…150°)" }),
                _ => "none".into(),
            };
            s += &format!(
                "\ntransmission angles: before {}, after {}\n",
                mu(&r.before_figures),
                mu(&r.after_figures)
            );
            let checks = |f: &stitchkin::study::tune::MatchFigures| {
                if f.failed_checks.is_empty() {
                    "all pass".to_string()
                } else {
                    format!("{} FAIL", f.failed_checks.join(", "))
                }
            };
            s += &format!(
                "physical checks: before {}, after {}\n",
                checks(&r.before_figures),
                checks(&r.after_figures)
            );
            s += "within one score point of the optimum (each setting alone, the others held):\n";
            for f in &r.flatness {
                let unit = r.names.iter().find(|n| n.0 == f.name).map_or("", |n| n.1);
                s += &format!("  {} from {} to {} {unit}\n", f.name, fmt(f.lo), fmt(f.hi));
            }
            for n in &r.notes {
                s += &format!("note: {n}\n");
            }
            s += &format!("({} cycles evaluated)\n", r.evaluations);
            s
        }
    };
    emit(out.as_bytes(), args.output.as_ref())
}

fn sweep_cmd(args: SweepArgs) -> Result<(), Error> {
    use stitchkin::study::design::{Design, Sweep, Vary};
    use stitchkin::study::{figures, sweep};
    let (model, params) = load(&args.model)?;
    let vary = args
        .vary
        .iter()
        .map(|v| Vary::parse(&model, v))
        .collect::<Result<Vec<_>, _>>()?;
    let design = match (args.samples, args.method) {
        (None, _) => Design::Grid,
        (Some(samples), Method::Lhs) => Design::Lhs {
            samples,
            seed: args.seed,
        },
        (Some(samples), Method::Random) => Design::Random {
            samples,
            seed: args.seed,
        },
    };
    let sw = Sweep::new(vary, design)?;
    let opts = CycleOptions {
        step_deg: args.step,
        rpm: None,
        analogs: false,
        points: None,
        lean: true,
    };
    // The nominal setting says which figures this model has.
    let nominal = eval::run_cycle(&model, &params, &opts)?;
    let available = figures::figures(&nominal);
    let patterns = args
        .figures
        .clone()
        .unwrap_or_else(|| figures::default_figures(&available));
    let names = figures::select_figures(&available, &patterns)?;
    let (k, n) = match &args.shard {
        None => (1, 1),
        Some(s) => {
            let parsed = s
                .split_once('/')
                .and_then(|(k, n)| Some((k.trim().parse::<usize>().ok()?, n.trim().parse::<usize>().ok()?)));
            match parsed {
                Some((k, n)) if n >= 1 && (1..=n).contains(&k) => (k, n),
                _ => {
                    return Err(Error::Param(stitchkin::error::ParamError {
                        message: format!("`{s}` is not a shard K/N with 1 ≤ K ≤ N"),
                        help: Some("e.g. --shard 2/4 evaluates the second quarter".into()),
                    }));
                }
            }
        }
    };
    let range = sw.shard(k, n);
    let total = range.len();
    let shared = figures::shared_stitch(&model, &params, &sw, args.step)?;
    let bar = if std::io::IsTerminal::is_terminal(&std::io::stderr()) {
        let b = indicatif::ProgressBar::new(total as u64);
        b.set_style(
            indicatif::ProgressStyle::with_template("{bar:40} {pos}/{len} settings, {per_sec}, ETA {eta}")
                .unwrap_or_else(|_| indicatif::ProgressStyle::default_bar()),
        );
        b
    } else {
        indicatif::ProgressBar::hidden()
    };
    // Stream to a temporary file next to the output (renamed at the end), or
    // to stdout.
    let mut sink = output::Sink::new(args.output.as_deref())?;
    let mut header = String::new();
    if k == 1 {
        header += "index";
        for v in &sw.vary {
            header += &format!(
                ",{}_{}",
                v.name,
                model.params[model.param_index(&v.name).unwrap_or(0)].unit_str()
            );
        }
        for f in &names {
            header += &format!(",{f}");
        }
        header += ",status\n";
    }
    sink.write(header.as_bytes())?;
    // The extremes of one figure, for the summary: the mean match score
    // when there is one, else the first figure.
    let key = names.iter().position(|n| n == "score.mean").unwrap_or(0);
    let mut lowest: Option<(f64, Vec<f64>)> = None;
    let mut highest: Option<(f64, Vec<f64>)> = None;
    let (mut ok, mut failed) = (0usize, 0usize);
    let mut line = String::new();
    sweep::run(
        &model,
        &params,
        &sw,
        &names,
        &opts,
        shared.as_ref(),
        range,
        |row| {
            line.clear();
            line += &row.index.to_string();
            for v in &row.values {
                line.push(',');
                line += &stitchkin::format::fmt_num(*v);
            }
            for f in &row.figures {
                line.push(',');
                if let Some(x) = f {
                    line += &stitchkin::format::fmt_num(*x);
                }
            }
            match &row.error {
                None => {
                    line += ",ok\n";
                    ok += 1;
                    if let Some(Some(x)) = row.figures.get(key) {
                        if lowest.as_ref().is_none_or(|(b, _)| x < b) {
                            lowest = Some((*x, row.values.clone()));
                        }
                        if highest.as_ref().is_none_or(|(b, _)| x > b) {
                            highest = Some((*x, row.values.clone()));
                        }
                    }
                }
                Some(e) => {
                    line += &format!(",\"{}\"\n", e.replace('"', "'"));
                    failed += 1;
                }
            }
            sink.write(line.as_bytes())
        },
        |d| bar.inc(d as u64),
    )?;
    bar.finish_and_clear();
    sink.finish()?;
    let mut s = format!("# sweep: {total} settings ({ok} evaluated, {failed} without assembly or with errors)");
    if n > 1 {
        s += &format!(", shard {k}/{n} of {}", sw.len());
    }
    s += "\n";
    for (word, ext) in [("largest", &highest), ("smallest", &lowest)] {
        if let (Some((x, values)), Some(f)) = (ext, names.get(key)) {
            let setting: Vec<String> = sw
                .vary
                .iter()
                .zip(values)
                .map(|(v, x)| format!("{} = {}", v.name, stitchkin::format::fmt_num(*x)))
                .collect();
            s += &format!(
                "# {word} {f} = {} at {}\n",
                stitchkin::format::fmt_num(*x),
                setting.join(", ")
            );
        }
    }
    eprint!("{s}");
    Ok(())
}

/// φ intervals for a summary line, each end within 0…360°.
fn intervals(iv: &[stitchkin::thread::Interval], none: &str) -> String {
    if iv.is_empty() {
        return none.to_string();
    }
    iv.iter()
        .map(|i| {
            if i.to_deg - i.from_deg >= 360.0 - 1e-9 {
                "the whole cycle".to_string()
            } else {
                format!("{:.0}°…{:.0}°", eval::wrap_deg(i.from_deg), eval::wrap_deg(i.to_deg))
            }
        })
        .collect::<Vec<_>>()
        .join(", ")
}

fn check(args: CheckArgs) -> Result<(), Error> {
    let (model, params) = load(&args.model)?;
    let table = eval::run_cycle(
        &model,
        &params,
        &CycleOptions {
            step_deg: args.step,
            ..Default::default()
        },
    )?;
    let m = &model.file.model;
    let mut out = String::new();
    out += &format!("{}: ok — {}\n", model.file_name, m.title.as_deref().unwrap_or(&m.name));
    out += &format!("parameters ({}):\n", model.params.len());
    for (p, v) in model.params.iter().zip(&params.values) {
        let value = if p.is_derived() {
            "derived".to_string()
        } else {
            format!("{v} {}", p.unit_str())
        };
        let range = p
            .range
            .map(|[a, b]| format!("  range {a}…{b} {}", p.unit_str()))
            .unwrap_or_default();
        let prov = p
            .provenance
            .map(|p| format!("  [{p:?}]").to_lowercase())
            .unwrap_or_default();
        out += &format!("  {:<10} {value}{range}{prov}\n", p.name);
    }
    out += &format!("solve order ({} steps):\n", model.step_labels().len());
    for (k, l) in model.step_labels().iter().enumerate() {
        out += &format!("  {:>2}. {l}\n", k + 1);
    }
    if let Some(threads) = &model.mechanism::<f64>(&params)?.threads {
        out += &format!(
            "thread paths ({}), {} distinct pieces:\n",
            threads.paths.len(),
            threads.spans.len()
        );
        for p in threads.paths.iter() {
            let nodes: Vec<String> = p
                .node_names
                .iter()
                .zip(&p.pin_span)
                .map(|(n, guide)| if guide.is_some() { format!("[{n}]") } else { n.clone() })
                .collect();
            let constant = p
                .spans
                .iter()
                .filter(|&&s| {
                    matches!(
                        threads.spans[s],
                        stitchkin::thread::Span::Straight { constant: true, .. }
                    )
                })
                .count();
            out += &format!(
                "  {:<10} {}  ({} pieces, {constant} of constant length)\n",
                p.name,
                nodes.join(" "),
                p.spans.len()
            );
        }
    }
    out += &format!(
        "assembles at every φ from {}° in steps of {}°\n",
        model.phi_start_deg(),
        args.step
    );
    out += &summary(&model, &table);
    if args.cross_check {
        let c = stitchkin::verify::cross_check(&model, &params, args.step)?;
        out += &format!(
            "cross-check: {} positions, closed-form groups and whole-system Newton agree to {:.2e} mm (largest at {} φ = {:.1}°)\n",
            c.positions,
            c.max_deviation_mm,
            c.at_point,
            eval::wrap_deg(c.at_phi_deg)
        );
    }
    emit(out.as_bytes(), None)?;
    // A setting no machine can realise does not pass the check.
    let failed: Vec<String> = table
        .stitch
        .iter()
        .flat_map(|s| s.checks.iter().filter(|c| !c.ok))
        .map(|c| format!("{} {}", c.thread, c.name))
        .collect();
    if failed.is_empty() {
        Ok(())
    } else {
        Err(Error::Physical(format!(
            "{} physical check(s) fail ({}): the model loads and assembles, but this setting cannot work on a real machine; \
             the `# check FAIL` lines above say why and what to change",
            failed.len(),
            failed.join(", ")
        )))
    }
}

fn compare(args: CompareArgs) -> Result<(), Error> {
    let (model, params) = load(&args.model)?;
    let c = stitchkin::study::compare2d3d::compare_2d3d(&model, &params, &args.plane, args.step)?;
    let bytes = match args.format {
        Format::Json => serde_json::to_vec_pretty(&c).map_err(|e| Error::Io(e.to_string()))?,
        Format::Csv => {
            let mut table = stitchkin::eval::CycleTable {
                step_deg: args.step,
                rpm: None,
                columns: vec![stitchkin::eval::Column {
                    name: "phi_deg".into(),
                    values: c.phi_deg.clone(),
                }],
                transmission: Vec::new(),
                ranges: Vec::new(),
                paths: Vec::new(),
                take_up: None,
                stitch: None,
                warnings: Vec::new(),
            };
            for p in &c.paths {
                for (suffix, v) in [("P3D_mm", &p.p3d_mm), ("P2D_mm", &p.p2d_mm), ("dP_mm", &p.dp_mm)] {
                    table.columns.push(stitchkin::eval::Column {
                        name: format!("{}.{suffix}", p.path),
                        values: v.clone(),
                    });
                }
            }
            let mut buf = Vec::new();
            output::write_csv(&table, &mut buf).map_err(|e| Error::Io(e.to_string()))?;
            buf
        }
    };
    emit(&bytes, args.output.as_ref())?;
    let w = c.paths.iter().map(|p| p.path.len()).max().unwrap_or(4);
    let mut s = format!(
        "# 2D model: every node projected onto the xy-plane of `{}`; ΔP = P3D − P2D\n",
        c.plane
    );
    for p in &c.paths {
        s += &format!(
            "# {:<w$} max |ΔP| {:.4} mm at φ = {:.1}° ({:.2} % of max P)\n",
            p.path, p.max_abs_dp_mm, p.phi_at_max_deg, p.max_rel_percent
        );
    }
    eprint!("{s}");
    Ok(())
}

fn consumption(args: ConsumptionArgs) -> Result<(), Error> {
    use stitchkin::stitch::consumption::{StitchGeometry, consumption};
    let width = match (args.width, args.stitch_type) {
        (Some(w), _) => w,
        (None, 500..=599) => {
            return Err(Error::Param(stitchkin::error::ParamError {
                message: format!("stitch type {} needs the overedge width", args.stitch_type),
                help: Some("give --width in mm, e.g. --width 4".into()),
            }));
        }
        (None, _) => 0.0,
    };
    let g = StitchGeometry {
        thickness_mm: args.thickness,
        stitch_mm: args.stitch,
        width_mm: width,
        incline_deg: args.incline,
        edge_fraction: args.edge,
    };
    let c = consumption(args.stitch_type, &g)?;
    let len = |v: Option<f64>| v.map_or("—".to_string(), |x| format!("{x:.4}"));
    let out = match args.format {
        TableFormat::Json => serde_json::to_string_pretty(&c).map_err(|e| Error::Io(e.to_string()))? + "\n",
        TableFormat::Csv => {
            let mut s = String::from("thread,contour,formula,length_mm\n");
            for t in &c.threads {
                let contour = t.contour.map_or(String::new(), |n| n.to_string());
                let value = t.length_mm.map_or(String::new(), stitchkin::format::fmt_num);
                s += &format!("{},{contour},\"{}\",{value}\n", t.thread, t.formula);
            }
            s
        }
        TableFormat::Table => {
            let mut s = format!(
                "stitch {}: m = {} mm, t = {} mm, a = {} mm, β = {}°, e = {}\n",
                c.stitch_type, g.thickness_mm, g.stitch_mm, g.width_mm, g.incline_deg, g.edge_fraction
            );
            s += &format!(
                "l_m = m/cos β = {:.4} mm, l = √(a² + t²) = {:.4} mm\n\n",
                c.l_m_mm, c.l_mm
            );
            s += &format!("{:<14} {:>7}  {:>12}  formula\n", "thread", "contour", "mm/stitch");
            for t in &c.threads {
                let contour = t.contour.map_or("—".to_string(), |n| n.to_string());
                s += &format!(
                    "{:<14} {:>7}  {:>12}  {}\n",
                    t.thread,
                    contour,
                    len(t.length_mm),
                    t.formula
                );
            }
            s += &format!("{:<14} {:>7}  {:>12}\n", "total", "", len(c.total_mm));
            if c.total_mm.is_none() {
                s += "(no total: a thread's contour is not derivable from the seeds)\n";
            }
            s
        }
    };
    emit(out.as_bytes(), None)
}

fn main() -> miette::Result<()> {
    // Into a pipe or a log, a diagnostic keeps each message on one line:
    // wrapping at an assumed 80 columns splits messages at places that
    // depend on the file's path, which makes logs hard to search.
    if !std::io::IsTerminal::is_terminal(&std::io::stderr()) {
        let _ = miette::set_hook(Box::new(|_| {
            Box::new(miette::MietteHandlerOpts::new().width(100_000).build())
        }));
    }
    let cli = Cli::parse();
    let result = match cli.command {
        Command::Presets => {
            let mut out = String::from("name          seed  machine\n");
            for p in presets::ALL {
                let (title, seed) = match Model::preset(p.name) {
                    Ok(m) => (
                        m.file.model.title.clone().unwrap_or_default(),
                        m.file.model.seed.clone().unwrap_or_default(),
                    ),
                    Err(e) => (format!("(does not load: {e})"), String::new()),
                };
                let default = if p.name == presets::DEFAULT { "  (default)" } else { "" };
                out += &format!("{:<13} {:<5} {title}{default}\n", p.name, seed);
            }
            emit(out.as_bytes(), None)
        }
        Command::Run(args) => run(args),
        Command::Check(args) => check(args),
        Command::Compare2d3d(args) => compare(args),
        Command::Consumption(args) => consumption(args),
        Command::Match(args) => matching::run(args),
        Command::Sweep(args) => sweep_cmd(args),
        Command::Tune(args) => tune_cmd(args),
        Command::Nomogram(args) => nomogram::run(args),
        Command::Sensitivity(args) => sensitivity::run(args),
        Command::Fit(args) => fit::run(args),
        Command::Stroke(args) => stroke::run(args),
        Command::Straightness(args) => straightness::run(args),
        Command::Tolerance(args) => straightness::tolerance(args),
        Command::Cam(args) => cam::run(args),
        Command::Plot(args) => plot::run(args),
        Command::Draw(args) => draw::run(args),
        Command::Serve(args) => serve::run(args),
        Command::Report(args) => report::run(args),
        Command::Schema => emit(stitchkin::model::schema_json().as_bytes(), None),
    };
    result.map_err(report)
}
