"""Plots: result -> matplotlib Figure; pure; no show().

Every function takes a fogts result and returns a new :class:`matplotlib.figure.Figure`
built without pyplot state, so it is safe in scripts, servers and worker processes.  Save
it with ``fig.savefig(path)``.
"""

from __future__ import annotations

from typing import Any

import numpy as np
from matplotlib.figure import Figure

from fogts._typing import FloatArray

__all__ = ["plot_allan", "plot_compensation", "plot_dynamic_allan", "plot_kalman",
           "plot_north_seeking", "plot_selection", "plot_timeseries"]


def _mpl_text(text: str) -> str:
    """Escape ``$`` so untrusted names are never parsed as mathtext."""
    return str(text).replace("$", r"\$")


def _envelope(t: FloatArray, y: FloatArray, bins: int) -> tuple[FloatArray, FloatArray,
                                                                FloatArray]:
    """Min-max envelope of ``y`` in ``bins`` equal-count blocks: (time, low, high)."""
    n = y.size
    size = int(np.ceil(n / bins))
    k = n // size
    head = y[: k * size].reshape(k, size)
    lo, hi = head.min(axis=1), head.max(axis=1)
    tc = t[: k * size : size] + 0.5 * (t[size - 1 : k * size : size] - t[: k * size : size])
    if n > k * size:
        lo = np.append(lo, y[k * size:].min())
        hi = np.append(hi, y[k * size:].max())
        tc = np.append(tc, t[k * size:].mean())
    return tc, lo, hi


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
        Figure width in inches.

    Returns
    -------
    matplotlib.figure.Figure

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
    t = np.asarray(run.time, dtype=np.float64)
    span = float(t[-1] - t[0]) if t.size > 1 else 0.0
    scale, unit = (3600.0, "h") if span >= 3 * 3600 else (60.0, "min") if span >= 180 \
        else (1.0, "s")
    ts = t / scale
    series = [(run.axis(i), f"{_mpl_text(name)} [{run.units}]", "C0")
              for i, name in enumerate(run.axes)]
    if has_temp:
        series.append((np.asarray(run.temperature, dtype=np.float64), "temperature [°C]",
                       "C3"))
    for ax, (y, label, color) in zip(axes, series, strict=True):
        if y.size > max_points:
            tc, lo, hi = _envelope(ts, y, max_points // 2)
            ax.fill_between(tc, lo, hi, color=color, alpha=0.35, linewidth=0,
                            label="min-max per block")
            size = int(np.ceil(y.size / (max_points // 2)))
            k = y.size // size
            ax.plot(tc[:k], y[: k * size].reshape(k, size).mean(axis=1), color=color, lw=0.8,
                    label="block mean")
            if ax is axes[0]:
                ax.legend(loc="upper right", fontsize="small", frameon=False)
        else:
            ax.plot(ts, y, color=color, lw=0.6)
        ax.set_ylabel(label)
        ax.grid(True, alpha=0.3)
    axes[-1].set_xlabel(f"time [{unit}]")
    name = str(run.source).replace("\\", "/").rsplit("/", 1)[-1]
    axes[0].set_title(_mpl_text(f"{name}: {run.n:,} samples at {run.fs_hz:.6g} Hz"),
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


def plot_dynamic_allan(result: Any, *, width_in: float = 10.0) -> Figure:
    """Dynamic Allan deviation as a heat map of log deviation over (time, log tau).

    In the style of Stable32's "dynamic stability" plot, drawn from above: each column is
    one window (placed at its centre time), each row one tau, and the colour the
    deviation on a logarithmic scale.  A strip above the map shows the deviation at the
    shortest tau against time with the stationary interval around the pooled value
    (windows outside it in red), and a dashed line marks the most likely change time when
    the record is not stationary.  A :class:`~fogts.allan.dynamic.DynamicAllanResultSet`
    gives one column of panels per axis.

    Parameters
    ----------
    result : DynamicAllanResult or DynamicAllanResultSet
    width_in : float
        Figure width in inches.

    Returns
    -------
    matplotlib.figure.Figure

    Examples
    --------
    >>> import numpy as np
    >>> from fogts.allan.dynamic import dynamic_allan
    >>> y = np.random.default_rng(0).normal(size=20_000)
    >>> fig = plot_dynamic_allan(dynamic_allan(y, fs_hz=1.0, window_s=1000, step_s=250))
    >>> len(fig.axes)   # strip, heat map, colour bar
    3
    """
    from matplotlib.colors import LogNorm
    from scipy.stats import chi2

    curves = list(getattr(result, "curves", [result]))
    ncol = len(curves)
    fig = Figure(figsize=(width_in * (1.0 if ncol == 1 else 0.45 * ncol + 0.1), 6.0),
                 layout="constrained")
    grid = fig.add_gridspec(2, ncol, height_ratios=[1.2, 3])
    dev_all = np.concatenate([c.dev[np.isfinite(c.dev) & (c.dev > 0)] for c in curves])
    norm = LogNorm(vmin=float(dev_all.min()), vmax=float(dev_all.max())) if dev_all.size \
        else None
    span = max(float(c.times_s[-1] + c.window_s / 2) for c in curves)
    scale, unit = (3600.0, "h") if span >= 3 * 3600 else (60.0, "min") if span >= 180 \
        else (1.0, "s")
    mesh = None
    for col, res in enumerate(curves):
        strip = fig.add_subplot(grid[0, col])
        ax = fig.add_subplot(grid[1, col], sharex=strip)
        t = res.times_s / scale
        stat = res.nonstationarity
        j = int(np.argmin(np.abs(res.tau_s - stat.tau_s)))
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
        strip.set_title(_mpl_text(f"{res.axis}: {res.kind}, window {res.window_s:g} s, step "
                                  f"{res.step_s:g} s\n{verdict} (non-stationarity score "
                                  f"{stat.score:.3g}, p = {stat.pvalue:.2g})"),
                        fontsize="medium" if ncol == 1 else "small", loc="left")
        mesh = ax.pcolormesh(_edges_linear(t), _edges_log(res.tau_s), res.dev.T, norm=norm,
                             cmap="viridis", shading="flat", rasterized=True)
        ax.set_yscale("log")
        ax.set_xlabel(f"window centre time [{unit}]")
        if col == 0:
            ax.set_ylabel("tau [s]")
        if stat.change_time_s is not None:
            for a in (strip, ax):
                a.axvline(stat.change_time_s / scale, color="w" if a is ax else "C3", lw=1.2,
                          ls="--")
            ax.annotate(f"change at {stat.change_time_s / scale:.4g} {unit}",
                        (stat.change_time_s / scale, float(res.tau_s[-1])), color="w",
                        fontsize="small", xytext=(4, -4), textcoords="offset points",
                        va="top")
    if mesh is not None:
        fig.colorbar(mesh, ax=fig.axes[1::2], label=f"deviation [{curves[0].units}]",
                     shrink=0.95)
    return fig


# ---- Allan deviation with the noise-term fit ----------------------------------------------
_TERM_STYLE: dict[str, tuple[str, str]] = {
    # term -> (colour, slope label)
    "Q": ("#8c564b", "−1"), "N": ("#1f77b4", "−1/2"), "B": ("#2ca02c", "0"),
    "K": ("#d62728", "+1/2"), "R": ("#9467bd", "+1"),
}
_TERM_UNIT_TEX: dict[str, str] = {
    "Q": "arcsec", "N": r"°/$\sqrt{\mathrm{h}}$", "B": "°/h", "K": r"°/h$^{1.5}$",
    "R": r"°/h$^{2}$",
}
_KIND_SYMBOL: dict[str, str] = {
    "adev": "Allan deviation", "oadev": "overlapping Allan deviation",
    "mdev": "modified Allan deviation", "hdev": "Hadamard deviation",
    "ohdev": "overlapping Hadamard deviation", "totdev": "total deviation",
}


def _num_tex(v: float) -> str:
    """A number with 3 significant digits, in scientific notation when far from 1."""
    if not np.isfinite(v):
        return "n/a"
    if v == 0 or 1e-3 <= abs(v) < 1e4:
        return f"{v:.3g}"
    mant, exp = f"{v:.2e}".split("e")
    return rf"{mant}$\times$10$^{{{int(exp)}}}$"


def _value_pm_tex(value: float, stderr: float) -> str:
    """``value ± stderr`` rounded to the standard error's two significant digits.

    The two share one power of ten when the value is outside [0.01, 1e4), e.g.
    ``(2.0030 ± 0.0045)×10^-3`` instead of ``0.002 ± 4.45×10^-6``, so the reader sees how
    many digits of the value mean something.
    """
    if not (np.isfinite(stderr) and stderr > 0 and np.isfinite(value) and value != 0):
        return _num_tex(value) + (rf" ± {_num_tex(stderr)}" if np.isfinite(stderr) else "")
    exp = 0 if 1e-2 <= abs(value) < 1e4 else int(np.floor(np.log10(abs(value))))
    scale = 10.0 ** exp
    decimals = max(0, 1 - int(np.floor(np.log10(stderr / scale))))
    text = f"{value / scale:.{decimals}f} ± {stderr / scale:.{decimals}f}"
    return text if exp == 0 else rf"({text})$\times$10$^{{{exp}}}$"


def _readoff_line(ax: Any, res: Any, readoff: Any, name: str, tau_ro: float,
                  dev_ro: float) -> None:
    """The dotted -1/2 or +1/2 line from the curve point it was drawn through to the point
    it is read at (B is read on the curve itself)."""
    if name not in ("N", "K"):
        return
    tau_from = float(getattr(readoff, f"tau_{name}_s"))
    tau = np.asarray(res.tau_s, dtype=np.float64)
    hit = np.flatnonzero(np.isclose(tau, tau_from, rtol=1e-9))
    if hit.size == 0 or tau_from == tau_ro:
        return
    dev_from = float(np.asarray(res.dev, dtype=np.float64)[hit[0]])
    ax.plot([tau_from, tau_ro], [dev_from, dev_ro], ":", color=_TERM_STYLE[name][0], lw=1.1,
            zorder=4)


def _allan_curve(ax: Any, res: Any, colour: str, label: str) -> None:
    tau = np.asarray(res.tau_s, dtype=np.float64)
    dev = np.asarray(res.dev, dtype=np.float64)
    lo = np.asarray(getattr(res, "ci_low", np.full_like(dev, np.nan)), dtype=np.float64)
    hi = np.asarray(getattr(res, "ci_high", np.full_like(dev, np.nan)), dtype=np.float64)
    ok = np.isfinite(dev) & (dev > 0)
    has_ci = ok & np.isfinite(lo) & np.isfinite(hi) & (lo > 0)
    level = float(getattr(res, "confidence", np.nan))
    if has_ci.any():
        ax.errorbar(tau[has_ci], dev[has_ci],
                    yerr=[dev[has_ci] - lo[has_ci], hi[has_ci] - dev[has_ci]], fmt="none",
                    ecolor=colour, elinewidth=1.0, capsize=2.5, alpha=0.8, zorder=3)
        if np.isfinite(level):
            label += f" ({100 * level:.1f} % CI)"
    ax.plot(tau[ok], dev[ok], "o", color=colour, ms=4.5, mfc="white", mew=1.3, label=label,
            zorder=4)


def plot_allan(result: Any, noise: Any = None, *, ax: Any = None) -> Figure:
    """Allan deviation on log-log axes, with the IEEE-952 fit and its term lines.

    Draws each point with its confidence interval, the fitted total curve, each fitted
    term's own line labelled with its slope (-1 Q, -1/2 N, 0 B, +1/2 K, +1 R; IEEE Std
    952-1997 Annex C, Fig. C.10) and value, and the classic slope read-off points
    (comparison only): the -1/2 line at tau = 1 s (N), the +1/2 line at tau = 3 s (K)
    and the minimum (B = minimum / 0.664).

    Parameters
    ----------
    result : AllanResult or AllanResultSet
        The curve(s).  A result set draws every axis in its own colour with its fitted
        total only (term lines would clutter the figure).
    noise : NoiseModel or sequence of NoiseModel, optional
        The fit (one per curve for a result set).
    ax : matplotlib Axes, optional
        Draw into this Axes (its Figure is returned); by default a new Figure is made.

    Returns
    -------
    matplotlib.figure.Figure

    Examples
    --------
    >>> import numpy as np, warnings
    >>> from fogts.allan import allan_deviation
    >>> from fogts.allan.noise import fit_noise
    >>> rng = np.random.default_rng(0)
    >>> y = rng.normal(scale=10.0, size=200_000) + np.cumsum(rng.normal(scale=0.01, size=200_000))
    >>> res = allan_deviation(y, fs_hz=100.0)
    >>> with warnings.catch_warnings():
    ...     warnings.simplefilter("ignore")
    ...     fig = plot_allan(res, fit_noise(res))
    >>> fig.axes[0].get_xscale(), fig.axes[0].get_yscale()
    ('log', 'log')
    """
    curves = list(getattr(result, "curves", [result]))
    models: list[Any]
    if noise is None:
        models = [None] * len(curves)
    elif isinstance(noise, list | tuple):
        models = list(noise)
    else:
        models = [noise]
    if len(models) != len(curves):
        from fogts.errors import DataError

        raise DataError(f"noise must give one model per curve: {len(curves)} curve(s), "
                        f"{len(models)} model(s)")
    if ax is None:
        fig = Figure(figsize=(8.0, 5.6), layout="constrained")
        ax = fig.add_subplot()
    else:
        fig = ax.figure
    single = len(curves) == 1
    tau_all = np.concatenate([np.asarray(c.tau_s, dtype=np.float64) for c in curves])
    dev_all = np.concatenate([np.asarray(c.dev, dtype=np.float64) for c in curves])
    good = np.isfinite(dev_all) & (dev_all > 0)
    lo_all = np.concatenate([np.asarray(getattr(c, "ci_low", c.dev), dtype=np.float64)
                             for c in curves])
    hi_all = np.concatenate([np.asarray(getattr(c, "ci_high", c.dev), dtype=np.float64)
                             for c in curves])
    ymin = float(np.nanmin(np.where(good & (lo_all > 0), lo_all, dev_all)[good]))
    ymax = float(np.nanmax(np.where(good & np.isfinite(hi_all), hi_all, dev_all)[good]))
    xlim = (float(tau_all.min()) / 1.5, float(tau_all.max()) * 1.5)
    if single and models[0] is not None:  # widen to show read-off points near the data
        near = [dev for _, tau, dev in models[0].readoff.points
                if np.isfinite(dev) and xlim[0] <= tau <= xlim[1]
                and ymin / 20 <= dev <= ymax * 20]
        ymin, ymax = min([ymin, *near]), max([ymax, *near])
    ylim = (ymin / 2.5, ymax * 2.5)
    fine = np.logspace(np.log10(xlim[0]), np.log10(xlim[1]), 400)

    for i, (res, model) in enumerate(zip(curves, models, strict=True)):
        colour = "0.15" if single else f"C{i}"
        label = _KIND_SYMBOL.get(res.kind, res.kind) if single else _mpl_text(res.axis)
        _allan_curve(ax, res, colour, label)
        if model is None:
            continue
        fit_label = (f"fitted total ({model.method.upper()})" if single
                     else f"{_mpl_text(res.axis)}: fit")
        ax.plot(fine, model.curve(fine), "-", color="0.15" if single else colour, lw=1.8,
                alpha=0.9, label=fit_label, zorder=5)
        if not single:
            continue
        for term in model.terms:
            if term.value <= 0:
                continue
            line = model.term_line(term.name, fine)
            shown = (line >= ylim[0]) & (line <= ylim[1])
            if not shown.any():
                continue
            tcolour, slope = _TERM_STYLE[term.name]
            flag = "" if term.identifiable else " (not identifiable)"
            ax.plot(fine[shown], line[shown], "--", color=tcolour, lw=1.3,
                    label=f"{term.name}: slope {slope}, {term.name} = "
                          f"{_value_pm_tex(term.value, term.stderr)} "
                          f"{_TERM_UNIT_TEX[term.name]}{flag}", zorder=2)
        ro = model.readoff
        names = {"N": f"read-off N = {_num_tex(ro.N)} {_TERM_UNIT_TEX['N']} (−1/2 line at τ = 1 s)",
                 "K": f"read-off K = {_num_tex(ro.K)} {_TERM_UNIT_TEX['K']} (+1/2 line at τ = 3 s)",
                 "B": f"read-off B = {_num_tex(ro.B)} {_TERM_UNIT_TEX['B']} (minimum / 0.664)"}
        markers = {"N": "v", "K": "^", "B": "s"}
        for name, tau_ro, dev_ro in ro.points:
            if (np.isfinite(dev_ro) and xlim[0] <= tau_ro <= xlim[1]
                    and ylim[0] <= dev_ro <= ylim[1]):
                ax.plot([tau_ro], [dev_ro], markers[name], color=_TERM_STYLE[name][0],
                        mfc="none", ms=9, mew=1.6, label=names[name], zorder=6)
                _readoff_line(ax, res, ro, name, tau_ro, dev_ro)
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlim(*xlim)
    ax.set_ylim(*ylim)
    units = curves[0].units
    kind = curves[0].kind
    ax.set_xlabel("averaging time τ [s]")
    ax.set_ylabel(f"{_KIND_SYMBOL.get(kind, kind)} σ(τ) [{_mpl_text(units)}]")
    ax.grid(True, which="major", alpha=0.45)
    ax.grid(True, which="minor", alpha=0.15)
    res = curves[0]
    if getattr(res, "fs_hz", 0) and getattr(res, "n_samples", 0):
        span = res.n_samples / res.fs_hz
        dur = (f"{span / 3600:.3g} h" if span >= 3 * 3600 else f"{span / 60:.3g} min"
               if span >= 180 else f"{span:.3g} s")
        who = res.axis if single else f"{len(curves)} axes"
        ax.set_title(_mpl_text(f"{who}: {res.n_samples} samples at {res.fs_hz:g} Hz "
                               f"({dur})"), loc="left", fontsize="medium")
    ax.legend(loc="best", fontsize="small", framealpha=0.85)
    return fig


# ---- start-up compensation (issue 6: kalman, thermal, northfind) --------------------------
def plot_kalman(result: Any, *, time_s: Any = None, units: str = "", max_points: int = 20000,
                width_in: float = 10.0) -> Figure:
    """Observed, Kalman-filtered and smoothed series of a :class:`fogts.startup.kalman.KalmanResult`.

    Long records are thinned to at most ``max_points`` points per line (every k-th sample).
    """
    obs = np.asarray(result.observed, dtype=float)
    t = np.arange(obs.size, dtype=float) if time_s is None else np.asarray(time_s, dtype=float)
    step = max(1, int(np.ceil(obs.size / max_points)))
    fig = Figure(figsize=(width_in, 4.0), layout="constrained")
    ax = fig.add_subplot()
    ax.plot(t[::step], obs[::step], lw=0.5, color="0.65", label="observed")
    ax.plot(t[::step], np.asarray(result.filtered)[::step], lw=0.8, color="C0", label="filtered")
    smoothed = np.asarray(result.smoothed, dtype=float)
    if np.isfinite(smoothed).any():
        ax.plot(t[::step], smoothed[::step], lw=0.8, color="C3", label="smoothed")
    ax.set_xlabel("time [s]" if time_s is not None else "sample")
    ax.set_ylabel(f"rate [{_mpl_text(units)}]" if units else "rate")
    ax.set_title(_mpl_text(f"Kalman filter, {result.model} + white noise "
                           f"(H = {result.measurement_noise:.3g}, {result.method})"))
    ax.legend(loc="upper right", fontsize="small")
    ax.grid(alpha=0.3)
    return fig


def plot_compensation(result: Any, *, max_points: int = 20000, width_in: float = 10.0) -> Figure:
    """Start-up compensation (:class:`fogts.startup.thermal.StartupCompensation`): raw rate, EMD trend
    and compensated rate on top, temperature below; bias stability before/after in the title."""
    frame = result.to_frame()
    t = frame["time"].to_numpy()
    step = max(1, int(np.ceil(t.size / max_points)))
    units = _mpl_text(result.run.units)
    fig = Figure(figsize=(width_in, 6.0), layout="constrained")
    ax1, ax2 = fig.subplots(2, 1, sharex=True, height_ratios=(2, 1))
    ax1.plot(t[::step], frame["raw"].to_numpy()[::step], lw=0.5, color="0.65", label="raw rate")
    trend = frame["trend"].to_numpy()
    if np.isfinite(trend).any():
        ax1.plot(t[::step], trend[::step], lw=1.2, color="C1", label="EMD trend")
    ax1.plot(t[::step], frame["compensated"].to_numpy()[::step], lw=0.5, color="C0", alpha=0.8,
             label="compensated")
    ax1.set_ylabel(f"rate [{units}]")
    b, a = result.before, result.after
    ax1.set_title(f"bias stability (1σ, {b.average_s:g} s average): {b.value:.3g} → "
                  f"{a.value:.3g} {_mpl_text(b.unit)}")
    ax1.legend(loc="upper right", fontsize="small")
    ax1.grid(alpha=0.3)
    ax2.plot(t[::step], frame["temperature"].to_numpy()[::step], lw=1.0, color="C3")
    ax2.set_ylabel("temperature [°C]")
    ax2.set_xlabel("time [s]")
    ax2.grid(alpha=0.3)
    return fig


def plot_north_seeking(study: Any, *, width_in: float = 8.0) -> Figure:
    """Azimuth errors of a :class:`fogts.startup.northfind.NorthSeekingStudy`, raw and compensated."""
    fig = Figure(figsize=(width_in, 4.0), layout="constrained")
    ax = fig.add_subplot()
    raw = np.asarray(study.raw_error_deg)
    ax.plot(np.arange(1, raw.size + 1), raw, "o", ms=3, color="0.5", label="raw")
    comp = study.compensated_error_deg
    if comp is not None:
        ax.plot(np.arange(1, raw.size + 1), np.asarray(comp), "o", ms=3, color="C0",
                label="compensated")
    ax.axhline(0.0, color="k", lw=0.6)
    ax.set_xlabel("trial")
    ax.set_ylabel("azimuth error [°]")
    ax.set_title(f"cold-start four-position north seeking at {study.latitude_deg:g}°")
    ax.legend(loc="upper right", fontsize="small")
    ax.grid(alpha=0.3)
    return fig


# ---- ARMA selection (issue 4: fogts select) -----------------------------------------------
def _stem(ax: Any, lags: FloatArray, values: FloatArray, colour: str) -> None:
    ax.vlines(lags, 0.0, values, colors=colour, lw=1.2)
    ax.plot(lags, values, "o", ms=3, color=colour)
    ax.axhline(0.0, color="k", lw=0.6)


def plot_selection(selection: Any, *, window: int = 400, width_in: float = 10.0) -> Figure:
    """Diagnostics of a :class:`fogts.arma.select.Selection` (seed 000, Figs. 3-5).

    Panels: the data's ACF (Bartlett band) and PACF (band 1.96/sqrt(n)), with the Box-Jenkins
    reading in their titles; the selected model's residual ACF with the band +-1.96/sqrt(n);
    a normal Q-Q plot of the standardised residuals; and the one-step-ahead prediction against
    the data over the first ``window`` samples, with the share of variance it removes.

    Parameters
    ----------
    selection : Selection
        The result of :func:`fogts.arma.select.select_arma`.
    window : int
        Samples shown in the prediction panel.
    width_in : float
        Figure width in inches.

    Returns
    -------
    matplotlib.figure.Figure

    Examples
    --------
    >>> from scipy.signal import lfilter
    >>> from fogts.arma import select_arma
    >>> e = np.random.default_rng(0).standard_normal(2000)
    >>> fig = plot_selection(select_arma(lfilter([1.0], [1.0, -0.5], e)))
    >>> len(fig.axes)
    5
    """
    from scipy.stats import norm

    corr = selection.correlogram
    best = selection.best
    fig = Figure(figsize=(width_in, 0.8 * width_in), layout="constrained")
    grid = fig.add_gridspec(3, 2, height_ratios=(1.0, 1.0, 1.1))
    ax_acf, ax_pacf = fig.add_subplot(grid[0, 0]), fig.add_subplot(grid[0, 1])
    ax_racf, ax_qq = fig.add_subplot(grid[1, 0]), fig.add_subplot(grid[1, 1])
    ax_pred = fig.add_subplot(grid[2, :])

    lags = np.arange(1, corr.nlags + 1, dtype=float)
    ax_acf.fill_between(lags, -corr.acf_band[1:], corr.acf_band[1:], color="C0", alpha=0.15,
                        lw=0, label="95 % band (Bartlett)")
    _stem(ax_acf, lags, corr.acf[1:], "C0")
    ax_acf.set_title(f"data ACF: {corr.acf_pattern.describe()}", loc="left", fontsize="medium")
    ax_pacf.axhspan(-corr.band, corr.band, color="C0", alpha=0.15, lw=0,
                    label="95 % band ±1.96/√n")
    _stem(ax_pacf, lags, corr.pacf[1:], "C0")
    ax_pacf.set_title(f"data PACF: {corr.pacf_pattern.describe()}", loc="left",
                      fontsize="medium")
    for ax in (ax_acf, ax_pacf):
        ax.set_xlabel("lag")
        ax.legend(loc="upper right", fontsize="small", framealpha=0.85)
        ax.grid(alpha=0.3)

    if best is None:
        for ax in (ax_racf, ax_qq, ax_pred):
            ax.text(0.5, 0.5, "no candidate could be fitted", ha="center", va="center",
                    transform=ax.transAxes)
            ax.set_axis_off()
        fig.suptitle(_mpl_text(selection.verdict[:120]), fontsize="medium")
        return fig

    diag = best.diagnostics
    rl = np.arange(1, diag.acf.size, dtype=float)
    ax_racf.axhspan(-diag.band, diag.band, color="C2", alpha=0.15, lw=0,
                    label="95 % band ±1.96/√n")
    _stem(ax_racf, rl, diag.acf[1:], "C2")
    lb = ", ".join(f"Q({x.lag}) p={x.pvalue:.2g}" for x in diag.ljung_box)
    ax_racf.set_title(_mpl_text(f"{best.model} residual ACF ({lb})"), loc="left",
                      fontsize="medium")
    ax_racf.set_xlabel("lag")
    ax_racf.legend(loc="upper right", fontsize="small", framealpha=0.85)
    ax_racf.grid(alpha=0.3)

    resid = np.asarray(best.resid, dtype=float)
    z = (resid - resid.mean()) / resid.std() if resid.std() > 0 else resid
    m = min(z.size, 2000)
    probs = (np.arange(1, m + 1) - 0.5) / m
    theo = norm.ppf(probs)
    ax_qq.plot(theo, np.quantile(z, probs), ".", ms=3, color="C2")
    lim = float(max(abs(theo[0]), abs(theo[-1])))
    ax_qq.plot([-lim, lim], [-lim, lim], color="k", lw=0.8)
    ax_qq.set_xlabel("normal quantile")
    ax_qq.set_ylabel("standardised residual")
    ax_qq.set_title(f"{best.model} residual Q–Q ({m} quantiles)", loc="left",
                    fontsize="medium")
    ax_qq.grid(alpha=0.3)

    pred = best.predict()
    k = min(pred.n, max(10, int(window)))
    t = pred.time[:k] if pred.time is not None else np.arange(k, dtype=float)
    ax_pred.plot(t, pred.observed[:k], "-", lw=0.8, color="0.55", label="observed x_t")
    ax_pred.plot(t, pred.predicted[:k], "-", lw=1.0, color="C1",
                 label="one-step prediction")
    ax_pred.set_xlabel("time [s]" if pred.time is not None else "sample")
    units = selection.units
    ax_pred.set_ylabel(_mpl_text(f"drift [{units}]") if units else "drift")
    ax_pred.set_title(_mpl_text(f"one-step prediction with {best.model}, first {k} of "
                                f"{pred.n} samples: removes "
                                f"{100 * pred.variance_removed:.1f} % of the variance"),
                      loc="left", fontsize="medium")
    ax_pred.legend(loc="upper right", fontsize="small", framealpha=0.85, ncol=2)
    ax_pred.grid(alpha=0.3)
    verdict = "white residuals" if best.white else "residuals NOT white"
    fig.suptitle(_mpl_text(f"selected {best.model} by {selection.criterion.upper()} "
                           f"({verdict}):  {best.equation()}"), fontsize="medium")
    return fig


def plot_allan_comparison(comparison: Any, *, width_in: float = 7.5) -> Figure:
    """Allan deviation before and after filtering on one log-log figure (seed 001).

    Both curves carry their confidence intervals; the filter's ``1/cutoff`` is marked,
    since filtering changes the noise seen at shorter tau, and the fitted totals of both
    curves are drawn over the tau range the fits used.

    Parameters
    ----------
    comparison : AllanComparison
        From :func:`fogts.allan.compare.compare_allan`.
    """
    fig = Figure(figsize=(width_in, 0.72 * width_in), layout="constrained")
    ax = fig.add_subplot()
    colours = ("tab:blue", "tab:orange")
    curves = (comparison.before, comparison.after)
    fits = (comparison.noise_before, comparison.noise_after)
    for res, fit, colour, label in zip(curves, fits, colours, comparison.labels, strict=True):
        _allan_curve(ax, res, colour, label)
        tau = np.logspace(np.log10(fit.tau_s[0]), np.log10(fit.tau_s[-1]), 200)
        ax.plot(tau, fit.curve(tau), "-", color=colour, lw=1.2, alpha=0.8,
                label=f"{label}: IEEE-952 fit")
    if comparison.cutoff_hz:
        edge = 1.0 / comparison.cutoff_hz
        ax.axvline(edge, color="0.4", ls="--", lw=1.0)
        ax.text(edge, 0.02, " 1/cutoff", transform=ax.get_xaxis_transform(), color="0.3",
                fontsize="small")
    if comparison.fit_min_tau_s > 0:
        ax.axvspan(comparison.before.tau_s[0], comparison.fit_min_tau_s, color="0.9",
                   zorder=0, label="not used by the fits")
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel(r"averaging time $\tau$ (s)")
    ax.set_ylabel(_mpl_text(f"Allan deviation ({comparison.before.units})"))
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize="small")
    ax.set_title("Allan deviation before and after filtering", fontsize="medium")
    return fig


def plot_allan_overlay(results: Any, labels: Any, noise: Any = None, *,
                       width_in: float = 7.5) -> Figure:
    """Several Allan curves (recordings or axes) on one log-log figure, for comparing gyros.

    Lower-left is better: a lower curve has less noise, and a minimum further right means
    a longer useful averaging time (seed 001).  Each curve carries its confidence
    intervals, its fitted IEEE-952 total (when given) and a marker at its minimum.

    Parameters
    ----------
    results : sequence of AllanResult
    labels : sequence of str
        One label per curve (file name, axis).
    noise : sequence of NoiseModel or None, optional
        One fit per curve (None entries are skipped).
    """
    curves = list(results)
    names = list(labels)
    fits = list(noise) if noise is not None else [None] * len(curves)
    fig = Figure(figsize=(width_in, 0.72 * width_in), layout="constrained")
    ax = fig.add_subplot()
    cmap = ["tab:blue", "tab:orange", "tab:green", "tab:red", "tab:purple", "tab:brown",
            "tab:pink", "tab:gray", "tab:olive", "tab:cyan"]
    units = {getattr(r, "units", "") for r in curves}
    for i, (res, label, fit) in enumerate(zip(curves, names, fits, strict=True)):
        colour = cmap[i % len(cmap)]
        _allan_curve(ax, res, colour, _mpl_text(label))
        dev = np.asarray(res.dev, dtype=np.float64)
        ok = np.isfinite(dev) & (dev > 0)
        if ok.any():
            j = int(np.argmin(np.where(ok, dev, np.inf)))
            ax.plot(res.tau_s[j], dev[j], marker="v", color=colour, ms=9, ls="none", zorder=5)
        if fit is not None:
            tau = np.logspace(np.log10(res.tau_s[0]), np.log10(res.tau_s[-1]), 200)
            ax.plot(tau, fit.curve(tau), "-", color=colour, lw=1.0, alpha=0.7)
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel(r"averaging time $\tau$ (s)")
    unit = units.pop() if len(units) == 1 else "mixed units"
    ax.set_ylabel(_mpl_text(f"Allan deviation ({unit})"))
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize="small", title="▼ minimum; line: IEEE-952 fit", title_fontsize="small")
    ax.set_title("Allan deviation comparison (lower-left is better)", fontsize="medium")
    return fig
