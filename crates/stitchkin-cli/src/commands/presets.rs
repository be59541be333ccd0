//! `stitchkin presets`: the shipped presets, and a preset's model file.

use std::path::PathBuf;

use stitchkin::error::Error;
use stitchkin::model::Model;
use stitchkin::presets;

use crate::common::{emit, emit_text, in_flag};

/// List the shipped presets (name, the paper it follows, machine), or write one's model
/// file as shipped (--export).
#[derive(clap::Args)]
#[command(
    after_help = "Examples:\n  stitchkin presets\n  stitchkin presets --export lockstitch -o lockstitch.toml\n  \
    stitchkin match lockstitch.toml      # the same as --preset lockstitch"
)]
pub(crate) struct Args {
    /// Write the preset NAME's model file exactly as shipped: a file to
    /// read, change and load like any other model.
    #[arg(long, value_name = "NAME")]
    export: Option<String>,
    /// With --export: write to FILE instead of stdout (written completely
    /// or not at all; an existing file is replaced, as by every command's -o).
    #[arg(short, long, value_name = "FILE", requires = "export")]
    output: Option<PathBuf>,
}

pub(crate) fn run(args: Args) -> Result<(), Error> {
    if let Some(name) = &args.export {
        let preset = presets::get(name).map_err(|e| in_flag(Error::Param(e), "--export"))?;
        return emit(preset.toml.as_bytes(), args.output.as_ref());
    }
    let mut rows = Vec::new();
    for p in presets::ALL {
        let (title, after) = match Model::preset(p.name) {
            Ok(m) => (
                m.title().unwrap_or_default().to_string(),
                m.seed()
                    .and_then(stitchkin::references::cite_seed)
                    .unwrap_or_default()
                    .to_string(),
            ),
            Err(e) => (format!("(does not load: {e})"), String::new()),
        };
        let default = if p.name == presets::DEFAULT { "  (default)" } else { "" };
        rows.push((p.name, after, format!("{title}{default}")));
    }
    let w = rows
        .iter()
        .map(|r| r.1.chars().count())
        .max()
        .unwrap_or(0)
        .max("after".len());
    let mut out = format!("{:<13} {:<w$}  machine\n", "name", "after");
    for (name, after, machine) in rows {
        out += &format!("{name:<13} {after:<w$}  {machine}\n");
    }
    emit_text(&out, None)
}
