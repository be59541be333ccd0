//! docs/looper-thread-feeds.md: each seed 004 variant's row is what the
//! binary computes for its model in examples/seed004-variants/: the match
//! of the synthesised lift with the Altin lower thread's P′, the cam checks
//! and the speed up to which a spring holds its follower.

use super::ok;

/// The number after `key` in `text`, up to the next space, comma or `°`.
fn number_after(text: &str, key: &str) -> f64 {
    let at = text.find(key).unwrap_or_else(|| panic!("no `{key}` in:\n{text}")) + key.len();
    let tail = text[at..].trim_start();
    let end = tail
        .find(|c: char| !(c.is_ascii_digit() || c == '.' || c == '-'))
        .unwrap_or(tail.len());
    tail[..end]
        .parse()
        .unwrap_or_else(|_| panic!("no number after `{key}` in:\n{text}"))
}

#[test]
fn the_variants_table_is_what_the_models_give() {
    let root = format!("{}/../..", env!("CARGO_MANIFEST_DIR"));
    let docs = std::fs::read_to_string(format!("{root}/docs/looper-thread-feeds.md")).unwrap();
    let target = format!("{root}/examples/altin504-lower-pprime.csv");
    for (file, group, spring) in [
        ("variant1.toml", "pusher", false),
        ("variant2.toml", "pusher", false),
        ("variant3.toml", "pusher", false),
        ("variant4.toml", "pusher", false),
        ("variant5.toml", "feed_arm", true),
        ("variant6.toml", "feed_arm", false),
    ] {
        let model = format!("{root}/examples/seed004-variants/{file}");
        let (o, e) = ok(&[
            "cam",
            "--follower",
            group,
            "--path",
            "lower",
            "--target",
            &target,
            "--smooth",
            "20",
            "--format",
            "table",
            &model,
        ]);
        let cam = format!("{o}{e}");
        let score = number_after(&cam, "tolerance 0.5 mm): score");
        let rms = number_after(&cam, ", RMS");
        let (o, e) = ok(&["run", &model, "--step", "90"]);
        let run = format!("{o}{e}");
        let pressure = number_after(&run, "cam_pressure");
        let limit = number_after(&run, "(allowed ≤");
        let radius = number_after(&run, "cam_curvature");
        let row = docs
            .lines()
            .find(|l| l.starts_with("| variant") && l.contains(&format!("`{file}`")))
            .unwrap_or_else(|| panic!("no row for {file} in docs/looper-thread-feeds.md"));
        let want = format!("| {score:.1} | {rms:.3} | {pressure:.1} ({limit:.0}) | {radius:.2} |");
        assert!(
            row.contains(&want),
            "{file}: the docs row\n{row}\ndoes not hold the computed\n{want}"
        );
        if spring {
            let rpm = number_after(&run, "holds it up to");
            assert!(
                row.contains(&format!("| {rpm:.0} (")),
                "{file}: the docs row\n{row}\nlacks the spring's {rpm} rpm"
            );
        }
        // Conclusion 7: the cam feeds the needed law closer than the base (90.3).
        assert!(score > 90.3 && row.ends_with("| yes |"), "{file}: {row}");
    }
}
