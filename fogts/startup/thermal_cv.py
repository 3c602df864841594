"""Out-of-sample bias-stability gain of the thermal model: cross-validation on held-out
runs or on contiguous time blocks.

An in-sample bias stability "before / after" rewards a model for absorbing whatever drift
its smooth regressors can follow.  Here the model is fitted without the part it is judged
on (Arlot & Celisse, "A survey of cross-validation procedures for model selection",
Statistics Surveys 4, 40-79, 2010, §8.1 on dependent data):

* **held-out runs** (two runs or more, e.g. cold starts at several ambients): each run in
  turn is compensated by the model fitted on the others, which is how a calibrated model is
  used;
* **time blocks** (one run): the record is cut into ``k`` contiguous blocks; each block is
  compensated by the model fitted on the other blocks, less a guard band of ``guard_s``
  on each side of the held-out block (the h-block scheme of Burman, Chow & Nolan,
  Biometrika 81(2), 351-358, 1994), so that the autocorrelated drift next to the block
  does not leak into its fit.  A warm-up is monotone in temperature, so a held-out block
  whose temperatures lie outside those of the training blocks asks the model to
  extrapolate beyond anything it saw: such a fold is reported but not scored.

Blocks of equal time put a warm-up that is short against the record in the first block
alone, which extrapolates: the scored blocks then see only the plateau and test nothing of
the temperature model.  Blocks are therefore cut at equal shares of the progress
``(t / duration + v(t) / v(duration)) / 2``, ``v(t)`` the temperature travel up to ``t``
(the integral of the smoothed ``|ΔT|``): half the blocks follow the temperature change, so
the warm-up is split into blocks whose temperatures lie between those of their neighbours
(interpolation, scored), and a temperature cycling evenly gives blocks of equal time.  Roberts et al.
("Cross-validation strategies for data with temporal, spatial, hierarchical, or
phylogenetic structure", Ecography 40, 913-929, 2017, §"Blocking and extrapolation")
recommend blocks that keep the held-out predictors within the training ones.  Equal time
blocks are used when the temperature is constant or a block would be shorter than two
bias-stability windows.

Coverage
--------
The gain measures the model only over the temperatures (and ΔT) of the scored folds.  When
those span less than :data:`MIN_COVERAGE` of the range the model was fitted on, in T or in
ΔT, the test does not cover the temperature change (:attr:`ThermalCrossValidation.covers_fit`
is False) and every text says so beside the figure.  Half, not all: the first block of a
monotone warm-up always extrapolates, so a single run never covers its lowest temperatures.

The folds fit the raw rate with the error model of the main fit: an EMD or Kalman
pre-filter of a run sees all of it, held-out part included.  Each fold's score is the bias
stability (:func:`~fogts.startup.compensation.bias_stability`) of the held-out raw rate
divided by that of the held-out rate minus the fold model's drift.

Interval
--------
The gain is the geometric mean of the scored folds' ratios, with a Student-t interval on
their logarithms (``k - 1`` degrees of freedom).  The log makes a ratio's sampling
distribution nearly symmetric; the t quantile allows for the few folds; a bootstrap over
three to five folds would have too few distinct resamples to give a usable percentile
interval.  The folds share training data, so they are not independent and no unbiased
estimate of the variance of a cross-validated score exists (Bengio & Grandvalet, JMLR 5,
1089-1105, 2004): the interval is approximate, and if anything too narrow.
"""

from __future__ import annotations

import math
import warnings
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
import pandas as pd
import scipy.stats

from fogts._typing import FloatArray, IntArray
from fogts._validate import check_fraction, check_int, check_positive, finite_or_none
from fogts.errors import DataError, InsufficientDataError
from fogts.startup.compensation import bias_stability
from fogts.startup.thermal_fit import fit_thermal
from fogts.startup.thermal_model import DEFAULT_DT_SMOOTHING_S, ErrorModel, temperature_rate

__all__ = ["DEFAULT_BLOCKS", "MIN_COVERAGE", "CvFold", "ThermalCrossValidation", "thermal_cross_validation"]

#: Contiguous time blocks of a single run.
DEFAULT_BLOCKS = 5
#: A held-out block extrapolates when its temperatures leave the training range by more
#: than this share of the training span.
EXTRAPOLATION_TOL = 0.05
#: The scored folds test the temperature model when they span at least this share of the
#: fitted temperature range and of the fitted ΔT range.
MIN_COVERAGE = 0.5


@dataclass(frozen=True)
class CvFold:
    """One held-out part: a run or a time block.

    Its fold model is fitted without this part (and, for a block, without the guard bands
    beside it) and judged on it alone: :attr:`ratio` above 1 means the compensation helped
    where it was not fitted.

    Attributes
    ----------
    label : str
        ``"block 1 (0-720 s)"`` or the held-out run's name.
    before, after : float
        Bias stability (deg/h) of the held-out raw rate and of it compensated by the fold
        model.
    temperature_degC, train_temperature_degC : tuple of float
        Temperature range of the held-out part and of the data the fold was fitted on.
    scored : bool
        False when the held-out block extrapolates (time blocks only).
    dT_degC_s : tuple of float
        ΔT range (°C/s) of the held-out part.
    """

    label: str
    before: float
    after: float
    temperature_degC: tuple[float, float]
    train_temperature_degC: tuple[float, float]
    scored: bool = True
    dT_degC_s: tuple[float, float] = (math.nan, math.nan)

    @property
    def ratio(self) -> float:
        """``before / after``."""
        return self.before / self.after if self.after > 0 else math.inf

    def to_dict(self) -> dict[str, Any]:
        return {"label": self.label, "before": self.before, "after": self.after,
                "ratio": self.ratio, "scored": self.scored,
                "temperature_degC": list(self.temperature_degC),
                "train_temperature_degC": list(self.train_temperature_degC),
                "dT_degC_s": list(self.dT_degC_s)}


@dataclass(frozen=True)
class ThermalCrossValidation:
    """Out-of-sample bias-stability gain of the thermal model (:func:`thermal_cross_validation`).

    Two or more runs are cross-validated by holding out one run at a time, a single run by
    holding out contiguous time blocks; a block that would need the model to extrapolate in
    temperature is not scored.

    Attributes
    ----------
    scheme : str
        ``"held-out runs"`` or ``"time blocks"``.
    folds : tuple of CvFold
        Every held-out part, scored or not, in the order of the runs or blocks.
    ratio : float
        Geometric mean of the scored folds' before/after ratios (NaN when none is scored).
    low, high : float
        Its ``confidence`` interval (NaN with fewer than two scored folds).
    confidence : float
    average_s : float
        Averaging time of the bias stability.
    guard_s : float
        Guard band each side of a held-out block (0 for held-out runs).
    fitted_temperature_degC, fitted_dT_degC_s : tuple of float
        T and ΔT ranges of all the data (what the model is fitted on).
    """

    scheme: str
    folds: tuple[CvFold, ...]
    ratio: float
    low: float
    high: float
    confidence: float
    average_s: float
    guard_s: float
    fitted_temperature_degC: tuple[float, float] = (math.nan, math.nan)
    fitted_dT_degC_s: tuple[float, float] = (math.nan, math.nan)

    @property
    def n_scored(self) -> int:
        return sum(f.scored for f in self.folds)

    def scored_range(self, quantity: str) -> tuple[float, float]:
        """Range of ``"temperature"`` (°C) or ``"dT"`` (°C/s) over the scored folds."""
        spans = [f.temperature_degC if quantity == "temperature" else f.dT_degC_s
                 for f in self.folds if f.scored]
        if not spans:
            return (math.nan, math.nan)
        return (min(a for a, _ in spans), max(b for _, b in spans))

    def coverage(self, quantity: str) -> float:
        """Share of the fitted range of ``quantity`` spanned by the scored folds (1 when the
        fitted range is empty or unknown, 0 with no scored fold)."""
        lo, hi = (self.fitted_temperature_degC if quantity == "temperature"
                  else self.fitted_dT_degC_s)
        if not hi - lo > 0:
            return 1.0
        a, b = self.scored_range(quantity)
        return float(min(b, hi) - max(a, lo)) / (hi - lo) if b >= a else 0.0

    @property
    def covers_fit(self) -> bool:
        """The scored folds span at least :data:`MIN_COVERAGE` of the fitted T and ΔT
        ranges: the gain tests the temperature model, not only a plateau."""
        return (self.n_scored > 0 and self.coverage("temperature") >= MIN_COVERAGE
                and self.coverage("dT") >= MIN_COVERAGE)

    def coverage_text(self) -> str:
        """``""`` when :attr:`covers_fit`, else why the figure does not test the model:
        ``"not tested over the warm-up: the scored folds span 45.05-45.83 °C of the
        20-45.83 °C fitted"``."""
        if self.covers_fit:
            return ""
        if self.n_scored == 0:
            return "not tested: no fold is scored"
        if self.coverage("temperature") < MIN_COVERAGE:
            (a, b), (lo, hi), unit = (self.scored_range("temperature"),
                                      self.fitted_temperature_degC, "°C")
        else:
            (a, b), (lo, hi), unit = self.scored_range("dT"), self.fitted_dT_degC_s, "°C/s"
        what = "" if unit == "°C" else "ΔT "
        return (f"not tested over the warm-up: the scored folds span {what}{a:.4g}-{b:.4g} "
                f"{unit} of the {lo:.4g}-{hi:.4g} {unit} fitted (less than "
                f"{100 * MIN_COVERAGE:g} %)")

    def to_dict(self) -> dict[str, Any]:
        return {"scheme": self.scheme, "improvement": finite_or_none(self.ratio),
                "low": finite_or_none(self.low), "high": finite_or_none(self.high),
                "confidence": self.confidence, "n_folds": len(self.folds),
                "n_scored": self.n_scored, "average_s": self.average_s,
                "guard_s": self.guard_s,
                "interval": "Student t on the log ratios of the scored folds",
                "fitted_temperature_degC": list(self.fitted_temperature_degC),
                "scored_temperature_degC": [finite_or_none(v) for v in
                                            self.scored_range("temperature")],
                "fitted_dT_degC_s": list(self.fitted_dT_degC_s),
                "scored_dT_degC_s": [finite_or_none(v) for v in self.scored_range("dT")],
                "coverage": {"temperature": self.coverage("temperature"),
                             "dT": self.coverage("dT"), "min": MIN_COVERAGE},
                "covers_fit": self.covers_fit,
                "folds": [f.to_dict() for f in self.folds]}

    def to_frame(self) -> pd.DataFrame:
        """One row per fold."""
        return pd.DataFrame([{k: v for k, v in f.to_dict().items()
                              if "_degC" not in k} for f in self.folds])

    def claim_gap(self) -> str:
        """``""`` when the gain supports an improvement claim, else why not, after "in sample
        only: ".  A claim needs scored folds that cover the fitted ranges and a gain whose
        interval lies above 1: a point estimate above 1 with an interval reaching below it
        (1.41x [0.73, 2.76]) is not evidence that the model improves data it was not
        fitted on, and one scored fold gives no interval."""
        if not self.covers_fit:
            return f"out of sample {self.coverage_text()}"
        if not self.ratio > 1.0:
            return f"out of sample it is {self.ratio:.3g}x, no better"
        if not math.isfinite(self.low):
            return f"out of sample {self.ratio:.3g}x from one scored fold, without an interval"
        if not self.low > 1.0:
            return f"out of sample {self.ratio:.3g}x, but its {self.interval_text()} reaches 1"
        return ""

    def interval_text(self) -> str:
        """``"95 % interval [1.0, 1.4]"``, or ``""`` without an interval."""
        if not math.isfinite(self.low):
            return ""
        return f"{100 * self.confidence:g} % interval [{self.low:.3g}, {self.high:.3g}]"

    def gain_text(self) -> str:
        """The gain in a few words: ``"1.2x, 95 % interval [1.0, 1.4]"``,
        ``"1.2x, one fold"`` or ``"not measured"``, followed by :meth:`coverage_text`
        when the scored folds do not cover the fitted range."""
        if self.n_scored == 0:
            return "not measured"
        gap = self.coverage_text()
        return (f"{self.ratio:.3g}x, " + (self.interval_text() or "one fold")
                + (f"; {gap}" if gap else ""))

    def summary(self) -> str:
        """``"out of sample (5 time blocks ...): 1.2x [1.0, 1.4] (95 %, ...)"``."""
        n = len(self.folds)
        head = (f"out of sample ({n} {self.scheme}, each compensated by the model fitted on "
                f"the others")
        head += f", {self.guard_s:g} s guard bands)" if self.guard_s > 0 else ")"
        if self.n_scored == 0:
            text = f"{head}: not measured"
        elif math.isfinite(self.low):
            text = (f"{head}: {self.ratio:.3g}x [{self.low:.3g}, {self.high:.3g}] "
                    f"({100 * self.confidence:g} % t interval over {self.n_scored} folds)")
        else:
            text = f"{head}: {self.ratio:.3g}x (one fold scored: no interval)"
        gap = self.coverage_text()
        if gap and self.n_scored:
            text += f"; {gap}"
        text += "; folds " + ", ".join(f"{f.ratio:.3g}x" + ("" if f.scored else "*")
                                       for f in self.folds)
        skipped = [f for f in self.folds if not f.scored]
        if skipped:
            text += ("; * not scored: the held-out temperatures leave the training range ("
                     + "; ".join(f"{f.label}: {f.temperature_degC[0]:.3g}-"
                                 f"{f.temperature_degC[1]:.3g} °C against "
                                 f"{f.train_temperature_degC[0]:.3g}-"
                                 f"{f.train_temperature_degC[1]:.3g} °C" for f in skipped)
                     + "); fit several cold starts (--calibration) to validate the warm-up "
                       "on held-out runs")
        return text


# Long only by its docstring: every option is documented.
def thermal_cross_validation(
    runs: Sequence[tuple[Any, Any]],
    *,
    fs_hz: float,
    units: str = "deg/h",
    blocks: int = DEFAULT_BLOCKS,
    guard_s: float | None = None,
    terms: Sequence[str] = ("T*dT", "T2", "T", "dT2", "dT", "1"),
    dT_smoothing_s: float | None = DEFAULT_DT_SMOOTHING_S,
    errors: ErrorModel = "ar",
    average_s: float = 10.0,
    confidence: float = 0.95,
    labels: Sequence[str] | None = None,
) -> ThermalCrossValidation:
    """Cross-validated bias-stability gain of the thermal drift model.

    Parameters
    ----------
    runs : sequence of (rate, temperature)
        One pair per run, sample by sample (rate in ``units``, temperature in °C).  Two or
        more: held-out runs; one: ``blocks`` contiguous time blocks.
    fs_hz : float
        Sample rate (all runs).
    units : str
        Rate unit.
    blocks : int
        Number of time blocks of a single run (at least 3).
    guard_s : float, optional
        Guard band dropped from the training data each side of a held-out block (default:
        ``dT_smoothing_s``, or ``average_s`` without smoothing).
    terms, dT_smoothing_s, errors
        As :func:`~fogts.startup.thermal_fit.fit_thermal`.
    average_s : float
        Averaging time of the bias stability.
    confidence : float
        Level of the interval.
    labels : sequence of str, optional
        Names of the runs.

    Returns
    -------
    ThermalCrossValidation

    Raises
    ------
    DataError
        Bad argument (fewer than 3 blocks, mismatched lengths).
    InsufficientDataError
        A block is shorter than two bias-stability windows.

    Examples
    --------
    >>> from fogts.startup.simulator import simulate_startup
    >>> runs = [simulate_startup(duration_s=3600, ambient_degC=a, rng=s).run
    ...         for a, s in ((15.0, 1), (20.0, 2), (25.0, 3))]
    >>> cv = thermal_cross_validation([(r.rate, r.temperature) for r in runs], fs_hz=1.0)
    >>> cv.scheme, cv.n_scored, cv.ratio > 2
    ('held-out runs', 3, True)
    """
    fs = check_positive("fs_hz", fs_hz)
    confidence = check_fraction("confidence", confidence)
    blocks = check_int("blocks", blocks, minimum=3)
    series = [_pair(i, r, t) for i, (r, t) in enumerate(runs)]
    if not series:
        raise DataError("runs must hold at least one (rate, temperature) pair")
    rates = [temperature_rate(t, fs_hz=fs, smoothing_s=dT_smoothing_s) for _, t in series]
    fit = {"terms": terms, "dT_smoothing_s": dT_smoothing_s, "errors": errors, "units": units}
    if len(series) > 1:
        names = list(labels) if labels is not None else [f"run {i + 1}" for i in
                                                         range(len(series))]
        folds = [_run_fold(series, rates, i, names[i], fs, fit, average_s)
                 for i in range(len(series))]
        scheme, guard = "held-out runs", 0.0
    else:
        guard = float(guard_s) if guard_s is not None else float(dT_smoothing_s or average_s)
        guard = check_positive("guard_s", guard, allow_zero=True)
        folds = _block_folds(*series[0], rates[0], blocks, round(guard * fs), fs, fit,
                             average_s)
        scheme = "time blocks"
    ratio, low, high = _log_t_interval([f.ratio for f in folds if f.scored], confidence)
    return ThermalCrossValidation(
        scheme=scheme, folds=tuple(folds), ratio=ratio, low=low, high=high,
        confidence=confidence, average_s=average_s, guard_s=guard,
        fitted_temperature_degC=_range(np.concatenate([t for _, t in series])),
        fitted_dT_degC_s=_range(np.concatenate(rates)))


def _pair(i: int, rate: Any, temperature: Any) -> tuple[FloatArray, FloatArray]:
    r = np.asarray(rate, dtype=np.float64).ravel()
    t = np.asarray(temperature, dtype=np.float64).ravel()
    if r.shape != t.shape:
        raise DataError(f"runs[{i}]: rate and temperature must have the same length, got "
                        f"{r.size} and {t.size}")
    return r, t


def _fitted_drift(y: FloatArray, temp: FloatArray, dtemp: FloatArray, train: Any,
                  fs: float, fit: dict[str, Any], temp_eval: FloatArray,
                  dtemp_eval: FloatArray) -> FloatArray:
    """Fit on the training samples and predict the drift at the evaluation samples."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # a fold's dropped terms repeat the main fit's
        model = fit_thermal(y[train], temp[train], fs_hz=fs, temperature_rate_degC_s=dtemp[train],
                            **fit)
    return np.asarray(model.predict(temp_eval, fs_hz=fs, temperature_rate_degC_s=dtemp_eval),
                      dtype=np.float64)


def _stability(x: FloatArray, fs: float, units: str, average_s: float) -> float:
    return bias_stability(x, fs_hz=fs, average_s=average_s, units=units).value


def _run_fold(series: list[tuple[FloatArray, FloatArray]], rates: list[FloatArray], i: int,
              label: str, fs: float, fit: dict[str, Any], average_s: float) -> CvFold:
    """Run ``i`` compensated by the model fitted on the other runs."""
    others = [j for j in range(len(series)) if j != i]
    y = np.concatenate([series[j][0] for j in others])
    temp = np.concatenate([series[j][1] for j in others])
    dtemp = np.concatenate([rates[j] for j in others])
    held_y, held_t = series[i]
    drift = _fitted_drift(y, temp, dtemp, slice(None), fs, fit, held_t, rates[i])
    units = fit["units"]
    return CvFold(label=label, before=_stability(held_y, fs, units, average_s),
                  after=_stability(held_y - drift, fs, units, average_s),
                  temperature_degC=_range(held_t), train_temperature_degC=_range(temp),
                  dT_degC_s=_range(rates[i]))


def _block_folds(y: FloatArray, temp: FloatArray, dtemp: FloatArray, k: int, guard: int,
                 fs: float, fit: dict[str, Any], average_s: float) -> list[CvFold]:
    """Each of ``k`` contiguous blocks (:func:`_block_edges`) compensated by the model
    fitted on the rest, less ``guard`` samples each side of the block."""
    n = y.size
    edges = _block_edges(dtemp, k, 2 * round(average_s * fs))
    if int(np.min(np.diff(edges))) < 2 * round(average_s * fs):
        raise InsufficientDataError(
            f"{k} time blocks of a {n / fs:g} s record are shorter than two {average_s:g} s "
            "bias-stability windows; use fewer blocks or a longer record")
    folds = []
    for i in range(k):
        a, b = int(edges[i]), int(edges[i + 1])
        train = np.ones(n, dtype=bool)
        train[max(0, a - guard):b + guard] = False
        drift = _fitted_drift(y, temp, dtemp, train, fs, fit, temp[a:b], dtemp[a:b])
        held, trained = _range(temp[a:b]), _range(temp[train])
        tol = EXTRAPOLATION_TOL * (trained[1] - trained[0])
        inside = held[0] >= trained[0] - tol and held[1] <= trained[1] + tol
        folds.append(CvFold(
            label=f"block {i + 1} ({a / fs:g}-{b / fs:g} s)",
            before=_stability(y[a:b], fs, fit["units"], average_s),
            after=_stability(y[a:b] - drift, fs, fit["units"], average_s),
            temperature_degC=held, train_temperature_degC=trained, scored=inside,
            dT_degC_s=_range(dtemp[a:b])))
    return folds


def _block_edges(dtemp: FloatArray, k: int, min_len: int) -> IntArray:
    """Edges of ``k`` blocks at equal shares of ``(t / duration + v(t) / v(duration)) / 2``,
    ``v`` the temperature travel (cumulative ``|dtemp|``, module docstring); equal time when
    the temperature is constant or a block would be shorter than ``min_len`` samples."""
    n = dtemp.size
    equal = np.linspace(0, n, k + 1).round().astype(np.int64)
    travel = np.cumsum(np.abs(np.nan_to_num(dtemp)))
    if not travel[-1] > 0:
        return equal
    progress = 0.5 * np.arange(n) / max(n - 1, 1) + 0.5 * travel / travel[-1]
    edges = np.searchsorted(progress, np.arange(1, k) / k).astype(np.int64)
    edges = np.concatenate(([0], edges, [n]))
    return edges if int(np.min(np.diff(edges))) >= min_len else equal


def _range(t: FloatArray) -> tuple[float, float]:
    return (float(np.nanmin(t)), float(np.nanmax(t)))


def _log_t_interval(ratios: list[float], confidence: float) -> tuple[float, float, float]:
    """Geometric mean of ``ratios`` and its Student-t interval on the log scale."""
    logs = np.log(np.asarray([r for r in ratios if 0 < r < math.inf], dtype=np.float64))
    if logs.size == 0:
        return math.nan, math.nan, math.nan
    centre = float(np.mean(logs))
    if logs.size < 2:
        return math.exp(centre), math.nan, math.nan
    half = float(scipy.stats.t.ppf(0.5 + confidence / 2, logs.size - 1)
                 * np.std(logs, ddof=1) / math.sqrt(logs.size))
    return math.exp(centre), math.exp(centre - half), math.exp(centre + half)
