"""Whole-series statistics of long series without series-length temporaries.

:func:`fogts.arma.fit.fit_arma` standardises the series (``x / scale``, minus its mean) for
the likelihood, which forms it block by block.  On a long series the statistics it needs
of the standardised series - its scale, its mean, the least-squares AR(3) check - are
taken here block by block too, so that a fit of a 1e8-sample series (800 MB) makes no
800 MB temporary besides the likelihood's workspace.  They differ from the whole-array
numpy reductions (pairwise summation) by rounding only, so :func:`fogts.arma.fit.fit_arma`
uses them only above ``BLOCKWISE_MIN_N`` samples, and the fits of shorter series are
bit-for-bit those of the whole-array path.
"""

from __future__ import annotations

import math

import numpy as np

from fogts._typing import FloatArray
from fogts.arma.correlation import dot, lag_products

__all__ = ["BLOCK", "BLOCKWISE_MIN_N", "lagged_products", "mean_of", "scale_and_offsets", "std"]

#: Above this many samples (8 MB of float64) the fit's statistics are taken block by block.
BLOCKWISE_MIN_N = 1 << 20
BLOCK = 1 << 16


def _scaled(seg: FloatArray, scale: float, offset: float) -> FloatArray:
    """seg / scale - offset (each step only if it changes seg), the subtraction in place on
    the division's new array: the same floating-point operations as the whole-array form."""
    if scale != 1.0:
        seg = seg / scale
        if offset:
            seg -= offset
    elif offset:
        seg = seg - offset
    return seg


def std(x: FloatArray) -> float:
    """Population standard deviation, two-pass (mean, then squared deviations block by
    block: :func:`fogts.arma.correlation.lag_products` at lag 0)."""
    mean = mean_of(x, 1.0, 0.0)
    return math.sqrt(float(lag_products(x, 0, center=mean)[0]) / x.shape[0])


def mean_of(x: FloatArray, scale: float, offset: float) -> float:
    """mean(x / scale - offset), summed block by block (each block as numpy forms it)."""
    total = 0.0
    for c0 in range(0, x.shape[0], BLOCK):
        total += float(np.sum(_scaled(x[c0:c0 + BLOCK], scale, offset)))
    return total / x.shape[0]


def scale_and_offsets(x: FloatArray, standardize: bool, mean: bool
                      ) -> tuple[float, float, float]:
    """The fit's scale (std of x, or 1), the mean of x / scale subtracted with ``mean``
    (else 0) and the mean of what remains (the demeaned fallback's offset)."""
    scale = std(x) if standardize else 1.0
    offset = mean_of(x, scale, 0.0) if mean else 0.0
    return scale, offset, mean_of(x, scale, offset)


def lagged_products(x: FloatArray, scale: float, offset: float, k: int) -> FloatArray:
    """M[i, j] = sum_{t=k}^{n-1} y_{t-i} y_{t-j}, i, j = 0..k, y = x / scale - offset,
    block by block (the normal equations of a least-squares AR(k) fit, Box, Jenkins &
    Reinsel 1994, sec. 7.2)."""
    n = x.shape[0]
    M = np.zeros((k + 1, k + 1))
    for c0 in range(k, n, BLOCK):
        c1 = min(n, c0 + BLOCK)
        seg = _scaled(x[c0 - k:c1], scale, offset)
        m = c1 - c0
        for i in range(k + 1):
            for j in range(i, k + 1):
                M[i, j] += dot(seg[k - i:k - i + m], seg[k - j:k - j + m])
    return np.triu(M) + np.triu(M, 1).T
