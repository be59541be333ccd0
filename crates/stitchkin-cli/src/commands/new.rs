//! `stitchkin new`: a starting model for one's own machine.

use std::path::PathBuf;

use stitchkin::error::Error;
use stitchkin::presets::templates;

use crate::common::emit;

/// Write a starting model of a mechanism family: a shipped preset's file,
/// renamed `my-machine`, under a header that says which parameters to
/// measure on your machine (mm, deg) and where to write them. It loads and
/// runs as it is.
#[derive(clap::Args)]
#[command(
    after_help = "Examples:\n  stitchkin new --list\n  stitchkin new rocking-takeup -o my-machine.toml\n  \
    stitchkin check my-machine.toml"
)]
pub(crate) struct Args {
    /// The mechanism family (see `stitchkin new --list`); without it, the
    /// families are listed.
    #[arg(value_name = "FAMILY", conflicts_with = "list")]
    family: Option<String>,
    /// List the families, one a line, with the preset each starts from.
    #[arg(long)]
    list: bool,
    /// Write to FILE instead of stdout (written completely or not at all).
    /// An existing file is kept unless --force: the file this writes is
    /// meant to be edited into one's own model.
    #[arg(short, long, value_name = "FILE")]
    output: Option<PathBuf>,
    /// Replace FILE when it exists.
    #[arg(long, requires = "output")]
    force: bool,
}

pub(crate) fn run(args: Args) -> Result<(), Error> {
    let Some(name) = args.family.as_deref() else {
        if args.output.is_some() {
            return Err(Error::Param(stitchkin::ParamError::general(
                "-o needs a family to write",
                Some(
                    "name one, e.g. `stitchkin new rocking-takeup -o my-machine.toml` (see `stitchkin new --list`)"
                        .into(),
                ),
            )));
        }
        return emit(list().as_bytes(), None);
    };
    let family = templates::get(name).map_err(Error::Param)?;
    if let Some(path) = &args.output
        && path.exists()
        && !args.force
    {
        return Err(Error::Param(stitchkin::ParamError::general(
            format!("`{}` exists, perhaps a model already edited", path.display()),
            Some("write to another file, or add --force to replace it".into()),
        )));
    }
    let text = templates::template(family);
    emit(text.as_bytes(), args.output.as_ref())
}

/// The families, one a line: name, the preset it starts from, the mechanism.
fn list() -> String {
    let mut out = String::from("family            from          mechanism\n");
    for f in templates::ALL {
        out += &format!("{:<17} {:<13} {}\n", f.name, f.preset, f.about);
    }
    out
}
