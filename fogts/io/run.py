"""The :class:`Run` record: one static gyro recording as read from a file or a frame.

Kept apart from :mod:`fogts.io.reader` (which reads files) so that analysis modules can accept a
Run without importing the reader.  ``Run`` is produced by :func:`fogts.io.reader.read_run`,
:func:`fogts.simulate.gyro.simulate_gyro` and :func:`fogts.startup.compensation.compensate`.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import numpy as np
import pandas as pd

from fogts._typing import FloatArray
from fogts.errors import DataError

__all__ = ["MissingReport", "RegularTime", "Run", "SamplingReport", "held_time"]


@dataclass(frozen=True)
class SamplingReport:
    """How regular the time base is.

    ``Run.sampling``: what :func:`~fogts.io.timebase.sampling_report` found in the time column.

    Attributes
    ----------
    median_dt_s : float
        Median time step (the nominal sample period).
    n_gaps : int
        Number of steps longer than 1.5 x the median.
    max_gap_s : float
        Longest step.
    gap_rows : tuple of int
        Row index (0-based, data rows) *after* which each gap occurs (first 100 kept).
    jitter_s : float
        Standard deviation of the time steps that are not gaps.
    jitter_rel : float
        ``jitter_s / median_dt_s``.
    regular : bool
        True when there are no gaps and relative jitter is below 1 %.
    from_time_column : bool
        False when the time base was built from ``fs_hz`` (so it is regular by construction).
    mean_dt_s : float
        Mean time step, ``(t[-1] - t[0]) / (n - 1)``.
    fs_source : str
        Where ``fs_hz`` came from: ``"given"``, ``"median step"``, ``"mean of jittered
        steps"`` (the steps that are not gaps, when their mean and median differ by more
        than 1e-6: a quantised or jittered clock), ``"mean step"`` (used when burst-logged
        stamps make the median step disagree with the mean step by more than 10 %),
        ``"file"`` (an ``fs_hz`` key in an .npz).
    """

    median_dt_s: float
    n_gaps: int
    max_gap_s: float
    gap_rows: tuple[int, ...]
    jitter_s: float
    jitter_rel: float
    regular: bool
    from_time_column: bool
    mean_dt_s: float = float("nan")
    fs_source: str = "given"

    def to_dict(self) -> dict[str, Any]:
        return {
            "median_dt_s": self.median_dt_s,
            "n_gaps": self.n_gaps,
            "max_gap_s": self.max_gap_s,
            "gap_rows": list(self.gap_rows),
            "jitter_s": self.jitter_s,
            "jitter_rel": self.jitter_rel,
            "regular": self.regular,
            "from_time_column": self.from_time_column,
            "mean_dt_s": self.mean_dt_s,
            "fs_source": self.fs_source,
        }


@dataclass(frozen=True)
class MissingReport:
    """Empty, NaN or infinite cells found when reading, and what was done with them.

    Attributes
    ----------
    policy : str
        ``"drop"`` (the rows were removed; with a time column they become gaps) or
        ``"interpolate"`` (filled linearly in time; leading/trailing cells take the
        nearest value).
    n_rows : int
        Rows that had at least one missing cell.
    by_column : dict of str -> int
        Missing cells per column.
    first_rows : tuple of int
        Data rows (0-based, in the file) of the first missing cells (at most 20).
    """

    policy: str
    n_rows: int
    by_column: dict[str, int]
    first_rows: tuple[int, ...]

    def to_dict(self) -> dict[str, Any]:
        return {"policy": self.policy, "n_rows": self.n_rows,
                "by_column": dict(self.by_column), "first_rows": list(self.first_rows)}

    def summary(self) -> str:
        """One line, e.g. ``"3 row(s) with empty/NaN cells dropped (rate: 3; first row 17)"``."""
        done = "dropped" if self.policy == "drop" else "interpolated linearly in time"
        cols = ", ".join(f"{k}: {v}" for k, v in self.by_column.items() if v)
        return (f"{self.n_rows} row(s) with empty/NaN/inf cells {done} ({cols}; first at data "
                f"row {self.first_rows[0] if self.first_rows else '-'})")


class RegularTime:
    """Stand-in for :attr:`Run.time` of a regular time base built from the sample rate:
    ``k / fs_hz`` for ``k < n``, formed (``arange(n) / fs_hz``, in place) on the first access
    of ``run.time`` and kept from then on.

    A reader without a time column passes ``time=RegularTime(n, fs_hz)`` so that a record of
    1e8 samples does not carry an 800 MB time array that the Allan chain never reads;
    :func:`held_time` tells callers whether the array exists without forming it.

    Examples
    --------
    >>> RegularTime(4, 8.0).array().tolist()
    [0.0, 0.125, 0.25, 0.375]
    """

    __slots__ = ("fs_hz", "n")

    def __init__(self, n: int, fs_hz: float) -> None:
        self.n = int(n)
        self.fs_hz = float(fs_hz)

    def array(self) -> FloatArray:
        """``arange(n) / fs_hz`` (the values the readers always formed)."""
        t = np.arange(self.n, dtype=np.float64)
        t /= self.fs_hz  # in place: one array, not two
        return t

    def __reduce__(self) -> tuple[type[RegularTime], tuple[int, float]]:
        return RegularTime, (self.n, self.fs_hz)

    def __repr__(self) -> str:
        return f"RegularTime(n={self.n}, fs_hz={self.fs_hz!r})"


class _TimeField:
    """The data descriptor behind :attr:`Run.time`: it stores what the constructor was given
    and turns a :class:`RegularTime` into its array on first access (cached in the
    instance).  Reading it on the class raises AttributeError, so that the dataclass sees a
    field without default and its signature is unchanged."""

    def __get__(self, obj: Any, owner: Any = None) -> FloatArray:
        if obj is None:
            raise AttributeError("time")
        value = obj.__dict__["time"]
        if isinstance(value, RegularTime):
            value = value.array()
            obj.__dict__["time"] = value
        return value  # type: ignore[no-any-return]

    def __set__(self, obj: Any, value: Any) -> None:
        obj.__dict__["time"] = value


def held_time(run: Run) -> FloatArray | None:
    """``run.time`` if the array exists; None for a regular time base not formed yet, whose
    ``k``-th time is ``k / run.fs_hz`` exactly (:class:`RegularTime`).  For callers that need
    a few time stamps, not the array.

    Examples
    --------
    >>> run = Run(rate=np.ones(3), time=RegularTime(3, 2.0), fs_hz=2.0, units="deg/h",
    ...           axes=("rate",))
    >>> held_time(run) is None, run.time.tolist(), held_time(run) is not None
    (True, [0.0, 0.5, 1.0], True)
    """
    value = run.__dict__["time"]
    return None if isinstance(value, RegularTime) else value  # type: ignore[no-any-return]


@dataclass(frozen=True)
class Run:
    """One gyro recording.

    Attributes
    ----------
    rate : ndarray of float64, shape (n,) or (n, n_axes)
        Angular rate in ``units``.
    time : ndarray of float64, shape (n,)
        Seconds since the first sample.  The constructor also takes a
        :class:`RegularTime` (a regular time base from the sample rate, as the readers pass
        without a time column): the array is then formed on first access.
    fs_hz : float
        Sample rate (from the median time step, or given).
    units : str
        Rate unit, one of :data:`fogts.units.RATE_UNITS`.
    axes : tuple of str
        Name of each rate column (one per axis).
    temperature : ndarray of float64 or None
        Temperature in degC, shape (n,), if a temperature column was found.
    columns : tuple of str
        All columns present in the source.
    source : str
        Path, or a description such as ``"<DataFrame>"``.
    sampling : SamplingReport
        Gaps and jitter of the time base.
    start_time : str or None
        ISO-8601 time of the first sample if the source had absolute time stamps.
    comments : tuple of str
        ``#`` comment lines found in a text file, in order.
    units_source : str
        Where ``units`` came from: ``"given"`` (the ``units`` argument, CLI ``--units``),
        ``"column name"`` (a hint such as ``gyro_x_deg_s``), ``"file key"`` (an .npz key
        such as ``gyro_deg_s``), ``"file metadata"`` (the ``units`` of a ``<file>.json``
        sidecar written by ``fogts simulate``) or ``"assumed"`` (nothing said: deg/h by
        convention; every command then warns).
    missing : MissingReport or None
        Empty/NaN/inf cells dropped or interpolated on reading (None: there were none).
    axis_units : tuple of str
        The unit of each axis when they differ (an IMU file: the gyro axes in a rate unit,
        the accelerometer axes, after them, in a specific-force unit such as m/s^2 or g;
        :func:`fogts.io.accel.accel_unit`); empty: every axis is in ``units``.  See
        :meth:`unit_of`.
    accel_units_source : str
        Where the accelerometer unit came from (``"given"``, ``"column name"``,
        ``"gravity magnitude"``, ``"assumed"``); empty without accelerometer axes.
    input_kind : str
        What the file held: ``"rate"``, ``"increment"`` (angle per sample) or ``"angle"``
        (integrated angle); see :mod:`fogts.io.angle`.
    angle : ndarray of float64 or None
        For angle and increment input: the angle itself, relative to the first, in
        ``units`` x seconds, shape ``(n + 1,)`` or ``(n + 1, n_axes)`` (the rate is its
        difference times ``fs_hz``).  The Allan estimators use it as the phase; None for
        rate input, and dropped by anything that changes the rate.
    """

    rate: FloatArray
    time: FloatArray
    fs_hz: float
    units: str
    axes: tuple[str, ...]
    temperature: FloatArray | None = None
    columns: tuple[str, ...] = ()
    source: str = "<array>"
    sampling: SamplingReport | None = None
    start_time: str | None = None
    comments: tuple[str, ...] = field(default=())
    units_source: str = "given"
    missing: MissingReport | None = None
    axis_units: tuple[str, ...] = ()
    accel_units_source: str = ""
    input_kind: str = "rate"
    angle: FloatArray | None = field(default=None, repr=False)

    def axis_angle(self, i: int) -> FloatArray | None:
        """The angle of axis ``i`` (None for rate input)."""
        if self.angle is None:
            return None
        return self.angle if self.angle.ndim == 1 else np.ascontiguousarray(self.angle[:, i])

    def unit_of(self, name_or_index: str | int = 0) -> str:
        """The unit of one axis (``units`` unless ``axis_units`` says otherwise)."""
        if not self.axis_units:
            return self.units
        i = (self.axes.index(name_or_index) if isinstance(name_or_index, str)
             and name_or_index in self.axes else name_or_index)
        if not isinstance(i, int):
            raise DataError(f"axis {name_or_index!r} not found; axes are: "
                            f"{', '.join(self.axes)}")
        return self.axis_units[i]

    @property
    def units_assumed(self) -> bool:
        """True when no unit was given or found and ``units`` is the deg/h default."""
        return self.units_source == "assumed"

    @property
    def n(self) -> int:
        """Number of samples."""
        return int(self.rate.shape[0])

    @property
    def n_axes(self) -> int:
        """Number of rate axes."""
        return 1 if self.rate.ndim == 1 else int(self.rate.shape[1])

    @property
    def duration_s(self) -> float:
        """The samples' time, ``n / fs_hz``; the time stamps of a record with gaps span
        longer (:func:`fogts.report.text.time_span_s`)."""
        return self.n / self.fs_hz

    def axis(self, name_or_index: str | int = 0) -> FloatArray:
        """The rate of one axis as a 1-D float64 array."""
        if isinstance(name_or_index, str):
            if name_or_index not in self.axes:
                raise DataError(f"axis {name_or_index!r} not found; axes are: "
                                f"{', '.join(self.axes)}")
            i = self.axes.index(name_or_index)
        else:
            i = int(name_or_index)
            if not -self.n_axes <= i < self.n_axes:
                raise DataError(f"axis index must be in [0, {self.n_axes - 1}], got {i}")
        return self.rate if self.rate.ndim == 1 else np.ascontiguousarray(self.rate[:, i])

    def to_frame(self) -> pd.DataFrame:
        """Columns ``time``, one per axis, and ``temperature`` if present."""
        data: dict[str, Any] = {"time": self.time}
        for i, name in enumerate(self.axes):
            data[name] = self.axis(i)
        if self.temperature is not None:
            data["temperature"] = self.temperature
        return pd.DataFrame(data)


# Set after the class is made, so that the dataclass sees ``time`` as a plain field without
# default (its signature and fields are unchanged); instances then store it through the
# descriptor, which forms a RegularTime on first access.
setattr(Run, "time", _TimeField())  # noqa: B010
