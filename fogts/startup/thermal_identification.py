"""Are the thermal coefficients separately identified, or only their curve along one run?

One warm-up moves T and ΔT = dT/dt together along a single path: T rises as ΔT decays, so
the six regressors of D = a·T·ΔT + b·T² + c·T + d·ΔT² + e·ΔT + f are nearly linear
combinations of one another along it.  A least-squares fit then determines the drift curve
along that path well (the model is jointly significant) while each coefficient has a huge
standard error and a sign set by chance: the classic symptom of multicollinearity, a
jointly significant set of individually insignificant coefficients (Greene, *Econometric
Analysis*, 7th ed., 2012, §4.8.1).  Such coefficients describe the fitted run only; on
another ambient or warm-up, (T, ΔT) leaves the path and their errors no longer cancel.

Diagnostics of the design matrix X (the regressors as fitted):

* **variance inflation factor** of each term other than the offset,
  ``VIF_j = 1 / (1 - R_j²)`` with ``R_j²`` from regressing column j on the other columns
  (statsmodels' :func:`~statsmodels.stats.outliers_influence.variance_inflation_factor`;
  centred when the offset "1" is fitted).  A largest VIF above :data:`VIF_THRESHOLD` = 10
  is the usual mark of collinearity that distorts the estimates (Kutner, Nachtsheim,
  Neter & Li, *Applied Linear Statistical Models*, 5th ed., 2005, §10.5);
* **condition number** of X with its columns scaled to unit length (Belsley, Kuh & Welsch,
  *Regression Diagnostics*, 1980, §3.2; above :data:`CONDITION_THRESHOLD` = 30 their
  "moderate to strong" dependencies), reported alongside.

The note of :func:`identification_note` is given when the model is jointly significant,
its largest VIF exceeds 10, and fewer than half of its thermal coefficients (the terms
other than the offset) are individually significant at 5 % (``|t| > 1.96``, a lenient
level against the joint test's 0.1 %, so the note is not given for a coefficient that
narrowly misses).  Fits on several cold starts at different ambients usually still have
VIFs far above 10 (T and T² over 15-50 °C are nearly collinear), but most of their
coefficients are then individually significant and no note is given.

A fitted model that the likelihood-ratio test does **not** find jointly significant
(:func:`~fogts.startup.thermal_test.thermal_significance`) gets the other note, of
:func:`significance_note`: its coefficients fit the run's own drift, not a temperature
dependence, and must not be reused on another run.  Either note travels with the saved
model (``identification_note``), and :func:`reuse_warning` repeats it when the model is
applied to another run.
"""

from __future__ import annotations

import math
import warnings
from collections.abc import Sequence
from statistics import NormalDist
from typing import TYPE_CHECKING, Any

import numpy as np

from fogts._typing import FloatArray

if TYPE_CHECKING:
    from fogts.startup.thermal_model import ThermalModel
    from fogts.startup.thermal_test import ThermalSignificance

__all__ = ["CONDITION_THRESHOLD", "NOT_SIGNIFICANT", "T_CRITICAL", "VIF_THRESHOLD",
           "collinearity", "identification_note", "note_in_brief", "reuse_warning",
           "significance_note", "significant_terms"]

#: Largest variance inflation factor of coefficients that are not collinear (Kutner et al.).
VIF_THRESHOLD = 10.0
#: Condition number (unit-length columns) above which Belsley et al. see strong dependencies.
CONDITION_THRESHOLD = 30.0
#: |t| of an individually significant coefficient (two-sided 5 %).
T_CRITICAL = NormalDist().inv_cdf(0.975)
#: How the note of :func:`significance_note` begins (and is told from the collinearity note).
NOT_SIGNIFICANT = "the model is not significant"


def collinearity(X: FloatArray, terms: Sequence[str]) -> dict[str, Any]:
    """Variance inflation factors and the scaled condition number of a design matrix.

    Parameters
    ----------
    X : ndarray
        The regressor columns, one per term (:func:`~fogts.startup.thermal_model.design_matrix`).
    terms : sequence of str
        Term of each column; the offset ``"1"`` gets no VIF.

    Returns
    -------
    dict
        ``{"vif": {term: VIF}, "max_vif", "max_vif_term", "condition_number",
        "vif_threshold", "condition_threshold"}`` (``max_vif`` NaN and ``max_vif_term``
        None without a term other than the offset).

    Examples
    --------
    >>> t = np.linspace(20.0, 45.0, 500)
    >>> d = collinearity(np.column_stack([t, t ** 2, np.ones_like(t)]), ["T", "T2", "1"])
    >>> d["max_vif"] > 10, d["vif"]["T"] == d["vif"]["T2"]
    (True, True)
    """
    from statsmodels.stats.outliers_influence import variance_inflation_factor

    x = np.asarray(X, dtype=np.float64)
    names = list(terms)
    vif: dict[str, float] = {}
    for j, term in enumerate(names):
        if term == "1":
            continue
        if x.shape[1] < 2:
            vif[term] = 1.0  # a lone column is collinear with nothing
            continue
        with warnings.catch_warnings():
            # its own "poorly conditioned" warning: the condition number is reported below
            warnings.simplefilter("ignore")
            vif[term] = float(variance_inflation_factor(x, j))
    norms = np.linalg.norm(x, axis=0)
    scaled = x / np.where(norms > 0, norms, 1.0)
    sv = np.linalg.svd(scaled, compute_uv=False) if x.size else np.ones(1)
    cond = float(sv[0] / sv[-1]) if sv[-1] > 0 else math.inf
    top = max(vif, key=lambda k: vif[k]) if vif else None
    return {"vif": vif, "max_vif": vif[top] if top is not None else math.nan,
            "max_vif_term": top, "condition_number": cond, "vif_threshold": VIF_THRESHOLD,
            "condition_threshold": CONDITION_THRESHOLD}


def significant_terms(model: ThermalModel) -> list[str]:
    """The thermal terms (not the offset) whose ``|value / stderr|`` exceeds
    :data:`T_CRITICAL`."""
    out = []
    for t in model.terms:
        se = model.stderr.get(t, math.nan)
        if t != "1" and math.isfinite(se) and se > 0 and abs(model.coefficients[t]) / se > T_CRITICAL:
            out.append(t)
    return out


def identification_note(model: ThermalModel, jointly_significant: bool) -> str | None:
    """The note for a model whose coefficients are not separately identified (module
    docstring for the rule), or None.

    Parameters
    ----------
    model : ThermalModel
        A fitted model carrying its :attr:`~ThermalModel.collinearity` diagnostics.
    jointly_significant : bool
        The verdict of the test against "no temperature dependence"
        (:func:`~fogts.startup.thermal_test.thermal_significance`).
    """
    diag = model.collinearity or {}
    max_vif = float(diag.get("max_vif", math.nan))
    thermal = [t for t in model.terms if t != "1"]
    if not jointly_significant or len(thermal) < 2 or not max_vif > VIF_THRESHOLD:
        return None
    n_sig = len(significant_terms(model))
    if 2 * n_sig >= len(thermal):
        return None
    return (f"the coefficients are not separately identified (collinear: largest variance "
            f"inflation factor {max_vif:.3g} ({diag.get('max_vif_term')}), above "
            f"{VIF_THRESHOLD:g}; {n_sig} of {len(thermal)} thermal coefficients individually "
            f"significant (|t| > {T_CRITICAL:.2f}) although the model is jointly significant); "
            "the model describes this run's warm-up path only; do not reuse it on another "
            "ambient or warm-up without a calibration run")


def significance_note(significance: ThermalSignificance) -> str | None:
    """The note for a fitted model the likelihood-ratio test does not find jointly
    significant, or None for a significant one.

    Parameters
    ----------
    significance : ThermalSignificance
        The verdict of :func:`~fogts.startup.thermal_test.thermal_significance` on the run
        the model was fitted to.

    Examples
    --------
    >>> from fogts.startup.thermal_test import ThermalSignificance
    >>> sig = ThermalSignificance(True, False, 3.65, 5, 0.6, 0.001, 20.0, 3000, 3.6)
    >>> significance_note(sig)[:75]
    'the model is not significant (likelihood-ratio test against a random-walk d'
    """
    if significance.significant:
        return None
    if significance.testable:
        why = f"{significance.test_text()}, above the level {significance.alpha:g}"
    else:
        why = (f"the temperature spans only {significance.span_degC:.3g} °C: the "
               "coefficients cannot be identified")
    return (f"{NOT_SIGNIFICANT} ({why}): its coefficients fit this run's drift, not a "
            "temperature dependence; do not reuse it to compensate another run")


def note_in_brief(model: ThermalModel) -> str | None:
    """The model's note in a few words (for a line such as "saved the model (with its note:
    ...)"), or None without a note."""
    note = model.identification_note
    if not note:
        return None
    if note.startswith(NOT_SIGNIFICANT):
        return "not significant, not for reuse on another run"
    return "not separately identified, not for reuse on another ambient or warm-up"


def reuse_warning(model: ThermalModel) -> str | None:
    """The warning for applying a saved model that carries an identification note to a run,
    or None."""
    if not model.identification_note:
        return None
    return (f"the thermal model applied here was fitted on another run and saved with this "
            f"note: {model.identification_note}")
