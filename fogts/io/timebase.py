"""The time base of a recording: time stamps in seconds, the sample rate and how regular
the sampling is (:class:`~fogts.io.run.SamplingReport`).

Time comes from a DatetimeIndex or TimedeltaIndex, or from a time column in seconds or
ISO-8601 date-times; it must increase strictly.  The sample rate is, in this order of
preference, the one given, ``1 / median step`` (``1 / mean step`` for burst-logged stamps)
or the file's own (an ``.npz`` ``fs_hz`` key).
"""

from __future__ import annotations

import warnings

import numpy as np
import pandas as pd

from fogts._typing import FloatArray
from fogts.errors import DataError, DataQualityWarning
from fogts.io.run import SamplingReport
from fogts.io.table import NUMBER, Table, numeric_column, where

__all__ = ["GAP_FACTOR", "is_numeric_time", "sample_rate", "sampling_report", "time_base"]

#: Gap threshold: a time step longer than this multiple of the nominal step is a gap.
GAP_FACTOR = 1.5


def time_base(table: Table, time_name: str | None
              ) -> tuple[FloatArray | None, str | None, FloatArray | None]:
    """Seconds since the first sample, the ISO-8601 start time (absolute stamps only) and
    the time steps; all None without a time index or time column."""
    if isinstance(table.from_index, pd.DatetimeIndex | pd.TimedeltaIndex):
        time, start = _datetime_seconds(table.from_index)
        name = "index"
    elif time_name is not None:
        time, start = _time_seconds(table, time_name)
        time = time - time[0]
        name = time_name
    else:
        return None, None, None
    dt = _check_monotonic(time, name, table)
    return time, start, dt


def is_numeric_time(table: Table, name: str) -> bool:
    """True when the time column holds seconds (not date-times)."""
    return table.frame[name].dtype.kind in "fiu" or bool(
        NUMBER.match(str(table.frame[name].iloc[0]).strip()))


def _time_seconds(table: Table, name: str) -> tuple[FloatArray, str | None]:
    col = table.frame[name]
    if col.dtype.kind in "fiu":
        return numeric_column(table, name), None
    if col.dtype.kind == "M" or isinstance(col.dtype, pd.DatetimeTZDtype):
        return _datetime_seconds(pd.DatetimeIndex(col))
    sample = str(col.iloc[0]).strip()
    if NUMBER.match(sample) or sample.lower() in ("nan", "inf", "-inf"):
        return numeric_column(table, name), None
    try:
        stamps = pd.to_datetime(col.astype(str).str.strip(), format="ISO8601")
    except (ValueError, TypeError) as exc:
        raise DataError(f"time column {name!r} is neither seconds nor ISO-8601 date-times "
                        f"(first value {sample!r}): {exc}") from None
    if stamps.isna().any():
        row = int(np.argmax(stamps.isna().to_numpy()))
        raise DataError(f"time column {name!r} has an empty or invalid time stamp at "
                        f"{where(table, row)}")
    return _datetime_seconds(pd.DatetimeIndex(stamps))


def _datetime_seconds(index: pd.DatetimeIndex | pd.TimedeltaIndex) -> tuple[FloatArray, str | None]:
    if isinstance(index, pd.TimedeltaIndex):
        delta = index - index[0]
        return np.asarray(delta.total_seconds(), dtype=np.float64), None
    delta = index - index[0]
    seconds = np.asarray(pd.TimedeltaIndex(delta).total_seconds(), dtype=np.float64)
    return seconds, index[0].isoformat()


def _check_monotonic(time: FloatArray, name: str, table: Table) -> FloatArray:
    dt = np.diff(time)
    bad = dt <= 0
    if bad.any():
        i = int(np.argmax(bad)) + 1
        kind = "duplicated" if dt[i - 1] == 0 else "decreasing"
        raise DataError(f"time column {name!r} is {kind} at {where(table, i)}: "
                        f"t={time[i]:.9g} after t={time[i - 1]:.9g}; time stamps must be "
                        "strictly increasing")
    return dt


def sampling_report(dt: FloatArray | None, fs_hz: float, fs_source: str) -> SamplingReport:
    """Measure gaps (steps > 1.5 x the nominal step ``1/fs_hz``) and jitter of a time base."""
    nominal = 1.0 / fs_hz
    if dt is None:
        return SamplingReport(nominal, 0, nominal, (), 0.0, 0.0, True, False, nominal, fs_source)
    median = float(np.median(dt))
    gaps = dt > GAP_FACTOR * nominal
    normal = dt[~gaps]
    jitter = float(np.std(normal)) if normal.size > 1 else 0.0
    gap_rows = tuple(int(i) for i in np.flatnonzero(gaps)[:100])
    jitter_rel = jitter / nominal
    return SamplingReport(
        median_dt_s=median,
        n_gaps=int(gaps.sum()),
        max_gap_s=float(dt.max()),
        gap_rows=gap_rows,
        jitter_s=jitter,
        jitter_rel=jitter_rel,
        regular=bool(not gaps.any() and jitter_rel < 0.01),
        from_time_column=True,
        mean_dt_s=float(np.mean(dt)),
        fs_source=fs_source,
    )


def _round_rate(fs: float) -> float:
    """Round a rate measured from float time stamps to 10 significant digits.

    Stamps such as ``i / 10`` give 1/median step = 10.000000000000568 Hz; the noise in the
    last digits is float rounding of the stamps, not information.
    """
    return float(f"{fs:.10g}")


def _whole_multiples(ratio: FloatArray) -> bool:
    """True when most step ratios are close to whole numbers (dropped samples)."""
    return bool(np.median(np.abs(ratio - np.rint(ratio))) < 0.1)


def sample_rate(dt: FloatArray | None, given: float | None, from_file: float | None,
                source: str) -> tuple[float, str]:
    """Pick the sample rate: given > median time step > file metadata.

    Burst-logged stamps (samples buffered and stamped in clumps) make the median step far
    shorter than the true mean step.  When more than 5 % of the steps are longer than
    1.5 x the median (so the median does not describe the sampling; a few real gaps do not
    trigger this), the mean step is used and a warning is issued -- unless the long steps
    are whole multiples of the median step (median distance to the nearest multiple below
    0.1 step): that is a clock that dropped samples, so the median step is the rate and
    the long steps are gaps (:func:`sampling_report` lists them).
    """
    if given is not None:
        return given, "given"
    if dt is not None:
        median, mean = float(np.median(dt)), float(np.mean(dt))
        long = dt[dt > GAP_FACTOR * median]
        if long.size <= 0.05 * dt.size or _whole_multiples(long / median):
            return _round_rate(1.0 / median), "median step"
        # stacklevel 4: the warning names the caller of read_run
        warnings.warn(f"{source}: median time step {median:.6g} s differs from the mean step "
                      f"{mean:.6g} s by more than 10 % (burst-logged time stamps); using the "
                      f"mean rate {1.0 / mean:.6g} Hz", DataQualityWarning, stacklevel=4)
        return _round_rate(1.0 / mean), "mean step"
    if from_file is not None:
        return from_file, "file"
    raise DataError("no sample rate")
