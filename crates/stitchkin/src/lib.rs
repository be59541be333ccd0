//! stitchkin: kinematics of sewing-machine mechanisms and the thread they
//! move.
//!
//! A machine is described in one TOML model file ([`model`]); a
//! [`model::Model`] resolves with parameter values into a
//! [`mechanism::Mechanism`] that is solved group by group at any main-shaft
//! angle φ. The same closed-form code runs on `f64` (positions) and on dual
//! numbers (exact velocity and acceleration analogs); [`eval`] tabulates a
//! full cycle.
//!
//! ```
//! use stitchkin::{eval, model::Model};
//! let model = Model::preset("needle876").unwrap();
//! let table = eval::run_cycle(&model, &model.defaults(), &eval::CycleOptions::default()).unwrap();
//! let y = table.column("G.y_mm").unwrap();
//! let stroke = y.iter().cloned().fold(f64::MIN, f64::max) - y.iter().cloned().fold(f64::MAX, f64::min);
//! assert!((stroke - 18.0).abs() < 1.0);
//! ```

pub mod error;
pub mod eval;
pub mod format;
pub mod geometry;
pub mod jobs;
pub mod mechanism;
pub mod model;
mod numeric;
pub mod output;
pub mod presets;
pub mod references;
pub mod scalar;
pub mod stitch;
pub mod study;
pub mod thread;
pub mod verify;

// The vocabulary a user of the library works with, from the crate root.
pub use error::{
    AssemblyError, Error, Input, IoError, ModelError, NotFiniteError, ParamError, PhysicalError, StitchError,
    ThreadError,
};
pub use eval::{CycleOptions, CycleTable, run_cycle};
pub use model::{Machine, Model, ParamDef, Params};
pub use presets::Preset;
pub use stitch::consumption::{Consumption, Seam, StitchGeometry, ThreadConsumption, consumption};
pub use thread::measured::{
    CurveKind, MeasuredCurve, ReadingOptions, parse_curve_csv, parse_curve_csv_with, read_curve, read_curve_with,
};
