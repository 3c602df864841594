"""Tests for fogts.report.plots.plot_allan with fitted noise models and read-offs."""

from __future__ import annotations

import numpy as np
import pytest

from fogts.allan import AllanResult, AllanResultSet, allan_deviation
from fogts.errors import DataError
from fogts.report.plots import plot_allan
from tests.allan.noise_cases import quiet_fit, smac_result


def test_plot_allan_single_curve(tmp_path: object) -> None:
    res = smac_result("kvh1750", "deg/s")
    model = quiet_fit(res)
    fig = plot_allan(res, model)
    ax = fig.axes[0]
    assert ax.get_xscale() == "log" and ax.get_yscale() == "log"
    assert len(fig.axes) == 2  # the residual panel underneath carries the tau label
    assert "τ [s]" in fig.axes[1].get_xlabel() and "[deg/s]" in ax.get_ylabel()
    labels = [t.get_text() for t in ax.get_legend().get_texts()]
    assert any(lbl.startswith("N: slope −1/2") for lbl in labels)
    assert any(lbl.startswith("K: slope +1/2") for lbl in labels)
    assert any("fitted total" in lbl for lbl in labels)
    assert any("read-off" in lbl for lbl in labels)
    assert any("95.4 % CI" in lbl for lbl in labels)
    assert len(ax.collections) >= 1  # the error bars


@pytest.mark.parametrize(("value", "stderr", "text"), [
    (0.002003, 4.46e-6, r"(2.0030 ± 0.0045)$\times$10$^{-3}$"),
    (0.01303, 0.00207, "0.0130 ± 0.0021"),
    (0.03413, 0.0141, "0.034 ± 0.014"),
    (1234.6, 67.0, "1235 ± 67"),
    (0.5, float("nan"), "0.5"),
])
def test_value_pm_text_keeps_the_digits_the_error_supports(value: float, stderr: float,
                                                            text: str) -> None:
    from fogts.report.plots import value_pm_tex

    assert value_pm_tex(value, stderr) == text


def test_plot_allan_shows_every_readoff_with_its_line() -> None:
    """The K read-off of a white + RRW record lies below the curve: the axes widen to show
    it, and a dotted +1/2 line joins it to the curve point it was drawn through."""
    rng = np.random.default_rng(7)
    y = rng.standard_normal(400_000) + np.cumsum(rng.standard_normal(400_000)) * 2e-3
    res = allan_deviation(y, fs_hz=100.0, units="deg/h")
    model = quiet_fit(res)
    fig = plot_allan(res, model)
    ax = fig.axes[0]
    labels = [t.get_text() for t in ax.get_legend().get_texts()]
    for name in "NKB":
        assert any(lbl.startswith(f"read-off {name} =") for lbl in labels), name
    lo, hi = ax.get_ylim()
    assert all(lo <= dev <= hi for _, _, dev in model.readoff.points)
    dotted = [ln for ln in ax.get_lines() if ln.get_linestyle() == ":"]
    assert len(dotted) >= 1
    k_line = [ln for ln in dotted if 3.0 in ln.get_xdata()]
    assert k_line and model.readoff.tau_K_s in k_line[0].get_xdata()


def test_plot_allan_set_and_axes() -> None:
    from matplotlib.figure import Figure

    a, b = smac_result("ln200", "rad/s", "Gyro. X"), smac_result("ln200", "rad/s", "Gyro. Y")
    a = AllanResult(**{**{f: getattr(a, f) for f in a.__dataclass_fields__}, "axis": "x"})
    b = AllanResult(**{**{f: getattr(b, f) for f in b.__dataclass_fields__}, "axis": "y"})
    pair = AllanResultSet(curves=(a, b))
    fig = plot_allan(pair, [quiet_fit(a), quiet_fit(b)])
    labels = [t.get_text() for t in fig.axes[0].get_legend().get_texts()]
    assert labels == ["x (95.4 % CI)", "x: fit", "y (95.4 % CI)", "y: fit"]
    own = Figure()
    ax = own.add_subplot()
    assert plot_allan(a, ax=ax) is own
    with pytest.raises(DataError, match="one model per curve: 2 curve"):
        plot_allan(pair, quiet_fit(a))


def test_plot_allan_leaves_out_a_readoff_the_curve_cannot_give() -> None:
    """White noise and a flicker floor (the exact IEEE-952 curve): no segment rises at
    +1/2, so the figure neither labels nor draws a K read-off, nor widens its axes to reach
    it (ADIS16405 run 1 X drew "read-off K = 53.9" from a +0.13 segment near the floor, and
    its y axis went down to 1e-4 for it)."""
    from fogts.allan.readoff import readoff_supported
    from tests.allan.noise_cases import avar, make_result

    tau = 2.0 ** np.arange(-4, 12)
    dev = np.sqrt(avar(tau, N=0.02, B=0.1))
    res = make_result(tau, dev, ci=(0.95 * dev, 1.05 * dev))
    model = quiet_fit(res)
    assert readoff_supported(model.readoff, "N") and not readoff_supported(model.readoff, "K")
    fig = plot_allan(res, model)
    ax = fig.axes[0]
    labels = [t.get_text() for t in ax.get_legend().get_texts()]
    assert any(lbl.startswith("read-off N =") for lbl in labels)
    assert not any(lbl.startswith("read-off K") for lbl in labels)
    k_dev = next(d for name, _, d in model.readoff.points if name == "K")
    lo, _ = ax.get_ylim()
    assert k_dev < lo  # the unread K point stays outside: the axes were not widened for it
    assert not [ln for ln in ax.get_lines()
                if ln.get_linestyle() == ":" and 3.0 in ln.get_xdata()]
