//! The stitch process over a cycle: P'(φ) of every thread next to the
//! take-up P(φ) of the path it is compared with, and their mismatch
//! (`docs/stitch-formation.md` §5, §8).

use serde::Serialize;

use super::{Column, wrap_deg};
use crate::error::Error;
use crate::model::stitch::StitchSetup;
use crate::model::{Model, Params};
use crate::stitch::mismatch::{Mismatch, mismatch};
use crate::stitch::pprime::required_take_up;
use crate::stitch::spec::{EventKind, ThreadRole};

/// A moment of a thread's cyclogram, at the model's φ.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct StitchEvent {
    pub name: String,
    pub phi_deg: f64,
    pub kind: EventKind,
    /// η after minus η before, mm.
    pub jump_mm: f64,
}

/// One thread of the stitch: what it needs, and how the take-up gives it.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct StitchThreadSummary {
    pub thread: String,
    pub role: ThreadRole,
    /// The thread path P is taken from.
    pub path: Option<String>,
    /// Contour of seed 004 §2.6.
    pub contour: u8,
    /// Thread per stitch by the contour formula, and as cut from the P'
    /// model at its lock (the two agree), mm.
    pub per_stitch_mm: f64,
    pub locked_mm: f64,
    /// The lock, model φ.
    pub lock_phi_deg: f64,
    pub max_pprime_mm: f64,
    pub phi_at_max_pprime_deg: f64,
    /// Needle threads: the largest P' split at B (the eye at TDC), as the
    /// seeds plot it, mm.
    pub max_pprime_b_mm: Option<f64>,
    pub events: Vec<StitchEvent>,
    /// P − P' metrics (with a path).
    pub mismatch: Option<Mismatch>,
}

/// The stitch process of a cycle.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct StitchSummary {
    pub stitch_type: u16,
    pub m_mm: f64,
    pub t_mm: f64,
    /// The model's φ of the needle's BDC (φ_c = 0).
    pub cyclogram_zero_deg: f64,
    /// P' = 0 here, model φ.
    pub phi0_deg: f64,
    pub threads: Vec<StitchThreadSummary>,
    /// Derived moments, model φ.
    pub moments: Vec<(String, f64)>,
    pub warnings: Vec<String>,
}

/// Is model-φ `phi` inside the window [from, to] (which may wrap past 360°)?
pub(crate) fn in_window(phi: f64, w: [f64; 2]) -> bool {
    let (a, len) = (w[0].rem_euclid(360.0), (w[1] - w[0]).rem_euclid(360.0));
    (phi - a).rem_euclid(360.0) <= len
}

/// The stitch process of a model resolved for one φ grid: its setup and P'
/// of every thread. Depends on the parameters only through the stitch's
/// inputs (m, t, the organs' motions), so a study can compute it once for
/// many settings that leave those alone.
#[derive(Debug, Clone)]
pub struct Prepared {
    pub setup: StitchSetup,
    pub required: crate::stitch::spec::RequiredTakeUp,
    /// The model φ grid it was computed on, and φ0 (where P' = 0).
    pub phis: Vec<f64>,
    pub phi0_deg: f64,
}

/// P' of the model's stitch process with `params` on the cycle grid of
/// `step_deg`; `None` when the model has no `[stitch]`.
pub fn prepare(model: &Model, params: &Params, step_deg: f64) -> Result<Option<Prepared>, Error> {
    super::check_options(&super::CycleOptions { step_deg, ..Default::default() })?;
    let Some(setup) = model.stitch_setup(params)? else { return Ok(None) };
    let phis = super::cycle_phis_deg(model.phi_start_deg(), step_deg);
    let phi0_deg = model.file.thread.as_ref().and_then(|t| t.phi0_deg).unwrap_or(model.phi_start_deg());
    let to_c = |phi: f64| (phi - setup.cyclogram_zero_deg).rem_euclid(360.0);
    // φ0 rides at the end of the grid, for S(φ0) of P'_B.
    let mut grid: Vec<f64> = phis.iter().map(|&p| to_c(p)).collect();
    grid.push(to_c(phi0_deg));
    let required = required_take_up(&setup.spec, &grid, to_c(phi0_deg))?;
    Ok(Some(Prepared { setup, required, phis, phi0_deg }))
}

/// Adds the stitch columns (`THR.eta_mm`, `THR.Pprime_mm`, needle threads'
/// `THR.Pprime_B_mm` and `THR.gamma_deg`, and `THR.D_mm` = P − P' where the
/// thread has a path) and returns the summary. `phis` are the cycle's model
/// φ (uniform), the grid `prepared` was computed on.
pub(crate) fn stitch_columns(prepared: &Prepared, phis: &[f64], lean: bool, columns: &mut Vec<Column>) -> Result<StitchSummary, Error> {
    if prepared.phis.len() != phis.len() || prepared.phis.first() != phis.first() {
        return Err(Error::Stitch("the stitch process was prepared for another φ grid; prepare it with the same step".into()));
    }
    let (setup, req, phi0_deg) = (&prepared.setup, &prepared.required, prepared.phi0_deg);
    let from_c = |phi_c: f64| wrap_deg(phi_c + setup.cyclogram_zero_deg);
    let n = phis.len();
    let compared: Vec<bool> = phis.iter().map(|&p| !setup.regulator_window_deg.iter().any(|w| in_window(wrap_deg(p), *w))).collect();
    let mut threads = Vec::new();
    for (th, path) in req.threads.iter().zip(&setup.paths) {
        let name = &th.name;
        let pprime = &th.pprime_mm[..n];
        let push = |columns: &mut Vec<Column>, col: &str, values: Vec<f64>| {
            columns.push(Column { name: format!("{name}.{col}"), values });
        };
        push(columns, "eta_mm", th.eta_mm[..n].to_vec());
        push(columns, "Pprime_mm", pprime.to_vec());
        let mut max_pprime_b_mm = None;
        if let Some(s) = &th.travel_mm {
            let s0 = s[n];
            let pb: Vec<f64> = (0..n).map(|k| pprime[k] + s[k] - s0).collect();
            max_pprime_b_mm = pb.iter().cloned().reduce(f64::max);
            push(columns, "Pprime_B_mm", pb);
        }
        if let Some(g) = &th.gamma_deg {
            push(columns, "gamma_deg", g[..n].to_vec());
        }
        let mut m = None;
        if let Some(path) = path {
            let p_name = format!("{path}.P_mm");
            let p = columns
                .iter()
                .find(|c| c.name == p_name)
                .map(|c| c.values.clone())
                .ok_or_else(|| Error::Stitch(format!("thread `{name}`: the take-up column `{p_name}` of its path is missing")))?;
            let d: Vec<f64> = (0..n).map(|k| p[k] - pprime[k]).collect();
            push(columns, "D_mm", d);
            m = mismatch(phis, &p, pprime, &compared, setup.tolerance_mm, !lean).map(|mut m| {
                m.max_abs_d_at_deg = wrap_deg(m.max_abs_d_at_deg);
                for ivs in [&mut m.excess_intervals_deg, &mut m.deficit_intervals_deg] {
                    for iv in ivs.iter_mut() {
                        *iv = [wrap_deg(iv[0]), wrap_deg(iv[1])];
                    }
                    ivs.sort_by(|a, b| a[0].total_cmp(&b[0]));
                }
                m
            });
        }
        let kmax = (0..n).max_by(|&a, &b| pprime[a].total_cmp(&pprime[b]).then(b.cmp(&a))).unwrap_or(0);
        threads.push(StitchThreadSummary {
            thread: name.clone(),
            role: th.role,
            path: path.clone(),
            contour: th.contour,
            per_stitch_mm: th.per_stitch_mm,
            locked_mm: th.cut_mm,
            lock_phi_deg: from_c(th.lock_deg),
            max_pprime_mm: pprime[kmax],
            phi_at_max_pprime_deg: wrap_deg(phis[kmax]),
            max_pprime_b_mm,
            events: th
                .events
                .iter()
                .map(|e| StitchEvent { name: e.name.clone(), phi_deg: from_c(e.phi_c_deg), kind: e.kind, jump_mm: e.eta_right_mm - e.eta_left_mm })
                .collect(),
            mismatch: m,
        });
    }
    Ok(StitchSummary {
        stitch_type: setup.spec.stitch_type.number(),
        m_mm: setup.spec.m_mm,
        t_mm: setup.spec.t_mm,
        cyclogram_zero_deg: setup.cyclogram_zero_deg,
        phi0_deg: wrap_deg(phi0_deg),
        threads,
        moments: req.moments.iter().map(|(s, p)| (s.clone(), from_c(*p))).collect(),
        warnings: req.warnings.clone(),
    })
}

#[cfg(test)]
mod tests {
    use super::in_window;

    #[test]
    fn windows_may_wrap() {
        assert!(in_window(10.0, [350.0, 20.0]));
        assert!(in_window(355.0, [350.0, 20.0]));
        assert!(!in_window(30.0, [350.0, 20.0]));
        assert!(in_window(100.0, [90.0, 120.0]));
        assert!(!in_window(89.0, [90.0, 120.0]));
    }
}
