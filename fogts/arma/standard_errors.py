"""Standard errors of an exact ML ARMA fit from the observed information.

The observed information is minus the Hessian of the log-likelihood in (phi, theta, sigma2),
as gretl and statsmodels' ``cov_type="approx"`` report it (statsmodels' default, the outer
product of gradients, differs by several percent).  With sigma2 concentrated out,

    l(beta, s2) = -n/2 log(2 pi s2) - D(beta)/2 - S(beta)/(2 s2),

and its Hessian at s2 = S/n follows from the gradient of S and the Hessians of S and D of
:mod:`fogts.arma.likelihood`: exact ones (central differences of the exact gradient) or, on
long series, the analytic Hessian of the last Newton step (with D's curvature from the
start-up block above 4e5 samples, :mod:`fogts.arma.startup_curvature`; dropped below).
Both are evaluated at the optimum itself, so the standard errors do not depend on the path
the iterations took (nor on the data's scale or the BLAS kernel).
"""

from __future__ import annotations

import numpy as np

from fogts._typing import FloatArray
from fogts.arma.likelihood import ExactLikelihood
from fogts.arma.optimiser import NewtonResult

__all__ = ["covariance", "full_hessian", "standard_errors"]


def full_hessian(n: int, S: float, dS: FloatArray, d2S: FloatArray,
                 d2D: FloatArray) -> FloatArray:
    """Hessian of l(beta, s2) = -n/2 log(2 pi s2) - D/2 - S/(2 s2) at s2 = S/n."""
    k = dS.shape[0]
    s2 = S / n
    H = np.empty((k + 1, k + 1))
    H[:k, :k] = -0.5 * d2D - d2S / (2 * s2)
    H[:k, k] = H[k, :k] = dS / (2 * s2 * s2)
    H[k, k] = n / (2 * s2 * s2) - S / s2**3
    return H


def standard_errors(model: ExactLikelihood, res: NewtonResult, *,
                    exact: bool) -> tuple[FloatArray, FloatArray, str | None]:
    """Standard errors of (phi, theta, sigma2) at the optimum ``res.ev``, their covariance
    (the inverse observed information; NaN if it is singular) and a note if the observed
    information is not positive definite (NaN where a variance is undefined).

    ``exact``: Hessians of S and D by central differences of the exact gradient; otherwise
    the last Newton step's analytic ones (``res.dD``, ``res.HS``, ``res.HD``).
    """
    n = model.nu       # n, or n - 1 with the mean removed (restricted likelihood)
    ev = res.ev
    assert res.HS is not None and res.HD is not None and res.dD is not None
    S = ev.S
    if exact:
        _, dD_opt, _ = model.derivatives(ev, hessian=False)
        d2S, d2D = model.fd_hessians(ev)
    else:
        dD_opt, d2S, d2D = res.dD, res.HS, res.HD
    dS_opt = -(S / n) * dD_opt     # the stationarity condition of f at the optimum
    return covariance(full_hessian(n, S, dS_opt, d2S, d2D))


def covariance(H: FloatArray) -> tuple[FloatArray, FloatArray, str | None]:
    """Standard errors and covariance from the log-likelihood's Hessian ``H`` (the inverse
    observed information -H^-1; NaN if singular), and a note if -H is not positive
    definite (NaN standard errors where a variance is undefined)."""
    note = None
    with np.errstate(invalid="ignore"):
        try:
            cov = np.linalg.inv(-H)
        except np.linalg.LinAlgError:
            cov = np.full(H.shape, np.nan)
        var = np.diag(cov)
        if not np.all(np.isfinite(var) & (var > 0)):
            note = ("the observed information matrix is not positive definite; "
                    "standard errors are NaN where undefined")
        se = np.sqrt(np.where(var > 0, var, np.nan))
    return se, np.asarray(cov, dtype=np.float64), note
