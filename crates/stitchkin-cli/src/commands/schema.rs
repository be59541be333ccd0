//! `stitchkin schema`: the JSON Schema of the model file.

use stitchkin::error::Error;

/// Print the JSON Schema of the model file format.
#[derive(clap::Args)]
#[command(after_help = "Example:\n  stitchkin schema > stitchkin-model.schema.json")]
pub(crate) struct Args {}

pub(crate) fn run(_args: Args) -> Result<(), Error> {
    crate::common::emit(stitchkin::model::schema_json().as_bytes(), None)
}
