//! Thread consumed by one finished stitch, from the stitch's geometry
//! (seed 004 §2.6; derivation in `docs/stitch-formation.md` §6).
//!
//! Elementary lengths: through the material along the needle `l_m = m/cos β`
//! (β the needle's inclination), a looper-thread leg over one stitch
//! `l = √(a_e² + t²)` (a_e the overedge width, t the stitch length). Contours
//! (the thesis's Table 1 numbering):
//! - 1: needle thread looped at the needle line, `t + 2·l_m`;
//! - 2: contour 1 plus one looper-leg, `t + 2·l_m + l`;
//! - 3: needle thread drawn to the edge (503), `t + 2·l_m + 2·a_e + 2·e·m`;
//! - 10: looper thread on the top face, `a_e + l + 2·(1 − e)·m`;
//! - 13: looper thread on the bottom face, `a_e + l + 2·e·m`;
//!
//! with the looper threads meeting at the edge at height `e·m`. The other
//! contours (4–7, 9, 11, 12, 14–16) were drawn in the thesis's figures, which
//! are lost: they are reported as not derivable rather than guessed.
//!
//! Outside class 500, by the same conventions (docs §6.2): lockstitch 301,
//! needle `t + 2·f·l_m` and bobbin `t + 2·(1 − f)·l_m` with the threads
//! interlacing at depth `f·m`; chain and cover stitches (401, 406, 407,
//! 602, 605), each needle `t + 2·l_m`, the looper thread of 401 `3·t`. The
//! looper threads of the multi-needle stitches and the cover thread of
//! 602/605 are reported as not derivable.
//!
//! Every figure is the taut consumption ([`TAUT`]); [`Consumption::for_seam`]
//! gives it per length of seam and for a seam, with a waste allowance.

use serde::Serialize;

use crate::error::{Input, ParamError};

/// The technological parameters of a stitch, mm and degrees.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct StitchGeometry {
    /// Material thickness m (compressed under the presser foot), mm.
    pub thickness_mm: f64,
    /// Stitch length t, mm.
    pub stitch_mm: f64,
    /// Overedge width a_e (class 500), mm.
    pub width_mm: f64,
    /// Needle inclination β from the normal to the material, degrees.
    pub incline_deg: f64,
    /// Height of the looper threads' meeting point on the edge, as a fraction
    /// e of the thickness (0…1; 0.5 = mid-edge).
    pub edge_fraction: f64,
    /// Lockstitch 301: where the needle and bobbin threads interlace, as a
    /// fraction f of the thickness below the top face (0…1; 0.5 = in the
    /// middle of the material, the balanced stitch).
    pub interlace_fraction: f64,
}

impl StitchGeometry {
    /// A stitch of thickness `m` and length `t`, mm, with the other inputs
    /// at their defaults: no overedge width, the needle normal to the
    /// material, looper threads meeting mid-edge, a balanced lockstitch.
    pub fn new(thickness_mm: f64, stitch_mm: f64) -> StitchGeometry {
        StitchGeometry {
            thickness_mm,
            stitch_mm,
            width_mm: 0.0,
            incline_deg: 0.0,
            edge_fraction: 0.5,
            interlace_fraction: 0.5,
        }
    }
}

/// How much seam the thread is wanted for, and the allowance for waste.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Seam {
    /// Seam length, mm.
    pub length_mm: f64,
    /// Allowance for waste (thread chains at the seam's ends, trimming,
    /// breaks, cone ends), per cent of the seam's thread; added on top of
    /// the taut consumption, never inside it.
    pub waste_pct: f64,
}

impl Default for Seam {
    /// One metre of seam, no waste.
    fn default() -> Self {
        Seam {
            length_mm: 1000.0,
            waste_pct: 0.0,
        }
    }
}

/// One thread of a stitch type.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ThreadConsumption {
    /// `needle 1`, `lower looper`, …
    pub thread: String,
    /// Contour number (seed 004 Table 1); `None` for chain-stitch threads.
    pub contour: Option<u8>,
    /// The formula, or why there is none.
    pub formula: String,
    /// Thread per stitch, mm (`None`: not derivable).
    pub length_mm: Option<f64>,
    /// Thread per length of seam (mm of thread per mm of seam, = m/m), the
    /// ratio thread makers tabulate: `length_mm / t`.
    pub ratio: Option<f64>,
    /// Thread for the seam ([`Seam::length_mm`]), without waste, m.
    pub seam_m: Option<f64>,
    /// The same with the waste allowance, m.
    pub seam_with_waste_m: Option<f64>,
}

/// A stitch type's consumption per stitch.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Consumption {
    pub stitch_type: u16,
    pub geometry: StitchGeometry,
    pub threads: Vec<ThreadConsumption>,
    /// The seam the totals are for.
    pub seam: Seam,
    /// Stitches in the seam: its length over t.
    pub stitches: f64,
    /// Sum over the threads, when every one is derivable.
    pub total_mm: Option<f64>,
    /// The total per length of seam, mm/mm.
    pub total_ratio: Option<f64>,
    /// The total for the seam, without and with waste, m.
    pub total_seam_m: Option<f64>,
    pub total_seam_with_waste_m: Option<f64>,
    /// Elementary lengths l_m and l, mm.
    pub l_m_mm: f64,
    pub l_mm: f64,
    /// What the figures are and what they leave out.
    pub notes: Vec<String>,
}

/// Stitch types stitchkin knows, for messages.
pub const TYPES: &str = "301, 401, 406, 407, 501–512, 514, 521, 602 and 605";

/// Seed 004 §2.6 Table 3: contour of the 1st needle, 2nd needle, lower
/// looper and upper looper thread of each class-500 type (0: no such thread).
const MATRIX: &[(u16, [u8; 4])] = &[
    (501, [5, 0, 0, 0]),
    (502, [1, 0, 11, 0]),
    (503, [3, 0, 10, 0]),
    (504, [1, 0, 13, 10]),
    (505, [2, 0, 14, 7]),
    (506, [2, 1, 15, 9]),
    (507, [2, 1, 7, 15]),
    (508, [1, 1, 11, 0]),
    (509, [1, 1, 12, 0]),
    (510, [5, 5, 0, 0]),
    (511, [6, 6, 0, 0]),
    (512, [1, 1, 16, 7]),
    (514, [1, 1, 16, 9]),
    (521, [4, 4, 7, 0]),
];

impl StitchGeometry {
    fn check(&self) -> Result<(), ParamError> {
        let bad = |input: Input, what: &str, v: f64, want: &str| {
            Err(ParamError::new(
                input,
                format!("{what} = {v} is out of range"),
                Some(want.to_string()),
            ))
        };
        // A stitch needs material: m = 0 would be a stitch through nothing.
        if !(self.thickness_mm.is_finite() && self.thickness_mm > 0.0) {
            return bad(
                Input::Thickness,
                "the material thickness",
                self.thickness_mm,
                "give the compressed material's thickness, m > 0 mm, e.g. 2.5",
            );
        }
        if !(self.stitch_mm.is_finite() && self.stitch_mm > 0.0) {
            return bad(
                Input::StitchLength,
                "the stitch length",
                self.stitch_mm,
                "give t > 0 mm, e.g. 2.8",
            );
        }
        if !(self.width_mm.is_finite() && self.width_mm >= 0.0) {
            return bad(
                Input::Width,
                "the overedge width",
                self.width_mm,
                "give a ≥ 0 mm, e.g. 4",
            );
        }
        if !(self.incline_deg.is_finite() && self.incline_deg.abs() < 80.0) {
            return bad(
                Input::Incline,
                "the needle inclination",
                self.incline_deg,
                "give β between −80° and 80°, e.g. 20",
            );
        }
        if !(0.0..=1.0).contains(&self.interlace_fraction) {
            return bad(
                Input::Interlace,
                "the interlacing depth",
                self.interlace_fraction,
                "give f between 0 and 1, a fraction of the thickness below the top face (0.5: in the middle, a balanced stitch)",
            );
        }
        if !(0.0..=1.0).contains(&self.edge_fraction) {
            return bad(
                Input::EdgeFraction,
                "the edge fraction",
                self.edge_fraction,
                "give e between 0 and 1 (0.5: the looper threads meet mid-edge)",
            );
        }
        Ok(())
    }
}

/// Thread per stitch for stitch type `stitch_type` with geometry `g`, and
/// for one metre of seam without waste ([`Consumption::for_seam`] for
/// another).
pub fn consumption(stitch_type: u16, g: &StitchGeometry) -> Result<Consumption, ParamError> {
    g.check()?;
    // An overedge stitch wraps the edge: its threads' contours need a > 0.
    if (500..600).contains(&stitch_type) && g.width_mm == 0.0 {
        return Err(ParamError::new(
            Input::Width,
            format!("stitch type {stitch_type} needs the overedge width a > 0"),
            Some("give the overedge width in mm, e.g. 4".into()),
        ));
    }
    let (m, t, a) = (g.thickness_mm, g.stitch_mm, g.width_mm);
    let l_m = m / g.incline_deg.to_radians().cos();
    let l = a.hypot(t);
    let threads = match stitch_type {
        301 => lockstitch(g, l_m),
        401 | 406 | 407 | 602 | 605 => chain_or_cover(stitch_type, t, l_m),
        _ => overedge(stitch_type, g, l_m, l)?,
    };
    let total_mm = threads.iter().map(|t| t.length_mm).sum::<Option<f64>>();
    let lengths = threads
        .iter()
        .filter_map(|t| t.length_mm)
        .chain(total_mm)
        .chain([l_m, l]);
    if lengths.into_iter().any(|v| !v.is_finite()) {
        return Err(ParamError::general(
            format!("the thread lengths overflow for m = {m} mm, t = {t} mm, a = {a} mm"),
            Some("give the dimensions of a real stitch (a few mm)".into()),
        ));
    }
    Consumption {
        stitch_type,
        geometry: *g,
        threads,
        seam: Seam::default(),
        stitches: 0.0,
        total_mm,
        total_ratio: None,
        total_seam_m: None,
        total_seam_with_waste_m: None,
        l_m_mm: l_m,
        l_mm: l,
        notes: vec![TAUT.to_string()],
    }
    .for_seam(&Seam::default())
}

/// A thread's formula and its length per stitch, mm (`None`: not derivable).
type Formula = (String, Option<f64>);

impl ThreadConsumption {
    /// A thread per stitch; the per-seam figures come with
    /// [`Consumption::for_seam`].
    fn per_stitch(thread: &str, contour: Option<u8>, (formula, length_mm): Formula) -> ThreadConsumption {
        ThreadConsumption {
            thread: thread.to_string(),
            contour,
            formula,
            length_mm,
            ratio: None,
            seam_m: None,
            seam_with_waste_m: None,
        }
    }
}

/// Lockstitch 301 (G7): the threads interlace at depth f·m on the needle
/// line; each lies along its face from hole to hole and goes into the hole
/// to the interlacing and back.
fn lockstitch(g: &StitchGeometry, l_m: f64) -> Vec<ThreadConsumption> {
    let (t, f) = (g.stitch_mm, g.interlace_fraction);
    vec![
        ThreadConsumption::per_stitch("needle 1", None, ("t + 2·f·l_m".into(), Some(t + 2.0 * f * l_m))),
        ThreadConsumption::per_stitch(
            "bobbin",
            None,
            ("t + 2·(1 − f)·l_m".into(), Some(t + 2.0 * (1.0 - f) * l_m)),
        ),
    ]
}

/// Chain stitches 401, 406, 407 and cover stitches 602, 605: the needle
/// threads, the looper thread (derivable with one needle) and the cover
/// thread (600 class).
fn chain_or_cover(stitch_type: u16, t: f64, l_m: f64) -> Vec<ThreadConsumption> {
    let needles = match stitch_type {
        401 => 1,
        406 | 602 => 2,
        _ => 3,
    };
    // Each needle loop collapses at its hole on the underside (G2), and on
    // the top face a cover thread (602, 605) lies flat under the needle
    // thread: t + 2·l_m, as contour 1.
    let mut threads: Vec<ThreadConsumption> = (1..=needles)
        .map(|j| ThreadConsumption::per_stitch(&format!("needle {j}"), None, ("t + 2·l_m".into(), Some(t + 2.0 * l_m))))
        .collect();
    let looper: Formula = if needles == 1 {
        // The looper thread passes through the needle loop at its hole, and
        // its own loop (hole j to hole j + 1 and back) holds the next needle
        // loop; one more leg carries it on: three legs of t (docs §6.2).
        ("3·t".into(), Some(3.0 * t))
    } else {
        (
            format!(
                "not derivable: its loop holds {needles} needle loops at once, and how its legs run between \
                 the needle lines is not given by the seeds or the sources at hand"
            ),
            None,
        )
    };
    threads.push(ThreadConsumption::per_stitch("looper", None, looper));
    if stitch_type >= 600 {
        threads.push(ThreadConsumption::per_stitch(
            "cover",
            None,
            (
                "not derivable: the spreader lays it across the needles on the top face, and its path per \
                 stitch follows the spreader's motion, which no source at hand gives"
                    .into(),
                None,
            ),
        ));
    }
    threads
}

/// A class-500 stitch by the structure matrix (seed 004 Table 3): each
/// organ's thread by its contour.
fn overedge(stitch_type: u16, g: &StitchGeometry, l_m: f64, l: f64) -> Result<Vec<ThreadConsumption>, ParamError> {
    let (m, t, a, e) = (g.thickness_mm, g.stitch_mm, g.width_mm, g.edge_fraction);
    let contour = |c: u8| -> Formula {
        match c {
            1 => ("t + 2·l_m".into(), Some(t + 2.0 * l_m)),
            2 => ("t + 2·l_m + l".into(), Some(t + 2.0 * l_m + l)),
            3 => (
                "t + 2·l_m + 2·a + 2·e·m".into(),
                Some(t + 2.0 * l_m + 2.0 * a + 2.0 * e * m),
            ),
            10 => ("a + l + 2·(1 − e)·m".into(), Some(a + l + 2.0 * (1.0 - e) * m)),
            13 => ("a + l + 2·e·m".into(), Some(a + l + 2.0 * e * m)),
            _ => (
                "not derivable: the thesis's drawing of this contour is lost".into(),
                None,
            ),
        }
    };
    let Some((_, row)) = MATRIX.iter().find(|(ty, _)| *ty == stitch_type) else {
        return Err(ParamError::new(
            Input::StitchType,
            format!("stitch type {stitch_type} is not covered"),
            Some(format!("stitch types: {TYPES}")),
        ));
    };
    Ok(["needle 1", "needle 2", "lower looper", "upper looper"]
        .iter()
        .zip(row)
        .filter(|(_, c)| **c != 0)
        .map(|(name, &c)| ThreadConsumption::per_stitch(name, Some(c), contour(c)))
        .collect())
}

/// What the figures are and leave out (docs/stitch-formation.md §6.1).
pub const TAUT: &str = "taut consumption: threads of zero thickness pulled straight and loops collapsed onto \
    the threads they hold. Real seams take more in all (the threads' own diameter and bending stiffness, \
    crimp around the interlacings, slack the tensions leave, the material's recovery after the presser \
    foot), and how it divides between the threads follows the tension balance. The waste allowance is \
    added separately";

impl Seam {
    fn check(&self) -> Result<(), ParamError> {
        if !(self.length_mm.is_finite() && self.length_mm > 0.0 && self.length_mm <= 1e9) {
            return Err(ParamError::new(
                Input::SeamLength,
                format!("the seam length {} mm is out of range", self.length_mm),
                Some("give the seam's length in mm, greater than 0 and at most 10⁹ (1 000 km), e.g. 1000".into()),
            ));
        }
        if !(self.waste_pct.is_finite() && (0.0..=100.0).contains(&self.waste_pct)) {
            return Err(ParamError::new(
                Input::Waste,
                format!("the waste allowance {} % is out of range", self.waste_pct),
                Some("give a percentage from 0 to 100 of the seam's thread, e.g. 12".into()),
            ));
        }
        Ok(())
    }
}

impl Consumption {
    /// The same stitch's thread for `seam`: per thread and in total, the
    /// ratio to the seam (mm/mm), the thread for the seam's length, and that
    /// with the waste allowance (m).
    pub fn for_seam(mut self, seam: &Seam) -> Result<Consumption, ParamError> {
        seam.check()?;
        let t = self.geometry.stitch_mm;
        let waste = 1.0 + seam.waste_pct / 100.0;
        // mm of thread per mm of seam; for the seam, m of thread.
        let ratio = |l: f64| l / t;
        let seam_m = |l: f64| ratio(l) * seam.length_mm / 1000.0;
        for th in &mut self.threads {
            th.ratio = th.length_mm.map(ratio);
            th.seam_m = th.length_mm.map(seam_m);
            th.seam_with_waste_m = th.seam_m.map(|v| v * waste);
        }
        self.seam = *seam;
        self.stitches = seam.length_mm / t;
        self.total_ratio = self.total_mm.map(ratio);
        self.total_seam_m = self.total_mm.map(seam_m);
        self.total_seam_with_waste_m = self.total_seam_m.map(|v| v * waste);
        let figures = [self.total_ratio, self.total_seam_with_waste_m, Some(self.stitches)];
        if figures.into_iter().flatten().any(|v| !v.is_finite()) {
            return Err(ParamError::general(
                format!("the thread for {} mm of seam overflows with t = {t} mm", seam.length_mm),
                Some("give the dimensions of a real stitch (a few mm)".into()),
            ));
        }
        Ok(self)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_relative_eq;

    fn altin() -> StitchGeometry {
        StitchGeometry {
            thickness_mm: 2.5,
            stitch_mm: 2.8,
            width_mm: 4.0,
            incline_deg: 20.0,
            edge_fraction: 0.5,
            interlace_fraction: 0.5,
        }
    }

    #[test]
    fn overedge_504_and_503() {
        let c = consumption(504, &altin()).unwrap();
        assert_relative_eq!(c.l_m_mm, 2.5 / 20f64.to_radians().cos(), epsilon = 1e-12);
        assert_relative_eq!(c.l_mm, 4.0f64.hypot(2.8), epsilon = 1e-12);
        assert_eq!(c.threads.len(), 3);
        assert_relative_eq!(c.threads[0].length_mm.unwrap(), 2.8 + 2.0 * c.l_m_mm, epsilon = 1e-12);
        assert_relative_eq!(c.total_mm.unwrap(), 30.8861334, epsilon = 1e-6);
        assert_relative_eq!(
            consumption(503, &altin()).unwrap().total_mm.unwrap(),
            30.0035111,
            epsilon = 1e-6
        );
        // Types whose contours are lost: no total, no guessed numbers.
        let c = consumption(505, &altin()).unwrap();
        assert!(c.total_mm.is_none() && c.threads.iter().any(|t| t.length_mm.is_none()));
    }

    #[test]
    fn an_overedge_stitch_needs_its_width() {
        let g = StitchGeometry {
            width_mm: 0.0,
            ..altin()
        };
        for stitch_type in [503, 504, 512] {
            let e = consumption(stitch_type, &g).unwrap_err();
            assert_eq!(e.input, Some(Input::Width), "{e}");
            assert!(e.message.contains("needs the overedge width"), "{e}");
        }
        assert!(consumption(407, &g).is_ok());
    }

    #[test]
    fn lockstitch_301_splits_at_the_interlacing() {
        let g = StitchGeometry {
            incline_deg: 0.0,
            ..StitchGeometry::new(2.0, 2.5)
        };
        let c = consumption(301, &g).unwrap();
        let names: Vec<&str> = c.threads.iter().map(|t| t.thread.as_str()).collect();
        assert_eq!(names, ["needle 1", "bobbin"]);
        // Balanced: t + m each, 2t + 2m in all.
        assert_relative_eq!(c.threads[0].length_mm.unwrap(), 4.5, epsilon = 1e-12);
        assert_relative_eq!(c.threads[1].length_mm.unwrap(), 4.5, epsilon = 1e-12);
        assert_relative_eq!(c.total_mm.unwrap(), 9.0, epsilon = 1e-12);
        // Interlacing at the top face: the bobbin thread goes through.
        let top = consumption(
            301,
            &StitchGeometry {
                interlace_fraction: 0.0,
                ..g
            },
        )
        .unwrap();
        assert_relative_eq!(top.threads[0].length_mm.unwrap(), 2.5, epsilon = 1e-12);
        assert_relative_eq!(top.threads[1].length_mm.unwrap(), 6.5, epsilon = 1e-12);
        assert_relative_eq!(top.total_mm.unwrap(), c.total_mm.unwrap(), epsilon = 1e-12);
        let e = consumption(
            301,
            &StitchGeometry {
                interlace_fraction: 1.2,
                ..g
            },
        )
        .unwrap_err();
        assert_eq!(e.input, Some(Input::Interlace), "{e}");
    }

    /// American & Efird's bulletin "Estimating Thread Consumption" prints
    /// Union Special's 401 chart at 8 stitches per inch: 4.88, 4.96, 5.04,
    /// 5.12, 5.20 inches of thread per inch of seam for seams 0.055 … 0.075
    /// inch thick. The taut 401 (needle t + 2m, looper 3t) gives them.
    #[test]
    fn chain_stitch_401_reproduces_the_union_special_chart() {
        let t = 25.4 / 8.0;
        for (thickness_in, published) in [
            (0.055, 4.88),
            (0.060, 4.96),
            (0.065, 5.04),
            (0.070, 5.12),
            (0.075, 5.20),
        ] {
            let c = consumption(401, &StitchGeometry::new(thickness_in * 25.4, t)).unwrap();
            assert_relative_eq!(c.threads[1].length_mm.unwrap(), 3.0 * t, epsilon = 1e-12);
            assert!(
                (c.total_ratio.unwrap() - published).abs() < 0.005,
                "{thickness_in}: {c:?}"
            );
        }
    }

    #[test]
    fn multi_needle_chain_and_cover_stitches_leave_out_what_is_not_derivable() {
        let g = StitchGeometry::new(3.0, 3.0);
        for (ty, needles, cover) in [(406, 2, false), (407, 3, false), (602, 2, true), (605, 3, true)] {
            let c = consumption(ty, &g).unwrap();
            let needle: Vec<_> = c.threads.iter().filter(|t| t.thread.starts_with("needle")).collect();
            assert_eq!(needle.len(), needles, "{ty}");
            assert!(needle.iter().all(|t| t.length_mm == Some(9.0)), "{ty}");
            let looper = c.threads.iter().find(|t| t.thread == "looper").unwrap();
            assert!(
                looper.length_mm.is_none() && looper.formula.starts_with("not derivable"),
                "{ty}"
            );
            assert_eq!(c.threads.iter().any(|t| t.thread == "cover"), cover, "{ty}");
            assert!(c.total_mm.is_none() && c.total_seam_m.is_none(), "{ty}");
        }
    }

    #[test]
    fn per_seam_and_waste() {
        let c = consumption(301, &StitchGeometry::new(2.0, 2.5)).unwrap();
        // One metre of seam by default: 400 stitches of 9 mm.
        assert_eq!(c.seam, Seam::default());
        assert_relative_eq!(c.stitches, 400.0, epsilon = 1e-12);
        assert_relative_eq!(c.total_ratio.unwrap(), 3.6, epsilon = 1e-12);
        assert_relative_eq!(c.total_seam_m.unwrap(), 3.6, epsilon = 1e-12);
        assert_relative_eq!(c.total_seam_with_waste_m.unwrap(), 3.6, epsilon = 1e-12);
        let seam = Seam {
            length_mm: 2500.0,
            waste_pct: 15.0,
        };
        let c = c.for_seam(&seam).unwrap();
        assert_relative_eq!(c.threads[0].ratio.unwrap(), 1.8, epsilon = 1e-12);
        assert_relative_eq!(c.threads[0].seam_m.unwrap(), 4.5, epsilon = 1e-12);
        assert_relative_eq!(c.threads[0].seam_with_waste_m.unwrap(), 4.5 * 1.15, epsilon = 1e-12);
        assert_relative_eq!(c.total_seam_with_waste_m.unwrap(), 9.0 * 1.15, epsilon = 1e-12);
        for (bad, input) in [
            (
                Seam {
                    length_mm: 0.0,
                    waste_pct: 0.0,
                },
                Input::SeamLength,
            ),
            (
                Seam {
                    length_mm: f64::NAN,
                    waste_pct: 0.0,
                },
                Input::SeamLength,
            ),
            (
                Seam {
                    length_mm: 1000.0,
                    waste_pct: -1.0,
                },
                Input::Waste,
            ),
            (
                Seam {
                    length_mm: 1000.0,
                    waste_pct: 101.0,
                },
                Input::Waste,
            ),
        ] {
            assert_eq!(c.clone().for_seam(&bad).unwrap_err().input, Some(input), "{bad:?}");
        }
        // A stitch too short for the seam's arithmetic is refused, not inf.
        let tiny = consumption(301, &StitchGeometry::new(2.0, 1e-307)).unwrap_err();
        assert!(tiny.message.contains("overflow"), "{tiny}");
    }

    #[test]
    fn chain_stitch_needles_and_bad_input() {
        let g = StitchGeometry {
            thickness_mm: 3.0,
            stitch_mm: 3.0,
            width_mm: 0.0,
            incline_deg: 0.0,
            edge_fraction: 0.5,
            interlace_fraction: 0.5,
        };
        let c = consumption(407, &g).unwrap();
        assert_eq!(c.threads.iter().filter(|t| t.thread.starts_with("needle")).count(), 3);
        assert_eq!(c.threads[0].length_mm, Some(9.0));
        assert!(consumption(300, &g).unwrap_err().help.unwrap().contains("501"));
        assert!(consumption(504, &StitchGeometry { stitch_mm: 0.0, ..g }).is_err());
        assert!(
            consumption(
                504,
                &StitchGeometry {
                    edge_fraction: 1.5,
                    interlace_fraction: 0.5,
                    ..g
                }
            )
            .is_err()
        );
        // More thread for thicker material and longer stitches.
        let base = consumption(504, &altin()).unwrap().total_mm.unwrap();
        assert!(
            consumption(
                504,
                &StitchGeometry {
                    thickness_mm: 3.0,
                    ..altin()
                }
            )
            .unwrap()
            .total_mm
            .unwrap()
                > base
        );
        assert!(
            consumption(
                504,
                &StitchGeometry {
                    stitch_mm: 3.2,
                    ..altin()
                }
            )
            .unwrap()
            .total_mm
            .unwrap()
                > base
        );
    }
}
