"""Intervals of the terms below bias instability that allow for its unknown band limit.

The IEEE-952 bias-instability term B is flat flicker rate noise, :math:`S(f) \\propto 1/f`
at every frequency, so its Allan variance :math:`(2\\ln 2/\\pi)B^2` is flat at every tau.
Real bias instability is band-limited: it is a superposition of exponentially correlated
(first-order Markov) fluctuations whose correlation times span a finite range
:math:`T_{min} .. T_{max}` (van der Ziel, *Physica* 16(4), 1950; Keshner, *Proc. IEEE*
70(3), 1982), and its Allan curve rolls off below :math:`T_{min}` and above
:math:`T_{max}` (IEEE Std 952-1997 Annex C, "exponentially correlated noise"; El-Sheimy,
Hou & Niu, *IEEE Trans. Instrum. Meas.* 57(1), 2008).  Below B's region, where white noise
N dominates, B makes up a small share of :math:`\\sigma^2` and the data hardly tell a flat
B line from a rolled-off one, yet N is read from exactly there: a flat line extrapolated
to 0.01 s where the true flicker stopped near 1 s moves N by a fraction of a per mille,
which is a standard error of N (its EDF at short tau is huge).  The intervals of the terms
measured below B's region (Q, N) therefore also cover the fit with a band-limited B.

Band-limited flicker
    With equal power per logarithmic interval of correlation time (the 1/f construction
    above), the Markov Allan variances (:func:`fogts.allan.markov.markov_avar`) integrate in
    closed form; the share of the flat flicker level kept at tau when the correlation times
    below :math:`T` are absent is

    .. math::

        h(u) = 1 + \\Phi(u) / (2\\ln 2), \\quad u = \\tau/T, \\quad
        \\Phi(u) = -\\frac{2}{u} + \\frac{3}{2u^2} - \\frac{2e^{-u}}{u^2}
                  + \\frac{2e^{-u}}{u} + \\frac{e^{-2u}}{2u^2} - \\frac{e^{-2u}}{u}
                  - 2E_1(u) + 2E_1(2u)

    (:func:`flicker_share`; :math:`h \\to 1` for :math:`\\tau \\gg T`, :math:`h \\approx
    u/(3\\ln 2)` for :math:`\\tau \\ll T`), and without the times above :math:`T` it is
    :math:`1 - h(\\tau/T)`.  The B column of the fit becomes :math:`h(\\tau/T_{min})`
    (or :math:`1 - h(\\tau/T_{max})`).

The best band-limited fit (:func:`band_profile`)
    For each lower limit :math:`T` on a half-octave grid from 1/8 of the shortest tau to 8
    times the longest (and no limit), the active terms are refitted by generalised least
    squares with the limited B column and the fit's covariance of the estimates :math:`V`
    (model covariance plus model error, :mod:`fogts.allan.noise_lsq`) held fixed:
    :math:`\\hat a(T)` minimises, and :math:`D(T)` is the minimum of,
    :math:`(y - A_Ta)^T V^{-1} (y - A_Ta)` (the Gaussian deviance of the variance
    estimates the covariance describes).  :math:`\\hat T` minimises :math:`D` (no limit
    when the flat line fits best), and :math:`\\delta_j = \\hat a_j(\\hat T) -
    \\hat a_j(\\text{no limit})` is the shift it implies.

Interval
    Two models describe the curve, flat and band-limited flicker, and the data do not
    choose between them reliably (:math:`T` is not identified when the flicker is flat, so
    the deviance gain of the best limit has no usable reference distribution; Davies,
    *Biometrika* 74(1), 1987).  The intervals therefore account for both (model
    uncertainty; Draper, *J. R. Stat. Soc. B* 57(1), 1995), with :math:`se` the five-term
    fit's standard error; the term's ``value`` and ``stderr`` stay those of the five-term
    fit, only ``ci_low`` and ``ci_high`` move.

    * Q and N, measured below the flicker's region, get the *union* of the two models'
      intervals, :math:`[\\hat a_j + \\min(\\delta_j, 0) - z\\,se,\\; \\hat a_j +
      \\max(\\delta_j, 0) + z\\,se]`, clipped at 0 (N's upper end: a rolled-off flicker
      leaves more of the short-tau variance to N).
    * B and K, which the limit moves only through their trade-off with N, get the central
      interval of the two models' equal-weight mixture
      :math:`\\tfrac12 N(\\hat a_j, se^2) + \\tfrac12 N(\\hat a_j + \\delta_j, se^2)`
      (a model-averaged interval with equal model weights: Hoeting, Madigan, Raftery &
      Volinsky, *Stat. Sci.* 14(4), 1999, eq. 1; Burnham & Anderson, *Model Selection and
      Multimodel Inference*, 2nd ed., 2002, sec. 4.3), clipped at 0
      (:func:`mixture_interval`).  Equal weights, because the likelihood ratio of the
      best limit is not calibrated (above).

    Why two rules (tests/README.md, "Interval coverage when bias instability is a
    Gauss–Markov sum"): on the exact Allan curve of a Gauss–Markov-sum bias instability
    the flat fit has N 1.19 standard errors low and the best band limit moves it up by
    only 0.95, so the truth lies beyond the band-limited fit and only the union reaches
    it; for B the flat fit is 0.70 standard errors low and the band-limited fit 0.46
    high, for K 0.42 high and 0.03 low, so the truth lies between the two fits, which the
    mixture covers and the union over-covers (B 80-83 %).  Measured alternatives: the full
    profile-likelihood interval over :math:`T` (the union of :math:`\\hat a_j(T) \\pm
    se\\sqrt{z^2 - \\Delta D(T)}`) over-covers on flat flicker: N 83-93 % at 5 Hz; the same
    union for K over the upper limit :math:`T_{max}` covers K in 80-82 % of the tactical
    records; the mixture for N covers it in 59 % of the MEMS records; a mixture weighted
    by Akaike weights :math:`\\propto e^{-D/2 - 1}` leaves MEMS B at 55 % (the band-limited
    fit gets nearly all the weight and over-shoots).
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass

import numpy as np
from scipy.linalg import solve_triangular
from scipy.optimize import brentq
from scipy.special import exp1

from fogts._typing import FloatArray
from fogts.allan.distributions import norm_cdf, norm_ppf
from fogts.allan.noise_lsq import LsqProblem
from fogts.allan.noise_model import NoiseTerm
from fogts.allan.noise_selection import TermSelection
from fogts.allan.terms import TERM_POWER, term_rows

__all__ = ["BandProfile", "band_profile", "flicker_share", "mixture_interval",
           "widen_for_band_limits"]

#: Spacing of the grid of band limits, in octaves.
BAND_STEP_OCTAVES = 0.5
#: The grid reaches this many octaves beyond the data taus on each side.
BAND_REACH_OCTAVES = 3.0
_LN4 = 2.0 * math.log(2.0)
_SERIES_BELOW = 1e-2  # below this u the closed form cancels; its series is exact to 1e-10


def flicker_share(u: FloatArray) -> FloatArray:
    """Share ``h(u)`` of the flat flicker Allan variance at ``tau = u T`` when the flicker's
    correlation times below ``T`` are absent (module docstring).

    Examples
    --------
    >>> import numpy as np
    >>> flicker_share(np.array([0.001, 1.0, 100.0])).round(4).tolist()
    [0.0005, 0.3446, 0.9857]
    """
    u = np.asarray(u, dtype=np.float64)
    out = np.empty_like(u)
    small = u < _SERIES_BELOW
    s = u[small]
    # integral of the Taylor series 2/3 - u/2 + 7u^2/30 - u^3/12 of the integrand
    out[small] = s * (2.0 / 3.0 - s * (1.0 / 4.0 - s * (7.0 / 90.0 - s / 48.0))) / _LN4
    v = u[~small]
    e1, e2 = np.exp(-v), np.exp(-2.0 * v)
    phi = (-2.0 / v + 1.5 / v**2 - 2.0 * e1 / v**2 + 2.0 * e1 / v + 0.5 * e2 / v**2
           - e2 / v - 2.0 * exp1(v) + 2.0 * exp1(2.0 * v))
    out[~small] = 1.0 + phi / _LN4
    return np.asarray(np.clip(out, 0.0, 1.0), dtype=np.float64)


@dataclass(frozen=True)
class BandProfile:
    """The fit refitted with the flicker's correlation times limited to ``>= limit_s`` (module
    docstring).

    Attributes
    ----------
    limit_s : ndarray
        The lower limits ``T`` (s); the first, 0, is "no limit".
    delta_d : ndarray
        Profile deviance over its minimum, ``D(T) - min D``.
    shift : ndarray, shape (n_limits, n_terms)
        Change of each (scaled) coefficient from the fit without a limit; 0 for inactive
        terms.
    """

    limit_s: FloatArray
    delta_d: FloatArray
    shift: FloatArray


def band_profile(problem: LsqProblem, selection: TermSelection, tau: FloatArray,
                 column: int) -> BandProfile | None:
    """Profile the fit over the lower band limit of the flicker column ``column`` (module
    docstring); None if the flicker term is not active, for ``ols``, or when ``V`` is not
    positive definite."""
    fit, a = selection.fit, selection.a
    active = np.flatnonzero(a > 0)
    if a[column] <= 0 or problem.method == "ols":
        return None
    k = int(np.searchsorted(active, column))
    design = problem.design[:, active]
    eps2 = fit.model_error**2 if math.isfinite(fit.model_error) else 0.0
    if problem.covm is not None:
        v = problem.covm(a, fit.mu, problem.edf) + np.diag((eps2 + 1e-10) * fit.mu**2)
    else:
        v = np.diag(fit.mu**2 * (2.0 / problem.edf + eps2) / problem.density)
    try:
        chol = np.linalg.cholesky(v)
    except np.linalg.LinAlgError:  # a covariance the fit could not use either
        return None
    y_white = solve_triangular(chol, problem.y, lower=True)
    step = BAND_STEP_OCTAVES
    grid = tau[0] * 2.0 ** np.arange(-BAND_REACH_OCTAVES,
                                     math.log2(tau[-1] / tau[0]) + BAND_REACH_OCTAVES + 1e-9,
                                     step)
    limits = np.concatenate([[0.0], grid])
    with np.errstate(divide="ignore"):  # "no limit": u = inf, share 1
        u = tau[None, :] / limits[:, None]
    keep = flicker_share(u)
    x = np.repeat(design[None, :, :], limits.size, axis=0)
    x[:, :, k] *= keep
    x_white = solve_triangular(chol, np.concatenate(list(x), axis=1), lower=True)
    x_white = x_white.reshape(tau.size, limits.size, active.size).transpose(1, 0, 2)
    a_gls = _batched_lstsq(x_white, y_white)
    r = y_white[None, :] - np.einsum("lnk,lk->ln", x_white, a_gls)
    dev = np.einsum("ln,ln->l", r, r)
    shift = np.zeros((limits.size, a.size))
    shift[:, active] = a_gls - a_gls[0]
    return BandProfile(limit_s=limits, delta_d=dev - float(np.min(dev)), shift=shift)


def _batched_lstsq(x: FloatArray, y: FloatArray) -> FloatArray:
    """Least squares ``x[l] @ a[l] ~ y`` for every ``l`` (columns scaled; SVD)."""
    col = np.linalg.norm(x, axis=1, keepdims=True)
    col[col == 0] = 1.0
    sol = np.einsum("lkn,n->lk", np.linalg.pinv(x / col, rcond=1e-13), y)
    return np.asarray(sol / col[:, 0, :], dtype=np.float64)


def _union_interval(a_j: float, se: float, z: float, profile: BandProfile, j: int
                    ) -> tuple[float, float]:
    """``a_j +- z se`` joined with the same interval about the best band-limited fit's
    ``a_j + shift`` (module docstring); clipped at 0."""
    shift = float(profile.shift[int(np.argmin(profile.delta_d)), j])
    return max(a_j + min(shift, 0.0) - z * se, 0.0), a_j + max(shift, 0.0) + z * se


def mixture_interval(a_j: float, se: float, shift: float, confidence: float
                     ) -> tuple[float, float]:
    """Central ``confidence`` interval of ``N(a_j, se^2) / 2 + N(a_j + shift, se^2) / 2``,
    clipped at 0 (module docstring).

    Examples
    --------
    >>> [round(v, 3) for v in mixture_interval(1.0, 0.1, 0.0, 0.683)]
    [0.9, 1.1]
    >>> [round(v, 3) for v in mixture_interval(1.0, 0.1, 0.1, 0.683)]
    [0.937, 1.163]
    """
    if not se > 0:
        return max(a_j + min(shift, 0.0), 0.0), max(a_j + max(shift, 0.0), 0.0)

    def tail_gap(x: float, p: float) -> float:
        return float(0.5 * (norm_cdf((x - a_j) / se) + norm_cdf((x - a_j - shift) / se))) - p

    lo_b, hi_b = a_j + min(shift, 0.0) - 10.0 * se, a_j + max(shift, 0.0) + 10.0 * se
    lo = brentq(tail_gap, lo_b, hi_b, args=(0.5 - confidence / 2,), xtol=1e-12 * se)
    hi = brentq(tail_gap, lo_b, hi_b, args=(0.5 + confidence / 2,), xtol=1e-12 * se)
    return max(float(lo), 0.0), max(float(hi), 0.0)


def widen_for_band_limits(terms: tuple[NoiseTerm, ...], names: tuple[str, ...],
                          problem: LsqProblem, selection: TermSelection, tau: FloatArray,
                          confidence: float, scale: float, quantity: str = "rate"
                          ) -> tuple[NoiseTerm, ...]:
    """``terms`` with the intervals of the active Q and N (union) and B and K (equal-weight
    mixture) allowing for the flicker's unknown lower band limit (module docstring).

    ``scale`` turns the square root of a scaled coefficient into ``C_n`` (as in
    :func:`fogts.allan.noise_selection.term_estimates`).  Without an active B, or for
    ``ols``, ``terms`` is returned unchanged; R is never changed.
    """
    if "B" not in names:
        return terms
    column = names.index("B")
    a = selection.a
    active = np.flatnonzero(a > 0)
    profile = band_profile(problem, selection, tau, column)
    if profile is None:
        return terms
    var = np.diag(selection.fit.cov(active))
    z = float(norm_ppf(0.5 + confidence / 2))
    rows = term_rows(quantity)
    out = list(terms)
    for j, name in enumerate(names):
        if a[j] <= 0 or TERM_POWER[name] > 1:
            continue
        se = math.sqrt(max(float(var[int(np.searchsorted(active, j))]), 0.0))
        factor = rows[name].factor * scale
        if TERM_POWER[name] < 0:
            lo, hi = _union_interval(float(a[j]), se, z, profile, j)
            out[j] = dataclasses.replace(
                terms[j], ci_low=min(terms[j].ci_low, factor * math.sqrt(lo)),
                ci_high=max(terms[j].ci_high, factor * math.sqrt(hi)))
        else:
            shift = float(profile.shift[int(np.argmin(profile.delta_d)), j])
            lo, hi = mixture_interval(float(a[j]), se, shift, confidence)
            out[j] = dataclasses.replace(terms[j], ci_low=factor * math.sqrt(lo),
                                         ci_high=factor * math.sqrt(hi))
    return tuple(out)
