//! Starting models for one's own machine: a shipped preset of each
//! mechanism family, renamed, under a header that says what to measure and
//! where to write it. The model below the header is the preset's, so a
//! template loads and runs before anything is changed.

use crate::error::{ParamError, did_you_mean};

/// The name a template gives the model (`[model] name`).
pub const MODEL_NAME: &str = "my-machine";

/// A mechanism family and the preset its template starts from.
#[derive(Debug, Clone, Copy)]
pub struct Family {
    /// What `stitchkin new` takes: `rocking-takeup`.
    pub name: &'static str,
    /// The mechanism in one line.
    pub about: &'static str,
    /// The preset the template is made from.
    pub preset: &'static str,
}

/// Every family, in the order `stitchkin new --list` lists them.
pub const ALL: &[Family] = &[
    Family {
        name: "rocking-takeup",
        about: "a rocking take-up arm driven by an eccentric, with take-up eyelets on the needle bar, \
                on a chain-stitch machine (stitch 407, three needles)",
        preset: "mf7923d",
    },
    Family {
        name: "lockstitch-lever",
        about: "a four-bar take-up lever with the needle bar on its crank pin and a rotary hook, \
                on a lockstitch machine (stitch 301)",
        preset: "lockstitch",
    },
    Family {
        name: "takeup-lever",
        about: "a four-bar take-up lever with eyelets on its lever and on its link's fork, the lever alone",
        preset: "takeup-lever",
    },
    Family {
        name: "needle-bar",
        about: "an eight-link needle bar mechanism whose stroke is set by moving a fixed hinge",
        preset: "needle876",
    },
    Family {
        name: "overlock",
        about: "an overedge machine (stitch 504): a straight-line needle mechanism, a lower and an upper looper \
                and their thread feed",
        preset: "altin504",
    },
];

/// A family by name, or the error that names the closest family and lists
/// them all.
pub fn get(name: &str) -> Result<&'static Family, ParamError> {
    ALL.iter().find(|f| f.name == name).ok_or_else(|| {
        let hint = did_you_mean(name, ALL.iter().map(|f| f.name))
            .map(|s| format!(" (did you mean `{s}`?)"))
            .unwrap_or_default();
        ParamError::general(
            format!("no mechanism family named `{name}`{hint}"),
            Some(format!(
                "the families are: {}",
                ALL.iter().map(|f| f.name).collect::<Vec<_>>().join(", ")
            )),
        )
    })
}

/// One value parameter of the preset, as the header lists it.
struct Listed {
    name: String,
    value: String,
    unit: String,
    range: Option<String>,
    label: String,
    illustrative: bool,
}

/// The value parameters of `toml` by kind: dimensions, settings, inputs,
/// and those without a `kind`.
fn parameters(toml: &str) -> [Vec<Listed>; 4] {
    let mut out: [Vec<Listed>; 4] = Default::default();
    let Ok(table) = toml.parse::<toml::Table>() else {
        return out;
    };
    let Some(params) = table.get("parameters").and_then(|p| p.as_table()) else {
        return out;
    };
    let number = |v: &toml::Value| match v {
        toml::Value::Integer(i) => Some(i.to_string()),
        toml::Value::Float(f) => Some(f.to_string()),
        _ => None,
    };
    for (name, p) in params {
        let Some(p) = p.as_table() else { continue };
        let Some(value) = p.get("value").and_then(number) else {
            continue;
        };
        let text = |key: &str| p.get(key).and_then(|v| v.as_str()).unwrap_or_default().to_string();
        let range = p
            .get("range")
            .and_then(|r| r.as_array())
            .and_then(|r| match r.as_slice() {
                [lo, hi] => Some(format!("{}..{}", number(lo)?, number(hi)?)),
                _ => None,
            });
        let slot = match text("kind").as_str() {
            "dimension" => 0,
            "setting" => 1,
            "input" => 2,
            _ => 3,
        };
        out[slot].push(Listed {
            name: name.clone(),
            value,
            unit: match text("unit").as_str() {
                "1" => String::new(),
                u => u.to_string(),
            },
            range,
            label: text("label"),
            illustrative: text("provenance") == "illustrative",
        });
    }
    out
}

/// The lines listing `params`, aligned, each as a comment.
fn list(params: &[Listed]) -> String {
    let width = params.iter().map(|p| p.name.len()).max().unwrap_or(0);
    let value_width = params
        .iter()
        .map(|p| p.value.len() + 1 + p.unit.len())
        .max()
        .unwrap_or(0);
    let mut out = String::new();
    for p in params {
        let mark = if p.illustrative { "*" } else { " " };
        let value = format!("{} {}", p.value, p.unit);
        let range = p.range.as_ref().map(|r| format!(" (range {r})")).unwrap_or_default();
        let line = format!(
            "#    {mark} {:<width$}  {:<value_width$}  {}{range}",
            p.name,
            value.trim_end(),
            p.label
        );
        out += line.trim_end();
        out.push('\n');
    }
    out
}

/// The model file `stitchkin new` writes for `family`: a header on adapting
/// it, then the preset's file with its `[model]` name and title made the
/// user's.
pub fn template(family: &Family) -> String {
    let preset = super::find(family.preset).expect("every family names a shipped preset");
    let [dimensions, settings, inputs, others] = parameters(preset.toml);
    let has_stitch = preset.toml.lines().any(|l| l.trim() == "[stitch]");
    let mut h = wrap(&format!("{MODEL_NAME}: {}", family.about));
    h += &format!(
        "#\n\
         # A starting model made by `stitchkin new {family}` from the shipped preset\n\
         # `{preset}`. It loads and runs as it is (give this file's name):\n\
         #\n\
         #   stitchkin check {MODEL_NAME}.toml     # loads it, solves a cycle, runs the physical checks\n\
         #   stitchkin run {MODEL_NAME}.toml       # every position over a main-shaft turn\n",
        family = family.name,
        preset = family.preset,
    );
    if has_stitch {
        h += &format!("#   stitchkin match {MODEL_NAME}.toml     # the take-up P against what the stitch needs, P'\n");
    }
    h += "#\n\
          # MAKING IT YOUR MACHINE. Every number below is the preset's until you\n\
          # change it. Lengths are in mm, angles in deg, forces in N; coordinates are\n\
          # in the frames the file describes (the preset's notes below say where each\n\
          # frame's origin is and which way its axes point).\n\
          #\n\
          # 1. Name it: `name` and `title` under [model].\n";
    if !dimensions.is_empty() {
        h += "# 2. Fixed dimensions (kind = \"dimension\": a part's size or place, made so):\n\
              #    measure each on your machine and write it as the parameter's `value`\n\
              #    in [parameters]. Those marked * are illustrative in the preset (no\n\
              #    source gives them): measure those first.\n";
        h += &list(&dimensions);
    }
    if !settings.is_empty() {
        h += "# 3. Machine settings (kind = \"setting\": what a technician adjusts): write\n\
              #    where your machine is set now as `value`, within `range`; widen the\n\
              #    range to what your machine allows. `stitchkin tune` adjusts these.\n";
        h += &list(&settings);
    } else {
        h += "# 3. Machine settings (kind = \"setting\"): this model has none yet. A\n\
              #    parameter your machine lets a technician adjust becomes one: give it\n\
              #    kind = \"setting\" and the `range` the machine allows, and `stitchkin\n\
              #    tune` can adjust it.\n";
    }
    if !inputs.is_empty() {
        h += "# 4. Job inputs (kind = \"input\": what the job brings: material, stitch,\n\
              #    thread): give your usual job's here; a run can change them without\n\
              #    editing the file (see `stitchkin run --help`).\n";
        h += &list(&inputs);
    } else {
        h += "# 4. Job inputs (kind = \"input\": the material, stitch or thread): this\n\
              #    model has none.\n";
    }
    if !others.is_empty() {
        h += "#    Without a kind (taken from what the model does with them):\n";
        h += &list(&others);
    }
    h += "# 5. Points written as coordinates rather than through a parameter are in\n\
          #    mm too: measure them the same way. Change a few numbers at a time and\n\
          #    run `stitchkin check` after each: an error names the line and what to\n\
          #    give.\n\
          # 6. Say where each number comes from: a parameter's `source` (\"measured\n\
          #    on my machine\") and `provenance`. The [model] notes and caveats are\n\
          #    the preset's: rewrite them as your measurements replace its numbers.\n\
          #\n\
          # docs/model-format.md describes every table of this file.\n\
          #\n\
          # ----------------------------------------------------------------------------\n\
          # The preset's own notes follow, as shipped.\n\
          #\n";
    h + &renamed(preset.toml, family)
}

/// `text` as comment lines of at most 78 characters.
fn wrap(text: &str) -> String {
    let mut out = String::new();
    let mut line = String::from("#");
    for word in text.split_whitespace() {
        if line.len() + 1 + word.len() > 78 && line.len() > 1 {
            out += &line;
            out.push('\n');
            line = String::from("#");
        }
        line.push(' ');
        line += word;
    }
    out + &line + "\n"
}

/// `toml` with the `[model]` table's `name` and `title` made the user's.
fn renamed(toml: &str, family: &Family) -> String {
    let title = format!("My machine (started from the preset {})", family.preset);
    let mut out = String::with_capacity(toml.len() + 200);
    let mut in_model = false;
    let mut titled = false;
    for line in toml.split_inclusive('\n') {
        let trimmed = line.trim_start();
        if trimmed.starts_with('[') {
            if in_model && !titled {
                // A preset without a title: give it one at the end of [model].
                out += &format!("title = \"{title}\"\n");
                titled = true;
            }
            in_model = trimmed.trim_end() == "[model]";
        }
        let key = trimmed.split('=').next().unwrap_or("").trim();
        if in_model && trimmed.contains('=') && key == "name" {
            out += &format!("name = \"{MODEL_NAME}\"\n");
        } else if in_model && trimmed.contains('=') && key == "title" {
            out += &format!("title = \"{title}\"\n");
            titled = true;
        } else {
            out += line;
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::Model;

    /// Every template loads, is named the user's, keeps the preset's
    /// parameters and their defaults, and solves a cycle.
    #[test]
    fn every_template_loads_and_runs_as_its_preset() {
        for f in ALL {
            let text = template(f);
            let model = Model::from_toml_str(&text, "template")
                .unwrap_or_else(|e| panic!("the {} template does not load: {e}", f.name));
            let preset = Model::preset(f.preset).unwrap();
            assert_eq!(model.name(), MODEL_NAME, "{}", f.name);
            assert!(
                model.title().unwrap_or_default().starts_with("My machine ("),
                "{}: {:?}",
                f.name,
                model.title()
            );
            assert_eq!(model.defaults().values, preset.defaults().values, "{}", f.name);
            model
                .machine::<f64>(&model.defaults())
                .unwrap_or_else(|e| panic!("the {} template does not solve: {e}", f.name));
            // The header lists every value parameter by kind, each once.
            let [d, s, i, o] = parameters(crate::presets::find(f.preset).unwrap().toml);
            assert!(o.is_empty(), "{}: parameters without a kind", f.name);
            assert!(!d.is_empty() && d.len() + s.len() + i.len() > 3, "{}", f.name);
            for p in d.iter().chain(&s).chain(&i) {
                assert!(
                    text.lines()
                        .take_while(|l| l.starts_with('#'))
                        .any(|l| l.split_whitespace().any(|w| w == p.name)),
                    "{}: the header does not list `{}`",
                    f.name,
                    p.name
                );
            }
            assert!(text.starts_with(&format!("# {MODEL_NAME}: ")));
            assert!(text.contains(&format!("stitchkin new {}", f.name)));
        }
    }

    #[test]
    fn a_misspelt_family_is_named_with_the_closest() {
        let e = get("rocking-takup").unwrap_err();
        assert!(e.message.contains("did you mean `rocking-takeup`"), "{}", e.message);
        assert!(e.help.unwrap().contains("needle-bar"));
        assert!(get("needle-bar").is_ok());
    }

    #[test]
    fn only_the_model_tables_name_and_title_change() {
        let f = get("takeup-lever").unwrap();
        let preset = crate::presets::find(f.preset).unwrap().toml;
        let body = renamed(preset, f);
        let changed: Vec<_> = preset.lines().zip(body.lines()).filter(|(a, b)| a != b).collect();
        assert_eq!(changed.len(), 2, "{changed:?}");
        assert_eq!(preset.lines().count(), body.lines().count());
    }
}
