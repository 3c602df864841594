"""The GMWM estimator on one wavelet-variance curve: composite models, the weighted fit, the
model choice and the asymptotic covariance (used by :mod:`fogts.allan.gmwm`).

Everything here works on the Haar wavelet variance scaled by its median ``s``
(:class:`WvData`): the moment vector :math:`\\hat\\nu` and the model
:math:`\\nu(\\theta)` (:mod:`fogts.allan.wv_models`).

Estimator (Guerrier, Skaloud, Stebler & Victoria-Feser 2013, *J. Am. Stat. Assoc.* 108,
eq. 2)
    :math:`\\hat\\theta = \\arg\\min_\\theta (\\hat\\nu - \\nu(\\theta))^T\\Omega
    (\\hat\\nu - \\nu(\\theta))`, solved as the nonlinear least squares of the whitened
    residual :math:`L^{-1}(\\hat\\nu - \\nu(\\theta))`, :math:`\\Omega^{-1} = LL^T`
    (``scipy.optimize.least_squares``, trust-region reflective), with every positive
    parameter by its logarithm: :math:`\\log a_n` of each power law, and
    :math:`\\log s^2_j, \\log T_j` of each Gauss-Markov term (``T_j`` bounded to
    ``[Delta t, tau_max / 8]``: :data:`T_MAX_DIVISOR`).  Starting values come from a pilot fit (the five-term
    WLS fit of :mod:`fogts.allan.noise_lsq`): its power laws, and ``k`` Gauss-Markov
    terms spread over the region of its flicker term from three spreads (multiple starts).

Asymptotic covariance (ibid., Proposition 2; Hansen, *Econometrica* 50(4), 1982, Thm 3.1)
    :math:`\\mathrm{Var}\\,\\hat\\theta = (A^T\\Omega A)^{-1}A^T\\Omega V\\Omega A
    (A^T\\Omega A)^{-1}`, :math:`A = \\partial\\nu/\\partial\\theta^T` at
    :math:`\\hat\\theta`, with :math:`V` the covariance of :math:`\\hat\\nu`; it is
    :math:`(A^TV^{-1}A)^{-1}` when :math:`\\Omega = V^{-1}`.

Model choice (Andrews & Lu, "Consistent model and moment selection procedures for GMM
estimation with application to dynamic panel data models", *J. Econometrics* 101(1),
2001, 123-164, MMSC-HQIC)
    With the moments fixed, the model with the smallest :math:`J + 2.01\\,p\\ln\\ln n`
    wins (:math:`J` the objective at the optimum, ``p`` parameters, ``n`` samples of the
    record; their BIC-type :math:`p\\ln n` needs :math:`z > 3.7` for a term to enter at
    1e6 samples, which drops rate random walks that the curve does show);
    :func:`select_model` runs a backward elimination of the power laws from each starting
    structure (the requested power laws with flicker, or with ``k`` Gauss-Markov terms).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy.linalg import cho_factor, cho_solve, solve_triangular
from scipy.optimize import least_squares

from fogts._typing import FloatArray
from fogts.allan.covariance import RANDOM_TERMS
from fogts.allan.wv_models import GM_PEAK, ar1_wv, power_law_wv

__all__ = ["Composite", "GmwmSolution", "WvData", "fit_composite", "model_covariance_wv",
           "select_model", "solution_covariance"]

_SPREADS: tuple[float, ...] = (4.0, 16.0, 64.0)
#: A Gauss-Markov correlation time is at most tau_max / 8: its Allan hump (peak at 1.89 T)
#: then lies two octaves inside the data, and a longer one is a rate random walk to the data.
T_MAX_DIVISOR = 8.0
#: Re-weightings of each full model with the covariance at its fit (iterated GMWM).
V_STEPS = 2
#: Q of Andrews & Lu's MMSC-HQIC, J + Q p ln ln n (they require Q > 2).
HQ_FACTOR = 2.01
_FD_STEP = 1e-5
_TOL = 1e-6            # relative change of J (or of the log parameters) at convergence
_NFEV_PER_PARAM = 40


@dataclass(frozen=True)
class WvData:
    """One curve's wavelet variances, scaled by their median ``scale``, and what the
    covariance of the estimates needs.

    ``basis`` is the model-covariance basis of the Allan-variance estimates
    (:func:`fogts.allan.covariance.covariance_basis`, power laws Q, N, B, K), ``dt`` the
    sampling interval, ``n_samples`` the record length."""

    tau: FloatArray
    nu: FloatArray
    scale: float
    dt: float
    n_samples: int
    basis: FloatArray


@dataclass(frozen=True)
class Composite:
    """A composite model: the power laws ``powers`` (subset of Q, N, B, K, R by power) and
    ``n_gm`` Gauss-Markov terms; theta = log a of each power law, then (log s2, log T)
    of each Gauss-Markov term."""

    powers: tuple[int, ...]
    n_gm: int

    @property
    def n_params(self) -> int:
        return len(self.powers) + 2 * self.n_gm

    def label(self) -> str:
        names = {-2: "Q", -1: "N", 0: "B", 1: "K", 2: "R"}
        parts = [names[p] for p in self.powers] + (
            [f"{self.n_gm} GM"] if self.n_gm else [])
        return " + ".join(parts) if parts else "(empty)"


@dataclass(frozen=True)
class GmwmSolution:
    """One fitted composite model.

    ``theta`` (logs, scaled units), ``j_stat`` (the objective at the optimum),
    ``jac_w`` (Jacobian of the whitened residual, ``-L^{-1} A``), ``nfev``,
    ``converged``, and the whitening matrix ``w`` it was fitted with."""

    model: Composite
    theta: FloatArray
    j_stat: float
    jac_w: FloatArray
    nfev: int
    converged: bool
    w: FloatArray

    def criterion(self, n_samples: int) -> float:
        """MMSC-HQIC of Andrews & Lu (2001): ``J + 2.01 p ln ln n``."""
        return self.j_stat + HQ_FACTOR * self.model.n_params * math.log(math.log(n_samples))


def model_parts(theta: FloatArray, model: Composite, data: WvData) -> list[FloatArray]:
    """Each term's scaled WV at the data taus: the power laws, then the Gauss-Markov ones."""
    k = len(model.powers)
    out = [power_law_wv(math.exp(theta[i]), p, data.tau) for i, p in enumerate(model.powers)]
    for j in range(model.n_gm):
        s2, t_c = math.exp(theta[k + 2 * j]), math.exp(theta[k + 2 * j + 1])
        out.append(ar1_wv(s2, t_c, data.tau, data.dt))
    return out


def model_wv(theta: FloatArray, model: Composite, data: WvData) -> FloatArray:
    parts = model_parts(theta, model, data)
    return np.sum(parts, axis=0) if parts else np.zeros_like(data.tau)


def model_jacobian(theta: FloatArray, model: Composite, data: WvData) -> FloatArray:
    """``d nu / d theta``: analytic for the log amplitudes, central differences in log T."""
    parts = model_parts(theta, model, data)
    k = len(model.powers)
    jac = np.empty((data.tau.size, model.n_params))
    for i in range(k):
        jac[:, i] = parts[i]
    for j in range(model.n_gm):
        jac[:, k + 2 * j] = parts[k + j]
        s2, lt = math.exp(theta[k + 2 * j]), theta[k + 2 * j + 1]
        hi = ar1_wv(s2, math.exp(lt + _FD_STEP), data.tau, data.dt)
        lo = ar1_wv(s2, math.exp(lt - _FD_STEP), data.tau, data.dt)
        jac[:, k + 2 * j + 1] = (hi - lo) / (2 * _FD_STEP)
    return jac


def model_covariance_wv(data: WvData, parts: list[FloatArray], powers: list[int],
                        gm_parts: list[FloatArray]) -> FloatArray:
    """Covariance of the scaled WV estimates implied by a model (:mod:`fogts.allan.covariance`).

    ``parts`` are the scaled WVs of power laws with ``powers`` (rate ramps carry no
    variance); each Gauss-Markov WV in ``gm_parts`` is represented at each tau by the
    power laws around its local log-log slope ``s`` in [-1, 1]: the share ``|s|`` by white
    rate noise (``s < 0``) or a rate random walk (``s > 0``), the rest by flicker, an
    approximation exact where the process is white (``tau >> T``) or a walk
    (``tau << T``); :class:`fogts.allan.markov.ExtendedCovariance` uses the two-regime
    version of it.
    """
    tau = data.tau
    coef = np.zeros((tau.size, len(RANDOM_TERMS)))
    for part, p in zip(parts, powers, strict=True):
        if p in RANDOM_TERMS:
            coef[:, RANDOM_TERMS.index(p)] += part * tau ** float(-p)
    for part in gm_parts:
        slope = np.clip(_log_slope(part, tau), -1.0, 1.0)
        white, walk = np.maximum(-slope, 0.0), np.maximum(slope, 0.0)
        coef[:, RANDOM_TERMS.index(-1)] += white * part * tau
        coef[:, RANDOM_TERMS.index(1)] += walk * part / tau
        coef[:, RANDOM_TERMS.index(0)] += (1.0 - white - walk) * part
    cov = np.einsum("ijpq,ip,jq->ij", data.basis, coef, coef)
    return np.asarray(0.5 * (cov + cov.T), dtype=np.float64)


def solution_covariance(sol: GmwmSolution, data: WvData) -> FloatArray:
    """:func:`model_covariance_wv` at a fitted composite model."""
    parts = model_parts(sol.theta, sol.model, data)
    k = len(sol.model.powers)
    return model_covariance_wv(data, parts[:k], list(sol.model.powers), parts[k:])


def _log_slope(v: FloatArray, tau: FloatArray) -> FloatArray:
    if tau.size < 2:
        return np.zeros_like(tau)
    lv = np.log(np.maximum(v, np.finfo(float).tiny))
    return np.asarray(np.gradient(lv, np.log(tau)), dtype=np.float64)


def whitener(cov: FloatArray) -> FloatArray:
    """``L^{-1}`` with ``cov = L L^T`` (a tiny ridge if ``cov`` is near singular)."""
    ridge = 0.0
    for _ in range(6):
        try:
            low = np.linalg.cholesky(cov + ridge * np.diag(np.diag(cov)))
            return np.asarray(solve_triangular(low, np.eye(cov.shape[0]), lower=True),
                              dtype=np.float64)
        except np.linalg.LinAlgError:
            ridge = 1e-10 if ridge == 0.0 else ridge * 100.0
    raise np.linalg.LinAlgError("the covariance of the wavelet variances is not positive "
                                "definite")


def fit_composite(model: Composite, data: WvData, w: FloatArray,
                  starts: list[FloatArray]) -> GmwmSolution:
    """Minimise ``|w (nu_hat - nu(theta))|^2`` from each start; the best solution."""
    lo, hi = _bounds(model, data)

    def resid(theta: FloatArray) -> FloatArray:
        return np.asarray(w @ (data.nu - model_wv(theta, model, data)), dtype=np.float64)

    def jac(theta: FloatArray) -> FloatArray:
        return np.asarray(-(w @ model_jacobian(theta, model, data)), dtype=np.float64)

    best: GmwmSolution | None = None
    for x0 in starts:
        x0 = np.clip(x0, lo + 1e-9, hi - 1e-9)
        res = least_squares(resid, x0, jac=jac, bounds=(lo, hi), method="trf",
                            x_scale=1.0, ftol=_TOL, xtol=_TOL, gtol=_TOL,
                            max_nfev=_NFEV_PER_PARAM * max(model.n_params, 1))
        sol = GmwmSolution(model, np.asarray(res.x), float(2.0 * res.cost),
                           np.asarray(res.jac), int(res.nfev), bool(res.status > 0), w)
        if best is None or sol.j_stat < best.j_stat:
            best = sol
    assert best is not None
    return best


def _bounds(model: Composite, data: WvData) -> tuple[FloatArray, FloatArray]:
    lo = np.full(model.n_params, -80.0)
    hi = np.full(model.n_params, 80.0)
    k = len(model.powers)
    lo[k + 1::2] = math.log(data.dt)
    hi[k + 1::2] = math.log(float(data.tau[-1]) / T_MAX_DIVISOR)
    return lo, hi


def pilot_starts(model: Composite, data: WvData, pilot: dict[int, float]) -> list[FloatArray]:
    """Starting values: the pilot's power laws (a term the pilot put at zero starts where
    it is 1e-3 of the data at every tau) and, for ``k`` Gauss-Markov terms, one start per
    spread of correlation times around the pilot's flicker region."""
    base = [math.log(pilot[p]) if pilot.get(p, 0.0) > 0 else _small_start(p, data)
            for p in model.powers]
    if model.n_gm == 0:
        return [np.array(base)]
    level, centre = _flicker_region(data, pilot)
    out = []
    for spread in _SPREADS:
        offsets = (np.arange(model.n_gm) - (model.n_gm - 1) / 2.0) * math.log(spread)
        t_c = np.exp(math.log(centre / 1.89) + offsets)
        s2 = level / (GM_PEAK * model.n_gm ** 0.5)
        gm = np.column_stack([np.full(model.n_gm, math.log(s2)), np.log(t_c)]).ravel()
        out.append(np.concatenate([base, gm]))
    return out


def _small_start(power: int, data: WvData) -> float:
    return math.log(1e-3 * float(np.min(2.0 * data.nu / data.tau ** float(power))))


def _flicker_region(data: WvData, pilot: dict[int, float]) -> tuple[float, float]:
    """The pilot's flicker WV level and the geometric centre of the taus where it makes up
    the largest share (the data's smallest WV and its tau if the pilot has no flicker)."""
    b = pilot.get(0, 0.0) / 2.0
    if b <= 0:
        i = int(np.argmin(data.nu))
        return 0.3 * float(data.nu[i]), float(data.tau[i])
    total = sum(power_law_wv(v, p, data.tau) for p, v in pilot.items())
    share = b / total
    top = share >= 0.5 * float(np.max(share))
    return b, float(np.exp(np.mean(np.log(data.tau[top]))))


def select_model(data: WvData, w: FloatArray, structures: list[Composite],
                 pilot: dict[int, float]) -> tuple[GmwmSolution, list[GmwmSolution]]:
    """The MMSC-HQIC choice (module docstring) among the ``structures`` and their
    sub-models, and every model fitted on the way."""
    tried: list[GmwmSolution] = []
    best: GmwmSolution | None = None
    for full in structures:
        current = fit_composite(full, data, w, pilot_starts(full, data, pilot))
        for _ in range(V_STEPS):  # re-weight with V at the fit (iterated GMWM)
            w_k = whitener(solution_covariance(current, data))
            current = fit_composite(full, data, w_k, [current.theta])
        tried.append(current)
        current = _eliminate(current, data, current.w, tried)
        if best is None or current.criterion(data.n_samples) < best.criterion(data.n_samples):
            best = current
    assert best is not None
    return best, tried


def _eliminate(current: GmwmSolution, data: WvData, w: FloatArray,
               tried: list[GmwmSolution]) -> GmwmSolution:
    """Drop power laws one at a time while that lowers the criterion."""
    while len(current.model.powers) + current.model.n_gm > 1:
        options = []
        for i in range(len(current.model.powers)):
            smaller = Composite(current.model.powers[:i] + current.model.powers[i + 1:],
                                current.model.n_gm)
            start = np.delete(current.theta, i)
            options.append(fit_composite(smaller, data, w, [start]))
        tried.extend(options)
        if not options:
            break
        cand = min(options, key=lambda s: s.criterion(data.n_samples))
        if cand.criterion(data.n_samples) >= current.criterion(data.n_samples):
            break
        current = cand
    return current


def theta_covariance(sol: GmwmSolution, v: FloatArray) -> FloatArray:
    """The sandwich ``(A'WA)^-1 A'W V W A (A'WA)^-1`` with ``W = w'w`` the solution's
    weights (module docstring); ``jac_w = -w A``."""
    jw, w = sol.jac_w, sol.w
    bread = np.linalg.pinv(jw.T @ jw)
    meat_root = jw.T @ w            # -A' W  (up to sign, which cancels)
    meat = meat_root @ v @ meat_root.T
    cov = bread @ meat @ bread
    return np.asarray(0.5 * (cov + cov.T), dtype=np.float64)


def gls_solve(xw: FloatArray, rw: FloatArray) -> FloatArray:
    """Least squares of ``rw`` on the columns of ``xw`` via the normal equations."""
    c = cho_factor(xw.T @ xw)
    return np.asarray(cho_solve(c, xw.T @ rw), dtype=np.float64)
