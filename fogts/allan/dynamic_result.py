"""Result records of the dynamic Allan analysis: the (window time x tau) surface of one
axis (:class:`DynamicAllanResult`), one per axis, and the non-stationarity verdict."""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np
import pandas as pd

from fogts._typing import BoolArray, FloatArray, IntArray
from fogts._validate import finite_or_none
from fogts.allan.result import AxisIndexed
from fogts.allan.taus import DroppedTau
from fogts.preprocess.glitches import Glitch
from fogts.tables import Column, Table, TableView

__all__ = ["DynamicAllanResult", "DynamicAllanResultSet", "Nonstationarity", "Transient"]


@dataclass(frozen=True)
class Transient:
    """The largest excursion of the window deviations: the run of consecutive windows,
    outside the stationary interval, around the window farthest from the pooled value.

    A short event (a glitch, a burst) raises the deviation of every window that holds it,
    so the windows of the run share the event: it lies where they overlap, from the start
    of the last window to the end of the first.  An event longer than a window leaves no
    common part; it then lies between the end of the first window and the start of the
    last.  Both cases give ``[min(a, b), max(a, b)]`` with ``a`` the start of the last
    window and ``b`` the end of the first.

    Attributes
    ----------
    start_s, end_s : float
        Where the event lies (s from the start), as above.
    ratio : float
        Deviation in the run's windows over the deviation in the windows clear of them on
        one side, the side whose level is nearer (geometric means of the variances, at the
        headline tau): an event stands out from both sides, half of a step from one only.
    n_windows : int
        Windows in the run.
    peak_time_s : float
        Centre of the window farthest from the pooled deviation.
    glitches : tuple of Glitch
        Glitches found by the reader (:func:`fogts.preprocess.glitches.detect_glitches`)
        within one step of ``[start_s, end_s]``: the likely cause.
    """

    start_s: float
    end_s: float
    ratio: float
    n_windows: int
    peak_time_s: float
    glitches: tuple[Glitch, ...]

    @property
    def effect(self) -> float:
        """``|ratio - 1|``."""
        return abs(self.ratio - 1.0)

    def to_dict(self) -> dict[str, Any]:
        return {"start": self.start_s, "end": self.end_s, "ratio": finite_or_none(self.ratio),
                "effect": finite_or_none(self.effect), "n_windows": self.n_windows,
                "peak_time": self.peak_time_s,
                "glitch_times": [g.time_s for g in self.glitches]}

    def describe(self, units: str) -> str:
        """``"transient at t = 4040-4060 s: deviation x1.19 in the 10 windows holding it
        (glitch at ...)"``."""
        where = (f"t = {self.start_s:.6g}-{self.end_s:.6g} s" if self.end_s > self.start_s
                 else f"t = {self.start_s:.6g} s")
        text = (f"transient at {where}: deviation x{self.ratio:.3g} in the {self.n_windows} "
                f"window(s) holding it")
        if self.glitches:
            largest = sorted(self.glitches, key=lambda g: -abs(g.sigmas))[:2]
            text += (f" (glitch{'es' if len(self.glitches) > 1 else ''} found by the reader: "
                     + "; ".join(g.describe(units) for g in largest)
                     + (f"; and {len(self.glitches) - 2} more" if len(self.glitches) > 2
                        else "") + ")")
        return text


@dataclass(frozen=True)
class Nonstationarity:
    """How much the deviation varies between windows, against chance.

    :func:`~fogts.allan.dynamic.dynamic_allan` computes it from the windows' variances
    (:attr:`DynamicAllanResult.nonstationarity`).  A significant score alone does not make
    the record non-stationary: the change (or a transient) must also reach ``min_change``,
    since a long record makes a tiny change significant.

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
        False only when the score is significant (``pvalue < level``) *and* the change is
        at least ``min_change``.
    change_time_s : float or None
        Most likely single change time (s from the start), when not stationary.
    change_ratio : float or None
        Deviation after the change divided by the deviation before it (at ``tau_s``).
    flagged_windows : tuple of int
        Windows whose variance at ``tau_s`` lies outside the stationary interval
        (chi-squared at the Bonferroni level ``level / n_independent``).
    tau_scores : ndarray of float64
        The score at every tau of the result.
    significant : bool
        ``pvalue < level``.
    effect : float
        The size of the step change, ``|change_ratio - 1|``.
    min_change : float
        The smallest effect called a change.
    transient : Transient or None
        The largest excursion of single windows (None when no window is outside the
        stationary interval, or the run of windows reaches an end of the record).  The record is also not stationary when it is at least
        ``min_change`` (its windows are significant on their own, at the Bonferroni level).
    units : str
        Unit of the glitch values named in the text.
    window_s : float
        Length of the windows compared (NaN when unknown): the verdict names it, since a
        change shorter than a window is diluted in it, and the same record can be "NOT
        stationary" in 200 s windows and "stationary within 10 %" in 1000 s windows.
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
    significant: bool = False
    effect: float = 0.0
    min_change: float = 0.0
    transient: Transient | None = None
    units: str = ""
    window_s: float = math.nan

    @property
    def step_is_change(self) -> bool:
        """The step change is significant and at least ``min_change``."""
        return self.significant and self.effect >= self.min_change

    @property
    def transient_is_change(self) -> bool:
        """The transient is at least ``min_change``."""
        return self.transient is not None and self.transient.effect >= self.min_change

    def to_dict(self) -> dict[str, Any]:
        return {
            "tau": self.tau_s, "score": finite_or_none(self.score), "observed_var": finite_or_none(self.observed_var),
            "expected_var": finite_or_none(self.expected_var), "edf": finite_or_none(self.edf),
            "n_independent": self.n_independent, "pvalue": finite_or_none(self.pvalue),
            "level": self.level, "stationary": self.stationary,
            "change_time": self.change_time_s, "change_ratio": self.change_ratio,
            "flagged_windows": list(self.flagged_windows),
            "tau_scores": [finite_or_none(v) for v in self.tau_scores],
            "significant": self.significant, "effect": finite_or_none(self.effect),
            "min_change": self.min_change,
            "transient": self.transient.to_dict() if self.transient is not None else None,
        }

    def _verdict(self) -> tuple[str, str]:
        """The verdict and, for a significant change below ``min_change``, its size."""
        windows = f" in {self.window_s:g} s windows" if math.isfinite(self.window_s) else ""
        if not self.stationary:
            return f"NOT stationary{windows}", ""
        if self.significant:
            return (f"stationary within {100 * self.min_change:.3g} %{windows}",
                    f"the change is significant but only {100 * self.effect:.2g} %")
        return f"stationary{windows}", ""

    def _changes(self) -> list[str]:
        """Every change at least ``min_change``, the largest first."""
        changes = []  # (effect, text)
        if self.step_is_change and self.change_time_s is not None \
                and self.change_ratio is not None:
            changes.append((self.effect, f"most likely change at t = {self.change_time_s:.6g} "
                                         f"s, deviation x {self.change_ratio:.3g}"))
        if self.transient is not None and self.transient_is_change:
            changes.append((self.transient.effect, self.transient.describe(self.units)))
        return [t for _, t in sorted(changes, key=lambda c: -c[0])]

    def noise_level(self) -> str:
        """The verdict in one line for a summary of the noise terms: whether the noise level
        is stationary, in the words of :meth:`summary`, and, when it is not, that the
        noise terms fitted to the whole record average over the change."""
        head = (f"non-stationarity score {self.score:.3g} at tau = {self.tau_s:g} s, "
                f"p = {self.pvalue:.3g}")
        verdict, size = self._verdict()
        if self.stationary:
            return f"noise level: {verdict} (DAVAR: {head}{'; ' + size if size else ''})"
        return (f"noise level: {verdict} (DAVAR: {'; '.join(self._changes()) or head}): "
                "the noise terms average over it")

    def summary(self) -> str:
        """The verdict, then the changes it rests on, the largest first."""
        verdict, size = self._verdict()
        text = (f"non-stationarity score {self.score:.3g} at tau = {self.tau_s:g} s "
                f"(1 = chance; p = {self.pvalue:.3g}, {self.n_independent} independent "
                f"windows): {verdict}{f' ({size})' if size else ''}")
        text += "".join(f"; {t}" for t in self._changes())
        if self.flagged_windows:
            text += f"; {len(self.flagged_windows)} window(s) outside the stationary interval"
            if self.transient is not None and not self.transient_is_change:
                text += f", the largest a {self.transient.describe(self.units)}"
        return text


@dataclass(frozen=True, repr=False)
class DynamicAllanResult(TableView):
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
        ``"cumsum"`` or ``"kernel"`` (see :mod:`fogts.allan.window_sums`).
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
        Power-law noise type of each tau, identified on the samples of one window from the
        middle of the record.
    reference_dev : ndarray (n_tau,)
        Pooled deviation: the root of the mean window variance (the stationary hypothesis).
    outside : ndarray of bool (n_win, n_tau)
        Window variance outside the stationary chi-squared interval around the pooled
        variance (Bonferroni level, see :class:`Nonstationarity`).
    nonstationarity : Nonstationarity
    dropped : tuple of DroppedTau
    notes : tuple of str
    glitches : tuple of Glitch
        Glitches the reader found on this axis (given to :func:`dynamic_allan`), marked on
        the heat map.
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
    glitches: tuple[Glitch, ...] = ()

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
            "method": self.method, "confidence": finite_or_none(self.confidence),
            "taus": self.tau_s.tolist(), "m": self.m.tolist(), "n": self.n.tolist(),
            "edf": [finite_or_none(v) for v in self.edf], "alpha": self.alpha.tolist(),
            "times": self.times_s.tolist(),
            "dev": [[finite_or_none(v) for v in row] for row in self.dev],
            "ci_low": [[finite_or_none(v) for v in row] for row in self.ci_low],
            "ci_high": [[finite_or_none(v) for v in row] for row in self.ci_high],
            "reference_dev": [finite_or_none(v) for v in self.reference_dev],
            "nonstationarity": self.nonstationarity.to_dict(),
            "dropped": [d.to_dict() for d in self.dropped],
            "notes": list(self.notes),
        }

    # -------------------------------------------------------------- notebook view
    def _view_table(self) -> Table:
        """Per tau: the pooled deviation, its range over the windows and the share of
        windows outside the stationary interval."""
        rows = [(float(self.tau_s[j]), float(self.reference_dev[j]),
                 float(np.nanmin(self.dev[:, j])), float(np.nanmax(self.dev[:, j])),
                 float(np.mean(self.outside[:, j])))
                for j in range(self.tau_s.size)]
        return Table.build(
            f"Dynamic {self.kind} of {self.axis} ({self.units}), {self.shape[0]} windows of "
            f"{self.window_s:g} s", (Column("tau (s)"), Column("pooled"), Column("window min"),
                                     Column("window max"), Column("share outside", digits=2)),
            rows, caption=self.nonstationarity.summary())

    def _view_headline(self) -> str:
        verdict = "stationary" if self.nonstationarity.stationary else "not stationary"
        return (f"{self.kind} of {self.axis!r}, {self.shape[0]} windows of {self.window_s:g} s, "
                f"{self.tau_s.size} taus: {verdict}")

    def summary(self, max_rows: int = 12) -> str:
        """Text: the set-up, the verdict, and the deviation at a few taus over time."""
        nw, nt = self.shape
        # the lengths in samples too: at 99.3171 Hz a 60 s window is 5959 samples, 59.9997 s
        lines = [f"Dynamic {self.kind} of axis {self.axis!r}: {nw} windows of "
                 f"{self.window_s:g} s ({self.window_n} samples) every {self.step_s:g} s "
                 f"({self.step_n} samples) over {self.n_samples} samples "
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
        """Long format: an ``axis`` column, then those of :meth:`DynamicAllanResult.to_frame`."""
        return self._long_frame()

    def to_dict(self) -> dict[str, Any]:
        first = self.curves[0]
        return {"kind": first.kind, "window_s": first.window_s, "step_s": first.step_s,
                "axes": list(self.axes), "curves": [c.to_dict() for c in self.curves]}

    def summary(self) -> str:
        return "\n\n".join(c.summary() for c in self.curves)
