"""Figures over time: the recorded rate (and temperature), and the dynamic Allan deviation."""

from __future__ import annotations

from typing import Any

import numpy as np
from matplotlib.figure import Figure

from fogts._typing import FloatArray
from fogts.io.run import Run, held_time
from fogts.report.plots._common import minmax_envelope, mpl_text, time_unit

__all__ = ["plot_dynamic_allan", "plot_timeseries"]


class _TimeAxis:
    """The plotted time, ``run.time / scale``, formed slice by slice: the envelope of a
    1e8-sample record reads two strided slices and a tail, not a full-length copy, and a
    regular time base from the sample rate (:class:`fogts.io.run.RegularTime`) is not formed
    at all (its ``k``-th time is ``k / fs_hz``, the same floating-point value)."""

    def __init__(self, run: Any) -> None:
        self._held = held_time(run) if isinstance(run, Run) else np.asarray(run.time, float)
        self._fs = float(run.fs_hz)
        self.size = int(run.n)
        self.scale = 1.0

    def _seconds(self, sl: slice) -> FloatArray:
        if self._held is not None:
            return np.asarray(self._held[sl], dtype=np.float64)
        return np.arange(*sl.indices(self.size), dtype=np.float64) / self._fs

    @property
    def span_s(self) -> float:
        """Last minus first time (0 for one sample)."""
        if self.size < 2:
            return 0.0
        return float(self._seconds(slice(-1, None))[0] - self._seconds(slice(0, 1))[0])

    def __getitem__(self, sl: slice) -> FloatArray:
        return self._seconds(sl) / self.scale


def plot_timeseries(run: Any, *, max_points: int = 4000, width_in: float = 10.0) -> Figure:
    """Rate of every axis against time, and the temperature below it if recorded.

    Records longer than ``max_points`` samples are drawn as a min-max envelope per block
    (plus the block means), so spikes stay visible and the figure stays small.

    Parameters
    ----------
    run : fogts.io.run.Run
        The recording.
    max_points : int
        Largest number of samples drawn point by point.
    width_in : float
        Figure width in inches (each panel is 2 inches high).

    Returns
    -------
    matplotlib.figure.Figure
        One panel per rate axis, then the temperature, sharing the time axis.

    Examples
    --------
    >>> import numpy as np
    >>> from fogts.io.reader import read_run
    >>> fig = plot_timeseries(read_run(np.random.default_rng(0).normal(size=50_000), fs_hz=10))
    >>> len(fig.axes)
    1
    """
    has_temp = run.temperature is not None
    rows = run.n_axes + (1 if has_temp else 0)
    fig = Figure(figsize=(width_in, 1.0 + 2.0 * rows), layout="constrained")
    axes = fig.subplots(rows, 1, sharex=True, squeeze=False)[:, 0]
    ts = _TimeAxis(run)
    scale, unit = time_unit(ts.span_s)
    ts.scale = scale
    series = [(run.axis(i), f"{mpl_text(name)} [{run.units}]", "C0")
              for i, name in enumerate(run.axes)]
    if has_temp:
        series.append((np.asarray(run.temperature, dtype=np.float64), "temperature [°C]",
                       "C3"))
    for ax, (y, label, color) in zip(axes, series, strict=True):
        if y.size > max_points:
            tc, lo, hi, mean = minmax_envelope(ts, y, max_points // 2)
            ax.fill_between(tc, lo, hi, color=color, alpha=0.35, linewidth=0,
                            label="min-max per block")
            ax.plot(tc[:mean.size], mean, color=color, lw=0.8, label="block mean")
            if ax is axes[0]:
                ax.legend(loc="upper right", fontsize="small", frameon=False)
        else:
            ax.plot(ts[:], y, color=color, lw=0.6)
        ax.set_ylabel(label)
        ax.grid(True, alpha=0.3)
    axes[-1].set_xlabel(f"time [{unit}]")
    name = str(run.source).replace("\\", "/").rsplit("/", 1)[-1]
    axes[0].set_title(mpl_text(f"{name}: {run.n:,} samples at {run.fs_hz:.6g} Hz"),
                      fontsize="medium", loc="left")
    return fig


# ---- dynamic Allan deviation ------------------------------------------------------------
def _edges_linear(c: FloatArray) -> FloatArray:
    """Cell edges around sorted centres (mid-points; end cells mirrored)."""
    if c.size == 1:
        return np.array([c[0] - 0.5, c[0] + 0.5])
    mid = 0.5 * (c[1:] + c[:-1])
    return np.concatenate([[c[0] - (mid[0] - c[0])], mid, [c[-1] + (c[-1] - mid[-1])]])


def _edges_log(c: FloatArray) -> FloatArray:
    return np.exp(_edges_linear(np.log(c)))


def _stationarity_strip(strip: Any, res: Any, t: FloatArray, j: int, small: bool) -> None:
    """The deviation at tau index ``j`` against window time, with the stationary interval
    around the pooled value and the windows outside it."""
    from scipy.stats import chi2

    stat = res.nonstationarity
    ref = float(res.reference_dev[j])
    flagged = res.outside[:, j]
    edf = float(res.edf[j])
    if np.isfinite(edf) and edf > 0:
        # the stationary interval the window flags use (Bonferroni level)
        a = stat.level / stat.n_independent
        band = ref * np.sqrt(np.array([chi2.ppf(a / 2, edf), chi2.isf(a / 2, edf)]) / edf)
        strip.axhspan(band[0], band[1], color="0.85", lw=0, label="stationary interval")
    strip.axhline(ref, color="0.4", lw=0.8, ls=":")
    strip.plot(t, res.dev[:, j], color="C0", lw=0.9)
    if flagged.any():
        strip.plot(t[flagged], res.dev[flagged, j], "o", color="C3", ms=2.5,
                   label="window outside it")
    strip.legend(loc="upper left", fontsize="x-small", framealpha=0.8, ncols=2)
    strip.set_ylabel(f"dev @ {stat.tau_s:.3g} s", fontsize="small")
    strip.tick_params(labelbottom=False, labelsize="small")
    strip.grid(True, alpha=0.3)
    verdict = "stationary" if stat.stationary else "not stationary"
    strip.set_title(mpl_text(f"{res.axis}: {res.kind}, window {res.window_s:g} s, step "
                              f"{res.step_s:g} s\n{verdict} (non-stationarity score "
                              f"{stat.score:.3g}, p = {stat.pvalue:.2g})"),
                    fontsize="small" if small else "medium", loc="left")


def _mark_glitches(strip: Any, ax: Any, res: Any, scale: float) -> None:
    """The glitches the reader found: a red triangle above the heat map and a dotted line
    through it at each; the largest transient shaded on the strip."""
    tr = res.nonstationarity.transient
    if tr is not None and tr.effect >= res.nonstationarity.min_change:
        strip.axvspan(tr.start_s / scale, max(tr.end_s, tr.start_s + res.step_s) / scale,
                      color="C3", alpha=0.25, lw=0, label="transient")
        strip.legend(loc="upper left", fontsize="x-small", framealpha=0.8, ncols=3)
    if not res.glitches:
        return
    tg = np.array([g.time_s for g in res.glitches]) / scale
    for t in tg:
        ax.axvline(t, color="C3", lw=0.8, ls=":")
    ax.plot(tg, np.full(tg.size, float(res.tau_s[-1])), "v", color="C3", ms=6,
            clip_on=False, label=f"glitch ({tg.size})")
    ax.legend(loc="lower right", fontsize="x-small", framealpha=0.8)


def _mark_change(strip: Any, ax: Any, res: Any, scale: float, unit: str) -> None:
    """A dashed line at the most likely change time, on the strip and the heat map."""
    change = res.nonstationarity.change_time_s
    if change is None:
        return
    for a in (strip, ax):
        a.axvline(change / scale, color="w" if a is ax else "C3", lw=1.2, ls="--")
    ax.annotate(f"change at {change / scale:.4g} {unit}", (change / scale, float(res.tau_s[-1])),
                color="w", fontsize="small", xytext=(4, -4), textcoords="offset points",
                va="top")


def plot_dynamic_allan(result: Any, *, width_in: float = 10.0) -> Figure:
    """Dynamic Allan deviation as a heat map of log deviation over (time, log tau).

    In the style of Stable32's "dynamic stability" plot, drawn from above: each column is
    one window (placed at its centre time), each row one tau, and the colour the
    deviation on a logarithmic scale.  A strip above the map shows the deviation at the
    shortest tau against time with the stationary interval around the pooled value
    (windows outside it in red), and a dashed line marks the most likely change time when
    the record is not stationary; a transient of at least ``min_change`` is shaded on the
    strip, and the glitches the reader found (``glitches=`` of
    :func:`~fogts.allan.dynamic.dynamic_allan`) are red triangles and dotted lines on the
    map.  A :class:`~fogts.allan.dynamic.DynamicAllanResultSet`
    gives one column of panels per axis.

    Parameters
    ----------
    result : DynamicAllanResult or DynamicAllanResultSet
    width_in : float
        Width of the whole figure in inches.

    Returns
    -------
    matplotlib.figure.Figure
        Per axis a strip above a heat map, and one colour bar.

    Examples
    --------
    >>> from fogts.allan.dynamic import dynamic_allan
    >>> y = np.random.default_rng(0).normal(size=20_000)
    >>> fig = plot_dynamic_allan(dynamic_allan(y, fs_hz=1.0, window_s=1000, step_s=250))
    >>> len(fig.axes)   # strip, heat map, colour bar
    3
    """
    from matplotlib.colors import LogNorm

    curves = list(getattr(result, "curves", [result]))
    ncol = len(curves)
    fig = Figure(figsize=(width_in * (1.0 if ncol == 1 else 0.45 * ncol + 0.1), 6.0),
                 layout="constrained")
    grid = fig.add_gridspec(2, ncol, height_ratios=[1.2, 3])
    dev_all = np.concatenate([c.dev[np.isfinite(c.dev) & (c.dev > 0)] for c in curves])
    norm = LogNorm(vmin=float(dev_all.min()), vmax=float(dev_all.max())) if dev_all.size \
        else None
    scale, unit = time_unit(max(float(c.times_s[-1] + c.window_s / 2) for c in curves))
    mesh = None
    for col, res in enumerate(curves):
        strip = fig.add_subplot(grid[0, col])
        ax = fig.add_subplot(grid[1, col], sharex=strip)
        t = res.times_s / scale
        j = int(np.argmin(np.abs(res.tau_s - res.nonstationarity.tau_s)))
        _stationarity_strip(strip, res, t, j, small=ncol > 1)
        mesh = ax.pcolormesh(_edges_linear(t), _edges_log(res.tau_s), res.dev.T, norm=norm,
                             cmap="viridis", shading="flat", rasterized=True)
        ax.set_yscale("log")
        ax.set_xlabel(f"window centre time [{unit}]")
        if col == 0:
            ax.set_ylabel("tau [s]")
        _mark_change(strip, ax, res, scale, unit)
        _mark_glitches(strip, ax, res, scale)
    if mesh is not None:
        fig.colorbar(mesh, ax=fig.axes[1::2], label=f"deviation [{curves[0].units}]",
                     shrink=0.95)
    return fig
