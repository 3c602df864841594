"""Thermal compensation of a run and bias stability."""

from __future__ import annotations

import numpy as np
import pytest

from fogts.errors import DataError, InsufficientDataError
from fogts.io.run import Run
from fogts.startup.compensation import bias_stability, compensate
from fogts.startup.simulator import simulate_startup
from fogts.startup.thermal_fit import fit_thermal


def test_compensation_improves_bias_stability_on_held_out_run() -> None:
    cal = simulate_startup(rng=11)
    model = fit_thermal(cal.run.rate, cal.run.temperature, fs_hz=1.0)
    test = simulate_startup(rng=12, ambient_degC=23.0)
    before = bias_stability(test.run.rate, fs_hz=1.0, average_s=10)
    after = bias_stability(compensate(test.run, model).rate, fs_hz=1.0, average_s=10)
    assert before.average_s == after.average_s == 10.0
    assert before.value >= 2.0 * after.value     # >= 2x where drift dominates (~4x)


def test_compensate_keeps_reference_level_and_other_axes() -> None:
    cal = simulate_startup(rng=21, white_sigma_deg_h=0.05, arma_sigma_deg_h=0.01)
    model = fit_thermal(cal.run.rate, cal.run.temperature, fs_hz=1.0)
    out = compensate(cal.run, model)
    # the compensated rate sits at the steady-state (reference) drift level
    ref = model.reference_drift()
    assert abs(np.mean(out.rate[-600:]) - ref) < 0.05
    assert "compensated" in out.source
    two = Run(rate=np.column_stack([cal.run.rate, cal.run.rate]), time=cal.run.time, fs_hz=1.0,
              units="deg/h", axes=("x", "y"), temperature=cal.run.temperature)
    out2 = compensate(two, model, axis="y")
    np.testing.assert_allclose(out2.rate[:, 0], cal.run.rate)
    np.testing.assert_allclose(out2.rate[:, 1], out.rate)
    # a model in deg/h applied to a run in deg/s is converted
    run_s = Run(rate=cal.run.rate / 3600.0, time=cal.run.time, fs_hz=1.0, units="deg/s",
                axes=("g",), temperature=cal.run.temperature)
    np.testing.assert_allclose(compensate(run_s, model).rate * 3600.0, out.rate, atol=1e-9)


def test_bias_stability_states_averaging_time() -> None:
    x = np.random.default_rng(1).normal(0.0, 1.0, 36000) / 3600.0     # deg/s
    b = bias_stability(x, fs_hz=10.0, average_s=10.0, units="deg/s")
    assert b.unit == "deg/h" and b.n_windows == 360
    assert b.value == pytest.approx(1.0 / np.sqrt(100), rel=0.1)   # sigma / sqrt(samples)
    assert "10 s average" in b.summary() and b.to_dict()["average_s"] == 10.0


def test_bad_input() -> None:
    rng = np.random.default_rng(0)
    g = rng.standard_normal(500)
    temp = 20.0 + 10.0 * (1.0 - np.exp(-np.arange(500.0) / 200.0))
    run = Run(rate=g, time=np.arange(500.0), fs_hz=1.0, units="deg/h", axes=("g",),
              columns=("time", "g"))
    model = fit_thermal(g, temp, fs_hz=1.0, terms=("T", "1"))
    with pytest.raises(DataError, match="has no temperature column"):
        compensate(run, model)
    with pytest.raises(DataError, match="run must be a fogts Run"):
        compensate(g, model)  # type: ignore[arg-type]
    with pytest.raises(DataError, match="model must be a ThermalModel"):
        compensate(run, {"T": 1.0})  # type: ignore[arg-type]
    with pytest.raises(InsufficientDataError, match="at least two windows"):
        bias_stability(g[:15], fs_hz=1.0, average_s=10)
    with pytest.raises(DataError, match="shorter than one sample"):
        bias_stability(g, fs_hz=1.0, average_s=0.1)
