//! `stitchkin presets`: the shipped presets.

use stitchkin::error::Error;
use stitchkin::model::Model;
use stitchkin::presets;

/// List the shipped presets (name, machine, seed).
#[derive(clap::Args)]
#[command(after_help = "Example:\n  stitchkin presets")]
pub(crate) struct Args {}

pub(crate) fn run(_args: Args) -> Result<(), Error> {
    let mut out = String::from("name          seed  machine\n");
    for p in presets::ALL {
        let (title, seed) = match Model::preset(p.name) {
            Ok(m) => (
                m.title().unwrap_or_default().to_string(),
                m.seed().unwrap_or_default().to_string(),
            ),
            Err(e) => (format!("(does not load: {e})"), String::new()),
        };
        let default = if p.name == presets::DEFAULT { "  (default)" } else { "" };
        out += &format!("{:<13} {:<5} {title}{default}\n", p.name, seed);
    }
    crate::common::emit(out.as_bytes(), None)
}
