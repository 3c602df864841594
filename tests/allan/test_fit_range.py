"""The noise fit over a tau range (fit_noise(tau_range=...), fogts allan --fit-tau-min/max)."""

from __future__ import annotations

import json
import warnings
from pathlib import Path

import pytest
from typer.testing import CliRunner

import fogts
from fogts.cli import app
from fogts.errors import DataError
from tests.conftest import error_output, shared_path

EXAMPLE = Path(__file__).resolve().parents[2] / "data" / "example_fog_10hz_3h.csv"


def test_adis16405_x_without_the_shortest_taus() -> None:
    """The issue's hand-made experiment (first three taus dropped: N = 2.401 +- 0.012,
    B = 29.3, K = 51) as an option; tolerance 1e-3 relative (published to 4 digits)."""
    run = fogts.read_run(shared_path("imu", "adis_16405_imu1_gyro.npz"), units="deg/s")
    res = fogts.allan_deviation(run, axis=0)
    with pytest.warns(fogts.errors.FogtsWarning):
        model = fogts.fit_noise(res, tau_range=(0.08, None))
    assert model.tau_s[0] == pytest.approx(0.08)
    assert model["N"].value == pytest.approx(2.401, rel=1e-3)
    assert model["N"].stderr == pytest.approx(0.012, rel=0.05)
    assert model["B"].value == pytest.approx(29.3, rel=2e-3)
    assert model["K"].value == pytest.approx(51.3, rel=2e-3)


def test_within_keeps_the_points_in_range() -> None:
    res = fogts.allan_deviation(fogts.read_run(EXAMPLE))
    part = res.within(1.0, 100.0)
    assert part.tau_s.min() >= 1.0 and part.tau_s.max() <= 100.0
    assert part.m.size == part.dev.size == part.edf.size == part.tau_s.size
    with pytest.raises(DataError, match="tau_min < tau_max, got tau_min = 5 s and tau_max = 1 s"):
        res.within(5.0, 1.0)


def test_a_range_with_too_few_points_is_refused() -> None:
    res = fogts.allan_deviation(fogts.read_run(EXAMPLE))
    with pytest.raises(DataError, match="holds 2 tau\\(s\\); 5 terms need at least 6"):
        fogts.fit_noise(res, tau_range=(1000.0, None))
    with pytest.raises(DataError, match="tau_min must be a finite number > 0"):
        fogts.fit_noise(res, tau_range=(-1.0, None))


def test_cli_fit_range_in_the_json(tmp_path: Path) -> None:
    out = tmp_path / "a.json"
    res = CliRunner().invoke(app, ["allan", str(EXAMPLE), "--fit-tau-min", "1", "--json",
                                   str(out)])
    assert res.exit_code == 0, res.stderr
    doc = json.loads(out.read_text())
    assert doc["fit_range"] == [1.0, None] and doc["fit_check"]["ok"] is True
    assert "taus 1.6..3277 s" in res.stdout  # the octave grid's first tau >= 1 s is 1.6 s


@pytest.mark.parametrize(("args", "message"), [
    (["--fit-tau-min", "100", "--fit-tau-max", "10"],
     "error: the tau range must have --fit-tau-min < --fit-tau-max, got --fit-tau-min = 100 s"),
    (["--fit-tau-min", "1000"], "error: the fit range --fit-tau-min = 1000 s"),
    (["--fit-tau-min", "-1"], "error: --fit-tau-min must be a finite number > 0, got -1.0"),
])
def test_cli_bad_fit_range_names_the_option(args: list[str], message: str) -> None:
    res = CliRunner().invoke(app, ["allan", str(EXAMPLE), *args])
    assert res.exit_code == 2
    assert error_output(res.stderr).startswith(message)


def test_the_read_offs_come_from_the_whole_curve_and_say_when_outside_the_fit() -> None:
    """The example record fitted over 2..200 s (octave taus 3.2..102.4 s): the slope
    read-offs are the whole curve's (the points table's), so B's minimum is the curve
    read-out's (204.8 s, beyond the fit), and each read-off and dominant range that leaves
    the fitted taus says so.  Before, B was 'not read (no floor ... at 102.4 s)' beside a
    curve table whose minimum and floor were at 204.8 s."""
    res = fogts.allan_deviation(fogts.read_run(EXAMPLE))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", fogts.errors.FogtsWarning)
        whole = fogts.fit_noise(res)
        ranged = fogts.fit_noise(res, tau_range=(2.0, 200.0))
    lo, hi = float(ranged.tau_s[0]), float(ranged.tau_s[-1])
    assert (lo, hi) == pytest.approx((3.2, 102.4))
    ro, readout = ranged.readoff, res.readout(ranged)
    assert ro.fit_tau_s == (lo, hi)
    # the same read-offs as from the fit over every point: they read the curve, not the fit
    for name in ("N", "K", "B"):
        assert getattr(ro, name) == pytest.approx(getattr(whole.readoff, name), rel=1e-12)
    assert whole.readoff.outside == () and whole.readoff.fit_tau_s is None
    # B is the minimum of the curve read-out, at 204.8 s, outside the fit range
    assert ro.tau_B_s == pytest.approx(readout.tau_min_s) == pytest.approx(204.8)
    assert ro.B == pytest.approx(readout.bias_instability_floor, rel=1e-12)
    assert set(ro.outside) == {"N", "K", "B"}  # N through 0.8..1.6 s, K and B at 204.8 s
    text = ranged.describe_readoff()
    assert "B = 0.01909 deg/h (minimum / 0.664; read at tau = 204.8 s, outside the fit " \
           "range 3.2 .. 102.4 s; it lies outside the fit's" in text
    assert "(-1/2 line at tau = 1 s; read through tau = 0.8 s, outside the fit range 3.2 " \
           ".. 102.4 s)" in text
    d = ranged.to_dict()["readoff"]
    assert [d[t]["outside_fit_range"] for t in "NKB"] == [True, True, True]
    assert not any(whole.to_dict()["readoff"][t]["outside_fit_range"] for t in "NKB")
    # the dominant ranges reach beyond the fitted taus: the fitted lines extrapolated
    assert readout.fit_tau_s == (lo, hi)
    assert [(d.term, d.extrapolated) for d in readout.dominant] == [("N", True), ("B", True)]
    assert not any(d.extrapolated for d in res.readout(whole).dominant)
    cells = [row[2] for row in readout.table("deg/h").rows if "dominates" in row[0]]
    assert all(c.endswith("; beyond the fit range 3.2 .. 102.4 s the fitted lines are "
                          "extrapolated") for c in cells)


def test_a_read_off_inside_the_fit_range_is_not_marked() -> None:
    """Fitted from 0.5 s on (the octave grid's 0.8..3277 s): N's -1/2 segment 0.8..1.6 s
    and B's minimum (204.8 s) lie inside; no dominant range leaves the fit either."""
    res = fogts.allan_deviation(fogts.read_run(EXAMPLE))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", fogts.errors.FogtsWarning)
        model = fogts.fit_noise(res, tau_range=(0.5, None))
    assert model.readoff.fit_tau_s == pytest.approx((0.8, 3276.8))
    assert "N" not in model.readoff.outside and "B" not in model.readoff.outside
    assert "outside the fit range" not in model.describe_readoff()
    dominant = res.readout(model).dominant
    assert dominant and dominant[0].tau_from_s == pytest.approx(0.1)  # N from the first tau
    assert dominant[0].extrapolated and not dominant[-1].extrapolated


def test_cli_read_offs_and_curve_table_agree_with_a_fit_range(tmp_path: Path) -> None:
    """`fogts allan --fit-tau-min 2 --fit-tau-max 200`: the read-off line, the curve table
    and the JSON name the same minimum, and mark what lies outside the fit."""
    from matplotlib import pyplot as plt

    out, png = tmp_path / "a.json", tmp_path / "a.png"
    res = CliRunner().invoke(app, ["allan", str(EXAMPLE), "--fit-tau-min", "2",
                                   "--fit-tau-max", "200", "--json", str(out), "--plot",
                                   str(png)])
    assert res.exit_code == 0, res.stderr
    doc = json.loads(out.read_text())["axes"][0]
    b, minimum = doc["noise_fit"]["readoff"]["B"], doc["curve"]["minimum"]
    assert b["tau"] == pytest.approx(minimum["tau"]) == pytest.approx(204.8)
    assert b["value"] == pytest.approx(minimum["bias_instability_floor"], rel=1e-12)
    assert b["outside_fit_range"] is True and b["supported"] is True
    assert [d["extrapolated"] for d in doc["curve"]["dominant"]] == [True, True]
    assert "B = 0.01909 deg/h (minimum / 0.664; read at tau = 204.8 s, outside the fit " \
           "range 3.2 .. 102.4 s" in res.stdout
    assert "floor/0.664 = 0.01909 deg/h" in res.stdout  # the curve table's minimum row
    # the dominant rows of the curve table (a cell may fold onto a second line)
    assert res.stdout.count("slope -0.5; beyond the fit range 3.2 .. 102.4 s the fitted") == 1
    assert png.stat().st_size > 1000
    plt.close("all")


def test_the_figure_labels_a_read_off_outside_the_fit_range() -> None:
    from matplotlib import pyplot as plt

    from fogts.report.plots import plot_allan

    res = fogts.allan_deviation(fogts.read_run(EXAMPLE))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", fogts.errors.FogtsWarning)
        model = fogts.fit_noise(res, tau_range=(2.0, 200.0))
    fig = plot_allan(res, model, fit_range=(2.0, 200.0))
    labels = [t.get_text() for t in fig.axes[0].get_legend().get_texts()]
    b = next(label for label in labels if label.startswith("read-off B"))
    assert b.endswith(", outside the fit, read outside the fit range")
    plt.close(fig)


def test_gmwm_over_a_range_reads_the_whole_curve_too() -> None:
    """Up to 400 s (fitted taus 0.1..204.8 s): K's closest segment, 204.8..409.6 s, leaves
    the fit range and says so; B's minimum at 204.8 s is inside."""
    res = fogts.allan_deviation(fogts.read_run(EXAMPLE))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", fogts.errors.FogtsWarning)
        model = fogts.fit_noise(res, method="gmwm", tau_range=(None, 400.0))
    assert model.readoff.fit_tau_s == pytest.approx((0.1, 204.8))
    assert model.readoff.outside == ("K",)
    assert model.readoff.tau_B_s == pytest.approx(res.readout(model).tau_min_s)
