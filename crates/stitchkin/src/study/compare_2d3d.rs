//! How much a planar model of a spatial thread path errs (seed 000 §4.6,
//! eq. 13): every node is projected onto a plane (seed 000: w = 0, the UV
//! plane), pins are taken across that plane, P is recomputed, and
//! ΔP(φ) = P3D(φ) − P2D(φ) is reported.

use serde::Serialize;

use crate::error::{Error, Input, ParamError};
use crate::eval::{check_options, cycle_phis_deg, path_error, wrap_deg};
use crate::mechanism::Phi;
use crate::model::{Machine, Model, Params};

/// One path compared.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct PathComparison {
    pub path: String,
    pub p3d_mm: Vec<f64>,
    pub p2d_mm: Vec<f64>,
    /// ΔP = P3D − P2D.
    pub dp_mm: Vec<f64>,
    /// Largest |ΔP| and where.
    pub max_abs_dp_mm: f64,
    pub phi_at_max_deg: f64,
    /// Largest |ΔP| relative to the largest |P3D|, % (P at the path's
    /// split: B for a needle thread).
    pub max_rel_percent: f64,
}

/// The comparison for every path of a model.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Comparison {
    /// Frame whose xy-plane is the 2D model's plane.
    pub plane: String,
    pub phi_deg: Vec<f64>,
    pub paths: Vec<PathComparison>,
}

/// Compares the 3D paths of `model` with their projections on the xy-plane
/// of frame `plane` over a cycle of `step_deg`.
pub fn compare_2d3d(model: &Model, params: &Params, plane: &str, step_deg: f64) -> Result<Comparison, Error> {
    check_options(&crate::eval::CycleOptions {
        step_deg,
        ..Default::default()
    })?;
    let frame = model.frame_index(plane).ok_or_else(|| {
        Error::Param(ParamError::new(
            Input::Plane,
            format!("the model has no frame `{plane}`"),
            Some(format!("frames: {}", model.frame_names().join(", "))),
        ))
    })?;
    let Machine {
        mechanism: mech,
        threads,
    } = model.machine::<f64>(params)?;
    let Some(threads) = &threads else {
        return Err(Error::Param(ParamError::general(
            format!("model `{}` has no thread paths to compare", model.name()),
            Some("add a [thread] table with [[thread.paths]] (docs/model-format.md)".into()),
        )));
    };
    let phis = cycle_phis_deg(model.phi_start_deg(), step_deg);
    let mut pose = mech.new_pose(phis.len());
    mech.solve(&Phi::table(&phis), &mut pose)?;
    let mut pose0 = mech.new_pose(1);
    mech.solve(&[Phi::at_deg(threads.phi0_deg)], &mut pose0)?;
    let plane = mech.frame_plane(frame);
    let tracks = |proj| -> Result<(Vec<Vec<f64>>, Vec<f64>), Error> {
        let xi = threads.evaluate(&pose, proj).map_err(|e| {
            let phi = phis[e.k];
            path_error(e, phi)
        })?;
        let xi0 = threads
            .evaluate(&pose0, proj)
            .map_err(|e| path_error(e, threads.phi0_deg))?;
        // P at the path's split (B for a needle thread): ΔP is the same at
        // either split, its size relative to P is not.
        Ok((
            xi.into_iter()
                .map(|t| (0..t.xi.len()).map(|k| t.xi_at_split(k)).collect())
                .collect(),
            xi0.into_iter().map(|t| t.xi_at_split(0)).collect(),
        ))
    };
    let (xi3, xi3_0) = tracks(None)?;
    let (xi2, xi2_0) = tracks(Some(&plane))?;
    let mut paths = Vec::new();
    for (i, path) in threads.paths.iter().enumerate() {
        let p3d: Vec<f64> = xi3[i]
            .iter()
            .map(|x| threads.convention.take_up(*x, xi3_0[i]))
            .collect();
        let p2d: Vec<f64> = xi2[i]
            .iter()
            .map(|x| threads.convention.take_up(*x, xi2_0[i]))
            .collect();
        let dp: Vec<f64> = p3d.iter().zip(&p2d).map(|(a, b)| a - b).collect();
        let k = (0..dp.len())
            .max_by(|&i, &j| dp[i].abs().total_cmp(&dp[j].abs()))
            .unwrap_or(0);
        let p_max = p3d.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        paths.push(PathComparison {
            path: path.name.clone(),
            max_abs_dp_mm: dp[k].abs(),
            phi_at_max_deg: wrap_deg(phis[k]),
            max_rel_percent: if p_max > 0.0 { 100.0 * dp[k].abs() / p_max } else { 0.0 },
            p3d_mm: p3d,
            p2d_mm: p2d,
            dp_mm: dp,
        });
    }
    Ok(Comparison {
        plane: model.frame_names()[frame].to_string(),
        phi_deg: phis,
        paths,
    })
}
