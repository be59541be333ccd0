//! The cycles of a varied parameter: one per value, run in parallel, and
//! P(φ) of one thread path with its P'(φ) kept for the family and surface
//! charts (seed 000 Fig. 7).

use rayon::prelude::*;

use super::{check_vary, param_unit, select_paths};
use crate::error::Error;
use crate::eval::{CycleOptions, CycleTable, run_cycle};
use crate::model::{Model, Params};
use crate::output::plots::{FamilyData, VaryGrid, closed, column};
use crate::study::design::Vary;

/// Runs the cycle with `opts` for each of the N values of `vary` (in
/// parallel, ascending; `vary` checked by the caller). A value whose cycle
/// fails is `None` in the runs, its reason kept in the grid; when all
/// fail, the first error is returned.
pub(super) fn run_grid(
    model: &Model,
    params: &Params,
    vary: &Vary,
    opts: &CycleOptions,
) -> Result<(VaryGrid, Vec<Option<CycleTable>>), Error> {
    let (lo, hi) = (vary.lo.min(vary.hi), vary.lo.max(vary.hi));
    let ascending = Vary {
        name: vary.name.clone(),
        lo,
        hi,
        n: vary.n,
    };
    let values: Vec<f64> = (0..vary.n).map(|k| ascending.grid_value(k)).collect();
    let runs: Vec<Result<CycleTable, Error>> = values
        .par_iter()
        .map(|&v| {
            let mut p = params.clone();
            model.set(&mut p, &vary.name, v)?;
            run_cycle(model, &p, opts)
        })
        .collect();
    if let Some(Err(e)) = runs.first()
        && runs.iter().all(Result::is_err)
    {
        return Err(e.clone());
    }
    let mut phis = Vec::new();
    let mut failures = Vec::new();
    for (run, &v) in runs.iter().zip(&values) {
        match run {
            Ok(t) if phis.is_empty() => {
                let ph = column(t, "phi_deg")?;
                phis = closed(ph, ph).iter().map(|q| q.0).collect();
            }
            Ok(_) => {}
            Err(e) => failures.push((v, e.to_string().replace('\n', " "))),
        }
    }
    let grid = VaryGrid {
        name: vary.name.clone(),
        unit: param_unit(model, &vary.name),
        values,
        phis,
        failures,
        step_deg: opts.step_deg,
    };
    Ok((grid, runs.into_iter().map(Result::ok).collect()))
}

/// Runs the cycle for each of the N values of `vary` (in parallel) and
/// keeps P of `path` (`None`: the model's first thread path) and the P' of
/// the stitch thread compared with it. A value whose cycle fails is kept
/// as a gap with its reason; when all fail, the first error is returned.
pub fn family_data(
    model: &Model,
    params: &Params,
    vary: &Vary,
    path: Option<&str>,
    step_deg: f64,
) -> Result<FamilyData, Error> {
    check_vary(model, vary)?;
    let wanted: Vec<String> = path.map(|p| vec![p.to_string()]).unwrap_or_default();
    let path = select_paths(model, &wanted)?.remove(0);
    let opts = CycleOptions {
        step_deg,
        analogs: false,
        points: Some(Vec::new()),
        lean: true,
        ..Default::default()
    };
    let (grid, runs) = run_grid(model, params, vary, &opts)?;
    let thread = runs.iter().flatten().find_map(|t| {
        t.stitch
            .as_ref()?
            .threads
            .iter()
            .find(|th| th.path.as_deref() == Some(path.as_str()))
            .map(|th| th.thread.clone())
    });
    let (mut p, mut pprime) = (Vec::new(), Vec::new());
    for run in &runs {
        match run {
            Some(t) => {
                let ph = column(t, "phi_deg")?;
                let p_column = t
                    .paths
                    .iter()
                    .find(|q| q.path == path)
                    .map_or(format!("{path}.P_mm"), |q| q.p_column.clone());
                let pts = closed(ph, column(t, &p_column)?);
                p.push(Some(pts.iter().map(|q| q.1).collect()));
                let pprime_column = t
                    .stitch
                    .as_ref()
                    .and_then(|s| s.threads.iter().find(|x| Some(&x.thread) == thread.as_ref()))
                    .map(|x| x.pprime_column());
                pprime.push(match pprime_column {
                    Some(c) => t.column(&c).map(|c| closed(ph, c).iter().map(|q| q.1).collect()),
                    None => None,
                });
            }
            None => {
                p.push(None);
                pprime.push(None);
            }
        }
    }
    Ok(FamilyData {
        grid,
        path,
        p,
        thread,
        pprime,
    })
}
