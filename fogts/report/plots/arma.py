"""ARMA figures: the diagnostics of a model selection."""

from __future__ import annotations

from typing import Any

import numpy as np
from matplotlib.figure import Figure

from fogts._typing import FloatArray
from fogts.report.plots._common import mpl_text

__all__ = ["plot_selection"]

_BAND_LABEL = "95 % band ±1.96/√n"


def _stem(ax: Any, lags: FloatArray, values: FloatArray, colour: str) -> None:
    ax.vlines(lags, 0.0, values, colors=colour, lw=1.2)
    ax.plot(lags, values, "o", ms=3, color=colour)
    ax.axhline(0.0, color="k", lw=0.6)


def _correlogram_panels(ax_acf: Any, ax_pacf: Any, corr: Any) -> None:
    """The data's ACF (Bartlett band) and PACF (band 1.96/sqrt(n)), with the Box-Jenkins
    reading of each in its title."""
    lags = np.arange(1, corr.nlags + 1, dtype=float)
    ax_acf.fill_between(lags, -corr.acf_band[1:], corr.acf_band[1:], color="C0", alpha=0.15,
                        lw=0, label="95 % band (Bartlett)")
    _stem(ax_acf, lags, corr.acf[1:], "C0")
    ax_acf.set_title(f"data ACF: {corr.acf_pattern.describe()}", loc="left", fontsize="medium")
    ax_pacf.axhspan(-corr.band, corr.band, color="C0", alpha=0.15, lw=0, label=_BAND_LABEL)
    _stem(ax_pacf, lags, corr.pacf[1:], "C0")
    ax_pacf.set_title(f"data PACF: {corr.pacf_pattern.describe()}", loc="left",
                      fontsize="medium")
    for ax in (ax_acf, ax_pacf):
        ax.set_xlabel("lag")
        ax.legend(loc="upper right", fontsize="small", framealpha=0.85)
        ax.grid(alpha=0.3)


def _residual_acf_panel(ax: Any, best: Any) -> None:
    """The selected model's residual ACF with its band, and the Ljung-Box p-values."""
    diag = best.diagnostics
    rl = np.arange(1, diag.acf.size, dtype=float)
    ax.axhspan(-diag.band, diag.band, color="C2", alpha=0.15, lw=0, label=_BAND_LABEL)
    _stem(ax, rl, diag.acf[1:], "C2")
    lb = ", ".join(f"Q({x.lag}) p={x.pvalue:.2g}" for x in diag.ljung_box)
    ax.set_title(mpl_text(f"{best.model} residual ACF ({lb})"), loc="left", fontsize="medium")
    ax.set_xlabel("lag")
    ax.legend(loc="upper right", fontsize="small", framealpha=0.85)
    ax.grid(alpha=0.3)


def _qq_panel(ax: Any, best: Any) -> None:
    """Normal Q-Q plot of the standardised residuals (at most 2000 quantiles)."""
    from scipy.stats import norm

    resid = np.asarray(best.resid, dtype=float)
    z = (resid - resid.mean()) / resid.std() if resid.std() > 0 else resid
    m = min(z.size, 2000)
    probs = (np.arange(1, m + 1) - 0.5) / m
    theo = norm.ppf(probs)
    ax.plot(theo, np.quantile(z, probs), ".", ms=3, color="C2")
    lim = float(max(abs(theo[0]), abs(theo[-1])))
    ax.plot([-lim, lim], [-lim, lim], color="k", lw=0.8)
    ax.set_xlabel("normal quantile")
    ax.set_ylabel("standardised residual")
    ax.set_title(f"{best.model} residual Q–Q ({m} quantiles)", loc="left", fontsize="medium")
    ax.grid(alpha=0.3)


def _prediction_panel(ax: Any, best: Any, units: str, window: int) -> None:
    """The one-step-ahead prediction against the data over the first ``window`` samples."""
    pred = best.predict()
    k = min(pred.n, max(10, int(window)))
    t = pred.time[:k] if pred.time is not None else np.arange(k, dtype=float)
    ax.plot(t, pred.observed[:k], "-", lw=0.8, color="0.55", label="observed x_t")
    ax.plot(t, pred.predicted[:k], "-", lw=1.0, color="C1", label="one-step prediction")
    ax.set_xlabel("time [s]" if pred.time is not None else "sample")
    ax.set_ylabel(mpl_text(f"drift [{units}]") if units else "drift")
    ax.set_title(mpl_text(f"one-step prediction with {best.model}, first {k} of {pred.n} "
                           f"samples: removes {100 * pred.variance_removed:.1f} % of the "
                           "variance"), loc="left", fontsize="medium")
    ax.legend(loc="upper right", fontsize="small", framealpha=0.85, ncol=2)
    ax.grid(alpha=0.3)


def plot_selection(selection: Any, *, window: int = 400, width_in: float = 10.0) -> Figure:
    """Diagnostics of an ARMA model selection in five panels.

    Panels: the data's ACF (Bartlett band) and PACF (band 1.96/sqrt(n)), with the Box-Jenkins
    reading in their titles; the selected model's residual ACF with the band +-1.96/sqrt(n);
    a normal Q-Q plot of the standardised residuals; and the one-step-ahead prediction against
    the data over the first ``window`` samples, with the share of variance it removes.

    Parameters
    ----------
    selection : fogts.arma.select.Selection
        The result of :func:`fogts.arma.select.select_arma`.
    window : int
        Samples shown in the prediction panel.
    width_in : float
        Figure width in inches; the height is 0.8 times it.

    Returns
    -------
    matplotlib.figure.Figure
        Two correlogram panels, two residual panels and the prediction below them.

    Examples
    --------
    >>> from scipy.signal import lfilter
    >>> from fogts.arma import select_arma
    >>> e = np.random.default_rng(0).standard_normal(2000)
    >>> fig = plot_selection(select_arma(lfilter([1.0], [1.0, -0.5], e)))
    >>> len(fig.axes)
    5
    """
    best = selection.best
    fig = Figure(figsize=(width_in, 0.8 * width_in), layout="constrained")
    grid = fig.add_gridspec(3, 2, height_ratios=(1.0, 1.0, 1.1))
    ax_acf, ax_pacf = fig.add_subplot(grid[0, 0]), fig.add_subplot(grid[0, 1])
    ax_racf, ax_qq = fig.add_subplot(grid[1, 0]), fig.add_subplot(grid[1, 1])
    ax_pred = fig.add_subplot(grid[2, :])
    _correlogram_panels(ax_acf, ax_pacf, selection.correlogram)
    if best is None:
        for ax in (ax_racf, ax_qq, ax_pred):
            ax.text(0.5, 0.5, "no candidate could be fitted", ha="center", va="center",
                    transform=ax.transAxes)
            ax.set_axis_off()
        fig.suptitle(mpl_text(selection.verdict[:120]), fontsize="medium")
        return fig
    _residual_acf_panel(ax_racf, best)
    _qq_panel(ax_qq, best)
    _prediction_panel(ax_pred, best, selection.units, window)
    verdict = "white residuals" if best.white else "residuals NOT white"
    fig.suptitle(mpl_text(f"selected {best.model} by {selection.criterion.upper()} "
                           f"({verdict}):  {best.equation()}"), fontsize="medium")
    return fig
