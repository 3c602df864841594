"""ARMA Kalman filter: against statsmodels' own SARIMAX filter, steady state vs exact."""

from __future__ import annotations

import numpy as np
import pandas as pd
import pytest
from scipy.signal import lfilter
from statsmodels.tsa.statespace.sarimax import SARIMAX

from fogts.errors import DataError, InsufficientDataError
from fogts.startup.kalman import arma_kalman, arma_state_space

AR = (1.2, -0.3)
MA = (0.4,)
S2 = 0.04
H = 0.25
PARAMS = {"ar.L1": AR[0], "ar.L2": AR[1], "ma.L1": MA[0], "sigma2": S2}


def _data(n: int, seed: int = 6) -> tuple[np.ndarray, np.ndarray]:
    """Known ARMA(2,1) drift plus white measurement noise."""
    rng = np.random.default_rng(seed)
    drift = lfilter([1.0, MA[0]], [1.0, -AR[0], -AR[1]], rng.normal(0, np.sqrt(S2), n + 500))[500:]
    return drift, drift + rng.normal(0.0, np.sqrt(H), n)


def test_matches_statsmodels_sarimax_filter_and_smoother() -> None:
    drift, y = _data(1500)
    res = arma_kalman(y, PARAMS, measurement_noise=H, method="exact", demean=False)
    ref = SARIMAX(y, order=(2, 0, 1), trend="n", measurement_error=True).smooth(
        [AR[0], AR[1], MA[0], H, S2])
    # the same state-space machinery: agreement to rounding, checked at 1e-8
    np.testing.assert_allclose(res.filtered, ref.filter_results.filtered_state[0], atol=1e-8)
    np.testing.assert_allclose(res.smoothed, ref.smoothed_state[0], atol=1e-8)
    np.testing.assert_allclose(res.predicted, ref.filter_results.forecasts[0], atol=1e-8)
    assert res.loglike == pytest.approx(ref.llf, abs=1e-6)
    # and it lowers the RMS error against the true drift
    rms_obs = np.sqrt(np.mean((y - drift) ** 2))
    rms_filt = np.sqrt(np.mean((res.filtered - drift) ** 2))
    rms_smooth = np.sqrt(np.mean((res.smoothed - drift) ** 2))
    assert rms_filt < 0.75 * rms_obs and rms_smooth < rms_filt


def test_steady_state_equals_exact_after_transient() -> None:
    _, y = _data(3000, seed=7)
    ex = arma_kalman(y, PARAMS, measurement_noise=H, method="exact")
    ss = arma_kalman(y, PARAMS, measurement_noise=H, method="steady-state")
    assert ss.method == "steady-state" and 0 < ss.n_transient < 200
    # exact over the transient, constant gain after it: agreement to 1e-8 everywhere
    # (set by the 1e-12 Riccati convergence tolerance)
    for name in ("filtered", "smoothed", "predicted"):
        np.testing.assert_allclose(getattr(ss, name), getattr(ex, name), atol=1e-8, err_msg=name)
    assert ss.loglike == pytest.approx(ex.loglike, abs=1e-6)


def test_estimated_measurement_noise_is_close_to_truth() -> None:
    _, y = _data(20000, seed=8)
    res = arma_kalman(y, PARAMS)                     # auto -> steady-state likelihood
    assert res.measurement_noise_source == "estimated" and res.method == "steady-state"
    assert res.measurement_noise == pytest.approx(H, rel=0.1)
    small = arma_kalman(y[:3000], PARAMS, method="exact")
    assert small.measurement_noise == pytest.approx(H, rel=0.2)


def test_model_fitted_to_observations_gives_zero_noise_note() -> None:
    rng = np.random.default_rng(3)
    y = lfilter([1.0], [1.0, -0.7], rng.standard_normal(2000))
    res = arma_kalman(y, {"ar.L1": 0.7, "sigma2": 1.0})
    assert res.measurement_noise < 0.05
    assert res.notes and "already explains" in res.notes[0] and "negligible" in res.notes[0]


def test_series_index_kept_and_model_objects_accepted() -> None:
    _, y = _data(400)
    idx = pd.date_range("2024-01-01", periods=y.size, freq="1s")
    s = pd.Series(y, index=idx)

    class Fit:  # duck-typed ArmaFit: ar, ma, sigma2
        ar = np.array(AR)
        ma = np.array(MA)
        sigma2 = S2

    class Selection:
        best = Fit()

    res = arma_kalman(s, Selection(), measurement_noise=H)
    assert isinstance(res.filtered, pd.Series) and res.filtered.index.equals(idx)
    assert res.to_frame().index.equals(idx)
    np.testing.assert_allclose(res.filtered, arma_kalman(y, PARAMS, measurement_noise=H).filtered)
    assert res.model == "ARMA(2,1)" and "ARMA(2,1)" in res.summary()
    assert res.to_dict()["measurement_noise"] == H


def test_state_space_matrices() -> None:
    ss = arma_state_space({"ar.L1": 0.5, "ma.L1": 0.3, "ma.L2": 0.1, "sigma2": 2.0})
    assert ss.T.tolist() == [[0.5, 1.0, 0.0], [0.0, 0.0, 1.0], [0.0, 0.0, 0.0]]
    assert ss.R.ravel().tolist() == [1.0, 0.3, 0.1] and ss.Z.ravel().tolist() == [1.0, 0.0, 0.0]


def test_bad_input() -> None:
    y = np.random.default_rng(0).standard_normal(100)
    with pytest.raises(DataError, match="not stationary"):
        arma_kalman(y, {"ar.L1": 1.01, "sigma2": 1.0})
    with pytest.raises(DataError, match="sigma2 must be a finite number > 0"):
        arma_kalman(y, {"ar.L1": 0.5, "sigma2": -1.0})
    with pytest.raises(DataError, match="statsmodels names"):
        arma_kalman(y, {"phi": 0.5})
    with pytest.raises(DataError, match="model must be an ArmaFit"):
        arma_kalman(y, 42)
    with pytest.raises(DataError, match="measurement_noise must be one of estimate"):
        arma_kalman(y, PARAMS, measurement_noise="guess")  # type: ignore[arg-type]
    with pytest.raises(DataError, match="measurement_noise must be a finite number >= 0"):
        arma_kalman(y, PARAMS, measurement_noise=-1.0)
    with pytest.raises(DataError, match="method must be one of auto"):
        arma_kalman(y, PARAMS, method="fast")  # type: ignore[arg-type]
    with pytest.raises(DataError, match="coefficients must be finite"):
        arma_kalman(y, {"ar.L1": float("nan"), "sigma2": 1.0})
    with pytest.raises(InsufficientDataError, match="at least 10"):
        arma_kalman(y[:5], PARAMS)


def test_auto_model_warnings_name_the_series() -> None:
    """A seasonal AR at lag 12 (x_t = 0.8 x_{t-12} + e_t): no low-order candidate whitens
    it, and the selection's NotWhiteWarning says which series it was about."""
    from fogts.errors import NotWhiteWarning
    from fogts.startup.kalman import resolve_arma_model

    e = np.random.default_rng(12).normal(size=3000)
    x = lfilter([1.0], np.r_[1.0, np.zeros(11), -0.8], e)
    with pytest.warns(NotWhiteWarning, match=r"^the temperature's EMD rest: no candidate "
                                             r"leaves white residuals"):
        resolve_arma_model(x, "auto", series="the temperature's EMD rest")
    with pytest.warns(NotWhiteWarning, match=r"^no candidate leaves white residuals"):
        resolve_arma_model(x, "auto")
