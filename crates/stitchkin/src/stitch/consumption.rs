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
}

/// A stitch type's consumption per stitch.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Consumption {
    pub stitch_type: u16,
    pub geometry: StitchGeometry,
    pub threads: Vec<ThreadConsumption>,
    /// Sum over the threads, when every one is derivable.
    pub total_mm: Option<f64>,
    /// Elementary lengths l_m and l, mm.
    pub l_m_mm: f64,
    pub l_mm: f64,
}

/// Stitch types stitchkin knows, for messages.
pub const TYPES: &str = "401, 406, 407 and 501–512, 514, 521";

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
        if !(self.thickness_mm.is_finite() && self.thickness_mm >= 0.0) {
            return bad(
                Input::Thickness,
                "the material thickness",
                self.thickness_mm,
                "give m ≥ 0 mm, e.g. 2.5",
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

/// Thread per stitch for stitch type `stitch_type` with geometry `g`.
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
    let (m, t, a, e) = (g.thickness_mm, g.stitch_mm, g.width_mm, g.edge_fraction);
    let l_m = m / g.incline_deg.to_radians().cos();
    let l = a.hypot(t);
    let contour = |c: u8| -> (String, Option<f64>) {
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
    let mut threads = Vec::new();
    match stitch_type {
        401 | 406 | 407 => {
            let needles = match stitch_type {
                401 => 1,
                406 => 2,
                _ => 3,
            };
            for j in 1..=needles {
                threads.push(ThreadConsumption {
                    thread: format!("needle {j}"),
                    contour: None,
                    formula: "t + 2·l_m".into(),
                    length_mm: Some(t + 2.0 * l_m),
                });
            }
            threads.push(ThreadConsumption {
                thread: "looper".into(),
                contour: None,
                formula: "not derived (the looper thread of chain stitches is outside the seeds)".into(),
                length_mm: None,
            });
        }
        _ => {
            let Some((_, row)) = MATRIX.iter().find(|(ty, _)| *ty == stitch_type) else {
                return Err(ParamError::new(
                    Input::StitchType,
                    format!("stitch type {stitch_type} is not covered"),
                    Some(format!("stitch types: {TYPES}")),
                ));
            };
            for (name, &c) in ["needle 1", "needle 2", "lower looper", "upper looper"].iter().zip(row) {
                if c == 0 {
                    continue;
                }
                let (formula, length_mm) = contour(c);
                threads.push(ThreadConsumption {
                    thread: name.to_string(),
                    contour: Some(c),
                    formula,
                    length_mm,
                });
            }
        }
    }
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
    Ok(Consumption {
        stitch_type,
        geometry: *g,
        threads,
        total_mm,
        l_m_mm: l_m,
        l_mm: l,
    })
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
    fn chain_stitch_needles_and_bad_input() {
        let g = StitchGeometry {
            thickness_mm: 3.0,
            stitch_mm: 3.0,
            width_mm: 0.0,
            incline_deg: 0.0,
            edge_fraction: 0.5,
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
