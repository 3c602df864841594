"""Tests of fogts.simulate.gyro: the simulated record, its axes, units and argument checks."""

from __future__ import annotations

import math

import numpy as np
import pytest

from fogts.errors import DataError
from fogts.simulate.gyro import simulate_gyro
from fogts.units import parse_duration


def test_units_conversion_and_bias() -> None:
    spec = {"N": 0.01, "bias": 15.0}
    dph = simulate_gyro(spec, fs_hz=10, duration_s=60, rng=3)
    dps = simulate_gyro(spec, fs_hz=10, duration_s=60, rng=3, units="deg/s")
    assert dps.units == "deg/s"
    np.testing.assert_allclose(dps.rate * 3600.0, dph.rate, rtol=1e-12)
    sd = 0.01 * 60 * math.sqrt(10)  # white-noise sd per sample in deg/h
    assert abs(np.mean(dph.rate) - 15.0) < 4 * sd / math.sqrt(dph.n)


def test_multi_axis_names_and_independence() -> None:
    run = simulate_gyro({"N": 0.01}, fs_hz=10, duration_s=1000, rng=1, n_axes=3)
    assert run.axes == ("rate_x", "rate_y", "rate_z") and run.rate.shape == (10000, 3)
    corr = np.corrcoef(run.rate.T)
    assert np.all(np.abs(corr[np.triu_indices(3, 1)]) < 0.05)  # 5 sigma at n = 1e4
    frame = run.to_frame()
    assert list(frame.columns) == ["time", "rate_x", "rate_y", "rate_z"]
    per_axis = simulate_gyro([{"N": 0.01}, {"N": 0.04}], fs_hz=10, duration_s=1000, rng=1)
    ratio = np.std(per_axis.rate[:, 1]) / np.std(per_axis.rate[:, 0])
    assert per_axis.axes == ("rate_x", "rate_y") and abs(ratio - 4.0) < 0.2
    many = simulate_gyro({"N": 0.01}, fs_hz=10, duration_s=10, rng=1, n_axes=4)
    assert many.axes == ("rate_1", "rate_2", "rate_3", "rate_4")


def test_run_record_fields() -> None:
    run = simulate_gyro({"N": 0.002, "B": 0.005}, fs_hz=10, duration_s="90min", rng=2)
    assert run.n == 54000 and run.fs_hz == 10.0 and run.axes == ("rate",)
    np.testing.assert_allclose(run.time[:3], [0.0, 0.1, 0.2])
    assert run.sampling is not None and run.sampling.regular
    assert run.columns == ("time", "rate") and run.temperature is None
    assert "N=0.002 deg/sqrt(h)" in run.comments[1]


# --------------------------------------------------------------------------- simulate_gyro errors
@pytest.mark.parametrize("kwargs, match", [
    ({"fs_hz": -1}, "fs_hz must be a finite number > 0"),
    ({"duration_s": "3 parsecs"}, "unknown unit 'parsecs'"),
    ({"duration_s": 0.01}, "at least 2 samples"),
    ({"units": "furlongs"}, "units must be one of"),
    ({"flicker": "pink"}, "flicker must be one of markov, kasdin"),
    ({"chunk_size": 0}, "chunk_size must be >= 1"),
    ({"n_axes": 0}, "n_axes must be >= 1"),
    ({"rng": "seed"}, "rng must be a numpy Generator"),
    ({"thermal_coefficients": {"T": 1.0}}, "need a temperature profile"),
    ({"thermal_coefficients": [1.0], "temperature": "constant:20"}, "must be a mapping"),
    ({"temperature": np.ones(3)}, "one value per sample"),
    ({"temperature": np.full(100, np.nan)}, "non-finite"),
    ({"temperature": "constant:20", "thermal_coefficients": {"T3": 1.0}},
     "thermal coefficient names must be among"),
])
def test_simulate_gyro_errors(kwargs: dict, match: str) -> None:
    args = {"fs_hz": 10.0, "duration_s": 10.0, "rng": 0} | kwargs
    with pytest.raises(DataError, match=match):
        simulate_gyro({"N": 0.01}, **args)


def test_simulate_gyro_spec_errors() -> None:
    with pytest.raises(DataError, match="below the Nyquist frequency"):
        simulate_gyro({"Omega_0": 1, "f_0": 5}, fs_hz=10, duration_s=10)
    with pytest.raises(DataError, match="does not match the 2 noise"):
        simulate_gyro([{"N": 1}, {"N": 2}], fs_hz=10, duration_s=10, n_axes=3)
    with pytest.raises(DataError, match="at least one axis"):
        simulate_gyro([], fs_hz=10, duration_s=10)


# --------------------------------------------------------------------------- durations
@pytest.mark.parametrize("text, seconds", [
    ("3h", 10800.0), ("90min", 5400.0), ("600s", 600.0), ("1d", 86400.0), ("250ms", 0.25),
    ("1h30min", 5400.0), ("1.5 h", 5400.0), ("42", 42.0), (7, 7.0), ("2 hours", 7200.0),
])
def test_parse_duration(text: str, seconds: float) -> None:
    assert parse_duration(text) == pytest.approx(seconds)


@pytest.mark.parametrize("text, match", [
    ("3m", "unknown unit 'm'"), ("abc", "must look like 3h"), ("", "must look like 3h"),
    ("0s", "must be > 0"), ("3h junk", "must look like"), ("1h 2", "must look like"),
])
def test_parse_duration_errors(text: str, match: str) -> None:
    with pytest.raises(DataError, match=match):
        parse_duration(text)
