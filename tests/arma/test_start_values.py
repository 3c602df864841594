"""Hannan-Rissanen start values against statsmodels (AR least squares exactly, ARMA within
the two implementations' sampling differences) and the truth."""

from __future__ import annotations

import numpy as np
import pytest
from statsmodels.tsa.ar_model import AutoReg
from statsmodels.tsa.arima.estimators.hannan_rissanen import hannan_rissanen as sm_hr
from statsmodels.tsa.arima_process import ArmaProcess

from fogts.arma.start_values import START_SAMPLES, hannan_rissanen, normal_equations


def _arma(phi: list[float], theta: list[float], n: int, seed: int) -> np.ndarray:
    proc = ArmaProcess(ar=np.r_[1.0, -np.asarray(phi)], ma=np.r_[1.0, theta])
    return proc.generate_sample(n, distrvs=np.random.default_rng(seed).standard_normal,
                                burnin=500)


@pytest.mark.parametrize("p", [1, 2, 3])
def test_ar_is_statsmodels_conditional_least_squares(p: int) -> None:
    """A pure AR start is the least squares of x_t on its p lags, t >= p: statsmodels'
    ``AutoReg(trend="n")``; equal to 1e-10 (the same normal equations solved two ways)."""
    x = _arma([0.5, -0.2, 0.1][:p], [], 5000, 41 + p)
    phi, theta = hannan_rissanen(x, p, 0)
    ref = AutoReg(x, lags=p, trend="n").fit().params
    np.testing.assert_allclose(phi, ref, rtol=1e-10, atol=1e-12)
    assert theta.size == 0


def test_normal_equations_equal_lstsq_on_the_lag_matrix() -> None:
    """Two lagged regressors from two series: equal to numpy's least squares on the explicit
    design matrix to 1e-10 (rounding of X'X against QR)."""
    rng = np.random.default_rng(5)
    y, a = rng.standard_normal(2000), rng.standard_normal(2000)
    t0 = 3
    coef = normal_equations(y, [(y, 1), (a, 2)], t0)
    X = np.column_stack((y[t0 - 1:-1], a[t0 - 2:-2]))
    ref = np.linalg.lstsq(X, y[t0:], rcond=None)[0]
    np.testing.assert_allclose(coef, ref, rtol=1e-10)


@pytest.mark.parametrize(("phi", "theta"), [([0.7], [0.4]), ([0.5, 0.2], [-0.5])])
def test_arma_start_is_consistent(phi: list[float], theta: list[float]) -> None:
    """n = 1e5 ARMA data: the start values lie within 0.03 of the truth (their sampling sd is
    about 0.005-0.01 here) and within 0.03 of statsmodels' Hannan-Rissanen (which fits its
    long AR by least squares rather than Yule-Walker)."""
    x = _arma(phi, theta, 100_000, 77)
    got_phi, got_theta = hannan_rissanen(x, len(phi), len(theta))
    np.testing.assert_allclose(got_phi, phi, atol=0.03)
    np.testing.assert_allclose(got_theta, theta, atol=0.03)
    ref, _ = sm_hr(x, ar_order=len(phi), ma_order=len(theta), demean=False)
    np.testing.assert_allclose(got_phi, ref.ar_params, atol=0.03)
    np.testing.assert_allclose(got_theta, ref.ma_params, atol=0.03)


def test_only_the_first_samples_are_used() -> None:
    """Samples after START_SAMPLES never change the start values."""
    x = _arma([0.6], [0.3], START_SAMPLES + 1000, 9)
    y = x.copy()
    y[START_SAMPLES:] = 1e6
    for a, b in zip(hannan_rissanen(x, 1, 1), hannan_rissanen(y, 1, 1), strict=True):
        np.testing.assert_array_equal(a, b)


def test_an_explosive_estimate_is_shrunk_into_the_region() -> None:
    """A random walk's AR(1) least squares is ~1: the start is pulled inside 0.98."""
    x = np.cumsum(np.random.default_rng(3).standard_normal(3000))
    phi, _ = hannan_rissanen(x, 1, 0)
    assert abs(phi[0]) < 0.98 + 1e-12
