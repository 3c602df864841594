"""Tests of fogts.simulate.arma_series: ARMA series against statsmodels' theory."""

from __future__ import annotations

from types import SimpleNamespace

import numpy as np
import pandas as pd
import pytest
import statsmodels.tsa.arima_process as sm_arima

from fogts.arma.spec import ArmaSpec
from fogts.errors import DataError, FogtsWarning
from fogts.simulate.arma_series import simulate_arma
from fogts.simulate.gyro import simulate_gyro


def test_simulate_arma_matches_theoretical_acf() -> None:
    """ARMA(2,1) in statsmodels' sign convention: sample ACF vs arma_acf (statsmodels)."""
    ar, ma = [0.6, -0.3], [0.4]
    x = simulate_arma({"ar": ar, "ma": ma, "sigma2": 2.0}, 200_000, rng=1)
    acf = np.array([np.corrcoef(x[:-k], x[k:])[0, 1] for k in range(1, 6)])
    theory = sm_arima.arma_acf(np.r_[1, -np.array(ar)], np.r_[1, ma], lags=6)[1:]
    np.testing.assert_allclose(acf, theory, atol=0.012)  # ~5 sigma at n = 2e5
    var = sm_arima.arma_acovf(np.r_[1, -np.array(ar)], np.r_[1, ma], nobs=1, sigma2=2.0)[0]
    assert np.var(x) == pytest.approx(var, rel=0.03)


def test_simulate_arma_accepts_fits_and_param_names() -> None:
    fit = SimpleNamespace(ar=np.array([0.9]), ma=np.array([]),
                          params=pd.Series({"ar.L1": 0.9, "sigma2": 0.5}))
    selection = SimpleNamespace(best=fit)
    a = simulate_arma(fit, 1000, rng=3)
    b = simulate_arma(selection, 1000, rng=3)
    c = simulate_arma({"ar.L1": 0.9, "sigma2": 0.5}, 1000, rng=3)
    d = simulate_arma({"params": {"ar.L1": 0.9, "sigma2": 0.5}}, 1000, rng=3)
    e = simulate_arma("ar=0.9;sigma2=0.5", 1000, rng=3)
    f = simulate_arma(([0.9], [], 0.5), 1000, rng=3)
    for other in (b, c, d, e, f):
        np.testing.assert_array_equal(a, other)
    spec = ArmaSpec.from_any({"ar.L2": 0.1, "ma.L1": 0.2, "sigma2": 1, "const": 3.0})
    assert abs(np.mean(simulate_arma(spec, 20000, rng=1)) - 3.0) < 0.05
    white = simulate_arma({"sigma2": 4.0}, 50_000, rng=2)
    assert np.std(white) == pytest.approx(2.0, rel=0.02)


def test_simulate_arma_with_a_real_fit() -> None:
    from fogts.arma.fit import fit_arma

    x = simulate_arma({"ar": [0.7], "ma": [0.3], "sigma2": 1.0}, 3000, rng=4)
    fit = fit_arma(x, p=1, q=1)
    y = simulate_arma(fit, 3000, rng=5)
    assert y.shape == (3000,) and np.var(y) == pytest.approx(np.var(x), rel=0.15)


def test_simulate_arma_from_a_selection() -> None:
    """``Selection.best`` (fogts select) feeds simulate_arma directly."""
    from fogts.arma.select import select_arma

    x = simulate_arma({"ar": [0.8], "sigma2": 0.25}, 2000, rng=11)
    selection = select_arma(x)
    best = selection.best
    assert best is not None
    y = simulate_arma(selection, 50_000, rng=12)
    phi = np.corrcoef(y[:-1], y[1:])[0, 1]
    assert phi == pytest.approx(float(sm_arima.arma_acf(np.r_[1, -best.ar], np.r_[1, best.ma],
                                                        lags=2)[1]), abs=0.02)


def test_arma_added_to_gyro() -> None:
    run = simulate_gyro({}, fs_hz=10, duration_s=1000, rng=8, arma={"ar": [0.8], "sigma2": 1})
    assert np.var(run.rate) == pytest.approx(1 / (1 - 0.64), rel=0.1)
    assert "arma: ar=[0.8]" in run.comments[-1]


def test_simulate_arma_errors_and_warnings() -> None:
    with pytest.raises(DataError, match="n must be >= 1"):
        simulate_arma({"sigma2": 1}, 0)
    with pytest.raises(DataError, match="burn_in must be >= 0"):
        simulate_arma({"sigma2": 1}, 10, burn_in=-1)
    with pytest.warns(FogtsWarning, match="burn-in is capped"):
        simulate_arma({"ar": [0.9999999], "sigma2": 1}, 10, rng=0)
