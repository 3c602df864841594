"""Which IEEE-952 terms the data support: term selection, intervals, upper limits, identifiability.

Term selection (``significance`` :math:`\\alpha`)
    A term absent from the data is still estimated, and the non-negative fit keeps it
    whenever the noise pushes it up; Q and N are nearly collinear over the first taus (as
    are K and R over the last), so a spurious term takes part of its neighbour's share.
    :func:`backward_elimination`: among the terms that are neither significant (Wald
    statistic :math:`z_j = a_j / se(a_j) < z_{1-\\alpha}`, standard error from the fit's
    covariance, which accounts for the correlation between taus) nor visible in the curve
    (fewer than :data:`MIN_COVERED_POINTS` taus where the term makes up
    :data:`COVERAGE_SHARE` of the fitted :math:`\\sigma^2`), drop the one with the smallest
    :math:`z_j`, refit (model error included) and repeat; terms the NNLS put at zero stay
    there.  A term that shapes the curve over several taus is kept even when its z is
    small: dropping a real but weakly determined B or K would hand its share to its
    neighbours.  A term that reaches :data:`COVERAGE_SHARE` at *no* data tau is dropped
    whatever its z: it is then measured only through the curvature of the curve at the
    edge of the tau range, which a small departure of its neighbours from their ideal
    shapes produces as well (a bias instability made of Gauss–Markov processes rolls off
    below its shortest correlation time, and an unsupported Q fitted to that roll-off takes
    its share from N).  For :math:`a_j` on the boundary :math:`a_j = 0`, :math:`\\max(z_j, 0)^2`
    has the 50:50 :math:`\\chi^2_0 / \\chi^2_1` null distribution of the likelihood-ratio
    statistic (Self & Liang, *J. Am. Stat. Assoc.* 82(398), 1987; Chernoff, *Ann. Math.
    Stat.* 25, 1954), so the one-sided :math:`z > z_{1-\\alpha}` is its level-:math:`\\alpha`
    test; the Wald form is used because the Gamma likelihood treats correlated taus as
    independent and its ratio would be miscalibrated.

Intervals (:func:`term_estimates`)
    :math:`a_n \\pm z\\,se(a_n)` clipped at 0, and for :math:`C_n` the square roots of its
    ends (asymmetric); :math:`se(C_n) = se(a_n)/(2C_n)` (delta method).  A term at zero
    (fitted there, ``at_bound``, or dropped) has no standard error (NaN) and the upper limit
    :math:`[0, \\sqrt{z\\,se}]`, ``se`` from the active set plus that term.
    :func:`fogts.allan.noise_band.widen_for_band_limits` then widens the intervals of the
    fitted Q and N for the flicker's unknown lower band limit.

Identifiability (:func:`identify_terms`)
    A term's *region* is where it makes up at least :data:`COVERAGE_SHARE` of the fitted
    :math:`\\sigma^2`.  The term is *identifiable* when the data have at least
    :data:`MIN_COVERED_POINTS` taus in its region, or one tau and an interval that excludes
    zero; otherwise its value is at best an upper limit.

Terms seen only at low-EDF points (:func:`identify_terms`)
    A fitted term that *dominates* the fitted :math:`\\sigma^2` (its line the largest, as
    in the curve read-out's "dominates" ranges, :func:`fogts.allan.readout.read_curve`)
    only at taus whose points have fewer than
    :data:`~fogts.allan.readout.MIN_EDF_FOR_MINIMUM` equivalent degrees of freedom is an
    upper limit whatever its z (:attr:`~fogts.allan.noise_model.NoiseTerm.low_edf_taus`).
    The threshold is the read-outs' own (the minimum, and the N and K slope read-offs, of
    :mod:`fogts.allan.readout` and :mod:`fogts.allan.readoff` do not rest on such points),
    so the fit does not call measured what the curve read-out beside it declines to read.
    The reason is the same too: a point with :math:`\\nu < 10` EDF is an average over
    fewer than about ten independent spans of that tau, its variance is distributed as
    :math:`\\sigma^2\\chi^2_\\nu/\\nu` (NIST SP1065 sec. 5.3), strongly skewed, with a 68 %
    interval wider than about +-25 % on the deviation; the Wald z and its sandwich standard
    error are first-order, normal approximations, least reliable exactly when all of a
    term's evidence comes from such points (and a term seen only at the last one or two
    octaves of a record is confounded with any slow departure the five terms do not model).
    The z rule still decides for every other term.  The audit's case: a 655 s MPU6050
    record "measured" R = 265 +- 35 deg/h^2 (z = 3.8) from its 82 s and 165 s points, EDF
    7.5 and 3.0, while the read-out beside it found a floor from 41 s with no rise.

B on a curve without a floor (:func:`floorless_flicker`)
    B is the flat bottom of the curve (IEEE Std 952-1997, Annex C: the flicker floor, read
    at the minimum).  When the curve read-out finds no floor, the curve still falling at its
    last trusted tau (:func:`fogts.allan.readout.read_curve`), and B dominates the fitted
    :math:`\\sigma^2` at fewer than two trusted points (EDF at least
    :data:`~fogts.allan.readout.MIN_EDF_FOR_MINIMUM`), the fitted B rests on the bend of
    one point where the data end: the data have not reached the bottom, and only
    ``sigma >= 0.664 B`` at every tau is known, an upper limit.  B is then marked so
    whatever its z (:attr:`~fogts.allan.noise_model.NoiseTerm.no_floor`), as the read-off
    beside it declines to read B there.  Either sign alone leaves B measured: a B that
    dominates at several trusted points is measured by the curve's bend even where the
    read-out's minimum is where the trusted points end (ADIS16405 run 3, X and Y axes:
    B = 36 and 41 deg/h, as the other runs' 27-45, dominant at five trusted points, the
    curve ending lower at EDF below 10), and a B seen at one trusted point on a curve that
    levels out is the floor itself.  The audit's case: the first 5 s of ADIS16405 run 1
    "measured" B = 424 +- 88 deg/h (z = 2.4; dominant at 0.32 s, EDF 21, and at 0.64 and
    1.28 s, EDF 9.6 and 3.9, the curve falling through them), where the whole 2.8 h record
    gives 33.7 +- 2.8 deg/h.
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from fogts._typing import FloatArray
from fogts.allan.distributions import norm_ppf
from fogts.allan.noise_lsq import LsqFit, LsqProblem
from fogts.allan.noise_model import NoiseModel, NoiseTerm
from fogts.allan.readout import MIN_EDF_FOR_MINIMUM
from fogts.allan.terms import TERM_POWER, term_rows

__all__ = ["COVERAGE_SHARE", "MIN_COVERED_POINTS", "TermSelection", "backward_elimination",
           "floorless_flicker", "identify_terms", "term_estimates"]

#: A term's region: where it makes up at least this share of the fitted sigma^2.
COVERAGE_SHARE = 0.25
#: A term must have this many data taus in its region to count as identified.
MIN_COVERED_POINTS = 2


@dataclass(frozen=True)
class TermSelection:
    """The final fit after term selection.

    What :func:`backward_elimination` returns; :func:`term_estimates` turns it into the
    model's terms.

    Attributes
    ----------
    fit : LsqFit
    a : ndarray
        Its coefficients with NNLS round-off set to 0 (:func:`round_off_zero`).
    dropped_z : dict of int to float
        Column index of each dropped term to the Wald statistic it was dropped with.
    """

    fit: LsqFit
    a: FloatArray
    dropped_z: dict[int, float]


def backward_elimination(problem: LsqProblem, z_crit: float | None) -> TermSelection:
    """Fit every term, then drop weak ones one at a time (module docstring).

    ``z_crit`` is :math:`z_{1-\\alpha}`; None keeps every term (a single fit).
    """
    free = np.ones(problem.design.shape[1], dtype=bool)
    fit = problem.solve(free)
    a = round_off_zero(problem.design, fit)
    dropped_z: dict[int, float] = {}
    while z_crit is not None:
        free &= a > 0  # terms the NNLS put at zero stay there
        z_act = z_scores(fit, a)
        covered = np.count_nonzero(
            problem.design * a[None, :] >= COVERAGE_SHARE * fit.mu[:, None], axis=0)
        weak = [(z, j) for j, z in z_act.items()
                if (z < z_crit and covered[j] < MIN_COVERED_POINTS) or covered[j] == 0]
        if not weak or np.count_nonzero(free) <= 1:
            break
        z_min, j_min = min(weak)
        dropped_z[j_min] = z_min
        free[j_min] = False
        fit = problem.solve(free)
        a = round_off_zero(problem.design, fit)
    return TermSelection(fit, a, dropped_z)


def round_off_zero(design: FloatArray, fit: LsqFit) -> FloatArray:
    """The fitted ``a`` with NNLS round-off (< 1e-9 of the curve at every tau) set to 0."""
    share = np.max(design / fit.mu[:, None], axis=0) * fit.a
    return np.where(share < 1e-9, 0.0, fit.a)


def z_scores(fit: LsqFit, a: FloatArray) -> dict[int, float]:
    """Wald statistic ``a_j / se(a_j)`` of every non-zero term (covariance of the fit)."""
    idx = np.flatnonzero(a > 0)
    if not idx.size:
        return {}
    var = np.diag(fit.cov(idx))
    return {int(j): (float(a[j] / math.sqrt(v)) if v > 0 else math.inf)
            for j, v in zip(idx, var, strict=True)}


def term_estimates(names: tuple[str, ...], selection: TermSelection, confidence: float,
                   scale: float, quantity: str = "rate") -> tuple[NoiseTerm, ...]:
    """Each term's value, standard error and interval (an upper limit at zero).

    ``scale`` turns the square root of a scaled coefficient into ``C_n`` in deg/h units
    (m/s^2 units for ``quantity="accel"``; the terms then follow
    :data:`~fogts.allan.terms.ACCEL_TERMS`).
    Identifiability is filled in later by :func:`identify_terms`.
    """
    fit, a, dropped_z = selection.fit, selection.a, selection.dropped_z
    active = a > 0
    z_final = z_scores(fit, a)
    z = float(norm_ppf(0.5 + confidence / 2))
    idx_active = np.flatnonzero(active)
    var_active = np.diag(fit.cov(idx_active)) if idx_active.size else np.zeros(0)
    out: list[NoiseTerm] = []
    rows = term_rows(quantity)
    for j, name in enumerate(names):
        if active[j]:
            se_a = math.sqrt(max(float(var_active[int(np.searchsorted(idx_active, j))]), 0.0))
            c = math.sqrt(a[j])
            c_se = se_a / (2 * c)
            lo_a, hi_a = max(0.0, a[j] - z * se_a), a[j] + z * se_a
            status, z_score = "fitted", z_final[j]
        else:
            idx = np.append(np.flatnonzero(active), j)
            se_bound = math.sqrt(max(float(fit.cov(idx)[-1, -1]), 0.0))
            c, c_se = 0.0, math.nan
            lo_a, hi_a = 0.0, z * se_bound
            status = "dropped" if j in dropped_z else "at_bound"
            z_score = dropped_z.get(j, 0.0)
        tf = rows[name].factor
        out.append(NoiseTerm(
            name=name, value=tf * c * scale, stderr=tf * c_se * scale,
            ci_low=tf * math.sqrt(lo_a) * scale, ci_high=tf * math.sqrt(hi_a) * scale,
            unit=rows[name].unit, c_coeff=c * scale, c_stderr=c_se * scale,
            c_unit=rows[name].c_unit, power=TERM_POWER[name], at_bound=not bool(active[j]),
            identifiable=True, n_covered=0, region_tau_s=(math.nan, math.nan), status=status,
            z_score=z_score))
    return tuple(out)


def identify_terms(model: NoiseModel, tau: FloatArray,
                   extra_avar: Callable[[FloatArray], FloatArray] | None = None
                   ) -> tuple[tuple[NoiseTerm, ...], list[str]]:
    """The model's terms with their region, identifiability and the low-EDF taus where they
    alone dominate, and a message for each term that is not identifiable or is a limit for
    dominating only at low-EDF points (module docstring).  ``tau``: the fitted taus, those
    of ``model.edf``; ``extra_avar``: the Allan variance (curve units) of fitted parts that
    are no term's line (a GMWM's Gauss-Markov terms left out of B), added to the total the
    shares are taken of."""
    def total(t: FloatArray) -> FloatArray:
        return model.curve(t) ** 2 + (0.0 if extra_avar is None else extra_avar(t))

    share = np.vstack(list(model.lines(tau).values())) ** 2 / total(tau)
    low_edf = _low_edf_dominance(model, tau, share)
    wide = np.logspace(math.log10(tau[0]) - 3, math.log10(tau[-1]) + 3, 601)
    wide_share = np.vstack(list(model.lines(wide).values())) ** 2 / total(wide)
    out: list[NoiseTerm] = []
    messages: list[str] = []
    for j, term in enumerate(model.terms):
        n_cov = int(np.count_nonzero(share[j] >= COVERAGE_SHARE))
        where = wide_share[j] >= COVERAGE_SHARE
        region = ((float(wide[where][0]), float(wide[where][-1])) if np.any(where)
                  else (math.nan, math.nan))
        ok = n_cov >= MIN_COVERED_POINTS or (n_cov == 1 and term.ci_low > 0)
        if not ok:
            messages.append(_unidentifiable_message(model, term, tau, n_cov, region))
        if low_edf[j]:
            messages.append(_low_edf_message(model, term, tau, low_edf[j]))
        out.append(dataclasses.replace(term, identifiable=ok, n_covered=n_cov,
                                       region_tau_s=region, low_edf_taus=low_edf[j]))
    return tuple(out), messages


def floorless_flicker(model: NoiseModel) -> tuple[tuple[NoiseTerm, ...], str]:
    """The model's terms with B marked an upper limit when its slope read-off found no floor
    and it dominates at fewer than two trusted points
    (:attr:`~fogts.allan.noise_model.NoiseTerm.no_floor`, module docstring), and the
    message to warn with when that makes a measured B a limit ("" otherwise)."""
    notes = [note for name, note in model.readoff.notes
             if name == "B" and "no floor" in note]
    if not notes or "B" not in model.names or model["B"].at_bound:
        return model.terms, ""
    trusted = _trusted_dominance(model, model.tau_s)[model.names.index("B")]
    if trusted >= 2:
        return model.terms, ""
    reason = notes[0].split(";")[0]
    term = model["B"]
    message = "" if term.is_limit else (
        f"noise term B (bias instability) is fitted with z(C²) = {term.z_score:.2f}, but it "
        f"dominates the fitted sigma^2 at {trusted} point{'' if trusted == 1 else 's'} with "
        f"EDF >= {MIN_EDF_FOR_MINIMUM:g} and {reason.removeprefix('no floor: ')}: the data "
        "do not reach the flat bottom that B is read on (IEEE 952 Annex C); treat its value "
        "as an upper limit")
    marked = dataclasses.replace(term, no_floor=reason)
    return tuple(marked if t.name == "B" else t for t in model.terms), message


def _trusted_dominance(model: NoiseModel, tau: FloatArray) -> list[int]:
    """Per term: the number of taus where it dominates the fitted sigma^2 (its line the
    largest) and the point has EDF >= MIN_EDF_FOR_MINIMUM."""
    dominates, trusted = _dominance(model, np.vstack(list(model.lines(tau).values())) ** 2)
    if trusted is None:
        return [0] * len(model.terms)
    return [int(np.count_nonzero(d & trusted)) for d in dominates]


def _dominance(model: NoiseModel, share: FloatArray) -> tuple[np.ndarray, np.ndarray | None]:
    """Per term and tau whether the term dominates there (its share of sigma^2, or its
    line, the largest and positive), and per tau whether the point has EDF >=
    MIN_EDF_FOR_MINIMUM (a NaN EDF counts as too few; None when the model's EDF are not
    those of these taus)."""
    winner = np.argmax(share, axis=0)
    dominates = (winner == np.arange(share.shape[0])[:, None]) & (share > 0)
    edf = np.asarray(model.edf, dtype=np.float64)
    if edf.shape != share.shape[1:]:
        return dominates, None
    return dominates, np.isfinite(edf) & (edf >= MIN_EDF_FOR_MINIMUM)


def _low_edf_dominance(model: NoiseModel, tau: FloatArray, share: FloatArray
                       ) -> list[tuple[float, ...]]:
    """Per term: the taus where it dominates, if all have EDF < MIN_EDF_FOR_MINIMUM (a NaN
    EDF counts as too few), else () (module docstring)."""
    dominates, trusted = _dominance(model, share)
    if trusted is None:
        return [()] * len(model.terms)
    return [tuple(float(t) for t in tau[d]) if d.any() and not trusted[d].any() else ()
            for d in dominates]


def _low_edf_message(model: NoiseModel, term: NoiseTerm, tau: FloatArray,
                     taus: tuple[float, ...]) -> str:
    edf = [float(e) for t, e in zip(tau, model.edf, strict=True) if t in taus]
    description = term_rows(model.quantity)[term.name].description
    return (f"noise term {term.name} ({description}, slope {term.slope:+g}) dominates the "
            f"fitted sigma^2 only at tau {', '.join(f'{t:.4g}' for t in taus)} s, where the "
            f"points have EDF < {MIN_EDF_FOR_MINIMUM:g} "
            f"({', '.join(f'{e:.3g}' for e in edf)}): too few degrees of freedom to measure "
            "it; treat its value as an upper limit")


def _drop_reason(term: NoiseTerm, significance: float | None) -> str:
    """Why backward elimination dropped ``term``: not significant, or (whatever its z)
    visible at no data tau (module docstring)."""
    level = significance if significance is not None else math.nan
    if math.isfinite(level) and term.z_score >= float(norm_ppf(1.0 - level)):
        return (f"it was dropped although z(C²) = {term.z_score:.2f} passes the level-{level:g} "
                f"test: it reaches {100 * COVERAGE_SHARE:g} % of sigma^2 at no data tau, so "
                "only the curvature at the edge of the tau range measures it")
    return (f"it was dropped as not significant, z(C²) = {term.z_score:.2f} at level "
            f"{level:g}")


def _unidentifiable_message(model: NoiseModel, term: NoiseTerm, tau: FloatArray, n_cov: int,
                            region: tuple[float, float]) -> str:
    pct = f"{100 * COVERAGE_SHARE:g} %"
    if term.short_gm:
        why = term.short_gm
    elif term.status == "dropped":
        why = _drop_reason(term, model.significance)
    elif term.at_bound:
        why = "it was fitted to zero"
    elif math.isnan(region[0]):
        why = f"it never reaches {pct} of the fitted curve"
    else:
        why = f"it would reach {pct} only at tau {region[0]:.3g}..{region[1]:.3g} s"
    description = term_rows(model.quantity)[term.name].description
    return (f"noise term {term.name} ({description}, slope "
            f"{term.slope:+g}) is not identifiable from taus {tau[0]:.4g}..{tau[-1]:.4g}"
            f" s: it makes up at least {pct} of the fitted sigma^2 at {n_cov} of "
            f"{tau.size} taus ({why}); treat its value as an upper limit")
