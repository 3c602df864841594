"""The one analysis chain behind ``fogts allan``, ``fogts select``, ``fogts batch`` and the
HTML report: read and check a recording, then per axis prepare -> Allan deviation ->
noise fit -> read-outs, and prepare -> ARMA selection.

The results' ``to_dict()`` is the JSON contract (DESIGN.md, "Contracts"): what
``fogts allan --json`` and ``fogts select --json`` write, and what ``fogts batch`` stores
per run under ``"allan"`` and ``"select"``.  Nothing here prints; the callers present.
"""

from __future__ import annotations

import warnings
from collections.abc import Sequence
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import TYPE_CHECKING, Any

from fogts.errors import FogtsWarning

if TYPE_CHECKING:
    import os

    from fogts.allan.api import TauSpec
    from fogts.allan.curve_input import CurveProvenance
    from fogts.allan.misfit import FitCheck
    from fogts.allan.noise import NoiseModel
    from fogts.allan.noise_compare import MethodComparison
    from fogts.allan.plausibility import PlausibilityReport
    from fogts.allan.readout import CurveReadout
    from fogts.allan.result import AllanResult
    from fogts.arma.select import Selection
    from fogts.io.run import Run
    from fogts.preprocess.hygiene import DataQuality
    from fogts.preprocess.prepare import Prepared

__all__ = ["AllanAnalysis", "AllanSettings", "AxisAllan", "AxisSelection", "InputColumns",
           "ReadSettings", "SelectSettings", "analyse_allan", "analyse_allan_axis",
           "analyse_curve", "analyse_selection", "load"]

_ALL_TERMS = ("Q", "N", "B", "K", "R")
_DEFAULT_CANDIDATES = ((1, 0), (2, 0), (3, 0), (1, 1), (2, 1))


# --------------------------------------------------------------------------- reading


@dataclass(frozen=True)
class InputColumns:
    """Which columns hold the rate, time and temperature, the sample rate and the rate unit
    (None: detect); ``rate_column`` may name several columns separated by commas.  Shared
    by :class:`ReadSettings` and :class:`fogts.batch.BatchOptions`."""

    rate_column: str | None = None
    time_column: str | None = None
    temperature_column: str | None = None
    fs_hz: float | None = None
    units: str | None = None
    topic: str | None = None
    input: str | None = None
    accel_units: str | None = None


@dataclass(frozen=True)
class ReadSettings(InputColumns):
    """How to read a recording: the columns, sample rate and unit (:class:`InputColumns`),
    the missing-value and gap policies (:func:`fogts.io.read_run`,
    :func:`fogts.preprocess.assess_run`)."""

    nan: str = "error"
    gaps: str = "warn"
    glitches: bool = True

    @property
    def rate_columns(self) -> str | list[str] | None:
        """``rate_column`` split at commas (one name stays a string)."""
        if not self.rate_column:
            return None
        parts = [c.strip() for c in self.rate_column.split(",") if c.strip()]
        return parts if len(parts) > 1 else parts[0]


def load(path: str | os.PathLike[str], settings: ReadSettings | None = None
         ) -> tuple[Run, DataQuality]:
    """Read ``path`` and check its hygiene; returns the Run (the longest regular segment
    with ``gaps="split"``) and its :class:`~fogts.preprocess.DataQuality`."""
    from fogts.io.reader import read_run
    from fogts.preprocess.hygiene import assess_run

    s = settings or ReadSettings()
    run = read_run(path, rate_column=s.rate_columns, time_column=s.time_column,
                   temperature_column=s.temperature_column, fs_hz=s.fs_hz, units=s.units,
                   nan=s.nan, topic=s.topic, input=s.input,
                   accel_units=s.accel_units)  # type: ignore[arg-type]
    return assess_run(run, gaps=s.gaps, glitches=s.glitches)  # type: ignore[arg-type]


# --------------------------------------------------------------------------- Allan


@dataclass(frozen=True)
class AllanSettings:
    """The Allan analysis of one axis: estimator, tau grid and confidence
    (:func:`fogts.allan_deviation`), the noise fit (:func:`fogts.fit_noise`; ``significance``
    None keeps every term; ``compare_methods``: further methods fitted beside ``method``,
    shown side by side in :attr:`AxisAllan.comparison`), optional preparation
    (:func:`fogts.prepare`: the data are analysed raw unless ``outliers``, ``detrend`` or
    ``decimate`` is given), the allantools cross-check and the thread count."""

    kind: str = "oadev"
    taus: TauSpec = "octave"
    confidence: float = 0.683
    terms: tuple[str, ...] = _ALL_TERMS
    method: str = "wls"
    compare_methods: tuple[str, ...] = ()
    significance: float | None = 0.05
    bias_correction: bool = False
    outliers: float | None = None
    detrend: int | None = None
    decimate: int | None = None
    check_allantools: bool = False
    workers: int | None = None
    fit_tau_min: float | None = None
    fit_tau_max: float | None = None

    @property
    def fit_range(self) -> tuple[float | None, float | None] | None:
        """The tau range of the noise fit (None: every point)."""
        if self.fit_tau_min is None and self.fit_tau_max is None:
            return None
        return (self.fit_tau_min, self.fit_tau_max)

    @property
    def prepares(self) -> bool:
        """Whether the data are prepared before the analysis."""
        return any(v is not None for v in (self.outliers, self.detrend, self.decimate))

    @property
    def reads_rate_after_curve(self) -> bool:
        """Whether :func:`analyse_allan_axis` reads the axis' rate again once its Allan curve
        is computed: preparing (and the outlier effect's second curve), the ML fit (chosen
        or compared) and the allantools check do; the other fits use the curve alone."""
        return (self.prepares or self.check_allantools
                or "ml" in (self.method, *self.compare_methods))


@dataclass(frozen=True)
class AxisAllan:
    """The Allan analysis of one axis.

    Attributes
    ----------
    result : AllanResult
        The deviations with their confidence intervals.
    model : NoiseModel or None
        The IEEE-952 fit (None for estimators the terms are not defined for).
    readout : CurveReadout
        Minimum, regions, dominant terms and slope read-offs.
    prepared : Prepared or None
        The preparation, when one was asked for.
    check : dict or None
        The allantools cross-check (:func:`fogts.allan.peer.allantools_check`).
    plausibility : PlausibilityReport or None
        N and B against the range of real gyros.
    outliers_effect : dict or None
        With ``outliers``: how many samples were replaced and the change in N.
    fit_check : FitCheck or None
        Whether the fitted model lies within the points' intervals
        (:func:`fogts.allan.misfit.check_fit`), over the fit range.
    fit_range : (float or None, float or None) or None
        The tau range the noise terms were fitted over (None: every point).
    comparison : MethodComparison or None
        With ``AllanSettings.compare_methods``: every method's fit side by side, ``model``
        (the primary fit) first.
    """

    result: AllanResult
    model: NoiseModel | None
    readout: CurveReadout
    prepared: Prepared | None = None
    check: dict[str, Any] | None = None
    plausibility: PlausibilityReport | None = None
    outliers_effect: dict[str, Any] | None = None
    fit_check: FitCheck | None = None
    fit_range: tuple[float | None, float | None] | None = None
    comparison: MethodComparison | None = None

    @property
    def notes(self) -> list[str]:
        """The preparation steps and the outlier effect, as sentences."""
        lines = list(self.prepared.steps) if self.prepared is not None else []
        if self.outliers_effect is not None:
            lines.append(self.outliers_effect["text"])
        return lines

    def plausibility_warning(self, run: Run | CurveProvenance) -> str | None:
        """The warning to show when N and B are implausible, or could be in another unit
        than the assumed one (``run``: the recording or curve file read); else None."""
        p = self.plausibility
        if p is None or not (p.verdict == "implausible" or (run.units_assumed and p.ambiguous)):
            return None
        return f"{Path(run.source).name}: {self.result.axis}: {p.message}"

    def to_dict(self) -> dict[str, Any]:
        """One axis of the ``fogts allan`` JSON."""
        import numpy as np

        res, model = self.result, self.model
        points = res.to_dict()["points"]
        fit = model.curve(res.tau_s) if model is not None else np.full(len(points), np.nan)
        for p, f in zip(points, fit, strict=True):
            p["fit"] = float(f)
        out: dict[str, Any] = {
            "axis": res.axis, "kind": res.kind, "units": res.units,
            "confidence": res.confidence, "bias_corrected": res.bias_corrected,
            "points": points,
            "noise": model.noise_dict() if model is not None else {},
            "noise_si": ({t.name: model.in_units(t.name, "si") for t in model.terms}
                         if model is not None else {}),
            "noise_fit": ({k: v for k, v in model.to_dict().items() if k != "terms"}
                          if model is not None else
                          {"skipped": f"IEEE-952 terms are fitted to adev, oadev or totdev "
                                      f"curves only, not {res.kind}"}),
            "dropped": [d.to_dict() for d in res.dropped], "notes": list(res.notes),
            "preprocessing": self.prepared.to_dict() if self.prepared is not None else None,
        }
        if self.check is not None:
            out["allantools_check"] = self.check
        out["curve"] = self.readout.to_dict()
        if self.outliers_effect is not None:
            out["outliers_effect"] = self.outliers_effect
        if self.plausibility is not None:
            out["plausibility"] = self.plausibility.to_dict()
        if self.fit_check is not None:
            out["fit_check"] = self.fit_check.to_dict()
        if self.fit_range is not None:
            out["fit_range"] = list(self.fit_range)
        if self.comparison is not None:
            out["methods"] = self.comparison.to_dict()
        return out


@dataclass(frozen=True)
class AllanAnalysis:
    """The Allan analysis of the chosen axes of one recording."""

    run: Run
    quality: DataQuality
    axes: tuple[AxisAllan, ...] = field(default_factory=tuple)

    def to_dict(self) -> dict[str, Any]:
        """The ``fogts allan`` JSON of one file: the input, ``"axes"`` (one block per axis)
        and the data quality.  The top level also repeats the first axis' block: those keys
        are deprecated (listed under ``"deprecated"``) and will be removed in the next
        release; read ``axes[i]`` instead."""
        run = self.run
        blocks = [a.to_dict() for a in self.axes]
        first = blocks[0]
        return {
            "input": {"source": run.source, "n": run.n, "fs_hz": run.fs_hz,
                      "duration_s": run.duration_s, "units": run.units,
                      "units_source": run.units_source,
                      "axis": first["axis"], "axes": [b["axis"] for b in blocks],
                      "columns": list(run.columns)},
            "axes": blocks,
            "data_quality": self.quality.to_dict(),
            **first,
            "deprecated": {"fields": sorted(first),
                           "note": "these top-level fields repeat axes[0] and will be removed "
                                   "in the next release; read axes[i] instead"},
        }


def _fit(result: AllanResult, s: AllanSettings, series: Any = None,
         fs_hz: float | None = None) -> NoiseModel | None:
    from fogts.allan.noise import FITTABLE_KINDS, fit_noise

    if s.method == "ml" and series is not None and fs_hz is not None:
        return _fit_ml(result, s, series, fs_hz)
    if result.kind not in FITTABLE_KINDS:
        warnings.warn(f"noise terms are fitted to adev, oadev or totdev curves only; "
                      f"not fitted to {result.kind}", FogtsWarning, stacklevel=1)
        return None
    return fit_noise(result, terms=s.terms, method=s.method,  # type: ignore[arg-type]
                     confidence=s.confidence, significance=s.significance,
                     tau_range=s.fit_range)


def _fit_ml(result: AllanResult, s: AllanSettings, series: Any, fs_hz: float
            ) -> NoiseModel:
    """``method="ml"``: :func:`fogts.allan.ml.fit_noise_ml` on the (prepared) series, with
    the terms it models (Q, M and S are left out, with a warning)."""
    from fogts.allan.ml import ML_TERMS, fit_noise_ml
    from fogts.errors import DataError

    if s.fit_range is not None:
        raise DataError("fit_tau_min/fit_tau_max do not apply to method 'ml' (it fits "
                        "the record, not the curve); leave them out")
    terms = tuple(t for t in s.terms if t in ML_TERMS)
    left = [t for t in s.terms if t not in ML_TERMS]
    if left:
        warnings.warn(f"method 'ml' does not model {', '.join(left)}; fitted "
                      f"{', '.join(terms)}", FogtsWarning, stacklevel=2)
    return fit_noise_ml(series, fs_hz, units=result.units, axis=result.axis, terms=terms,
                        confidence=s.confidence)


def _allan(source: Any, s: AllanSettings, axis: int | None, units: str | None = None
           ) -> AllanResult:
    from fogts.allan.api import allan_deviation
    from fogts.allan.result import AllanResult

    res = allan_deviation(source, kind=s.kind, taus=s.taus,  # type: ignore[arg-type]
                          confidence=s.confidence, axis=axis, workers=s.workers,
                          bias_correction=s.bias_correction, units=units)
    assert isinstance(res, AllanResult)
    return res


def _plausibility(model: NoiseModel, units: str) -> PlausibilityReport:
    from fogts.allan.plausibility import check_plausibility

    return check_plausibility(*(model[t].value if t in model.names else None for t in "NB"),
                              units=units)


def analyse_allan_axis(run: Run, axis: int, settings: AllanSettings | None = None
                       ) -> AxisAllan:
    """Prepare (if asked), compute the deviations, fit the noise terms, read the curve and
    check the terms' plausibility for axis ``axis`` of ``run``."""
    from fogts.allan.noise import curve_named
    from fogts.allan.peer import allantools_check
    from fogts.preprocess.prepare import prepare

    s = settings or AllanSettings()
    prepared = None
    if s.prepares:
        prepared = prepare(run, axis=axis, outliers=s.outliers, detrend=s.detrend,
                           decimate=s.decimate, stationarity=False)
        res = _allan(prepared, s, None, run.unit_of(axis))
        series, fs_hz = prepared.x, prepared.fs_hz
    else:
        res = _allan(run, s, axis, run.unit_of(axis))
        series, fs_hz = run.axis(axis), run.fs_hz
    with curve_named(f"the Allan curve of axis {run.axes[axis]!r} of {run.source}"):
        done = analyse_curve(res, s, series=series, fs_hz=fs_hz, units=run.units)
    check = (allantools_check(prepared.x if prepared is not None else run.axis(axis), res)
             if s.check_allantools else None)
    effect = (_outlier_effect(run, axis, prepared, done.model, s)
              if prepared is not None and prepared.outliers is not None else None)
    return replace(done, prepared=prepared, check=check, outliers_effect=effect)


def analyse_curve(result: AllanResult, settings: AllanSettings | None = None, *,
                  series: Any = None, fs_hz: float | None = None, units: str | None = None
                  ) -> AxisAllan:
    """Fit the noise terms to one Allan curve (``series``, ``fs_hz``: the record, which only
    method ``"ml"`` reads), read the curve, check the terms' plausibility in ``units``
    (default: the curve's) and the fit against the points' intervals."""
    s = settings or AllanSettings()
    model = _fit(result, s, series, fs_hz)
    return AxisAllan(result=result, model=model, readout=result.readout(model),
                     plausibility=_plausibility(model, units or result.units)
                     if model is not None and model.quantity == "rate" else None,
                     fit_range=s.fit_range,
                     comparison=_compare(result, s, series, fs_hz, model),
                     fit_check=_fit_check(result if s.fit_range is None
                                          else result.within(*s.fit_range), model))


def _compare(result: AllanResult, s: AllanSettings, series: Any, fs_hz: float | None,
             model: NoiseModel | None) -> MethodComparison | None:
    """The fits by ``s.compare_methods`` beside ``model``; their warnings say which method
    they come from."""
    import re

    from fogts.allan.noise_compare import side_by_side

    if not s.compare_methods or model is None:
        return None
    models = [model]
    for method in s.compare_methods:
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            other = _fit(result, replace(s, method=method), series, fs_hz)
        for w in caught:  # "method 'gmwm': noise term Q ...", not "...: axis 'x': ..."
            text = re.sub(r"^axis '[^']*': ", "", str(w.message))
            tag = f"method {method!r}"
            warnings.warn(text if text.startswith(tag) else f"{tag}: {text}", w.category,
                          stacklevel=2)
        if other is not None:  # None: a curve fit of a kind without terms (warned)
            models.append(other)
    return side_by_side(models) if len(models) > 1 else None


def _fit_check(result: AllanResult, model: NoiseModel | None) -> FitCheck | None:
    """The misfit verdict (a warning when the model misses the curve)."""
    from fogts.allan.misfit import check_fit

    if model is None or not result.has_ci:
        return None
    verdict = check_fit(result, model)
    if not verdict.ok:
        warnings.warn(f"axis {result.axis!r}: {verdict.verdict}", FogtsWarning, stacklevel=2)
    return verdict


def _outlier_effect(run: Run, axis: int, prepared: Prepared, model: NoiseModel | None,
                    s: AllanSettings) -> dict[str, Any]:
    """How many samples ``outliers`` replaced and what that did to N (the same analysis of
    the data without the replacement)."""
    from fogts.preprocess.prepare import prepare

    report = prepared.outliers
    assert report is not None
    share = report.count / max(prepared.n_input, 1)
    out: dict[str, Any] = {"replaced": report.count, "share": share,
                           "sigma_factor": report.sigma_factor}
    text = (f"outliers={report.sigma_factor:g}: replaced {report.count:,} of "
            f"{prepared.n_input:,} samples ({100 * share:.3g} %)")
    if model is None or "N" not in model.names:
        out["text"] = text
        return out
    if s.detrend is not None or s.decimate is not None:
        raw = _allan(prepare(run, axis=axis, outliers=None, detrend=s.detrend,
                             decimate=s.decimate, stationarity=False), s, None,
                     run.unit_of(axis))
    else:
        raw = _allan(run, s, axis, run.unit_of(axis))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # the unscreened fit's own warnings are not news
        raw_model = _fit(raw, s)
    assert raw_model is not None
    n_clean = model["N"].value
    n_raw = raw_model["N"].value if "N" in raw_model.names else float("nan")
    change = n_clean / n_raw - 1.0 if n_raw > 0 else float("nan")
    out.update({"N": n_clean, "N_unscreened": n_raw, "N_change": change})
    out["text"] = (f"{text}; N = {n_clean:.4g} {model['N'].unit} against {n_raw:.4g} without "
                   f"the replacement ({100 * change:+.1f} %)")
    return out


def analyse_allan(run: Run, quality: DataQuality, settings: AllanSettings | None = None, *,
                  axes: Sequence[int] | None = None) -> AllanAnalysis:
    """:func:`analyse_allan_axis` for each of ``axes`` (default: every axis)."""
    picks = range(run.n_axes) if axes is None else axes
    return AllanAnalysis(run=run, quality=quality,
                         axes=tuple(analyse_allan_axis(run, i, settings) for i in picks))


# --------------------------------------------------------------------------- ARMA


@dataclass(frozen=True)
class SelectSettings:
    """The ARMA analysis of one axis: preparation (:func:`fogts.prepare`; the mean is
    always removed), the candidates and the ranking criterion (:func:`fogts.select_arma`)."""

    outliers: float | None = None
    detrend: int | None = None
    decimate: int | None = None
    candidates: tuple[tuple[int, int], ...] = _DEFAULT_CANDIDATES
    criterion: str = "aic"
    stationarity: bool = True


@dataclass(frozen=True)
class AxisSelection:
    """The ARMA analysis of one axis: its preparation and the ranked candidates."""

    run: Run
    quality: DataQuality
    prepared: Prepared
    selection: Selection
    file: str

    def to_dict(self) -> dict[str, Any]:
        """The ``fogts select`` JSON."""
        payload = self.selection.to_dict()
        payload["input"] = {**payload["input"], "file": self.file,
                            "units_source": self.run.units_source}
        payload["data_quality"] = self.quality.to_dict()
        return payload


def analyse_selection(run: Run, quality: DataQuality, axis: int,
                      settings: SelectSettings | None = None, *, file: str | None = None
                      ) -> AxisSelection:
    """Prepare axis ``axis`` of ``run`` and select its ARMA model; ``file`` is the name the
    JSON gives the input (default: the run's source)."""
    from fogts.arma.select import select_arma
    from fogts.preprocess.prepare import prepare

    s = settings or SelectSettings()
    prepared = prepare(run, axis=axis, outliers=s.outliers, detrend=s.detrend,
                       decimate=s.decimate, stationarity=s.stationarity)
    sel = select_arma(prepared, candidates=s.candidates,
                      criterion=s.criterion)  # type: ignore[arg-type]
    return AxisSelection(run=run, quality=quality, prepared=prepared, selection=sel,
                         file=file if file is not None else run.source)
