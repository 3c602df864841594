"""Tests of fogts.simulate.temperature: profiles and the thermal drift they drive."""

from __future__ import annotations

import math

import numpy as np
import pytest

from fogts.errors import DataError, InsufficientDataError
from fogts.simulate.gyro import simulate_gyro
from fogts.simulate.temperature import TemperatureProfile, thermal_drift


def test_temperature_hook_adds_the_thermal_model() -> None:
    coef = {"T": 0.02, "dT": 40.0, "T2": -1e-4, "1": 0.3}
    profile = "warmup:20,30,10min"
    base = simulate_gyro({"N": 0.01}, fs_hz=10, duration_s=3600, rng=4, temperature=profile)
    hot = simulate_gyro({"N": 0.01}, fs_hz=10, duration_s=3600, rng=4, temperature=profile,
                        thermal_coefficients=coef)
    assert hot.temperature is not None and hot.columns[-1] == "temperature"
    assert hot.temperature[0] == pytest.approx(20.0)
    assert hot.temperature[-1] == pytest.approx(30.0 - 10.0 * math.exp(-3599.9 / 600), rel=1e-9)
    drift = thermal_drift(hot.temperature, coef, fs_hz=10)
    np.testing.assert_allclose(hot.rate - base.rate, drift, atol=1e-12)
    # closed form of the regressors at t = 0: dT = 10/600 degC/s
    assert drift[0] == pytest.approx(0.02 * 20 + 40 * 10 / 600 - 1e-4 * 400 + 0.3, rel=1e-3)
    arr = simulate_gyro({}, fs_hz=10, duration_s=10, rng=4,
                        temperature=np.full(100, 25.0), thermal_coefficients={"T": 1.0})
    np.testing.assert_allclose(arr.rate, 25.0)
    fn = simulate_gyro({"N": 0.01}, fs_hz=10, duration_s=10, rng=4,
                       temperature=lambda t: 20 + t / 10)
    assert fn.temperature is not None and fn.temperature[-1] == pytest.approx(20.99)


def test_temperature_profiles() -> None:
    t = np.array([0.0, 1800.0, 3600.0])
    assert TemperatureProfile.parse("constant:25").evaluate(t, duration_s=3600).tolist() == \
        [25.0] * 3
    assert TemperatureProfile.parse("ramp:20,26").evaluate(t, duration_s=3600).tolist() == \
        [20.0, 23.0, 26.0]
    warm = TemperatureProfile.parse("warmup:20, 30, 30min")
    assert warm.time_constant_s == 1800.0
    assert warm.to_dict()["kind"] == "warmup"
    for bad in ("warmup:20,30", "sine:1,2", "ramp:a,b", "constant:-300"):
        with pytest.raises(DataError, match="temperature"):
            TemperatureProfile.parse(bad)
    with pytest.raises(DataError, match="time constant"):
        TemperatureProfile("warmup", 20.0, 30.0, -5.0)


def test_thermal_drift_errors() -> None:
    with pytest.raises(InsufficientDataError, match="temperature needs at least 5 samples"):
        thermal_drift([1.0], {"T": 1.0}, fs_hz=1)
    with pytest.raises(DataError, match="thermal coefficient 'T' must be finite"):
        thermal_drift(np.ones(9), {"T": float("nan")}, fs_hz=1)
