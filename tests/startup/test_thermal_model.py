"""Thermal drift model: the temperature rate, the regressors, and the model's evaluation,
serialisation and bad inputs."""

from __future__ import annotations

import json

import numpy as np
import pandas as pd
import pytest

from fogts.errors import DataError
from fogts.startup.simulator import simulate_startup, warmup_temperature
from fogts.startup.thermal_fit import fit_thermal
from fogts.startup.thermal_model import ThermalModel, design_matrix, temperature_rate


def test_model_round_trips_through_json() -> None:
    sim = simulate_startup(rng=5)
    m = fit_thermal(pd.Series(sim.run.rate), sim.run.temperature, fs_hz=1.0)
    assert isinstance(m.residual, pd.Series)
    text = json.dumps(m.to_dict())
    back = ThermalModel.from_dict(json.loads(text))
    assert back.coefficients == m.coefficients and back.terms == m.terms
    np.testing.assert_allclose(back.predict(sim.run.temperature), m.predict(sim.run.temperature))
    assert "T·ΔT" in m.equation() and "R²" in m.summary()
    assert list(m.to_frame().index) == list(m.terms)


def test_temperature_rate_and_warmup_profile() -> None:
    t = np.arange(3600.0)
    temp, rate = warmup_temperature(t, peak_rate_degC_s=0.05)
    assert rate.max() == pytest.approx(0.05, rel=1e-4)   # peak between 1 s samples
    est = temperature_rate(temp, fs_hz=1.0, smoothing_s=11)
    assert np.max(np.abs(est - rate)[30:-30]) < 1e-4      # measured 6e-5 (curvature bias)
    assert np.all(temperature_rate(np.full(50, 25.0), fs_hz=1.0) == 0.0)


def test_design_matrix_columns() -> None:
    cols = design_matrix(np.array([20.0, 30.0]), np.array([0.1, -0.2]),
                         ["T*dT", "T2", "T", "dT2", "dT", "1"])
    np.testing.assert_allclose(cols, [[2.0, 400.0, 20.0, 0.01, 0.1, 1.0],
                                      [-6.0, 900.0, 30.0, 0.04, -0.2, 1.0]])
    assert design_matrix(np.zeros(3), np.zeros(3), []).shape == (3, 0)


def test_bad_input() -> None:
    rng = np.random.default_rng(0)
    g = rng.standard_normal(500)
    temp = 20.0 + 10.0 * (1.0 - np.exp(-np.arange(500.0) / 200.0))
    model = fit_thermal(g, temp, fs_hz=1.0, terms=("T", "1"))
    with pytest.raises(DataError, match="needs the keys 'terms' and 'units'"):
        ThermalModel.from_dict({"r2": 1.0})
    with pytest.raises(DataError, match="unknown thermal term 'T3'"):
        ThermalModel.from_dict({"terms": {"T3": {"value": 1.0}}, "units": "deg/h"})
    with pytest.raises(DataError, match="malformed thermal model"):
        ThermalModel.from_dict({"terms": {"T": {"stderr": 1.0}}, "units": "deg/h"})
    with pytest.raises(DataError, match="'terms' must map"):
        ThermalModel.from_dict({"terms": [1, 2], "units": "deg/h"})
    with pytest.raises(DataError, match="temperature_rate_degC_s has 3 samples"):
        model.predict(temp, temperature_rate_degC_s=[0.0, 0.0, 0.0])
