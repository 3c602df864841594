"""Parameter redundancy of a fitted ARMA model: nearly cancelling roots, insignificant terms.

* *near cancellation*: an AR inverse root and an MA inverse root closer than
  :data:`NEAR_CANCEL_TOL` in the complex plane.  The factor (1 - lambda B) then nearly
  divides both sides, so ARMA(p, q) is close to ARMA(p - 1, q - 1) and the pair is not
  identified.  Example: the drift paper's x_t = -0.2699 x_{t-1} - 0.002968 x_{t-2} + a_t +
  0.277 a_{t-1} has AR inverse roots -0.2584 and -0.0115 and the MA inverse root -0.277:
  distance 0.019;
* *common factor*: the AR and MA polynomials share a root within the sampling uncertainty
  of the fit (the Wald test of a zero resultant does not reject at 5 %), so the model is not
  identified and its reduced model ARMA(p - 1, q - 1) describes the data as well
  (:func:`common_factor`); ``select_arma`` ranks such a candidate after identified ones;
* *insignificant coefficient*: an AR or MA coefficient with |estimate / stderr| < 1.96.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any, Literal

import numpy as np

from fogts._typing import FloatArray
from fogts.arma.fit_result import model_name
from fogts.arma.roots import Roots, unit_circle_root
from fogts.arma.whiteness import BAND_Z

__all__ = ["NEAR_CANCEL_TOL", "RedundancyFlag", "common_factor", "common_factor_z",
           "insignificant_terms", "near_cancellations", "resultant"]

#: Largest distance between an AR and an MA inverse root called a near cancellation.
NEAR_CANCEL_TOL = 0.1


@dataclass(frozen=True)
class RedundancyFlag:
    """A sign that a candidate has more parameters than the data support.

    Attributes
    ----------
    kind : {"near_cancellation", "common_factor", "insignificant"}
    message : str
        One plain-language sentence.
    details : dict
        ``near_cancellation``: ``ar_root``, ``ma_root`` (inverse roots, complex),
        ``distance``, ``tolerance``; ``common_factor``: ``resultant``, ``resultant_se``, ``z``,
        ``critical``, ``ar_root``, ``ma_root`` (the closest pair), ``reduced`` (the reduced
        model's name), ``ma_on_unit_circle``; ``insignificant``: ``param``, ``estimate``,
        ``bse``, ``t``.
    """

    kind: Literal["near_cancellation", "common_factor", "insignificant"]
    message: str
    details: dict[str, Any]

    def to_dict(self) -> dict[str, Any]:
        det: dict[str, Any] = {}
        for k, v in self.details.items():
            det[k] = ({"real": float(v.real), "imag": float(v.imag)}
                      if isinstance(v, complex | np.complexfloating) else v)
        return {"kind": self.kind, "message": self.message, **det}


def _fmt_root(z: complex) -> str:
    if abs(z.imag) < 1e-12:
        return f"{z.real:+.4g}"
    return f"{z.real:+.4g}{z.imag:+.4g}i"


def near_cancellations(roots: Roots, *, tol: float = NEAR_CANCEL_TOL
                       ) -> tuple[RedundancyFlag, ...]:
    """AR/MA inverse-root pairs closer than ``tol``: a common factor that nearly cancels.

    Each MA inverse root is paired with its nearest AR inverse root (each AR root used
    once, closest pairs first).

    Examples
    --------
    >>> from fogts.arma.roots import arma_roots
    >>> f = near_cancellations(arma_roots([-0.2699, -0.002968], [0.277]))
    >>> f[0].kind, round(f[0].details["distance"], 3)
    ('near_cancellation', 0.019)
    """
    lam, mu = roots.ar_inverse, roots.ma_inverse
    if lam.size == 0 or mu.size == 0:
        return ()
    dist = np.abs(lam[:, None] - mu[None, :])
    pairs = sorted((float(dist[i, j]), i, j) for i in range(lam.size) for j in range(mu.size))
    used_i: set[int] = set()
    used_j: set[int] = set()
    flags = []
    for d, i, j in pairs:
        if d >= tol or i in used_i or j in used_j:
            continue
        used_i.add(i)
        used_j.add(j)
        ar_r, ma_r = complex(lam[i]), complex(mu[j])
        flags.append(RedundancyFlag(
            "near_cancellation",
            f"AR root {_fmt_root(ar_r)} nearly cancels MA root {_fmt_root(ma_r)} "
            f"(distance {d:.3g} < {tol:g}): the model is close to one with a lower order",
            {"ar_root": ar_r, "ma_root": ma_r, "distance": d, "tolerance": tol}))
    return tuple(flags)


def insignificant_terms(params: dict[str, float], bse: dict[str, float], *,
                        z: float = BAND_Z) -> tuple[RedundancyFlag, ...]:
    """AR/MA coefficients whose |estimate / standard error| < ``z`` (default 1.96).

    ``sigma2`` is not tested; a coefficient without a finite standard error is skipped.

    Examples
    --------
    >>> f = insignificant_terms({"ar.L1": 0.5, "ar.L2": 0.01, "sigma2": 1.0},
    ...                         {"ar.L1": 0.01, "ar.L2": 0.01, "sigma2": 0.01})
    >>> [x.details["param"] for x in f]
    ['ar.L2']
    """
    flags = []
    for name, est in params.items():
        if not name.startswith(("ar.", "ma.")):
            continue
        se = bse.get(name, math.nan)
        if not (math.isfinite(se) and se > 0):
            continue
        t = est / se
        if abs(t) < z:
            flags.append(RedundancyFlag(
                "insignificant",
                f"{name} = {est:.4g} is not significant (|t| = {abs(t):.2f} < {z:g})",
                {"param": name, "estimate": float(est), "bse": float(se), "t": float(t)}))
    return tuple(flags)


def resultant(ar: Any, ma: Any) -> float:
    """The resultant of the AR and MA polynomials: prod_ij (lambda_i - mu_j).

    lambda_i and mu_j are the inverse AR and MA roots (phi(B) = prod (1 - lambda_i B),
    theta(B) = prod (1 - mu_j B)), i.e. the roots of z^p - phi_1 z^(p-1) - ... - phi_p and
    z^q + theta_1 z^(q-1) + ... + theta_q.  It is the determinant of their Sylvester matrix,
    a polynomial in the coefficients, and it is 0 exactly when the two polynomials share a
    root (a common factor).  1.0 when p or q is 0 (no pair can cancel).

    Examples
    --------
    >>> round(resultant([0.5], [-0.5]), 12)      # phi(B) = theta(B) = 1 - 0.5 B
    0.0
    >>> round(resultant([0.6], [0.4]), 12)       # lambda = 0.6, mu = -0.4
    1.0
    """
    a = np.r_[1.0, -np.atleast_1d(np.asarray(ar, dtype=float))]
    b = np.r_[1.0, np.atleast_1d(np.asarray(ma, dtype=float))]
    p, q = a.size - 1, b.size - 1
    if p == 0 or q == 0:
        return 1.0
    syl = np.zeros((p + q, p + q))
    for i in range(q):
        syl[i, i:i + p + 1] = a
    for j in range(p):
        syl[q + j, j:j + q + 1] = b
    return float(np.linalg.det(syl))


def _resultant_gradient(ar: FloatArray, ma: FloatArray) -> FloatArray:
    """d resultant / d (phi, theta) by central differences.  The resultant is a polynomial
    of degree q in each phi_i and p in each theta_j, so the step's error is of order h^2
    times its third derivative (none for degree <= 2)."""
    h = 1e-6
    x = np.r_[ar, ma]
    g = np.empty(x.size)
    for k in range(x.size):
        up, dn = x.copy(), x.copy()
        up[k] += h
        dn[k] -= h
        g[k] = (resultant(up[:ar.size], up[ar.size:])
                - resultant(dn[:ar.size], dn[ar.size:])) / (2 * h)
    return g


def _resultant_se(phi: FloatArray, theta: FloatArray, cov: FloatArray,
                  nobs: int | None) -> tuple[float, float, complex | None]:
    """The resultant, its delta-method standard error (NaN if its variance is not > 0) and
    the MA inverse root on the unit circle (None if there is none; see :func:`common_factor`)."""
    res = resultant(phi, theta)
    grad = _resultant_gradient(phi, theta)
    c = np.asarray(cov, dtype=float)
    edge = None if nobs is None else unit_circle_root(np.roots(np.r_[1.0, theta]), nobs)
    if edge is not None:
        # theta known: the covariance of phi given theta (Schur complement), phi's gradient
        k = phi.size
        with np.errstate(invalid="ignore"):
            try:
                c = c[:k, :k] - c[:k, k:] @ np.linalg.solve(c[k:, k:], c[k:, :k])
            except np.linalg.LinAlgError:
                c = np.full((k, k), np.nan)
        grad = grad[:k]
    var = float(grad @ c @ grad)
    return res, (math.sqrt(var) if math.isfinite(var) and var > 0 else math.nan), edge


def common_factor_z(ar: Any, ma: Any, cov: FloatArray | None, *,
                    nobs: int | None = None) -> float:
    """The Wald statistic R / se(R) of :func:`common_factor`; NaN for a pure AR or MA model,
    without ``cov`` or when se(R) is undefined.

    Examples
    --------
    >>> import numpy as np
    >>> round(common_factor_z([0.5, 0.2], [0.5], np.diag([0.03, 0.03, 0.03]) ** 2), 1)
    5.3
    """
    phi = np.atleast_1d(np.asarray(ar, dtype=float))
    theta = np.atleast_1d(np.asarray(ma, dtype=float))
    if phi.size == 0 or theta.size == 0 or cov is None:
        return math.nan
    res, se, _ = _resultant_se(phi, theta, cov, nobs)
    return res / se if math.isfinite(se) else math.nan


def common_factor(ar: Any, ma: Any, cov: FloatArray | None, *, nobs: int | None = None,
                  z: float = BAND_Z) -> tuple[RedundancyFlag, ...]:
    """A flag if the AR and MA polynomials share a root within the fit's sampling uncertainty.

    The hypothesis of a common factor is that the resultant R of the two polynomials
    (:func:`resultant`) is 0.  Its Wald statistic is R / se(R), with se(R)^2 = g' C g by the
    delta method (g the gradient of R in the coefficients, C ``cov``, their covariance from
    the observed information).  If |R / se(R)| < ``z`` (1.96: a two-sided 5 % test) the data
    cannot tell the model from one whose AR and MA parts share a factor; such a model is
    ARMA(p - 1, q - 1) with the factor cancelled, its parameters are not identified (Box,
    Jenkins & Reinsel, *Time Series Analysis*, 3rd ed., 1994, sec. 7.3.5, "parameter
    redundancy"; Brockwell & Davis, *Time Series: Theory and Methods*, 2nd ed., 1991,
    secs. 3.1 and 8.8), and parsimony prefers the reduced model.  The Wald test of
    common-factor restrictions is Sargan's (1980, *Econometrica* 48, 879-897, "COMFAC").
    If R has no finite standard error (the observed information is not positive definite,
    itself a sign of a flat likelihood), a common factor cannot be ruled out and the flag is
    raised too.  Nothing is flagged for a pure AR or MA model or without ``cov``.

    On the boundary, an MA inverse root on the unit circle (within 1/n, given ``nobs``), the
    MA estimate converges at rate n, not sqrt(n), and is not asymptotically normal (Davis &
    Dunsmuir 1996, *Econometric Theory* 12, 1-29): its observed-information variance means
    nothing there.  The test then takes theta as known, as its O(1/n) error is negligible
    against phi's O(1/sqrt(n)): se(R) uses phi's gradient and phi's covariance given theta
    (the Schur complement of the theta block).

    Parameters
    ----------
    ar, ma : array_like
        phi_1..phi_p and theta_1..theta_q (statsmodels' signs).
    cov : ndarray or None
        Covariance of (phi_1..phi_p, theta_1..theta_q), e.g. ``ArmaFit.coef_cov``.
    nobs : int, optional
        Series length, for the boundary case; without it no MA root counts as on the circle.
    z : float
        Critical value of |R / se(R)|.

    Examples
    --------
    >>> import numpy as np
    >>> cov = np.diag([0.03, 0.03, 0.03]) ** 2
    >>> f = common_factor([0.2, 0.35], [0.5], cov)   # inverse roots 0.7, -0.5 and MA -0.5
    >>> f[0].details["reduced"], round(f[0].details["z"], 2)
    ('AR(1)', 0.0)
    >>> common_factor([0.5, 0.2], [0.5], cov)         # inverse roots 0.76, -0.26; MA -0.5
    ()
    """
    phi = np.atleast_1d(np.asarray(ar, dtype=float))
    theta = np.atleast_1d(np.asarray(ma, dtype=float))
    if phi.size == 0 or theta.size == 0 or cov is None:
        return ()
    res, se, edge = _resultant_se(phi, theta, cov, nobs)
    stat = res / se if math.isfinite(se) else math.nan
    if math.isfinite(stat) and abs(stat) >= z:
        return ()
    lam = np.roots(np.r_[1.0, -phi])
    mu = np.roots(np.r_[1.0, theta])
    i, j = np.unravel_index(int(np.argmin(np.abs(lam[:, None] - mu[None, :]))),
                            (lam.size, mu.size))
    ar_r, ma_r = complex(lam[i]), complex(mu[j])
    p, q = phi.size - 1, theta.size - 1
    reduced = "white noise" if p + q == 0 else model_name(p, q)
    if math.isfinite(stat):
        why = (f"their resultant {res:.3g} is {abs(stat):.2f} standard errors ({se:.2g}) "
               f"from 0, < {z:g}")
        if edge is not None:
            why += f" (the MA root {_fmt_root(edge)} on the unit circle taken as known)"
    else:
        why = (f"their resultant {res:.3g} has no standard error (the observed information "
               "is not positive definite), so a shared root cannot be ruled out")
    return (RedundancyFlag(
        "common_factor",
        f"the AR and MA parts may share a root (closest pair: AR {_fmt_root(ar_r)}, MA "
        f"{_fmt_root(ma_r)}): {why}; the model is then {reduced} with a cancelled factor, "
        "not identified",
        {"resultant": res, "resultant_se": se, "z": stat, "critical": z, "ar_root": ar_r,
         "ma_root": ma_r, "reduced": reduced, "ma_on_unit_circle": edge is not None}),)
