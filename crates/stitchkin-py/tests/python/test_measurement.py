"""Repeated readings processed as Polyakov (2022) §3.4 from Python: the same
table as `stitchkin measured`, as NumPy arrays, and errors with their place
and help."""

import csv
import io
import os
import pathlib
import subprocess

import numpy as np
import pytest

import stitchkin

BENCH = pathlib.Path(__file__).resolve().parents[4] / "examples" / "seed004-bench-lower.csv"


def cli(*args):
    exe = os.environ.get("STITCHKIN_CLI")
    if not exe:
        pytest.fail("STITCHKIN_CLI names no stitchkin binary: run these tests through `cargo test --workspace`")
    return subprocess.run([exe, *args], capture_output=True, text=True, check=True).stdout


def test_the_bench_file_is_processed_as_the_command_line_does():
    r = stitchkin.process_readings(BENCH)
    assert r["confidence"] == 0.95 and r["resolution_mm"] == 0.05
    assert r["column"] == "lower.P_mm"
    assert len(r["phi_deg"]) == 36 and (r["n"] == 10).all()
    # t(0.975, 9) = 2.262 (Student's table).
    assert np.allclose(r["t"], 2.262157, atol=1e-6)
    # Δ = √(Δr² + Δs²), the interval x̄ ± Δ, σ = √(s²/n + Δs²/3).
    assert np.allclose(r["total_mm"], np.hypot(r["random_mm"], r["systematic_mm"]))
    assert np.allclose(r["ci_high_mm"] - r["mean_mm"], r["total_mm"])
    assert np.allclose(r["sigma_mm"], np.sqrt(r["s_mm"] ** 2 / r["n"] + 0.05**2 / 3))
    # The slipped reading is flagged.
    k = int(np.argmin(abs(r["phi_deg"] - 474.85)))
    assert 7 in r["outliers"][k]
    # The same numbers as the command line's CSV.
    rows = list(csv.DictReader(io.StringIO(cli("measured", str(BENCH)))))
    for name in ["phi_deg", "mean_mm", "s_mm", "t", "total_mm", "sigma_mm"]:
        assert np.allclose(r[name], [float(row[name]) for row in rows]), name
    rel = [float(row["relative_pct"]) if row["relative_pct"] else np.nan for row in rows]
    assert np.allclose(r["relative_pct"], rel, equal_nan=True)


def test_resolution_and_confidence_stand_for_the_files_lines():
    r = stitchkin.process_readings(BENCH, resolution_mm=0.2, confidence=0.99)
    assert r["resolution_mm"] == 0.2 and r["confidence"] == 0.99
    assert np.allclose(r["t"], 3.249836, atol=1e-6)


def test_rows_per_reading_hand_computed(tmp_path):
    # Three readings φ-wise, x − 0.1, x, x + 0.1: mean x, s = 0.1.
    lines = ["# resolution_mm = 0.05", "phi_deg,P_mm"]
    for k in range(12):
        for j in (-1, 0, 1):
            lines.append(f"{30 * k},{0.3 * k + 0.1 * j}")
    f = tmp_path / "rows.csv"
    f.write_text("\n".join(lines) + "\n")
    r = stitchkin.process_readings(f)
    assert np.allclose(r["mean_mm"], 0.3 * np.arange(12))
    assert np.allclose(r["s_mm"], 0.1)
    assert np.allclose(r["random_mm"], 4.302653 * 0.1 / np.sqrt(3), atol=1e-6)


def test_bad_files_say_where_and_what_to_do(tmp_path):
    f = tmp_path / "nores.csv"
    f.write_text("phi_deg,P_mm,P_mm\n" + "".join(f"{30 * k},1,1.1\n" for k in range(12)))
    with pytest.raises(stitchkin.StitchkinError) as e:
        stitchkin.process_readings(f)
    assert e.value.line == 1 and "resolution_mm = 0.05" in e.value.help
    with pytest.raises(stitchkin.StitchkinError, match="not a length > 0"):
        stitchkin.process_readings(f, resolution_mm=0.0)
    plain = tmp_path / "plain.csv"
    plain.write_text("phi_deg,P_mm\n" + "".join(f"{30 * k},1\n" for k in range(12)))
    with pytest.raises(stitchkin.StitchkinError, match="one reading per φ"):
        stitchkin.process_readings(plain)
