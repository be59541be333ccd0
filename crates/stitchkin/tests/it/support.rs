//! Helpers several test files share.

use stitchkin::model::Model;

/// The preset `name` with its stitch's regulator window assumed, the last
/// 60° before each thread's stitch is pulled tight (`regulator = {
/// width_deg = 60 }`, the accounting without thread physics), instead of
/// computed from the thread's tension: the stitch process's and the
/// kinematic match's own figures, which the computed window moves with
/// every setting.
pub fn assumed_window(name: &str) -> Model {
    Model::from_toml_str(&assumed_text(name), &format!("preset:{name} (window assumed)")).unwrap()
}

/// The text of [`assumed_window`].
pub fn assumed_text(name: &str) -> String {
    let text = stitchkin::presets::find(name).expect("a preset").toml;
    let text = text.replacen("\n[stitch]\n", "\n[stitch]\nregulator = { width_deg = 60 }\n", 1);
    assert!(text.contains("width_deg = 60 }"), "{name} has a [stitch] table");
    text
}
