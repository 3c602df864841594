"""Dynamic Allan variance (DAVAR): Allan-family deviations in a window sliding along time.

The classic Allan variance assumes a stationary signal.  The dynamic Allan variance of
L. Galleani and P. Tavella ("The dynamic Allan variance", IEEE Trans. Ultrason.,
Ferroelectr., Freq. Control 56(3), 450-464, 2009; "Detection of atomic clock frequency
jumps with the Kalman filter", ibid. 59(3), 2012) computes it on a window of length
``T`` centred at each time ``t``, so that its surface over ``(t, tau)`` shows how the
stability changes: a jump of the noise level, a burst, a drift that switches on.  The
seed paper uses ``T = 201 s``.  Here each window's deviation is the same estimator as
:func:`fogts.allan.allan_deviation` (overlapping Allan by default) on that window's
samples, and the taus are limited by the window (``tau <= T/2`` for the Allan variance).

Computation
-----------
For the overlapping estimators (``oadev``, ``mdev``, ``ohdev``) every window's sum of
squared differences is a difference of one running sum over the whole record, so each
tau costs O(n) however many windows overlap (``method="cumsum"``): the squared second
(third) differences of the once-integrated phase (:func:`fogts.allan.estimators.
phase_from_rate`) are accumulated in cache-sized chunks and the running sum is sampled
only at the window edges.  ``method="kernel"`` instead calls the estimator kernel of
:mod:`fogts.allan.estimators` on each window (O(n T / step) per tau; it serves every
kind, and is the reference the fast path is tested against).

Non-stationarity
----------------
Under stationarity every window's variance estimate is ``avar * chi2_nu / nu`` with
``nu`` the window's equivalent degrees of freedom (Greenhall's EDF for the identified
noise type, :mod:`fogts.allan.confidence`), so ``log(avar_i)`` varies between windows
with variance ``psi'(nu/2)`` (the trigamma function).  The *non-stationarity score* at a
tau is the observed variance of ``log(avar_i)`` across windows divided by that
chance value: about 1 for a stationary record, much larger when the level changes.
Its p-value treats ``(K - 1) score`` as chi-squared with ``K - 1`` degrees of freedom,
``K`` being the number of non-overlapping windows in the record (overlapping windows are
not independent).  Windows whose variance lies outside the chi-squared interval around
the pooled (all-window) variance at a Bonferroni-corrected level are flagged, and the
most likely single change time is the split of the window sequence that minimises the
within-segment sum of squares of the window variances (binary segmentation, one step; on
the variance rather than its log, because a window straddling the change holds a linear
mixture of the two levels, so the split falls in the middle of the transition); the
deviation ratio compares the windows entirely before and after it.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any, Literal, get_args

import numpy as np
import pandas as pd
import scipy.special
import scipy.stats

from fogts._typing import BoolArray, FloatArray, IntArray
from fogts._validate import check_choice, check_fraction, check_positive
from fogts.allan.api import is_multi_axis, unpack_axes
from fogts.allan.estimators import ESTIMATORS, phase_from_rate
from fogts.allan.result import AxisIndexed
from fogts.allan.taus import KINDS, DroppedTau, Kind, n_terms, tau_grid
from fogts.errors import DataError, InsufficientDataError

__all__ = [
    "DynamicAllanResult",
    "DynamicAllanResultSet",
    "Nonstationarity",
    "dynamic_allan",
]

Method = Literal["auto", "cumsum", "kernel"]
METHODS: tuple[str, ...] = get_args(Method)
#: Kinds with an O(n)-per-tau running-sum implementation.
CUMSUM_KINDS: tuple[str, ...] = ("oadev", "mdev", "ohdev")
#: Family-wise significance level of the stationarity verdict and of the window flags.
DEFAULT_ALPHA = 0.01
_CHUNK = 1 << 16
#: Fewest windows a dynamic Allan analysis needs.
MIN_WINDOWS = 2
#: The power-law noise type of each tau is identified on this many windows' worth of
#: samples from the middle of the record (as allan_deviation would on one window).
ID_WINDOWS = 1


# --------------------------------------------------------------------------- results
@dataclass(frozen=True)
class Nonstationarity:
    """How much the deviation varies between windows, against chance.

    Attributes
    ----------
    tau_s : float
        The tau of the headline score (the shortest tau: most degrees of freedom).
    score : float
        Observed variance of ``log(avar)`` across windows at ``tau_s`` divided by the
        variance chance predicts from the EDF (``psi'(edf/2)``); ~1 when stationary.
    observed_var, expected_var : float
        The two variances of the score.
    edf : float
        Equivalent degrees of freedom of one window at ``tau_s``.
    n_independent : int
        Non-overlapping windows in the record (degrees of freedom of the test + 1).
    pvalue : float
        P-value of the score under stationarity (chi-squared with ``n_independent - 1``).
    level : float
        Significance level of the verdict.
    stationary : bool
        ``pvalue >= level``.
    change_time_s : float or None
        Most likely single change time (s from the start), when not stationary.
    change_ratio : float or None
        Deviation after the change divided by the deviation before it (at ``tau_s``).
    flagged_windows : tuple of int
        Windows whose variance at ``tau_s`` lies outside the stationary interval
        (chi-squared at the Bonferroni level ``level / n_independent``).
    tau_scores : ndarray of float64
        The score at every tau of the result.
    """

    tau_s: float
    score: float
    observed_var: float
    expected_var: float
    edf: float
    n_independent: int
    pvalue: float
    level: float
    stationary: bool
    change_time_s: float | None
    change_ratio: float | None
    flagged_windows: tuple[int, ...]
    tau_scores: FloatArray

    def to_dict(self) -> dict[str, Any]:
        return {
            "tau": self.tau_s, "score": _num(self.score), "observed_var": _num(self.observed_var),
            "expected_var": _num(self.expected_var), "edf": _num(self.edf),
            "n_independent": self.n_independent, "pvalue": _num(self.pvalue),
            "level": self.level, "stationary": self.stationary,
            "change_time": self.change_time_s, "change_ratio": self.change_ratio,
            "flagged_windows": list(self.flagged_windows),
            "tau_scores": [_num(v) for v in self.tau_scores],
        }

    def summary(self) -> str:
        verdict = "stationary" if self.stationary else "NOT stationary"
        text = (f"non-stationarity score {self.score:.3g} at tau = {self.tau_s:g} s "
                f"(1 = chance; p = {self.pvalue:.3g}, {self.n_independent} independent "
                f"windows): {verdict}")
        if self.change_time_s is not None and self.change_ratio is not None:
            text += (f"; most likely change at t = {self.change_time_s:.6g} s, deviation x "
                     f"{self.change_ratio:.3g}")
        if self.flagged_windows:
            text += f"; {len(self.flagged_windows)} window(s) outside the stationary interval"
        return text


@dataclass(frozen=True)
class DynamicAllanResult:
    """Dynamic Allan deviation of one axis: a (window time x tau) surface.

    Attributes
    ----------
    kind, units, axis : str
    fs_hz : float
    n_samples : int
        Samples in the record.
    window_s, step_s : float
        Window length and step actually used (whole samples).
    window_n, step_n : int
        The same in samples.
    method : str
        ``"cumsum"`` or ``"kernel"`` (see the module notes).
    confidence : float
        Level of ``ci_low`` / ``ci_high``.
    tau_s : ndarray (n_tau,)
    m : ndarray of int64 (n_tau,)
    n : ndarray of int64 (n_tau,)
        Terms per window at each tau.
    times_s : ndarray (n_win,)
        Window centres in seconds from the start (first sample at t = 0).
    start_s : ndarray (n_win,)
        Window starts.
    dev : ndarray (n_win, n_tau)
        ``dev[i, j]``: deviation of window ``i`` at ``tau_s[j]``, in ``units``.
    ci_low, ci_high : ndarray (n_win, n_tau)
        Chi-squared interval of each window's deviation.
    edf : ndarray (n_tau,)
        Equivalent degrees of freedom of one window.
    alpha : ndarray of int64 (n_tau,)
        Power-law noise type identified on the whole record.
    reference_dev : ndarray (n_tau,)
        Pooled deviation: the root of the mean window variance (the stationary hypothesis).
    outside : ndarray of bool (n_win, n_tau)
        Window variance outside the stationary chi-squared interval around the pooled
        variance (Bonferroni level, see :class:`Nonstationarity`).
    nonstationarity : Nonstationarity
    dropped : tuple of DroppedTau
    notes : tuple of str
    """

    kind: str
    units: str
    axis: str
    fs_hz: float
    n_samples: int
    window_s: float
    step_s: float
    window_n: int
    step_n: int
    method: str
    confidence: float
    tau_s: FloatArray
    m: IntArray
    n: IntArray
    times_s: FloatArray
    start_s: FloatArray
    dev: FloatArray
    ci_low: FloatArray
    ci_high: FloatArray
    edf: FloatArray
    alpha: IntArray
    reference_dev: FloatArray
    outside: BoolArray
    nonstationarity: Nonstationarity
    dropped: tuple[DroppedTau, ...] = ()
    notes: tuple[str, ...] = ()

    @property
    def shape(self) -> tuple[int, int]:
        """``(n_windows, n_taus)``."""
        return (int(self.times_s.size), int(self.tau_s.size))

    @property
    def avar(self) -> FloatArray:
        return self.dev**2

    def to_frame(self) -> pd.DataFrame:
        """Long format, one row per (window, tau): ``time, tau, m, dev, ci_low, ci_high,
        outside``."""
        nw, nt = self.shape
        return pd.DataFrame({
            "time": np.repeat(self.times_s, nt), "tau": np.tile(self.tau_s, nw),
            "m": np.tile(self.m, nw), "dev": self.dev.ravel(),
            "ci_low": self.ci_low.ravel(), "ci_high": self.ci_high.ravel(),
            "outside": self.outside.ravel(),
        })

    def to_dict(self) -> dict[str, Any]:
        """JSON-safe dict (the ``fogts davar`` contract plus detail); NaN becomes None."""
        return {
            "kind": self.kind, "units": self.units, "axis": self.axis,
            "fs_hz": float(self.fs_hz), "n_samples": int(self.n_samples),
            "window_s": float(self.window_s), "step_s": float(self.step_s),
            "window_n": int(self.window_n), "step_n": int(self.step_n),
            "method": self.method, "confidence": _num(self.confidence),
            "taus": self.tau_s.tolist(), "m": self.m.tolist(), "n": self.n.tolist(),
            "edf": [_num(v) for v in self.edf], "alpha": self.alpha.tolist(),
            "times": self.times_s.tolist(),
            "dev": [[_num(v) for v in row] for row in self.dev],
            "ci_low": [[_num(v) for v in row] for row in self.ci_low],
            "ci_high": [[_num(v) for v in row] for row in self.ci_high],
            "reference_dev": [_num(v) for v in self.reference_dev],
            "nonstationarity": self.nonstationarity.to_dict(),
            "dropped": [d.to_dict() for d in self.dropped],
            "notes": list(self.notes),
        }

    def summary(self, max_rows: int = 12) -> str:
        """Text: the set-up, the verdict, and the deviation at a few taus over time."""
        nw, nt = self.shape
        lines = [f"Dynamic {self.kind} of axis {self.axis!r}: {nw} windows of "
                 f"{self.window_s:g} s every {self.step_s:g} s over {self.n_samples} samples "
                 f"at {self.fs_hz:g} Hz; {nt} taus {self.tau_s[0]:g}..{self.tau_s[-1]:g} s; "
                 f"unit {self.units}",
                 self.nonstationarity.summary()]
        cols = np.unique(np.linspace(0, nt - 1, min(nt, 6)).round().astype(int))
        rows = np.unique(np.linspace(0, nw - 1, min(nw, max_rows)).round().astype(int))
        head = f"{'t [s]':>10}" + "".join(f"{f'tau={self.tau_s[j]:.3g}':>13}" for j in cols)
        lines.append(head)
        for i in rows:
            cells = "".join(f"{self.dev[i, j]:12.4g}{'*' if self.outside[i, j] else ' '}"
                            for j in cols)
            lines.append(f"{self.times_s[i]:10.6g}" + cells)
        lines.append(f"{'pooled':>10}" + "".join(f"{self.reference_dev[j]:12.4g} " for j in cols))
        lines.append("(* = outside the stationary interval)")
        if self.dropped:
            lines.append(f"dropped {len(self.dropped)} tau(s): "
                         + "; ".join(f"tau={d.tau_s:g} s: {d.reason}" for d in self.dropped[:3]))
        lines += [f"note: {note}" for note in self.notes]
        return "\n".join(lines)


@dataclass(frozen=True)
class DynamicAllanResultSet(AxisIndexed[DynamicAllanResult]):
    """One :class:`DynamicAllanResult` per axis of a multi-axis record (index it by axis
    name or position)."""

    curves: tuple[DynamicAllanResult, ...]

    def __post_init__(self) -> None:
        self._check_curves()

    def to_frame(self) -> pd.DataFrame:
        frames = [c.to_frame().assign(axis=c.axis) for c in self.curves]
        out = pd.concat(frames, ignore_index=True)
        return out[["axis", *[c for c in out.columns if c != "axis"]]]

    def to_dict(self) -> dict[str, Any]:
        first = self.curves[0]
        return {"kind": first.kind, "window_s": first.window_s, "step_s": first.step_s,
                "axes": list(self.axes), "curves": [c.to_dict() for c in self.curves]}

    def summary(self) -> str:
        return "\n\n".join(c.summary() for c in self.curves)


# --------------------------------------------------------------------------- public API
def dynamic_allan(
    x: Any,
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
) -> DynamicAllanResult | DynamicAllanResultSet:
    """Dynamic Allan deviation: the deviation in a window sliding along the record.

    Galleani & Tavella's DAVAR (IEEE Trans. UFFC 56(3), 2009): for each window of
    ``window_s`` seconds, starting every ``step_s`` seconds, the Allan-family deviation
    ``kind`` of the window's samples at each tau (seed 000 eq. 3 / NIST SP1065 eq. 11 for
    the default ``oadev``).  The seed paper's window is T = 201 s.

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
    level : float
        Significance level of the stationarity verdict and of the window flags.

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
    window = check_positive("window_s", window_s)
    step = check_positive("step_s", step_s)
    if method == "cumsum" and kind not in CUMSUM_KINDS:
        raise DataError(f"method='cumsum' serves kinds {', '.join(CUMSUM_KINDS)}; got "
                        f"kind={kind!r} (use method='kernel' or 'auto')")
    series, fs, unit, notes = unpack_axes(x, fs_hz=fs_hz, axis=axis, units=units)
    curves = [_one(s.y, s.name, fs=fs, units=unit, window=window, step=step, kind=kind,
                   taus=taus, confidence=confidence, method=method, level=level, notes=notes)
              for s in series]
    if len(curves) == 1 and (axis is not None or not is_multi_axis(x)):
        return curves[0]
    return DynamicAllanResultSet(curves=tuple(curves))


def _one(y: FloatArray, name: str, *, fs: float, units: str, window: float, step: float,
         kind: str, taus: Any, confidence: float, method: str, level: float,
         notes: tuple[str, ...]) -> DynamicAllanResult:
    n = y.size
    win_n = round(window * fs)
    step_n = max(1, round(step * fs))
    if win_n < 4:
        raise DataError(f"window_s={window:g} s is {win_n} sample(s) at {fs:g} Hz; a window "
                        "needs at least 4 samples")
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
        dev = _cumsum_devs(y, kind=kind, m=m, terms=terms, starts=starts)
    else:
        dev = _kernel_devs(y, kind=kind, m=m, starts=starts, win_n=win_n, fs=fs)

    from fogts.allan.confidence import chi2_interval, edf_for, identify_noise

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
    n_indep = max(n // win_n, MIN_WINDOWS)
    outside = _outside(avar, reference**2, edf, level / n_indep)
    times = np.asarray((starts + win_n / 2.0) / fs, dtype=np.float64)
    stat = _nonstationarity(avar, edf, m / fs, times, win_n / fs / 2.0, outside, n_indep,
                            level)
    return DynamicAllanResult(
        kind=kind, units=units, axis=name, fs_hz=fs, n_samples=n, window_s=win_n / fs,
        step_s=step_n / fs, window_n=win_n, step_n=step_n, method=use, confidence=confidence,
        tau_s=grid.tau_s, m=m, n=terms, times_s=times, start_s=starts / fs, dev=dev,
        ci_low=low, ci_high=high,
        edf=edf, alpha=alpha, reference_dev=reference, outside=outside, nonstationarity=stat,
        dropped=grid.dropped, notes=(*grid.notes, *notes))


# --------------------------------------------------------------------------- kernels
def _kernel_devs(y: FloatArray, *, kind: str, m: IntArray, starts: IntArray, win_n: int,
                 fs: float) -> FloatArray:
    """The estimator kernel of :mod:`fogts.allan.estimators` on every window."""
    fn = ESTIMATORS[kind]
    out = np.empty((starts.size, m.size), dtype=np.float64)
    for i, s in enumerate(starts.tolist()):
        out[i] = fn(y[s:s + win_n], fs_hz=fs, m=m, workers=1).dev
    return out


def _cumsum_devs(y: FloatArray, *, kind: str, m: IntArray, terms: IntArray,
                 starts: IntArray) -> FloatArray:
    """Every window's deviation from one pass over the record per tau (O(n) per tau).

    Window ``i`` covers rate samples ``[s_i, s_i + L)``, i.e. phase points
    ``x[s_i .. s_i + L]``; its terms are the global terms ``s_i .. s_i + terms - 1`` of
    the whole record's phase (the phase offset cancels in every difference).  The squared
    terms are summed between consecutive window edges (``numpy.add.reduceat``) and each
    window's sum is a difference of the running sum of those few block sums.  The
    normalisations are those of :mod:`fogts.allan.estimators` (unscaled phase).
    """
    x = phase_from_rate(y)
    out = np.empty((starts.size, m.size), dtype=np.float64)
    for j, (mj, tj) in enumerate(zip(m.tolist(), terms.tolist(), strict=True)):
        if kind == "oadev":
            sq = _second_sq(x, mj)
            norm = 2.0 * mj * mj * tj
        elif kind == "ohdev":
            sq = _third_sq(x, mj)
            norm = 6.0 * mj * mj * tj
        else:  # mdev
            sq = _mod_sq(x, mj)
            norm = 2.0 * float(mj) ** 4 * tj
        sums = _window_sums(sq, starts, tj, chunk=max(_CHUNK, mj))
        out[:, j] = np.sqrt(np.maximum(sums, 0.0) / norm)
    return out


SquaredTerms = Callable[[int, int], FloatArray]


def _second_sq(x: FloatArray, m: int) -> SquaredTerms:
    buf_a, buf_b = np.empty(0), np.empty(0)

    def terms(c0: int, c1: int) -> FloatArray:
        nonlocal buf_a, buf_b
        k = c1 - c0
        if buf_a.size < k:
            buf_a, buf_b = np.empty(k), np.empty(k)
        a, b = buf_a[:k], buf_b[:k]
        # (x2 - x1) - (x1 - x0): both inner differences are small, so this is accurate
        np.subtract(x[c0 + 2 * m:c1 + 2 * m], x[c0 + m:c1 + m], out=a)
        np.subtract(x[c0 + m:c1 + m], x[c0:c1], out=b)
        np.subtract(a, b, out=a)
        return np.multiply(a, a, out=a)
    return terms


def _third_sq(x: FloatArray, m: int) -> SquaredTerms:
    buf_a, buf_b = np.empty(0), np.empty(0)

    def terms(c0: int, c1: int) -> FloatArray:
        nonlocal buf_a, buf_b
        k = c1 - c0
        if buf_a.size < k:
            buf_a, buf_b = np.empty(k), np.empty(k)
        a, b = buf_a[:k], buf_b[:k]
        np.subtract(x[c0 + 3 * m:c1 + 3 * m], x[c0:c1], out=a)
        np.subtract(x[c0 + 2 * m:c1 + 2 * m], x[c0 + m:c1 + m], out=b)
        b *= 3.0
        np.subtract(a, b, out=a)
        return np.multiply(a, a, out=a)
    return terms


def _mod_sq(x: FloatArray, m: int) -> SquaredTerms:
    """(sum_{i=j}^{j+m-1} v_i)^2 with v the second differences, for j in [c0, c1)."""
    def terms(c0: int, c1: int) -> FloatArray:
        hi = c1 + m - 1
        v = x[c0 + 2 * m:hi + 2 * m] - x[c0 + m:hi + m]
        v -= x[c0 + m:hi + m] - x[c0:hi]
        run = np.empty(v.size + 1)
        run[0] = 0.0
        np.cumsum(v, out=run[1:])
        s = run[m:] - run[:-m]
        return np.square(s, out=s)
    return terms


def _window_sums(sq: SquaredTerms, starts: IntArray, count: int, *, chunk: int
                 ) -> FloatArray:
    """``sum(t[s : s + count])`` for every start ``s`` of the squared terms ``t``.

    The window edges cut the terms into blocks; each block is summed once (``reduceat``
    over cache-sized pieces that end on an edge), and a window's sum is the sum of the
    block sums it spans (a difference of their running sum: a few thousand numbers, so
    no precision is lost to a long running sum).
    """
    edges = _sorted_unique(np.concatenate([starts, starts + count]))
    block = np.empty(edges.size - 1)
    # pieces of consecutive blocks, each about `chunk` terms long
    cut = np.searchsorted(edges, edges[0] + chunk * np.arange(1, (edges[-1] - edges[0])
                                                              // chunk + 2))
    bounds = _sorted_unique(np.concatenate([[0], np.minimum(cut, edges.size - 1),
                                            [edges.size - 1]]))
    for b0, b1 in zip(bounds[:-1].tolist(), bounds[1:].tolist(), strict=True):
        if b1 <= b0:
            continue
        lo, hi = int(edges[b0]), int(edges[b1])
        t = sq(lo, hi)
        block[b0:b1] = np.add.reduceat(t, edges[b0:b1] - lo)
    run = np.concatenate([[0.0], np.cumsum(block)])
    i0 = np.searchsorted(edges, starts)
    i1 = np.searchsorted(edges, starts + count)
    return run[i1] - run[i0]


def _sorted_unique(v: IntArray) -> IntArray:
    v = np.sort(v)
    keep = np.empty(v.size, dtype=np.bool_)
    keep[:1] = True
    np.not_equal(v[1:], v[:-1], out=keep[1:])
    return v[keep]


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
                     half_window: float, outside: BoolArray, n_indep: int, level: float
                     ) -> Nonstationarity:
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
    stationary = bool(not (pvalue < level))
    change_time: float | None = None
    change_ratio: float | None = None
    if not stationary and np.all(np.isfinite(logv[:, j])):
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
    flagged = tuple(int(i) for i in np.flatnonzero(outside[:, j]))
    return Nonstationarity(
        tau_s=float(tau[j]), score=score, observed_var=float(obs[j]),
        expected_var=float(exp[j]), edf=float(edf[j]), n_independent=n_indep, pvalue=pvalue,
        level=level, stationary=stationary, change_time_s=change_time,
        change_ratio=change_ratio, flagged_windows=flagged,
        tau_scores=np.asarray(scores, dtype=np.float64))


def _best_split(v: FloatArray) -> int:
    """Index k (1..K-1) minimising SSE(v[:k]) + SSE(v[k:]) (one binary-segmentation step)."""
    size = v.size
    c1 = np.cumsum(v)
    c2 = np.cumsum(v * v)
    k = np.arange(1, size)
    left = c2[k - 1] - c1[k - 1] ** 2 / k
    right = (c2[-1] - c2[k - 1]) - (c1[-1] - c1[k - 1]) ** 2 / (size - k)
    return int(k[np.argmin(left + right)])


def _num(v: Any) -> float | None:
    f = float(v)
    return f if math.isfinite(f) else None
