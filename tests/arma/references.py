"""statsmodels reference fits and the tolerances the ARMA fit tests hold fogts to.

* ``PARAM_TOL = 1e-4`` absolute on AR/MA coefficients wherever the model is identified and both
  fits reach the same optimum; sigma2 to ``1e-4`` relative.
* ``AIC_TOL = 0.05``: fogts' AIC is never worse than statsmodels' ``ARIMA(...).fit()`` on the
  standardised series by more than this.
* ``LLF_EXACT = 1e-6``: fogts' log-likelihood equals statsmodels' own ``loglike`` evaluated at
  fogts' parameters (the reported llf is the exact state-space likelihood).
* Standard errors: the observed information, as gretl and statsmodels ``cov_type="approx"``
  report; ``1e-3`` relative below 50,000 samples (finite-difference Hessian of the exact
  gradient), ``20/n`` relative for the analytic Hessian used above that.
* gretl (``arma_refs``): params ``1e-4``, llf ``1e-3``, bse ``3e-3`` relative.
"""

from __future__ import annotations

import warnings

import numpy as np
from statsmodels.tsa.arima.model import ARIMA

from fogts.arma.fit import ArmaFit
from tests.arma.simulated import arma_series

PARAM_TOL = 1e-4
AIC_TOL = 0.05
LLF_EXACT = 1e-6
CANDIDATES = [(1, 0), (2, 0), (3, 0), (1, 1), (2, 1)]


def simulate(ar: list[float], ma: list[float], n: int, seed: int, scale: float) -> np.ndarray:
    """x_t = sum ar_i x_{t-i} + a_t + sum ma_j a_{t-j}, a_t ~ N(0, scale^2), 500 burn-in."""
    return arma_series(ar, ma, n, seed, scale, burn=500)


def sm_fit(xs: np.ndarray, p: int, q: int, **kw):
    """statsmodels' reference fit on the standardised series (no covariance unless asked).

    ``low_memory=True`` only stops statsmodels from storing the filter output: the optimiser
    and its answer are the same."""
    kw.setdefault("cov_type", "none")
    kw.setdefault("low_memory", True)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return ARIMA(xs, order=(p, 0, q), trend="n").fit(**kw)


def near_redundant(ar: np.ndarray, ma: np.ndarray, gap: float = 0.15) -> bool:
    """An inverse AR root within ``gap`` of an inverse MA root (a near-common factor)."""
    if len(ar) == 0 or len(ma) == 0:
        return False
    ar_roots = np.roots(np.r_[1.0, -np.asarray(ar)])
    ma_roots = np.roots(np.r_[1.0, np.asarray(ma)])
    return bool(np.min(np.abs(ar_roots[:, None] - ma_roots[None, :])) < gap)


def sm_loglike(xs: np.ndarray, fit: ArmaFit) -> float:
    """statsmodels' exact log-likelihood of the standardised series at fogts' parameters."""
    params = np.r_[fit.ar, fit.ma, fit.sigma2 / fit.scale**2]
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return float(ARIMA(xs, order=(fit.p, 0, fit.q), trend="n").loglike(params))
