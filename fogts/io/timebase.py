"""The time base of a recording: time stamps in seconds, the sample rate and how regular
the sampling is (:class:`~fogts.io.run.SamplingReport`).

Time comes from a DatetimeIndex or TimedeltaIndex, or from a time column in seconds or
ISO-8601 date-times; it must increase strictly.  The sample rate is, in this order of
preference, the one given, ``1 / median step`` (``1 / mean step`` of the steps that are not
gaps for jittered stamps, and of all steps for burst-logged stamps) or the file's own (an
``.npz`` ``fs_hz`` key).
"""

from __future__ import annotations

import warnings

import numpy as np
import pandas as pd

from fogts._typing import FloatArray
from fogts.errors import DataError, DataQualityWarning
from fogts.io.run import SamplingReport
from fogts.io.table import NUMBER, Table, finite_and_bounded, numeric_column, where
from fogts.io.timesteps import LEAF, StepSummary, step_deviation, summarise_steps

__all__ = ["GAP_FACTOR", "GIVEN_RATE_TOLERANCE", "JITTERED_STAMPS", "REGULAR_JITTER", "Steps",
           "burst_logging_text", "check_given_rate", "is_numeric_time", "median_step", "sample_rate",
           "sampling_report", "step_stats", "time_base"]

#: Gap threshold: a time step longer than this multiple of the nominal step is a gap.
GAP_FACTOR = 1.5
#: A time base without gaps is regular when the std of its steps is below this share of
#: the nominal step.
REGULAR_JITTER = 0.01
#: Burst-logged time stamps said once: the read's warning, the data-quality line of
#: :class:`~fogts.preprocess.hygiene.DataQuality` and ``fogts info`` all use this wording.
BURST_LOGGED = ("the time stamps are logged in bursts: the sample rate is the mean step's{rate}, "
                "and the steps over 1.5 x the mean step are the bursts' pattern, not gaps, so "
                "no time is counted as missing")


def burst_logging_text(fs_hz: float | None = None) -> str:
    """The one sentence for burst-logged time stamps (:data:`BURST_LOGGED`), with the mean
    rate ``fs_hz`` when given.

    Examples
    --------
    >>> burst_logging_text(99.3171)[:72]
    "the time stamps are logged in bursts: the sample rate is the mean step's"
    """
    return BURST_LOGGED.format(rate="" if fs_hz is None else f" ({fs_hz:.6g} Hz)")


#: Fewest steps for which :func:`median_step` counts instead of sorting.
_COUNTED_MEDIAN_MIN = 1 << 16


class Steps:
    """The steps of a time base, ``numpy.diff(time)``: the array itself, or the time and
    the :class:`~fogts.io.timesteps.StepSummary` of one pass over it, the array then formed
    only if a statistic needs it (an irregular time base).

    :meth:`sample_rate` and :meth:`report` return what :func:`sample_rate` and
    :func:`sampling_report` return for the array, bit for bit.
    """

    def __init__(self, dt: FloatArray | None = None, *, time: FloatArray | None = None,
                 summary: StepSummary | None = None) -> None:
        self._dt, self._time, self._summary = dt, time, summary
        self._stats: tuple[float, float] | None = None

    def array(self) -> FloatArray:
        """The steps, formed on first use."""
        if self._dt is None:
            assert self._time is not None
            self._dt = np.diff(self._time)
        return self._dt

    def stats(self) -> tuple[float, float]:
        """:func:`step_stats`: the median and mean step."""
        if self._stats is None:
            median = self._summary.median() if self._summary is not None else None
            self._stats = ((median, self._summary.mean) if median is not None
                           and self._summary is not None else step_stats(self.array()))
        return self._stats

    def _regular(self, threshold: float) -> bool:
        """Whether the one-pass summary settles that no step exceeds ``threshold``."""
        return self._summary is not None and self._summary.longest <= threshold

    def sample_rate(self, given: float | None, from_file: float | None, source: str
                    ) -> tuple[float, str]:
        """:func:`sample_rate` of these steps."""
        if given is not None:  # said when it contradicts the steps (5: read_run's caller)
            check_given_rate(given, self.stats(), from_file, source, stacklevel=5)
            return given, "given"
        median, mean = self.stats()
        if self._regular(GAP_FACTOR * median):  # no long step: every step is a sample's
            return _rate_of_regular_steps(median, mean)
        return sample_rate(self.array(), given, from_file, source, steps=self.stats(),
                           stacklevel=5)  # one frame more than from _table_to_run

    def report(self, fs_hz: float, fs_source: str) -> SamplingReport:
        """:func:`sampling_report` of these steps."""
        nominal = 1.0 / fs_hz
        if not self._regular(GAP_FACTOR * nominal) or self._time is None:
            return sampling_report(self.array(), fs_hz, fs_source, steps=self.stats())
        assert self._summary is not None
        median, mean = self.stats()
        jitter = step_deviation(self._time, mean)  # no gap: every step is a normal one
        return SamplingReport(median, 0, self._summary.longest, (), jitter, jitter / nominal,
                              jitter / nominal < REGULAR_JITTER, True, mean, fs_source)


def time_base(table: Table, time_name: str | None
              ) -> tuple[FloatArray | None, str | None, Steps | None]:
    """Seconds since the first sample, the ISO-8601 start time (absolute stamps only) and
    the time steps; all None without a time index or time column.

    Above ``2 * LEAF`` stamps, the shifted time and the statistics of the steps are
    formed in one pass (:func:`~fogts.io.timesteps.summarise_steps`)."""
    origin: float | None = None
    if isinstance(table.from_index, pd.DatetimeIndex | pd.TimedeltaIndex):
        time, start = _datetime_seconds(table.from_index)
        name = "index"
    elif time_name is not None:
        fused = _fused_seconds(table, time_name)
        if fused is not None:
            return fused
        time, start = _time_seconds(table, time_name)
        origin = float(time[0])
        name = time_name
    else:
        return None, None, None
    if time.size > 2 * LEAF:
        time, summary = summarise_steps(np.ascontiguousarray(time, dtype=np.float64), origin)
        if summary.smallest > 0:
            return time, start, Steps(time=time, summary=summary)
    elif origin is not None:
        time = time - origin
    return time, start, Steps(_check_monotonic(time, name, table, origin or 0.0))


def _fused_seconds(table: Table, name: str
                   ) -> tuple[FloatArray, None, Steps] | None:
    """The time base of a long float time column in seconds from one pass, its values
    checked by it: stamps that increase strictly lie between the first and the last, so
    they are finite and within bounds when these two are.  None when the pass does not
    settle it (the general path then checks the column and names a bad cell)."""
    col = table.frame[name]
    if col.dtype != np.float64 or col.size <= 2 * LEAF:
        return None
    raw = np.ascontiguousarray(col.to_numpy())
    ends = raw[[0, -1]]
    if not finite_and_bounded(ends):
        return None
    time, summary = summarise_steps(raw, float(raw[0]))
    return (time, None, Steps(time=time, summary=summary)) if summary.smallest > 0 else None


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


def _check_monotonic(time: FloatArray, name: str, table: Table, origin: float = 0.0
                     ) -> FloatArray:
    """The steps of ``time`` (seconds since the first stamp); a step that is not positive
    is refused, naming the stamps as the file has them (``time + origin``)."""
    dt = np.diff(time)
    if dt.size and dt.min() <= 0:  # a pass without allocation before the search
        i = int(np.argmax(dt <= 0)) + 1
        kind = "duplicated" if dt[i - 1] == 0 else "decreasing"
        raise DataError(f"time column {name!r} is {kind} at {where(table, i)}: "
                        f"t={time[i] + origin:.9g} after t={time[i - 1] + origin:.9g}; time "
                        "stamps must be strictly increasing")
    return dt


def median_step(dt: FloatArray) -> float:
    """``np.median(dt)`` of positive time steps, bit for bit, in a few counting passes.

    The median is the k-th smallest step (for an even count, the mean of the k-th and the
    next).  A candidate from a strided sample of about 1000 steps is checked by counting
    the steps below and at it: time stamps written at a fixed rate take few distinct steps,
    so the candidate is the median.  Otherwise the steps within a narrow bracket around it
    are partitioned (about 6 % of them), and only when the bracket misses the median does
    this fall back to ``np.median``.

    Examples
    --------
    >>> dt = np.diff(np.arange(100_001) / 100.0)
    >>> median_step(dt) == float(np.median(dt))
    True
    """
    n = dt.size
    if n < _COUNTED_MEDIAN_MIN:
        return float(np.median(dt))
    ks = [n // 2 - 1, n // 2] if n % 2 == 0 else [n // 2]
    sample = np.sort(dt[::n // 1024])
    at = ks[0] * sample.size // n
    guess = sample[at]
    below = int(np.count_nonzero(dt < guess))
    if below <= ks[0] and ks[-1] < int(np.count_nonzero(dt <= guess)):
        picked = np.full(len(ks), guess)
    else:
        lo, hi = sample[max(at - 32, 0)], sample[min(at + 32, sample.size - 1)]
        below = int(np.count_nonzero(dt < lo))
        inside = dt[(dt >= lo) & (dt <= hi)]
        if not below <= ks[0] <= ks[-1] < below + inside.size:
            return float(np.median(dt))
        picked = np.partition(inside, [k - below for k in ks])[[k - below for k in ks]]
    return float(np.mean(picked))


def step_stats(dt: FloatArray) -> tuple[float, float]:
    """The median and the mean of the time steps (:func:`sample_rate` and
    :func:`sampling_report` both use them; computed once for both)."""
    return median_step(dt), float(np.mean(dt))


def sampling_report(dt: FloatArray | None, fs_hz: float, fs_source: str, *,
                    steps: tuple[float, float] | None = None) -> SamplingReport:
    """Measure gaps (steps > 1.5 x the nominal step ``1/fs_hz``) and jitter of a time base.

    ``steps``: ``step_stats(dt)``, when the caller has it already.
    """
    nominal = 1.0 / fs_hz
    if dt is None:
        return SamplingReport(nominal, 0, nominal, (), 0.0, 0.0, True, False, nominal, fs_source)
    median, mean = steps if steps is not None else step_stats(dt)
    longest = float(dt.max())
    gap_at = _steps_above(dt, GAP_FACTOR * nominal, longest)
    normal = np.delete(dt, gap_at) if gap_at.size else dt
    jitter = float(np.std(normal)) if normal.size > 1 else 0.0
    gap_rows = tuple(int(i) for i in gap_at[:100])
    jitter_rel = jitter / nominal
    return SamplingReport(
        median_dt_s=median,
        n_gaps=int(gap_at.size),
        max_gap_s=longest,
        gap_rows=gap_rows,
        jitter_s=jitter,
        jitter_rel=jitter_rel,
        regular=bool(not gap_at.size and jitter_rel < REGULAR_JITTER),
        from_time_column=True,
        mean_dt_s=mean,
        fs_source=fs_source,
    )


def _steps_above(dt: FloatArray, threshold: float, longest: float) -> np.ndarray:
    """Indices of the steps longer than ``threshold``; ``longest`` (``dt.max()``) spares
    the search in the usual case of none."""
    if longest <= threshold:
        return np.empty(0, dtype=np.intp)
    return np.flatnonzero(dt > threshold)


def _round_rate(fs: float) -> float:
    """Round a rate measured from float time stamps to 10 significant digits.

    Stamps such as ``i / 10`` give 1/median step = 10.000000000000568 Hz; the noise in the
    last digits is float rounding of the stamps, not information.
    """
    return float(f"{fs:.10g}")


#: Relative difference between the median and the mean of the regular steps above which
#: the stamps are jittered (quantised clock reads) and the mean is the period.
JITTERED_STAMPS = 1e-6


def _rate_of_regular_steps(median: float, mean: float) -> tuple[float, str]:
    """The rate of a record whose steps are all samples' (gaps left out): ``1 / median``,
    or ``1 / mean`` when the two differ by more than :data:`JITTERED_STAMPS`.

    Stamps read from a quantised or jittered clock have steps of a few discrete lengths
    whose median can sit one quantum off the true period (steps of 9.9, 10.0 and 10.1 ms
    with median 10.1 ms: every tau 1 % long); their mean, the elapsed time over the
    steps, is the period.  For clean stamps the two agree to rounding and the median is
    kept.

    Examples
    --------
    >>> _rate_of_regular_steps(0.01, 0.01 * (1 + 1e-12))
    (100.0, 'median step')
    >>> _rate_of_regular_steps(0.0101, 0.0099971)
    (100.0290084, 'mean of jittered steps')
    """
    if abs(mean / median - 1.0) > JITTERED_STAMPS:
        return _round_rate(1.0 / mean), "mean of jittered steps"
    return _round_rate(1.0 / median), "median step"


#: A given sample rate further than this (relative) from both rates of the time stamps, or
#: from the file's own rate, is reported (the burst-logging rule's 10 %).
GIVEN_RATE_TOLERANCE = 0.1


def check_given_rate(given: float, steps: tuple[float, float] | None,
                     from_file: float | None, source: str, *, stacklevel: int = 4) -> None:
    """Warn when a given sample rate contradicts what the file says: the rates of the
    median and the mean time step (``steps``, :func:`step_stats`) or the file's own rate.

    The given rate wins (it sets every tau and the gap threshold), so a wrong ``--fs``
    scales every tau; the warning shows both numbers.

    Examples
    --------
    >>> import warnings
    >>> with warnings.catch_warnings(record=True) as w:
    ...     warnings.simplefilter("always")
    ...     check_given_rate(10.0, (0.01, 0.01), None, "x.csv")
    >>> str(w[0].message).startswith("x.csv: fs_hz = 10 Hz (given) disagrees with")
    True
    """
    def far(rate: float) -> bool:
        return abs(given / rate - 1.0) > GIVEN_RATE_TOLERANCE

    said: str | None = None
    if steps is not None and steps[0] > 0 and steps[1] > 0:
        median, mean = steps
        if far(1.0 / median) and far(1.0 / mean):
            said = (f"the time stamps (median step {median:.6g} s: {1.0 / median:.6g} Hz; "
                    f"mean step {mean:.6g} s: {1.0 / mean:.6g} Hz)")
    elif from_file is not None and far(from_file):
        said = f"the file's own sample rate {from_file:.6g} Hz"
    if said is not None:
        warnings.warn(f"{source}: fs_hz = {given:.6g} Hz (given) disagrees with {said} by "
                      f"more than {100 * GIVEN_RATE_TOLERANCE:g} %; the given rate is used "
                      "for every tau", DataQualityWarning, stacklevel=stacklevel)


def _whole_multiples(ratio: FloatArray) -> bool:
    """True when most step ratios are close to whole numbers (dropped samples)."""
    return bool(np.median(np.abs(ratio - np.rint(ratio))) < 0.1)


def sample_rate(dt: FloatArray | None, given: float | None, from_file: float | None,
                source: str, *, steps: tuple[float, float] | None = None,
                stacklevel: int = 4) -> tuple[float, str]:
    """Pick the sample rate: given > median time step (the mean of the steps that are not
    gaps for jittered stamps, :func:`_rate_of_regular_steps`) > file metadata.

    Burst-logged stamps (samples buffered and stamped in clumps) make the median step far
    shorter than the true mean step.  When more than 5 % of the steps are longer than
    1.5 x the median (so the median does not describe the sampling; a few real gaps do not
    trigger this), the mean step is used and a warning is issued -- unless the long steps
    are whole multiples of the median step (median distance to the nearest multiple below
    0.1 step): that is a clock that dropped samples, so the median step is the rate and
    the long steps are gaps (:func:`sampling_report` lists them).
    """
    if given is not None:  # said when it contradicts the steps or the file's own rate
        check_given_rate(given, steps if steps is not None else
                         (step_stats(dt) if dt is not None else None), from_file, source,
                         stacklevel=stacklevel + 1)
        return given, "given"
    if dt is not None:
        median, mean = steps if steps is not None else step_stats(dt)
        gaps = _steps_above(dt, GAP_FACTOR * median, float(dt.max()))
        long = dt[gaps]
        if long.size <= 0.05 * dt.size or _whole_multiples(long / median):
            regular_mean = mean if gaps.size == 0 else float(
                (np.sum(dt) - np.sum(long)) / (dt.size - gaps.size))
            return _rate_of_regular_steps(median, regular_mean)
        # stacklevel (4 from _table_to_run): the warning names the caller of read_run
        # (the median step is over 10 % off the mean step: burst-logged time stamps)
        rate = _round_rate(1.0 / mean)
        warnings.warn(f"{source}: {burst_logging_text(rate)}", DataQualityWarning,
                      stacklevel=stacklevel)
        return rate, "mean step"
    if from_file is not None:
        return from_file, "file"
    raise DataError("no sample rate")
