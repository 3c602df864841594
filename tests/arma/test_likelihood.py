"""The exact likelihood's innovations against statsmodels' Kalman filter, and its failures."""

from __future__ import annotations

import warnings

import numpy as np
import pytest
from statsmodels.tsa.arima.model import ARIMA

from fogts.arma.fit import fit_arma
from fogts.arma.likelihood import ExactLikelihood
from fogts.errors import ModelFitError
from tests.arma.references import (
    simulate,
)


def test_resid_are_statsmodels_innovations() -> None:
    x = simulate([0.8], [0.4], 700, 5, 1e-3)
    fit = fit_arma(x, 1, 1)
    xs = x / fit.scale
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        res = ARIMA(xs, order=(1, 0, 1), trend="n").filter(
            np.r_[fit.ar, fit.ma, fit.sigma2 / fit.scale**2])
    np.testing.assert_allclose(fit.resid, res.resid * fit.scale, rtol=0, atol=1e-9 * fit.scale)
    assert fit.resid.shape == (700,)


def test_nonstationary_covariance_is_a_fit_error() -> None:
    model = ExactLikelihood(np.random.default_rng(0).standard_normal(600), 1, 0)
    with pytest.raises(ModelFitError, match="not positive definite"):
        model.transient(np.array([[1.5]]), np.zeros((1, 0)))


def test_nonfinite_likelihood_is_a_fit_error() -> None:
    model = ExactLikelihood(np.full(600, 1e200), 1, 0)
    with np.errstate(over="ignore", invalid="ignore"), \
            pytest.raises(ModelFitError, match="likelihood is not finite"):
        model.evaluate(np.array([0.5]), np.zeros(0))
