//! The mechanism drawing: the machine solved at the frames' φ (and over the
//! cycle, for trajectories and slider travel) here, drawn by
//! [`crate::output::drawing`].

use crate::error::{Error, Input};
use crate::eval::cycle_phis_deg;
use crate::geometry::V3;
use crate::mechanism::{Mechanism, Phi, Step};
use crate::model::{Model, Params};
pub use crate::output::drawing::{DrawOptions, Solved};

/// The drawing of `model` at `params` as an SVG document (still, or
/// animated over one turn): see [`DrawOptions`].
pub fn render(model: &Model, params: &Params, opts: &DrawOptions) -> Result<String, Error> {
    crate::output::drawing::render(model, solve(model, params, opts)?, opts)
}

/// Solves `model` at `params` for the frames of `opts`, and over the cycle
/// when it assembles all round (required with trajectories).
pub fn solve(model: &Model, params: &Params, opts: &DrawOptions) -> Result<Solved, Error> {
    crate::output::drawing::check_options(opts)?;
    let machine = model.machine::<f64>(params)?;
    let traced = opts
        .trajectories
        .iter()
        .map(|p| model.moving_point_slot(p).map_err(|e| e.given_in(Input::Trajectories)))
        .collect::<Result<Vec<usize>, Error>>()?;
    let nf = if opts.animate { opts.frames } else { 1 };
    let phis: Vec<f64> = (0..nf).map(|k| opts.phi_deg + 360.0 * k as f64 / nf as f64).collect();
    let slots = solve_at(model, &machine.mechanism, &phis)?;
    // The cycle: for trajectories (required) and the travel of sliders on
    // their guides (when it assembles all round).
    let cycle = match solve_at(model, &machine.mechanism, &cycle_phis_deg(model.phi_start_deg(), 1.0)) {
        Ok(c) => Some(c),
        Err(e) if !traced.is_empty() => return Err(e),
        Err(_) => None,
    };
    Ok(Solved {
        machine,
        traced,
        phis,
        slots,
        cycle,
    })
}

/// Positions of every point slot at each φ of `phis` (degrees, increasing).
/// Numerical groups follow their assembly by continuation from the model's
/// start in steps of at most 1°; closed-form groups are solved at `phis`
/// alone. No assembly at some φ is the library's usual error.
fn solve_at(model: &Model, mech: &Mechanism<f64>, phis: &[f64]) -> Result<Vec<Vec<V3<f64>>>, Error> {
    let continuation = mech.steps.iter().any(|s| matches!(s, Step::Newton(_)));
    let mut grid = Vec::new();
    let mut pick = Vec::with_capacity(phis.len());
    let fill = |grid: &mut Vec<f64>, from: f64, to: f64| {
        let k = ((to - from) / 1.0).ceil().max(1.0) as usize;
        for j in 1..k {
            grid.push(from + (to - from) * j as f64 / k as f64);
        }
    };
    for (i, &phi) in phis.iter().enumerate() {
        if continuation {
            let from = if i == 0 {
                phi - (phi - model.phi_start_deg()).rem_euclid(360.0)
            } else {
                phis[i - 1]
            };
            if i == 0 {
                grid.push(from);
            }
            fill(&mut grid, from, phi);
            if i > 0 || phi != from {
                grid.push(phi);
            }
        } else {
            grid.push(phi);
        }
        pick.push(grid.len() - 1);
    }
    let mut pose = mech.new_pose(grid.len());
    mech.solve(&Phi::table(&grid), &mut pose)?;
    Ok(pick
        .into_iter()
        .map(|k| (0..mech.n_points()).map(|s| pose.point(s, k)).collect())
        .collect())
}
