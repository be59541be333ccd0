//! The grid of a heat map: one figure of merit over two varied
//! parameters, evaluated as `stitchkin sweep` evaluates a grid.

use super::{check_vary, param_unit};
use crate::error::{Error, Input};
use crate::eval::{CycleOptions, run_cycle};
use crate::model::{Model, Params};
use crate::output::plots::{FigureGrid, param_error};
use crate::study::design::{Design, Sweep, Vary};
use crate::study::figures::{figures, select_figures, shared_stitch};
use crate::study::sweep::{self, SweepJob};

/// Evaluates the grid of the two `vary` parameters (in parallel, as
/// `stitchkin sweep`) for the one figure of merit `figure` matches: the
/// first parameter across, the second up, each ascending.
pub fn figure_grid(
    model: &Model,
    params: &Params,
    vary: &[Vary],
    figure: &str,
    step_deg: f64,
) -> Result<FigureGrid, Error> {
    let (across, up) = two_parameters(model, vary)?;
    let opts = CycleOptions::for_figures(step_deg);
    let name = one_figure(model, params, figure, &opts)?;
    let sw = Sweep::new(vec![across.clone(), up.clone()], Design::Grid)?;
    let shared = shared_stitch(model, params, &sw, step_deg)?;
    let mut rows = Vec::with_capacity(sw.len());
    let job = SweepJob {
        model,
        base: params,
        sweep: &sw,
        names: std::slice::from_ref(&name),
        opts: &opts,
        shared: shared.as_ref(),
    };
    sweep::run(
        job,
        0..sw.len(),
        |r| -> Result<(), Error> {
            rows.push(r.clone());
            Ok(())
        },
        |_| {},
    )?;
    Ok(FigureGrid {
        figure: name,
        across_unit: param_unit(model, &across.name),
        up_unit: param_unit(model, &up.name),
        across,
        up,
        rows,
        step_deg,
    })
}

/// The names of the figures of merit the model offers at `params` (what
/// `--figure` may name).
pub fn figure_names(model: &Model, params: &Params, step_deg: f64) -> Result<Vec<String>, Error> {
    Ok(
        figures(&run_cycle(model, params, &CycleOptions::for_figures(step_deg))?)
            .into_iter()
            .map(|(n, _)| n)
            .collect(),
    )
}

/// The two parameters of a heat map, each checked and ascending.
fn two_parameters(model: &Model, vary: &[Vary]) -> Result<(Vary, Vary), Error> {
    if vary.len() != 2 {
        return Err(param_error(
            Input::Vary,
            format!("a heat map needs exactly 2 varied parameters, got {}", vary.len()),
            "vary two parameters, e.g. z=-10:10:11 and dphi=-20:20:11 (the first across, the second up)".into(),
        ));
    }
    if vary[0].name == vary[1].name {
        return Err(param_error(
            Input::Vary,
            format!("`{}` is varied twice", vary[0].name),
            "vary two different parameters".into(),
        ));
    }
    let ascending = |v: &Vary| Vary {
        name: v.name.clone(),
        lo: v.lo.min(v.hi),
        hi: v.lo.max(v.hi),
        n: v.n,
    };
    let (across, up) = (ascending(&vary[0]), ascending(&vary[1]));
    check_vary(model, &across)?;
    check_vary(model, &up)?;
    Ok((across, up))
}

/// The one figure of merit `figure` matches among those of the cycle at
/// `params`.
fn one_figure(model: &Model, params: &Params, figure: &str, opts: &CycleOptions) -> Result<String, Error> {
    let nominal = run_cycle(model, params, opts)?;
    let names = select_figures(&figures(&nominal), &[figure.to_string()]).map_err(|e| match e {
        Error::Param(p) => Error::Param(p.in_input(Input::Figure)),
        e => e,
    })?;
    match names.as_slice() {
        [one] => Ok(one.clone()),
        many => Err(param_error(
            Input::Figure,
            format!(
                "`{figure}` matches {} figures of merit; a heat map shows one",
                many.len()
            ),
            format!("name one of: {}", many.join(", ")),
        )),
    }
}
