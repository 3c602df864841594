"""Dynamic Allan variance (DAVAR): Allan-family deviations in a window sliding along time.

The classic Allan variance assumes a stationary signal.  The dynamic Allan variance of
L. Galleani and P. Tavella ("The dynamic Allan variance", IEEE Trans. Ultrason.,
Ferroelectr., Freq. Control 56(3), 450-464, 2009; "Detection of atomic clock frequency
jumps with the Kalman filter", ibid. 59(3), 2012) computes it on a window of length
``T`` centred at each time ``t``, so that its surface over ``(t, tau)`` shows how the
stability changes: a jump of the noise level, a burst, a drift that switches on.  Here
each window's deviation is the same estimator as :func:`fogts.allan.allan_deviation`
(overlapping Allan by default) on that window's samples (:mod:`fogts.allan.window_sums`),
and the taus are limited by the window (``tau <= T/2`` for the Allan variance).

Non-stationarity
----------------
Under stationarity every window's variance estimate is ``avar * chi2_nu / nu`` with
``nu`` the window's equivalent degrees of freedom (Greenhall's EDF for the identified
noise type, :mod:`fogts.allan.edf`), so ``log(avar_i)`` varies between windows
with variance ``psi'(nu/2)`` (the trigamma function).  The *non-stationarity score* at a
tau is the observed variance of ``log(avar_i)`` across windows divided by that
chance value: about 1 for a stationary record, much larger when the level changes.
Its p-value treats ``(K - 1) score`` as chi-squared with ``K - 1`` degrees of freedom,
``K`` being the number of non-overlapping windows in the record (overlapping windows are
not independent), or the number of windows computed when the step is longer than the
window (the samples between them are not tested).  Windows whose variance lies outside the chi-squared interval around
the pooled (all-window) variance at a Bonferroni-corrected level are flagged, and the
most likely single change time is the split of the window sequence that minimises the
within-segment sum of squares of the window variances (binary segmentation, one step; on
the variance rather than its log, because a window straddling the change holds a linear
mixture of the two levels, so the split falls in the middle of the transition); the
deviation ratio compares the windows entirely before and after it.  A short event (a
glitch, a burst) is no step: it raises the windows that hold it, so the largest excursion
is also located, as the run of flagged windows around the window farthest from the pooled
value (:class:`~fogts.allan.dynamic_result.Transient`), and matched with the glitches the
reader found.
"""

from __future__ import annotations

import dataclasses
import math
from typing import Any, Literal, get_args

import numpy as np
import pandas as pd
import scipy.special
import scipy.stats

from fogts._typing import ArrayLike1D, BoolArray, FloatArray
from fogts._validate import check_choice, check_fraction, check_positive
from fogts.allan.api import analysis_context
from fogts.allan.confidence import chi2_interval
from fogts.allan.dynamic_result import (
    DynamicAllanResult,
    DynamicAllanResultSet,
    Nonstationarity,
    Transient,
)
from fogts.allan.edf import edf_for
from fogts.allan.noise_identification import identify_noise
from fogts.allan.taus import KINDS, Kind, n_terms, tau_grid
from fogts.allan.window_sums import CUMSUM_KINDS, cumsum_devs, kernel_devs
from fogts.errors import DataError, InsufficientDataError
from fogts.io.run import Run
from fogts.preprocess.glitches import Glitch
from fogts.preprocess.inputs import ensure_axes
from fogts.preprocess.prepare import Prepared

__all__ = ["MIN_WINDOWS", "MIN_WINDOW_SAMPLES", "DynamicAllanResult", "DynamicAllanResultSet",
           "Nonstationarity", "Transient", "dynamic_allan"]

#: Family-wise significance level of the stationarity verdict and of the window flags.
DEFAULT_ALPHA = 0.01
#: Smallest change of the deviation (relative) that makes a record "not stationary".
DEFAULT_MIN_CHANGE = 0.10
#: Fewest windows a dynamic Allan analysis needs.
MIN_WINDOWS = 2
#: Fewest samples in one window: below it a window holds a handful of octave taus with
#: EDFs of a few, too few for a deviation curve to follow (the HTML report's DAVar section
#: asks the same, :data:`fogts.report.html.DAVAR_MIN_WINDOW_SAMPLES`).
MIN_WINDOW_SAMPLES = 256
#: The power-law noise type of each tau is identified on this many windows' worth of
#: samples from the middle of the record (as allan_deviation would on one window).
ID_WINDOWS = 1
#: How the window deviations are computed (:mod:`fogts.allan.window_sums`).
Method = Literal["auto", "cumsum", "kernel"]
METHODS: tuple[str, ...] = get_args(Method)


# --------------------------------------------------------------------------- public API
# Long only by its docstring: the public entry point documents every option.
def dynamic_allan(
    x: ArrayLike1D | pd.DataFrame | Run | Prepared,
    *,
    fs_hz: float | None = None,
    window_s: float,
    step_s: float,
    kind: Kind = "oadev",
    taus: Any = "octave",
    confidence: float = 0.683,
    axis: int | str | None = None,
    units: str | None = None,
    method: Method = "auto",
    level: float = DEFAULT_ALPHA,
    min_change: float = DEFAULT_MIN_CHANGE,
    glitches: Any = None,
) -> DynamicAllanResult | DynamicAllanResultSet:
    """Dynamic Allan deviation: the deviation in a window sliding along the record.

    Galleani & Tavella's DAVAR (IEEE Trans. UFFC 56(3), 2009): for each window of
    ``window_s`` seconds, starting every ``step_s`` seconds, the Allan-family deviation
    ``kind`` of the window's samples at each tau (NIST SP1065 eq. 11 for the default
    ``oadev``).

    Parameters
    ----------
    x : ndarray, Series, Run or Prepared
        Rate data; a multi-axis Run or 2-D array gives one result per axis unless
        ``axis`` picks one.
    fs_hz : float, optional
        Sample rate (required for ndarray input).
    window_s : float
        Window length in seconds (rounded to whole samples).
    step_s : float
        Step between window starts in seconds (rounded to whole samples, at least one).
    kind : {"oadev", "mdev", "ohdev", "adev", "hdev", "totdev"}
        Estimator applied to each window.
    taus : {"octave", "decade", "dense", "all"} or array_like
        Tau grid, built for the window length (:func:`fogts.allan.taus.tau_grid`).
    confidence : float
        Level of each window's chi-squared interval.
    axis : int or str, optional
        Analyse one axis of a multi-axis input.
    units : str, optional
        Rate unit of array input (default deg/h).
    method : {"auto", "cumsum", "kernel"}
        ``cumsum``: O(n) per tau from running sums (oadev, mdev, ohdev); ``kernel``: the
        estimator kernel on each window (every kind); ``auto`` picks ``cumsum`` when
        available.
    min_change : float
        Smallest change of the deviation, relative (0.1 = 10 %), that makes the record
        "not stationary": a significant but smaller change is reported as stationary within
        it (a long record makes tiny changes significant).
    level : float
        Significance level of the stationarity verdict and of the window flags.
    glitches : DataQuality, GlitchReport or sequence of GlitchReport, optional
        Glitches the reader found (:func:`fogts.preprocess.hygiene.assess_run`), matched to
        the axes by name: those inside the largest transient are named as its likely cause,
        and all are marked on the heat map.

    Returns
    -------
    DynamicAllanResult or DynamicAllanResultSet

    Raises
    ------
    DataError
        Bad argument (kind, method, window or step not positive, ``cumsum`` with a kind
        it does not serve).
    InsufficientDataError
        The window is longer than the record, or fewer than two windows fit.

    Examples
    --------
    >>> import numpy as np
    >>> y = np.random.default_rng(0).normal(size=20_000)        # 1 Hz white noise
    >>> y[10_000:] *= 2.0                                         # level doubles half-way
    >>> res = dynamic_allan(y, fs_hz=1.0, window_s=1000, step_s=250)
    >>> res.shape, res.nonstationarity.stationary
    ((77, 9), False)
    >>> abs(res.nonstationarity.change_time_s - 10_000) <= 250     # within one step
    True
    >>> round(res.nonstationarity.change_ratio, 1)
    2.0
    """
    kind = check_choice("kind", kind, KINDS)  # type: ignore[assignment]
    method = check_choice("method", method, METHODS)  # type: ignore[assignment]
    confidence = check_fraction("confidence", confidence)
    level = check_fraction("level", level)
    min_change = check_positive("min_change", min_change, allow_zero=True)
    window = check_positive("window_s", window_s)
    step = check_positive("step_s", step_s)
    if method == "cumsum" and kind not in CUMSUM_KINDS:
        raise DataError(f"method='cumsum' serves kinds {', '.join(CUMSUM_KINDS)}; got "
                        f"kind={kind!r} (use method='kernel' or 'auto')")
    inp = ensure_axes(x, fs_hz=fs_hz, axis=axis, units=units)
    fs, unit, notes = analysis_context(inp)
    curves = [_one(y, name, fs=fs, units=unit, window=window, step=step, kind=kind,
                   taus=taus, confidence=confidence, method=method, level=level, notes=notes,
                   min_change=min_change, glitches=_axis_glitches(glitches, name))
              for name, y in inp.columns()]
    if len(curves) == 1 and (axis is not None or not inp.multi_axis_form):
        return curves[0]
    return DynamicAllanResultSet(curves=tuple(curves))


def _one(y: FloatArray, name: str, *, fs: float, units: str, window: float, step: float,
         kind: str, taus: Any, confidence: float, method: str, level: float,
         notes: tuple[str, ...], min_change: float = 0.0,
         glitches: tuple[Glitch, ...] = ()) -> DynamicAllanResult:
    n = y.size
    win_n = round(window * fs)
    step_n = max(1, round(step * fs))
    if win_n < MIN_WINDOW_SAMPLES:
        raise DataError(f"window_s={window:g} s is {win_n} sample(s) at {fs:g} Hz; a window "
                        f"needs at least {MIN_WINDOW_SAMPLES} samples "
                        f"({MIN_WINDOW_SAMPLES / fs:g} s at {fs:g} Hz)")
    if win_n > n:
        raise InsufficientDataError(f"window_s={window:g} s ({win_n} samples) is longer than "
                                    f"the record ({n} samples, {n / fs:g} s)")
    n_win = (n - win_n) // step_n + 1
    if n_win < MIN_WINDOWS:
        raise InsufficientDataError(
            f"only {n_win} window of {window:g} s fits in the {n / fs:g} s record with step "
            f"{step:g} s; at least {MIN_WINDOWS} are needed (shorten the window or the step)")
    grid = tau_grid(taus, fs_hz=fs, n_samples=win_n, kind=kind)
    m = grid.m
    terms = n_terms(kind, m, win_n)
    starts = np.arange(n_win, dtype=np.int64) * step_n
    use = "cumsum" if method == "cumsum" or (method == "auto" and kind in CUMSUM_KINDS) \
        else "kernel"
    if use == "cumsum":
        dev = cumsum_devs(y, kind=kind, m=m, terms=terms, starts=starts)
    else:
        dev = kernel_devs(y, kind=kind, m=m, starts=starts, win_n=win_n, fs=fs)

    # Noise type per tau from the central window (ID_WINDOWS windows): the EDF describes
    # one window, and identifying on the whole record would cost more than the surface.
    span = min(n, ID_WINDOWS * win_n)
    lo = (n - span) // 2
    alpha = np.asarray(identify_noise(y[lo:lo + span], m, fs_hz=fs, kind=kind),
                       dtype=np.int64)
    edf = np.asarray(edf_for(kind, alpha, m, win_n + 1), dtype=np.float64)
    f_low, f_high = chi2_interval(np.ones(m.size), edf, confidence)  # per-tau factors
    low = dev * np.asarray(f_low, dtype=np.float64)
    high = dev * np.asarray(f_high, dtype=np.float64)
    avar = dev**2
    with np.errstate(divide="ignore", invalid="ignore"):
        reference = np.sqrt(np.mean(avar, axis=0))
    # independent windows: the record's non-overlapping windows, but never more than the
    # windows computed (a step longer than the window leaves the record between them out)
    n_indep = max(min(n // win_n, n_win), MIN_WINDOWS)
    outside = _outside(avar, reference**2, edf, level / n_indep)
    times = np.asarray((starts + win_n / 2.0) / fs, dtype=np.float64)
    stat = _nonstationarity(avar, edf, m / fs, times, win_n / fs / 2.0, outside, n_indep,
                            level, min_change)
    j = int(np.argmin(np.abs(m / fs - stat.tau_s)))  # the headline tau
    stat = dataclasses.replace(stat, units=units, window_s=win_n / fs, transient=_transient(
        avar[:, j], outside[:, j], starts / fs, win_n / fs, step_n / fs, glitches))
    stat = dataclasses.replace(stat, stationary=stat.stationary and not stat.transient_is_change)
    return DynamicAllanResult(
        kind=kind, units=units, axis=name, fs_hz=fs, n_samples=n, window_s=win_n / fs,
        step_s=step_n / fs, window_n=win_n, step_n=step_n, method=use, confidence=confidence,
        tau_s=grid.tau_s, m=m, n=terms, times_s=times, start_s=starts / fs, dev=dev,
        ci_low=low, ci_high=high,
        edf=edf, alpha=alpha, reference_dev=reference, outside=outside, nonstationarity=stat,
        dropped=grid.dropped, notes=(*grid.notes, *notes), glitches=glitches)


# --------------------------------------------------------------------------- statistics
def _outside(avar: FloatArray, ref_avar: FloatArray, edf: FloatArray, alpha: float
             ) -> BoolArray:
    """Window variance outside the two-sided chi-squared interval around the pooled one."""
    with np.errstate(invalid="ignore"):
        lo = scipy.stats.chi2.ppf(alpha / 2, edf) / edf
        hi = scipy.stats.chi2.isf(alpha / 2, edf) / edf
        ratio = avar / ref_avar
        out = (ratio < lo) | (ratio > hi)
    out &= np.isfinite(edf) & (edf > 0)
    return np.asarray(out, dtype=np.bool_)


def _nonstationarity(avar: FloatArray, edf: FloatArray, tau: FloatArray, times: FloatArray,
                     half_window: float, outside: BoolArray, n_indep: int, level: float,
                     min_change: float = 0.0) -> Nonstationarity:
    """The score test (significance) and the size of the most likely single change (the
    effect); "not stationary" needs both: p < ``level`` and a change of at least
    ``min_change`` (relative, on the deviation)."""
    with np.errstate(divide="ignore", invalid="ignore"):
        logv = np.log(avar)
        obs = np.var(logv, axis=0, ddof=1)
        exp = scipy.special.polygamma(1, edf / 2.0)
        scores = obs / exp
    valid = np.isfinite(scores)
    j = int(np.argmax(valid)) if valid.any() else 0
    score = float(scores[j])
    dof = n_indep - 1
    pvalue = float(scipy.stats.chi2.sf(dof * score, dof)) if math.isfinite(score) else \
        float("nan")
    significant = bool(pvalue < level)
    change_time: float | None = None
    change_ratio: float | None = None
    if np.all(np.isfinite(logv[:, j])) and logv.shape[0] > 1:
        # split on the variance itself: a window straddling the change holds a linear
        # mixture of the two variances, so the least-squares split of the (linear) ramp
        # falls at its middle, i.e. at the change (log would bias it early)
        k = _best_split(avar[:, j])
        change_time = float((times[k - 1] + times[k]) / 2.0)
        clean_before = times + half_window <= change_time
        clean_after = times - half_window >= change_time
        if clean_before.any() and clean_after.any():
            diff = np.mean(logv[clean_after, j]) - np.mean(logv[clean_before, j])
        else:
            diff = np.mean(logv[k:, j]) - np.mean(logv[:k, j])
        change_ratio = float(np.exp(diff / 2.0))
    effect = abs(change_ratio - 1.0) if change_ratio is not None else 0.0
    stationary = not (significant and effect >= min_change)
    if stationary:  # no step to locate; its size stays in ``effect``
        change_time = change_ratio = None
    flagged = tuple(int(i) for i in np.flatnonzero(outside[:, j]))
    return Nonstationarity(
        tau_s=float(tau[j]), score=score, observed_var=float(obs[j]),
        expected_var=float(exp[j]), edf=float(edf[j]), n_independent=n_indep, pvalue=pvalue,
        level=level, stationary=stationary, change_time_s=change_time,
        change_ratio=change_ratio, flagged_windows=flagged,
        tau_scores=np.asarray(scores, dtype=np.float64), significant=significant,
        effect=effect, min_change=min_change)


def _best_split(v: FloatArray) -> int:
    """Index k (1..K-1) minimising SSE(v[:k]) + SSE(v[k:]) (one binary-segmentation step)."""
    size = v.size
    c1 = np.cumsum(v)
    c2 = np.cumsum(v * v)
    k = np.arange(1, size)
    left = c2[k - 1] - c1[k - 1] ** 2 / k
    right = (c2[-1] - c2[k - 1]) - (c1[-1] - c1[k - 1]) ** 2 / (size - k)
    return int(k[np.argmin(left + right)])


def _transient(avar: FloatArray, outside: BoolArray, starts: FloatArray, window: float,
               step: float, glitches: tuple[Glitch, ...]) -> Transient | None:
    """The run of flagged windows around the one farthest from the pooled variance, where
    it lies, and its deviation against the windows clear of it (None when no window is
    flagged or none is clear)."""
    if not outside.any() or not np.all(np.isfinite(avar)) or np.any(avar <= 0):
        return None
    logv = np.log(avar)
    off = logv - np.log(np.mean(avar))
    peak = int(np.argmax(np.where(outside, np.abs(off), -np.inf)))
    # the run: flagged windows on the peak's side (a large event lifts the pooled value,
    # so the quiet windows next to it can be flagged on the other side)
    same = outside & (np.sign(off) == np.sign(off[peak]))
    first = last = peak
    while first > 0 and same[first - 1]:
        first -= 1
    while last < same.size - 1 and same[last + 1]:
        last += 1
    # against the windows clear of it on each side, the side nearer in level: an event
    # stands out from both neighbours, a step's half from one only (and a run reaching an
    # end of the record cannot be told from a step)
    before = starts + window <= starts[first]
    after = starts >= starts[last] + window
    if not (before.any() and after.any()):
        return None
    inside = np.mean(logv[first:last + 1])
    diff = min(inside - np.mean(logv[before]), inside - np.mean(logv[after]), key=abs)
    ratio = math.exp(diff / 2.0)
    a, b = float(starts[last]), float(starts[first] + window)
    lo, hi = min(a, b), max(a, b)
    near = tuple(g for g in glitches if lo - step <= g.time_s <= hi + step)
    return Transient(start_s=lo, end_s=hi, ratio=ratio, n_windows=last - first + 1,
                     peak_time_s=float(starts[peak] + window / 2.0), glitches=near)


def _axis_glitches(glitches: Any, axis: str) -> tuple[Glitch, ...]:
    """The glitch events of ``axis`` from a DataQuality, a GlitchReport or a sequence of
    them (empty when None)."""
    if glitches is None:
        return ()
    reports = getattr(glitches, "glitches", glitches)
    if hasattr(reports, "events"):
        reports = [reports]
    return tuple(e for r in reports if r.axis == axis for e in r.events)
