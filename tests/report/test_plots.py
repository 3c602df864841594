"""fogts.report.plots: the shared helpers, and the figures no other test draws."""

from __future__ import annotations

from types import SimpleNamespace

import numpy as np
import pytest
from scipy.signal import lfilter

from fogts.arma import select_arma
from fogts.report.plots import plot_selection
from fogts.report.plots._common import minmax_envelope, mpl_text, thin_step, time_unit


def test_time_unit_thresholds() -> None:
    assert time_unit(0.0) == (1.0, "s")
    assert time_unit(179.9) == (1.0, "s")
    assert time_unit(180.0) == (60.0, "min")
    assert time_unit(3 * 3600.0) == (3600.0, "h")


def test_thin_step_keeps_at_most_max_points() -> None:
    assert thin_step(100, 1000) == 1
    assert thin_step(10_001, 1000) == 11
    assert len(range(0, 10_001, thin_step(10_001, 1000))) <= 1000


def test_envelope_keeps_the_extremes_of_every_block() -> None:
    rng = np.random.default_rng(1)
    y = rng.normal(size=1003)
    y[500] = 40.0  # a spike must survive the thinning
    t = np.arange(y.size, dtype=float)
    tc, lo, hi, mean = minmax_envelope(t, y, 100)
    assert tc.size == lo.size == hi.size == mean.size + 1  # a shorter last block
    assert hi.max() == pytest.approx(40.0, rel=1e-12)
    assert lo.min() == pytest.approx(y.min(), rel=1e-12)
    assert np.all(np.diff(tc) > 0)
    assert mean[0] == pytest.approx(y[:11].mean(), rel=1e-12)


def test_mpl_text_escapes_mathtext() -> None:
    assert mpl_text("a$b$") == r"a\$b\$"


def test_selection_figure_without_a_fitted_model() -> None:
    e = np.random.default_rng(0).standard_normal(2000)
    sel = select_arma(lfilter([1.0], [1.0, -0.5], e))
    failed = SimpleNamespace(correlogram=sel.correlogram, best=None,
                             verdict="no candidate could be fitted: $x$")
    fig = plot_selection(failed)
    assert len(fig.axes) == 5
    assert sum(ax.axison for ax in fig.axes) == 2  # only the data ACF and PACF


def test_overlay_draws_rates_in_one_unit_and_marks_the_minimum_the_text_reads() -> None:
    """audit2: a deg/h and a deg/s curve were drawn on one axis labelled "mixed units" (the
    100x noisier MEMS below the FOG under "lower-left is better"), and the minimum marker
    sat on the lowest point even where its EDF is 1, not on the read-out's minimum."""
    from fogts.allan import allan_deviation
    from fogts.allan.readout import MIN_EDF_FOR_MINIMUM
    from fogts.report.plots import plot_allan_overlay

    rng = np.random.default_rng(4)
    fog = allan_deviation(rng.normal(0.0, 1.0, 20_000), fs_hz=10.0, units="deg/h")
    mems = allan_deviation(rng.normal(0.0, 0.01, 20_000), fs_hz=10.0, units="deg/s")
    fig = plot_allan_overlay([fog, mems], ["fog", "mems"])
    ax = fig.axes[0]
    assert ax.get_ylabel() == "Allan deviation (deg/h)"
    points = [ln for ln in ax.get_lines() if ln.get_marker() == "o"]
    np.testing.assert_allclose(points[1].get_ydata(), 3600.0 * np.asarray(mems.dev), rtol=1e-12)
    markers = [ln for ln in ax.get_lines() if ln.get_marker() == "v"]
    for res, marker in zip((fog, mems), markers, strict=True):
        trusted = np.asarray(res.edf) >= MIN_EDF_FOR_MINIMUM
        expected = np.asarray(res.tau_s)[trusted][np.argmin(np.asarray(res.dev)[trusted])]
        assert marker.get_xdata()[0] == expected
    accel = allan_deviation(rng.normal(0.0, 0.001, 20_000), fs_hz=10.0, units="g")
    assert plot_allan_overlay([fog, accel], ["gyro", "acc"]).axes[0].get_ylabel() == \
        "Allan deviation (mixed units)"


def test_allan_title_says_the_length_as_the_text_does() -> None:
    """audit2 N18: a 10000 s record's title said "167 min" where the text says "2.78 h":
    the title now uses the text's :func:`fogts.report.text.duration_text`."""
    from fogts.allan import allan_deviation
    from fogts.report.plots import plot_allan
    from fogts.report.text import duration_text

    res = allan_deviation(np.random.default_rng(5).normal(0.0, 1.0, 100_000), fs_hz=10.0,
                          units="deg/h", taus="decade")
    title = plot_allan(res, residuals=False).axes[0].get_title(loc="left")
    assert title.endswith("100000 samples at 10 Hz, 2.78 h (10000 s)")
    assert duration_text(10_000.0) in title and "min" not in title
