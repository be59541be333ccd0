//! The stand-in cases of the independent numpy reference
//! (`crates/stitchkin/tests/data/stitch/`, `docs/stitch-formation.md` §11):
//! stitch specs with the reference's motion laws, for tests and examples
//! that check stitchkin against it.

use std::sync::Arc;

use crate::geometry::V3;
use crate::stitch::spec::*;

/// altin504: Textima Altin, stitch 504 (seed 004), with the reference's
/// stand-in laws, for thickness `m` and stitch length `t` (mm).
pub fn altin504(m: f64, t: f64) -> StitchSpec {
    StitchSpec {
        stitch_type: StitchType::S504,
        m_mm: m,
        t_mm: t,
        tilt_deg: 20.0,
        a_e_mm: 4.0,
        edge_split: 0.5,
        feed: FeedLaw::Harmonic {
            start_deg: 134.0,
            duration_deg: 100.0,
        },
        needles: vec![NeedleSpec {
            name: "needle".into(),
            eye: Motion::NeedleLaw {
                x_mm: 0.0,
                eye_above_plate_mm: 11.5,
                stroke_mm: 25.44,
                bdc_deg: 0.0,
                tilt_deg: 20.0,
            },
            point_below_eye_mm: 2.0,
            catch_deg: Some(30.0),
            drop_deg: Some(300.0),
        }],
        looper: Some(LooperSpec {
            eye: Motion::LooperLaw {
                stroke_mm: 17.32,
                far_deg: 180.0,
                catch_deg: 30.0,
                catch_x_mm: 0.0,
                y0_mm: (4.0 + 2.5) * 20f64.to_radians().tan(), // (k + b)·tan β
                avoid_mm: 0.75,
                depth_mm: 5.5,
            },
            k_mm: 4.0,
            a_mm: 1.0,
            b_mm: 2.5,
            gamma_max_rad: 0.4,
        }),
        hook: None,
        interlace: 0.5,
        upper_looper: Some(UpperLooperSpec {
            eye: Motion::PolylineLaw {
                points: Arc::from(vec![
                    V3::new(13.0, 1.0, -6.0),
                    V3::new(5.5, 0.0, 4.0),
                    V3::new(-1.0, -1.0, 4.0),
                ]),
                low_deg: 110.0,
                high_deg: 270.0,
            },
            pick_window_deg: [120.0, 200.0],
        }),
        spreader: None,
        moments: Moments {
            stab_deg: 270.0,
            upper_release_deg: 290.0,
            draw_in_deg: 330.0,
        },
        regulator: Regulator::AtLock,
    }
}

/// altin503: the altin504 stand-ins (needle, lower looper, feed, φ1, φ3,
/// φ4, φ5) with the reference's illustrative spreader in place of the upper
/// looper, releasing the looper thread at φ_SD = 290°.
pub fn altin503(m: f64, t: f64) -> StitchSpec {
    StitchSpec {
        stitch_type: StitchType::S503,
        upper_looper: None,
        spreader: Some(SpreaderSpec {
            eye: Motion::PolylineLaw {
                points: Arc::from(vec![
                    V3::new(11.0, 1.5, -3.0),
                    V3::new(5.5, 0.0, 4.0),
                    V3::new(-1.0, -1.0, 4.0),
                ]),
                low_deg: 110.0,
                high_deg: 270.0,
            },
            pick_window_deg: [120.0, 200.0],
        }),
        ..altin504(m, t)
    }
}

/// Seed 000 eq. 11 (e1 = 0): needle travel below TDC at machine angle φ.
pub fn slider_crank_travel(phi_machine_deg: f64) -> f64 {
    let (r2, l_de) = (15.5, 54.5);
    let phi = phi_machine_deg.to_radians();
    r2 * (1.0 - phi.cos()) + l_de - (l_de * l_de - (r2 * phi.sin()).powi(2)).sqrt()
}

/// mf7923d, stitch 407 (seed 000): three needles on the seed-000 slider-crank
/// law, the reference's harmonic looper and feed.
pub fn mf7923d_407(m: f64, t: f64) -> StitchSpec {
    let needle = |name: &str, x: f64| {
        // The eye tabulated at 0.01° of φ_c (machine φ = φ_c + 180°), s_B = 20.5.
        let points: Vec<V3<f64>> = (0..36_000)
            .map(|k| V3::new(x, 0.0, 20.5 - slider_crank_travel(k as f64 * 0.01 + 180.0)))
            .collect();
        NeedleSpec {
            name: name.into(),
            eye: Motion::Table {
                start_deg: 0.0,
                step_deg: 0.01,
                points: Arc::from(points),
                slopes: None,
            },
            point_below_eye_mm: 2.0,
            catch_deg: None,
            drop_deg: None,
        }
    };
    StitchSpec {
        stitch_type: StitchType::S407,
        m_mm: m,
        t_mm: t,
        tilt_deg: 0.0,
        a_e_mm: 0.0,
        edge_split: 0.5,
        feed: FeedLaw::Harmonic {
            start_deg: 130.0,
            duration_deg: 100.0,
        },
        needles: vec![needle("n1", -4.0), needle("n2", 0.0), needle("n3", 4.0)],
        looper: Some(LooperSpec {
            eye: Motion::LooperLaw {
                stroke_mm: 32.0,
                far_deg: 180.0,
                catch_deg: 30.0,
                catch_x_mm: -4.0,
                y0_mm: 0.0,
                avoid_mm: 0.0,
                depth_mm: 5.5,
            },
            k_mm: 4.0,
            a_mm: 1.0,
            b_mm: 2.5,
            gamma_max_rad: 0.4,
        }),
        hook: None,
        interlace: 0.5,
        upper_looper: None,
        spreader: None,
        moments: Moments {
            stab_deg: 270.0,
            upper_release_deg: 290.0,
            draw_in_deg: 330.0,
        },
        regulator: Regulator::AtLock,
    }
}

/// A lockstitch 301 stand-in (§13): a harmonic needle of stroke 30 mm, its
/// eye 17 mm above the plate at TDC (13 mm below at BDC), a rotary hook of
/// beak radius 14 mm around a bobbin case of radius 11 mm, its axis 11.5 mm
/// along the seam from the needle line and 17.5 mm below the plate; the
/// catch at 2 mm of needle rise (the beak then 1.48 mm above the eye); the
/// loop cast off after 270° of the
/// beak's turn; the feed from 110° for 140°. Illustrative numbers in the
/// range of the makers' timing (docs/references.md).
pub fn lockstitch301(m: f64, t: f64) -> StitchSpec {
    StitchSpec {
        stitch_type: StitchType::S301,
        m_mm: m,
        t_mm: t,
        tilt_deg: 0.0,
        a_e_mm: 0.0,
        edge_split: 0.5,
        feed: FeedLaw::Harmonic {
            start_deg: 110.0,
            duration_deg: 140.0,
        },
        needles: vec![NeedleSpec {
            name: "needle".into(),
            eye: Motion::NeedleLaw {
                x_mm: 0.0,
                eye_above_plate_mm: 17.0,
                stroke_mm: 30.0,
                bdc_deg: 0.0,
                tilt_deg: 0.0,
            },
            point_below_eye_mm: 2.0,
            catch_deg: None,
            drop_deg: None,
        }],
        looper: None,
        hook: Some(HookSpec {
            beak_radius_mm: 14.0,
            case_radius_mm: 11.0,
            offset_mm: 11.5,
            depth_mm: 17.5,
            catch_rise_mm: 2.0,
            cast_off_deg: 270.0,
        }),
        interlace: 0.5,
        upper_looper: None,
        spreader: None,
        // A lockstitch has no looper thread and so no looper-thread moments.
        moments: Moments::NONE,
        regulator: Regulator::default(),
    }
}
