"""Weighted least squares on the Allan variance: the fits of :func:`fogts.allan.noise.fit_noise`.

The model :math:`\\sigma^2(\\tau) = \\sum_n a_n \\tau^n` is linear in :math:`a_n = C_n^2 \\ge 0`
(:mod:`fogts.allan.terms`); every fit here is non-negative least squares
(``scipy.optimize.nnls``) on :math:`\\sigma^2`, with columns scaled (the basis spans many
decades).

Weights (``method="wls"``)
    An estimate with ``edf`` degrees of freedom is distributed as
    :math:`\\sigma^2\\chi^2_{edf}/edf`, so :math:`\\mathrm{Var}[\\hat\\sigma^2] =
    2\\sigma^4/edf` (NIST SP1065 sec. 5.3; IEEE 952 C.3).  Each point is weighted by the
    inverse of that variance at the *model* value :math:`\\mu_i` (a weight from the
    observation favours points that happen to fall low and biases the fit downwards), so
    the fit is iterated (IRLS) until :math:`\\mu` changes by less than ``1e-7`` relative:
    the maximum-likelihood estimate for independent scaled-chi-square observations, a Gamma
    GLM with identity link (McCullagh & Nelder, *Generalized Linear Models*, 2nd ed., 1989,
    ch. 8) restricted to :math:`a_n \\ge 0`.  Each weight is also multiplied by the width in
    octaves (at most 1) of the tau interval its point represents (:func:`octave_density`),
    so that a dense grid does not count the data shared by close taus many times.

Model error
    :math:`\\mathrm{Var}[\\hat\\sigma^2_i] = \\mu_i^2 (2/edf_i + \\epsilon^2)`, with
    :math:`\\epsilon` estimated by maximum likelihood profiled over the coefficients: Gamma
    with shape :math:`1/(2/edf_i + \\epsilon^2)`, or Gaussian with covariance
    :math:`V + \\epsilon^2 \\mathrm{diag}(\\mu^2)` for ``gls``.  This is the random-effects
    model of Paule & Mandel (*J. Res. NBS* 87(5), 1982) with a likelihood instead of their
    moment equation.  :math:`\\epsilon^2 = 0` lies on the boundary, so :math:`\\epsilon` is
    kept only if :math:`2(\\ell(\\hat\\epsilon) - \\ell(0))` exceeds ``crit``, the critical
    value of the 50:50 mixture of :math:`\\chi^2_0` and :math:`\\chi^2_1`, i.e.
    :math:`z_{1-\\alpha}^2` (Self & Liang, *J. Am. Stat. Assoc.* 82(398), 1987, case 1);
    ``crit = 0`` keeps the unrestricted ML estimate.

Coefficient covariance
    The sandwich :math:`H^{-1}A^TWVWAH^{-1}`, :math:`H = A^TWA`, with :math:`V` the model
    covariance of the estimates (:mod:`fogts.allan.covariance`; overlapping estimates at
    neighbouring octave taus correlate about 0.5 for white rate noise and 0.9 for a rate
    random walk) plus the model error; for ``totdev`` :math:`V` takes the correlations of
    the oadev model covariance at the same taus and totdev's own EDF variances
    :math:`2\\mu_i^2/edf_i`.  The rate ramp R has no variance of its own.  Without ``m``,
    ``n_samples`` and ``fs_hz``, or with more than :data:`MAX_COVARIANCE_POINTS` taus,
    :math:`V` is the EDF diagonal.  ``method="gls"`` fits with :math:`V` itself (recomputed
    from the current fit, whitened by its Cholesky factor, NNLS; covariance
    :math:`(A^TV^{-1}A)^{-1}`); ``method="ols"`` is unweighted NNLS with covariance
    :math:`s^2(A^TA)^{-1}`.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np
import numpy.typing as npt
from scipy.optimize import minimize_scalar, nnls
from scipy.special import gammaln

from fogts._typing import FloatArray, IntArray
from fogts.allan.covariance import CovarianceModel, covariance_basis
from fogts.allan.noise_input import FitCurve
from fogts.choices import FIT_METHODS, FitMethod

__all__ = ["FIT_METHODS", "IRLS_MAX_ITER", "MAX_COVARIANCE_POINTS", "FitMethod", "LsqFit",
           "LsqProblem", "chi2_sentence", "curve_covariance_basis", "octave_density"]

#: Largest grid for which the full model covariance of the estimates is computed.
MAX_COVARIANCE_POINTS = 200
#: Most reweighting iterations of one IRLS fit.
IRLS_MAX_ITER = 60
_IRLS_TOL = 1e-7


@dataclass(frozen=True)
class LsqFit:
    """One least-squares fit of the scaled :math:`\\sigma^2`.

    Attributes
    ----------
    a : ndarray
        Squared coefficients (scaled units).
    mu : ndarray
        Model sigma^2 at the data taus.
    w : ndarray
        Final diagonal weights.
    cov : callable
        ``cov(idx)``: covariance of ``a[idx]`` with the terms ``idx`` free, the rest fixed.
    stderr_method : str
        Which covariance ``cov`` uses.
    model_error : float
        Relative standard deviation added to every point (NaN for OLS).
    chi2, dof : float
        Pearson chi-square (residual sum of squares for OLS) and degrees of freedom.
    iterations : int
    converged : bool
    """

    a: FloatArray
    mu: FloatArray
    w: FloatArray
    cov: Callable[[IntArray], FloatArray]
    stderr_method: str
    model_error: float
    chi2: float
    dof: float
    iterations: int
    converged: bool


@dataclass(frozen=True)
class LsqProblem:
    """A noise fit's least-squares problem: ``y ~ design @ a``, ``a >= 0``.

    Attributes
    ----------
    design : ndarray, shape (n_tau, n_terms)
        ``tau^n`` of each requested term.
    y : ndarray
        The Allan variances divided by ``scale``.
    scale : float
        Median of the Allan variances.
    edf, density : ndarray
        Degrees of freedom and octave width (:func:`octave_density`) per point.
    covm : CovarianceModel or None
        Model covariance of the estimates (None: EDF diagonal).
    method : str
        ``"wls"``, ``"gls"`` or ``"ols"``.
    crit : float
        Critical value of the model-error likelihood-ratio test (0: unrestricted).
    """

    design: FloatArray
    y: FloatArray
    scale: float
    edf: FloatArray
    density: FloatArray
    covm: CovarianceModel | None
    method: str
    crit: float

    def solve(self, free: npt.NDArray[np.bool_]) -> LsqFit:
        """Fit the ``free`` terms (the others stay at 0) by the problem's method."""
        if self.method == "ols":
            return _fit_ols(self.design, self.y)
        wls = _fit_wls(self.design, self.y, self.edf, self.density, self.covm, free,
                       self.crit)
        if self.method == "gls":
            assert self.covm is not None
            return _fit_gls(self.design, self.y, self.edf, self.covm, wls, free, self.crit)
        return wls


def curve_covariance_basis(curve: FitCurve, powers: IntArray) -> FloatArray | None:
    """The model-covariance basis of the curve's estimates (:mod:`fogts.allan.covariance`),
    or None without ``m``, ``n_samples`` and ``fs_hz`` or with more than
    :data:`MAX_COVARIANCE_POINTS` taus."""
    if (curve.m is None or curve.n_samples is None or curve.fs_hz is None
            or curve.tau.size > MAX_COVARIANCE_POINTS):
        return None
    return covariance_basis(curve.kind, curve.m, curve.n_samples, curve.fs_hz, powers)


def octave_density(tau: FloatArray) -> FloatArray:
    """Width in octaves (<= 1) of the tau interval each point represents.

    Half the log2-distance to the neighbours (the full distance at the ends); 1 on octave
    or sparser grids.

    Examples
    --------
    >>> octave_density(np.array([1.0, 2.0, 4.0, 4.5])).round(3).tolist()
    [1.0, 1.0, 0.585, 0.17]
    """
    if tau.size == 1:
        return np.ones(1)
    lg = np.log2(tau)
    gaps = np.diff(lg)
    width = np.empty_like(lg)
    width[0], width[-1] = gaps[0], gaps[-1]
    width[1:-1] = 0.5 * (gaps[:-1] + gaps[1:])
    return np.minimum(width, 1.0)


def _wnnls(design: FloatArray, y: FloatArray, w: FloatArray) -> FloatArray:
    """Weighted NNLS with column scaling (the basis spans many decades)."""
    sw = np.sqrt(w)
    return _nnls_scaled(design * sw[:, None], y * sw)


def _nnls_scaled(a: FloatArray, b: FloatArray) -> FloatArray:
    col = np.linalg.norm(a, axis=0)
    col[col == 0] = 1.0
    sol, _ = nnls(a / col, b, maxiter=50 * a.shape[1])
    return np.asarray(sol / col, dtype=np.float64)


def _forward_substitution(lower: npt.NDArray[np.floating[Any]], rhs: FloatArray) -> FloatArray:
    """Solve ``lower @ x = rhs`` row by row.

    For these small systems (at most MAX_COVARIANCE_POINTS rows) a plain loop avoids the
    overhead of LAPACK's threaded triangular solve; it is exact to round-off.
    """
    x = np.empty_like(rhs)
    for i in range(lower.shape[0]):
        x[i] = (rhs[i] - lower[i, :i] @ x[:i]) / lower[i, i]
    return x


def _scaled_inverse(normal: FloatArray) -> FloatArray:
    d = np.sqrt(np.abs(np.diag(normal)))
    d[d == 0] = 1.0
    return np.asarray(np.linalg.pinv(normal / np.outer(d, d), rcond=1e-13) / np.outer(d, d),
                      dtype=np.float64)


def _irls(step: Callable[[FloatArray, FloatArray], tuple[FloatArray, FloatArray]],
          mu0: FloatArray, a0: FloatArray) -> tuple[FloatArray, FloatArray, int, bool]:
    """Iterate ``(a, mu) -> step`` until mu changes by < 1e-7 relative (damped late)."""
    mu, a = mu0, a0
    for it in range(1, IRLS_MAX_ITER + 1):
        a, new = step(mu, a)
        if it > IRLS_MAX_ITER // 3:  # damp a slow oscillation between active sets
            new = np.sqrt(new * mu)
        change = float(np.max(np.abs(new - mu) / mu))
        mu = new
        if change < _IRLS_TOL:
            return a, mu, it, True
    return a, mu, IRLS_MAX_ITER, False


def _ml_eps2(nll: Callable[[float], float], crit: float) -> float:
    """The model-error variance eps2 >= 0 that minimises ``nll`` (profile likelihood).

    eps2 = 0 is kept unless the likelihood-ratio statistic ``2 (nll(0) - nll(eps2))``
    exceeds ``crit`` (the chi-bar-squared critical value of the boundary test; 0 accepts
    any improvement, i.e. the unrestricted ML estimate).
    """
    base = nll(0.0)
    best = minimize_scalar(lambda t: nll(math.exp(t)), bounds=(math.log(1e-8), math.log(10.0)),
                           method="bounded", options={"xatol": 1e-3})
    return math.exp(float(best.x)) if 2.0 * (base - float(best.fun)) > crit else 0.0


def _nnls_free(a: FloatArray, b: FloatArray, free: npt.NDArray[np.bool_]) -> FloatArray:
    """NNLS on the ``free`` columns only; the other coefficients are fixed at 0."""
    out = np.zeros(a.shape[1])
    out[free] = _nnls_scaled(a[:, free], b)
    return out


def _fit_wls(design: FloatArray, y: FloatArray, edf: FloatArray, density: FloatArray,
             covm: CovarianceModel | None, free: npt.NDArray[np.bool_], crit: float) -> LsqFit:
    """EDF-weighted IRLS + ML model error; sandwich errors (module docstring).

    Only the ``free`` terms are fitted (the others stay at 0); ``crit`` is the critical
    value of the likelihood-ratio test of the model error (:func:`_ml_eps2`).
    """
    floor = 1e-12 * float(np.max(y))
    state: dict[str, Any] = {"mu": y.copy(), "a": np.zeros(design.shape[1]), "iters": 0}

    def solve(eps2: float) -> tuple[FloatArray, FloatArray, FloatArray, int, bool]:
        rel = 2.0 / edf + eps2

        def step(mu: FloatArray, a: FloatArray) -> tuple[FloatArray, FloatArray]:
            sw = np.sqrt(density / (rel * mu**2))
            a_new = _nnls_free(design * sw[:, None], y * sw, free)
            return a_new, np.maximum(design @ a_new, floor)

        a, mu, it, ok = _irls(step, state["mu"], state["a"])
        state.update(mu=mu, a=a, iters=state["iters"] + it)
        return a, mu, density / (rel * mu**2), it, ok

    def nll(eps2: float) -> float:
        # Gamma likelihood of sigma^2-hat with mean mu and shape k = 1 / (2/edf + eps2)
        _, mu, _, _, _ = solve(eps2)
        k = 1.0 / (2.0 / edf + eps2)
        ll = k * np.log(k) - k * np.log(mu) + (k - 1) * np.log(y) - k * y / mu - gammaln(k)
        return -float(np.sum(density * ll))

    eps2 = _ml_eps2(nll, crit)
    a, mu, w, _, ok = solve(eps2)
    chi2 = float(np.sum(w * (y - mu) ** 2))
    dof = float(np.sum(density)) - np.count_nonzero(a > 0)
    if covm is not None:
        v = covm(a, mu, edf) + np.diag(eps2 * mu**2)
        how = f"sandwich with {covm.label}"
    else:  # kept as its diagonal: a grid of every tau has ~n/2 points
        v_diag = mu**2 * (2.0 / edf + eps2)
        how = "EDF diagonal (correlation between taus ignored)"

    def cov(idx: IntArray) -> FloatArray:
        x = design[:, idx] * w[:, None]
        h_inv = _scaled_inverse(design[:, idx].T @ x)
        meat = x.T @ v @ x if covm is not None else x.T @ (v_diag[:, None] * x)
        return h_inv @ meat @ h_inv

    return LsqFit(a=a, mu=mu, w=w, cov=cov, stderr_method=how, model_error=math.sqrt(eps2),
                  chi2=chi2, dof=dof, iterations=int(state["iters"]), converged=ok)


def _fit_gls(design: FloatArray, y: FloatArray, edf: FloatArray, covm: CovarianceModel,
             start: LsqFit, free: npt.NDArray[np.bool_], crit: float) -> LsqFit:
    """GLS with the model covariance recomputed from the fit (IRLS) + ML model error."""
    floor = 1e-12 * float(np.max(y))
    state: dict[str, Any] = {"iters": 0}

    def cov_of(a: FloatArray, mu: FloatArray, eps2: float) -> FloatArray:
        return covm(a, mu, edf) + np.diag((eps2 + 1e-10) * mu**2)

    def solve(eps2: float) -> tuple[FloatArray, FloatArray, FloatArray, int, bool]:
        def step(mu: FloatArray, a: FloatArray) -> tuple[FloatArray, FloatArray]:
            chol = np.linalg.cholesky(cov_of(a, mu, eps2))
            white = _forward_substitution(chol, np.column_stack([design, y]))
            a_new = _nnls_free(white[:, :-1], white[:, -1], free)
            return a_new, np.maximum(design @ a_new, floor)

        a, mu, it, ok = _irls(step, start.mu, start.a)
        state["iters"] += it
        return a, mu, cov_of(a, mu, eps2), it, ok

    def nll(eps2: float) -> float:
        # Gaussian approximation: r' V^-1 r + log det V
        _, mu, v, _, _ = solve(eps2)
        r = y - mu
        chol = np.linalg.cholesky(v)
        z = _forward_substitution(chol, r[:, None])[:, 0]
        return 0.5 * float(z @ z) + float(np.sum(np.log(np.diag(chol))))

    eps2 = _ml_eps2(nll, crit)
    a, mu, v, _, ok = solve(eps2)
    r = y - mu
    v_inv = np.linalg.inv(v)

    def cov(idx: IntArray) -> FloatArray:
        x = design[:, idx]
        return _scaled_inverse(x.T @ v_inv @ x)

    return LsqFit(a=a, mu=mu, w=1.0 / np.diag(v), cov=cov,
                  stderr_method=f"GLS with {covm.label}", model_error=math.sqrt(eps2),
                  chi2=float(r @ v_inv @ r), dof=float(y.size - np.count_nonzero(a > 0)),
                  iterations=start.iterations + int(state["iters"]), converged=ok)


def _fit_ols(design: FloatArray, y: FloatArray) -> LsqFit:
    """Unweighted NNLS on sigma^2 (the traditional fit); covariance s^2 (A^T A)^-1."""
    w = np.ones_like(y)
    a = _wnnls(design, y, w)
    mu = design @ a
    rss = float(np.sum((y - mu) ** 2))
    dof = float(y.size - np.count_nonzero(a > 0))
    s2 = rss / dof if dof > 0 else math.nan

    def cov(idx: IntArray) -> FloatArray:
        x = design[:, idx]
        return s2 * _scaled_inverse(x.T @ x)

    return LsqFit(a=a, mu=mu, w=w, cov=cov, stderr_method="OLS residual variance",
                  model_error=math.nan, chi2=rss, dof=dof, iterations=1, converged=True)


def chi2_sentence(chi2: float, dof: float, model_error: float) -> str:
    """The least-squares fit's chi-square with what it can and cannot tell: a model error
    estimated by maximum likelihood (:mod:`fogts.allan.noise_lsq`) is added to the
    variances in the weights, which brings chi2 near its dof whatever the misfit; the
    model error itself, and the fit check, measure the misfit then.

    Examples
    --------
    >>> chi2_sentence(14.9, 17, 0.122)
    'chi2 = 14.9 on 17 dof after adding the fitted model error 0.122 (relative, on sigma^2) to the variances (which brings chi2 near its dof: the model error and the fit check measure the misfit)'
    >>> chi2_sentence(15.2, 17, 0.0)
    'chi2 = 15.2 on 17 dof; no model error needed (relative, on sigma^2)'
    """
    head = f"chi2 = {chi2:.4g} on {dof:.4g} dof"
    if not math.isfinite(model_error):
        return head + " (unweighted residual sum of squares)"
    if model_error == 0:
        return head + "; no model error needed (relative, on sigma^2)"
    return (f"{head} after adding the fitted model error {model_error:.3g} (relative, on "
            "sigma^2) to the variances (which brings chi2 near its dof: the model error and "
            "the fit check measure the misfit)")
