"""One-step-ahead prediction: equal to statsmodels' get_prediction, index kept, lfilter path.

Tolerances: predictions equal statsmodels' Kalman one-step predictions at the same
parameters to 1e-8 relative to the series' scale (exact-likelihood innovations on both sides).
"""

from __future__ import annotations

import numpy as np
import pandas as pd
import pytest
from statsmodels.tsa.arima.model import ARIMA

from fogts.arma import one_step_prediction, predict_arma, select_arma
from fogts.errors import DataError
from tests.arma.simulated import arma_series


def _arma(ar: list[float], ma: list[float], n: int, seed: int, scale: float = 1.0) -> np.ndarray:
    return arma_series(ar, ma, n, seed, scale, burn=1000)


@pytest.mark.parametrize("method", ["fast", "statsmodels"])
def test_prediction_equals_statsmodels_get_prediction(method: str) -> None:
    x = _arma([0.5, -0.2], [0.4], 300, 5, scale=1e-3)
    x = x - x.mean()
    s = float(np.std(x))
    sel = select_arma(x, candidates="AR(1),AR(2),ARMA(1,1),ARMA(2,1)",
                      method=method)  # type: ignore[arg-type]
    for c in sel.candidates:
        pred = c.predict()
        # statsmodels' Kalman filter at fogts' parameters.  It runs on x / std(x): on the raw
        # series (variance 1e-6) statsmodels' own filter is off by ~3e-4 of the scale (its
        # steady-state tolerance is absolute), while fogts matches the dense Cholesky below.
        # select_arma estimates the mean (GLS): statsmodels' trend="c" with it as const
        res = ARIMA(x / s, order=(c.p, 0, c.q), trend="c").filter(
            np.r_[c.params["mean"] / s, c.ar, c.ma, c.sigma2 / s**2])
        ref = np.asarray(res.get_prediction().predicted_mean) * s
        assert np.allclose(pred.predicted, ref, rtol=0, atol=1e-8 * s), c.model
        assert np.allclose(pred.residual, x - ref, rtol=0, atol=1e-8 * s)
        assert np.allclose(pred.observed, x, rtol=0, atol=1e-15 * s)   # demeaned again


def test_innovations_equal_dense_cholesky() -> None:
    # exact innovations of the Gaussian likelihood: x = L e with Gamma = L D L' (Brockwell &
    # Davis, sec. 5.2), computed densely from statsmodels' ARMA autocovariances
    from scipy.linalg import cholesky, solve_triangular, toeplitz
    from statsmodels.tsa.arima_process import ArmaProcess

    x = _arma([0.5, -0.2], [0.4], 300, 5, scale=1e-3)
    x = x - x.mean()
    sel = select_arma(x, candidates="ARMA(2,1)")
    c = sel.best
    assert c is not None
    gamma = toeplitz(ArmaProcess(np.r_[1.0, -c.ar], np.r_[1.0, c.ma]).acovf(x.size)) * c.sigma2
    chol = cholesky(gamma, lower=True)
    exact = solve_triangular(chol, x - c.params["mean"], lower=True) * np.diag(chol)
    assert np.allclose(c.predict().residual, exact, rtol=0, atol=1e-10 * np.std(x))


def test_prediction_matches_statsmodels_own_fit() -> None:
    # statsmodels' own optimum on the standardised series, scaled back (the "statsmodels"
    # path: select_arma's default maximises the restricted likelihood, whose coefficients
    # differ from ML ones by O(1/n))
    x = _arma([0.6], [0.3], 400, 2, scale=1e-3)
    x = x - x.mean()
    s = float(np.std(x))
    sel = select_arma(x, candidates="ARMA(1,1)", method="statsmodels")
    res = ARIMA(x / s, order=(1, 0, 1), trend="c").fit()
    ref = np.asarray(res.get_prediction().predicted_mean) * s
    assert sel.best is not None
    assert np.allclose(sel.best.predict().predicted, ref, rtol=0, atol=1e-3 * s)


def test_prediction_keeps_series_index_and_time() -> None:
    idx = pd.date_range("2024-05-01 12:00", periods=2000, freq="100ms", name="stamp")
    x = pd.Series(_arma([0.7], [], 2000, 1), index=idx)
    sel = select_arma(x, candidates="AR(1)", fs_hz=10.0)
    assert sel.best is not None
    pred = sel.best.predict()
    frame = pred.to_frame()
    assert frame.index.equals(idx)
    assert list(frame.columns) == ["time", "observed", "predicted", "residual"]
    assert frame["time"].iloc[10] == pytest.approx(1.0)
    assert np.allclose(frame["observed"] - frame["predicted"], frame["residual"], atol=1e-15)


def test_variance_removed() -> None:
    x = _arma([0.8], [], 20_000, 3)
    sel = select_arma(x, candidates="AR(1)")
    assert sel.best is not None
    pred = sel.best.predict()
    expected = 1.0 - np.var(pred.residual) / np.var(pred.observed)
    assert pred.variance_removed == pytest.approx(expected, rel=1e-12)
    assert pred.variance_removed == pytest.approx(0.64, abs=0.03)   # phi^2 for AR(1)
    d = pred.to_dict()
    assert d["variance_removed"] == pred.variance_removed and d["n"] == 20_000
    assert "% of the variance removed" in pred.summary()


def test_predict_arma_on_new_data_is_the_arma_recursion() -> None:
    x = _arma([0.5], [0.3], 500, 4)
    phi, theta = 0.5, 0.3
    a = np.zeros_like(x)
    for t in range(x.size):   # a_t = x_t - phi x_{t-1} - theta a_{t-1}, zero pre-sample values
        a[t] = x[t] - (phi * x[t - 1] if t else 0.0) - (theta * a[t - 1] if t else 0.0)
    pred = predict_arma(x, ar=[phi], ma=[theta], model="ARMA(1,1)")
    assert pred.method == "conditional"
    assert np.allclose(pred.residual, a, rtol=0, atol=1e-12)
    assert np.allclose(pred.predicted, x - a, rtol=0, atol=1e-12)


def test_candidate_predict_on_new_data_converges_to_exact() -> None:
    x = _arma([0.6], [0.3], 3000, 6)
    sel = select_arma(x, candidates="ARMA(1,1)")
    assert sel.best is not None
    exact = sel.best.predict()
    mean = sel.best.params["mean"]       # the GLS mean of the demeaned series
    cond = sel.best.predict(x - np.mean(x) - mean)
    assert cond.method == "conditional"
    # after the start-up the conditional recursion equals the exact innovations
    assert np.allclose(cond.predicted[100:] + mean, exact.predicted[100:], rtol=0, atol=1e-10)


def test_one_step_prediction_and_errors() -> None:
    p = one_step_prediction(pd.Series([1.0, 2.0, 3.0], index=[10, 20, 30]), [1.0, 0.5, 0.5])
    assert p.predicted.tolist() == [0.0, 1.5, 2.5] and list(p.to_frame().index) == [10, 20, 30]
    assert list(p.to_frame().columns) == ["observed", "predicted", "residual"]
    with pytest.raises(DataError, match="innovations must have the same length as observed .3., "
                                        "got 2"):
        one_step_prediction([1.0, 2.0, 3.0], [1.0, 2.0])
    with pytest.raises(DataError, match="time must have the same length as observed .3., got 2"):
        one_step_prediction([1.0, 2.0, 3.0], [1.0, 2.0, 3.0], time=[0.0, 1.0])
    with pytest.raises(DataError, match="index must have the same length as observed .3., got 2"):
        one_step_prediction([1.0, 2.0, 3.0], [1.0, 2.0, 3.0], index=pd.Index([1, 2]))
    with pytest.raises(DataError, match=r"ma=\[1.5\] is not invertible"):
        predict_arma([1.0, 2.0, 3.0], ma=[1.5])
    with pytest.raises(DataError, match="ar and ma must be finite"):
        predict_arma([1.0, 2.0, 3.0], ar=[np.nan])
    with pytest.raises(DataError, match="time must have the same length as x .3., got 1"):
        predict_arma([1.0, 2.0, 3.0], ar=[0.5], time=[0.0])
