"""The plain-language verdict of an ARMA selection, and the notes on its data."""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np

from fogts._typing import FloatArray
from fogts.arma.candidate import Candidate
from fogts.arma.identification import Correlogram
from fogts.arma.margins import CLOSE_CALL, equivalent_simpler
from fogts.arma.redundancy import common_factor_z
from fogts.arma.roots import unit_circle_root
from fogts.arma.whiteness import BAND_Z

__all__ = ["CLOSE_CALL", "QUANT_CHECK_SAMPLES", "QUANT_MAX_LEVELS", "SMALL_PREDICTION",
           "on_unit_circle", "quantization_note", "ranks_down", "write_verdict"]

#: Below this share of variance removed by the one-step prediction, the verdict says the
#: series is nearly white (the model explains almost nothing).
SMALL_PREDICTION = 0.05
#: A raw rate with at most this many distinct values (in the first QUANT_CHECK_SAMPLES) is
#: reported as quantized.
QUANT_MAX_LEVELS = 64
QUANT_CHECK_SAMPLES = 200_000


def on_unit_circle(c: Candidate) -> complex | None:
    """The MA inverse root of a fitted candidate that lies on the unit circle, else None.

    "On" means within 1/n of it: there an MA(1) coefficient theta = -1 + gamma/n cannot be
    told from theta = -1 (local-to-unity asymptotics, Davis & Dunsmuir 1996, *Econometric
    Theory* 12, 1-29), and it is where ML estimates pile up by chance.
    """
    if c.roots is None or c.fit is None:
        return None
    return unit_circle_root(c.roots.ma_inverse, c.fit.nobs)


def ranks_down(c: Candidate) -> bool:
    """Whether the candidate ranks after the others of its group (white or not): its AR and
    MA parts may share a root (not identified), or an MA root lies on the unit circle (not
    invertible).  See :mod:`fogts.arma.select`, "Ranking rule"."""
    return bool(c.flagged("common_factor")) or on_unit_circle(c) is not None


def quantization_note(raw: FloatArray | None, units: str | None) -> str | None:
    """A note if the raw rate takes few distinct values (a quantized gyro output)."""
    if raw is None or raw.size < 100:
        return None
    levels = np.unique(raw[:QUANT_CHECK_SAMPLES])
    if levels.size > QUANT_MAX_LEVELS:
        return None
    step = float(np.min(np.diff(levels))) if levels.size > 1 else 0.0
    unit = f" {units}" if units else ""
    return (f"The raw rate takes only {levels.size} distinct values (step {step:.4g}{unit}): "
            "it is quantized, so its residuals cannot look Gaussian; block-average it "
            "(decimate) before modelling the drift.")


def _cancellation_sentence(sel: Candidate, ranked: Sequence[Candidate], criterion: str,
                           simpler_exists: bool) -> str:
    """What nearly cancelling AR/MA roots mean here: a lower order does as well only when a
    lower-order candidate is white and close in the criterion, or fails the residual checks
    only marginally (``simpler_exists``; the caller says which); otherwise say why not, with
    the numbers of the best lower-order candidate."""
    lead = " Its AR and MA roots nearly cancel"
    if not sel.flagged("common_factor") and sel.fit is not None:
        z = common_factor_z(sel.ar, sel.ma, sel.fit.coef_cov, nobs=sel.fit.nobs)
        if math.isfinite(z):
            lead += (f", though not within their sampling uncertainty (common-factor "
                     f"|z| = {abs(z):.2f} >= {BAND_Z:g})")
    if simpler_exists:
        return lead + "."
    crit = criterion.upper()
    lower = [c for c in ranked if c.ok and c.p + c.q < sel.p + sel.q]
    if not lower:
        return lead + "; no lower-order candidate was fitted."
    best = min(lower, key=lambda c: getattr(c, criterion))
    delta = getattr(best, criterion) - getattr(sel, criterion)
    why = "and is not white" if not best.white else "though white"
    return (f"{lead}, yet no lower order does as well: the best "
            f"lower-order candidate, {best.model}, is {delta:+.1f} {crit} units {why}; keep "
            f"{sel.model}.")


def _among(demoted: Sequence[Candidate]) -> str:
    """How "the white candidates" is qualified when some with a lower criterion ranked down."""
    why = []
    if any(c.flagged("common_factor") for c in demoted):
        why.append("a possible common AR/MA factor")
    if any(on_unit_circle(c) is not None for c in demoted):
        why.append("an MA root on the unit circle")
    return f" without {' or '.join(why)}" if why else ""


def _common_factor_sentence(sel: Candidate, demoted: Sequence[Candidate],
                            criterion: str) -> str:
    """Why a candidate with a lower criterion (``demoted``, in ``sel``'s white or not-white
    group) was ranked below ``sel``: its AR and MA parts may share a root
    (:func:`fogts.arma.redundancy.common_factor`) or an MA root lies on the unit circle;
    else the caution that ``sel`` itself may have a common factor."""
    crit = criterion.upper()
    if demoted:
        low = min(demoted, key=lambda c: getattr(c, criterion))
        gap = getattr(sel, criterion) - getattr(low, criterion)
        return (f" {low.model} has a lower {crit} (by {gap:.1f}) but ranks below it: "
                f"{_ranked_down_reason(low)}.")
    own = sel.flagged("common_factor")
    return f" Caution: {own[0].message}." if own else ""


def _ranked_down_reason(c: Candidate) -> str:
    """The reason ``c`` ranks down (:func:`ranks_down`), with its numbers."""
    flags = c.flagged("common_factor")
    if flags:
        return flags[0].message
    mu = on_unit_circle(c)
    assert mu is not None
    return (f"its MA inverse root {mu.real:.6g}{mu.imag:+.3g}j lies on the unit circle "
            "(within 1/n), so it is not invertible and its innovations cannot be recovered "
            "from the data (a boundary pile-up of the estimate, or an over-differenced or "
            "filtered series)")


def write_verdict(sel: Candidate | None, ranked: Sequence[Candidate], criterion: str,
                  corr: Correlogram) -> str:
    """One paragraph on the selected candidate ``sel`` (None if every fit failed): whether it
    describes the drift, a simpler white model close in the criterion, the cancelling roots
    and how much the one-step prediction removes; the candidates that failed are named."""
    if sel is None:
        reasons: dict[str, list[str]] = {}
        for c in ranked:
            reasons.setdefault(str(c.reason), []).append(c.model)
        text = "; ".join(r if len(reasons) == 1 else f"{', '.join(m)}: {r}"
                         for r, m in reasons.items())
        return f"No candidate could be fitted: {text}."
    return _selected_verdict(sel, ranked, criterion, corr) + _failed_sentence(ranked)


def _failed_sentence(ranked: Sequence[Candidate]) -> str:
    """Name the candidates that could not be fitted (never silently left out)."""
    failed = [c for c in ranked if not c.ok]
    if not failed:
        return ""
    reasons = "; ".join(f"{c.model}: {c.reason}" for c in failed)
    return (f" Not compared: {', '.join(c.model for c in failed)} could not be fitted "
            f"({reasons}).")


def _selected_verdict(sel: Candidate, ranked: Sequence[Candidate], criterion: str,
                      corr: Correlogram) -> str:
    crit = criterion.upper()
    removed_fraction = float(sel.prediction_summary()["variance_removed"])
    removed = 100.0 * removed_fraction
    # candidates of sel's group (white or not) with a lower criterion, ranked below it for a
    # possible common AR/MA factor
    demoted = [c for c in ranked if c.ok and c.white == sel.white
               and ranks_down(c) and getattr(c, criterion) < getattr(sel, criterion)]
    among = _among(demoted)
    if sel.white and on_unit_circle(sel) is not None:
        return (_non_invertible_verdict(sel, ranked, criterion, among)
                + _common_factor_sentence(sel, demoted, criterion))
    if sel.white:
        text = (f"{sel.model} describes the drift: its residuals are white (rho_a2, rho_ax3 and "
                f"Ljung-Box all pass), lowest {crit} among the white candidates{among}; one-step "
                f"prediction removes {removed:.1f} % of the variance.")
        text += _common_factor_sentence(sel, demoted, criterion)
        simpler = [c for c in ranked if c.white and c.p + c.q < sel.p + sel.q
                   and getattr(c, criterion) - getattr(sel, criterion) < CLOSE_CALL]
        # a simpler candidate that fails the residual checks only marginally
        marginal = None if simpler else equivalent_simpler(sel, ranked, criterion)
        if sel.flagged("near_cancellation"):
            text += _cancellation_sentence(sel, ranked, criterion,
                                           bool(simpler) or marginal is not None)
        if simpler:
            alt = min(simpler, key=lambda c: (c.p + c.q, getattr(c, criterion)))
            text += (f" The simpler {alt.model} is within {CLOSE_CALL:g} {crit} units and also "
                     f"white: the data support it about as well.")
        elif marginal is not None:
            text += marginal.sentence(sel.model)
        if removed_fraction < SMALL_PREDICTION:
            text += (" The series is nearly white at this sample rate (white rate noise, i.e. "
                     "angle random walk, dominates): decimate to model the slower drift.")
        elif corr.acf_pattern.kind == "none" and corr.pacf_pattern.kind == "none":
            text += " The data are close to white noise to begin with."
        return text
    assert sel.diagnostics is not None
    why = "; ".join(sel.diagnostics.reasons)
    return (f"No candidate leaves white residuals: the best by {crit}{among}, {sel.model}, "
            f"still fails ({why}).{_common_factor_sentence(sel, demoted, criterion)} The drift "
            f"needs a richer model or more preprocessing (detrend, remove outliers, "
            f"decimate); use this model with care.")


def _non_invertible_verdict(sel: Candidate, ranked: Sequence[Candidate], criterion: str,
                            among: str = "") -> str:
    """The selected model has an MA root on the unit circle: what that means, and the best
    white candidate without one (``among`` qualifies "the white candidates")."""
    crit = criterion.upper()
    mu = on_unit_circle(sel)
    assert mu is not None
    where = ("frequency 0" if abs(mu.imag) < 1e-8 and mu.real > 0 else
             "the Nyquist frequency" if abs(mu.imag) < 1e-8 else
             f"{abs(np.angle(mu)) / (2 * np.pi):.3g} cycles per sample")
    text = (f"{sel.model} has the lowest {crit} among the white candidates{among}, but it is not "
            f"invertible: its MA inverse root {mu.real:.6g}{mu.imag:+.3g}j lies on the unit "
            f"circle (within 1/n), a zero of the spectrum at {where}. Either the series was "
            "over-differenced or filtered (a component removed), or the estimate piled up on "
            "the boundary by chance, as it does in short records. The innovations of a "
            "non-invertible model cannot be recovered from the data: "
            f"{sel.model} does not describe the drift.")
    others = [c for c in ranked if c.white and c is not sel and on_unit_circle(c) is None]
    if others:
        alt = min(others, key=lambda c: getattr(c, criterion))
        delta = getattr(alt, criterion) - getattr(sel, criterion)
        text += (f" The best invertible white candidate is {alt.model} ({delta:+.1f} {crit} "
                 "units).")
    else:
        text += " No white candidate is invertible."
    return text
