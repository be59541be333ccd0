//! `stitchkin draw`, run as a user would.

use super::{fails, ok, scratch};

#[test]
fn draw_writes_svg_to_stdout_or_a_file() {
    let (svg, _) = ok(&["draw", "--preset", "needle876", "--phi", "120"]);
    assert!(svg.starts_with("<svg ") && svg.trim_end().ends_with("</svg>"));
    assert!(svg.contains(">needle876: mechanism at φ = 120°</text>") && !svg.contains("NaN"));
    assert_eq!(svg.matches("class=\"link ").count(), 6);
    assert_eq!(svg.matches("class=\"pivot\"").count(), 3);
    // The default preset, spatial, in the isometric view and a frame's plane.
    let (svg, _) = ok(&["draw", "--view", "iso", "--dimensions"]);
    assert!(svg.contains("isometric") && svg.matches("class=\"thread\"").count() == 6);
    assert!(svg.contains(">l_AB = "), "the RSSR rod is dimensioned");
    let (svg, _) = ok(&["draw", "--view", "uvw", "--phi", "180"]);
    assert!(svg.contains("the xy-plane of frame `uvw`") && svg.contains("class=\"guide pin free\""));
    let d = scratch("draw");
    let file = d.join("n876.svg");
    let (out, said) = ok(&[
        "draw",
        "--preset",
        "needle876",
        "--set",
        "alpha=30",
        "--trajectories",
        "G,E",
        "-o",
        file.to_str().unwrap(),
    ]);
    assert!(out.is_empty());
    assert!(
        said.contains("wrote ") && said.contains(file.to_str().unwrap()),
        "{said}"
    );
    let svg = std::fs::read_to_string(&file).unwrap();
    assert_eq!(svg.matches("class=\"trajectory\"").count(), 2);
    // Nothing but the file is left in the folder (the write is atomic).
    assert_eq!(std::fs::read_dir(&d).unwrap().count(), 1);
}

#[test]
fn draw_animates_one_turn() {
    let (svg, _) = ok(&[
        "draw",
        "--preset",
        "takeup-lever",
        "--animate",
        "--frames",
        "12",
        "--duration",
        "2.5",
        "--trajectories",
        "P5",
    ]);
    assert!(
        svg.contains("data-frames=\"12\"")
            && svg.contains("dur=\"2.5s\"")
            && svg.contains("repeatCount=\"indefinite\"")
    );
    let i = svg.find("class=\"thread\"").unwrap();
    let anim = &svg[i..][svg[i..].find("<animate ").unwrap()..];
    let values = &anim[anim.find("values=\"").unwrap() + 8..];
    assert_eq!(
        values[..values.find('"').unwrap()].split(';').count(),
        13,
        "12 frames and back to the first"
    );
    let (svg, _) = ok(&["draw", "--preset", "altin504", "--animate"]);
    assert!(svg.contains("data-frames=\"72\"") && svg.contains("dur=\"4s\""));
}

#[test]
fn draw_rejects_bad_input_with_the_fix() {
    let e = fails(&["draw", "--animate", "--frames", "1"]);
    assert!(e.contains("--frames") && e.contains("at least 2"), "{e}");
    let e = fails(&["draw", "--animate", "--duration", "0"]);
    assert!(e.contains("--duration") && e.contains("seconds"), "{e}");
    let e = fails(&["draw", "--frames", "24"]);
    assert!(e.contains("--animate"), "{e}");
    let e = fails(&["draw", "--view", "uwv"]);
    assert!(
        e.contains("no frame `uwv`") && e.contains("uvw") && e.contains("iso"),
        "{e}"
    );
    let e = fails(&["draw", "--preset", "needle876", "--trajectories", "G,Q"]);
    assert!(e.contains("no point `Q`") && e.contains("--trajectories"), "{e}");
    let e = fails(&["draw", "--phi", "nan"]);
    assert!(e.contains("--phi"), "{e}");
    let e = fails(&["draw", "--phi", "abc"]);
    assert!(e.contains("--phi"), "{e}");
    // A position where the mechanism cannot be assembled: the group, φ and the fix.
    let d = scratch("draw-jam");
    let model = d.join("jam.toml");
    std::fs::write(
        &model,
        "[model]\nname = \"jam\"\n[points]\nO1 = [0, 0]\nO2 = [60, 0]\n[[drivers]]\ntype = \"crank\"\ncenter = \"O1\"\nout = \"A\"\nradius = 35\n\
         [[groups]]\ntype = \"rrr\"\nname = \"coupler_rocker\"\njoints = [\"A\", \"O2\"]\nlengths = [50, 40]\nout = \"B\"\nbranch = \"left\"\n",
    )
    .unwrap();
    ok(&["draw", model.to_str().unwrap(), "--phi", "10"]);
    let e = fails(&["draw", model.to_str().unwrap(), "--phi", "180"]);
    assert!(
        e.contains("no assembly at φ = 180.000°") && e.contains("coupler_rocker") && e.contains("check the dimensions"),
        "{e}"
    );
    let e = fails(&["draw", model.to_str().unwrap(), "--animate"]);
    assert!(e.contains("no assembly") && e.contains("coupler_rocker"), "{e}");
}

#[test]
fn draw_writes_a_still_png_but_not_an_animated_one() {
    let dir = scratch("draw-png");
    let png = dir.join("needle876.png");
    ok(&[
        "draw",
        "--preset",
        "needle876",
        "--phi",
        "90",
        "-o",
        png.to_str().unwrap(),
    ]);
    let bytes = std::fs::read(&png).unwrap();
    assert_eq!(&bytes[..8], b"\x89PNG\r\n\x1a\n");
    assert_eq!(
        u32::from_be_bytes(bytes[16..20].try_into().unwrap()),
        1800,
        "900 px drawing at 2 px per unit"
    );
    let anim = dir.join("anim.png");
    let err = fails(&[
        "draw",
        "--preset",
        "needle876",
        "--animate",
        "-o",
        anim.to_str().unwrap(),
    ]);
    assert!(err.contains("animation cannot be written as PNG"), "{err}");
    assert!(!anim.exists());
}

#[test]
fn draw_picks_the_view_that_suits_the_model() {
    let (planar, _) = ok(&["draw", "--preset", "needle876"]);
    assert!(planar.contains("world xy-plane"), "a planar model in its plane");
    let (spatial, _) = ok(&["draw", "--preset", "mf7923d"]);
    assert!(spatial.contains("isometric"), "a spatial model isometric");
}

#[test]
fn draw_shows_a_cam_with_its_profile_pitch_curve_and_roller() {
    let model = format!("{}/../../examples/cam-rocking-roller.toml", env!("CARGO_MANIFEST_DIR"));
    let (svg, _) = ok(&["draw", &model, "--phi", "40"]);
    for class in ["cam-profile", "cam-pitch", "cam-roller"] {
        assert_eq!(svg.matches(&format!("class=\"{class}\"")).count(), 1, "{class}");
    }
    assert!(!svg.contains("NaN"));
    let groove = format!(
        "{}/../../examples/cam-translating-groove.toml",
        env!("CARGO_MANIFEST_DIR")
    );
    let (svg, _) = ok(&["draw", &groove, "--animate", "--frames", "8"]);
    assert!(svg.contains("class=\"cam-groove\"") && svg.contains("<animate "));
}

#[test]
fn draw_shows_a_rocking_flat_face_on_its_cam() {
    let rocking = std::fs::read_to_string(format!(
        "{}/../../examples/cam-rocking-roller.toml",
        env!("CARGO_MANIFEST_DIR")
    ))
    .unwrap();
    let flat = rocking
        .replace("contact = \"roller\"", "contact = \"flat\"\noffset = 3")
        .replace("roller_radius = \"r_r\"\n", "");
    let dir = scratch("draw-flat-face");
    let model = dir.join("flat.toml");
    std::fs::write(&model, flat).unwrap();
    let (svg, _) = ok(&["draw", model.to_str().unwrap(), "--animate", "--frames", "8"]);
    assert_eq!(svg.matches("class=\"cam-face\"").count(), 1);
    assert!(!svg.contains("class=\"cam-roller\"") && !svg.contains("NaN"));
}
