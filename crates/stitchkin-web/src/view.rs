//! The mechanism drawing as the page asks for it: a view by name (`auto`
//! is the model's best, [`View::default_for`]), a φ, still or animated.

use serde_json::{Value, json};
use stitchkin::error::Error;
use stitchkin::model::{Model, Params};
use stitchkin::output::drawing::{DrawOptions, View};

/// The page's view names, `auto` first, with labels for the menu.
pub fn names(model: &Model) -> Vec<Value> {
    let auto = View::default_for(model);
    let mut out = vec![json!({ "name": "auto", "label": format!("auto ({})", auto.name()) })];
    for v in View::choices(model) {
        let label = match v.as_str() {
            "xy" | "xz" | "yz" => format!("world {v}-plane"),
            "iso" => "isometric".to_string(),
            frame => format!("frame {frame}"),
        };
        out.push(json!({ "name": v, "label": label }));
    }
    out
}

/// What `/api/drawing` asks for (checked there).
#[derive(Debug, Clone)]
pub struct DrawingRequest {
    pub phi_deg: f64,
    /// `auto` or a name of [`names`].
    pub view: String,
    pub animate: bool,
    pub trajectories: Vec<String>,
}

/// The drawing, or the library's error (an unknown view or point is a
/// parameter error, so a 400; no assembly a 422).
pub fn render(model: &Model, params: &Params, r: &DrawingRequest) -> Result<String, Error> {
    let view = match r.view.as_str() {
        "auto" => View::default_for(model),
        name => {
            let choices = View::choices(model);
            if !choices.iter().any(|c| c == name) {
                return Err(Error::Param(stitchkin::error::ParamError::general(
                    format!("view = `{name}` is not a view of this model"),
                    Some(format!("views are auto, {}", choices.join(", "))),
                )));
            }
            View::parse(name)?
        }
    };
    let opts = DrawOptions {
        phi_deg: r.phi_deg,
        view,
        animate: r.animate,
        trajectories: r.trajectories.clone(),
        ..Default::default()
    };
    stitchkin::jobs::drawing::render(model, params, &opts)
}
