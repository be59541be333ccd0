"""The Python package against the command line: the same presets, the same
numbers, errors with their place and help."""

import ast
import csv
import importlib
import importlib.util
import io
import os
import signal
import subprocess
import sys
import warnings

import numpy as np
import pytest

import stitchkin


def cli(*args):
    """Runs the command line (its path in STITCHKIN_CLI) and returns stdout."""
    exe = os.environ.get("STITCHKIN_CLI")
    if not exe:
        pytest.fail("STITCHKIN_CLI names no stitchkin binary: run these tests through `cargo test --workspace`")
    done = subprocess.run([exe, *args], capture_output=True, text=True, check=True)
    return done.stdout


def cli_error(*args):
    """The message and help of the command line's error for ARGS (it must
    fail): the text after `×` and after `help:`, as one line each."""
    exe = os.environ.get("STITCHKIN_CLI")
    if not exe:
        pytest.fail("STITCHKIN_CLI names no stitchkin binary: run these tests through `cargo test --workspace`")
    done = subprocess.run([exe, *args], capture_output=True, text=True)
    assert done.returncode != 0, f"stitchkin {' '.join(args)} succeeded"
    text = done.stderr
    message, _, help = text.split("×", 1)[1].partition("help:")
    return " ".join(message.split()), " ".join(help.split())


def need(module):
    """Imports `module`, or skips the test with a warning that names what
    is not installed (shown in pytest's summary; `cargo test` installs the
    test requirements and fails on any skipped test)."""
    if importlib.util.find_spec(module) is None:
        message = (
            f"`{module}` is not installed, so this test did not run: "
            "pip install -r crates/stitchkin-py/requirements-test.txt"
        )
        warnings.warn(message)
        pytest.skip(message)
    return importlib.import_module(module)


def cli_table(*args):
    """The CSV of `stitchkin run ARGS --format csv` as {name: [float]}."""
    rows = list(csv.reader(io.StringIO(cli("run", *args, "--format", "csv"))))
    names, values = rows[0], np.array(rows[1:], dtype=float)
    return names, {n: values[:, k] for k, n in enumerate(names)}


def as_written(x):
    """x rounded to the 12 significant digits the CSV carries."""
    return np.array([float(f"{v:.11e}") for v in x])


def assert_rows_equal(columns, names, rows):
    """`columns` (a Table or a DataFrame) holds the CSV `rows` under `names`:
    `index` and `status` as written, every other column at the CSV's 12
    digits, an empty cell as NaN."""
    assert list(columns) == names and len(columns[names[0]]) == len(rows)
    for k, name in enumerate(names):
        column = [r[k] for r in rows]
        got = np.asarray(columns[name])
        if name == "status":
            assert list(got) == column
        elif name == "index":
            assert list(got) == [int(x) for x in column]
        else:
            expected = np.array([float(x) if x else np.nan for x in column])
            np.testing.assert_array_equal(as_written(got), expected, err_msg=name)


def test_presets_are_the_command_lines():
    listed = cli("presets")
    assert stitchkin.default_preset() == "mf7923d"
    for name in stitchkin.presets():
        assert name in listed


@pytest.mark.parametrize("preset", stitchkin.presets())
def test_run_gives_the_command_lines_numbers(preset):
    names, expected = cli_table("--preset", preset)
    table = stitchkin.Model.preset(preset).run()
    assert list(table) == names
    for name in names:
        got = table[name]
        assert got.dtype == np.float64 and got.shape == (table.rows,)
        np.testing.assert_array_equal(as_written(got), expected[name], err_msg=name)


def test_run_with_settings_and_columns():
    names, expected = cli_table("--preset", "mf7923d", "--set", "r1=5", "--step", "2", "--columns", "*.P_B_mm")
    table = stitchkin.Model.preset("mf7923d").run(step=2.0, set={"r1": 5.0}, columns=["*.P_B_mm"])
    assert list(table) == names and names[0] == "phi_deg" and len(names) == 7
    assert table.rows == 180
    for name in names:
        np.testing.assert_array_equal(as_written(table[name]), expected[name], err_msg=name)
    # The setting is applied: r1 = 5 mm is not the default 4 mm.
    default = stitchkin.Model.preset("mf7923d").run(step=2.0, columns=["*.P_B_mm"])
    assert not np.array_equal(default["n1_A.P_B_mm"], table["n1_A.P_B_mm"])


def cli_sweep(*args):
    rows = list(csv.reader(io.StringIO(cli("sweep", *args))))
    return rows[0], rows[1:]


@pytest.mark.parametrize(
    "args, kwargs",
    [
        (["--vary", "z=-10:10:5", "--vary", "r1=4:6:3"], {"vary": {"z": (-10, 10, 5), "r1": (4, 6, 3)}}),
        (
            ["--vary", "z=-10:10", "--vary", "dphi=-20:20", "--samples", "40", "--seed", "7", "--figures", "*.score,checks.ok"],
            {"vary": ["z=-10:10", "dphi=-20:20"], "samples": 40, "seed": 7, "figures": ["*.score", "checks.ok"]},
        ),
    ],
)
def test_sweep_gives_the_command_lines_rows(args, kwargs):
    names, rows = cli_sweep("--preset", "mf7923d", *args)
    table = stitchkin.Model.preset("mf7923d").sweep(**kwargs)
    assert table.rows == len(rows)
    assert_rows_equal(table, names, rows)


@pytest.mark.parametrize("args, kwargs", [([], {}), (["--set", "r1=4.5", "--step", "2"], {"set": {"r1": 4.5}, "step": 2.0})])
def test_match_gives_the_command_lines_json(args, kwargs):
    import json

    expected = json.loads(cli("match", "--preset", "mf7923d", "--format", "json", *args))
    expected.pop("measured", None)
    got = stitchkin.Model.preset("mf7923d").match(**kwargs)
    assert got == expected
    assert [t["thread"] for t in got["threads"]] == ["n1", "n2", "n3"]
    assert all(c["ok"] for c in got["checks"])


def test_thread_tension_is_the_command_lines():
    """The thread's tension: its columns, its JSON object, its sweep figures
    and the tuning for the lowest peak, as the command line gives them."""
    import json

    names, expected = cli_table("--preset", "lockstitch", "--step", "2", "--columns", "needle.T_*,needle.s*_mm")
    table = stitchkin.Model.preset("lockstitch").run(step=2.0, columns=["needle.T_*", "needle.s*_mm"])
    assert list(table) == names and "needle.T_reg_N" in names and "needle.spring_mm" in names
    for name in names:
        np.testing.assert_array_equal(as_written(table[name]), expected[name], err_msg=name)
    got = stitchkin.Model.preset("lockstitch").match(step=2.0)
    expected = json.loads(cli("match", "--preset", "lockstitch", "--step", "2", "--format", "json"))
    expected.pop("measured", None)
    assert got == expected
    tension = got["threads"][0]["tension"]
    assert tension["peak_N"] > 0 and tension["regulator_windows_deg"] and tension["spring"]["force_N"] == [0.25, 0.35]
    figures = ["n1.max_T_N", "*.tension_margin", "*.max_slack_mm", "*.set_slack_mm"]
    names, rows = cli_sweep("--preset", "mf7923d", "--vary", "regulator=0.3:0.5:3", "--step", "4", "--figures", ",".join(figures))
    table = stitchkin.Model.preset("mf7923d").sweep(vary=["regulator=0.3:0.5:3"], step=4.0, figures=figures)
    assert "n1.max_T_N" in names
    assert_rows_equal(table, names, rows)
    expected = json.loads(
        cli("tune", "--preset", "mf7923d", "--adjust", "regulator", "--objective", "peak-tension", "--step", "4", "--format", "json")
    )
    got = stitchkin.Model.preset("mf7923d").tune(adjust=["regulator"], objective="peak-tension", step=4.0)
    assert got == expected and got["objective"] == "peak_tension"
    with pytest.raises(ValueError, match="peak-tension"):
        stitchkin.Model.preset("mf7923d").tune(objective="tension")


def test_match_needs_a_stitch():
    with pytest.raises(stitchkin.StitchkinError, match="no \\[stitch\\] table"):
        stitchkin.Model.preset("needle876").match()


def test_check_lists_the_stitchs_and_the_cams_checks():
    """Model.check: the checks `stitchkin check` judges, a cam's spring at
    the speed asked."""
    root = os.path.join(os.path.dirname(__file__), "..", "..", "..", "..")
    m = stitchkin.Model.load(os.path.join(root, "examples", "cam-rocking-roller.toml"))
    got = m.check()
    assert got["ok"] is True
    names = [c["name"] for c in got["checks"]]
    assert names == ["cam_pressure", "cam_curvature", "follower_contact"]
    cam = got["cams"][0]
    assert cam["group"] == "feed_arm" and 1000 < cam["limit_rpm"] < 3000
    fast = m.check(rpm=3000)
    assert fast["ok"] is False
    contact = [c for c in fast["checks"] if c["name"] == "follower_contact"][0]
    assert contact["ok"] is False and contact["value"] < 0 and "leaves the cam" in contact["message"]
    # The stitch's checks of a preset, all passing at its default.
    mf = stitchkin.Model.preset("mf7923d").check()
    assert mf["ok"] is True and mf["cams"] == [] and len(mf["checks"]) > 0
    with pytest.raises(stitchkin.StitchkinError, match="rpm"):
        m.check(rpm=-1)


def json_dumps(value):
    import json

    return json.dumps(value)


def test_tune_gives_the_command_lines_json():
    import json

    expected = json.loads(cli("tune", "--preset", "mf7923d", "--adjust", "z,dphi", "--seed", "3", "--format", "json"))
    got = stitchkin.Model.preset("mf7923d").tune(adjust=["z", "dphi"], seed=3)
    assert got == expected
    with pytest.raises(stitchkin.StitchkinError):
        stitchkin.Model.preset("mf7923d").tune(samples=10**9)


def test_tune_adjusts_machine_settings_unless_told_otherwise():
    model = stitchkin.Model.preset("mf7923d")
    with pytest.raises(stitchkin.StitchkinError, match="job input") as e:
        model.tune(adjust=["m"])
    assert "allow_inputs=True" in str(e.value)
    with pytest.raises(stitchkin.StitchkinError, match="allow_dimensions=True"):
        model.tune(adjust=["l_ab"])
    got = model.tune(adjust=["m"], allow_inputs=True, samples=8, step=4.0)
    assert "m" in json_dumps(got)


@pytest.mark.parametrize(
    "args, kwargs",
    [
        (["--type", "504", "--thickness", "2.5", "--stitch", "2.8", "--width", "4", "--incline", "20"],
         dict(stitch_type=504, thickness=2.5, stitch=2.8, width=4.0, incline=20.0)),
        (["--type", "407", "--thickness", "3", "--stitch", "3"], dict(stitch_type=407, thickness=3.0, stitch=3.0)),
        (["--type", "301", "--thickness", "2", "--stitch", "2.5", "--interlace", "0.4", "--seam", "2500", "--waste", "15"],
         dict(stitch_type=301, thickness=2.0, stitch=2.5, interlace=0.4, seam=2500.0, waste=15.0)),
    ],
)
def test_consumption_gives_the_command_lines_json(args, kwargs):
    import json

    assert stitchkin.consumption(**kwargs) == json.loads(cli("consumption", *args, "--format", "json"))


def test_consumption_errors():
    with pytest.raises(stitchkin.StitchkinError):
        stitchkin.consumption(504, 2.5, 2.8)
    with pytest.raises(stitchkin.StitchkinError):
        stitchkin.consumption(999, 2.5, 2.8)
    with pytest.raises(stitchkin.StitchkinError):
        stitchkin.consumption(407, -1.0, 2.8)
    with pytest.raises(stitchkin.StitchkinError, match="waste"):
        stitchkin.consumption(301, 2.0, 2.5, waste=-5.0)
    with pytest.raises(stitchkin.StitchkinError, match="seam"):
        stitchkin.consumption(301, 2.0, 2.5, seam=0.0)


def test_consumption_per_seam():
    c = stitchkin.consumption(301, 2.0, 2.5, seam=2500.0, waste=15.0)
    needle, bobbin = c["threads"]
    assert (needle["thread"], bobbin["thread"]) == ("needle 1", "bobbin")
    assert needle["length_mm"] == pytest.approx(4.5) and needle["ratio"] == pytest.approx(1.8)
    assert c["total_seam_m"] == pytest.approx(9.0) and c["total_seam_with_waste_m"] == pytest.approx(10.35)
    assert "taut" in c["notes"][0]


@pytest.mark.parametrize("spec", ["zz=-10:10", "z=10", "z=-100:100:3", "z=1:2:x", "z=3:3:4", "z", "dphi=-20:20:1"])
def test_a_sweeps_errors_are_the_command_lines(spec):
    """A misspelt parameter (with its "did you mean"), a range without its
    ends, a value outside the parameter's range, a malformed N: the command
    line's message and help (its `--vary` named `vary`), from `sweep` and
    from the check a Dask sweep runs before it sends work."""
    message, help = cli_error("sweep", "--preset", "mf7923d", "--vary", spec, "--samples", "3")
    assert message.endswith("(in --vary)")
    message = message.replace("(in --vary)", "(in `vary`)")
    model = stitchkin.Model.preset("mf7923d")
    for call in (model.sweep, model._check_sweep):
        with pytest.raises(stitchkin.StitchkinError) as e:
            call([spec], samples=3)
        assert e.value.help == help
        assert str(e.value) == f"{message}\n  help: {help}"
    if spec == "zz=-10:10":
        assert help == "did you mean `z`?"


def test_a_descending_range_sweeps_down_as_the_command_lines():
    """`z=5:1` is the values from 5 mm down to 1 mm, as `--vary z=5:1`."""
    names, rows = cli_sweep("--preset", "mf7923d", "--vary", "z=5:1:3", "--figures", "score.mean")
    table = stitchkin.Model.preset("mf7923d").sweep(vary=["z=5:1:3"], figures=["score.mean"])
    assert list(table["z_mm"]) == [5.0, 3.0, 1.0]
    assert_rows_equal(table, names, rows)
    assert stitchkin.Model.preset("mf7923d")._check_sweep(["z=5:1"], samples=7) == 7


def test_a_missing_column_is_a_key_error_that_says_what_there_is():
    table = stitchkin.Model.preset("mf7923d").run(step=30.0, columns=["*.P_B_mm"])
    with pytest.raises(KeyError) as e:
        table["n1_A.P_B_m"]
    assert isinstance(e.value, stitchkin.MissingColumnError) and isinstance(e.value, stitchkin.StitchkinError)
    assert e.value.name == "n1_A.P_B_m" and e.value.help == "did you mean `n1_A.P_B_mm`?"
    assert str(e.value) == "the table has no column `n1_A.P_B_m`\n  help: did you mean `n1_A.P_B_mm`?"
    # The same "did you mean" as the command line's for a misspelt name
    # (the library's did_you_mean), here for a parameter.
    _, help = cli_error("run", "--preset", "mf7923d", "--set", "r11=5")
    with pytest.raises(stitchkin.StitchkinError) as p:
        stitchkin.Model.preset("mf7923d").run(set={"r11": 5.0})
    assert help == p.value.help == "did you mean `r1`?"
    # Nothing close: some of the columns, and how to see them all.
    with pytest.raises(KeyError) as e:
        table["typo"]
    assert e.value.help.startswith("its columns are phi_deg, n1_A.P_B_mm, n1_B.P_B_mm")
    assert "did you mean" not in str(e.value)
    big = stitchkin.Model.preset("mf7923d").run(step=30.0)
    with pytest.raises(KeyError, match="columns; list\\(table\\) names them all"):
        big["typo"]
    # A sweep's parameter column without its unit: the column with it.
    grid = stitchkin.Model.preset("mf7923d").sweep(vary={"z": (-10, 10, 3)}, figures=["score.mean"])
    with pytest.raises(KeyError, match="did you mean `z_mm`"):
        grid["z"]
    # The rest of the mapping is a dict's.
    assert "typo" not in table and table.get("typo") is None and table.get("typo", 1) == 1
    assert "n1_A.P_B_mm" in table
    # Whole through pickle (as from a Dask worker).
    import pickle

    again = pickle.loads(pickle.dumps(e.value))
    assert type(again) is stitchkin.MissingColumnError
    assert (str(again), again.help, again.name) == (str(e.value), e.value.help, e.value.name)


def test_sweep_errors():
    model = stitchkin.Model.preset("mf7923d")
    with pytest.raises(stitchkin.StitchkinError):
        model.sweep(vary=["z=-100:100:3"])
    with pytest.raises(stitchkin.StitchkinError):
        model.sweep(vary=["nope=1:2:3"])
    with pytest.raises(stitchkin.StitchkinError):
        model.sweep(vary={"z": (-10, 10, 3)}, figures=["no.such.figure"])
    with pytest.raises(ValueError):
        model.sweep(vary={"z": (-10, 10, 2.5)})
    with pytest.raises(ValueError):
        model.sweep(vary=["z=-10:10"], samples=10, method="sobol")
    with pytest.raises(TypeError):
        model.sweep(vary="z=-10:10:3")


def test_parameters_carry_unit_range_and_source():
    params = {p["name"]: p for p in stitchkin.Model.preset("mf7923d").parameters}
    r1 = params["r1"]
    assert r1["unit"] == "mm" and r1["value"] == 4.0 and r1["range"] == (4.0, 6.0)
    # Papers cited by authors and year, as the command line prints them.
    assert "Manoilenko et al. (2024)" in r1["source"] and "seed 0" not in r1["source"]
    assert not r1["derived"]


def test_a_model_file_error_has_its_place_and_help(tmp_path):
    text = '[model]\nname = "x"\n\n[points]\nO = [0, 0]\n\n[[drivers]]\ntype = "crank"\ncenter = "O"\nout = "A"\nradius = -5\n'
    with pytest.raises(stitchkin.StitchkinError) as e:
        stitchkin.Model.from_toml(text, "bad.toml")
    assert (e.value.file, e.value.line) == ("bad.toml", 11)
    assert e.value.column >= 1 and e.value.key == "drivers[0].radius"
    assert e.value.help
    path = tmp_path / "bad.toml"
    path.write_text(text)
    with pytest.raises(stitchkin.StitchkinError) as e:
        stitchkin.Model.load(path)
    assert e.value.line == 11 and str(path) in e.value.file


def test_run_with_points_fixed_and_moving():
    args = ("--preset", "mf7923d", "--step", "5", "--no-analogs", "--points", "G4_1,B,T1_1")
    names, expected = cli_table(*args)
    table = stitchkin.Model.preset("mf7923d").run(step=5.0, analogs=False, points=["G4_1", "B", "T1_1"])
    assert list(table) == names and "G4_1.x_mm" in names and "B.z_mm" in names
    for name in names:
        np.testing.assert_array_equal(as_written(table[name]), expected[name], err_msg=name)
    with pytest.raises(stitchkin.StitchkinError, match="no point `Q`") as e:
        stitchkin.Model.preset("mf7923d").run(points=["Q"])
    assert "its points are" in e.value.help


def test_a_missing_file_and_a_bad_setting_are_errors(tmp_path):
    with pytest.raises(stitchkin.StitchkinError, match="nope.toml"):
        stitchkin.Model.load(tmp_path / "nope.toml")
    model = stitchkin.Model.preset("mf7923d")
    with pytest.raises(stitchkin.StitchkinError) as e:
        model.run(set={"r1": 50.0})
    assert "r1" in str(e.value) and e.value.help and e.value.line is None
    with pytest.raises(stitchkin.StitchkinError):
        model.run(set={"no_such_parameter": 1.0})
    with pytest.raises(stitchkin.StitchkinError):
        model.run(step=0.0)
    with pytest.raises(stitchkin.StitchkinError):
        model.run(columns=["nothing*matches"])
    with pytest.raises(stitchkin.StitchkinError):
        stitchkin.Model.preset("no-such-preset")


def test_to_pandas():
    pandas = need("pandas")
    frame = stitchkin.Model.preset("needle876").run(step=10.0).to_pandas()
    assert isinstance(frame, pandas.DataFrame) and frame.shape[0] == 36
    assert frame.columns[0] == "phi_deg"


DOCS = os.path.join(os.path.dirname(__file__), "..", "..", "..", "..", "docs", "python.md")


def docs_blocks():
    """The ```python blocks of docs/python.md, in order: the snippets, and
    the scripts (a block with an `if __name__ == "__main__":` guard, which
    runs as a file of its own)."""
    with open(DOCS, encoding="utf-8") as f:
        text = f.read()
    blocks = [b.split("```", 1)[0] for b in text.split("```python\n")[1:]]
    is_script = ['if __name__ == "__main__":' in b for b in blocks]
    return [b for b, s in zip(blocks, is_script) if not s], [b for b, s in zip(blocks, is_script) if s]


def test_the_docs_snippets_run():
    """Every ```python block of docs/python.md that is not a script, in
    order, in one namespace."""
    snippets, _ = docs_blocks()
    assert len(snippets) >= 4
    namespace = {}
    for block in snippets:
        exec(compile(block, DOCS, "exec"), namespace)


@pytest.mark.parametrize("script", docs_blocks()[1])
def test_the_docs_scripts_run_as_files(script, tmp_path):
    """Each script block of docs/python.md, written to a file and run as
    `python script.py` in a process of its own, as a user pastes it (a
    Dask LocalCluster's workers import that file)."""
    for node in ast.walk(ast.parse(script)):
        if isinstance(node, ast.Import):
            for alias in node.names:
                need(alias.name.split(".")[0])
    path = tmp_path / "script.py"
    path.write_text(script, encoding="utf-8")
    # A process group of its own: on a timeout the script and every process it
    # started (a cluster's workers) are stopped together.
    proc = subprocess.Popen(
        [sys.executable, str(path)], stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, cwd=tmp_path, preexec_fn=os.setpgrp
    )
    try:
        stdout, stderr = proc.communicate(timeout=120)
    except subprocess.TimeoutExpired:
        os.killpg(proc.pid, signal.SIGKILL)
        stdout, stderr = proc.communicate()
        pytest.fail(f"the script of docs/python.md did not finish in 120 s:\n{script}\n{stderr[-3000:]}")
    assert proc.returncode == 0, f"python script.py failed:\n{script}\n{stdout}\n{stderr}"
    assert stdout.strip(), "the script printed nothing"


def test_the_docs_have_the_dask_script():
    """The Dask sweep of docs/python.md is a script guarded for the
    workers' processes, so the test above runs it as a file."""
    _, scripts = docs_blocks()
    assert any("distributed.LocalCluster" in s and "stitchkin.dask.sweep" in s for s in scripts)


def test_the_peer_bench_runs():
    """bench/peers.py runs and prints its tables (its figures are not checked
    here: timing belongs in the bench)."""
    import sys

    bench = os.path.join(os.path.dirname(__file__), "..", "..", "bench", "peers.py")
    done = subprocess.run([sys.executable, bench, "--repeat", "3"], capture_output=True, text=True)
    assert done.returncode == 0, done.stderr
    assert "Rust core" in done.stdout and "NumPy, vectorised" in done.stdout
    # Both NumPy peers were checked against stitchkin before they were timed.
    assert "NumPy's positions of B and P are stitchkin's within" in done.stdout
    assert "MF-7923D take-up" in done.stdout and "is stitchkin's within" in done.stdout
