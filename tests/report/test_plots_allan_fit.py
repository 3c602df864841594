"""fogts.report.plots.allan_fit: the fit range and the residual panel of the Allan figure.

Structure, not pixels: how many axes, where the shaded fit range starts and ends, which
points are drawn as outside it, and that the residuals drawn are the misfit module's
(:func:`fogts.allan.misfit.check_fit`) to round-off (1e-12 relative: the same numbers,
only passed through matplotlib's float64 line data).
"""

from __future__ import annotations

import dataclasses
import warnings
from types import SimpleNamespace
from typing import Any

import numpy as np
import pytest
from matplotlib.lines import Line2D

import fogts
from fogts.allan import AllanResultSet
from fogts.allan.misfit import MISS_Z, check_fit
from fogts.report.plots import plot_allan
from fogts.report.plots.allan_fit import FIT_RANGE_GID, fit_span


def _fit(res: Any, **kw: Any) -> Any:
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return fogts.fit_noise(res, **kw)


@pytest.fixture(scope="module")
def five_term() -> Any:
    """N, B and K, 3 h at 100 Hz (seed 1): the five-term model describes it."""
    run = fogts.simulate_gyro({"N": 0.01, "B": 0.15, "K": 1.0}, fs_hz=100,
                              duration_s=3 * 3600, rng=1)
    return fogts.allan_deviation(run)


@pytest.fixture(scope="module")
def quantized() -> Any:
    """Quantization under white noise, 30 min at 100 Hz (seed 2): a fit of N, B, K from
    0.5 s on misses the shortest taus by far more than 3 half-widths."""
    run = fogts.simulate_gyro({"Q": 2.0, "N": 0.01}, fs_hz=100, duration_s=1800, rng=2)
    return fogts.allan_deviation(run)


def _span_patch(ax: Any) -> Any:
    patches = [p for p in ax.patches if p.get_gid() == FIT_RANGE_GID]
    assert len(patches) == 1
    return patches[0]


def _span_extent(ax: Any) -> tuple[float, float]:
    rect = _span_patch(ax)
    return rect.get_x(), rect.get_x() + rect.get_width()


def _residual_lines(ax: Any) -> list[Line2D]:
    return [ln for ln in ax.get_lines() if ln.get_marker() == "o"]


def test_the_fit_range_is_shaded_on_both_panels(five_term: Any) -> None:
    model = _fit(five_term, tau_range=(0.1, 500.0))
    fig = plot_allan(five_term, model, fit_range=(0.1, 500.0))
    assert len(fig.axes) == 2
    main, resid = fig.axes
    for ax in (main, resid):
        assert _span_extent(ax) == pytest.approx((0.1, 500.0), rel=1e-12)
    labels = [t.get_text() for t in main.get_legend().get_texts()]
    assert "fit range τ = 0.1..500 s" in labels
    assert "outside the fit range (not fitted)" in labels
    assert "fitted total, extrapolated" in labels
    outside = next(ln for ln in main.get_lines()
               if ln.get_label() == "outside the fit range (not fitted)")
    tau = five_term.tau_s
    np.testing.assert_allclose(outside.get_xdata(), tau[(tau < 0.1) | (tau > 500.0)],
                               rtol=1e-12)
    assert resid.get_xlabel() == "averaging time τ [s]" and main.get_xlabel() == ""


def test_an_open_range_ends_at_the_fitted_taus(five_term: Any) -> None:
    model = _fit(five_term, tau_range=(0.3, None))
    assert fit_span(model, (0.3, None)) == (0.3, float(model.tau_s[-1]))
    fig = plot_allan(five_term, model)  # no range given: the taus the model used
    assert _span_extent(fig.axes[0]) == pytest.approx(
        (float(model.tau_s[0]), float(model.tau_s[-1])), rel=1e-12)


def test_the_residuals_are_the_misfit_check(five_term: Any) -> None:
    model = _fit(five_term, tau_range=(0.1, 500.0))
    fig = plot_allan(five_term, model, fit_range=(0.1, 500.0))
    resid = fig.axes[1]
    check = check_fit(five_term, model)
    inside = (check.tau_s >= 0.1) & (check.tau_s <= 500.0)
    fitted, outside = _residual_lines(resid)
    np.testing.assert_allclose(fitted.get_xdata(), check.tau_s[inside], rtol=1e-12)
    np.testing.assert_allclose(fitted.get_ydata(), check.residual[inside], rtol=1e-12)
    np.testing.assert_allclose(outside.get_ydata(), check.residual[~inside], rtol=1e-12)
    np.testing.assert_allclose(check.residual, -check.z, rtol=0)
    # the five-term truth stays within the +-3 band over the fit range; linear axis
    assert np.all(np.abs(fitted.get_ydata()) < MISS_Z)
    assert resid.get_yscale() == "linear"
    bands = sorted(round(p.get_height(), 9) for p in resid.patches
                   if p.get_gid() != FIT_RANGE_GID)
    assert bands == [2.0, 2 * MISS_Z]  # the +-1 and +-3 half-width bands


def test_large_misses_get_a_symlog_axis(quantized: Any) -> None:
    model = _fit(quantized, terms="N,B,K", tau_range=(0.5, None))
    fig = plot_allan(quantized, model, fit_range=(0.5, None))
    resid = fig.axes[1]
    check = check_fit(quantized, model)
    assert float(np.nanmax(np.abs(check.residual))) > 2 * MISS_Z
    assert resid.get_yscale() == "symlog"
    lo, hi = resid.get_ylim()
    assert lo <= float(np.nanmin(check.residual)) and hi >= float(np.nanmax(check.residual))


def test_no_residual_panel_without_one_fitted_curve_with_intervals(five_term: Any) -> None:
    from matplotlib.figure import Figure

    model = _fit(five_term)
    assert len(plot_allan(five_term, model, residuals=False).axes) == 1
    assert len(plot_allan(five_term).axes) == 1
    own = Figure()
    ax = own.add_subplot()
    assert plot_allan(five_term, model, ax=ax) is own and len(own.axes) == 1
    assert _span_extent(ax) == pytest.approx((five_term.tau_s[0], five_term.tau_s[-1]))
    pair = AllanResultSet(curves=(five_term, dataclasses.replace(five_term, axis="y")))
    assert len(plot_allan(pair, [model, model]).axes) == 1
    tau = 2.0 ** np.arange(-5, 12)
    bare = SimpleNamespace(kind="oadev", units="deg/h", axis="x", tau_s=tau,
                           dev=np.sqrt(0.25 / tau + 1e-4 * tau / 3),
                           edf=np.full(tau.size, 100.0))
    assert len(plot_allan(bare, _fit(bare, terms="N,K")).axes) == 1
