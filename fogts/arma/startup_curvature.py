"""The curvature of the log-determinant term D of the exact ARMA likelihood, without the data.

The profile objective of :mod:`fogts.arma.likelihood` is f = nu/2 log(S/nu) + D/2 with
D = sum log F_t (plus log(s11/n) with the GLS mean).  F_t, the relative innovation variances,
and s11 = 1' R^-1 1 depend on the parameters and n only, not on the data (Brockwell & Davis
1991, eqs. 8.7.4-8.7.5; Harville 1974 for s11), and F_t = 1 from the steady part on.  So the
Hessian of D is a function of the start-up block alone: a few banded Cholesky factorisations
of its covariance (Ansley 1979), none of a series-length pass.

Away from the boundary of the stationarity region D is O(1) and its curvature negligible
against S's O(n); but near a unit AR root, as an ARMA(1,1) fit of a white + random-walk gyro
record reaches, D grows like -log(1 - phi) and its curvature, 1/(1 - phi)^2, is as large as
the data's: a Newton step without it overshoots the boundary and the line search crawls.

References
----------
P. J. Brockwell and R. A. Davis, *Time Series: Theory and Methods*, 2nd ed., 1991.
C. F. Ansley, "An algorithm for the exact likelihood of a mixed autoregressive-moving average
process", Biometrika 66 (1979) 59-65.
D. A. Harville, "Bayesian inference for variance components using only error contrasts",
Biometrika 61 (1974) 383-385.
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING

import numpy as np

from fogts._typing import FloatArray
from fogts.arma.region import admissible, spectral_radius
from fogts.arma.startup_block import banded_innovations

if TYPE_CHECKING:
    from fogts.arma.likelihood import Evaluation, ExactLikelihood

__all__ = ["CURVATURE_STEP", "STREAMED_BLOCK", "d_hessian"]

#: Samples of a streamed start-up block whose D's curvature :func:`d_hessian` takes.
STREAMED_BLOCK = 1 << 18

#: Largest central-difference step of the second differences of D (halved until every
#: perturbed model is stationary and invertible).
CURVATURE_STEP = 1e-5


def _d_values(model: ExactLikelihood, betas: FloatArray, s: int) -> FloatArray:
    """D at each row of ``betas`` with a start-up block of ``s`` samples (the same terms as
    :meth:`ExactLikelihood.evaluate`: sum log F_t, and log(s11 / n) with the GLS mean),
    one row at a time (one block's factor in memory)."""
    p = model.p
    zeros = np.zeros(s)
    out = np.empty(betas.shape[0])
    for r, beta in enumerate(betas):
        e, F, _ = banded_innovations(beta[:p], beta[p:], zeros, with_ones=model.mean)
        d = float(np.sum(np.log(F)))
        if model.mean:
            s11 = model._s11_perturbed(beta[None, :], s, e[None, :, 1], F[None, :])[0]
            d += math.log(s11 / model.n)
        out[r] = d
    return out


def _steps(beta: FloatArray, p: int) -> FloatArray:
    """One step per parameter: ``CURVATURE_STEP``, at most 1 % of the distance g of the
    largest inverse AR or MA root from the unit circle, halved until every corner
    beta +- h_i +- h_j (and +- 2 h_i) is admissible.

    Near a unit root D ~ -log(g), and the second difference with step 2h is off by
    2 (h / g)^2 relative (its Taylor remainder), 2e-4 at h = g / 100.
    """
    k = beta.size
    gap = 1.0 - max(spectral_radius(beta[:p]), spectral_radius(-beta[p:]))
    h = np.full(k, min(CURVATURE_STEP, 0.01 * gap))
    for _ in range(60):
        corners = [beta + sgn * 2.0 * h[i] * np.eye(k)[i] for i in range(k) for sgn in (1, -1)]
        corners += [beta + si * h[i] * np.eye(k)[i] + sj * h[j] * np.eye(k)[j]
                    for i in range(k) for j in range(i + 1, k)
                    for si in (1, -1) for sj in (1, -1)]
        if all(admissible(c[:p], c[p:], margin=0.0) for c in corners):
            return h
        h *= 0.5
    return h


def d_hessian(model: ExactLikelihood, ev: Evaluation) -> FloatArray:
    """Hessian of D at ``ev`` by central second differences of D (data-free, see the module
    docstring).  For a start-up block too long to hold (``ev.streamed``) it is that of its
    first ``STREAMED_BLOCK`` samples, the filter taken as steady after them (the unit AR
    root's term -log(1 - phi) sits in the first few samples): an approximation, which the
    Newton steps tolerate (their gradient is exact).

    Second differences: H_ii = (D(+2h_i) - 2 D + D(-2h_i)) / (4 h_i^2),
    H_ij = (D(+h_i+h_j) - D(+h_i-h_j) - D(-h_i+h_j) + D(-h_i-h_j)) / (4 h_i h_j).
    """
    k = model.p + model.q
    if k == 0:
        return np.zeros((k, k))
    s = ev.s if not ev.streamed else min(ev.s, STREAMED_BLOCK)
    beta = ev.beta
    h = _steps(beta, model.p)
    eye = np.eye(k)
    rows = [beta] + [beta + sgn * 2.0 * h[i] * eye[i] for i in range(k) for sgn in (1, -1)]
    pairs = [(i, j) for i in range(k) for j in range(i + 1, k)]
    rows += [beta + si * h[i] * eye[i] + sj * h[j] * eye[j]
             for i, j in pairs for si in (1, -1) for sj in (1, -1)]
    d = _d_values(model, np.array(rows), s)
    H = np.empty((k, k))
    for i in range(k):
        H[i, i] = (d[1 + 2 * i] - 2.0 * d[0] + d[2 + 2 * i]) / (4.0 * h[i] * h[i])
    base = 1 + 2 * k
    for m, (i, j) in enumerate(pairs):
        pp, pm, mp, mm = d[base + 4 * m:base + 4 * m + 4]
        H[i, j] = H[j, i] = (pp - pm - mp + mm) / (4.0 * h[i] * h[j])
    return H
