"""Generalized Method of Wavelet Moments (GMWM) noise fit: ``fit_noise(..., method="gmwm")``.

Guerrier, Skaloud, Stebler & Victoria-Feser (2013), "Wavelet-variance-based estimation for
composite stochastic processes", *J. Am. Stat. Assoc.* 108(503), 1021-1030: fit a sum of
simple processes through the Haar wavelet variance (WV) :math:`\\hat\\nu` with the weight
matrix :math:`\\Omega = \\hat V^{-1}`, the inverse of the covariance of the WV estimates.

Where the WV and its covariance come from
    From the :class:`~fogts.allan.result.AllanResult`, not from the raw series (which the
    result does not carry): at octave taus (``m = 2^(j-1)``) the unbiased Haar-MODWT WV
    estimator is exactly half the overlapping Allan variance (Percival & Guttorp 1994;
    :mod:`fogts.allan.wv_models`), so ``allan_deviation(run, taus="octave")`` *is* the
    GMWM's moment vector; other grids and the non-overlapping ``adev`` give the same
    moments at other scales or with another estimator of them, and are accepted.  The
    covariance :math:`V` is fogts' model covariance of the Allan-variance estimates
    (:mod:`fogts.allan.covariance`, exact for Gaussian power-law noise), divided by 4.
    This needs ``m``, ``n_samples`` and ``fs_hz`` on the result and at most
    :data:`~fogts.allan.noise_lsq.MAX_COVARIANCE_POINTS` taus.  Why not the paper's
    nonparametric estimate of :math:`V` from the wavelet coefficients: it needs the raw
    series, and at the few long scales that carry K it is itself very noisy, while the
    model covariance is smooth and cheap (one basis per curve, ~0.1 s for 1e6 samples).

Two steps
    1. A pilot: the five-term EDF-weighted fit (:mod:`fogts.allan.noise_lsq`) gives
       :math:`V_0 = V(\\text{pilot})` and the starting values; :math:`\\Omega = V_0^{-1}`.
    2. The GMWM fit of each composite model -- the requested power laws with flicker
       (Haar WV flat, :math:`(2\\ln 2/\\pi)B^2/2`), or the power laws Q, N, K, R with
       ``k = 1..max_gm`` Gauss-Markov (AR(1)) terms in place of flicker, each refitted
       twice with the covariance at its own fit (iterated GMWM), then backward
       elimination of power laws -- and the choice among them by :math:`J + 2.01\\,p\\ln\\ln n`
       (MMSC-HQIC; :mod:`fogts.allan.gmwm_core`).  The standard errors are the sandwich
       :math:`(A^T\\Omega A)^{-1}A^T\\Omega V_1\\Omega A(A^T\\Omega A)^{-1}` with
       :math:`V_1` the covariance at the fit (Gauss-Markov terms represented by their local
       power law), or, with ``n_bootstrap > 0``, a parametric bootstrap of the WV:
       :math:`\\hat\\nu^* \\sim N(\\nu(\\hat\\theta), V_1)`, refitted with the same model
       and weights (the WV estimates are close to Gaussian at the scales that carry most
       information; the far scales are chi-square-like with few degrees of freedom, where
       this bootstrap is optimistic).

Bias instability as a Gauss-Markov sum
    A sum of first-order Gauss-Markov processes with spread correlation times approximates
    a 1/f (flicker) spectrum over a finite band (sum of Lorentzians; Keshner, *Proc. IEEE*
    70(3), 1982).  ``B`` is reported as its flicker equivalent: the level ``B`` whose flat
    Allan variance :math:`(2\\ln 2/\\pi)B^2` (IEEE 952; 0.664 B on the deviation,
    :mod:`fogts.allan.terms`) is the geometric mean of the Gauss-Markov sum's Allan variance
    over the data taus, each tau weighted by the sum's share of the model there (so where
    bias instability is what the curve shows).  The approximation: flicker is flat at all
    taus, the sum only over the band of its correlation times; the two agree where the sum
    dominates the curve.  The components themselves are in ``NoiseModel.gmwm``.

Which components count toward B
    Those with :math:`T_c \\ge 4\\,\\Delta t` (:data:`~fogts.allan.gmwm_result.GM_MIN_TC_SAMPLES`
    sample periods).  The Allan variance of a GM process of variance :math:`\\sigma^2` is
    :math:`(2\\sigma^2T_c/\\tau)\\,[1 - \\tfrac{T_c}{2\\tau}(3 - 4e^{-\\tau/T_c} + e^{-2\\tau/T_c})]`
    (IEEE 952-1997 Annex C; :mod:`fogts.allan.markov`): flicker-like (deviation log slope
    within +-1/4 of B's 0) only for :math:`0.77\\,T_c \\le \\tau \\le 4.1\\,T_c` (peak at
    :math:`1.89\\,T_c`), and beyond that white noise, :math:`2\\sigma^2T_c/\\tau` (within
    15 % from :math:`10\\,T_c`), which N already draws.  With :math:`T_c` below the sample
    period the component is white at every tau an Allan curve sampled at 1/fs has; with
    :math:`T_c < 4\\,\\Delta t` its flicker-like part ends before about :math:`16\\,\\Delta t`,
    within the first four octave taus, where the sensor's anti-alias and decimation filters
    shape the curve (a one-pole filter of corner :math:`f_c` makes white noise a GM of
    :math:`T_c = 1/(2\\pi f_c)`, below :math:`4\\,\\Delta t` for any corner above
    :math:`f_s/(8\\pi)`).  Such a component draws that short-tau roll-off, not bias
    instability (the ADIS16405 runs at 100 Hz: a GM at the lower bound :math:`T_c = \\Delta t`
    in 12 of 18 axes, which made B 3x the slope read-off).  It stays in the fit, in
    ``NoiseModel.gmwm`` (``in_b`` False), the fitted curve and the total the terms' shares
    are taken of (identifiability, dominance), but not in B.  If no
    component is left, this fit does not measure B: it is reported at zero (status
    ``"at_bound"``) with the upper limit of a dropped term (below), and
    :attr:`~fogts.allan.noise_term.NoiseTerm.short_gm` (in ``limit_reason`` and the
    warning) says why.

Honesty rules (as for the least-squares fits)
    A term the model choice leaves out is reported at zero with status ``"dropped"`` and an
    upper limit (its one-parameter GLS estimate at the chosen fit plus ``z`` standard
    errors); a fitted term with Wald ``z = a / se(a)`` below 2 is an upper limit
    (:attr:`~fogts.allan.noise_model.NoiseTerm.is_limit`); the J statistic, chi-squared
    on ``n_tau - p`` dof (Hansen 1982; Guerrier et al. 2013 sec. 3), gives the verdict
    on the fit, and a rejected fit warns.  Intervals are symmetric on the log scale of the
    parameters (the scale they are estimated on).
"""

from __future__ import annotations

import dataclasses
import math
import warnings
from collections.abc import Callable, Sequence
from typing import Any

import numpy as np
from scipy.stats import chi2, norm

from fogts._validate import check_fraction
from fogts.allan.covariance import covariance_basis
from fogts.allan.gmwm_core import (
    Composite,
    GmwmSolution,
    WvData,
    fit_composite,
    gls_solve,
    model_covariance_wv,
    model_parts,
    model_wv,
    select_model,
    solution_covariance,
    theta_covariance,
    whitener,
)
from fogts.allan.gmwm_result import GM_MIN_TC_SAMPLES, GaussMarkovTerm, GmwmSummary
from fogts.allan.markov import markov_avar, split_terms
from fogts.allan.noise_input import FitCurve, read_fit_curve
from fogts.allan.noise_lsq import MAX_COVARIANCE_POINTS, LsqProblem, octave_density
from fogts.allan.noise_model import NoiseModel, NoiseTerm
from fogts.allan.noise_selection import identify_terms
from fogts.allan.readoff import readoff_of
from fogts.allan.terms import NOISE_TERMS, TERM_POWER, term_rows
from fogts.allan.wv_models import power_law_wv
from fogts.errors import (
    ConvergenceWarning,
    DataError,
    FogtsWarning,
    InsufficientDataError,
    UnidentifiableTermWarning,
)
from fogts.units import base_unit_factor, quantity_of

__all__ = ["GMWM_KINDS", "MAX_GM", "counted_in_b", "fit_gmwm", "fitted_term",
           "log_b_equivalent"]

#: Allan kinds whose estimates have a model covariance (fogts.allan.covariance).
GMWM_KINDS: tuple[str, ...] = ("oadev", "adev")
#: Most Gauss-Markov terms in a composite model.
MAX_GM = 3
_GRAD_STEP = 1e-5


def fit_gmwm(allan_result: Any, *, terms: Sequence[str] | str = NOISE_TERMS,
             max_gm: int = MAX_GM, confidence: float = 0.683,
             significance: float = 0.05, n_bootstrap: int = 0,
             rng: np.random.Generator | int | None = None) -> NoiseModel:
    """Fit a composite noise model to an Allan curve by the GMWM (module docstring).

    Parameters
    ----------
    allan_result : AllanResult
        One ``oadev`` (octave taus: the Haar WV exactly) or ``adev`` curve with ``m``,
        ``n_samples`` and ``fs_hz``.
    terms : sequence of str or str
        Which of Q, N, B, K, R may enter; ``B`` stands for ``1..max_gm`` Gauss-Markov
        terms, reported as the flicker-equivalent B.
    max_gm : int
        Most Gauss-Markov terms, 0..3.
    confidence : float
        Level of the intervals, in (0, 1).
    significance : float
        Level of the J test, in (0, 0.5).
    n_bootstrap : int
        0: asymptotic standard errors; else that many parametric bootstrap replicates of
        the wavelet variances (at least 20).
    rng : Generator, int or None
        For the bootstrap.

    Returns
    -------
    NoiseModel
        ``method="gmwm"``; ``gmwm`` holds the model, the Gauss-Markov components and the
        J test.

    Raises
    ------
    DataError
        Bad ``terms``, ``max_gm``, ``confidence``, ``significance``, ``n_bootstrap``; a
        curve without ``m``, ``n_samples`` or ``fs_hz``, of another kind, or with too many
        taus.
    InsufficientDataError
        Fewer taus than parameters plus one.

    Examples
    --------
    >>> import warnings
    >>> from fogts.allan import allan_deviation
    >>> from fogts.simulate.gyro import simulate_gyro
    >>> run = simulate_gyro({"N": 0.01, "K": 1.0}, fs_hz=100, duration_s=2000, rng=1)
    >>> with warnings.catch_warnings():
    ...     warnings.simplefilter("ignore")
    ...     model = fit_gmwm(allan_deviation(run, taus="octave"), terms="N,B,K")
    >>> model.method, round(model["N"].value, 3)
    ('gmwm', 0.01)
    """
    names = _gmwm_terms(terms)
    max_gm = _check_count("max_gm", max_gm, 0, MAX_GM)
    confidence = check_fraction("confidence", confidence)
    significance = check_fraction("significance", significance)
    if significance >= 0.5:
        raise DataError(f"significance must be in (0, 0.5), got {significance!r}")
    n_boot = _check_count("n_bootstrap", n_bootstrap, 0, 100_000)
    if 0 < n_boot < 20:
        raise DataError(f"n_bootstrap must be 0 or at least 20, got {n_bootstrap!r}")
    curve = read_fit_curve(allan_result)
    structures = _structures(names, max_gm)
    data, w, pilot = _prepare(curve, max(s.n_params for s in structures))
    best, tried = select_model(data, w, structures, pilot)
    v_fit = solution_covariance(best, data)
    cov = theta_covariance(best, v_fit)
    stderr = ("GMWM asymptotic sandwich covariance with the model covariance of the "
              f"{curve.kind} estimates")
    if n_boot:
        cov = _bootstrap_cov(best, data, v_fit, n_boot, rng)
        stderr = (f"parametric bootstrap of the wavelet variances ({n_boot} replicates, "
                  "Gaussian with the model covariance at the fit)")
    return _noise_model(curve, names, data, best, cov, tried, confidence, significance,
                        stderr, n_boot)


def _gmwm_terms(terms: Sequence[str] | str) -> tuple[str, ...]:
    names, extras = split_terms(terms)
    if extras:
        raise DataError(f"terms {', '.join(extras)} are not fitted by method='gmwm'; its "
                        "Gauss-Markov terms come with B; use terms from Q, N, B, K, R")
    return names


def _structures(names: tuple[str, ...], max_gm: int) -> list[Composite]:
    """The starting models: the requested power laws (with flicker if B is requested),
    and, if B is, the power laws other than flicker with 1..max_gm Gauss-Markov terms."""
    powers = tuple(TERM_POWER[n] for n in names)
    out = [Composite(powers, 0)]
    if "B" in names:
        others = tuple(p for p in powers if p != TERM_POWER["B"])
        out += [Composite(others, k) for k in range(1, max_gm + 1)]
    return out


def _check_count(name: str, value: Any, lo: int, hi: int) -> int:
    if isinstance(value, bool) or not isinstance(value, int | np.integer) or not (
            lo <= int(value) <= hi):
        raise DataError(f"{name} must be an integer in {lo}..{hi}, got {value!r}")
    return int(value)


def _prepare(curve: FitCurve, n_params: int) -> tuple[WvData, np.ndarray, dict[int, float]]:
    """The scaled WV with its covariance basis, the pilot fit and the weights ``w``
    (``w^T w = V_0^{-1}``)."""
    if curve.kind not in GMWM_KINDS:
        raise DataError(f"method='gmwm' needs an oadev or adev curve, got kind "
                        f"{curve.kind!r} (its estimates have no model covariance here)")
    if curve.m is None or curve.n_samples is None or curve.fs_hz is None:
        raise DataError("method='gmwm' needs the curve's m, n_samples and fs_hz (an "
                        "AllanResult from allan_deviation) for the covariance of the "
                        "wavelet variances")
    if curve.tau.size > MAX_COVARIANCE_POINTS:
        raise DataError(f"method='gmwm' takes at most {MAX_COVARIANCE_POINTS} taus, got "
                        f"{curve.tau.size}; use taus='octave'")
    if curve.tau.size < n_params + 1:
        raise InsufficientDataError(
            f"allan_result has {curve.tau.size} usable taus; method='gmwm' needs at least "
            f"{n_params + 1} for {n_params} parameters; use more taus or fewer terms")
    avar = curve.dev**2
    scale = float(np.median(avar)) / 2.0
    basis = covariance_basis(curve.kind, curve.m, curve.n_samples, curve.fs_hz,
                             np.array([-2, -1, 0, 1]))
    if basis is None:
        raise DataError("the covariance of the wavelet variances is not available for "
                        "this curve (a tau with no second difference)")
    data = WvData(curve.tau, avar / 2.0 / scale, scale, 1.0 / curve.fs_hz,
                  curve.n_samples, basis)
    pilot = _pilot(curve, avar, scale)
    parts = [power_law_wv(a, p, data.tau) for p, a in pilot.items()]
    v0 = model_covariance_wv(data, parts, list(pilot), [])
    return data, whitener(v0), pilot


def _pilot(curve: FitCurve, avar: np.ndarray, scale: float) -> dict[int, float]:
    """The five-term EDF-weighted fit: power to ``a_n`` in WV-scaled units."""
    powers = np.array([TERM_POWER[n] for n in NOISE_TERMS])
    design = curve.tau[:, None] ** powers[None, :].astype(np.float64)
    s = float(np.median(avar))
    problem = LsqProblem(design=design, y=avar / s, scale=s, edf=curve.edf,
                         density=octave_density(curve.tau), covm=None, method="wls",
                         crit=0.0)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        fit = problem.solve(np.ones(powers.size, dtype=bool))
    return {int(p): float(a) * s / scale for p, a in zip(powers, fit.a, strict=True)}


def _bootstrap_cov(sol: GmwmSolution, data: WvData, v_fit: np.ndarray, n_boot: int, rng: np.random.Generator | int | None) -> np.ndarray:
    """Covariance of theta (and, as a last row/column, log a_B) over WV replicates."""
    gen = np.random.default_rng(rng)
    mu = model_wv(sol.theta, sol.model, data)
    low = np.linalg.cholesky(v_fit + 1e-12 * np.diag(np.diag(v_fit)))
    draws = []
    for _ in range(n_boot):
        nu = mu + low @ gen.standard_normal(mu.size)
        rep = WvData(data.tau, nu, data.scale, data.dt, data.n_samples, data.basis)
        draws.append(fit_composite(sol.model, rep, sol.w, [sol.theta]).theta)
    return np.atleast_2d(np.cov(np.array(draws), rowvar=False))


def log_b_equivalent(theta: np.ndarray, model: Composite, data: WvData,
                     counted: Sequence[bool] | None = None) -> float:
    """log of the flicker-equivalent ``a_0 = (2 ln 2/pi) B^2`` (scaled units) of the
    Gauss-Markov sum: the share-weighted mean log of its Allan variance (module
    docstring); ``counted``: which components enter the sum (default all; at least one)."""
    parts = model_parts(theta, model, data)
    k = len(model.powers)
    use = [True] * model.n_gm if counted is None else list(counted)
    gm = np.sum([p for p, u in zip(parts[k:], use, strict=True) if u], axis=0)
    share = gm / np.sum(parts, axis=0)
    return float(np.sum(share * np.log(2.0 * gm)) / np.sum(share))


def counted_in_b(theta: np.ndarray, model: Composite, dt: float) -> tuple[bool, ...]:
    """Per Gauss-Markov component: whether its correlation time is at least
    :data:`~fogts.allan.gmwm_result.GM_MIN_TC_SAMPLES` sample periods ``dt``, so that it
    counts toward B (module docstring)."""
    k = len(model.powers)
    return tuple(math.exp(float(theta[k + 2 * j + 1])) >= GM_MIN_TC_SAMPLES * dt * (1 - 1e-9)
                 for j in range(model.n_gm))


def _short_gm_reason(theta: np.ndarray, model: Composite, dt: float) -> str:
    """Why B is only a limit when no component counts toward it."""
    k = len(model.powers)
    t_c = [math.exp(float(theta[k + 2 * j + 1])) for j in range(model.n_gm)]
    which = ", ".join(f"{t:.3g} s = {t / dt:.3g}x the sample period" for t in t_c)
    return (f"not measured by this fit: its Gauss-Markov term{'s' if len(t_c) > 1 else ''}"
            f" (T_c = {which}) {'are' if len(t_c) > 1 else 'is'} below "
            f"{GM_MIN_TC_SAMPLES} sample periods ({GM_MIN_TC_SAMPLES * dt:.3g} s), white noise "
            "at the data taus, not bias instability; upper limit from a flicker term added "
            "to the fit")


def _uncounted_avar(best: GmwmSolution, data: WvData
                    ) -> Callable[[np.ndarray], np.ndarray] | None:
    """The Allan variance (curve units) of the Gauss-Markov components left out of B: still
    part of the fitted curve, so of the total the terms' shares are taken of."""
    k = len(best.model.powers)
    short = [(math.exp(float(best.theta[k + 2 * j])) * data.scale,
              math.exp(float(best.theta[k + 2 * j + 1])))
             for j, c in enumerate(counted_in_b(best.theta, best.model, data.dt)) if not c]
    if not short:
        return None
    return lambda t: sum((markov_avar(math.sqrt(2 * v / t_c), t_c, t) for v, t_c in short),
                         np.zeros(np.shape(t)))


def _b_gradient(theta: np.ndarray, model: Composite, data: WvData,
                counted: Sequence[bool]) -> np.ndarray:
    grad = np.zeros(theta.size)
    for i in range(theta.size):
        step = np.zeros(theta.size)
        step[i] = _GRAD_STEP
        grad[i] = (log_b_equivalent(theta + step, model, data, counted)
                   - log_b_equivalent(theta - step, model, data, counted)) / (2 * _GRAD_STEP)
    return grad


def _noise_model(curve: FitCurve, names: tuple[str, ...], data: WvData, best: GmwmSolution, cov: np.ndarray, tried: list[GmwmSolution],
                 confidence: float, significance: float, stderr: str, n_boot: int
                 ) -> NoiseModel:
    quantity = quantity_of(curve.units)
    factor = base_unit_factor(curve.units)
    z = float(norm.ppf(0.5 + confidence / 2))
    logs = _term_logs(names, best, cov, data)
    terms, a_out = [], []
    for name in names:
        if name in logs:
            log_a, se_log = logs[name]
            terms.append(fitted_term(name, log_a, se_log, data.scale, factor, z, quantity))
            a_out.append(math.exp(log_a) * data.scale)
        else:
            term = _dropped_term(name, best, data, factor, z, quantity)
            if name == "B" and best.model.n_gm:  # GM terms, none counted (module docstring)
                term = dataclasses.replace(term, status="at_bound", short_gm=_short_gm_reason(
                    best.theta, best.model, data.dt))
            terms.append(term)
            a_out.append(0.0)
    dof = float(data.tau.size - best.model.n_params)
    p_value = float(chi2.sf(best.j_stat, dof)) if dof > 0 else math.nan
    summary = GmwmSummary(
        model=best.model.label(), gauss_markov=_gm_terms(best, cov, data, factor),
        j_stat=best.j_stat, dof=dof, p_value=p_value, level=significance,
        criterion="J + 2.01 p ln ln n (MMSC-HQIC)",
        candidates=tuple((s.model.label(), s.criterion(data.n_samples)) for s in tried),
        stderr=stderr, n_bootstrap=n_boot)
    weight = 1.0 / np.diag(np.linalg.inv(best.w.T @ best.w))  # w^T w = V^{-1}
    model = NoiseModel(
        terms=tuple(terms), confidence=confidence, method="gmwm", kind=curve.kind,
        units=curve.units, axis=curve.axis, deg_per_hour_factor=factor, tau_s=curve.tau,
        dev=curve.dev, fitted_dev=np.sqrt(2.0 * data.scale * model_wv(best.theta,
                                                                       best.model, data)),
        weight=weight / np.max(weight), edf=curve.edf, edf_source=curve.edf_source,
        chi2=best.j_stat, dof=dof, model_error=math.nan, stderr_method=stderr,
        iterations=sum(s.nfev for s in tried), converged=best.converged,
        readoff=readoff_of(curve, factor, quantity),
        excluded_tau_s=tuple(curve.excluded), significance=significance,
        _a=tuple(a_out), quantity=quantity, gmwm=summary)
    return _with_warnings(model, curve, best, summary, data)


def _term_logs(names: tuple[str, ...], best: GmwmSolution, cov: np.ndarray, data: WvData
               ) -> dict[str, tuple[float, float]]:
    """Each fitted term's ``log a_n`` (scaled) and its standard error."""
    out: dict[str, tuple[float, float]] = {}
    for name in names:
        p = TERM_POWER[name]
        if p in best.model.powers:
            i = best.model.powers.index(p)
            out[name] = (float(best.theta[i]), math.sqrt(max(float(cov[i, i]), 0.0)))
        elif name == "B" and any(counted := counted_in_b(best.theta, best.model, data.dt)):
            log_b = log_b_equivalent(best.theta, best.model, data, counted)
            g = _b_gradient(best.theta, best.model, data, counted)
            out[name] = (log_b, math.sqrt(max(float(g @ cov @ g), 0.0)))
    return out


def fitted_term(name: str, log_a: float, se_log: float, scale: float, factor: float,
                 z: float, quantity: str) -> NoiseTerm:
    row = term_rows(quantity)[name]
    c = math.sqrt(math.exp(log_a) * scale) * factor
    lo, hi = c * math.exp(-z * se_log / 2), c * math.exp(z * se_log / 2)
    return NoiseTerm(name=name, value=row.factor * c, stderr=row.factor * c * se_log / 2,
                     ci_low=row.factor * lo, ci_high=row.factor * hi, unit=row.unit,
                     c_coeff=c, c_stderr=c * se_log / 2, c_unit=row.c_unit,
                     power=TERM_POWER[name], at_bound=False, identifiable=True,
                     n_covered=0, region_tau_s=(math.nan, math.nan), status="fitted",
                     z_score=1.0 / se_log if se_log > 0 else math.inf)


def _dropped_term(name: str, best: GmwmSolution, data: WvData, factor: float, z: float,
                  quantity: str) -> NoiseTerm:
    """A term the model choice left out: 0 with an upper limit from its GLS estimate
    added to the chosen fit (module docstring)."""
    x = best.w @ power_law_wv(1.0, TERM_POWER[name], data.tau)
    r = best.w @ (data.nu - model_wv(best.theta, best.model, data))
    cols = np.column_stack([-best.jac_w, x])
    est = gls_solve(cols, r)
    se = math.sqrt(max(float(np.linalg.pinv(cols.T @ cols)[-1, -1]), 0.0))
    a_hi = max(float(est[-1]), 0.0) + z * se
    row = term_rows(quantity)[name]
    return NoiseTerm(name=name, value=0.0, stderr=math.nan, ci_low=0.0,
                     ci_high=row.factor * math.sqrt(a_hi * data.scale) * factor,
                     unit=row.unit, c_coeff=0.0, c_stderr=math.nan, c_unit=row.c_unit,
                     power=TERM_POWER[name], at_bound=True, identifiable=True, n_covered=0,
                     region_tau_s=(math.nan, math.nan), status="dropped",
                     z_score=max(float(est[-1]) / se, 0.0) if se > 0 else 0.0)


def _gm_terms(best: GmwmSolution, cov: np.ndarray, data: WvData, factor: float
              ) -> tuple[GaussMarkovTerm, ...]:
    k = len(best.model.powers)
    in_b = counted_in_b(best.theta, best.model, data.dt)
    out = []
    for j in range(best.model.n_gm):
        i = k + 2 * j
        sigma = math.sqrt(math.exp(best.theta[i]) * data.scale) * factor
        t_c = math.exp(best.theta[i + 1])
        se_s = math.sqrt(max(float(cov[i, i]), 0.0)) / 2
        se_t = math.sqrt(max(float(cov[i + 1, i + 1]), 0.0))
        out.append(GaussMarkovTerm(sigma, sigma * se_s, t_c, t_c * se_t, in_b[j]))
    return tuple(out)


def _with_warnings(model: NoiseModel, curve: FitCurve, best: GmwmSolution,
                   summary: GmwmSummary, data: WvData) -> NoiseModel:
    issued: list[str] = []
    identified, messages = identify_terms(model, curve.tau, _uncounted_avar(best, data))
    for message in messages:
        _warn(issued, UnidentifiableTermWarning, message, curve.axis)
    if not best.converged:
        _warn(issued, ConvergenceWarning, "the GMWM optimiser did not converge", curve.axis)
    if not summary.consistent:
        _warn(issued, FogtsWarning, summary.verdict, curve.axis)
    return dataclasses.replace(model, terms=identified, warnings=tuple(issued))


def _warn(issued: list[str], category: type[Warning], message: str, axis: str) -> None:
    message = f"axis {axis!r}: {message}" if axis else message
    issued.append(message)
    warnings.warn(message, category, stacklevel=4)
