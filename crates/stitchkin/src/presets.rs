//! Machines of the seed papers, shipped inside the binary.

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
