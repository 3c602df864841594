"""Data hygiene of one recording: units, missing cells, gaps and glitches, said up front.

Every command runs :func:`assess_run` right after reading, so that what could make an
answer wrong is printed before the answer, and recorded in the JSON:

* the rate unit was assumed (no unit in the column names, no ``--units``);
* empty/NaN cells were dropped or interpolated (:class:`fogts.io.run.MissingReport`);
* the time base has gaps (:class:`GapReport`), handled by the gap policy: ``warn``
  (analyse as if regular and say so), ``error``, ``split`` (the longest regular
  segment) or ``ignore`` (no warning; still recorded);
* glitches: samples far outside the noise that arrive by a jump (:func:`detect_glitches`).

Nothing here changes the data except ``gaps="split"``, which is recorded.
"""

from __future__ import annotations

import dataclasses
import itertools
from dataclasses import dataclass
from typing import Any, Literal

import numpy as np
import pandas as pd

from fogts._typing import FloatArray, IntArray
from fogts._validate import check_choice, check_positive
from fogts.errors import DataError
from fogts.io.run import MissingReport, Run, SamplingReport

__all__ = [
    "GAP_POLICIES",
    "GLITCH_SIGMAS",
    "DataQuality",
    "Gap",
    "GapReport",
    "Glitch",
    "GlitchReport",
    "assess_run",
    "detect_glitches",
    "find_gaps",
]

GapPolicy = Literal["warn", "error", "split", "ignore"]
#: What a command may do with a time base that has gaps.
GAP_POLICIES: tuple[str, ...] = ("warn", "error", "split", "ignore")
#: A step longer than this multiple of the nominal step 1/fs is a gap (as in
#: :func:`fogts.io.reader.sampling_report`).
GAP_FACTOR = 1.5
#: Default glitch threshold in robust sigmas.  A white Gaussian sample is flagged only if
#: it is beyond 7 sigma from the median *and* the step into or out of it is beyond 7 sigma
#: of the first difference.  The first condition alone has P(|Z| > 7) = 2.6e-12, i.e.
#: 2.6e-4 expected false alarms in 1e8 samples; the second makes it rarer still.
GLITCH_SIGMAS = 7.0
#: MAD -> sigma for Gaussian data, 1 / Phi^-1(3/4) (Hampel 1974; Rousseeuw & Croux 1993).
MAD_TO_SIGMA = 1.482602218505602
#: Robust scales are estimated on at most this many evenly strided samples (the
#: sampling error of a MAD from 2e6 points is about 0.05 %).
SCALE_SAMPLES = 2_000_000
#: Samples processed at a time (bounds the temporary memory on 1e8-sample records).
CHUNK = 4_000_000
#: Gaps and glitch events listed one by one (the counts are always complete).
MAX_LISTED = 50
#: A glitch event longer than this is described as a level shift.
LEVEL_SHIFT_S = 1.0


# --------------------------------------------------------------------------- glitches


@dataclass(frozen=True)
class Glitch:
    """One glitch event: consecutive samples beyond the threshold, entered or left by a
    jump.

    Attributes
    ----------
    row : int
        Row (0-based) of the sample farthest from the median.
    time_s : float
        Its time stamp (seconds since the first sample).
    n_samples : int
        Samples in the event.
    value : float
        The rate at ``row``.
    sigmas : float
        ``(value - median) / sigma`` of the rate.
    duration_s : float
        From the first to the last sample of the event; beyond :data:`LEVEL_SHIFT_S` the
        event is described as a level shift (a jump that does not come back).
    """

    row: int
    time_s: float
    n_samples: int
    value: float
    sigmas: float
    duration_s: float = 0.0

    def describe(self, units: str) -> str:
        what = (f"level shift lasting {self.duration_s:.4g} s" if self.duration_s > LEVEL_SHIFT_S
                else f"{self.n_samples} sample{'s' if self.n_samples > 1 else ''}")
        return (f"t = {self.time_s:.6g} s: {self.value:.4g} {units} ({self.sigmas:+.0f} sigma"
                f", {what})".replace("  (", " ("))


@dataclass(frozen=True)
class GlitchReport:
    """Glitches of one axis (see :func:`detect_glitches`).

    Attributes
    ----------
    axis : str
    threshold : float
        In robust sigmas.
    median : float
    sigma_rate, sigma_diff : float
        Robust standard deviations of the rate and of its first difference.
    scale : str
        How the sigmas were estimated (``"MAD"`` or the fallback used for coarsely
        quantised data).
    n_flagged : int
        Samples in all events.
    n_events : int
    events : tuple of Glitch
        The first :data:`MAX_LISTED` events, in time order.
    """

    axis: str
    units: str
    threshold: float
    median: float
    sigma_rate: float
    sigma_diff: float
    scale: str
    n_flagged: int
    n_events: int
    events: tuple[Glitch, ...]

    def to_dict(self) -> dict[str, Any]:
        return {"axis": self.axis, "units": self.units, "threshold_sigma": self.threshold, "median": self.median,
                "sigma_rate": self.sigma_rate, "sigma_diff": self.sigma_diff,
                "scale": self.scale, "n_flagged": self.n_flagged, "n_events": self.n_events,
                "events": [dataclasses.asdict(e) for e in self.events]}

    def to_frame(self) -> pd.DataFrame:
        """One row per listed event."""
        return pd.DataFrame([dataclasses.asdict(e) for e in self.events],
                            columns=["row", "time_s", "n_samples", "value", "sigmas",
                                     "duration_s"])

    def summary(self, shown: int = 3) -> str:
        """``"1 glitch ... beyond 7 robust sigmas: t = 4046 s: -17 deg/s (-47 sigma, ...)"``;
        the ``shown`` largest events first."""
        if self.n_events == 0:
            return f"no glitch beyond {self.threshold:g} robust sigmas"
        largest = sorted(self.events, key=lambda e: -abs(e.sigmas))[:shown]
        listed = "; ".join(e.describe(self.units) for e in largest)
        more = self.n_events - len(largest)
        tail = f"; and {more} more (all counted in the JSON)" if more > 0 else ""
        plural = "es" if self.n_events > 1 else ""
        return (f"{self.n_events} glitch{plural} ({self.n_flagged} sample(s)) beyond "
                f"{self.threshold:g} robust sigmas: {listed}{tail}")


def _robust_sigma(values: FloatArray) -> tuple[float, float, str]:
    """Median and a robust sigma that is never zero unless the data are constant.

    1.4826 MAD first; coarsely quantised sensors (most samples on one grid value) can give
    MAD = 0, then half the 15.9..84.1 % inter-quantile range, then the standard deviation
    of the central 98 %, then the plain standard deviation."""
    med = float(np.median(values))
    mad = MAD_TO_SIGMA * float(np.median(np.abs(values - med)))
    if mad > 0:
        return med, mad, "MAD"
    lo, hi = np.quantile(values, [0.15865525393145707, 0.8413447460685429])
    if hi > lo:
        return med, float(hi - lo) / 2.0, "inter-quantile range (MAD = 0: quantised data)"
    q01, q99 = np.quantile(values, [0.01, 0.99])
    central = values[(values >= q01) & (values <= q99)]
    if central.size > 1 and np.std(central) > 0:
        return med, float(np.std(central)), "std of the central 98 % (quantised data)"
    return med, float(np.std(values)), "standard deviation (quantised data)"


def _strided(x: FloatArray, limit: int = SCALE_SAMPLES) -> FloatArray:
    return x[:: max(1, x.size // limit)]


def _jump_rows(x: FloatArray, med: float, limit_x: float, limit_d: float) -> IntArray:
    """Rows beyond ``limit_x`` from the median whose step in or out exceeds ``limit_d``."""
    found: list[IntArray] = []
    for start in range(0, x.size, CHUNK):
        lo, hi = max(start - 1, 0), min(start + CHUNK + 1, x.size)
        seg = x[lo:hi]
        far = np.abs(seg - med) > limit_x
        step = np.abs(np.diff(seg)) > limit_d
        jump = np.zeros(seg.size, dtype=bool)
        jump[1:] |= step
        jump[:-1] |= step
        rows = np.flatnonzero(far & jump) + lo
        found.append(rows[(rows >= start) & (rows < start + CHUNK)])
    return np.unique(np.concatenate(found)) if found else np.empty(0, np.int64)


def _run_bounds(far_of: Any, row: int, n: int) -> tuple[int, int]:
    """First and one-past-last row of the run of far-from-median samples around ``row``."""
    lo = row
    width = 16
    while lo > 0:
        a = max(lo - width, 0)
        block = far_of(a, lo)
        near = np.flatnonzero(~block)
        if near.size:
            lo = a + int(near[-1]) + 1
            break
        lo, width = a, width * 2
    hi = row + 1
    width = 16
    while hi < n:
        b = min(hi + width, n)
        near = np.flatnonzero(~far_of(hi, b))
        if near.size:
            hi = hi + int(near[0])
            break
        hi, width = b, width * 2
    return lo, hi


def detect_glitches(
    x: Any,
    *,
    time_s: Any = None,
    fs_hz: float | None = None,
    threshold: float = GLITCH_SIGMAS,
    axis: str = "rate",
    units: str = "",
) -> GlitchReport:
    """Find glitches: samples far outside the noise that arrive or leave by a jump.

    A sample is a *jump sample* when it is more than ``threshold`` robust sigmas from the
    median of the rate **and** the step into it or out of it is more than ``threshold``
    robust sigmas of the first difference.  An event is the run of consecutive samples
    beyond the rate threshold that contains a jump sample, so a one-sample spike, a burst
    of corrupt samples and a jump to a new level are all found, while a slow drift or a
    rate random walk (far from the median, but by small steps) and honest white noise are
    not.  Robust sigmas are 1.4826 x MAD (Hampel 1974; Rousseeuw & Croux 1993, JASA 88,
    1273), as in Stable32's MAD outlier screen, with fallbacks for quantised data.

    Parameters
    ----------
    x : array_like, shape (n,)
        One rate axis.
    time_s : array_like, optional
        Time stamps (for the event times); default ``row / fs_hz``.
    fs_hz : float, optional
        Needed when ``time_s`` is not given.
    threshold : float
        In robust sigmas; the default :data:`GLITCH_SIGMAS` flags nothing by chance in
        1e8 white Gaussian samples.
    axis, units : str
        Labels for the report.

    Returns
    -------
    GlitchReport

    Examples
    --------
    >>> import numpy as np
    >>> x = np.random.default_rng(1).standard_normal(100_000)
    >>> x[40_000] = 60.0
    >>> rep = detect_glitches(x, fs_hz=100.0, units="deg/h")
    >>> rep.n_events, rep.events[0].time_s
    (1, 400.0)
    """
    values = np.ascontiguousarray(x, dtype=np.float64)
    if values.ndim != 1 or values.size < 3:
        raise DataError(f"x must be one axis of at least 3 samples, got shape {values.shape}")
    threshold = check_positive("threshold", threshold)
    med, sig_x, how = _robust_sigma(_strided(values))
    _, sig_d, how_d = _robust_sigma(_strided(np.diff(_strided(values, 4 * SCALE_SAMPLES))
                                             if values.size > 4 * SCALE_SAMPLES
                                             else np.diff(values)))
    scale = how if how == how_d else f"{how} (rate), {how_d} (difference)"
    if sig_x == 0 or sig_d == 0:
        return GlitchReport(axis, units, threshold, med, sig_x, sig_d, scale, 0, 0, ())
    rows = _jump_rows(values, med, threshold * sig_x, threshold * sig_d)

    def far_of(a: int, b: int) -> np.ndarray:
        return np.abs(values[a:b] - med) > threshold * sig_x

    events: list[tuple[int, int]] = []
    for r in rows:
        if events and r < events[-1][1]:
            continue  # inside the previous event
        events.append(_run_bounds(far_of, int(r), values.size))
    times = (np.asarray(time_s, dtype=np.float64) if time_s is not None else None)
    if times is None and fs_hz is None:
        raise DataError("detect_glitches needs time_s or fs_hz to time the events")
    listed = []
    for lo, hi in events[:MAX_LISTED]:
        peak = lo + int(np.argmax(np.abs(values[lo:hi] - med)))
        def at(row: int) -> float:
            return float(times[row]) if times is not None else row / float(fs_hz)  # type: ignore[arg-type]

        listed.append(Glitch(peak, at(peak), hi - lo, float(values[peak]),
                             float((values[peak] - med) / sig_x), at(hi - 1) - at(lo)))
    flagged = int(sum(hi - lo for lo, hi in events))
    return GlitchReport(axis, units, threshold, med, sig_x, sig_d, scale, flagged, len(events),
                        tuple(listed))


# --------------------------------------------------------------------------- gaps


@dataclass(frozen=True)
class Gap:
    """One gap: the time base jumps from ``time_s`` to ``time_s + length_s`` after ``row``."""

    row: int
    time_s: float
    length_s: float


@dataclass(frozen=True)
class GapReport:
    """Gaps of a time base (steps longer than 1.5 x the nominal step).

    Attributes
    ----------
    n_gaps : int
    missing_s : float
        Time not covered by samples: the sum over gaps of (step - nominal step).
    largest_s : float
        Longest step.
    gaps : tuple of Gap
        The first :data:`MAX_LISTED` gaps.
    segments : tuple of (int, int)
        Row ranges ``[start, stop)`` of the regular stretches between gaps (all of them).
    jitter_rel : float
        Jitter of the non-gap steps relative to the nominal step.
    burst_logged : bool
        The sample rate came from the mean step (burst-logged stamps).
    """

    n_gaps: int
    missing_s: float
    largest_s: float
    gaps: tuple[Gap, ...]
    segments: tuple[tuple[int, int], ...]
    jitter_rel: float = 0.0
    burst_logged: bool = False

    @property
    def regular(self) -> bool:
        return self.n_gaps == 0 and self.jitter_rel < 0.01

    def longest_segment(self) -> tuple[int, int]:
        return max(self.segments, key=lambda s: (s[1] - s[0], -s[0]))

    def to_dict(self) -> dict[str, Any]:
        return {"n_gaps": self.n_gaps, "missing_s": self.missing_s,
                "largest_s": self.largest_s, "jitter_rel": self.jitter_rel,
                "burst_logged": self.burst_logged, "n_segments": len(self.segments),
                "gaps": [dataclasses.asdict(g) for g in self.gaps]}

    def to_frame(self) -> pd.DataFrame:
        """One row per listed gap."""
        return pd.DataFrame([dataclasses.asdict(g) for g in self.gaps],
                            columns=["row", "time_s", "length_s"])

    def summary(self) -> str:
        if self.n_gaps == 0:
            return "no gaps in the time base"
        first = self.gaps[0]
        longest = max(self.gaps, key=lambda g: g.length_s)
        return (f"{self.n_gaps} gap(s) in the time base ({self.missing_s:.4g} s missing; "
                f"first at t = {first.time_s:.6g} s, longest {longest.length_s:.4g} s at "
                f"t = {longest.time_s:.6g} s)")


def find_gaps(time_s: Any, *, fs_hz: float, sampling: SamplingReport | None = None
              ) -> GapReport:
    """Every step longer than 1.5 x ``1/fs_hz`` in ``time_s`` and the regular segments
    between them (same rule as :func:`fogts.io.reader.sampling_report`).

    Examples
    --------
    >>> import numpy as np
    >>> t = np.r_[np.arange(100), np.arange(150, 200)] / 10.0
    >>> rep = find_gaps(t, fs_hz=10.0)
    >>> rep.n_gaps, rep.gaps[0].time_s, rep.segments
    (1, 9.9, ((0, 100), (100, 150)))
    """
    t = np.asarray(time_s, dtype=np.float64)
    fs_hz = check_positive("fs_hz", fs_hz)
    nominal = 1.0 / fs_hz
    rows: list[IntArray] = []
    for start in range(0, max(t.size - 1, 0), CHUNK):
        step = np.diff(t[start:start + CHUNK + 1])
        rows.append(np.flatnonzero(step > GAP_FACTOR * nominal) + start)
    after = np.concatenate(rows) if rows else np.empty(0, np.int64)
    lengths = t[after + 1] - t[after]
    bounds = np.r_[0, after + 1, t.size]
    segments = tuple((int(a), int(b)) for a, b in itertools.pairwise(bounds.tolist()))
    jitter = sampling.jitter_rel if sampling is not None else 0.0
    burst = sampling is not None and sampling.fs_source == "mean step"
    return GapReport(
        n_gaps=int(after.size),
        missing_s=float(np.sum(lengths - nominal)) if after.size else 0.0,
        largest_s=float(lengths.max()) if after.size else nominal,
        gaps=tuple(Gap(int(r), float(t[r]), float(d))
                   for r, d in zip(after[:MAX_LISTED], lengths[:MAX_LISTED], strict=True)),
        segments=segments, jitter_rel=float(jitter), burst_logged=bool(burst))


def _segment_run(run: Run, start: int, stop: int) -> Run:
    """``run`` restricted to rows ``[start, stop)``, its time rebased to zero."""
    from fogts.io.reader import sampling_report

    time = run.time[start:stop] - run.time[start]
    dt = np.diff(time) if stop - start > 1 else None
    fs_source = run.sampling.fs_source if run.sampling is not None else "given"
    return dataclasses.replace(
        run, rate=run.rate[start:stop], time=time,
        temperature=None if run.temperature is None else run.temperature[start:stop],
        sampling=sampling_report(dt, run.fs_hz, fs_source),
        source=run.source)


# --------------------------------------------------------------------------- together


@dataclass(frozen=True)
class DataQuality:
    """What :func:`assess_run` found, and what it did (only ``gaps="split"`` changes the
    data: the longest regular segment is analysed).

    Attributes
    ----------
    source, units, units_source : str
    missing : MissingReport or None
    gap_policy : str
    gaps : GapReport
    segment : tuple of (int, int) or None
        Rows analysed under ``gaps="split"`` (None otherwise).
    n_input : int
        Samples read (before any split).
    glitches : tuple of GlitchReport
        One per axis (empty when glitch detection was off).
    """

    source: str
    units: str
    units_source: str
    axes: tuple[str, ...]
    missing: MissingReport | None
    gap_policy: str
    gaps: GapReport
    segment: tuple[int, int] | None
    n_input: int
    fs_hz: float
    glitches: tuple[GlitchReport, ...] = ()

    def glitch_count(self, axis: str) -> int:
        """Glitch events found on ``axis`` (0 when detection was off)."""
        return next((g.n_events for g in self.glitches if g.axis == axis), 0)

    def warnings(self) -> list[str]:
        """The lines a command prints (after ``warning: <file>:``) before its output."""
        out: list[str] = []
        if self.units_source == "assumed":
            cols = ", ".join(repr(a) for a in self.axes)
            out.append(f"no unit in the rate column(s) {cols}; assuming {self.units}; pass "
                       "--units (deg/h, deg/s, rad/s, arcsec/s)")
        if self.missing is not None:
            out.append(self.missing.summary())
        out += self._gap_lines()
        out += [f"axis {g.axis!r}: {g.summary()}; kept in the analysis (--outliers K "
                "replaces samples beyond K robust sigmas)" for g in self.glitches
                if g.n_events]
        return out

    def _gap_lines(self) -> list[str]:
        g = self.gaps
        if self.gap_policy == "ignore" or g.n_gaps == 0:
            return [] if self.gap_policy == "ignore" or g.jitter_rel < 0.01 or g.burst_logged \
                else [f"time steps jitter by {100 * g.jitter_rel:.3g} % of the nominal step; "
                      "analysed as if regular"]
        if self.segment is not None:
            a, b = self.segment
            return [f"{g.summary()}; --gaps split: analysing the longest regular segment, "
                    f"rows {a}..{b - 1} ({b - a:,} of {self.n_input:,} samples, "
                    f"{(b - a) / self.fs_hz:.6g} s) of {len(g.segments)}"]
        return [f"{g.summary()}; analysed as if the samples were regular (--gaps split "
                "analyses the longest regular segment, --gaps error refuses the file)"]

    def to_dict(self) -> dict[str, Any]:
        return {"units": self.units, "units_source": self.units_source,
                "missing": self.missing.to_dict() if self.missing is not None else None,
                "gap_policy": self.gap_policy, "gaps": self.gaps.to_dict(),
                "segment": ({"start_row": self.segment[0], "stop_row": self.segment[1],
                             "n": self.segment[1] - self.segment[0]}
                            if self.segment is not None else None),
                "glitches": [g.to_dict() for g in self.glitches],
                "warnings": self.warnings()}

    def to_frame(self) -> pd.DataFrame:
        """One row per warning (``issue``, ``text``): empty when nothing was found."""
        return pd.DataFrame({"text": self.warnings()}, dtype=object)

    def summary(self) -> str:
        lines = self.warnings()
        return "\n".join(lines) if lines else "no data-quality issue found"


def assess_run(run: Run, *, gaps: GapPolicy = "warn", glitches: bool = True,
               glitch_threshold: float = GLITCH_SIGMAS) -> tuple[Run, DataQuality]:
    """Check one recording before analysis: units, missing cells, gaps, glitches.

    Parameters
    ----------
    run : Run
    gaps : {"warn", "error", "split", "ignore"}
        ``warn``: analyse as if regular, and say so; ``error``: raise if there are gaps;
        ``split``: return the longest regular segment; ``ignore``: no warning (the gaps
        are still in the report).
    glitches : bool
        Run :func:`detect_glitches` on every axis.
    glitch_threshold : float
        In robust sigmas.

    Returns
    -------
    (Run, DataQuality)
        The run to analyse (a segment under ``split``) and what was found.

    Raises
    ------
    DataError
        ``gaps="error"`` and the time base has gaps.

    Examples
    --------
    >>> import numpy as np
    >>> from fogts.io.reader import read_run
    >>> run, q = assess_run(read_run(np.random.default_rng(0).standard_normal(1000),
    ...                              fs_hz=10.0))
    >>> q.warnings()
    ["no unit in the rate column(s) 'rate'; assuming deg/h; pass --units (deg/h, deg/s, rad/s, arcsec/s)"]
    """
    check_choice("gaps", gaps, GAP_POLICIES)
    report = find_gaps(run.time, fs_hz=run.fs_hz, sampling=run.sampling) \
        if run.sampling is not None and run.sampling.n_gaps else \
        GapReport(0, 0.0, 1.0 / run.fs_hz, (), ((0, run.n),),
                  run.sampling.jitter_rel if run.sampling is not None else 0.0,
                  run.sampling is not None and run.sampling.fs_source == "mean step")
    if gaps == "error" and report.n_gaps:
        raise DataError(f"{run.source}: {report.summary()}; gaps='error' (CLI --gaps error) "
                        "refuses it: pass gaps='split' to analyse the longest regular "
                        "segment or gaps='warn'")
    segment = report.longest_segment() if gaps == "split" and report.n_gaps else None
    n_input = run.n
    if segment is not None:
        run = _segment_run(run, *segment)
    found = tuple(detect_glitches(run.axis(i), time_s=run.time, threshold=glitch_threshold,
                                  axis=name, units=run.units)
                  for i, name in enumerate(run.axes)) if glitches else ()
    quality = DataQuality(run.source, run.units, run.units_source, run.axes, run.missing,
                          gaps, report, segment, n_input, run.fs_hz, found)
    return run, quality
