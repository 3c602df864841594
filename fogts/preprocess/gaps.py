"""Gaps in the time base: steps longer than 1.5 x the nominal step ``1/fs``, the regular
segments between them, and a record cut to one segment.
"""

from __future__ import annotations

import dataclasses
import itertools
from dataclasses import dataclass
from typing import Any

import numpy as np
import pandas as pd

from fogts._typing import IntArray
from fogts._validate import check_positive
from fogts.errors import DataError
from fogts.io.run import Run, SamplingReport
from fogts.io.timebase import GAP_FACTOR, burst_logging_text, sampling_report

__all__ = ["Gap", "GapReport", "fill_gaps_nan", "find_gaps", "segment_run"]

#: Time steps examined at a time (bounds the temporary memory on 1e8-sample records).
CHUNK = 4_000_000
#: Gaps listed one by one (the count is always complete).
MAX_LISTED = 50


@dataclass(frozen=True)
class Gap:
    """One gap: the time base jumps from ``time_s`` to ``time_s + length_s`` after ``row``."""

    row: int
    time_s: float
    length_s: float


@dataclass(frozen=True)
class GapReport:
    """Gaps of a time base (steps longer than 1.5 x the nominal step).

    What :func:`find_gaps` returns; under ``gaps="split"``
    :func:`~fogts.preprocess.hygiene.assess_run` analyses its longest segment.

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
        The sample rate came from the mean step (burst-logged stamps): the steps over
        1.5 x the nominal step are then mostly the bursts' pattern, and ``missing_s``
        counts time that is not missing.
    longest : Gap or None
        The longest gap (anywhere in the record, not only among ``gaps``).
    """

    n_gaps: int
    missing_s: float
    largest_s: float
    gaps: tuple[Gap, ...]
    segments: tuple[tuple[int, int], ...]
    jitter_rel: float = 0.0
    burst_logged: bool = False
    longest: Gap | None = None

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
        longest = self.longest or max(self.gaps, key=lambda g: g.length_s)
        where = (f"first at t = {first.time_s:.6g} s, longest {longest.length_s:.4g} s at "
                 f"t = {longest.time_s:.6g} s")
        if self.burst_logged:
            return f"{burst_logging_text()} ({self.n_gaps} such step(s); {where})"
        return f"{self.n_gaps} gap(s) in the time base ({self.missing_s:.4g} s missing; {where})"


def find_gaps(time_s: Any, *, fs_hz: float, sampling: SamplingReport | None = None
              ) -> GapReport:
    """Every step longer than 1.5 x ``1/fs_hz`` in ``time_s`` and the regular segments
    between them (same rule as :func:`fogts.io.timebase.sampling_report`).

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
    top = int(np.argmax(lengths)) if after.size else None
    return GapReport(
        n_gaps=int(after.size),
        missing_s=float(np.sum(lengths - nominal)) if after.size else 0.0,
        largest_s=float(lengths.max()) if after.size else nominal,
        gaps=tuple(Gap(int(r), float(t[r]), float(d))
                   for r, d in zip(after[:MAX_LISTED], lengths[:MAX_LISTED], strict=True)),
        segments=segments, jitter_rel=float(jitter), burst_logged=bool(burst),
        longest=None if top is None else Gap(int(after[top]), float(t[after[top]]),
                                             float(lengths[top])))


def segment_run(run: Run, start: int, stop: int) -> Run:
    """``run`` restricted to rows ``[start, stop)``, its time (and angle) rebased to zero."""
    time = run.time[start:stop] - run.time[start]
    angle = None if run.angle is None else run.angle[start:stop + 1] - run.angle[start]
    dt = np.diff(time) if stop - start > 1 else None
    fs_source = run.sampling.fs_source if run.sampling is not None else "given"
    return dataclasses.replace(
        run, rate=run.rate[start:stop], time=time,
        temperature=None if run.temperature is None else run.temperature[start:stop],
        sampling=sampling_report(dt, run.fs_hz, fs_source),
        source=run.source, angle=angle)


def fill_gaps_nan(run: Run) -> Run:
    """``run`` on its regular grid ``k / fs`` (each sample at its nearest grid point), NaN
    where no sample fell: the input of the gap-robust ADEV (:func:`fogts.allan.gradev.
    gradev`).  Temperature gets NaN there too; an angle record's angle is dropped.

    Examples
    --------
    >>> import numpy as np
    >>> from fogts.io.run import Run
    >>> t = np.r_[0.0, 0.1, 0.2, 0.5, 0.6]
    >>> run = Run(rate=np.arange(5.0), time=t, fs_hz=10.0, units="deg/h", axes=("rate",))
    >>> fill_gaps_nan(run).rate.tolist()
    [0.0, 1.0, 2.0, nan, nan, 3.0, 4.0]
    """
    slot = np.rint(run.time * run.fs_hz).astype(np.int64)
    shared = int(np.count_nonzero(np.diff(slot) <= 0))
    if shared:
        raise DataError(
            f"{run.source}: gaps='nan' puts each sample at its nearest grid "
            f"point k/fs ({run.fs_hz:.6g} Hz), and {shared:,} sample(s) would land on the point "
            "of the sample before (time stamps logged in bursts, or jittering by half a step), "
            "merging samples: use gaps='warn' (analysed as regular) or gaps='split'")
    size = int(slot[-1]) + 1
    shape = (size,) if run.rate.ndim == 1 else (size, run.rate.shape[1])
    rate = np.full(shape, np.nan)
    rate[slot] = run.rate
    temperature = None
    if run.temperature is not None:
        temperature = np.full(size, np.nan)
        temperature[slot] = run.temperature
    time = np.arange(size, dtype=np.float64) / run.fs_hz
    return dataclasses.replace(
        run, rate=rate, time=time, temperature=temperature, angle=None,
        sampling=sampling_report(np.diff(time), run.fs_hz, "given"))
