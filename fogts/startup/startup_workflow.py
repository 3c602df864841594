"""The start-up drift compensation workflow on one axis of a run.

1. EMD of the gyro output (:func:`~fogts.startup.emd.separate_trend`): trend = the IMFs from
   the first whose mean energy rises again, rest = the faster IMFs;
2. ARMA model of the rest (:func:`~fogts.startup.kalman.resolve_arma_model`);
3. Kalman filter of the rest (:func:`~fogts.startup.kalman.arma_kalman`);
4. filtered gyro = trend + filtered rest;
5. the same for the temperature;
6. fit of D = a·T·ΔT + b·T² + c·T + d·ΔT² + e·ΔT + f
   (:func:`~fogts.startup.thermal_fit.fit_thermal`);
7. compensation (:func:`~fogts.startup.compensation.compensate`) and bias stability before
   and after;
8. when the model is significant, the same gain out of sample
   (:func:`~fogts.startup.thermal_cv.thermal_cross_validation`): on held-out runs when
   calibration runs are given, else on contiguous time blocks of the run.
"""

from __future__ import annotations

import math
import warnings
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field, replace
from functools import partial
from typing import TYPE_CHECKING, Any

import numpy as np
import pandas as pd

from fogts._typing import FloatArray
from fogts._validate import check_choice, check_positive
from fogts.choices import APPLY_RULES, ApplyRule
from fogts.errors import DataError, InsufficientDataError, ModelFitError, UnidentifiableTermWarning
from fogts.io.run import Run
from fogts.startup.compensation import (
    BiasStability,
    bias_stability,
    check_calibration_run,
    compensate,
    require_temperature,
)
from fogts.startup.thermal_cv import ThermalCrossValidation, thermal_cross_validation
from fogts.startup.thermal_fit import fit_thermal
from fogts.startup.thermal_identification import (
    collinearity,
    identification_note,
    reuse_warning,
    significance_note,
)
from fogts.startup.thermal_model import (
    DEFAULT_DT_SMOOTHING_S,
    ErrorModel,
    ThermalModel,
    design_matrix,
    temperature_rate,
)
from fogts.startup.thermal_test import ThermalSignificance, thermal_significance
from fogts.tables import Column, Table, TableView

if TYPE_CHECKING:  # annotations only: EMD and the Kalman filter are imported where they run
    from fogts.startup.emd import TrendSplit
    from fogts.startup.kalman.result import KalmanResult

__all__ = ["StartupCompensation", "startup_compensation"]

#: Appended to the missing-temperature error of the workflow (its input comes from a file).
_COLUMN_HINT = "; name it with temperature_column="


@dataclass(frozen=True, repr=False)
class StartupCompensation(TableView):
    """The start-up compensation workflow and its outcome.

    Attributes
    ----------
    run : Run
        The compensated recording (raw temperature kept).
    model : ThermalModel
        The thermal model fitted (or the one given).
    gyro_split, temperature_split : TrendSplit or None
        EMD trend separations (None without EMD).
    kalman : KalmanResult or None
        Kalman filter of the gyro's EMD rest.
    arma_model : str
        Name of the ARMA model of the rest ("" without EMD).
    gyro_used, temperature_used : ndarray
        The series the thermal model was fitted to (trend + filtered rest, or raw).
    raw_rate : ndarray
        The input rate of the compensated axis.
    before, after : BiasStability
        Bias stability of the raw and of the compensated rate (in sample).
    axis : str
    notes : tuple of str
    significance : ThermalSignificance or None
        The test against "no temperature dependence" (None for a given model).
    out_of_sample : ThermalCrossValidation or None
        The gain on held-out runs or time blocks (measured only for a significant model).
    applied : bool
        Whether the model was subtracted.  A fitted model that the test does not find
        significant is not, unless asked (``apply="always"``): ``run`` then holds the
        input rate and ``after`` equals ``before``.
    """

    run: Run
    model: ThermalModel
    gyro_split: TrendSplit | None
    temperature_split: TrendSplit | None
    kalman: KalmanResult | None
    arma_model: str
    gyro_used: FloatArray = field(repr=False)
    temperature_used: FloatArray = field(repr=False)
    raw_rate: FloatArray = field(repr=False)
    before: BiasStability
    after: BiasStability
    axis: str = ""
    notes: tuple[str, ...] = ()
    significance: ThermalSignificance | None = None
    out_of_sample: ThermalCrossValidation | None = None
    applied: bool = True

    @property
    def claim_basis(self) -> str:
        """``"given model"``, ``"out of sample"`` (a held-out gain above 1 on folds covering
        the fitted T and ΔT ranges: :meth:`ThermalCrossValidation.claim_gap`) or ``"in sample
        only"`` (a gain a fit absorbing drift also shows): what a claim rests on."""
        if self.significance is None:
            return "given model"
        cv = self.out_of_sample
        return "out of sample" if cv is not None and not cv.claim_gap() else "in sample only"

    @property
    def claims_improvement(self) -> bool:
        """Whether the compensation may be called an improvement: a given model, or a fitted
        one found significant whose gain holds out of sample (:attr:`claim_basis`), and the
        bias stability after it is better than before."""
        tested = self.significance is None or self.significance.significant
        return tested and self.improvement > 1.0 and self.claim_basis != "in sample only"

    @property
    def improvement(self) -> float:
        """Bias stability before / after."""
        return self.before.value / self.after.value if self.after.value > 0 else math.inf

    def to_dict(self) -> dict[str, Any]:
        emd = None
        if self.gyro_split is not None:
            emd = {"k": int(self.gyro_split.k),
                   "imf_energy": [float(v) for v in self.gyro_split.imf_energy],
                   "n_imfs": self.gyro_split.n_imfs,
                   "temperature_k": (None if self.temperature_split is None
                                     else int(self.temperature_split.k))}
        model = self.model.to_dict()
        return {
            "axis": self.axis,
            "emd": emd,
            "arma_model": self.arma_model or None,
            "kalman": None if self.kalman is None else self.kalman.to_dict(),
            "thermal": {"terms": {t: {"value": v["value"], "stderr": v["stderr"]}
                                  for t, v in model["terms"].items()},
                        "r2": model["r2"], "dropped": model["dropped"],
                        "equation": self.model.equation(), "model": model},
            "significance": (None if self.significance is None
                             else self.significance.to_dict()),
            "bias_stability": {"average_s": self.before.average_s, "before": self.before.value,
                               "after": self.after.value, "unit": self.before.unit,
                               "improvement": self.improvement,
                               "improvement_claimed": self.claims_improvement,
                               "claim_basis": self.claim_basis},
            "notes": list(self.notes),
            "out_of_sample": (None if self.out_of_sample is None
                              else self.out_of_sample.to_dict()),
            "applied": self.applied,
        }

    def to_frame(self) -> pd.DataFrame:
        """Columns time, raw, trend (EMD, NaN without), used (fit input), compensated,
        temperature."""
        trend = (np.asarray(self.gyro_split.trend, dtype=float) if self.gyro_split is not None
                 else np.full(self.raw_rate.size, np.nan))
        return pd.DataFrame({"time": self.run.time, "raw": self.raw_rate, "trend": trend,
                             "used": self.gyro_used,
                             "compensated": self.run.axis(self.axis or 0),
                             "temperature": self.run.temperature})

    # -------------------------------------------------------------- notebook view
    def _view_table(self) -> Table:
        """The bias stability before and after, and the model's verdict."""
        rows: list[tuple[Any, ...]] = [
            ("bias stability before", self.before.value, self.before.unit),
            ("bias stability after", self.after.value, self.after.unit),
            ("improvement" + (" in sample" if self.significance is not None else ""),
             self.improvement, "x" if self.claims_improvement else "x (not claimed)")]
        if self.out_of_sample is not None:
            rows.append(("improvement out of sample", self.out_of_sample.ratio,
                         f"x, {self.out_of_sample.gain_text().split(', ', 1)[-1]}"))
        rows.append(("thermal model R²", self.model.r2, ""))
        return Table.build(
            f"Start-up compensation of {self.axis or 'axis 0'} "
            f"({self.before.average_s:g} s averages)",
            (Column("quantity", numeric=False), Column("value"), Column("unit", numeric=False)),
            rows, caption=self.significance.verdict if self.significance is not None else "")

    def _view_headline(self) -> str:
        return (f"{self.axis or 'axis 0'}: bias stability {self.before.value:.4g} -> "
                f"{self.after.value:.4g} {self.after.unit}"
                + ("" if self.significance is None else " (in sample"
                   + (f"; out of sample {self.out_of_sample.gain_text()})"
                      if self.out_of_sample is not None else ")")))

    def summary(self) -> str:
        lines = []
        if self.gyro_split is not None:
            split = self.gyro_split
            trend = (f"trend from IMF {split.k} (mean-energy rule)" if split.k <= split.n_imfs
                     else "trend = the residue only (the mean-energy rule puts no IMF in it)")
            lines.append(f"EMD: {split.n_imfs} IMFs, {trend}; rest modelled as "
                         f"{self.arma_model}")
        if self.kalman is not None:
            lines.append(f"Kalman: H = {self.kalman.measurement_noise:.4g} "
                         f"({self.kalman.measurement_noise_source}), {self.kalman.method}")
        if self.significance is not None:
            lines.insert(0, f"verdict: {self.significance.verdict}")
        if not self.applied:
            lines.append(f"thermal model: fitted, not applied: {self.not_applied_reason()}; "
                         "the rate is left as it was (the coefficients are in the JSON and "
                         "--save-model; --apply always subtracts them)")
            lines.append(f"bias stability ({self.before.average_s:g} s average, 1σ): "
                         f"{self.before.value:.4g} {self.before.unit} (nothing compensated)")
        else:
            lines.append(self.model.summary())
            lines.append(self._stability_line())
        if self.out_of_sample is not None:
            lines.append(self.out_of_sample.summary())
        lines += [f"note: {n}" for n in self.notes]
        return "\n".join(lines)

    def _stability_line(self) -> str:
        stability = (f"bias stability ({self.before.average_s:g} s average, 1σ): "
                     f"before {self.before.value:.4g} {self.before.unit}, after "
                     f"{self.after.value:.4g} {self.after.unit}")
        if not self.claims_improvement:
            if self.claim_basis == "in sample only" and self.improvement > 1.0:
                stability += f" ({self.improvement:.2f}x in sample)"
            return f"{stability}; not claimed as an improvement: {self.no_claim_reason()}"
        if self.significance is None or self.out_of_sample is None:
            return (f"{stability} ({self.improvement:.2f}x by the given model: out of sample "
                    "unless it was fitted on this run)")
        return (f"{stability} ({self.improvement:.2f}x in sample; out of sample "
                f"{self.out_of_sample.gain_text()})")

    def not_applied_reason(self) -> str:
        """Why a fitted model was not subtracted (the verdict's reason, in a clause)."""
        if self.significance is not None and not self.significance.testable:
            return (f"the temperature spans {self.significance.span_degC:.3g} °C, too little "
                    "to identify its coefficients")
        return "the likelihood-ratio test finds no significant temperature dependence"

    def no_claim_reason(self) -> str:
        """Why the bias-stability change is not an improvement, as the verdict says (the
        terminal summary and the HTML report give this one reason)."""
        if (self.significance is None or self.significance.significant) \
                and not self.improvement > 1.0:
            return (f"the bias stability is {self.improvement:.2f}x, no better after the "
                    + ("given model: it does not describe this run's thermal drift"
                       if self.significance is None else "fitted model"))
        if self.significance is not None and not self.significance.testable:
            return ("the thermal model is not testable on this record, so the change is the "
                    "fit absorbing drift")
        if self.significance is not None and self.significance.significant:
            return "in sample only: " + (self.out_of_sample.claim_gap() if self.out_of_sample
                                         else "the out-of-sample gain was not measured")
        return "the model is not significant, so the change is the fit absorbing drift"


# over 80 lines only through its numpydoc docstring; the body is short
def startup_compensation(
    run: Run,
    *,
    axis: int | str = 0,
    emd: bool = True,
    model: ThermalModel | None = None,
    arma_model: str = "auto",
    measurement_noise: Any = "estimate",
    terms: Sequence[str] = ("T*dT", "T2", "T", "dT2", "dT", "1"),
    dT_smoothing_s: float | None = DEFAULT_DT_SMOOTHING_S,
    errors: ErrorModel = "ar",
    average_s: float = 10.0,
    calibration: Sequence[Run] = (),
    apply: ApplyRule = "significant",
) -> StartupCompensation:
    """Start-up drift compensation, steps 1-7 of the module docstring, on one axis of a run.

    With ``emd=False`` steps 1-5 are skipped and the model is fitted to the raw series.
    With ``model`` given, nothing is fitted: the saved model is applied (with a warning
    when it carries an identification note).  A fitted model that is jointly significant
    but whose coefficients are collinear and mostly insignificant gets that note and a
    warning (:mod:`~fogts.startup.thermal_identification`); one the likelihood-ratio test
    does not find significant gets the note of
    :func:`~fogts.startup.thermal_identification.significance_note` (the verdict says it, so
    no warning; the note warns when the saved model is reused).  ``calibration``
    adds further runs (same sample rate and units; for example cold starts at other ambient
    temperatures) to the fit: one warm-up determines only the combinations of the six
    coefficients along its own (T, ΔT) path, and several ambients make the model hold
    between them.  A fitted model is subtracted only when the likelihood-ratio test finds
    it significant, unless ``apply="always"``; a given one always is.  ``measurement_noise``
    is the Kalman H of the gyro rate's EMD rest, in (rate unit)^2, or ``"estimate"``; the
    temperature's is always estimated.

    Raises
    ------
    DataError
        The run has no temperature, or a bad option.

    Warns
    -----
    UnidentifiableTermWarning
        The fitted coefficients are not separately identified, or the given model was saved
        with that note.

    Examples
    --------
    >>> from fogts.startup.simulator import simulate_startup
    >>> sim = simulate_startup(duration_s=1800, rng=4)
    >>> res = startup_compensation(sim.run, emd=False)
    >>> res.after.value < res.before.value
    True
    """
    if not isinstance(run, Run):
        raise DataError(f"run must be a fogts Run, got {type(run).__name__}")
    if apply not in APPLY_RULES:
        raise DataError(f"apply must be one of {', '.join(map(repr, APPLY_RULES))}, "
                        f"got {apply!r}")
    # checked before the fit, which takes seconds and may warn before a late error
    from fogts.startup.kalman.api import MODEL_CHOICES

    check_choice("arma_model", arma_model, MODEL_CHOICES)
    average_s = check_positive("average_s", average_s)
    if dT_smoothing_s is not None:
        dT_smoothing_s = check_positive("dT_smoothing_s", dT_smoothing_s)
    require_temperature(run, hint=_COLUMN_HINT)
    gyro = run.axis(axis)
    name = axis if isinstance(axis, str) else run.axes[int(axis)]
    fs = run.fs_hz
    notes: list[str] = []
    significance = None
    out_of_sample = None
    if model is None:
        prepare = partial(_prepare_fit_run, axis=axis, emd=emd, arma_model=arma_model,
                          measurement_noise=measurement_noise)
        prep = prepare(run)
        model, fit_notes = _fit_on_runs(run, prep, calibration, prepare, terms=terms,
                                        dT_smoothing_s=dT_smoothing_s, errors=errors)
        notes = [*prep.notes, *fit_notes]
        significance = thermal_significance(gyro, run.temperature, fs_hz=fs, terms=terms,
                                            dT_smoothing_s=dT_smoothing_s)
        note = identification_note(model, significance.significant)
        if note is not None:
            warnings.warn(note, UnidentifiableTermWarning, stacklevel=2)
        else:  # the verdict says it here; the note keeps the model from silent reuse
            note = significance_note(significance)
        if note is not None:
            model = replace(model, identification_note=note)
        if significance.significant:
            out_of_sample, cv_note = _cross_validate(
                [run, *calibration], axis, terms=terms, dT_smoothing_s=dT_smoothing_s,
                errors=errors, average_s=average_s)
            notes += cv_note
    elif not isinstance(model, ThermalModel):
        raise DataError(f"model must be a ThermalModel or None, got {type(model).__name__}")
    else:
        reuse = reuse_warning(model)
        if reuse is not None:
            warnings.warn(reuse, UnidentifiableTermWarning, stacklevel=2)
        prep = _FitInput(gyro, np.asarray(run.temperature, dtype=float), None, None, None, "", [])
    applied = significance is None or significance.significant or apply == "always"
    comp = run
    if applied:
        comp = compensate(replace(run, temperature=prep.temp), model, axis=axis)
        comp = replace(comp, temperature=run.temperature)
    comp_rate = comp.axis(axis)
    before = bias_stability(gyro, fs_hz=fs, average_s=average_s, units=run.units)
    after = bias_stability(comp_rate, fs_hz=fs, average_s=average_s, units=run.units)
    return StartupCompensation(run=comp, model=model, gyro_split=prep.gyro_split,
                               temperature_split=prep.temp_split, kalman=prep.kalman,
                               arma_model=prep.arma, gyro_used=np.asarray(prep.gyro),
                               temperature_used=np.asarray(prep.temp), raw_rate=gyro,
                               before=before, after=after, axis=name, notes=tuple(notes),
                               significance=significance, out_of_sample=out_of_sample,
                               applied=applied)


# --------------------------------------------------------------------------- steps 1-5


@dataclass
class _FitInput:
    """The gyro and temperature series of one run to fit, and how they were obtained."""

    gyro: FloatArray
    temp: FloatArray
    gyro_split: TrendSplit | None
    temp_split: TrendSplit | None
    kalman: KalmanResult | None
    arma: str
    notes: list[str]


def _emd_kalman(x: FloatArray, fs: float, arma_model: str, measurement_noise: Any, series: str
                ) -> tuple[TrendSplit, KalmanResult | None, str, FloatArray]:
    """Steps 1-4 on one series (named ``series`` in warnings): EMD, ARMA and Kalman of the rest."""
    from fogts.startup.emd import separate_trend
    from fogts.startup.kalman import arma_kalman, resolve_arma_model

    split = separate_trend(x, fs_hz=fs)
    rest = np.asarray(split.rest, dtype=float)
    if split.k == 1 or float(np.ptp(rest)) == 0.0:
        return split, None, "", np.asarray(split.trend, dtype=float)
    fit = resolve_arma_model(rest, arma_model, series=f"ARMA model of the {series}'s EMD rest")
    kal = arma_kalman(rest, fit, measurement_noise=measurement_noise)
    name = str(getattr(fit, "name", kal.model))
    return split, kal, name, np.asarray(split.trend, dtype=float) + np.asarray(kal.filtered)


def _prepare_fit_run(run: Run, axis: int | str, *, emd: bool, arma_model: str,
                     measurement_noise: Any) -> _FitInput:
    """Steps 1-5 on one run: the gyro and temperature series to fit."""
    require_temperature(run, hint=_COLUMN_HINT)
    gyro = run.axis(axis)
    temp = np.asarray(run.temperature, dtype=float)
    if not emd:
        return _FitInput(gyro, temp, None, None, None, "", [])
    notes: list[str] = []
    gsplit, kal, arma_name, gyro_used = _emd_kalman(gyro, run.fs_hz, arma_model,
                                                    measurement_noise, "gyro rate")
    if kal is not None:
        notes.extend(kal.notes)
    tsplit = None
    temp_used = temp
    if float(np.ptp(temp)) > 0:
        try:
            tsplit, _, _, temp_used = _emd_kalman(  # a given variance is in (rate unit)^2
                temp, run.fs_hz, arma_model, "estimate", "temperature")
        except (InsufficientDataError, ModelFitError) as exc:
            from fogts.startup.emd import separate_trend

            tsplit = separate_trend(temp, fs_hz=run.fs_hz)
            temp_used = np.asarray(tsplit.trend, dtype=float)
            notes.append(f"temperature rest not Kalman-filtered ({exc}); used its EMD trend")
    else:
        notes.append("the temperature is constant: no EMD of the temperature")
    return _FitInput(gyro_used, temp_used, gsplit, tsplit, kal, arma_name, notes)


# --------------------------------------------------------------------------- step 8


def _cross_validate(runs: Sequence[Run], axis: int | str, *, terms: Sequence[str],
                    dT_smoothing_s: float | None, errors: ErrorModel, average_s: float
                    ) -> tuple[ThermalCrossValidation | None, list[str]]:
    """The out-of-sample gain on the raw rate of ``runs`` (a note instead when the record
    is too short for the time blocks)."""
    first = runs[0]
    try:
        cv = thermal_cross_validation(
            [(r.axis(axis), r.temperature) for r in runs], fs_hz=first.fs_hz,
            units=first.units, terms=terms, dT_smoothing_s=dT_smoothing_s, errors=errors,
            average_s=average_s, labels=[str(r.source).replace("\\", "/").rsplit("/", 1)[-1]
                                         for r in runs])
    except InsufficientDataError as exc:
        return None, [f"out-of-sample gain not measured: {exc}"]
    return cv, []


# --------------------------------------------------------------------------- step 6


def _fit_on_runs(run: Run, prep: _FitInput, calibration: Sequence[Run],
                 prepare: Callable[[Run], _FitInput], *, terms: Sequence[str],
                 dT_smoothing_s: float | None, errors: ErrorModel
                 ) -> tuple[ThermalModel, list[str]]:
    """Fit the thermal model to the prepared run and the calibration runs (each prepared with
    ``prepare``; ΔT computed run by run), with the reference temperature of the run."""
    fs = run.fs_hz
    gyros, temps, rates = [prep.gyro], [prep.temp], [
        temperature_rate(prep.temp, fs_hz=fs, smoothing_s=dT_smoothing_s)]
    for i, extra in enumerate(calibration):
        check_calibration_run(i, extra, run)
        more = prepare(extra)
        gyros.append(more.gyro)
        temps.append(more.temp)
        rates.append(temperature_rate(more.temp, fs_hz=fs, smoothing_s=dT_smoothing_s))
    notes = ([f"thermal model fitted on {1 + len(calibration)} runs (ΔT computed run by run)"]
             if calibration else [])
    tail = max(1, prep.gyro.size // 20)
    model = fit_thermal(np.concatenate(gyros), np.concatenate(temps), fs_hz=fs, terms=terms,
                        dT_smoothing_s=dT_smoothing_s, units=run.units, errors=errors,
                        temperature_rate_degC_s=np.concatenate(rates),
                        t_ref_degC=float(np.mean(prep.temp[-tail:])))
    X = design_matrix(np.concatenate(temps), np.concatenate(rates), model.terms)
    return replace(model, collinearity=collinearity(X, model.terms)), notes
