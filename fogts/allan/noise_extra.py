"""Fit the optional Markov (M) and sinusoid (S) terms (:mod:`fogts.allan.markov`) beside the
IEEE-952 terms, and test whether adding each is significant.

For a fixed parameter (``T_c`` or ``f_0``) the term is one more non-negative column of the
noise fit's least-squares problem (:mod:`fogts.allan.noise_lsq`: the same weights, model
error and covariance).  The parameter is profiled: every fit is scored by

.. math::

    D = r^T V^{-1} r + \\log\\det V,

:math:`-2\\log L` of the Gaussian likelihood of the (scaled) Allan variances with the
model covariance of the estimates plus the fit's model error (:math:`V`, the covariance
:mod:`fogts.allan.noise_lsq` uses for the standard errors; the EDF diagonal without it),
over a log-spaced grid of the parameter, refined by bounded 1-D minimisation
(``scipy.optimize.minimize_scalar``) between the best grid point's neighbours.

Standard errors
    The parameter's from the profile's curvature, :math:`se(\\ln\\theta) =
    \\sqrt{2/D''}` (second difference of :math:`D` at :math:`\\ln\\hat\\theta \\pm 0.1`);
    NaN at the edge of the search range or on a flat profile.  The amplitude's and the
    process sigma's combine the covariance of the fit at :math:`\\hat\\theta` with the
    parameter's uncertainty along the profile (delta method, :math:`(df/d\\ln\\theta)^2
    se(\\ln\\theta)^2` added).

    For the sinusoid the covariance gives the deterministic term no variance of its own
    (as for the rate ramp), so the standard error of ``f_0`` is too small: on a simulated
    0.02 Hz sinusoid the estimate was 4.4 stated standard errors (3.7 %) off.

Significance
    ``chi2_drop`` :math:`= D_{without} - D_{with}`, referred to :math:`\\chi^2_2` (amplitude
    and parameter).  The parameter is undefined without the term and the amplitude lies on
    its bound, so the reference distribution is approximate (Davies, *Biometrika* 74(1),
    1987): read p-values near the level with care.
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass

import numpy as np
from scipy.optimize import minimize_scalar

from fogts._typing import FloatArray
from fogts.allan.distributions import chi2_sf
from fogts.allan.markov import (
    EXTRA_FAMILIES,
    EXTRA_POWER,
    ExtendedCovariance,
    ExtraFamily,
    ExtraTerm,
)
from fogts.allan.noise_input import FitCurve
from fogts.allan.noise_lsq import LsqFit, LsqProblem, curve_covariance_basis
from fogts.allan.noise_selection import TermSelection, backward_elimination
from fogts.allan.terms import TERM_POWER

__all__ = ["ExtraFit", "fit_extra_terms"]

_CURVATURE_STEP = 0.1  # in ln(parameter)
_DF = 2


@dataclass(frozen=True)
class ExtraFit:
    """The fit with the optional terms: its problem and selection (columns: the five-term
    names, then the optional terms) and each optional term's result."""

    problem: LsqProblem
    selection: TermSelection
    terms: tuple[ExtraTerm, ...]


@dataclass(frozen=True)
class _Builder:
    """Makes the least-squares problem for given optional-term parameters."""

    curve: FitCurve
    base: LsqProblem
    basis: FloatArray | None  # covariance basis with N and K present, or None

    def problem(self, extras: list[tuple[ExtraFamily, float]]) -> LsqProblem:
        cols = [fam.basis(self.curve.tau, theta) for fam, theta in extras]
        design = np.column_stack([self.base.design, *cols]) if cols else self.base.design
        covm = None
        if self.base.covm is not None and self.basis is not None:
            n0 = self.base.design.shape[1]
            markov = next(((n0 + k, theta) for k, (fam, theta) in enumerate(extras)
                           if fam.name == "M"), None)
            powers = np.concatenate([self.base.covm.powers,
                                     np.full(len(extras), EXTRA_POWER, dtype=np.int64)])
            covm = ExtendedCovariance(self.basis, powers, self.base.covm.kind,
                                      tau=self.curve.tau, markov=markov)
        return dataclasses.replace(self.base, design=design, covm=covm)


def deviance(problem: LsqProblem, fit: LsqFit) -> float:
    """``-2 log L`` of the scaled Allan variances (module docstring)."""
    mu = fit.mu
    eps2 = fit.model_error**2 if math.isfinite(fit.model_error) else 0.0
    if problem.covm is None:  # the EDF diagonal (any number of taus): no matrix
        var = mu**2 * (2.0 / problem.edf + eps2) / problem.density
        r = problem.y - mu
        return float(np.sum(r * r / var) + np.sum(np.log(var)))
    v = problem.covm(fit.a, mu, problem.edf) + np.diag((eps2 + 1e-10) * mu**2)
    chol = np.linalg.cholesky(v)
    z = np.linalg.solve(chol, problem.y - mu)
    return float(z @ z + 2.0 * np.sum(np.log(np.diag(chol))))


def fit_extra_terms(curve: FitCurve, base: LsqProblem, base_selection: TermSelection,
                    extras: tuple[str, ...], z_crit: float | None, level: float,
                    deg_factor: float) -> ExtraFit:
    """Add the optional terms ``extras`` (in order M, S) one after the other, each profiled
    and tested against the model without it (module docstring).

    ``level`` is the test's level; ``deg_factor`` turns the curve's rate unit into deg/h.
    """
    basis = None
    if base.covm is not None:
        powers = np.union1d(base.covm.powers, [TERM_POWER["N"], TERM_POWER["K"]])
        basis = curve_covariance_basis(curve, powers.astype(np.int64))
        # the basis is indexed by RANDOM_TERMS, so a wider one serves the base powers too
    build = _Builder(curve, base, basis)
    done: list[tuple[ExtraFamily, float]] = []
    results: list[ExtraTerm] = []
    problem, selection = base, base_selection
    d_without = deviance(problem, selection.fit)
    for name in extras:
        fam = EXTRA_FAMILIES[name]
        theta, se_ln, profile = _profile(build, done, fam)
        problem = build.problem([*done, (fam, theta)])
        selection = backward_elimination(problem, z_crit)
        d_with = deviance(problem, selection.fit)
        results.append(_extra_term(fam, theta, se_ln, profile, problem, selection,
                                   max(d_without - d_with, 0.0), level, deg_factor))
        done.append((fam, theta))
        d_without = d_with
    return ExtraFit(problem, selection, tuple(results))


@dataclass(frozen=True)
class _Profile:
    """The profile around its minimum: ln(theta) and the squared amplitude (scaled units)
    at ln(theta) - step, at the minimum and at + step; the search range; at the edge?"""

    ln_theta: FloatArray
    amplitude2: FloatArray
    search: tuple[float, float]
    at_edge: bool


def _profile(build: _Builder, done: list[tuple[ExtraFamily, float]], fam: ExtraFamily
             ) -> tuple[float, float, _Profile]:
    """The best parameter, the standard error of its log and the profile around it."""
    lo, hi = fam.bounds(build.curve.tau)
    col = build.base.design.shape[1] + len(done)

    def fit_at(ln_theta: float) -> tuple[float, float]:
        problem = build.problem([*done, (fam, math.exp(ln_theta))])
        fit = problem.solve(np.ones(problem.design.shape[1], dtype=bool))
        return deviance(problem, fit), float(fit.a[col])

    grid = np.linspace(math.log(lo), math.log(hi), fam.grid)
    scores = np.array([fit_at(float(g))[0] for g in grid])
    k = int(np.argmin(scores))
    left, right = grid[max(k - 1, 0)], grid[min(k + 1, grid.size - 1)]
    best = minimize_scalar(lambda g: fit_at(float(g))[0], bounds=(left, right),
                           method="bounded", options={"xatol": 1e-4})
    ln_hat = float(best.x) if float(best.fun) < scores[k] else float(grid[k])
    step = _CURVATURE_STEP
    at_edge = ln_hat - step < grid[0] or ln_hat + step > grid[-1]
    points = [ln_hat - step, ln_hat, ln_hat + step]
    d, amp = zip(*(fit_at(p) for p in points), strict=True)
    curvature = (d[0] + d[2] - 2.0 * d[1]) / step**2
    se_ln = math.sqrt(2.0 / curvature) if curvature > 0 and not at_edge else math.nan
    return math.exp(ln_hat), se_ln, _Profile(np.array(points), np.array(amp), (lo, hi),
                                             at_edge)


# Long only by the many fields of the result it fills in.
def _extra_term(fam: ExtraFamily, theta: float, se_ln: float, profile: _Profile,
                problem: LsqProblem, selection: TermSelection, drop: float, level: float,
                deg_factor: float) -> ExtraTerm:
    """The result of one optional term (column ``-1`` of ``problem``)."""
    col = problem.design.shape[1] - 1
    a = float(selection.a[col])
    status = "fitted" if a > 0 else ("dropped" if col in selection.dropped_z else "at_bound")
    to_amp = math.sqrt(problem.scale) * deg_factor  # sqrt(scaled a) -> deg/h units
    amp = math.sqrt(a) * to_amp
    amp_se = sigma_se = math.nan
    if a > 0:
        idx = np.flatnonzero(selection.a > 0)
        var_a = float(fit_cov_diag(selection.fit, idx)[int(np.searchsorted(idx, col))])
        # the amplitude and sigma along the profile: f(a(theta), theta)
        amps = np.sqrt(np.maximum(profile.amplitude2, 0.0)) * to_amp
        sigmas = np.array([fam.sigma(float(v), math.exp(float(g)))
                           for v, g in zip(amps, profile.ln_theta, strict=True)])
        step = 2.0 * _CURVATURE_STEP
        var_ln = se_ln**2
        d_amp = (amps[2] - amps[0]) / step
        d_sigma = (sigmas[2] - sigmas[0]) / step
        amp_cond = math.sqrt(max(var_a, 0.0)) / (2.0 * math.sqrt(a)) * to_amp
        sigma_ratio = fam.sigma(amp, theta) / amp
        amp_se = math.sqrt(amp_cond**2 + d_amp**2 * var_ln)
        sigma_se = math.sqrt((sigma_ratio * amp_cond) ** 2 + d_sigma**2 * var_ln)
    return ExtraTerm(
        name=fam.name, description=fam.description, amplitude=amp, amplitude_stderr=amp_se,
        amplitude_unit=fam.amplitude_unit, parameter=theta,
        parameter_stderr=theta * se_ln, parameter_unit=fam.parameter_unit,
        sigma=fam.sigma(amp, theta), sigma_stderr=sigma_se, chi2_drop=drop, df=_DF,
        p_value=float(chi2_sf(drop, _DF)), level=level, status=status,
        at_edge=profile.at_edge, search_range=profile.search,
        avar_coeff=a * problem.scale)


def fit_cov_diag(fit: LsqFit, idx: np.ndarray) -> FloatArray:
    """The variances of the active coefficients ``idx`` of ``fit``."""
    return np.asarray(np.diag(fit.cov(idx)), dtype=np.float64)
