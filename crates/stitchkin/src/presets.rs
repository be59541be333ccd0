//! Machines of the seed papers, shipped inside the binary, and the starting
//! models made from them ([`templates`]).

pub mod templates;

use crate::error::{Input, ParamError, did_you_mean};

/// A shipped model file.
#[derive(Debug, Clone, Copy)]
pub struct Preset {
    pub name: &'static str,
    pub toml: &'static str,
}

/// The preset `stitchkin run` uses without a model.
pub const DEFAULT: &str = "mf7923d";

/// Every preset, in the order `stitchkin presets` lists them.
pub const ALL: &[Preset] = &[
    Preset {
        name: "needle876",
        toml: include_str!("../../../presets/needle876.toml"),
    },
    Preset {
        name: "overlock500",
        toml: include_str!("../../../presets/overlock500.toml"),
    },
    Preset {
        name: "altin-needle",
        toml: include_str!("../../../presets/altin-needle.toml"),
    },
    Preset {
        name: "altin504",
        toml: include_str!("../../../presets/altin504.toml"),
    },
    Preset {
        name: "mf7923d",
        toml: include_str!("../../../presets/mf7923d.toml"),
    },
    Preset {
        name: "takeup-lever",
        toml: include_str!("../../../presets/takeup-lever.toml"),
    },
    Preset {
        name: "lockstitch",
        toml: include_str!("../../../presets/lockstitch.toml"),
    },
];

/// A preset by name.
pub fn find(name: &str) -> Option<&'static Preset> {
    ALL.iter().find(|p| p.name == name)
}

/// A preset by name, or the error that names the closest preset and lists
/// them all.
pub fn get(name: &str) -> Result<&'static Preset, ParamError> {
    find(name).ok_or_else(|| {
        let hint = did_you_mean(name, ALL.iter().map(|p| p.name))
            .map(|s| format!(" (did you mean `{s}`?)"))
            .unwrap_or_default();
        ParamError::new(
            Input::Preset,
            format!("no preset named `{name}`{hint}"),
            Some(format!(
                "the presets are: {}",
                ALL.iter().map(|p| p.name).collect::<Vec<_>>().join(", ")
            )),
        )
    })
}
