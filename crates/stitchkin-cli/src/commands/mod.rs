//! The subcommands, one module each (cargo's `commands/` layout): each
//! module has its `Args`, with the command's about text and examples, and
//! its `run`, which parses, calls the library and prints.

pub(crate) mod cam;
pub(crate) mod check;
pub(crate) mod compare_2d3d;
pub(crate) mod consumption;
pub(crate) mod draw;
pub(crate) mod fit;
pub(crate) mod matching;
pub(crate) mod measured;
pub(crate) mod new;
pub(crate) mod nomogram;
pub(crate) mod plot;
pub(crate) mod presets;
pub(crate) mod report;
pub(crate) mod run;
pub(crate) mod schema;
pub(crate) mod sensitivity;
pub(crate) mod serve;
pub(crate) mod straightness;
pub(crate) mod stroke;
pub(crate) mod sweep;
pub(crate) mod tolerance;
pub(crate) mod tune;
