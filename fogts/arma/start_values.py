"""Start values of the likelihood maximisation: Hannan-Rissanen regressions.

References
----------
E. J. Hannan and J. Rissanen, "Recursive estimation of mixed autoregressive-moving average
order", Biometrika 69 (1982) 81-94.
"""

from __future__ import annotations

import numpy as np

from fogts._typing import FloatArray
from fogts.arma.correlation import dot
from fogts.arma.likelihood import lag_dot
from fogts.arma.region import admissible, shrink_into_region

__all__ = ["START_SAMPLES", "hannan_rissanen", "normal_equations"]

START_SAMPLES = 200_000  # Hannan-Rissanen start values use at most this many samples


def normal_equations(y: FloatArray, cols: list[tuple[FloatArray, int]], t0: int) -> FloatArray:
    """Least squares of y_t on the lagged regressors a_{t-lag}, t >= t0, via X'X (dots only)."""
    k = len(cols)
    XtX = np.empty((k, k))
    Xty = np.empty(k)
    for i, (ai, li) in enumerate(cols):
        Xty[i] = lag_dot(ai, y, li, 0, t0)
        for j in range(i, k):
            aj, lj = cols[j]
            XtX[i, j] = XtX[j, i] = lag_dot(ai, aj, li, lj, t0)
    try:
        return np.asarray(np.linalg.solve(XtX, Xty))
    except np.linalg.LinAlgError:
        return np.asarray(np.linalg.lstsq(XtX, Xty, rcond=None)[0])


def hannan_rissanen(xs: FloatArray, p: int, q: int) -> tuple[FloatArray, FloatArray]:
    """Hannan & Rissanen (1982) start values from the first ``START_SAMPLES`` samples.

    A long Yule-Walker AR fit gives innovation estimates; x_t is then regressed on its p lags and
    q lagged innovation estimates.  Pure AR models use least squares directly.
    """
    from scipy.linalg import solve_toeplitz
    from scipy.signal import lfilter

    y = xs[:START_SAMPLES]
    m = y.shape[0]
    if q == 0:
        phi = normal_equations(y, [(y, i) for i in range(1, p + 1)], p)
        theta = np.zeros(0)
    else:
        K = int(min(max(20, 3 * (p + q)), max(p + q + 1, m // 5)))
        acov = np.array([dot(y[:m - h], y[h:]) / m for h in range(K + 1)])
        pi = solve_toeplitz(acov[:K], acov[1:K + 1])
        ehat = lfilter(np.r_[1.0, -pi], [1.0], y)
        cols = [(y, i) for i in range(1, p + 1)] + [(ehat, j) for j in range(1, q + 1)]
        coef = normal_equations(y, cols, K + q)
        phi, theta = coef[:p], coef[p:]
    if not (np.all(np.isfinite(phi)) and np.all(np.isfinite(theta))):
        phi, theta = np.zeros(p), np.zeros(q)
    if not admissible(phi, theta, margin=0.02):
        phi, theta = shrink_into_region(phi, theta)
    return phi, theta

