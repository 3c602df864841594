"""Plots: result -> matplotlib Figure; pure; no show().

Every function takes a fogts result and returns a new :class:`matplotlib.figure.Figure`
built without pyplot state, so it is safe in scripts, servers and worker processes.  Save
it with ``fig.savefig(path)``.

Modules: :mod:`~fogts.report.plots.allan` (Allan deviation with its noise fit, overlays,
before/after filtering), :mod:`~fogts.report.plots.arma` (ARMA selection diagnostics),
:mod:`~fogts.report.plots.timeseries` (the record against time, dynamic Allan deviation)
and :mod:`~fogts.report.plots.startup` (Kalman filter, thermal compensation, north seeking).
"""

from __future__ import annotations

# value_pm_tex: the term-label format, tested on its own (tests import it from here)
from fogts.report.plots._common import value_pm_tex as value_pm_tex
from fogts.report.plots.allan import plot_allan, plot_allan_comparison, plot_allan_overlay
from fogts.report.plots.arma import plot_selection
from fogts.report.plots.startup import plot_compensation, plot_kalman, plot_north_seeking
from fogts.report.plots.timeseries import plot_dynamic_allan, plot_timeseries

__all__ = ["plot_allan", "plot_allan_comparison", "plot_allan_overlay", "plot_compensation",
           "plot_dynamic_allan", "plot_kalman", "plot_north_seeking", "plot_selection",
           "plot_timeseries"]
