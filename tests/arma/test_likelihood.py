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


@pytest.mark.parametrize(("n", "ar", "ma"), [
    (400, [0.6], []), (700, [0.5, 0.1], [-0.95]), (2000, [0.9], [-0.999]), (900, [], [0.3])])
def test_restricted_likelihood_and_gls_mean_against_dense_algebra(n: int, ar: list,
                                                                  ma: list) -> None:
    """With ``mean=True`` the objective is Harville's (1974) restricted likelihood and mu the
    GLS mean; reference: the same formulas with the dense covariance from statsmodels'
    ``arma_acovf`` and numpy's Cholesky (relative agreement 1e-9: rounding of an n x n
    solve; 2000 samples with an MA root at 0.999, whose innovations of the constant take
    ~30,000 steps to settle, also check the steady tail)."""
    from scipy.linalg import cho_factor, cho_solve, toeplitz
    from statsmodels.tsa.arima_process import arma_acovf

    x = simulate([0.6], [0.2], n, 21, 1.0) + 3.0
    phi, theta = np.array(ar, dtype=float), np.array(ma, dtype=float)
    model = ExactLikelihood(x, len(ar), len(ma), mean=True)
    ev = model.evaluate(phi, theta)
    R = toeplitz(arma_acovf(np.r_[1.0, -phi], np.r_[1.0, theta], nobs=n))
    cf = cho_factor(R, lower=True)
    ones = np.ones(n)
    r1, rx = cho_solve(cf, ones), cho_solve(cf, x)
    mu = float(ones @ rx / (ones @ r1))
    resid = x - mu
    S = float(resid @ cho_solve(cf, resid))
    logdet = 2.0 * float(np.sum(np.log(np.diag(cf[0]))))
    # profile of -2 l_R over sigma2 (up to constants): (n-1) log(S/(n-1)) + log|R| + log(1'R^-1 1 / n)
    ref = (n - 1) * np.log(S / (n - 1)) + logdet + np.log(ones @ r1 / n)
    assert ev.mu == pytest.approx(mu, rel=1e-9)
    assert ev.S == pytest.approx(S, rel=1e-9)
    assert ev.s11 == pytest.approx(float(ones @ r1), rel=1e-9)
    assert 2.0 * ev.f == pytest.approx(ref, rel=1e-9)
    # the innovations are those of x - mu (e.g. they give S)
    e = model.innovations(ev)
    assert float(np.sum(e[:ev.s] ** 2 / ev.F) + np.sum(e[ev.s:] ** 2)) == \
        pytest.approx(S, rel=1e-9)


@pytest.mark.parametrize(("ar_rest", "ma"), [([], [-0.9]), ([0.4], [-0.8])])
def test_restricted_likelihood_at_a_unit_root_is_the_differenced_likelihood(
        ar_rest: list, ma: list) -> None:
    """As an inverse AR root tends to 1 the restricted likelihood tends to the exact
    likelihood of the differenced series under ARMA(p - 1, q) plus log(n)/2 (the Jacobian of
    n - 1 differences against orthonormal contrasts): reference statsmodels' exact
    ``ARIMA(order=(p-1, 0, q), trend="n")`` log-likelihood of diff(x) at the same
    coefficients and sigma2.  Tolerance 1e-3 in the log-likelihood: at the inverse root
    1 - 1e-7 the limit is approached to O(n (1 - root)) = 1e-4."""
    from statsmodels.tsa.arima.model import ARIMA

    n = 1000
    x = np.cumsum(simulate(ar_rest, ma, n, 5, 1.0)) + 4.0
    rest, theta = np.array(ar_rest, dtype=float), np.array(ma, dtype=float)
    phi = -np.poly(np.r_[np.roots(np.r_[1.0, -rest]), 1.0 - 1e-7])[1:]
    model = ExactLikelihood(x, phi.size, theta.size, mean=True)
    ev = model.evaluate(phi, theta)
    sigma2 = ev.S / model.nu
    llf_r = -0.5 * (model.nu * np.log(2 * np.pi * sigma2) + ev.S / sigma2 + ev.D)
    d = np.diff(x)
    ref = ARIMA(d, order=(rest.size, 0, theta.size), trend="n").smooth(
        np.r_[rest, theta, sigma2]).llf
    assert llf_r == pytest.approx(ref + 0.5 * np.log(n), abs=1e-3)
