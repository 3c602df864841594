"""Public entry point of the Allan analysis: :func:`allan_deviation`.

It takes a rate series in any of the forms fogts knows (ndarray, Series, DataFrame,
:class:`~fogts.io.run.Run`, :class:`~fogts.preprocess.prepare.Prepared`), builds the tau grid
(:mod:`fogts.allan.taus`), runs the phase-based estimator (:mod:`fogts.allan.estimators`)
and attaches noise identification, EDF and chi-squared intervals
(:mod:`fogts.allan.confidence`) to every point.
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass
from typing import Any, Literal

import numpy as np
import numpy.typing as npt
import pandas as pd

from fogts._typing import FloatArray, IntArray
from fogts._validate import check_choice, check_fraction, check_positive, to_float_array
from fogts.allan.bias import totdev_bias
from fogts.allan.confidence import confidence_table
from fogts.allan.estimators import ESTIMATORS, EstimatorOutput, estimate_from_angle
from fogts.allan.gradev import gradev
from fogts.allan.result import AllanResult, AllanResultSet
from fogts.allan.taus import KINDS, DroppedTau, Kind, TauGrid, tau_grid
from fogts.choices import INPUT_KINDS, InputKind
from fogts.errors import DataError
from fogts.io.run import Run
from fogts.preprocess.prepare import Prepared
from fogts.units import parse_sensor_unit

__all__ = ["allan_deviation"]

TauSpec = Literal["octave", "decade", "dense", "all"] | npt.ArrayLike


@dataclass(frozen=True)
class AxisSeries:
    """One axis to analyse."""

    y: FloatArray
    name: str
    angle: FloatArray | None = None  # the integral of y (n + 1 points), used as the phase


# Long only by its docstring: the public entry point documents every option.
def allan_deviation(
    x: Any,
    *,
    fs_hz: float | None = None,
    kind: Kind = "oadev",
    taus: TauSpec = "octave",
    confidence: float | None = 0.683,
    axis: int | str | None = None,
    units: str | None = None,
    per_decade: int = 20,
    workers: int | None = None,
    bias_correction: bool = False,
    input: InputKind = "rate",
) -> AllanResult | AllanResultSet:
    """Allan-family deviation of gyro rate data, with confidence intervals.

    The rate is integrated once to angle (phase) and differenced (NIST SP1065 eqs. 7, 11,
    14, 18, 20, 25 for adev, oadev, mdev, hdev, ohdev, totdev).  Each
    point carries the number of terms, the identified power-law noise type, its equivalent
    degrees of freedom and a chi-squared confidence interval (see
    :mod:`fogts.allan.confidence`).

    Parameters
    ----------
    x : ndarray, Series, DataFrame, Run or Prepared
        Rate data.  A 2-D array ``(n, k)``, a DataFrame (every column an axis) or a
        multi-axis Run gives one curve per axis unless ``axis`` picks one.  A Series or
        DataFrame is read as a Run (:func:`run_from_pandas`).
    fs_hz : float, optional
        Sample rate.  Required for ndarray input; a Series/DataFrame with a
        DatetimeIndex/TimedeltaIndex, a Run or a Prepared carry their own (``fs_hz``
        overrides it).
    kind : {"oadev", "adev", "mdev", "hdev", "ohdev", "totdev"}
        Estimator; the overlapping Allan deviation is the default.
    taus : {"octave", "decade", "dense", "all"} or array_like of float
        Tau grid (see :func:`fogts.allan.taus.tau_grid`); an array gives taus in seconds.
        Taus that cannot be computed are listed in ``result.dropped``.
    confidence : float or None
        Confidence level of the intervals (default 0.683, i.e. 1 sigma); None skips the
        noise identification and intervals (``ci_low``, ``ci_high``, ``edf`` are NaN).
    axis : int or str, optional
        Analyse this axis only (name or position).
    units : str, optional
        Rate unit of array/Series/DataFrame input (default ``deg/h``); a Run or Prepared
        carries its own.
    per_decade : int
        Points per decade of the ``"dense"`` grid.
    workers : int, optional
        Threads for the estimator (default: all cores for large inputs).
    bias_correction : bool
        ``kind="totdev"`` only: divide TOTVAR by its bias ratio ``B = 1 - a tau/T`` at the
        points identified as flicker FM (``a = 1/(3 ln 2)``) or random-walk FM
        (``a = 3/4``), as Stable32 does (Howe 1999; :func:`fogts.allan.confidence.
        totdev_bias`).  Uncorrected TOTDEV of a rate random walk is ``sqrt(1 - 0.75 tau/T)``
        low at long tau, which biases K fitted from it.  The correction is only as good as
        the noise type identified at each tau, which is uncertain at the last few taus.
        The default (False) is the plain estimator that allantools also computes.
    input : {"rate", "increment", "angle"}
        What array/Series/DataFrame input holds: rate, angle increments per sample (the
        rate is ``x fs``) or integrated angle (``n + 1`` angles for ``n`` rates).  Angle
        and increments are used as the phase of the estimators directly (NIST SP1065
        sec. 5.2), never differenced and integrated back
        (:func:`fogts.allan.estimators.estimate_from_angle`); the deviations are in the
        rate unit (``units`` of an angle in deg is ``deg/s``).  A Run read from such a file
        carries its angle (:attr:`fogts.io.run.Run.angle`) and is used the same way.

    Returns
    -------
    AllanResult or AllanResultSet
        An :class:`AllanResultSet` for multi-axis input without ``axis``.

    Raises
    ------
    DataError
        Bad argument, non-finite data, unknown axis, missing sample rate;
        ``bias_correction`` with another kind or without ``confidence`` (the correction
        needs the per-point noise type).
    InsufficientDataError
        Too few samples for any tau.

    Examples
    --------
    >>> import numpy as np
    >>> y = np.random.default_rng(1).normal(scale=0.1, size=10_000)   # deg/h at 10 Hz
    >>> res = allan_deviation(y, fs_hz=10.0, taus="decade")
    >>> res.tau_s[:4].tolist()
    [0.1, 0.2, 0.4, 1.0]
    >>> bool(abs(res.dev[0] - 0.1) < 0.005), res.n[0].item()
    (True, 9999)
    """
    kind = check_choice("kind", kind, KINDS)  # type: ignore[assignment]
    if confidence is not None:
        confidence = check_fraction("confidence", confidence)
    _check_bias_correction(bias_correction, kind, confidence)
    if units is not None:
        units = parse_sensor_unit(units)
    input = check_choice("input", input, INPUT_KINDS)  # type: ignore[assignment]
    series, fs, unit, notes = unpack_axes(x, fs_hz=fs_hz, axis=axis, units=units, input=input)
    curves = [_one_curve(s, fs_hz=fs, units=unit, kind=kind, taus=taus, confidence=confidence,
                         per_decade=per_decade, workers=workers, notes=notes,
                         bias_correction=bias_correction)
              for s in series]
    if len(curves) == 1 and (axis is not None or not is_multi_axis(x)):
        return curves[0]
    return AllanResultSet(curves=tuple(curves))


def is_multi_axis(x: Any) -> bool:
    """True for input that carries several axes (a 2-D array, a DataFrame, a multi-axis Run)."""
    if isinstance(x, Run):
        return x.rate.ndim == 2
    if isinstance(x, pd.DataFrame):
        return True
    return isinstance(x, np.ndarray) and x.ndim == 2


def _check_bias_correction(bias_correction: Any, kind: str, confidence: float | None) -> None:
    if not isinstance(bias_correction, bool | np.bool_):
        raise DataError(f"bias_correction must be True or False, got {bias_correction!r}")
    if not bias_correction:
        return
    if kind != "totdev":
        raise DataError(f"bias_correction applies to kind='totdev' only (the other estimators "
                        f"are unbiased for every power-law noise), got kind={kind!r}")
    if confidence is None:
        raise DataError("bias_correction needs the per-tau noise identification; pass a "
                        "confidence level, not confidence=None")


def _with_gaps(s: AxisSeries, kind: str) -> bool:
    """Whether a Run's axis holds NaN for missing samples (``gaps="nan"``); inf is refused."""
    finite = np.isfinite(s.y)
    if finite.all():
        return False
    if np.isinf(s.y).any():
        raise DataError(f"axis {s.name!r} holds inf; rate data must be finite")
    if kind != "oadev":
        raise DataError(f"axis {s.name!r} has missing samples (NaN, gaps='nan'); only "
                        f"kind='oadev' has a gap-robust estimator, got kind={kind!r}")
    return True


def _gap_robust(y: FloatArray, fs_hz: float, grid: TauGrid) -> tuple[TauGrid, EstimatorOutput]:
    """:func:`gradev` on the grid, without the taus left with fewer than two terms free of
    missing samples (listed in ``dropped``)."""
    est = gradev(y, fs_hz=fs_hz, m=grid.m)
    keep = est.n >= 2
    if keep.all():
        return grid, est
    lost = tuple(DroppedTau(float(t), int(m), "fewer than 2 terms free of missing samples")
                 for t, m in zip(grid.tau_s[~keep], grid.m[~keep], strict=True))
    grid = dataclasses.replace(grid, m=grid.m[keep], tau_s=grid.tau_s[keep],
                               dropped=(*grid.dropped, *lost))
    return grid, dataclasses.replace(est, m=est.m[keep], tau_s=est.tau_s[keep],
                                     dev=est.dev[keep], n=est.n[keep])


def _one_curve(s: AxisSeries, *, fs_hz: float, units: str, kind: str, taus: Any,
               confidence: float | None, per_decade: int, workers: int | None,
               notes: tuple[str, ...], bias_correction: bool = False) -> AllanResult:
    grid = tau_grid(taus, fs_hz=fs_hz, n_samples=s.y.size, kind=kind, per_decade=per_decade)
    gaps = _with_gaps(s, kind)
    if gaps:  # Sesia & Tavella (2008): only the terms that touch no missing sample
        grid, est = _gap_robust(s.y, fs_hz, grid)
        notes = (*notes, f"{int(np.count_nonzero(np.isnan(s.y)))} missing samples (NaN): "
                 "gap-robust overlapping ADEV (Sesia & Tavella 2008); noise type and EDF "
                 "from the samples present")
        s = AxisSeries(s.y[np.isfinite(s.y)], s.name)
    else:
        est = (ESTIMATORS[kind](s.y, fs_hz=fs_hz, m=grid.m, workers=workers)
               if s.angle is None
               else estimate_from_angle(kind, s.angle, fs_hz=fs_hz, m=grid.m, workers=workers))
    size = grid.m.size
    nan = np.full(size, np.nan)
    ci_low, ci_high, edf = nan, nan, nan
    alpha: IntArray = np.zeros(size, dtype=np.int64)
    methods: tuple[str, ...] = ("none",) * size
    level = float("nan")
    if confidence is not None:
        table = confidence_table(s.y, fs_hz=fs_hz, kind=kind, m=grid.m, dev=est.dev,
                                 confidence=confidence)
        ci_low, ci_high = table.ci_low, table.ci_high
        edf, alpha = table.edf, table.alpha
        methods = tuple(str(v) for v in table.alpha_method)
        level = float(table.confidence)
    dev = est.dev
    if bias_correction:
        root_b = np.sqrt(totdev_bias(alpha, grid.m, s.y.size + 1))
        dev, ci_low, ci_high = dev / root_b, ci_low / root_b, ci_high / root_b
        notes = (*notes, "totdev divided by sqrt(B), B = 1 - a tau/T with a = 0.481 at "
                 "flicker-FM and 0.75 at random-walk-FM points (Howe 1999), as Stable32 "
                 f"reports it; {int(np.count_nonzero(root_b < 1))} of {root_b.size} points "
                 "corrected")
    return AllanResult(kind=kind, units=units, axis=s.name, fs_hz=fs_hz, n_samples=s.y.size,
                       confidence=level, tau_s=grid.tau_s, m=grid.m, n=est.n, dev=dev,
                       ci_low=ci_low, ci_high=ci_high, edf=edf, alpha=alpha,
                       dropped=grid.dropped, alpha_method=methods,
                       notes=(*grid.notes, *notes), bias_corrected=bias_correction)


def run_from_pandas(x: pd.Series | pd.DataFrame, *, fs_hz: float | None,
                    units: str | None, input: str | None = None) -> Run:
    """A Series or DataFrame as a :class:`~fogts.io.run.Run`, read by
    :func:`fogts.io.reader.read_run` (sample rate from a Datetime/Timedelta index unless
    ``fs_hz`` is given; time, temperature and rate columns recognised by name; a frame
    without a recognisable rate column has every column as an axis).

    This is the one place where the Allan analysis calls the reader.
    """
    from fogts.io.reader import read_run

    if isinstance(x, pd.Series):
        return read_run(x, rate_column=str(x.name) if x.name is not None else None,
                        fs_hz=fs_hz, units=units, input=input)
    frame = x.set_axis([str(c) for c in x.columns], axis=1)
    try:
        return read_run(frame, fs_hz=fs_hz, units=units, input=input)
    except DataError:  # no recognisable rate column: every column is an axis
        return read_run(frame, rate_column=list(frame.columns), fs_hz=fs_hz, units=units,
                        input=input)


def unpack_axes(x: Any, *, fs_hz: float | None, axis: int | str | None, units: str | None,
                input: str = "rate",
                ) -> tuple[list[AxisSeries], float, str, tuple[str, ...]]:
    """Split the input into 1-D float64 series (with their angle, for angle input), and
    find the sample rate and unit."""
    fs = check_positive("fs_hz", fs_hz) if fs_hz is not None else None
    if input != "rate" and isinstance(x, Run | Prepared):
        raise DataError(f"input={input!r} is for arrays and frames; a Run carries its own "
                        "(read_run(..., input=...))")
    if isinstance(x, Prepared):
        if axis is not None and axis not in (0, x.axis):
            raise DataError(f"axis {axis!r} not found; the Prepared series is axis {x.axis!r}")
        notes = tuple(f"prepared: {step}" for step in x.steps)
        return ([AxisSeries(to_float_array(x.x, "x"), x.axis)], fs or x.fs_hz, units or x.units,
                notes)
    if isinstance(x, pd.Series | pd.DataFrame):
        x = run_from_pandas(x, fs_hz=fs, units=units, input=input)
        fs = None  # already applied
    if isinstance(x, Run):
        names = x.axes
        if axis is not None:
            i = names.index(axis) if isinstance(axis, str) and axis in names else axis
            picked = x.axis(axis)
            name = axis if isinstance(axis, str) else names[int(axis)]
            series = [AxisSeries(to_float_array(picked, name, allow_nonfinite=True), name,
                                 x.axis_angle(int(i)) if x.angle is not None else None)]
        else:
            series = [AxisSeries(to_float_array(x.axis(i), n, allow_nonfinite=True), n,
                                 x.axis_angle(i)) for i, n in enumerate(names)]
        return series, fs or x.fs_hz, units or x.units, ()
    if fs is None:
        raise DataError("fs_hz is required for array input (or pass a Run, a Prepared, or a "
                        "Series with a DatetimeIndex)")
    arr = to_float_array(x, "x", ndim=2)
    unit = units or "deg/h"
    if input != "rate":
        return _angle_axes(arr, fs, axis, input), fs, unit, ()
    if arr.ndim == 1:
        if axis is not None and axis not in (0, "rate"):
            raise DataError(f"axis {axis!r} not found; a 1-D array has one axis (0)")
        return [AxisSeries(arr, "rate")], fs, unit, ()
    names = tuple(f"rate_{i}" for i in range(arr.shape[1]))
    if axis is None:
        return ([AxisSeries(np.ascontiguousarray(arr[:, i]), n) for i, n in enumerate(names)],
                fs, unit, ())
    if isinstance(axis, str):
        if axis not in names:
            raise DataError(f"axis {axis!r} not found; axes are: {', '.join(names)}")
        i = names.index(axis)
    else:
        i = int(axis)
        if not -len(names) <= i < len(names):
            raise DataError(f"axis index must be in [0, {len(names) - 1}], got {i}")
    return [AxisSeries(np.ascontiguousarray(arr[:, i]), names[i % len(names)])], fs, unit, ()


def _angle_axes(arr: FloatArray, fs: float, axis: int | str | None, input: str
                ) -> list[AxisSeries]:
    """Array input of angle increments or angle as axes with their angle (the phase)."""
    from fogts.io.angle import to_rate

    cols = [arr] if arr.ndim == 1 else [np.ascontiguousarray(arr[:, i])
                                         for i in range(arr.shape[1])]
    rates, angle = to_rate(input, cols, fs)
    names = ("rate",) if arr.ndim == 1 else tuple(f"rate_{i}" for i in range(arr.shape[1]))
    assert angle is not None
    angles = [angle] if angle.ndim == 1 else [np.ascontiguousarray(angle[:, i])
                                              for i in range(angle.shape[1])]
    series = [AxisSeries(r, n, a) for r, n, a in zip(rates, names, angles, strict=True)]
    if axis is None:
        return series
    picked = names.index(axis) if isinstance(axis, str) and axis in names else axis
    if not isinstance(picked, int) or not -len(names) <= picked < len(names):
        raise DataError(f"axis {axis!r} not found; axes are: {', '.join(names)}")
    return [series[picked]]
