"""Allan-deviation figures: one curve (or one per axis) with the IEEE-952 fit, several
recordings overlaid, and before/after filtering."""

from __future__ import annotations

from types import SimpleNamespace
from typing import Any

import numpy as np
from matplotlib.figure import Figure

from fogts._typing import FloatArray
from fogts.allan.readoff import fit_check, readoff_supported
from fogts.allan.readout import MIN_EDF_FOR_MINIMUM
from fogts.errors import DataError
from fogts.report.plots._common import mpl_text, num_tex, value_pm_tex
from fogts.report.plots.allan_fit import (
    draw_outside_points,
    draw_residuals,
    fit_span,
    inside_span,
    shade_fit_range,
)
from fogts.report.text import duration_text
from fogts.units import convert_sensor, quantity_of

__all__ = ["plot_allan", "plot_allan_comparison", "plot_allan_overlay"]

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
_READOFF_MARKER = {"N": "v", "K": "^", "B": "s"}


def _allan_curve(ax: Any, res: Any, colour: str, label: str,
                 span: tuple[float, float] | None = None) -> None:
    """The curve's points, with their confidence intervals as error bars where known; with
    a fit ``span``, the points outside it are drawn faded."""
    tau = np.asarray(res.tau_s, dtype=np.float64)
    dev = np.asarray(res.dev, dtype=np.float64)
    lo = np.asarray(getattr(res, "ci_low", np.full_like(dev, np.nan)), dtype=np.float64)
    hi = np.asarray(getattr(res, "ci_high", np.full_like(dev, np.nan)), dtype=np.float64)
    ok = np.isfinite(dev) & (dev > 0)
    if span is not None:
        outside = ok & ~inside_span(tau, span)
        if outside.any():
            draw_outside_points(ax, tau[outside], dev[outside], lo[outside], hi[outside])
        ok &= ~outside
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


def _log_axes(ax: Any) -> None:
    ax.set_xscale("log")
    ax.set_yscale("log")


# ---- plot_allan, step by step -------------------------------------------------------------
def _noise_models(curves: list[Any], noise: Any) -> list[Any]:
    """One noise model (or None) per curve."""
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
    return models


def _limits(curves: list[Any], model: Any) -> tuple[tuple[float, float], tuple[float, float]]:
    """Axis limits around every point and its interval; with one curve's ``model``, widened
    to show the slope read-off points near the data."""
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
    if model is not None:
        near = [dev for name, tau, dev in model.readoff.points
                if readoff_supported(model.readoff, name)  # only the read-offs drawn
                and np.isfinite(dev) and xlim[0] <= tau <= xlim[1]
                and ymin / 20 <= dev <= ymax * 20]
        ymin, ymax = min([ymin, *near]), max([ymax, *near])
    return xlim, (ymin / 2.5, ymax * 2.5)


def _term_lines(ax: Any, model: Any, fine: Any, ylim: tuple[float, float]) -> None:
    """Each measured term's own line, labelled with its slope and value, where it is
    visible (a term that is only an upper limit is not drawn as a fitted line)."""
    for term in model.terms:
        if term.value <= 0 or term.is_limit:
            continue
        line = model.term_line(term.name, fine)
        shown = (line >= ylim[0]) & (line <= ylim[1])
        if not shown.any():
            continue
        tcolour, slope = _TERM_STYLE[term.name]
        flag = "" if term.identifiable else " (not identifiable)"
        ax.plot(fine[shown], line[shown], "--", color=tcolour, lw=1.3,
                label=f"{term.name}: slope {slope}, {term.name} = "
                      f"{value_pm_tex(term.value, term.stderr)} "
                      f"{_TERM_UNIT_TEX[term.name]}{flag}", zorder=2)


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


def _readoff_points(ax: Any, res: Any, model: Any, xlim: tuple[float, float],
                    ylim: tuple[float, float]) -> None:
    """The classic slope read-offs (for comparison): the -1/2 line at tau = 1 s (N), the
    +1/2 line at tau = 3 s (K) and the minimum / the estimator's plateau factor (B), where
    inside the axes and supported by the curve; one outside the fit's bounds is marked so
    (:func:`fogts.allan.readoff.fit_check`), and so is one read outside the fit's tau range
    (:attr:`fogts.allan.readoff.SlopeReadoff.outside`)."""
    ro = model.readoff
    names = {"N": f"read-off N = {num_tex(ro.N)} {_TERM_UNIT_TEX['N']} (−1/2 line at τ = 1 s)",
             "K": f"read-off K = {num_tex(ro.K)} {_TERM_UNIT_TEX['K']} (+1/2 line at τ = 3 s)",
             "B": f"read-off B = {num_tex(ro.B)} {_TERM_UNIT_TEX['B']} "
                  f"(minimum / {ro.plateau:.4g})"}
    bounds = model.readoff_bounds()
    for name, tau_ro, dev_ro in ro.points:
        if not readoff_supported(ro, name):  # not supported by the curve: nothing read
            continue
        if name in bounds and fit_check(ro, name, bounds[name]):
            names[name] += ", outside the fit"
        if name in ro.outside:
            names[name] += ", read outside the fit range"
        if (np.isfinite(dev_ro) and xlim[0] <= tau_ro <= xlim[1]
                and ylim[0] <= dev_ro <= ylim[1]):
            ax.plot([tau_ro], [dev_ro], _READOFF_MARKER[name], color=_TERM_STYLE[name][0],
                    mfc="none", ms=9, mew=1.6, label=names[name], zorder=6)
            _readoff_line(ax, res, ro, name, tau_ro, dev_ro)


def _draw_curves(ax: Any, curves: list[Any], models: list[Any], xlim: tuple[float, float],
                 ylim: tuple[float, float], span: tuple[float, float] | None) -> None:
    """Every curve with its fitted total; a single curve also gets its term lines and the
    read-off points, and with a fit ``span`` its total is dotted outside it."""
    single = len(curves) == 1
    fine = np.logspace(np.log10(xlim[0]), np.log10(xlim[1]), 400)
    for i, (res, model) in enumerate(zip(curves, models, strict=True)):
        colour = "0.15" if single else f"C{i}"
        label = _KIND_SYMBOL.get(res.kind, res.kind) if single else mpl_text(res.axis)
        _allan_curve(ax, res, colour, label, span if single else None)
        if model is None:
            continue
        fit_label = (f"fitted total ({model.method.upper()})" if single
                     else f"{mpl_text(res.axis)}: fit")
        fitted = inside_span(fine, span) if single and span is not None else fine > 0
        ax.plot(fine[fitted], model.curve(fine[fitted]), "-",
                color="0.15" if single else colour, lw=1.8, alpha=0.9, label=fit_label,
                zorder=5)
        if not fitted.all():
            ax.plot(fine, np.where(fitted, np.nan, model.curve(fine)), ":", color="0.15",
                    lw=1.2, alpha=0.8, label="fitted total, extrapolated", zorder=5)
        if single:
            _term_lines(ax, model, fine, ylim)
            _readoff_points(ax, res, model, xlim, ylim)


def _decorate(ax: Any, curves: list[Any], xlim: tuple[float, float],
              ylim: tuple[float, float]) -> None:
    """Log axes, limits, labels, grid, the record's length in the title, and the legend."""
    _log_axes(ax)
    ax.set_xlim(*xlim)
    ax.set_ylim(*ylim)
    units = curves[0].units
    kind = curves[0].kind
    ax.set_xlabel("averaging time τ [s]")
    ax.set_ylabel(f"{_KIND_SYMBOL.get(kind, kind)} σ(τ) [{mpl_text(units)}]")
    ax.grid(True, which="major", alpha=0.45)
    ax.grid(True, which="minor", alpha=0.15)
    res = curves[0]
    if getattr(res, "fs_hz", 0) and getattr(res, "n_samples", 0):
        who = res.axis if len(curves) == 1 else f"{len(curves)} axes"
        ax.set_title(mpl_text(f"{who}: {res.n_samples} samples at {res.fs_hz:g} Hz, "
                               f"{duration_text(res.n_samples / res.fs_hz)}"),
                     loc="left", fontsize="medium")
    ax.legend(loc="best", fontsize="small", framealpha=0.85)


def plot_allan(result: Any, noise: Any = None, *, ax: Any = None,
               fit_range: tuple[float | None, float | None] | None = None,
               residuals: bool = True) -> Figure:
    """Allan deviation on log-log axes, with the IEEE-952 fit, its term lines and residuals.

    Draws each point with its confidence interval, the fitted total curve, each fitted
    term's own line labelled with its slope (-1 Q, -1/2 N, 0 B, +1/2 K, +1 R; IEEE Std
    952-1997 Annex C, Fig. C.10) and value, and the classic slope read-off points
    (comparison only): the -1/2 line at tau = 1 s (N), the +1/2 line at tau = 3 s (K)
    and the minimum (B = minimum / the plateau factor, 0.664 for oadev).  One curve with its fit also gets the fit range
    shaded (the points outside it faded, the total dotted there) and, when the curve has
    confidence intervals, a residual panel underneath: each point's
    ``(data - fit) / CI half-width`` (:attr:`fogts.allan.misfit.FitCheck.residual`) with
    the +-1 and +-3 bands (:mod:`fogts.report.plots.allan_fit`).

    Parameters
    ----------
    result : AllanResult or AllanResultSet
        The curve(s).  A result set draws every axis in its own colour with its fitted
        total only (term lines would clutter the figure).
    noise : NoiseModel or sequence of NoiseModel, optional
        The fit (one per curve for a result set).
    ax : matplotlib Axes, optional
        Draw into this Axes (its Figure is returned; no residual panel); by default a new
        Figure is made.
    fit_range : (float or None, float or None), optional
        The ``tau_range`` the model was fitted with (None ends: the first and last tau the
        model used); by default the model's own taus.
    residuals : bool
        Draw the residual panel (one curve with its fit and intervals, new Figure only).

    Returns
    -------
    matplotlib.figure.Figure

    Raises
    ------
    DataError
        ``noise`` does not give one model per curve.

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
    >>> fig.axes[0].get_xscale(), fig.axes[0].get_yscale(), len(fig.axes)
    ('log', 'log', 2)
    """
    curves = list(getattr(result, "curves", [result]))
    models = _noise_models(curves, noise)
    model = models[0] if len(curves) == 1 else None
    span = fit_span(model, fit_range) if model is not None else None
    ci_low = np.asarray(getattr(curves[0], "ci_low", [np.nan]), dtype=np.float64)
    with_residuals = (residuals and ax is None and model is not None
                      and bool(np.isfinite(ci_low).any()))
    rax = None
    if ax is not None:
        fig = ax.figure
    elif with_residuals:
        fig = Figure(figsize=(8.0, 7.4), layout="constrained")
        ax, rax = fig.subplots(2, 1, sharex=True, height_ratios=[3.0, 1.15])
    else:
        fig = Figure(figsize=(8.0, 5.6), layout="constrained")
        ax = fig.add_subplot()
    xlim, ylim = _limits(curves, model)
    if span is not None:
        shade_fit_range(ax, span, label=True)
    _draw_curves(ax, curves, models, xlim, ylim, span)
    _decorate(ax, curves, xlim, ylim)
    if rax is not None and span is not None:
        draw_residuals(rax, curves[0], model, span)
        rax.set_xlabel(ax.get_xlabel())
        ax.set_xlabel("")
    return fig


# ---- several curves on one figure ---------------------------------------------------------
def plot_allan_comparison(comparison: Any, *, width_in: float = 7.5) -> Figure:
    """Allan deviation before and after filtering on one log-log figure.

    Both curves carry their confidence intervals; the filter's ``1/cutoff`` is marked,
    since filtering changes the noise seen at shorter tau, and the fitted totals of both
    curves are drawn over the tau range the fits used.

    Parameters
    ----------
    comparison : AllanComparison
        From :func:`fogts.allan.compare.compare_allan`.
    width_in : float
        Figure width in inches.

    Returns
    -------
    matplotlib.figure.Figure
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
    _log_axes(ax)
    ax.set_xlabel(r"averaging time $\tau$ (s)")
    ax.set_ylabel(mpl_text(f"Allan deviation ({comparison.before.units})"))
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize="small")
    ax.set_title("Allan deviation before and after filtering", fontsize="medium")
    return fig


_OVERLAY_COLOURS = ("tab:blue", "tab:orange", "tab:green", "tab:red", "tab:purple",
                    "tab:brown", "tab:pink", "tab:gray", "tab:olive", "tab:cyan")


def plot_allan_overlay(results: Any, labels: Any, noise: Any = None, *,
                       width_in: float = 7.5) -> Figure:
    """Several Allan curves (recordings or axes) on one log-log figure, for comparing gyros.

    Lower-left is better: a lower curve has less noise, and a minimum further right means
    a longer useful averaging time.  Each curve carries its confidence intervals, its
    fitted IEEE-952 total (when given) and a marker at its minimum.

    Parameters
    ----------
    results : sequence of AllanResult
    labels : sequence of str
        One label per curve (file name, axis).
    noise : sequence of NoiseModel or None, optional
        One fit per curve (None entries are skipped).
    width_in : float
        Figure width in inches.

    Returns
    -------
    matplotlib.figure.Figure
    """
    curves = list(results)
    names = list(labels)
    fits = list(noise) if noise is not None else [None] * len(curves)
    fig = Figure(figsize=(width_in, 0.72 * width_in), layout="constrained")
    ax = fig.add_subplot()
    unit = _overlay_unit(curves)
    for i, (res, label, fit) in enumerate(zip(curves, names, fits, strict=True)):
        colour = _OVERLAY_COLOURS[i % len(_OVERLAY_COLOURS)]
        scale = _overlay_scale(res, unit)
        view = SimpleNamespace(
            tau_s=res.tau_s, dev=scale * np.asarray(res.dev, dtype=np.float64),
            ci_low=scale * np.asarray(getattr(res, "ci_low", np.full(len(res.dev), np.nan)),
                                      dtype=np.float64),
            ci_high=scale * np.asarray(getattr(res, "ci_high", np.full(len(res.dev), np.nan)),
                                       dtype=np.float64),
            confidence=getattr(res, "confidence", np.nan))
        _allan_curve(ax, view, colour, mpl_text(label))
        j = _minimum_index(view.dev, getattr(res, "edf", None))
        if j is not None:
            ax.plot(res.tau_s[j], view.dev[j], marker="v", color=colour, ms=9, ls="none",
                    zorder=5)
        if fit is not None:
            tau = np.logspace(np.log10(res.tau_s[0]), np.log10(res.tau_s[-1]), 200)
            ax.plot(tau, scale * fit.curve(tau), "-", color=colour, lw=1.0, alpha=0.7)
    _log_axes(ax)
    ax.set_xlabel(r"averaging time $\tau$ (s)")
    ax.set_ylabel(mpl_text(f"Allan deviation ({unit})"))
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize="small", title="▼ minimum; line: IEEE-952 fit", title_fontsize="small")
    ax.set_title("Allan deviation comparison (lower-left is better)", fontsize="medium")
    return fig


def _overlay_unit(curves: list[Any]) -> str:
    """The overlay's unit: the first curve's, when every curve is of its quantity (rates in
    deg/h, deg/s, ... are drawn in one unit, so that lower is less noise); else "mixed
    units"."""
    units = [str(getattr(r, "units", "")) for r in curves]
    if len(set(units)) == 1:
        return units[0]
    try:
        if len({quantity_of(u) for u in units}) == 1:
            return units[0]
    except DataError:
        pass
    return "mixed units"


def _overlay_scale(res: Any, unit: str) -> float:
    """Factor that takes ``res`` from its unit to the overlay's (1 for "mixed units")."""
    own = str(getattr(res, "units", ""))
    if unit == "mixed units" or own == unit:
        return 1.0
    return float(convert_sensor(1.0, own, unit))


def _minimum_index(dev: FloatArray, edf: Any) -> int | None:
    """The point the text's read-out calls the minimum: the lowest with EDF >=
    :data:`~fogts.allan.readout.MIN_EDF_FOR_MINIMUM` (the lowest of all when no point
    has that many, or no EDF is known), or None without a finite positive point."""
    ok = np.isfinite(dev) & (dev > 0)
    if not ok.any():
        return None
    if edf is not None:
        e = np.asarray(edf, dtype=np.float64)
        trusted = ok & np.isfinite(e) & (e >= MIN_EDF_FOR_MINIMUM)
        if trusted.any():
            ok = trusted
    return int(np.argmin(np.where(ok, dev, np.inf)))
