"""The machine's setting fitted to its measured take-up from Python
(`Model.fit_measured`): a known setting recovered from a noisy synthetic
measurement within its intervals, the warning for parameters the data
cannot tell apart, the advice, and bad inputs as errors.

The synthetic measurement, as the library's own test makes it: P of needle
thread n1 at B (`n1_A.P_B_mm`) from the preset mf7923d at z = −3 mm,
Δφ = 5 deg (the rest as shipped), every 10 deg of φ (36 samples), plus
Gaussian noise of σ = 0.05 mm drawn with a fixed NumPy seed."""

import pathlib

import numpy as np
import pytest

import stitchkin

TRUTH = {"z": -3.0, "dphi": 5.0}
NOISE_MM = 0.05
STEP_DEG = 10.0


@pytest.fixture(scope="module")
def model():
    return stitchkin.Model.preset("mf7923d")


def take_up(model, settings, path="n1_A"):
    """φ, deg, and P at B of `path`, mm, every 10 deg at `settings`."""
    t = model.run(step=STEP_DEG, set=settings, columns=[f"{path}.P_B_mm"])
    return t["phi_deg"], t[f"{path}.P_B_mm"]


def write_curve(path, column, phi, values, resolution_mm=None):
    """A CSV `phi_deg,COLUMN` (one reading per φ), or several readings per φ
    when `values` is 2-D (a column per reading) with the instrument's
    resolution."""
    values = np.asarray(values)
    readings = values.shape[1] if values.ndim == 2 else 1
    lines = [] if resolution_mm is None else [f"# resolution_mm = {resolution_mm}"]
    lines.append("phi_deg," + ",".join([column] * readings))
    for f, v in zip(phi, values):
        row = np.atleast_1d(v)
        lines.append(",".join(repr(float(x)) for x in [f, *row]))
    path.write_text("\n".join(lines) + "\n", encoding="utf-8")
    return path


@pytest.fixture(scope="module")
def noisy(model, tmp_path_factory):
    """The synthetic measurement of n1: its file and values."""
    phi, p = take_up(model, TRUTH)
    y = p + NOISE_MM * np.random.default_rng(4).standard_normal(len(p))
    f = write_curve(tmp_path_factory.mktemp("measured") / "n1.csv", "n1.P_B_mm", phi, y)
    return f, phi, y


def test_a_noisy_measurement_gives_back_z_and_dphi_within_their_intervals(model, noisy):
    f, phi, y = noisy
    start = {"z": 0.0, "dphi": 0.0}
    r = model.fit_measured(str(f), ["z", "dphi"], set=start)
    assert r["converged"], r["stop"]
    assert (r["samples"], r["dof"]) == (36, 34)
    assert not r["sigma_known"]
    assert [p["name"] for p in r["params"]] == ["z", "dphi"]
    for p in r["params"]:
        truth = TRUTH[p["name"]]
        lo, hi = p["interval"]
        assert lo <= truth <= hi, f"{p['name']} = {p['fitted']} {p['unit']}: {truth} not in {lo}…{hi}"
        # Close: within 4 standard errors, which are a fraction of a mm or deg.
        assert abs(p["fitted"] - truth) < 4 * p["std_error"], p
        assert p["std_error"] < {"z": 0.2, "dphi": 0.4}[p["name"]], p
        assert p["start"] == start[p["name"]] and not p["at_bound"]
        assert (p["lo"], p["hi"]) == {"z": (-10.0, 10.0), "dphi": (-20.0, 20.0)}[p["name"]]
        assert p["unit"] == {"z": "mm", "dphi": "deg"}[p["name"]] and p["label"]
        # The interval is fitted ± q·std_error.
        assert np.allclose([lo, hi], [p["fitted"] - r["quantile"] * p["std_error"], p["fitted"] + r["quantile"] * p["std_error"]])
    assert r["fitted"] == {p["name"]: p["fitted"] for p in r["params"]}
    # σ estimated from the residuals, Student's t with 34 degrees of freedom.
    assert abs(r["sigma_estimated_mm"] - NOISE_MM) < 0.4 * NOISE_MM, r["sigma_estimated_mm"]
    assert abs(r["quantile"] - 2.032245) < 1e-5 and "Student" in r["quantile_from"]
    assert r["confidence"] == 0.95
    assert np.isclose(r["chi2_per_dof"], r["sigma_estimated_mm"] ** 2)
    # z and Δφ are told apart: no warning that they are not.
    assert not any("cannot be told apart" in w for w in r["warnings"]), r["warnings"]
    c = r["correlation"]
    assert isinstance(c, np.ndarray) and c.shape == (2, 2)
    assert np.allclose(np.diag(c), 1.0) and np.isclose(c[0, 1], c[1, 0]) and abs(c[0, 1]) < 0.99
    assert np.isfinite(r["condition"]) and r["condition"] >= 1.0
    assert r["iterations"] >= 1 and r["advice"] is None
    assert all(isinstance(n, str) for n in r["notes"] + r["warnings"])
    # The curve: the measured values as written, the fitted model's P at
    # the same φ (as `run` gives it at the fitted setting), the residual.
    (curve,) = r["curves"]
    assert (curve["thread"], curve["path"], curve["kind"]) == ("n1", "n1_A", "take_up")
    assert curve["source"] == str(f) and curve["sigma_mm"] is None
    assert np.allclose(curve["phi_deg"], phi) and np.allclose(curve["measured_mm"], y)
    _, fitted_p = take_up(model, r["fitted"])
    assert np.allclose(curve["model_mm"], fitted_p, atol=1e-9)
    assert np.allclose(curve["residual_mm"], curve["model_mm"] - curve["measured_mm"])
    assert np.isclose(curve["rms_residual_mm"], np.sqrt(np.mean(curve["residual_mm"] ** 2)))


def test_repeated_readings_weigh_the_fit_and_give_normal_intervals(model, tmp_path):
    # Five readings per φ: each sample's σ comes from its readings.
    phi, p = take_up(model, TRUTH)
    rng = np.random.default_rng(7)
    readings = p[:, None] + NOISE_MM * rng.standard_normal((len(p), 5))
    f = write_curve(tmp_path / "n1-repeated.csv", "n1.P_B_mm", phi, readings, resolution_mm=0.01)
    r = model.fit_measured(f, ["z", "dphi"])
    assert r["sigma_known"] and r["sigma_estimated_mm"] is None
    assert abs(r["quantile"] - 1.959964) < 1e-5 and "normal" in r["quantile_from"]
    sigma = r["curves"][0]["sigma_mm"]
    assert isinstance(sigma, np.ndarray) and sigma.shape == (36,)
    assert np.allclose(sigma, stitchkin.process_readings(f)["sigma_mm"])
    for q in r["params"]:
        lo, hi = q["interval"]
        assert lo <= TRUTH[q["name"]] <= hi, q


def test_every_form_of_measured_gives_the_same_fit(model, noisy):
    f = noisy[0]
    forms = [str(f), f, f"n1={f}", [f"n1={f}"], [pathlib.Path(f)], {"n1": f}, {"n1": str(f)}]
    fits = [model.fit_measured(m, ["z", "dphi"])["fitted"] for m in forms]
    assert all(x == fits[0] for x in fits), fits
    # `adjust` as one string, as `--adjust z,dphi`.
    assert model.fit_measured(f, "z,dphi")["fitted"] == fits[0]


def test_two_curves_fit_together(model, noisy, tmp_path):
    f1 = noisy[0]
    phi, p2 = take_up(model, TRUTH, "n2_A")
    y2 = p2 + NOISE_MM * np.random.default_rng(5).standard_normal(len(p2))
    f2 = write_curve(tmp_path / "n2.csv", "n2.P_B_mm", phi, y2)
    r = model.fit_measured([f1, f2], ["z", "dphi"], step=STEP_DEG)
    assert r["samples"] == 72 and r["dof"] == 70 and r["step_deg"] == STEP_DEG
    assert [c["thread"] for c in r["curves"]] == ["n1", "n2"]
    for q in r["params"]:
        lo, hi = q["interval"]
        assert lo <= TRUTH[q["name"]] <= hi, q


def test_two_parameters_the_data_cannot_separate_are_named(model, noisy):
    # The eccentric's throw r1 and the ball arm's length l_o2b set the
    # take-up arm's swing through their ratio.
    settings = dict(TRUTH, r1=4.5)
    r = model.fit_measured(noisy[0], ["r1", "l_o2b"], set=settings)
    assert abs(r["correlation"][0, 1]) > 0.99, r["correlation"]
    named = [w for w in r["warnings"] if "`r1`" in w and "`l_o2b`" in w]
    assert named and "cannot be told apart" in named[0], r["warnings"]


def test_advise_tunes_from_the_fitted_setting(model, noisy):
    r = model.fit_measured(noisy[0], ["z", "dphi"], advise=True)
    advice = r["advice"]
    assert isinstance(advice["notes"], list)
    tuned = advice["tune"]
    assert tuned is not None and tuned["names"] == [["z", "mm"], ["dphi", "deg"]]
    # It starts from the fitted machine.
    assert tuned["before"] == [r["fitted"]["z"], r["fitted"]["dphi"]]
    # The same as `Model.tune` from the fitted setting with its defaults.
    assert tuned == model.tune(adjust=["z", "dphi"], set=r["fitted"])


def test_bad_inputs_raise_clear_errors(model, noisy, tmp_path):
    f = noisy[0]
    missing = tmp_path / "no-such-file.csv"
    with pytest.raises(stitchkin.StitchkinError) as e:
        model.fit_measured(missing, ["z"])
    assert str(missing) in str(e.value) and "cannot read" in str(e.value) and e.value.help
    with pytest.raises(stitchkin.StitchkinError) as e:
        model.fit_measured(f, ["zz"])
    assert "no parameter `zz`" in str(e.value) and "dphi" in e.value.help
    with pytest.raises(stitchkin.StitchkinError) as e:
        model.fit_measured(f, [])
    assert "nothing to fit" in str(e.value)
    with pytest.raises(stitchkin.StitchkinError) as e:
        model.fit_measured(f"n7={f}", ["z"])
    assert "`n7`" in str(e.value) and "n1" in e.value.help
    with pytest.raises(stitchkin.StitchkinError) as e:
        model.fit_measured(f, ["z"], confidence=1.5)
    assert "confidence" in str(e.value)
    with pytest.raises(stitchkin.StitchkinError) as e:
        model.fit_measured([], ["z"])
    assert "no measured curve" in str(e.value)
    with pytest.raises(TypeError, match="measured is"):
        model.fit_measured(42, ["z"])
    with pytest.raises(TypeError, match="adjust is"):
        model.fit_measured(f, 3)
