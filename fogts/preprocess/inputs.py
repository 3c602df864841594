"""The one coercer of the data a public entry point is given (in the manner of arch's
``ensure1d``).

An ndarray, a pandas Series, a :class:`~fogts.io.run.Run` or a
:class:`~fogts.preprocess.prepare.Prepared` (and, for :func:`ensure_axes`, a 2-D array or a
DataFrame) becomes an :class:`InputData`: float64 values, the axis names, the sample rate and
rate unit the input carries, and the pandas index to re-wrap outputs with.  The rules are
the same for every entry point:

* a given ``fs_hz`` must be finite and > 0 and overrides what the input carries; a Run or a
  Prepared carries its own, a Series with a DatetimeIndex or TimedeltaIndex its median step;
* a given ``units`` is parsed by :func:`fogts.units.parse_rate_unit` and overrides the
  input's; ``InputData.units`` is None when nothing stated one;
* ``axis`` (name or position) picks one axis of a multi-axis input; a one-axis input
  accepts only its own name or position 0;
* a 1-D array or an unnamed Series is the axis ``"rate"``.

Every refusal names the argument, shows what was given and says what is allowed.
"""

from __future__ import annotations

from dataclasses import dataclass, replace
from typing import TYPE_CHECKING, Literal

import numpy as np
import pandas as pd

from fogts._typing import ArrayLike1D, FloatArray
from fogts._validate import all_finite, check_positive, to_float_array
from fogts.errors import DataError
from fogts.io.run import Run
from fogts.units import parse_sensor_unit

if TYPE_CHECKING:
    from fogts.preprocess.prepare import Prepared

__all__ = ["InputData", "ensure_axes", "ensure_series", "run_from_pandas"]

#: What the input was.
InputKind = Literal["array", "Series", "DataFrame", "Run", "Prepared"]
#: The axis name of a 1-D array or an unnamed Series.
DEFAULT_AXIS = "rate"


@dataclass(frozen=True)
class InputData:
    """Coerced input of an analysis entry point.

    Attributes
    ----------
    values : ndarray of float64, shape (n,) or (n, k)
        The data, finite; 2-D when several axes are kept.
    axes : tuple of str
        The name of each axis (one per column of ``values``).
    fs_hz : float or None
        Sample rate: given, or carried by the input; None if neither.
    units : str or None
        Canonical rate unit: given, or carried by a Run or a Prepared; None if neither.
    kind : {"array", "Series", "DataFrame", "Run", "Prepared"}
        What the input was.
    index : pandas.Index or None
        A Series' index, to re-wrap outputs.
    multi_axis_form : bool
        The input is of a multi-axis form (a 2-D array, a DataFrame, a multi-axis Run), even
        when ``axis`` picked one of its axes.
    run : Run or None
        The Run given (or read from a pandas frame).
    prepared : Prepared or None
        The Prepared given.
    angles : tuple of ndarray or None
        The angle of each axis for angle or increment input (:meth:`angle`).
    missing : bool
        Some values are NaN: a Run's missing samples, let through by ``allow_nan`` of
        :func:`ensure_axes`.  False means every value is finite.
    """

    values: FloatArray
    axes: tuple[str, ...]
    fs_hz: float | None
    units: str | None
    kind: InputKind
    index: pd.Index | None = None
    multi_axis_form: bool = False
    run: Run | None = None
    prepared: Prepared | None = None
    angles: tuple[FloatArray, ...] | None = None
    missing: bool = False

    @property
    def n(self) -> int:
        return int(self.values.shape[0])

    def column(self, i: int) -> FloatArray:
        """Axis ``i`` as a contiguous 1-D array."""
        return self.values if self.values.ndim == 1 else np.ascontiguousarray(self.values[:, i])

    def columns(self) -> list[tuple[str, FloatArray]]:
        """``(name, values)`` of every axis kept."""
        return [(name, self.column(i)) for i, name in enumerate(self.axes)]

    def angle(self, i: int) -> FloatArray | None:
        """The angle (the phase, n + 1 points) of axis ``i`` for angle or increment input,
        else None."""
        return None if self.angles is None else self.angles[i]

    def wrap(self, values: FloatArray, name: str) -> FloatArray | pd.Series:
        """``values`` as a Series on the input's index, or as is for array input."""
        return values if self.index is None else pd.Series(values, index=self.index, name=name)


def ensure_series(x: ArrayLike1D | Run | Prepared, name: str = "x", *,
                  fs_hz: float | None = None, units: str | None = None,
                  axis: int | str | None = None, min_length: int = 2,
                  accept_prepared: bool = True, require_fs: bool = False,
                  pick_hint: str = "pass axis= to pick one") -> InputData:
    """One series: a 1-D array, a Series, one axis of a Run, or a Prepared.

    Parameters
    ----------
    x : array_like, Series, Run or Prepared
        The data.
    name : str
        The argument's name in error messages.
    fs_hz, units, axis
        See the module docstring.  A multi-axis Run needs ``axis``.
    min_length : int
        Fewest samples (fewer raise :class:`~fogts.errors.InsufficientDataError`).
    accept_prepared : bool
        False refuses a Prepared (for :func:`~fogts.preprocess.prepare.prepare` itself).
    require_fs : bool
        Refuse input that carries no sample rate when none is given.
    pick_hint : str
        How to pick an axis, said when a multi-axis Run comes without ``axis``.

    Raises
    ------
    DataError
        A DataFrame, a 2-D array, a refused Prepared, an unknown axis, a bad ``fs_hz`` or
        ``units``, non-numeric or non-finite values, a missing sample rate.
    InsufficientDataError
        Fewer than ``min_length`` samples.
    """
    fs, unit = _given(fs_hz, units)
    allowed = ("an ndarray, a Series, a Run or a Prepared" if accept_prepared
               else "an ndarray, a Series or a Run")
    prepared = _as_prepared(x)
    if prepared is not None:
        if not accept_prepared:
            raise DataError(f"{name} is already Prepared; pass the Run or the raw series")
        return _from_prepared(prepared, fs, unit, axis)
    if isinstance(x, pd.DataFrame):
        raise DataError(f"{name} must be one series ({allowed}), got a DataFrame; for a "
                        "DataFrame use fogts.io.reader.read_run(frame) first")
    if isinstance(x, Run):
        if axis is None and x.n_axes > 1:
            raise DataError(f"{name} is a Run with {x.n_axes} axes ({', '.join(x.axes)}); "
                            f"{pick_hint}")
        return _from_run(x, fs, unit, 0 if axis is None else axis, min_length)
    index = x.index if isinstance(x, pd.Series) else None
    kind: InputKind = "Series" if index is not None else "array"
    axis_name = str(x.name) if isinstance(x, pd.Series) and x.name is not None else DEFAULT_AXIS
    if fs is None:
        fs = _fs_from_index(index)
    if fs is None and require_fs:
        raise DataError(_fs_required(kind, accept_prepared))
    values = to_float_array(x, name, min_length=min_length)
    _check_one_axis(axis, axis_name)
    return InputData(values, (axis_name,), fs, unit, kind, index=index)


def ensure_axes(x: ArrayLike1D | Run | Prepared | pd.DataFrame, name: str = "x", *,
                fs_hz: float | None = None, units: str | None = None,
                axis: int | str | None = None, input: str = "rate",
                allow_nan: bool = False) -> InputData:
    """Every axis of a recording (or the one ``axis`` picks), with its sample rate.

    A 2-D array ``(n, k)`` has the axes ``rate_0`` .. ``rate_{k-1}``; a Series or a
    DataFrame is read as a Run (:func:`run_from_pandas`).  The sample rate is required.
    ``input`` says what array, Series or DataFrame input holds (``"rate"``,
    ``"increment"`` or ``"angle"``, :mod:`fogts.io.angle`; a Run carries its own), and the
    angle of each axis is kept (:meth:`InputData.angle`).  ``allow_nan`` lets a Run's
    missing samples (NaN on its regular grid) through; inf is always refused.

    Raises
    ------
    DataError
        An unknown axis, a bad ``fs_hz`` or ``units``, array input without ``fs_hz``,
        non-numeric or non-finite values.
    InsufficientDataError
        Fewer than 2 samples.
    """
    fs, unit = _given(fs_hz, units)
    prepared = _as_prepared(x)
    if input != "rate" and (prepared is not None or isinstance(x, Run)):
        raise DataError(f"input={input!r} is for arrays and frames; a Run carries its own "
                        "(read_run(..., input=...))")
    if prepared is not None:
        return _from_prepared(prepared, fs, unit, axis)
    frame = isinstance(x, pd.DataFrame)
    if isinstance(x, pd.Series | pd.DataFrame):
        x = run_from_pandas(x, fs_hz=fs, units=unit, input=input)
        fs = None  # already applied
    if isinstance(x, Run):
        inp = _run_axes(x, fs, unit, axis, allow_nan)
        return replace(inp, kind="DataFrame", multi_axis_form=True) if frame else inp
    if fs is None:
        raise DataError(_fs_required("array", True))
    arr = to_float_array(x, name, ndim=2)
    if input != "rate":
        return _angle_axes(arr, fs, unit, axis, input)
    if arr.ndim == 1:
        _check_one_axis(axis, DEFAULT_AXIS)
        return InputData(arr, (DEFAULT_AXIS,), fs, unit, "array")
    names = tuple(f"{DEFAULT_AXIS}_{i}" for i in range(arr.shape[1]))
    if axis is None:
        return InputData(arr, names, fs, unit, "array", multi_axis_form=True)
    i = _axis_position(axis, names)
    return InputData(np.ascontiguousarray(arr[:, i]), (names[i],), fs, unit, "array",
                     multi_axis_form=True)


def run_from_pandas(x: pd.Series | pd.DataFrame, *, fs_hz: float | None,
                    units: str | None, input: str = "rate") -> Run:
    """A Series or DataFrame as a :class:`~fogts.io.run.Run`, read by
    :func:`fogts.io.reader.read_run` (sample rate from a Datetime/Timedelta index unless
    ``fs_hz`` is given; time, temperature and rate columns recognised by name; a frame
    without a recognisable rate column has every column as an axis)."""
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


def _given(fs_hz: float | None, units: str | None) -> tuple[float | None, str | None]:
    fs = check_positive("fs_hz", fs_hz) if fs_hz is not None else None
    return fs, parse_sensor_unit(units) if units is not None else None


def _as_prepared(x: object) -> Prepared | None:
    from fogts.preprocess.prepare import Prepared

    return x if isinstance(x, Prepared) else None


def _from_prepared(p: Prepared, fs: float | None, unit: str | None,
                   axis: int | str | None) -> InputData:
    if axis is not None and axis not in (0, p.axis):
        raise DataError(f"axis {axis!r} not found; the Prepared series is axis {p.axis!r}")
    return InputData(to_float_array(p.x, "x"), (p.axis,), fs or p.fs_hz, unit or p.units,
                     "Prepared", index=p.index, prepared=p)


def _from_run(run: Run, fs: float | None, unit: str | None, axis: int | str,
              min_length: int, allow_nan: bool = False) -> InputData:
    picked = run.axis(axis)
    axis_name = axis if isinstance(axis, str) else run.axes[int(axis)]
    values, missing = _checked_columns(picked, (axis_name,), min_length, allow_nan)
    angles = None
    if run.angle is not None:
        i = run.axes.index(axis_name)
        angle = run.axis_angle(i)
        assert angle is not None
        angles = (angle,)
    return InputData(values, (axis_name,), fs or run.fs_hz, unit or run.units, "Run",
                     multi_axis_form=run.rate.ndim == 2, run=run, angles=angles,
                     missing=missing)


def _run_axes(run: Run, fs: float | None, unit: str | None, axis: int | str | None,
              allow_nan: bool) -> InputData:
    """Every axis of a Run (or the one ``axis`` picks), with their angles."""
    if axis is not None:
        return _from_run(run, fs, unit, axis, 2, allow_nan)
    angles = None
    if run.angle is not None:
        angles = tuple(a for a in (run.axis_angle(i) for i in range(run.n_axes))
                       if a is not None)
    values, missing = _checked_columns(run.rate, run.axes, 2, allow_nan)
    return InputData(values, run.axes, fs or run.fs_hz, unit or run.units, "Run",
                     multi_axis_form=run.rate.ndim == 2, run=run, angles=angles,
                     missing=missing)


def _checked_columns(rate: FloatArray, axes: tuple[str, ...], min_length: int,
                     allow_nan: bool = False) -> tuple[FloatArray, bool]:
    """``rate`` as float64, each axis checked (and named in the error) as one series, and
    whether it holds NaN: a missing sample passes with ``allow_nan``, inf never."""
    arr = to_float_array(rate, "rate", min_length=min_length, allow_nonfinite=True, ndim=2)
    if all_finite(arr):
        return arr, False
    bad = np.isinf(arr) if allow_nan else ~np.isfinite(arr)
    if np.any(bad):
        for i, axis_name in enumerate(axes):  # the first bad axis raises, naming itself
            column = arr if arr.ndim == 1 else arr[:, i]
            to_float_array(np.where(np.isnan(column), 0.0, column) if allow_nan else column,
                           axis_name)
    return arr, True


def _angle_axes(arr: FloatArray, fs: float, unit: str | None, axis: int | str | None,
                input: str) -> InputData:
    """Array input of angle increments or angle: the rate of each axis and its angle."""
    from fogts.io.angle import to_rate

    cols = [arr] if arr.ndim == 1 else [np.ascontiguousarray(arr[:, i])
                                         for i in range(arr.shape[1])]
    rates, angle = to_rate(input, cols, fs)
    assert angle is not None
    names = ((DEFAULT_AXIS,) if arr.ndim == 1
             else tuple(f"{DEFAULT_AXIS}_{i}" for i in range(arr.shape[1])))
    angles = tuple([angle] if angle.ndim == 1 else [np.ascontiguousarray(angle[:, i])
                                                     for i in range(angle.shape[1])])
    picked = range(len(names)) if axis is None else [_axis_position(axis, names)]
    values = [rates[i] for i in picked]
    return InputData(values[0] if len(values) == 1 else np.column_stack(values),
                     tuple(names[i] for i in picked), fs, unit, "array",
                     multi_axis_form=arr.ndim == 2, angles=tuple(angles[i] for i in picked))


def _check_one_axis(axis: int | str | None, axis_name: str) -> None:
    if axis is not None and axis not in (0, axis_name):
        raise DataError(f"axis {axis!r} not found; a 1-D series has one axis (0 or "
                        f"{axis_name!r})")


def _axis_position(axis: int | str, names: tuple[str, ...]) -> int:
    if isinstance(axis, str):
        if axis not in names:
            raise DataError(f"axis {axis!r} not found; axes are: {', '.join(names)}")
        return names.index(axis)
    i = int(axis)
    if not -len(names) <= i < len(names):
        raise DataError(f"axis index must be in [0, {len(names) - 1}], got {i}")
    return i % len(names)


def _fs_from_index(index: pd.Index | None) -> float | None:
    """The sample rate of a DatetimeIndex or TimedeltaIndex (its median step), else None."""
    if not isinstance(index, pd.DatetimeIndex | pd.TimedeltaIndex) or index.size < 2:
        return None
    steps = pd.TimedeltaIndex(index[1:] - index[:-1]).total_seconds()
    return 1.0 / float(np.median(np.asarray(steps)))


def _fs_required(kind: str, accept_prepared: bool) -> str:
    carriers = "a Run, a Prepared" if accept_prepared else "a Run"
    return (f"fs_hz is required for {kind} input (or pass {carriers}, or a Series with a "
            "DatetimeIndex or TimedeltaIndex)")
