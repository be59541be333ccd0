//! `stitchkin nomogram`: the tuned setting over a grid of material thickness
//! and stitch length (stitchkin::study::nomogram).

use stitchkin::error::{Error, Input};
use stitchkin::study::nomogram::{Axis, NomogramOptions, default_thickness, nomogram};

use crate::common::{
    ModelArgs, OutputArgs, STITCH_AXIS_HELP, SearchArgs, THICKNESS_AXIS_HELP, TableFormat, json, load_without_job,
    note_line, progress_bar,
};

/// Tune at every point of a grid of material thickness (and stitch
/// length): the recommended settings, their tolerance and the match
/// before and after, as the nomogram a technician reads.
#[derive(clap::Args)]
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
    point where no setting passes the physical checks. The adjusted settings are the model's machine\n\
    settings (as `stitchkin tune`), never the thickness or stitch length the nomogram is drawn over.")]
#[command(mut_arg("thickness", |a| a.value_name("LO:HI:N").help(THICKNESS_AXIS_HELP)))]
#[command(mut_arg("stitch", |a| a.value_name("LO:HI:N").help(STITCH_AXIS_HELP)))]
pub(crate) struct Args {
    #[command(flatten)]
    model: ModelArgs,
    #[command(flatten)]
    search: SearchArgs,
    #[command(flatten)]
    output: OutputArgs,
}

pub(crate) fn run(args: Args) -> Result<(), Error> {
    args.search.check()?;
    let (mut model, params) = load_without_job(&args.model)?;
    args.search.allow(&mut model);
    // The thickness and the stitch length the nomogram is drawn over are
    // refused by the nomogram itself, in its words.
    let axes = [model.stitch_param("m"), model.stitch_param("t")];
    let named: Vec<String> = args
        .search
        .adjust
        .iter()
        .flatten()
        .filter(|n| !axes.contains(&Some(n.as_str())))
        .cloned()
        .collect();
    SearchArgs::check_kinds(&model, &named)?;
    // A bad -o is reported before the tuning, not after it.
    if let Some(path) = &args.output.output {
        stitchkin::output::check_folder(path)?;
    }
    let thickness = match &args.model.thickness {
        Some(t) => Axis::parse(t, Input::Thickness)?,
        None => default_thickness(&model)?,
    };
    let stitch = args
        .model
        .stitch
        .as_deref()
        .map(|s| Axis::parse(s, Input::StitchLength))
        .transpose()?;
    let opts = NomogramOptions {
        thickness,
        stitch,
        tune: args.search.options(args.search.adjust.clone().unwrap_or_default()),
    };
    let points = thickness.n * stitch.map_or(1, |s| s.n);
    let bar = progress_bar(points, "{bar:40} {pos}/{len} grid points tuned, ETA {eta}");
    let started = std::time::Instant::now();
    let result = nomogram(&model, &params, &opts, || bar.inc(1));
    bar.finish_and_clear();
    let n = result?;
    let out = match args.output.format() {
        TableFormat::Table => stitchkin::output::text::nomogram::table(&n),
        TableFormat::Csv => stitchkin::output::text::nomogram::csv(&n),
        TableFormat::Json => json(&n)?,
    };
    args.output.emit(&out)?;
    let failed = n.points.iter().filter(|p| p.tuned.is_none()).count();
    let cycles: usize = n.tuned().map(|(_, r)| r.evaluations).sum();
    note_line(&format!(
        "# nomogram: {} grid points tuned ({failed} failed), {cycles} cycles in {:.1} s",
        n.points.len() - failed,
        started.elapsed().as_secs_f64()
    ));
    if n.all_scores_zero() && !matches!(args.output.format(), TableFormat::Table) {
        note_line(
            "warning: every match score is 0 at every grid point: no setting in the ranges fits this stitch (the recommendations only minimise J)",
        );
    }
    Ok(())
}
