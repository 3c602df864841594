"""The AR(p) likelihood from sufficient statistics against the general exact likelihood.

Tolerances: S, D and the GLS mean are the same sums formed in another order, so they agree to
rounding (1e-12 relative here: the cancellation in beta' D beta is below 1e2 on these series);
the fits agree in AIC to rounding and in the parameters far inside their standard errors
(both optimisers stop within 1e-6 of the optimum's position in SE units).  The standard
errors agree to 1e-6 where the general path takes exact Hessians (n <= 5e4); above, its
analytic Hessian drops O(1) start-up terms of O(n) sums and D's curvature (up to 4e5
samples), which near a unit root (phi = 0.995) is a relative 1e-3.
"""

from __future__ import annotations

import numpy as np
import pytest
from scipy.signal import lfilter

import fogts.arma.fit as fitmod
from fogts.arma.ar_exact import ar_statistics, log_det_gamma, maximise_ar, objective
from fogts.arma.correlation import lag_products
from fogts.arma.likelihood import ExactLikelihood
from fogts.arma.startup_block import banded_innovations

CASES = [[0.6], [0.5, 0.2], [0.4, 0.2, -0.3], [0.995]]


def _series(ar: list[float], n: int, seed: int) -> np.ndarray:
    e = np.random.default_rng(seed).standard_normal(n)
    return lfilter([1.0], np.r_[1.0, -np.array(ar)], e) * 3.0 + 10.0


@pytest.mark.parametrize("ar", CASES)
@pytest.mark.parametrize("mean", [False, True])
def test_objective_matches_exact_likelihood(ar: list[float], mean: bool) -> None:
    p = len(ar)
    y = _series(ar, 5000, 11) - 10.0
    st = ar_statistics(lag_products(y, p), float(np.sum(y)), y[:p], y[-p:], y.size)
    phi = 0.97 * np.array(ar)
    ev = ExactLikelihood(y, p, 0, mean=mean).evaluate(phi, np.zeros(0))
    ob = objective(st, phi, mean)
    assert ob.S == pytest.approx(ev.S, rel=1e-12)
    assert ob.D == pytest.approx(ev.D, rel=1e-12, abs=1e-12)
    assert ob.mu == pytest.approx(ev.mu, rel=1e-10, abs=1e-14)
    assert ob.f == pytest.approx(ev.f, rel=1e-12)


@pytest.mark.parametrize("ar", CASES)
def test_log_det_gamma_is_the_start_up_blocks(ar: list[float]) -> None:
    phi = np.array(ar)
    _, F, _ = banded_innovations(phi, np.zeros(0), np.zeros(64))
    assert log_det_gamma(phi) == pytest.approx(float(np.sum(np.log(F))), rel=1e-12)
    assert log_det_gamma(np.array([1.0])) == np.inf


def test_newton_reaches_a_zero_gradient() -> None:
    y = _series([0.5, 0.2], 20_000, 3)
    y = y - y.mean()
    st = ar_statistics(lag_products(y, 2), float(np.sum(y)), y[:2], y[-2:], y.size)
    ob, n_iter, converged = maximise_ar(st, True)
    assert converged and n_iter <= 6
    assert np.max(np.abs(ob.grad)) < 1e-6


def _both(monkeypatch: pytest.MonkeyPatch, x: np.ndarray, p: int, mean: bool):
    monkeypatch.setattr(fitmod, "BLOCKWISE_MIN_N", 1000)
    fast = fitmod.fit_arma(x, p, 0, mean=mean)
    monkeypatch.setattr(fitmod, "fit_exact_ar", lambda *a, **k: None)
    general = fitmod.fit_arma(x, p, 0, mean=mean)
    return fast, general


@pytest.mark.parametrize("n, se_rel", [(10_000, 1e-6), (30_000, 1e-6), (100_000, 2e-3)])
@pytest.mark.parametrize("ar", CASES)
@pytest.mark.parametrize("mean", [False, True])
def test_fit_matches_the_general_path(monkeypatch: pytest.MonkeyPatch, n: int, se_rel: float,
                                      ar: list[float], mean: bool) -> None:
    x = _series(ar, n, 900 + n // 1000)
    fast, general = _both(monkeypatch, x, len(ar), mean)
    assert fast.converged and general.converged
    assert fast.aic == pytest.approx(general.aic, rel=1e-12)
    for k, v in general.params.items():
        assert abs(fast.params[k] - v) <= 1e-5 * general.bse[k]
        assert fast.bse[k] == pytest.approx(general.bse[k], rel=se_rel)
    np.testing.assert_allclose(fast.resid, general.resid, rtol=0, atol=1e-6 * x.std())
