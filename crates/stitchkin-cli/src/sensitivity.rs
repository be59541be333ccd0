//! `stitchkin sensitivity`: how much each adjustable parameter moves each
//! figure of merit, ranked (stitchkin::study::sensitivity).

use std::path::PathBuf;

use clap::{Args, ValueEnum};
use stitchkin::error::Error;
use stitchkin::format::fmt_num;
use stitchkin::study::sensitivity::{Method, RankBy, SensitivityOptions, SensitivityResult, sensitivity};

#[derive(Args)]
pub struct SensitivityArgs {
    #[command(flatten)]
    model: crate::ModelArgs,
    /// Figures of merit, comma-separated patterns with `*` (names as in
    /// `stitchkin sweep --figures`; default: max P per path, match score per
    /// thread, transmission-angle extremes, measure ranges, point strokes).
    #[arg(
        long = "output",
        visible_alias = "figures",
        value_delimiter = ',',
        value_name = "FIGURE,…"
    )]
    outputs: Option<Vec<String>>,
    /// Parameters to study, comma-separated (default: every parameter with
    /// an adjustable range).
    #[arg(long, value_delimiter = ',', value_name = "NAME,…")]
    params: Option<Vec<String>>,
    /// Rank by the local effect |dF/dp| × range width (`local`; the match
    /// figures by their span) or by the span max − min of the figure over
    /// the parameter's range (`range`).
    #[arg(long, value_enum, default_value_t = Rank::Local)]
    rank: Rank,
    /// Step of the main-shaft angle φ, degrees.
    #[arg(long, default_value_t = 1.0, value_name = "DEG", allow_negative_numbers = true)]
    step: f64,
    /// Output format: a readable table, CSV (one row per figure and
    /// parameter) or JSON.
    #[arg(long, value_enum, default_value_t = Format::Table)]
    format: Format,
    /// Write to FILE instead of stdout (written completely or not at all).
    #[arg(short = 'o', value_name = "FILE")]
    file: Option<PathBuf>,
}

#[derive(Clone, Copy, ValueEnum)]
enum Rank {
    Local,
    Range,
}

#[derive(Clone, Copy, ValueEnum)]
enum Format {
    Table,
    Csv,
    Json,
}

pub fn run(args: SensitivityArgs) -> Result<(), Error> {
    let (model, params) = crate::load(&args.model)?;
    let opts = SensitivityOptions {
        params: args.params.clone().unwrap_or_default(),
        figures: args.outputs.clone().unwrap_or_default(),
        step_deg: args.step,
        rank: match args.rank {
            Rank::Local => RankBy::Local,
            Rank::Range => RankBy::Range,
        },
    };
    let r = sensitivity(&model, &params, &opts)?;
    let out = match args.format {
        Format::Json => serde_json::to_string_pretty(&r).map_err(|e| Error::Io(e.to_string()))? + "\n",
        Format::Csv => csv(&r),
        Format::Table => table(&r),
    };
    crate::emit(out.as_bytes(), args.file.as_ref())
}

/// `x` with `sig` significant digits, without an exponent for everyday
/// magnitudes.
fn sig(x: f64, sig: usize) -> String {
    if x == 0.0 || !x.is_finite() {
        return if x == 0.0 { "0".into() } else { format!("{x}") };
    }
    let mag = x.abs().log10().floor() as i32;
    if !(-4..=6).contains(&mag) {
        return format!("{x:.*e}", sig.saturating_sub(1));
    }
    let decimals = (sig as i32 - 1 - mag).max(0) as usize;
    format!("{x:.decimals$}")
}

fn signed(x: Option<f64>, unit: &str) -> String {
    x.map_or("—".into(), |x| {
        format!("{}{} {unit}", if x > 0.0 { "+" } else { "" }, sig(x, 5))
    })
}

/// The unit of a derivative: figure unit per parameter unit.
fn per(fig: &str, param: &str) -> String {
    format!("{fig}/{param}")
}

fn table(r: &SensitivityResult) -> String {
    let setting: Vec<String> = r
        .params
        .iter()
        .map(|p| format!("{} = {} {}", p.name, fmt_num(p.nominal), p.unit))
        .collect();
    let mut s = format!(
        "Sensitivity of `{}` at {} (φ step {}°)\n",
        r.model,
        setting.join(", "),
        r.step_deg
    );
    s += "d/dp: exact (dual numbers) unless marked (c), a central difference; effect = d/dp × the range width;\n";
    s += "at lo, at hi: the figure at the range's ends, the others nominal; span: its max − min over the range.\n";
    let w = r.params.iter().map(|p| p.name.len()).max().unwrap_or(4).max(9);
    let plain = |x: Option<f64>| x.map_or("—".into(), |x| sig(x, 6));
    for f in &r.figures {
        let unit = f.unit;
        let by = if f.ranked_by == "effect" {
            "ranked by |effect|"
        } else {
            "ranked by span"
        };
        s += &format!("\n{} = {} {unit}   ({by})\n", f.figure, sig(f.nominal, 6));
        s += &format!(
            "  {:>4}  {:<w$}  {:<18}  {:>22}  {:>14}  {:>12}  {:>12}  {:>12}\n",
            "rank", "parameter", "range", "d/dp", "effect", "at lo", "at hi", "span"
        );
        let mut none = Vec::new();
        for e in &f.effects {
            if e.effect == Some(0.0) && e.span == Some(0.0) && e.note.is_none() {
                none.push(e.param.as_str());
                continue;
            }
            let range = format!("{} … {} {}", fmt_num(e.lo), fmt_num(e.hi), e.param_unit);
            let d = e.derivative.map_or("—".into(), |d| {
                format!(
                    "{} {}{}",
                    sig(d, 5),
                    per(f.unit, e.param_unit),
                    if e.method == Method::Central { " (c)" } else { "" }
                )
            });
            s += &format!(
                "  {:>4}  {:<w$}  {:<18}  {:>22}  {:>14}  {:>12}  {:>12}  {:>12}\n",
                e.rank,
                e.param,
                range,
                d,
                signed(e.effect, unit),
                plain(e.at_lo),
                plain(e.at_hi),
                e.span.map_or("—".into(), |x| format!("{} {unit}", sig(x, 5)))
            );
            if let Some(n) = &e.note {
                s += &format!("        {n}\n");
            }
        }
        if !none.is_empty() {
            s += &format!("        no effect: {}\n", none.join(", "));
        }
    }
    if !r.insensitive.is_empty() {
        s += &format!("\nno parameter changes: {}\n", r.insensitive.join(", "));
    }
    s += &format!("({} cycles evaluated)\n", r.cycles);
    s
}

fn csv(r: &SensitivityResult) -> String {
    let mut s = String::from(
        "figure,figure_unit,nominal,rank,parameter,parameter_unit,range_lo,range_hi,derivative,derivative_unit,method,central_difference,effect,at_lo,at_hi,whole_range,span,note\n",
    );
    let num = |x: Option<f64>| x.map_or(String::new(), fmt_num);
    for f in &r.figures {
        for e in &f.effects {
            let method = match e.method {
                Method::Exact => "exact",
                Method::Central => "central",
            };
            s += &format!(
                "{},{},{},{},{},{},{},{},{},{},{method},{},{},{},{},{},{},\"{}\"\n",
                f.figure,
                f.unit,
                fmt_num(f.nominal),
                e.rank,
                e.param,
                e.param_unit,
                fmt_num(e.lo),
                fmt_num(e.hi),
                num(e.derivative),
                per(f.unit, e.param_unit),
                num(e.central),
                num(e.effect),
                num(e.at_lo),
                num(e.at_hi),
                num(e.whole_range),
                num(e.span),
                e.note.as_deref().unwrap_or("").replace('"', "'"),
            );
        }
    }
    s
}
