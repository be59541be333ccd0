"""The Python package against the command line: the same presets, the same
numbers, errors with their place and help."""

import csv
import io
import os
import subprocess

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


@pytest.mark.parametrize("args, kwargs", [([], {}), (["--set", "r1=5", "--step", "2"], {"set": {"r1": 5.0}, "step": 2.0})])
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


def test_tune_gives_the_command_lines_json():
    import json

    expected = json.loads(cli("tune", "--preset", "mf7923d", "--adjust", "z,dphi", "--seed", "3", "--format", "json"))
    got = stitchkin.Model.preset("mf7923d").tune(adjust=["z", "dphi"], seed=3)
    assert got == expected
    with pytest.raises(stitchkin.StitchkinError):
        stitchkin.Model.preset("mf7923d").tune(samples=10**9)


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
    assert "seed 000" in r1["source"] and not r1["derived"]


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
    pandas = pytest.importorskip("pandas")
    frame = stitchkin.Model.preset("needle876").run(step=10.0).to_pandas()
    assert isinstance(frame, pandas.DataFrame) and frame.shape[0] == 36
    assert frame.columns[0] == "phi_deg"


def test_the_docs_snippets_run():
    """Every ```python block of docs/python.md, in order, in one namespace."""
    docs = os.path.join(os.path.dirname(__file__), "..", "..", "..", "..", "docs", "python.md")
    with open(docs, encoding="utf-8") as f:
        text = f.read()
    blocks = [b.split("```", 1)[0] for b in text.split("```python\n")[1:]]
    assert len(blocks) >= 4
    namespace = {}
    for block in blocks:
        exec(compile(block, docs, "exec"), namespace)


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
