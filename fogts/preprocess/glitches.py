"""Glitches: samples far outside the noise that arrive or leave by a jump.

A one-sample spike, a burst of corrupt samples and a jump to a new level are found; a slow
drift, a rate random walk and honest white noise are not.  Robust sigmas are
1.4826 x MAD (Hampel 1974; Rousseeuw & Croux 1993), with fallbacks for quantized data.
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass
from typing import Any

import numpy as np
import pandas as pd

from fogts._typing import ArrayLike1D, FloatArray, IntArray
from fogts._validate import check_positive
from fogts.errors import DataError

__all__ = ["GLITCH_SIGMAS", "MAD_TO_SIGMA", "Glitch", "GlitchReport", "detect_glitches"]

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
#: Samples per block of the search for far rows (1 MiB of float64: its minimum and
#: maximum are taken while it is in the cache; bounds the temporary memory).
CHUNK = 1 << 17
#: Glitch events listed one by one (the count is always complete).
MAX_LISTED = 50
#: A glitch event longer than this is described as a level shift.
LEVEL_SHIFT_S = 1.0


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
        quantized data).
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

    1.4826 MAD first; coarsely quantized sensors (most samples on one grid value) can give
    MAD = 0, then half the 15.9..84.1 % inter-quantile range, then the standard deviation
    of the central 98 %, then the plain standard deviation."""
    med = float(np.median(values))
    mad = MAD_TO_SIGMA * float(np.median(np.abs(values - med)))
    if mad > 0:
        return med, mad, "MAD"
    lo, hi = np.quantile(values, [0.15865525393145707, 0.8413447460685429])
    if hi > lo:
        return med, float(hi - lo) / 2.0, "inter-quantile range (MAD = 0: quantized data)"
    q01, q99 = np.quantile(values, [0.01, 0.99])
    central = values[(values >= q01) & (values <= q99)]
    if central.size > 1 and np.std(central) > 0:
        return med, float(np.std(central)), "std of the central 98 % (quantized data)"
    return med, float(np.std(values)), "standard deviation (quantized data)"


def _strided(x: FloatArray, limit: int = SCALE_SAMPLES) -> FloatArray:
    return x[:: max(1, x.size // limit)]


def _strided_steps(x: FloatArray) -> FloatArray:
    """``_strided(numpy.diff(_strided(x, 4 * SCALE_SAMPLES)))`` without forming the
    intermediate difference: the steps ``x[a + s] - x[a]`` between neighbours of the
    thinned series ``x[::s]`` at every ``t``-th position, read straight from ``x``."""
    s = max(1, x.size // (4 * SCALE_SAMPLES))
    steps = (x.size - 1) // s  # len(x[::s]) - 1
    t = max(1, steps // SCALE_SAMPLES)
    count = -(-steps // t)
    return x[s :: s * t][:count] - x[:: s * t][:count]


def _jump_rows(x: FloatArray, med: float, limit_x: float, limit_d: float) -> IntArray:
    """Rows beyond ``limit_x`` from the median whose step in or out exceeds ``limit_d``.

    One pass over ``x`` in cache-sized blocks takes each block's minimum and maximum; only
    a block that reaches beyond ``limit_x`` (few: the threshold is many sigmas) is searched
    for its far rows, and the steps are then taken at those rows only.  Rounding is
    monotonic, so ``|x - med| <= limit_x`` holds for every value of a block whose extremes
    satisfy it: the rows are those of ``|x - med| > limit_x`` computed for every value.
    The step into row ``r`` is ``x[r] - x[r-1]`` (``r >= 1``), the step out
    ``x[r+1] - x[r]`` (``r <= n - 2``), as ``numpy.diff`` forms them.
    """
    found: list[IntArray] = []
    for start in range(0, x.size, CHUNK):
        seg = x[start:start + CHUNK]
        if seg.max() - med <= limit_x and med - seg.min() <= limit_x:
            continue
        rows = np.flatnonzero(np.abs(seg - med) > limit_x) + start
        if rows.size:
            found.append(rows[_steps_beyond(x, rows, limit_d)])
    return np.unique(np.concatenate(found)) if found else np.empty(0, np.int64)


def _steps_beyond(x: FloatArray, rows: IntArray, limit_d: float) -> np.ndarray:
    """Whether the step into or out of each of ``rows`` exceeds ``limit_d``."""
    jump = np.zeros(rows.size, dtype=np.bool_)
    has_in = rows >= 1
    r = rows[has_in]
    jump[has_in] = np.abs(x[r] - x[r - 1]) > limit_d
    has_out = rows <= x.size - 2
    r = rows[has_out]
    jump[has_out] |= np.abs(x[r + 1] - x[r]) > limit_d
    return jump


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
    x: ArrayLike1D,
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
    1273), as in Stable32's MAD outlier screen, with fallbacks for quantized data.

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
    _, sig_d, how_d = _robust_sigma(_strided_steps(values))
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
    listed = _describe_events(values, med, sig_x, events[:MAX_LISTED], times, fs_hz)
    flagged = int(sum(hi - lo for lo, hi in events))
    return GlitchReport(axis, units, threshold, med, sig_x, sig_d, scale, flagged, len(events),
                        listed)


def _describe_events(values: FloatArray, med: float, sigma: float,
                     events: list[tuple[int, int]], times: FloatArray | None,
                     fs_hz: float | None) -> tuple[Glitch, ...]:
    """One :class:`Glitch` per event ``[lo, hi)``, timed by ``times`` or ``row / fs_hz``."""
    def at(row: int) -> float:
        return float(times[row]) if times is not None else row / float(fs_hz)  # type: ignore[arg-type]

    listed = []
    for lo, hi in events:
        peak = lo + int(np.argmax(np.abs(values[lo:hi] - med)))
        listed.append(Glitch(peak, at(peak), hi - lo, float(values[peak]),
                             float((values[peak] - med) / sigma), at(hi - 1) - at(lo)))
    return tuple(listed)
