"""The exact innovations of an ARMA(p, q) start-up block by Ansley's banded Cholesky factor.

z = (x_1..x_p, W_{p+1}..W_s), W_t = phi(B) x_t, has a banded covariance (bandwidth
max(p, q)) and the same innovations as x; its banded Cholesky factor L gives the relative
innovation variances F_t = L_tt^2 and the innovations e_t = L_tt (L^-1 z)_t: the Kalman
filter's output from the stationary covariance, computed by LAPACK dpbtrf/dtbtrs.

References
----------
C. F. Ansley, "An algorithm for the exact likelihood of a mixed autoregressive-moving average
process", Biometrika 66 (1979) 59-65.
P. J. Brockwell and R. A. Davis, *Time Series: Theory and Methods*, 2nd ed., 1991, eq. 3.3.8.
"""

from __future__ import annotations

import numpy as np

from fogts._typing import FloatArray
from fogts.errors import ModelFitError

__all__ = ["TOL_FLOOR", "TOL_STEADY", "ansley_z", "band_orders", "banded_innovations",
           "factor_solve", "row_deviation"]

TOL_STEADY = 1e-13     # the block is steady when its last row is this close to the filter's
TOL_FLOOR = 1e-11      # ... or this close, and no closer than half-way through the block


def band_orders(phi: FloatArray, theta: FloatArray) -> tuple[int, int, int]:
    """``(p, q, m)``: the AR and MA orders and the half-bandwidth ``m = max(p, q, 1)`` of the
    start-up block's covariance (Ansley's z is an MA(q) beyond its first p rows)."""
    p, q = phi.size, theta.size
    return p, q, max(p, q, 1)


def _psi_weights(phi: FloatArray, theta: FloatArray, nlag: int) -> FloatArray:
    """psi_0..psi_nlag of x_t = sum psi_j a_{t-j} (psi_j = theta_j + sum_k phi_k psi_{j-k})."""
    psi = np.zeros(nlag + 1)
    psi[0] = 1.0
    for j in range(1, nlag + 1):
        acc = theta[j - 1] if j <= theta.size else 0.0
        for k in range(1, min(j, phi.size) + 1):
            acc += phi[k - 1] * psi[j - k]
        psi[j] = acc
    return psi


def _arma_acov(phi: FloatArray, theta: FloatArray, psi: FloatArray, nlag: int) -> FloatArray:
    """Autocovariances gamma(0..nlag-1) of a unit-variance ARMA (Brockwell & Davis eq. 3.3.8)."""
    p, q = phi.size, theta.size
    if nlag == 0:
        return np.zeros(0)
    th = np.r_[1.0, theta]
    c = np.array([float(np.dot(th[k:q + 1], psi[:q + 1 - k])) if k <= q else 0.0
                  for k in range(p + 1)])
    A = np.eye(p + 1)
    for k in range(p + 1):
        for i in range(1, p + 1):
            A[k, abs(k - i)] -= phi[i - 1]
    gam = np.linalg.solve(A, c)
    return gam[:nlag]


def _band_covariance(phi: FloatArray, theta: FloatArray, s: int) -> FloatArray:
    """The band of Cov(z) in LAPACK's lower storage: ab[d, j] = Cov(z_{j+d}, z_j)."""
    p, q, m = band_orders(phi, theta)
    th = np.empty(q + 1)
    th[0] = 1.0
    th[1:] = theta
    psi = _psi_weights(phi, theta, q)
    gam_x = _arma_acov(phi, theta, psi, p)
    # the MA(q) autocovariance of W_t = phi(B)x_t everywhere but in the first p columns
    # (x-x and x-W covariances, Ansley 1979)
    ab = np.zeros((m + 1, s))
    for d in range(min(q, m) + 1):
        ab[d, :s - d] = float(np.dot(th[:q + 1 - d], th[d:q + 1]))
    for j in range(min(p, s)):
        for d in range(min(m, s - 1 - j) + 1):
            if j + d < p:
                ab[d, j] = gam_x[d]
            elif d <= q:
                ab[d, j] = float(np.dot(th[d:q + 1], psi[:q + 1 - d]))
            else:
                ab[d, j] = 0.0
    return ab


def banded_innovations(phi: FloatArray, theta: FloatArray, x: FloatArray, *,
                       check: bool = False, with_ones: bool = False
                       ) -> tuple[FloatArray, FloatArray, bool]:
    """Exact innovations and relative variances of the block ``x`` (length s) under ARMA.

    Returns the innovations (s,) - or (s, 2) with ``with_ones``, the second column those of
    the constant series 1 - the variances F (s,) and, with ``check``, whether the block is
    steady: |F - 1| and the distance of the last Cholesky row from (theta_q..theta_1, 1)
    below ``TOL_STEADY``, or below ``TOL_FLOOR`` and settled (the rounding floor a nearly
    non-stationary model puts under it; the steady filter then changes the innovations by
    that relative amount at most).

    Raises
    ------
    ModelFitError
        The block's covariance is not positive definite (a non-stationary phi).
    """
    p, q, m = band_orders(phi, theta)
    s = x.shape[0]
    c, e, F, _ = factor_solve(_band_covariance(phi, theta, s), ansley_z(phi, x, with_ones), s)
    steady = False
    if check and s > p + q:
        dev = row_deviation(c, F, theta, s - 1)
        # a near-unit AR root puts a rounding floor of ~1e-13 under the deviation: settled
        # there (no smaller at the last row than at the middle one), the block is as steady
        # as floating point makes it
        steady = dev < TOL_STEADY or (dev < TOL_FLOOR and s // 2 > m
                                      and dev >= 0.5 * row_deviation(c, F, theta, s // 2))
    return e, F, steady


def ansley_z(phi: FloatArray, x: FloatArray, with_ones: bool) -> FloatArray:
    """Ansley's z = (x_1..x_p, phi(B)x_{p+1..s}) of the block ``x``, with the constant
    series' as a second column (``with_ones``)."""
    p, s = phi.size, x.shape[0]
    z = np.column_stack((x, np.ones(s))) if with_ones else x.copy()
    if p:
        b = np.empty(p + 1)
        b[0] = 1.0
        b[1:] = -phi
        if with_ones:
            z[p:, 0] = np.convolve(x, b, mode="valid")
            z[p:, 1] = float(np.sum(b))
        else:
            z[p:] = np.convolve(x, b, mode="valid")
    return z


def factor_solve(ab: FloatArray, z: FloatArray, s: int
                 ) -> tuple[FloatArray, FloatArray, FloatArray, FloatArray]:
    """The banded Cholesky factor ``c`` of the band ``ab`` (LAPACK dpbtrf, lower storage),
    the innovations e = diag(c) (c^-1 z), the relative variances F = diag(c)^2 and the
    forward solution w = c^-1 z (LAPACK dtbtrs); ``s`` (the first row's index in the
    series) only names the rows in the error.

    Raises
    ------
    ModelFitError
        The band is not positive definite (a non-stationary phi).
    """
    from scipy.linalg import lapack

    c, info = lapack.dpbtrf(ab, lower=1)
    if info != 0:
        raise ModelFitError(f"the covariance of the first {s} samples is not positive "
                            f"definite (LAPACK dpbtrf info={info})")
    w, info = lapack.dtbtrs(c, z, uplo="L")
    w = np.asarray(w)
    diag = c[0]
    e = w * diag[:, None] if z.ndim == 2 else w.ravel() * diag
    return c, e, diag * diag, w


def row_deviation(c: FloatArray, F: FloatArray, theta: FloatArray, t: int) -> float:
    """max(|F_t - 1|, distance of the Cholesky row t from (theta_m..theta_1, 1)), LAPACK's
    lower band storage ``c``."""
    m = c.shape[0] - 1
    diag = c[0]
    dev = abs(F[t] - 1.0)
    for d in range(1, m + 1):
        target = theta[d - 1] if d <= theta.size else 0.0
        dev = max(dev, abs(c[d, t - d] / diag[t - d] - target))
    return float(dev)
