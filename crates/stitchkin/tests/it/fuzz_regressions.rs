//! Regression tests from fuzzing model loading (`fuzz/`, target `load_model`)
//! and hand-written nasty inputs: every input must load or fail with an
//! error, never panic, and a model that loads must run a short cycle without
//! panicking. Error messages are formatted too (their `Display` must not
//! panic either).

use stitchkin::eval::{CycleOptions, run_cycle};
use stitchkin::model::Model;

/// What the fuzz target does: load, then run a cycle at a 45° step.
/// Returns whether the model loaded; the cycle may fail, but not panic.
fn exercise(text: &str) -> Result<Model, String> {
    match Model::from_toml_str(text, "fuzz.toml") {
        Ok(model) => {
            let opts = CycleOptions {
                step_deg: 45.0,
                ..Default::default()
            };
            if let Err(e) = run_cycle(&model, &model.defaults(), &opts) {
                assert!(!e.to_string().is_empty());
            }
            Ok(model)
        }
        Err(e) => {
            let msg = e.to_string();
            assert!(!msg.is_empty());
            Err(msg)
        }
    }
}

#[track_caller]
fn rejects(text: &str) -> String {
    match exercise(text) {
        Ok(_) => panic!("expected an error for:\n{text}"),
        Err(msg) => msg,
    }
}

#[track_caller]
fn loads(text: &str) -> Model {
    match exercise(text) {
        Ok(m) => m,
        Err(msg) => panic!("expected the model to load, got: {msg}\n{text}"),
    }
}

/// A small valid mechanism (crank + RRR dyad) to append groups to.
const BASE: &str = r#"
[model]
name = "base"

[points]
O = [0, 0]
C = [20, 5]

[[drivers]]
type = "crank"
center = "O"
out = "A"
radius = 5

[[groups]]
type = "rrr"
joints = ["A", "C"]
lengths = [20, 10]
out = "B"
branch = "left"
"#;

fn with_params(params: &str) -> String {
    format!("[model]\nname = \"p\"\n\n[parameters]\n{params}\n")
}

// ---- sanity ------------------------------------------------------------------

#[test]
fn base_model_loads_and_runs() {
    loads(BASE);
}

#[test]
fn empty_and_garbage_inputs_are_errors() {
    rejects("");
    rejects("\n\n# only a comment\n");
    rejects("[model]");
    rejects("[model]\nname = 1");
    rejects("[[model]]\nname = \"x\"");
    rejects("\u{feff}[model]\nname = \"x\"\n[[groups]]\ntype = ");
    rejects("[model]\nname = \"x\"\n[[groups]]\ntype = \"\"");
    rejects("[model]\nname = \"x\"\n[[groups]]\ntype = \"rrr\"");
    rejects("[model]\nname = \"x\"\n[[groups]]\n");
    rejects("[model]\nname = \"x\"\nname = \"y\"");
    rejects("[model]\nname = \"x\"\n[model]\nname = \"y\"");
    rejects("a = \"\u{1F600}\"\n\"\u{e9}\" = 1");
    rejects("\0\0\0");
}

#[test]
fn a_name_only_model_loads() {
    let m = loads("[model]\nname = \"\"");
    assert!(m.point_names().is_empty());
    loads("[model]\nname = \"\u{e9}\u{1F600}\"\ntitle = \"\"\nnotes = \"\"");
}

// ---- numbers -----------------------------------------------------------------

#[test]
fn non_finite_numbers_are_rejected() {
    for v in ["nan", "inf", "-inf", "+nan", "-nan", "+inf"] {
        rejects(&with_params(&format!("a = {{ value = {v}, unit = \"mm\" }}")));
        rejects(&with_params(&format!(
            "a = {{ value = 1, unit = \"mm\", range = [{v}, 2] }}"
        )));
        rejects(&BASE.replace("radius = 5", &format!("radius = {v}")));
        rejects(&BASE.replace("C = [20, 5]", &format!("C = [20, {v}]")));
        rejects(&BASE.replace("lengths = [20, 10]", &format!("lengths = [20, {v}]")));
        rejects(&BASE.replace("radius = 5", &format!("radius = 5\nspeed = {v}")));
    }
}

#[test]
fn non_finite_cycle_settings_do_not_panic() {
    for v in ["nan", "inf", "-inf", "1e308", "-1e308", "5e-324"] {
        let _ = exercise(&BASE.replace("name = \"base\"", &format!("name = \"base\"\nphi_start_deg = {v}")));
        let _ = exercise(&BASE.replace("name = \"base\"", &format!("name = \"base\"\nrpm = {v}")));
    }
}

#[test]
fn huge_and_tiny_numbers_do_not_panic() {
    for v in [
        "1e308",
        "-1e308",
        "1.7976931348623157e308",
        "5e-324",
        "1e-300",
        "0.0",
        "-0.0",
    ] {
        let _ = exercise(&BASE.replace("radius = 5", &format!("radius = {v}")));
        let _ = exercise(&BASE.replace("C = [20, 5]", &format!("C = [{v}, {v}]")));
        let _ = exercise(&BASE.replace("lengths = [20, 10]", &format!("lengths = [{v}, {v}]")));
        let _ = exercise(&BASE.replace("radius = 5", &format!("radius = 5\nspeed = {v}")));
        let _ = exercise(&BASE.replace("radius = 5", &format!("radius = 5\nphase_deg = {v}")));
        let _ = exercise(&BASE.replace("radius = 5", &format!("radius = \"{v} * 1e10\"")));
        let _ = exercise(&with_params(&format!(
            "a = {{ value = {v}, unit = \"mm\", range = [{v}, {v}] }}"
        )));
    }
    // Overflow to infinity inside an expression is caught when resolving.
    rejects(&BASE.replace("radius = 5", "radius = \"1e308 * 10\""));
    rejects(&BASE.replace("radius = 5", "radius = \"1e308 + 1e308\""));
}

#[test]
fn zero_and_negative_lengths_are_rejected() {
    rejects(&BASE.replace("radius = 5", "radius = 0"));
    rejects(&BASE.replace("radius = 5", "radius = -5"));
    rejects(&BASE.replace("lengths = [20, 10]", "lengths = [0, 10]"));
    rejects(&BASE.replace("lengths = [20, 10]", "lengths = [20, -0.0]"));
    rejects(&BASE.replace("radius = 5", "radius = 5\nspeed = 0"));
}

#[test]
fn coincident_points_do_not_panic() {
    // Zero-length base lines and zero-length links between equal points.
    let _ = exercise(&BASE.replace("C = [20, 5]", "C = [0, 0]"));
    let _ = exercise(&BASE.replace("joints = [\"A\", \"C\"]", "joints = [\"A\", \"A\"]"));
    let _ = exercise(&BASE.replace("joints = [\"A\", \"C\"]", "joints = [\"C\", \"C\"]"));
    let _ = exercise(&format!(
        "{BASE}\n[[groups]]\ntype = \"rigid_point\"\nbase = [\"B\", \"B\"]\ndistance = 3\nout = \"R\"\n"
    ));
    let _ = exercise(&format!(
        "{BASE}\n[[groups]]\ntype = \"rigid_point_3d\"\nframe = [\"B\", \"B\", \"B\"]\nat = [1, 2, 3]\nout = \"R\"\n"
    ));
    let _ = exercise(&format!(
        "{BASE}\n[[groups]]\ntype = \"rpr\"\nfrom = \"C\"\npivot = \"C\"\ndistance = 3\nout = \"R\"\n"
    ));
    let _ = exercise(&format!(
        "{BASE}\n[[groups]]\ntype = \"rrp\"\nfrom = \"B\"\nlength = 5\nthrough = \"C\"\ntoward = \"C\"\nout = \"S\"\nbranch = \"forward\"\n"
    ));
    let _ = exercise(&format!(
        "{BASE}\n[[groups]]\ntype = \"point_on_line\"\nfrom = \"B\"\nlength = 5\nthrough = \"C\"\ntoward = \"C\"\nout = \"S\"\nbranch = \"forward\"\n"
    ));
    let _ = exercise(&format!(
        "{BASE}\n[[measures]]\ntype = \"line_deviation\"\nname = \"d\"\npoint = \"B\"\nthrough = \"C\"\ntoward = \"C\"\n"
    ));
    let _ = exercise(&format!(
        "{BASE}\n[[measures]]\ntype = \"line_deviation\"\nname = \"d\"\npoint = \"B\"\nthrough = \"C\"\ntoward = \"C\"\nplane = \"none\"\n"
    ));
}

#[test]
fn zero_direction_vectors_are_errors() {
    rejects(&BASE.replace("radius = 5", "radius = 5\naxis = [0, 0, 0]"));
    rejects(&BASE.replace("radius = 5", "radius = 5\nzero_dir = [0, 0, 0]"));
    rejects(&BASE.replace("radius = 5", "radius = 5\nzero_dir = \"z\""));
    rejects(&BASE.replace("radius = 5", "radius = 5\naxis = [1]"));
    rejects(&BASE.replace("radius = 5", "radius = 5\naxis = []"));
    rejects(&BASE.replace("radius = 5", "radius = 5\naxis = \"w\""));
    rejects(&BASE.replace("radius = 5", "radius = 5\naxis = \"--z\""));
    rejects(&BASE.replace("radius = 5", "radius = 5\naxis = \"\""));
    let _ = exercise(&BASE.replace("radius = 5", "radius = 5\naxis = [1e-300, 0, 0]"));
    let _ = exercise(&BASE.replace("radius = 5", "radius = 5\naxis = [1e300, 1e300, 1e300]"));
}

// ---- expressions -------------------------------------------------------------

#[test]
fn deeply_nested_expressions_are_errors() {
    let deep = "(".repeat(10_000) + "1" + &")".repeat(10_000);
    rejects(&BASE.replace("radius = 5", &format!("radius = \"{deep}\"")));
    let neg = "-".repeat(10_000) + "1";
    rejects(&BASE.replace("radius = 5", &format!("radius = \"{neg}\"")));
    let calls = "abs(".repeat(5_000) + "1" + &")".repeat(5_000);
    rejects(&BASE.replace("radius = 5", &format!("radius = \"{calls}\"")));
    // Long flat sums within reach of the recursion (see
    // `long_flat_expressions_do_not_overflow_the_stack` for longer ones).
    let flat = vec!["1"; 200].join(" + ");
    loads(&BASE.replace("radius = 5", &format!("radius = \"{flat} - 195\"")));
    let flat = vec!["a"; 200].join(" * ");
    let _ = exercise(&with_params(&format!(
        "a = {{ value = 1, unit = \"1\" }}\nb = {{ expr = \"{flat}\", unit = \"1\" }}"
    )));
    // Nested within the limit.
    let ok = "(".repeat(20) + "5" + &")".repeat(20);
    loads(&BASE.replace("radius = 5", &format!("radius = \"{ok}\"")));
}

#[test]
fn malformed_expressions_are_errors() {
    for e in [
        "",
        " ",
        "1 +",
        "(1",
        "1)",
        "1 2",
        "()",
        "abs()",
        "abs(1,)",
        "atan2(1)",
        "max(1,2,3)",
        "sin",
        "sin(",
        "foo(1)",
        "1 $ 2",
        "1e",
        "1e+",
        "..",
        "1.2.3",
        "^2",
        "2^",
        "2^0.5",
        "2^x",
        "2^17",
        "2^-17",
        "2^1e3",
        "\u{e9}",
        "a\u{e9}",
        "\u{1F600}",
        "1 + \u{1F600}",
        "unknown",
        "pi(1)",
        "1,2",
        "--",
        "1e99999",
    ] {
        rejects(&BASE.replace("radius = 5", &format!("radius = \"{e}\"")));
    }
}

#[test]
fn expression_errors_point_into_escaped_and_literal_strings() {
    // The error span is narrowed into plain strings; escapes, literal strings
    // and multi-line strings must not confuse it.
    for v in [
        r#""1 + \u00e9""#,
        r#"'1 + bogus'"#,
        r#"'''1 + bogus'''"#,
        "\"\"\"\n1 + bogus\"\"\"",
        r#""\"bogus\"""#,
        r#""1 + bogus\t""#,
        "\"\u{e9}\u{e9} + bogus\"",
        "'\u{e9}'",
    ] {
        rejects(&BASE.replace("radius = 5", &format!("radius = {v}")));
    }
}

// The next five tests reproduced library bugs found while writing this
// module (not by the fuzzer, whose 8 KB inputs and random mutations did not
// reach them); they panicked or aborted before commit ab22bc4 ("bounded
// expressions"), which caps unit exponents at ±12 and expressions at 512
// tokens.

/// A flat chain `1 + 1 + … + 1` parses into a left-deep tree one level per
/// operator, and `Expr::dimension` (also `eval`, `params`, drop) recurse once
/// per term. Before the token cap this overflowed the stack (abort, at
/// `model/expr.rs:372`, the `Add`/`Sub` arm of `dimension`): from about 4 000
/// terms (an 8 KB file) in a debug build on an 8 MiB main thread
/// (`stitchkin check`), about 50 000 in a release build.
#[test]
fn long_flat_expressions_do_not_overflow_the_stack() {
    for (op, n) in [("+", 5_000), ("*", 5_000), ("-", 50_000)] {
        let text = format!(
            "[model]\nname = \"x\"\n\n[parameters]\na = {{ expr = \"{}\", unit = \"1\" }}\n",
            vec!["1"; n].join(op)
        );
        // Same stack as a program's main thread, where `stitchkin` runs.
        let t = std::thread::Builder::new()
            .stack_size(8 << 20)
            .spawn(move || exercise(&text).is_ok())
            .unwrap();
        let _ = t.join().expect("loading must not panic");
    }
}

// Dimensions are powers of mm and deg held in `i8`: powers and products
// beyond ±127 used to overflow (debug builds panicked, release builds
// wrapped around and could accept e.g. mm^256 as a pure number).

/// Was `attempt to multiply with overflow` at `model/expr.rs:391:43`
/// (dimension of `Expr::Pow`): mm^16 raised to 16 = mm^256.
#[test]
fn power_of_a_power_overflowing_the_unit_exponent_is_an_error() {
    rejects(&with_params(
        "a = { value = 2, unit = \"mm\" }\nb = { expr = \"(a^16)^16\", unit = \"mm\" }",
    ));
    rejects(&with_params(
        "a = { value = 2, unit = \"mm\" }\nb = { expr = \"(a^16)^16\", unit = \"1\" }",
    ));
}

/// Was `attempt to multiply with overflow` at `model/expr.rs:391:73`
/// (angle exponent of `Expr::Pow`): deg^-256.
#[test]
fn negative_power_of_a_power_overflowing_the_unit_exponent_is_an_error() {
    rejects(&with_params(
        "a = { value = 2, unit = \"deg\" }\nb = { expr = \"(a^-16)^16\", unit = \"deg\" }",
    ));
}

/// Was `attempt to add with overflow` at `model/expr.rs:25:23` (`Dim::mul`):
/// 128 factors of mm.
#[test]
fn long_product_overflowing_the_unit_exponent_is_an_error() {
    let product = vec!["a"; 128].join("*");
    rejects(&with_params(&format!(
        "a = {{ value = 1, unit = \"mm\" }}\nb = {{ expr = \"{product}\", unit = \"mm\" }}"
    )));
    rejects(&with_params(&format!(
        "a = {{ value = 1, unit = \"mm\" }}\nb = {{ expr = \"{product}\", unit = \"1\" }}"
    )));
}

/// Was `attempt to subtract with overflow` at `model/expr.rs:28:23`
/// (`Dim::div`): mm^-129.
#[test]
fn long_quotient_overflowing_the_unit_exponent_is_an_error() {
    let quotient = vec!["a"; 129].join("/");
    rejects(&with_params(&format!(
        "a = {{ value = 1, unit = \"mm\" }}\nb = {{ expr = \"1/{quotient}\", unit = \"mm\" }}"
    )));
}

#[test]
fn unit_exponents_within_range_are_checked() {
    loads(&with_params(
        "a = { value = 2, unit = \"mm\" }\nb = { expr = \"sqrt((a^4)^2) / a^3\", unit = \"mm\" }",
    ));
    rejects(&with_params(
        "a = { value = 2, unit = \"mm\" }\nb = { expr = \"(a^16)^2\", unit = \"mm\" }",
    ));
    let product = vec!["a"; 127].join("*");
    rejects(&with_params(&format!(
        "a = {{ value = 1, unit = \"mm\" }}\nb = {{ expr = \"{product}\", unit = \"mm\" }}"
    )));
}

#[test]
fn out_of_domain_functions_are_errors() {
    for e in [
        "sqrt(-1)",
        "acos(2) * 0 + 1",
        "asin(-2) * 0 + 1",
        "1/0",
        "0/0 + 1",
        "tan(90) * 0 + 1",
    ] {
        let _ = exercise(&BASE.replace("radius = 5", &format!("radius = \"{e}\"")));
    }
    rejects(&BASE.replace("radius = 5", "radius = \"sqrt(-1)\""));
    rejects(&BASE.replace("radius = 5", "radius = \"1/0\""));
    rejects(&with_params(
        "a = { value = 0, unit = \"1\" }\nb = { expr = \"1/a\", unit = \"1\" }",
    ));
}

// ---- parameters ------------------------------------------------------------------

#[test]
fn bad_parameters_are_errors() {
    rejects(&with_params("\"\" = { value = 1, unit = \"mm\" }"));
    rejects(&with_params("\"\u{e9}\" = { value = 1, unit = \"mm\" }"));
    rejects(&with_params("\"1a\" = { value = 1, unit = \"mm\" }"));
    rejects(&with_params("\"a b\" = { value = 1, unit = \"mm\" }"));
    rejects(&with_params("sin = { value = 1, unit = \"mm\" }"));
    rejects(&with_params("pi = { value = 1, unit = \"1\" }"));
    rejects(&with_params("a = { value = 1 }"));
    rejects(&with_params("a = { unit = \"mm\" }"));
    rejects(&with_params("a = { value = 1, unit = \"cm\" }"));
    rejects(&with_params("a = { value = 1, unit = \"\" }"));
    rejects(&with_params("a = { value = 1, expr = \"2\", unit = \"mm\" }"));
    rejects(&with_params("a = { value = 5, unit = \"mm\", range = [0, 1] }"));
    rejects(&with_params("a = { value = 5, unit = \"mm\", range = [9, 1] }"));
    rejects(&with_params("a = { value = 5, unit = \"mm\", range = [1] }"));
    rejects(&with_params("a = { value = 5, unit = \"mm\", range = [1, 2, 3] }"));
    rejects(&with_params("a = { expr = \"1\", unit = \"mm\", range = [0, 2] }"));
    rejects(&with_params(
        "a = { value = 1, unit = \"mm\", provenance = \"guessed\" }",
    ));
    rejects(&with_params("a = { value = 1, unit = \"mm\", extra = 1 }"));
    rejects(&with_params(
        "a = { value = 1, unit = \"mm\" }\na = { value = 2, unit = \"mm\" }",
    ));
    rejects(&with_params(
        "a = { value = 1, unit = \"mm\" }\nb = { expr = \"a + c\", unit = \"mm\" }",
    ));
    rejects(&with_params(
        "a = { value = 1, unit = \"mm\" }\nb = { expr = \"a\", unit = \"deg\" }",
    ));
    rejects(&with_params(
        "a = { value = 1, unit = \"mm\" }\nb = { expr = \"sin(a)\", unit = \"1\" }",
    ));
    rejects(&with_params(
        "a = { value = 1, unit = \"1\", range = [1, 1] }\nb = { expr = \"\", unit = \"1\" }",
    ));
    loads(&with_params("a = { value = 1, unit = \"1\", range = [1, 1] }"));
    loads(&with_params(
        "_ = { value = 1, unit = \"1\" }\n_9 = { expr = \"_ * 2\", unit = \"1\" }",
    ));
}

#[test]
fn parameters_depending_on_themselves_are_errors() {
    rejects(&with_params("a = { expr = \"a\", unit = \"mm\" }"));
    rejects(&with_params("a = { expr = \"a + 1\", unit = \"mm\" }"));
    rejects(&with_params(
        "a = { expr = \"b\", unit = \"mm\" }\nb = { expr = \"a\", unit = \"mm\" }",
    ));
    rejects(&with_params(
        "a = { expr = \"b\", unit = \"mm\" }\nb = { expr = \"c\", unit = \"mm\" }\nc = { expr = \"a\", unit = \"mm\" }",
    ));
}

// ---- names, points, frames -------------------------------------------------------------

#[test]
fn bad_and_duplicate_point_names_are_errors() {
    rejects(&BASE.replace("C = [20, 5]", "C = [20, 5]\n\"\" = [1, 1]"));
    rejects(&BASE.replace("C = [20, 5]", "C = [20, 5]\n\"\u{e9}\" = [1, 1]"));
    rejects(&BASE.replace("C = [20, 5]", "C = [20, 5]\n\"a.b\" = [1, 1]"));
    rejects(&BASE.replace("C = [20, 5]", "C = [20, 5]\nA = [1, 1]"));
    rejects(&BASE.replace("out = \"B\"", "out = \"A\""));
    rejects(&BASE.replace("out = \"B\"", "out = \"C\""));
    rejects(&BASE.replace("out = \"B\"", "out = \"\""));
    rejects(&BASE.replace("out = \"B\"", "out = \"\u{1F600}\""));
    rejects(&BASE.replace("C = [20, 5]", "C = []"));
    rejects(&BASE.replace("C = [20, 5]", "C = [1]"));
    rejects(&BASE.replace("C = [20, 5]", "C = [1, 2, 3, 4]"));
    rejects(&BASE.replace("C = [20, 5]", "C = [\"\", 2]"));
    rejects(&BASE.replace("C = [20, 5]", "C = { at = [1, 2], frame = \"nope\" }"));
    rejects(&BASE.replace("C = [20, 5]", "C = { at = [1, 2], frame = \"\" }"));
    rejects(&BASE.replace("center = \"O\"", "center = \"A\""));
    rejects(&BASE.replace("center = \"O\"", "center = \"\""));
    rejects(&BASE.replace("joints = [\"A\", \"C\"]", "joints = [\"A\", \"Q\"]"));
    rejects(&BASE.replace("joints = [\"A\", \"C\"]", "joints = [\"A\"]"));
    rejects(&BASE.replace("joints = [\"A\", \"C\"]", "joints = [\"A\", \"C\", \"O\"]"));
}

#[test]
fn a_group_needing_its_own_output_is_an_error() {
    rejects(&BASE.replace("joints = [\"A\", \"C\"]", "joints = [\"A\", \"B\"]"));
    rejects(&BASE.replace("joints = [\"A\", \"C\"]", "joints = [\"B\", \"B\"]"));
    // Two groups that need each other.
    rejects(&format!(
        "{}\n[[groups]]\ntype = \"rrr\"\njoints = [\"B\", \"C\"]\nlengths = [5, 5]\nout = \"D\"\nbranch = \"left\"\n",
        BASE.replace("joints = [\"A\", \"C\"]", "joints = [\"A\", \"D\"]")
    ));
}

#[test]
fn frame_loops_and_bad_frames_are_errors() {
    let f = |frames: &str| format!("{BASE}\n{frames}\n");
    rejects(&f("[frames.world]\norigin = [0, 0]"));
    rejects(&f("[frames.a]\nparent = \"a\""));
    rejects(&f("[frames.a]\nparent = \"b\"\n[frames.b]\nparent = \"a\""));
    rejects(&f(
        "[frames.a]\nparent = \"b\"\n[frames.b]\nparent = \"c\"\n[frames.c]\nparent = \"b\"",
    ));
    rejects(&f("[frames.a]\nparent = \"nope\""));
    rejects(&f("[frames.a]\norigin = [1]"));
    rejects(&f("[frames.a]\nrotate = [[\"w\", 10]]"));
    rejects(&f("[frames.a]\nrotate = [[\"x\"]]"));
    // A third element in a rotation is currently ignored by the TOML shape
    // (serde's tuple struct); either way it must not panic.
    let _ = exercise(&f("[frames.a]\nrotate = [[\"x\", 10, 20]]"));
    rejects(&f("[frames.a]\nrotate = [[\"x\", \"10 * 1e308 * 10\"]]"));
    let _ = exercise(&f("[frames.a]\nrotate = [[\"x\", 1e308]]"));
    let _ = exercise(&f("[frames.\"\"]\norigin = [0, 0, 0]"));
    let _ = exercise(&f("[frames.\"\u{e9}\"]\norigin = [0, 0, 0]"));
    loads(&f(
        "[frames.a]\n[frames.b]\nparent = \"a\"\norigin = [1, 2, 3]\nrotate = [[\"z\", 90], [\"x\", -90]]",
    ));
}

#[test]
fn bad_branches_are_errors() {
    rejects(&BASE.replace("branch = \"left\"", "branch = \"forward\""));
    rejects(&BASE.replace("branch = \"left\"", "branch = \"up\""));
    rejects(&BASE.replace("branch = \"left\"", "branch = \"\""));
    rejects(&BASE.replace("branch = \"left\"", "branch = 1"));
}

// ---- each group kind with degenerate input -------------------------------------------------

const ALL_GROUPS: &str = r#"
[model]
name = "all"
phi_start_deg = 10

[parameters]
r = { value = 3, unit = "mm" }

[frames.tilt]
origin = [0, 0, 5]
rotate = [["x", 20], ["y", 10]]

[points]
O = [0, 0]
P = [0, -40]
Q = { at = [0, -30, 0], frame = "tilt" }
G = [30, 0]
T = [30, 80]

[[drivers]]
type = "crank"
center = "O"
out = "A"
radius = "r"

[[groups]]
type = "rpr"
from = "A"
pivot = "P"
offset = 1
distance = 50
out = "B"

[[groups]]
type = "rrp"
from = "B"
length = 70
through = "G"
toward = "T"
out = "S"
branch = "forward"

[[groups]]
type = "rssr"
from = "A"
rod = 28
pivot = "Q"
axis = "z"
frame = "tilt"
arm = 12
out = "K"
branch = "left"

[[groups]]
type = "point_on_line"
from = "K"
length = 60
through = "G"
direction = [0, 1, 0]
out = "L"
branch = "backward"

[[groups]]
type = "rigid_point_3d"
frame = ["A", "B", "K"]
at = [1, 2, 3]
out = "R"

[[groups]]
type = "newton"
name = "n"
unknowns = { N = [20, 30] }
constraints = [
  { distance = ["A", "N"], length = 30 },
  { distance = ["N", "G"], length = 30 },
]
"#;

#[test]
fn all_group_kinds_with_extreme_values_do_not_panic() {
    let _ = exercise(ALL_GROUPS);
    let edits: &[(&str, &str)] = &[
        ("distance = 50", "distance = 0"),
        ("distance = 50", "distance = -1e308"),
        ("offset = 1", "offset = 1e308"),
        ("length = 70", "length = 1e-300"),
        ("rod = 28", "rod = 1e308"),
        ("arm = 12", "arm = 1e-300"),
        ("axis = \"z\"", "axis = [1e-300, 0, 0]"),
        ("direction = [0, 1, 0]", "direction = [0, 0, 0]"),
        ("direction = [0, 1, 0]", "direction = [1e308, 1e308]"),
        ("at = [1, 2, 3]", "at = [1e308, -1e308, 1e308]"),
        ("at = [1, 2, 3]", "at = [1, 2]"),
        ("N = [20, 30]", "N = [1e308, 1e308]"),
        ("N = [20, 30]", "N = [0, 0]"),
        ("N = [20, 30]", "N = [20, 30, 40]"),
        ("N = [20, 30]", "N = []"),
        (
            "length = 30 },\n  { distance = [\"N\", \"G\"], length = 30 }",
            "length = 1e-300 },\n  { distance = [\"N\", \"G\"], length = 1e308 }",
        ),
        ("{ distance = [\"N\", \"G\"], length = 30 },", ""),
        (
            "{ distance = [\"N\", \"G\"], length = 30 },",
            "{ distance = [\"N\", \"N\"], length = 30 },",
        ),
        (
            "{ distance = [\"N\", \"G\"], length = 30 },",
            "{ on_line = \"N\", through = \"G\", toward = \"G\" },",
        ),
        (
            "{ distance = [\"N\", \"G\"], length = 30 },",
            "{ on_line = \"N\", through = \"N\", toward = \"G\" },",
        ),
        (
            "{ distance = [\"N\", \"G\"], length = 30 },",
            "{ on_line = \"G\", through = \"A\", toward = \"G\" },",
        ),
        (
            "{ distance = [\"N\", \"G\"], length = 30 },",
            "{ distance = [\"N\", \"G\"], length = 30 },\n{ distance = [\"N\", \"O\"], length = 30 },",
        ),
        ("unknowns = { N = [20, 30] }", "unknowns = {}"),
        (
            "unknowns = { N = [20, 30] }",
            "unknowns = { N = [20, 30] }\nplanar = false",
        ),
        (
            "unknowns = { N = [20, 30] }",
            "unknowns = { N = [20, 30] }\nplane = \"tilt\"",
        ),
        ("unknowns = { N = [20, 30] }", "unknowns = { A = [20, 30] }"),
        ("unknowns = { N = [20, 30] }", "unknowns = { \"\" = [20, 30] }"),
        ("phi_start_deg = 10", "phi_start_deg = 1e308"),
        ("phi_start_deg = 10", "phi_start_deg = nan"),
        (
            "rotate = [[\"x\", 20], [\"y\", 10]]",
            "rotate = [[\"x\", 90], [\"x\", 90], [\"x\", 180]]",
        ),
    ];
    for (from, to) in edits {
        assert!(ALL_GROUPS.contains(from), "{from}");
        let _ = exercise(&ALL_GROUPS.replace(from, to));
    }
}

#[test]
fn newton_group_references_itself() {
    // A newton group whose name is also one of its unknowns, or that is
    // named like an existing point.
    let _ = exercise(&ALL_GROUPS.replace("name = \"n\"", "name = \"N\""));
    let _ = exercise(&ALL_GROUPS.replace("name = \"n\"", "name = \"A\""));
    let _ = exercise(&ALL_GROUPS.replace("name = \"n\"", "name = \"\""));
}

// ---- cycle step sizes ------------------------------------------------------------------

#[test]
fn odd_cycle_steps_are_errors_or_run() {
    let model = loads(BASE);
    for step in [f64::NAN, f64::INFINITY, -1.0, 0.0, 1e-300, 1e-4, 360.0 + 1e-9, 1e308] {
        let opts = CycleOptions {
            step_deg: step,
            ..Default::default()
        };
        assert!(run_cycle(&model, &model.defaults(), &opts).is_err(), "step {step}");
    }
    for step in [1e-3, 0.7, 45.0, 359.999, 360.0] {
        let opts = CycleOptions {
            step_deg: step,
            ..Default::default()
        };
        let t = run_cycle(&model, &model.defaults(), &opts).unwrap();
        assert!(t.rows() >= 1);
    }
    for rpm in [f64::NAN, f64::INFINITY, 0.0, -1.0, 1e6] {
        let opts = CycleOptions {
            step_deg: 45.0,
            rpm: Some(rpm),
            ..Default::default()
        };
        assert!(run_cycle(&model, &model.defaults(), &opts).is_err(), "rpm {rpm}");
    }
}

// ---- measures and output -----------------------------------------------------------------

#[test]
fn bad_measures_and_outputs_are_errors() {
    let m = |s: &str| format!("{BASE}\n{s}\n");
    rejects(&m(
        "[[measures]]\ntype = \"distance\"\nname = \"\"\npoints = [\"A\", \"B\"]",
    ));
    rejects(&m(
        "[[measures]]\ntype = \"distance\"\nname = \"B\"\npoints = [\"A\", \"B\"]",
    ));
    rejects(&m(
        "[[measures]]\ntype = \"distance\"\nname = \"d\"\npoints = [\"A\", \"B\"]\n[[measures]]\ntype = \"distance\"\nname = \"d\"\npoints = [\"A\", \"C\"]",
    ));
    rejects(&m(
        "[[measures]]\ntype = \"coordinate\"\nname = \"c\"\npoint = \"A\"\naxis = \"q\"",
    ));
    rejects(&m(
        "[[measures]]\ntype = \"coordinate\"\nname = \"c\"\npoint = \"A\"\naxis = [0, 0, 0]",
    ));
    rejects(&m(
        "[[measures]]\ntype = \"line_deviation\"\nname = \"l\"\npoint = \"A\"\nthrough = \"O\"\ntoward = \"C\"\nplane = \"\"",
    ));
    rejects(&m("[[measures]]\ntype = \"bogus\"\nname = \"x\""));
    rejects(&m("[output]\npoints = [\"nope\"]"));
    rejects(&m("[output]\npoints = [\"\"]"));
    let _ = exercise(&m("[output]\npoints = []"));
    let _ = exercise(&m("[output]\npoints = [\"O\", \"O\", \"A\", \"A\"]"));
    let _ = exercise(&m("[output]"));
    loads(&m(
        "[[measures]]\ntype = \"distance\"\nname = \"d\"\npoints = [\"A\", \"A\"]",
    ));
}

// ---- error spans and messages -----------------------------------------------------------------

#[test]
fn error_messages_with_multibyte_text_do_not_panic() {
    // Spans next to multi-byte characters: line/column counting in Display.
    let e = rejects(&format!(
        "# \u{e9}\u{1F600}\n{}",
        BASE.replace("radius = 5", "radius = \"\u{e9} + 1\"")
    ));
    assert!(e.contains("fuzz.toml:"), "{e}");
    rejects("\u{1F600}\u{1F600} = [");
    rejects("[model]\nname = \"\u{1F600}\n");
    rejects("[model]\nname = '''\u{1F600}");
    rejects("\r\n[model]\r\nname = \"x\"\r\n[points]\r\nA = [\"\u{e9}\", 1]\r\n");
}

#[test]
fn a_zero_direction_along_a_named_axis_is_placed_at_its_key() {
    // Found by the fuzzer: `zero_dir` named the same axis as a named `axis`,
    // and the error had no line and column.
    for (axis, zero) in [
        ("", "\"z\""),
        ("axis = \"x\"\n", "\"-x\""),
        ("axis = \"-y\"\n", "\"y\""),
    ] {
        let text = BASE.replace("radius = 5", &format!("radius = 5\n{axis}zero_dir = {zero}"));
        let e = Model::from_toml_str(&text, "fuzz.toml").expect_err("parallel zero direction");
        let zero_line = text.lines().position(|l| l.starts_with("zero_dir")).unwrap() + 1;
        assert_eq!(e.line_col().map(|(l, _)| l), Some(zero_line), "{e}");
        assert!(e.to_string().contains("parallel to the axis"), "{e}");
    }
    // A perpendicular named zero direction still loads.
    loads(&BASE.replace("radius = 5", "radius = 5\nzero_dir = \"y\""));
}
