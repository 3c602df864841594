"""The noise fit on the Allan figure: the fit range (shaded, the taus outside it faded) and
the residual panel under the curve.

The residual of tau_i is the misfit module's normalised residual
(:attr:`fogts.allan.misfit.FitCheck.residual`): ``(dev_i - fit_i)`` in half-widths of the
point's confidence interval on the side the fit lies.  Within +-1 the fit passes through
the interval; beyond +-3 (:data:`fogts.allan.misfit.MISS_Z`) it misses the point.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from fogts._typing import BoolArray, FloatArray
from fogts.allan.misfit import MISS_Z, FitCheck, check_fit

__all__ = ["FIT_RANGE_GID", "draw_outside_points", "draw_residuals", "fit_span", "inside_span",
           "shade_fit_range"]

#: ``gid`` of the shaded fit-range patch (one per panel), so that it can be found again.
FIT_RANGE_GID = "fit-range"
_SPAN_COLOUR = "#fff5d9"
_OUTSIDE_COLOUR = "0.62"


def _residual_scale(ax: Any, largest: float) -> None:
    """Linear within +-3 and, when a point misses by more than 6, logarithmic beyond (the
    misses at the shortest taus of real sensors reach a few hundred); ticks at 0, +-1,
    +-3 and the powers of ten."""
    bound = max(1.3 * largest, MISS_Z + 1.0)
    ticks = [0.0, 1.0, MISS_Z]
    if largest > 2 * MISS_Z:
        ax.set_yscale("symlog", linthresh=MISS_Z, linscale=1.5)
        ticks += [10.0**k for k in range(1, int(np.log10(bound)) + 1)]
    ax.set_ylim(-bound, bound)
    ax.set_yticks(sorted({-t for t in ticks if t} | set(ticks)))
    ax.set_yticks([], minor=True)
    ax.yaxis.set_major_formatter(lambda v, _: f"{v:g}")


def fit_span(model: Any, fit_range: tuple[float | None, float | None] | None
             ) -> tuple[float, float]:
    """The tau range (s) the model was fitted over: ``fit_range`` with each open end
    replaced by the first or last tau the model used."""
    tau = np.asarray(model.tau_s, dtype=np.float64)
    lo, hi = fit_range if fit_range is not None else (None, None)
    return (float(tau[0]) if lo is None else float(lo),
            float(tau[-1]) if hi is None else float(hi))


def inside_span(tau: FloatArray, span: tuple[float, float]) -> BoolArray:
    """Whether each tau lies in ``span`` (with the relative slack of
    :meth:`fogts.allan.result.AllanResult.within`)."""
    return np.asarray((tau >= span[0] * (1 - 1e-9)) & (tau <= span[1] * (1 + 1e-9)))


def shade_fit_range(ax: Any, span: tuple[float, float], *, label: bool) -> None:
    """Shade ``span`` behind everything on ``ax``; with ``label``, name it in the legend."""
    text = f"fit range τ = {span[0]:.4g}..{span[1]:.4g} s" if label else None
    ax.axvspan(span[0], span[1], color=_SPAN_COLOUR, zorder=0, lw=0, label=text,
               gid=FIT_RANGE_GID)


def draw_outside_points(ax: Any, tau: FloatArray, dev: FloatArray, lo: FloatArray,
                        hi: FloatArray) -> None:
    """Points outside the fit range, faded, with their intervals."""
    has_ci = np.isfinite(lo) & np.isfinite(hi) & (lo > 0)
    if has_ci.any():
        ax.errorbar(tau[has_ci], dev[has_ci],
                    yerr=[dev[has_ci] - lo[has_ci], hi[has_ci] - dev[has_ci]], fmt="none",
                    ecolor=_OUTSIDE_COLOUR, elinewidth=0.9, capsize=2.0, alpha=0.7, zorder=3)
    ax.plot(tau, dev, "o", color=_OUTSIDE_COLOUR, ms=4.0, mfc="white", mew=1.0, alpha=0.9,
            label="outside the fit range (not fitted)", zorder=4)


def draw_residuals(ax: Any, result: Any, model: Any, span: tuple[float, float]
                   ) -> FitCheck:
    """The residual panel: the normalised residual of every point (those outside the fit
    range faded), the +-1 and +-3 half-width bands and the fit range; returns the check
    it drew."""
    check = check_fit(result, model)
    tau, r = check.tau_s, check.residual
    inside = inside_span(tau, span)
    shade_fit_range(ax, span, label=False)
    ax.axhspan(-MISS_Z, MISS_Z, color="0.90", zorder=0.5, lw=0,
               label=f"±{MISS_Z:g}: beyond, the fit misses the point")
    ax.axhspan(-1.0, 1.0, color="0.78", zorder=0.6, lw=0,
               label="±1: the fit passes through the interval")
    ax.axhline(0.0, color="0.3", lw=0.8, zorder=1)
    ax.plot(tau[inside], r[inside], "o-", color="0.15", ms=4.0, lw=0.9, mfc="white",
            mew=1.2, zorder=4)
    if (~inside).any():
        ax.plot(tau[~inside], r[~inside], "o", color=_OUTSIDE_COLOUR, ms=3.5, mfc="white",
                mew=1.0, zorder=3)
    _residual_scale(ax, float(np.nanmax(np.abs(r))) if np.isfinite(r).any() else 0.0)
    ax.set_ylabel("(data − fit) /\nCI half-width", fontsize="small")
    ax.grid(True, which="major", axis="x", alpha=0.45)
    ax.legend(loc="best", fontsize="x-small", framealpha=0.85)
    return check
