"""Lag products and sample auto- and partial autocorrelations of long float64 series.

The lag products behind every autocorrelation are computed block-wise in cache
(:func:`lag_products`) with ``np.einsum``, never with threaded BLAS (a multithreaded ``ddot``
stalls on a loaded host); on a long series half of each block's lags are summed on the
:class:`~fogts.arma.worker.Worker` thread.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from fogts._typing import FloatArray
from fogts._validate import check_int, to_float_array
from fogts.errors import InsufficientDataError

__all__ = ["autocorrelation", "dot", "fused_squares", "lag_products", "partial_autocorrelation",
           "sum_squares"]

#: Block length of the cache-friendly lag-product kernel.
_BLOCK = 65536


def dot(u: FloatArray, v: FloatArray) -> float:
    """Plain dot product without BLAS threading (multithreaded ddot stalls on loaded hosts)."""
    return float(np.einsum("i,i->", u, v))


#: np.einsum's buffer (numpy's default): its dot of a long pair adds the dots of 8192-long
#: pieces, in order, to a running sum.
EINSUM_BLOCK = 8192


def fused_squares() -> bool:
    """Whether :func:`sum_squares` reproduces :func:`dot` (numpy's buffer is the default)."""
    return np.getbufsize() == EINSUM_BLOCK


def sum_squares(total: float, y: FloatArray) -> float:
    """``total`` plus sum y^2, adding the dots of 8192-long pieces one by one as
    :func:`dot` (np.einsum) accumulates a longer array's: continued from 0.0 over
    consecutive blocks whose lengths are multiples of 8192 (but the last), it is
    ``dot(a, a)`` of their concatenation a, bit for bit, without reading a again."""
    for b0 in range(0, y.shape[0], EINSUM_BLOCK):
        piece = y[b0:b0 + EINSUM_BLOCK]
        total += dot(piece, piece)
    return total


def lag_products(x: FloatArray, max_lag: int, y: FloatArray | None = None, *,
                 center: float = 0.0) -> FloatArray:
    """Lag products ``c_k = sum_t x_{t+k} y_t`` for k = 0..max_lag (y defaults to x).

    Computed block by block, every lag of a block while the block is in cache, with
    ``np.einsum`` (no BLAS threads, which stall on a loaded machine); no series-length
    array is made.  ``center`` is subtracted from both series first (block by block).

    Parameters
    ----------
    x, y : ndarray of float64
        Series of equal length.
    max_lag : int
        Largest lag (``0 <= max_lag < len(x)``).
    center : float
        Subtracted from every sample of x and y (e.g. their mean).

    Returns
    -------
    ndarray of float64, shape (max_lag + 1,)

    Examples
    --------
    >>> lag_products(np.array([1.0, 2.0, 3.0]), 2)
    array([14.,  8.,  3.])
    """
    from fogts.arma.worker import Worker

    n = x.shape[0]
    same = y is None
    out = np.zeros(max_lag + 1)

    def lags(lo: int, hi: int, xs: FloatArray, ys: FloatArray, size: int) -> None:
        for k in range(lo, hi):
            m = min(size, xs.shape[0] - k)
            if m > 0:
                out[k] += dot(ys[:m], xs[k:k + m])

    # a long series: the worker thread sums the first lags of each block, in block order,
    # while this thread sums the others (each lag's sum the same, bit for bit)
    split = (max_lag + 1) // 2
    with Worker(n if split else 0) as worker:
        for s in range(0, n, _BLOCK):
            e = min(n, s + _BLOCK)
            xs = x[s:min(n, e + max_lag)]
            ys = xs[:e - s] if same else (y if y is not None else x)[s:e]
            if center:
                xs = xs - center
                ys = xs[:e - s] if same else ys - center
            if worker.threaded:
                worker.submit(lags, 0, split, xs, ys, e - s)
                lags(split, max_lag + 1, xs, ys, e - s)
            else:
                lags(0, max_lag + 1, xs, ys, e - s)
    return out


def autocorrelation(x: Any, *, nlags: int) -> FloatArray:
    """Sample autocorrelation r_0..r_nlags (demeaned, biased: divided by n).

    Identical to ``statsmodels.tsa.stattools.acf(x, nlags=nlags, adjusted=False)``
    (Box, Jenkins & Reinsel eq. 2.1.12), computed with :func:`lag_products` (no copy of x).

    Examples
    --------
    >>> r = autocorrelation(np.sin(np.arange(200) / 3.0), nlags=2)
    >>> float(r[0])
    1.0
    """
    arr = to_float_array(x, "x", min_length=2)
    nlags = check_int("nlags", nlags, minimum=0, maximum=arr.shape[0] - 1)
    c = lag_products(arr, nlags, center=float(arr.mean()))
    if c[0] == 0.0:
        raise InsufficientDataError("x is constant; its autocorrelation is undefined")
    return c / c[0]


def partial_autocorrelation(x: Any, *, nlags: int, acf: FloatArray | None = None) -> FloatArray:
    """Sample partial autocorrelation phi_00..phi_kk by Levinson-Durbin on the biased ACF.

    Identical to ``statsmodels.tsa.stattools.pacf(x, nlags, method="ldb")`` (Box, Jenkins &
    Reinsel eq. 3.2.32).  The biased autocovariances make |phi_kk| < 1 always.

    Examples
    --------
    >>> from scipy.signal import lfilter
    >>> e = np.random.default_rng(0).standard_normal(5000)
    >>> pac = partial_autocorrelation(lfilter([1.0], [1.0, -0.5], e), nlags=2)
    >>> round(float(pac[1]), 1), abs(float(pac[2])) < 0.05
    (0.5, True)
    """
    from statsmodels.tsa.stattools import levinson_durbin

    if acf is None:
        acf = autocorrelation(x, nlags=nlags)
    pac = levinson_durbin(np.asarray(acf[: nlags + 1]), nlags=nlags, isacov=True)[2]
    return np.asarray(pac, dtype=np.float64)

