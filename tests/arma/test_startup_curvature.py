"""D's curvature from the start-up block (data-free) and the Newton path that uses it on long
series, against the path without it."""

from __future__ import annotations

import warnings

import numpy as np
import pytest

import fogts.arma.optimiser as optimiser
from fogts.arma.fit import fit_arma
from fogts.arma.likelihood import ExactLikelihood
from fogts.arma.startup_curvature import d_hessian


def test_d_hessian_of_an_ar1_is_that_of_its_first_variance() -> None:
    """AR(1) zero-mean: F_0 = 1 / (1 - phi^2) and F_t = 1 after, so D = -log(1 - phi^2)
    and D'' = 2 (1 + phi^2) / (1 - phi^2)^2 (Brockwell & Davis 1991, eq. 8.7.4); the
    central second difference (step at most 1 % of 1 - phi) is within 2e-4 of it
    relative (its Taylor remainder, see ``_steps``): 1e-3."""
    model = ExactLikelihood(np.random.default_rng(0).standard_normal(5000), 1, 0)
    for phi in (0.3, 0.99, 0.99999):
        ev = model.evaluate(np.array([phi]), np.zeros(0))
        want = 2.0 * (1.0 + phi * phi) / (1.0 - phi * phi) ** 2
        assert d_hessian(model, ev)[0, 0] == pytest.approx(want, rel=1e-3)


def _white_rw(n: int) -> np.ndarray:
    r = np.random.default_rng(900107)
    x = 0.1 * r.standard_normal(n) + np.cumsum(1e-4 * r.standard_normal(n))
    return np.asarray(x - x.mean())


def _fits(monkeypatch: pytest.MonkeyPatch, x: np.ndarray, p: int, q: int):  # type: ignore[no-untyped-def]
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        new = fit_arma(x, p, q, mean=True)
        monkeypatch.setattr(optimiser, "d_hessian", lambda model, ev: np.zeros((p + q,) * 2))
        old = fit_arma(x, p, q, mean=True)
    return new, old


@pytest.mark.slow
def test_long_series_reach_the_optimum_of_the_path_without_d_curvature(
        monkeypatch: pytest.MonkeyPatch) -> None:
    """1e6 samples (> 4 PRESAMPLE: the Newton Hessian has D's curvature).

    Identified ARMA(2,1), phi = (0.5, 0.2), theta = 0.5: D's curvature is O(1) against
    O(n), both paths stop at the same optimum to far below their 1e-6 stopping step
    (measured 1e-10 standard errors): 1e-6 standard errors and 1e-6 of AIC.

    White noise + rate random walk, ARMA(1,1): the optimum is within a few standard errors
    of a unit AR root (D ~ -log(1 - phi)); the old path crawls along that boundary, and
    both stop on an absolute 1e-6 step, 0.02 standard errors of theta here (se 4.6e-5):
    they agree to that stopping precision only, 0.05 standard errors, and the AIC to the
    fast path's acceptance against statsmodels (``fit_arma``: at most 0.05 worse)
    (measured 0.016 and 0.016; at 4e6 samples the new path's AIC is 0.08 the better).
    """
    from scipy.signal import lfilter

    e = np.random.default_rng(21).standard_normal(1_001_000)
    x = np.asarray(lfilter([1.0, 0.5], [1.0, -0.5, -0.2], e)[1000:])
    new, old = _fits(monkeypatch, x, 2, 1)
    for k, v in old.params.items():
        assert abs(new.params[k] - v) <= 1e-6 * old.bse[k], k
    assert new.aic == pytest.approx(old.aic, abs=1e-6)
    monkeypatch.undo()
    new, old = _fits(monkeypatch, _white_rw(1_000_000), 1, 1)
    for k, v in old.params.items():
        assert abs(new.params[k] - v) <= 0.05 * old.bse[k], k
    assert new.aic == pytest.approx(old.aic, abs=0.05)
    assert new.n_iter is not None and old.n_iter is not None and new.n_iter <= old.n_iter
