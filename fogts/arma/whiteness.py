"""Whiteness checks of ARMA residuals: rho_a,2, rho_ax,3 and the Ljung-Box test.

Definitions (t counts from 1; both sums of a statistic run over the same t), each judged
against the band +-1.96/sqrt(n), n the number of residuals:

* rho_a,2  = sum_{t=3}^{n} a_t a_{t-2} / sum_{t=3}^{n} a_t^2  (drift paper, eq. 11);
* rho_ax,3 = sum_{t=4}^{n} a_t x_{t-3} / sqrt(sum_{t=4}^{n} a_t^2 * sum_{t=4}^{n} x_{t-3}^2)
  (drift paper, eq. 12);
* Ljung-Box (Ljung & Box 1978): Q(h) = n (n + 2) sum_{k=1}^{h} r_k^2 / (n - k), r_k the
  demeaned, biased residual autocorrelation, p = P(chi^2_{h - model_df} > Q) with
  ``model_df = p + q``; equal to ``statsmodels.stats.diagnostic.acorr_ljungbox(resid, lags,
  model_df=p+q)``, with r_k from :func:`fogts.arma.correlation.autocorrelation` instead of
  statsmodels' direct O(n^2) correlation.

The residuals are **white** when all three pass: |rho_a,2| and |rho_ax,3| <= 1.96/sqrt(n), and
the Ljung-Box p-value >= 0.05 at every requested lag (a lag h <= p + q has no degrees of
freedom and cannot be tested; if no lag is testable the residuals are not called white).

References
----------
G. M. Ljung and G. E. P. Box, "On a measure of lack of fit in time series models",
Biometrika 65 (1978) 297-303.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
import pandas as pd

from fogts._typing import FloatArray
from fogts._validate import check_int, to_float_array
from fogts.arma.correlation import autocorrelation, dot, lag_products
from fogts.errors import DataError, InsufficientDataError

__all__ = ["BAND_Z", "LB_ALPHA", "CorrelationCheck", "LjungBoxLag", "ResidualDiagnostics",
           "ljung_box", "residual_diagnostics", "rho_a2", "rho_ax3"]

#: Two-sided 95 % normal quantile used for every band and t-test.
BAND_Z = 1.96
#: Significance level of the Ljung-Box test.
LB_ALPHA = 0.05
_BLOCK = 1 << 16      # samples per block of the offset series' sums


def rho_a2(a: FloatArray) -> float:
    """Drift paper, eq. 11: rho_a,2 = sum_{t=3}^{n} a_t a_{t-2} / sum_{t=3}^{n} a_t^2.

    Examples
    --------
    >>> rho_a2(np.array([1.0, -1.0, 1.0, -1.0]))
    1.0
    """
    num = dot(a[2:], a[:-2])
    den = dot(a[2:], a[2:])
    return num / den if den > 0 else math.nan


def rho_ax3(a: FloatArray, x: FloatArray) -> float:
    """Drift paper, eq. 12: rho_ax,3 = sum a_t x_{t-3} / sqrt(sum a_t^2 * sum x_{t-3}^2), t >= 4.

    Examples
    --------
    >>> rho_ax3(np.array([0.0, 0.0, 0.0, 1.0, 2.0]), np.array([1.0, 2.0, 5.0, 5.0, 5.0]))
    1.0
    """
    num = dot(a[3:], x[:-3])
    den = math.sqrt(dot(a[3:], a[3:]) * dot(x[:-3], x[:-3]))
    return num / den if den > 0 else math.nan


def _rho_ax3_offset(a: FloatArray, x: FloatArray, offset: float) -> float:
    """:func:`rho_ax3` of ``a`` and ``x - offset``, the subtraction block by block (the same
    values as on the subtracted array; the sums accumulated per block)."""
    n = a.shape[0]
    num = sxx = 0.0
    for c0 in range(0, n - 3, _BLOCK):
        c1 = min(n - 3, c0 + _BLOCK)
        seg = x[c0:c1] - offset
        num += dot(a[c0 + 3:c1 + 3], seg)
        sxx += dot(seg, seg)
    den = math.sqrt(dot(a[3:], a[3:]) * sxx)
    return num / den if den > 0 else math.nan


@dataclass(frozen=True)
class CorrelationCheck:
    """One residual correlation statistic judged against +-``band``.

    Attributes
    ----------
    name : str
        ``"rho_a2"`` (drift paper, eq. 11) or ``"rho_ax3"`` (eq. 12).
    value : float
    band : float
        ``1.96 / sqrt(n)``.
    passed : bool
        ``|value| <= band``.
    """

    name: str
    value: float
    band: float
    passed: bool

    def to_dict(self) -> dict[str, Any]:
        return {"name": self.name, "value": self.value, "band": self.band, "pass": self.passed}


@dataclass(frozen=True)
class LjungBoxLag:
    """Ljung-Box Q at one lag: ``df = lag - model_df``; p is NaN and ``passed`` None if df <= 0."""

    lag: int
    q: float
    pvalue: float
    df: int
    passed: bool | None

    def to_dict(self) -> dict[str, Any]:
        return {"lag": self.lag, "q": self.q, "pvalue": self.pvalue, "df": self.df,
                "pass": self.passed}


@dataclass(frozen=True)
class ResidualDiagnostics:
    """Whiteness checks of one candidate's residuals (see the module docstring).

    Attributes
    ----------
    n : int
        Number of residuals.
    mean, variance : float
        Residual mean and variance (``ddof=0``).
    rho_a2, rho_ax3 : CorrelationCheck
        Drift paper, eqs. 11 and 12, with their +-1.96/sqrt(n) band.
    ljung_box : tuple of LjungBoxLag
        One entry per requested lag, ``model_df = p + q``.
    acf : ndarray of float64
        Residual autocorrelation r_0..r_K (K = the largest Ljung-Box lag).
    reasons : tuple of str
        Why the residuals are not white: each failed check (empty when all three pass).
    """

    n: int
    mean: float
    variance: float
    rho_a2: CorrelationCheck
    rho_ax3: CorrelationCheck
    ljung_box: tuple[LjungBoxLag, ...]
    acf: FloatArray
    reasons: tuple[str, ...]

    @property
    def white(self) -> bool:
        """All three checks pass: no reason against whiteness."""
        return not self.reasons

    @property
    def band(self) -> float:
        return self.rho_a2.band

    def to_frame(self) -> pd.DataFrame:
        """One row per check: statistic, value, threshold and pass/fail."""
        rows = [{"check": "rho_a2", "value": self.rho_a2.value, "threshold": self.band,
                 "pvalue": math.nan, "pass": self.rho_a2.passed},
                {"check": "rho_ax3", "value": self.rho_ax3.value, "threshold": self.band,
                 "pvalue": math.nan, "pass": self.rho_ax3.passed}]
        rows += [{"check": f"ljung_box({lb.lag})", "value": lb.q, "threshold": LB_ALPHA,
                  "pvalue": lb.pvalue, "pass": lb.passed} for lb in self.ljung_box]
        return pd.DataFrame(rows).set_index("check")

    def to_dict(self) -> dict[str, Any]:
        return {"n": self.n, "mean": self.mean, "variance": self.variance,
                "rho_a2": self.rho_a2.to_dict(), "rho_ax3": self.rho_ax3.to_dict(),
                "ljung_box": [lb.to_dict() for lb in self.ljung_box],
                "white": self.white, "reasons": list(self.reasons)}

    def summary(self) -> str:
        lb = ", ".join(f"Q({x.lag})={x.q:.4g} p={x.pvalue:.3g}" for x in self.ljung_box)
        verdict = "white" if self.white else "NOT white: " + "; ".join(self.reasons)
        return (f"rho_a2={self.rho_a2.value:+.4f} rho_ax3={self.rho_ax3.value:+.4f} "
                f"(band +-{self.band:.4f}); {lb}; {verdict}")


def ljung_box(resid: Any, *, lags: Sequence[int], model_df: int = 0,
              acf: FloatArray | None = None) -> tuple[LjungBoxLag, ...]:
    """Ljung-Box Q and p-value at each lag (equal to statsmodels' ``acorr_ljungbox``).

    Parameters
    ----------
    resid : array_like
        Residual series.
    lags : sequence of int
        Lags h at which Q(h) is reported (each ``1 <= h < n``).
    model_df : int
        Degrees of freedom used by the model (``p + q`` for ARMA residuals).
    acf : ndarray, optional
        Precomputed residual autocorrelation up to ``max(lags)``.

    Returns
    -------
    tuple of LjungBoxLag

    Notes
    -----
    Q(h) = n (n + 2) sum_{k=1}^{h} r_k^2 / (n - k) (Ljung & Box 1978, eq. 2.3), compared
    with chi^2 on ``h - model_df`` degrees of freedom.

    Examples
    --------
    >>> e = np.random.default_rng(1).standard_normal(1000)
    >>> lb = ljung_box(e, lags=[10], model_df=0)
    >>> lb[0].df, lb[0].pvalue > 0.05
    (10, True)
    """
    from scipy.stats import chi2

    arr = to_float_array(resid, "resid", min_length=3)
    n = arr.shape[0]
    hs = [check_int("lags", h, minimum=1, maximum=n - 1) for h in lags]
    if not hs:
        raise DataError("lags must name at least one lag, got an empty sequence")
    model_df = check_int("model_df", model_df, minimum=0)
    maxlag = max(hs)
    r = autocorrelation(arr, nlags=maxlag) if acf is None else acf
    terms = np.cumsum(r[1: maxlag + 1] ** 2 / (n - np.arange(1, maxlag + 1)))
    out = []
    for h in hs:
        q = float(n * (n + 2) * terms[h - 1])
        df = h - model_df
        if df > 0:
            pv = float(chi2.sf(q, df))
            out.append(LjungBoxLag(h, q, pv, df, pv >= LB_ALPHA))
        else:
            out.append(LjungBoxLag(h, q, math.nan, df, None))
    return tuple(out)


def residual_diagnostics(resid: Any, x: Any, *, p: int, q: int,
                         lags: Sequence[int] = (10, 20)) -> ResidualDiagnostics:
    """All whiteness checks of one fitted candidate.

    Parameters
    ----------
    resid : array_like
        Innovations a_t of the fit.
    x : array_like
        The series that was fitted (same length).
    p, q : int
        The candidate's orders (``model_df = p + q`` in Ljung-Box).
    lags : sequence of int
        Ljung-Box lags.

    Returns
    -------
    ResidualDiagnostics

    Examples
    --------
    >>> rng = np.random.default_rng(2)
    >>> a = rng.standard_normal(2000)
    >>> residual_diagnostics(a, a, p=0, q=0).white
    True
    """
    a = to_float_array(resid, "resid", min_length=5)
    xs = to_float_array(x, "x", min_length=5)
    return diagnostics_of(a, xs, p=p, q=q, lags=lags)


def diagnostics_of(a: FloatArray, xs: FloatArray, *, p: int, q: int, lags: Sequence[int],
                   x_offset: float = 0.0) -> ResidualDiagnostics:
    """:func:`residual_diagnostics` of float64 arrays, the series being ``xs - x_offset``
    (subtracted block by block in rho_ax,3: no series-length copy)."""
    if a.shape != xs.shape:
        raise DataError(f"resid and x must have the same length, got {a.shape[0]} and "
                        f"{xs.shape[0]}")
    n = a.shape[0]
    band = BAND_Z / math.sqrt(n)
    ra2 = rho_a2(a)
    rax3 = rho_ax3(a, xs) if not x_offset else _rho_ax3_offset(a, xs, x_offset)
    c_a2 = CorrelationCheck("rho_a2", ra2, band, bool(abs(ra2) <= band))
    c_ax3 = CorrelationCheck("rho_ax3", rax3, band, bool(abs(rax3) <= band))
    maxlag = max(check_int("lags", h, minimum=1, maximum=n - 1) for h in lags)
    mean = float(a.mean())
    c = lag_products(a, maxlag, center=mean)   # block-wise: no copy of the residuals
    if c[0] == 0.0:
        raise InsufficientDataError("resid is constant; its autocorrelation is undefined")
    acf = c / c[0]
    lb = ljung_box(a, lags=lags, model_df=p + q, acf=acf)
    reasons = []
    if not c_a2.passed:
        reasons.append(f"|rho_a2| = {abs(ra2):.4g} > {band:.4g}")
    if not c_ax3.passed:
        reasons.append(f"|rho_ax3| = {abs(rax3):.4g} > {band:.4g}")
    testable = [x for x in lb if x.passed is not None]
    if not testable:
        reasons.append(f"Ljung-Box not testable: every lag <= p + q = {p + q}")
    reasons += [f"Ljung-Box p = {x.pvalue:.3g} < {LB_ALPHA} at lag {x.lag}"
                for x in testable if not x.passed]
    return ResidualDiagnostics(n=n, mean=mean, variance=float(c[0]) / n,
                               rho_a2=c_a2, rho_ax3=c_ax3, ljung_box=lb, acf=acf,
                               reasons=tuple(reasons))

