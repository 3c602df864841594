"""The normal and chi-squared quantiles and tails the Allan analysis needs, from
:mod:`scipy.special`.

``scipy.stats`` costs about half a second to import, more than the rest of the analysis
of a small record; its ``norm`` and ``chi2`` evaluate these same special functions
(``ndtri``, ``ndtr``, ``gammaincinv``, ``chdtrc``; SciPy's ``_continuous_distns``), so the
values here are theirs bit for bit on the arguments the analysis passes (probabilities in
(0, 1), degrees of freedom > 0 or NaN).  Definitions: Abramowitz & Stegun (1964) 26.2.2
(normal), 26.4.2 and 26.4.19 (chi-squared as a regularised incomplete gamma function).
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

import numpy as np
import numpy.typing as npt
from scipy import special

__all__ = ["chi2_ppf", "chi2_sf", "norm_cdf", "norm_ppf"]


def _valid(*arrays: Any) -> tuple[npt.NDArray[np.float64], ...]:
    return tuple(np.asarray(a, dtype=np.float64) for a in arrays)


def _where(ok: npt.NDArray[np.bool_], fn: Callable[..., Any], *args: npt.NDArray[np.float64]
           ) -> npt.NDArray[np.float64]:
    """``fn(*args)`` where ``ok``, NaN elsewhere (``args`` broadcast to ``ok``'s shape)."""
    out = np.full(ok.shape, np.nan)
    out[ok] = fn(*(a[ok] for a in args))
    return out


def norm_ppf(q: npt.ArrayLike) -> Any:
    """Standard normal quantile ``Phi^-1(q)`` (``scipy.stats.norm.ppf``).

    ``q`` outside [0, 1] gives NaN, 0 and 1 give -inf and +inf.

    Examples
    --------
    >>> round(float(norm_ppf(0.975)), 6)
    1.959964
    """
    return special.ndtri(*_valid(q))[()]


def norm_cdf(x: npt.ArrayLike) -> Any:
    """Standard normal distribution function ``Phi(x)`` (``scipy.stats.norm.cdf``).

    Examples
    --------
    >>> float(norm_cdf(0.0))
    0.5
    """
    return special.ndtr(*_valid(x))[()]


def chi2_ppf(q: npt.ArrayLike, df: npt.ArrayLike) -> Any:
    """Chi-squared quantile with ``df`` degrees of freedom (``scipy.stats.chi2.ppf``):
    ``2 P^-1(df / 2, q)`` with ``P`` the regularised lower incomplete gamma function.

    NaN where ``df <= 0``, ``df`` is NaN or ``q`` is outside [0, 1]; ``q = 0`` gives 0 and
    ``q = 1`` gives +inf.

    Examples
    --------
    >>> round(float(chi2_ppf(0.95, 1.0)), 6)
    3.841459
    """
    qq, dd = np.broadcast_arrays(*_valid(q, df))
    ok = (dd > 0) & (qq >= 0) & (qq <= 1)
    out = _where(ok, lambda d, p: 2.0 * special.gammaincinv(d / 2.0, p), dd, qq)
    out[ok & (qq == 0)] = 0.0
    out[ok & (qq == 1)] = np.inf
    return out[()]


def chi2_sf(x: npt.ArrayLike, df: npt.ArrayLike) -> Any:
    """Chi-squared upper tail ``P(X > x)`` with ``df`` degrees of freedom
    (``scipy.stats.chi2.sf``); 1 for ``x <= 0``, NaN where ``df <= 0`` or an argument is
    NaN.

    Examples
    --------
    >>> round(float(chi2_sf(3.841459, 1.0)), 6)
    0.05
    """
    xx, dd = np.broadcast_arrays(*_valid(x, df))
    ok = (dd > 0) & ~np.isnan(xx)
    return _where(ok, lambda d, v: special.chdtrc(d, np.maximum(v, 0.0)), dd, xx)[()]
