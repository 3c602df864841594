"""The exact Gaussian likelihood of a pure AR(p) from its sufficient statistics.

For a stationary AR(p) with unit innovation variance and coefficients phi, write
beta = (1, -phi_1, ..., -phi_p).  The exact quadratic form of a series y_0..y_{n-1} (n >= 2p)
is a quadratic form in beta (Box, Jenkins & Reinsel 1994, sec. 7.4.1):

    y' Gamma_n^-1 y = beta' D beta,   D_ij = sum_{k=0}^{n-1-i-j} y_{i+k} y_{j+k},  i, j = 0..p,

and log det Gamma_n = log det Gamma_p = -sum_k k log(1 - kappa_k^2) (Levinson-Durbin;
kappa_k the partial autocorrelations, F_t = 1 from t = p on; Brockwell & Davis 1991,
sec. 8.7).  With a mean profiled out by GLS (Harville 1974) the same identity with the
series 1 gives s11 = 1' Gamma_n^-1 1 = beta' N beta (N_ij = n - i - j) and
sx1 = beta' G beta (G_ij the symmetrised sums of y_{i+k}), so that

    S = beta' D beta - (beta' G beta)^2 / beta' N beta,   D_f = log det Gamma_p + log(s11 / n),

the S and D of :meth:`fogts.arma.likelihood.ExactLikelihood.evaluate`.  D and G follow from
the lag products c_h = sum_t y_t y_{t+h} (h = 0..p), the sum of y and its first and last p
values: one pass over the data, after which the profile objective
f = nu/2 log(S/nu) + D_f/2, its gradient and Hessian cost O(p^2) each.

References
----------
G. E. P. Box, G. M. Jenkins and G. C. Reinsel, *Time Series Analysis: Forecasting and
Control*, 3rd ed., 1994, sec. 7.4.
P. J. Brockwell and R. A. Davis, *Time Series: Theory and Methods*, 2nd ed., 1991, sec. 8.7.
D. A. Harville, "Bayesian inference for variance components using only error contrasts",
Biometrika 61 (1974) 383-385.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from fogts._typing import FloatArray
from fogts.arma.blockwise import lagged_products
from fogts.arma.likelihood import Evaluation, ExactLikelihood
from fogts.arma.region import (
    UNIT_ROOT_GAP,
    admissible,
    shrink_into_region,
    spectral_radius,
    unit_root_gap,
)
from fogts.arma.standard_errors import covariance, full_hessian

__all__ = ["ArObjective", "ArStatistics", "ar_statistics", "fit_exact_ar", "log_det_gamma",
           "maximise_ar", "objective"]

_MAX_ITER = 50
_SMALL_STEP = 1e-12       # a Newton step this small is the last one ...
_SMALL_GAIN = 1e-12       # ... and so is one that would gain less likelihood than this


@dataclass(frozen=True)
class ArStatistics:
    """The sufficient statistics of an AR(p) likelihood: D, G and N of the module docstring,
    (p + 1) x (p + 1) each, and the series length n."""

    n: int
    D: FloatArray
    G: FloatArray
    N: FloatArray

    @property
    def p(self) -> int:
        return self.D.shape[0] - 1


def ar_statistics(lags: FloatArray, total: float, head: FloatArray, tail: FloatArray,
                  n: int) -> ArStatistics:
    """D, G and N from the full-range lag products ``lags[h] = sum_{t=0}^{n-1-h} y_t y_{t+h}``
    (h = 0..p), ``total = sum y_t``, the first p values ``head`` and the last p ``tail``.

    D_ij (i <= j, h = j - i) is c_h without its first i and last i terms, t from i to
    n - 1 - j; G_ij averages sum_{t=i}^{n-1-j} y_t and sum_{t=j}^{n-1-i} y_t.
    """
    p = lags.shape[0] - 1
    y_head = np.asarray(head[:p], dtype=float)
    y_tail = np.asarray(tail[tail.shape[0] - p:], dtype=float) if p else np.zeros(0)
    pad = np.r_[y_head, np.zeros(1), y_tail]    # y_0..y_{p-1}, *, y_{n-p}..y_{n-1}

    def value(t: int) -> float:     # y_t for t < p or t >= n - p
        return float(pad[t] if t < p else pad[p + 1 + t - (n - p)])

    D = np.empty((p + 1, p + 1))
    G = np.empty((p + 1, p + 1))
    for i in range(p + 1):
        for j in range(i, p + 1):
            h = j - i
            lead = sum(value(t) * value(t + h) for t in range(i))
            trail = sum(value(t) * value(t + h) for t in range(n - j, n - h))
            D[i, j] = D[j, i] = lags[h] - lead - trail
            s_ij = total - sum(value(t) for t in range(i)) - sum(value(t) for t in range(n - j, n))
            s_ji = total - sum(value(t) for t in range(j)) - sum(value(t) for t in range(n - i, n))
            G[i, j] = G[j, i] = 0.5 * (s_ij + s_ji)
    idx = np.arange(p + 1)
    N = (n - idx[:, None] - idx[None, :]).astype(float)
    return ArStatistics(n=n, D=D, G=G, N=N)


def _reflection(phi: FloatArray) -> FloatArray | None:
    """Partial autocorrelations kappa_1..kappa_p of the AR(p) ``phi`` by the Levinson-Durbin
    step-down recursion (Brockwell & Davis 1991, sec. 5.2); None if some |kappa| >= 1."""
    a = np.array(phi, dtype=float)
    p = a.size
    kappa = np.empty(p)
    for k in range(p, 0, -1):
        kk = a[k - 1]
        if not abs(kk) < 1.0:
            return None
        kappa[k - 1] = kk
        if k > 1:
            a = (a[:k - 1] + kk * a[k - 2::-1]) / (1.0 - kk * kk)
    return kappa


def log_det_gamma(phi: FloatArray) -> float:
    """log det Gamma_p of a stationary AR(p) with unit innovation variance:
    -sum_k k log(1 - kappa_k^2) (Levinson-Durbin); inf outside the stationary region."""
    kappa = _reflection(phi)
    if kappa is None:
        return math.inf
    k = np.arange(1, kappa.size + 1)
    return float(-np.sum(k * np.log1p(-kappa * kappa)))


def _fd_log_det(phi: FloatArray) -> tuple[FloatArray, FloatArray]:
    """Gradient and Hessian of :func:`log_det_gamma` by central differences (fourth-order
    for the gradient), steps at most 1e-3 of the distance of the largest inverse root from
    the unit circle, where the function behaves like -log(gap)."""
    p = phi.size
    gap = 1.0 - spectral_radius(phi)
    h = min(1e-4, 1e-3 * gap)
    eye = np.eye(p)

    def ld(v: FloatArray) -> float:
        return log_det_gamma(v)

    f0 = ld(phi)
    g = np.empty(p)
    H = np.empty((p, p))
    for i in range(p):
        e = h * eye[i]
        f1, fm1, f2, fm2 = ld(phi + e), ld(phi - e), ld(phi + 2 * e), ld(phi - 2 * e)
        g[i] = (8.0 * (f1 - fm1) - (f2 - fm2)) / (12.0 * h)
        H[i, i] = (-f2 + 16.0 * f1 - 30.0 * f0 + 16.0 * fm1 - fm2) / (12.0 * h * h)
        for j in range(i):
            ej = h * eye[j]
            H[i, j] = H[j, i] = (ld(phi + e + ej) - ld(phi + e - ej) - ld(phi - e + ej)
                                 + ld(phi - e - ej)) / (4.0 * h * h)
    return g, H


@dataclass(frozen=True)
class ArObjective:
    """The profile objective f at one phi, with S, D_f, the GLS mean and s11 (unit-sigma2
    scale), and the gradient and Hessian of f and of S and D_f (exact but for D_f's
    log det Gamma_p, by central differences)."""

    phi: FloatArray
    f: float
    S: float
    D: float
    mu: float
    s11: float
    grad: FloatArray
    hess: FloatArray
    dS: FloatArray
    d2S: FloatArray
    dD: FloatArray
    d2D: FloatArray


def _quad(M: FloatArray, beta: FloatArray) -> tuple[float, FloatArray, FloatArray]:
    """beta' M beta and its gradient and Hessian in phi (beta = (1, -phi))."""
    Mb = M @ beta
    return float(beta @ Mb), -2.0 * Mb[1:], 2.0 * M[1:, 1:]


def objective(stats: ArStatistics, phi: FloatArray, mean: bool) -> ArObjective:
    """f = nu/2 log(S/nu) + D_f/2 at ``phi`` (nu = n - 1 with the GLS mean, else n), see
    the module docstring; S at the GLS mean is profiled (S = Sxx - sx1^2 / s11)."""
    n = stats.n
    beta = np.r_[1.0, -np.asarray(phi, dtype=float)]
    S, dS, d2S = _quad(stats.D, beta)
    ld_g, ld_H = _fd_log_det(np.asarray(phi, dtype=float))
    D, dD, d2D = log_det_gamma(phi), ld_g, ld_H
    mu = s11 = 0.0
    if mean:
        a, da, d2a = _quad(stats.G, beta)
        b, db, d2b = _quad(stats.N, beta)
        mu, s11 = a / b, b
        S -= a * a / b
        dS = dS - (2.0 * a * da / b - a * a * db / b**2)
        d2S = d2S - (2.0 * np.outer(da, da) / b + 2.0 * a * d2a / b
                     - 2.0 * a * (np.outer(da, db) + np.outer(db, da)) / b**2
                     + 2.0 * a * a * np.outer(db, db) / b**3 - a * a * d2b / b**2)
        D += math.log(b / n)
        dD = dD + db / b
        d2D = d2D + d2b / b - np.outer(db, db) / b**2
    nu = n - 1 if mean else n
    f = 0.5 * nu * math.log(S / nu) + 0.5 * D if S > 0 else math.inf
    grad = 0.5 * nu / S * dS + 0.5 * dD
    hess = 0.5 * nu / S * d2S - 0.5 * nu / S**2 * np.outer(dS, dS) + 0.5 * d2D
    return ArObjective(phi=np.asarray(phi, dtype=float), f=f, S=S, D=D, mu=mu, s11=s11,
                       grad=grad, hess=hess, dS=dS, d2S=d2S, dD=dD, d2D=d2D)


def _start(stats: ArStatistics) -> FloatArray:
    """Least squares from D (conditional on the first p values), shrunk into the region."""
    p = stats.p
    try:
        phi = np.asarray(np.linalg.solve(stats.D[1:, 1:], stats.D[1:, 0]), dtype=np.float64)
    except np.linalg.LinAlgError:
        phi = np.zeros(p)
    if not admissible(phi, np.zeros(0), margin=0.02):
        phi, _ = shrink_into_region(phi, np.zeros(0))
    return np.asarray(phi, dtype=float)


def _rounding(stats: ArStatistics, ob: ArObjective) -> float:
    """The rounding level of f: S = beta' D beta cancels terms as large as
    |beta|' |D| |beta| (a series with a large mean or a root near 1), eps relative each."""
    beta = np.abs(np.r_[1.0, -ob.phi])
    big = float(beta @ np.abs(stats.D) @ beta)
    return 0.5 * stats.n * 4e-16 * big / ob.S + 1e-13 * abs(ob.f)


def maximise_ar(stats: ArStatistics, mean: bool) -> tuple[ArObjective, int, bool]:
    """The exact ML phi by damped Newton steps on :func:`objective` from least squares.

    Returns the objective at the optimum, the iterations and whether they converged (a step
    below 1e-12, or no descent left at the rounding level of f).
    """
    p = stats.p
    ob = objective(stats, _start(stats), mean)
    for it in range(1, _MAX_ITER + 1):
        try:
            np.linalg.cholesky(ob.hess)
            step = np.linalg.solve(ob.hess, ob.grad)
        except np.linalg.LinAlgError:
            step = ob.grad / max(float(np.max(np.abs(np.diag(ob.hess)))), 1.0)
        decrement = float(ob.grad @ step)        # predicted decrease of f, x 2
        if float(np.max(np.abs(step))) < _SMALL_STEP or 0.0 <= decrement < _SMALL_GAIN:
            cand = ob.phi - step
            if admissible(cand, np.zeros(0), margin=0.0):
                ob = objective(stats, cand, mean)
            return ob, it, True
        t, accepted = 1.0, None
        slack = _rounding(stats, ob)
        while t > 1e-12:
            cand = ob.phi - t * step
            if admissible(cand, np.zeros(0), margin=0.0):
                ob2 = objective(stats, cand, mean)
                if ob2.f <= ob.f - 1e-4 * t * float(ob.grad @ step) + slack:
                    accepted = ob2
                    break
            t *= 0.5
        if accepted is None:
            return ob, it, float(ob.grad @ step) < 1e-6
        ob = accepted
    return ob, _MAX_ITER, p == 0


def fit_exact_ar(x: FloatArray, head: FloatArray, scale: float, offsets: tuple[float, float],
                 p: int, mean: bool, products: FloatArray | None = None
                 ) -> tuple[ExactLikelihood, Evaluation, FloatArray, FloatArray, str | None,
                            int] | None:
    """The exact ML AR(p) fit of y = x / scale - offsets[0] (``offsets[0]`` with ``mean``)
    from its sufficient statistics; None where the general path must decide (Newton did not
    converge, or the restricted likelihood runs to a unit AR root).

    ``head``: the first samples of y; ``offsets[1]``: the mean of y; ``products``: the
    lagged products ``lagged_products(x, scale, offset, k)`` for some k >= p, if already
    formed (one pass over x otherwise).  The innovations, S and D at the optimum come from
    one exact evaluation of :class:`~fogts.arma.likelihood.ExactLikelihood` (its workspace
    holds them), the standard errors from the exact Hessians of S and D at the optimum
    (:func:`~fogts.arma.standard_errors.full_hessian`).  Returns the model, the evaluation,
    the standard errors of (phi, sigma2), their covariance, a note (or None) and the
    Newton iterations.
    """
    n = x.shape[0]
    off = offsets[0] if mean else 0.0
    M = lagged_products(x, scale, off, p) if products is None or products.shape[0] <= p \
        else products
    k = M.shape[0] - 1
    lags = np.array([M[0, h] + float(np.dot(head[:k - h], head[h:k])) for h in range(p + 1)])
    model = ExactLikelihood(x, p, 0, mean=mean, scale=scale, offsets=(off,) if mean else ())
    stats = ar_statistics(lags, offsets[1] * n, head[:p], model.series(n - p, n), n)
    ob, n_iter, converged = maximise_ar(stats, mean)
    if not converged or (mean and unit_root_gap(ob.phi) < UNIT_ROOT_GAP):
        return None
    ev = model.evaluate(ob.phi, np.zeros(0))
    dS_opt = -(ev.S / model.nu) * ob.dD      # the stationarity condition of f
    se, cov, note = covariance(full_hessian(model.nu, ev.S, dS_opt, ob.d2S, ob.d2D))
    return model, ev, se, cov, note, n_iter
