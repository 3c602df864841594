"""DAVar stationarity with an effect size: "not stationary" needs a significant score and a
change of at least ``min_change`` (10 % by default) of the deviation."""

from __future__ import annotations

import dataclasses
import re

import numpy as np
import pytest
from typer.testing import CliRunner

import fogts
from fogts.cli import app
from fogts.errors import DataError
from tests.conftest import error_output, shared_path

FS = 10.0
N = 36_000  # 1 h at 10 Hz
WINDOW_S = 300.0


def _white(seed: int, step: float = 1.0, n: int = N) -> np.ndarray:
    x = np.random.default_rng(seed).normal(size=n)
    x[n // 2:] *= step
    return x


@pytest.mark.parametrize("seed", [1, 2])
def test_a_20_percent_step_is_found_within_one_window(seed: int) -> None:
    res = fogts.dynamic_allan(_white(seed, 1.2), fs_hz=FS, window_s=WINDOW_S, step_s=75.0)
    ns = res.nonstationarity
    assert not ns.stationary and ns.significant and ns.effect >= 0.1
    assert ns.change_time_s == pytest.approx(N / FS / 2, abs=WINDOW_S)
    assert ns.change_ratio == pytest.approx(1.2, abs=0.05)
    assert "NOT stationary" in ns.summary()


@pytest.mark.parametrize("seed", [3, 4])
def test_white_noise_is_stationary(seed: int) -> None:
    ns = fogts.dynamic_allan(_white(seed), fs_hz=FS, window_s=WINDOW_S, step_s=75.0
                             ).nonstationarity
    assert ns.stationary and ns.effect < 0.1


def test_a_small_significant_change_is_stationary_within_the_threshold() -> None:
    """A 5 % step in 4 h: significant (p ~ 1e-21), but under the 10 % threshold."""
    x = _white(5, 1.05, n=4 * N)
    ns = fogts.dynamic_allan(x, fs_hz=FS, window_s=WINDOW_S, step_s=75.0).nonstationarity
    assert ns.significant and 0.02 < ns.effect < 0.1 and ns.stationary
    assert ns.change_time_s is None
    assert "stationary within 10 % in 300 s windows (the change is significant but only" \
        in ns.summary()
    strict = fogts.dynamic_allan(x, fs_hz=FS, window_s=WINDOW_S, step_s=75.0,
                                 min_change=0.02).nonstationarity
    assert not strict.stationary and strict.change_time_s is not None


def test_adis16405_z_is_stationary() -> None:
    run = fogts.read_run(shared_path("imu", "adis_16405_imu1_gyro.npz"), units="deg/s")
    res = fogts.dynamic_allan(run, axis="Gyro. Z", window_s=600, step_s=150)
    assert res.nonstationarity.stationary
    assert res.nonstationarity.to_dict()["effect"] < 0.1


def test_min_change_must_not_be_negative() -> None:
    with pytest.raises(DataError, match="min_change must be a finite number >= 0"):
        fogts.dynamic_allan(_white(6), fs_hz=FS, window_s=WINDOW_S, step_s=75.0,
                            min_change=-0.1)


def test_cli_names_the_option(tmp_path: pytest.TempPathFactory) -> None:
    res = CliRunner().invoke(app, ["davar", "data/example_fog_10hz_3h.csv", "--min-change",
                                   "-1"])
    assert res.exit_code == 2
    assert error_output(res.stderr).startswith("error: --min-change must be a finite number")


# --------------------------------------------------------------------------- transients
GLITCH_AT_S = 2000.0


def _glitched(seed: int) -> np.ndarray:
    """White noise (sd 1) with a 3-sample spike of 60 sigma at t = 2000 s."""
    x = _white(seed)
    i = int(GLITCH_AT_S * FS)
    x[i:i + 3] += 60.0
    return x


def test_a_glitch_is_named_as_the_largest_change_not_a_step() -> None:
    """At tau = 0.1 s (m = 1) the Allan variance of a 300 s window is the mean of 2999
    squared first differences (each 2 for unit white noise, halved); a 3-sample plateau of
    60 adds two differences of +-60, so the window's deviation grows by
    sqrt(1 + 2 * 3600 / (2 * 2999)) = 1.48; every window holding it is far above 10 %.
    The transient lies where those windows overlap (within a step of the spike) and the
    reader's glitch inside it is named."""
    run = fogts.read_run(_glitched(7), fs_hz=FS, units="deg/h")
    run, quality = fogts.assess_run(run)
    res = fogts.dynamic_allan(run, window_s=WINDOW_S, step_s=30.0, glitches=quality)
    ns = res.nonstationarity
    tr = ns.transient
    assert tr is not None and not ns.stationary and ns.transient_is_change
    assert tr.start_s - 30.0 <= GLITCH_AT_S <= tr.end_s + 30.0
    assert tr.n_windows == pytest.approx(WINDOW_S / 30.0, abs=1)
    assert tr.ratio == pytest.approx(1.48, abs=0.05)  # ~10 windows of edf ~2000 each
    assert tr.effect > ns.effect  # the transient, not a step, is largest
    assert ns.change_time_s is None  # the step is no change
    assert [round(g.time_s) for g in tr.glitches] == [GLITCH_AT_S]
    assert res.glitches == tr.glitches
    text = ns.summary()
    assert re.search(r"NOT stationary in \d+ s windows; transient at t = ", text) and "glitch found by the reader" in text
    assert ns.to_dict()["transient"]["glitch_times"] == [pytest.approx(GLITCH_AT_S)]


def test_glitches_from_a_report_or_a_list_and_of_other_axes() -> None:
    run, quality = fogts.assess_run(fogts.read_run(_glitched(8), fs_hz=FS, units="deg/h"))
    report = quality.glitches[0]
    one = fogts.dynamic_allan(run, window_s=WINDOW_S, step_s=30.0, glitches=report)
    listed = fogts.dynamic_allan(run, window_s=WINDOW_S, step_s=30.0, glitches=[report])
    assert one.glitches == listed.glitches and len(one.glitches) == 1
    other = dataclasses.replace(report, axis="elsewhere")
    assert fogts.dynamic_allan(run, window_s=WINDOW_S, step_s=30.0,
                               glitches=other).glitches == ()


def test_a_step_stays_the_named_change_over_its_windows() -> None:
    """A 20 % step also moves single windows from the pooled value, by about 10 %, but the
    windows of each half match their own side: the step is named, no transient."""
    ns = fogts.dynamic_allan(_white(1, 1.2), fs_hz=FS, window_s=WINDOW_S, step_s=75.0
                             ).nonstationarity
    assert ns.change_time_s is not None
    assert ns.transient is None or ns.transient.effect < 0.05  # a step's half is no event
    text = ns.summary()
    assert "most likely change at t" in text
    if "transient" in text:  # named after the larger step
        assert text.index("most likely change at t") < text.index("transient")


def test_the_heat_map_marks_the_glitches() -> None:
    from fogts.report.plots import plot_dynamic_allan

    run, quality = fogts.assess_run(fogts.read_run(_glitched(7), fs_hz=FS, units="deg/h"))
    res = fogts.dynamic_allan(run, window_s=WINDOW_S, step_s=30.0, glitches=quality)
    fig = plot_dynamic_allan(res)
    strip, heat = fig.axes[0], fig.axes[1]
    marks = [ln for ln in heat.get_lines() if ln.get_label() == "glitch (1)"]
    assert len(marks) == 1 and marks[0].get_xdata()[0] == pytest.approx(GLITCH_AT_S / 60.0)
    assert "transient" in [t.get_text() for t in strip.get_legend().get_texts()]


def test_adis16405_run4_names_its_glitch_on_x_and_no_change_elsewhere() -> None:
    """Run 4 has a glitch near t = 4046 s (-17 deg/s on X, -47 robust sigmas): the windows
    holding it are 19 % above the rest at tau = 0.01 s; Y (a -13 sigma echo of it) and Z
    change by under 3 %.  Measured: X transient t = 4040-4060 s, x1.19; Y x1.03; Z a 1.7 %
    step."""
    run, quality = fogts.assess_run(fogts.read_run(
        shared_path("imu", "adis_16405_imu4_gyro.npz"), units="deg/s"))
    res = fogts.dynamic_allan(run, window_s=200, step_s=20, glitches=quality)
    x, y, z = (res[a].nonstationarity for a in ("Gyro. X", "Gyro. Y", "Gyro. Z"))
    assert x.transient is not None and not x.stationary and x.change_time_s is None
    assert x.transient.start_s - 20 <= 4046.1 <= x.transient.end_s + 20
    assert x.transient.ratio == pytest.approx(1.19, abs=0.03)
    assert any(abs(g.time_s - 4046.07) < 0.05 for g in x.transient.glitches)
    assert "t = 4046.07 s" in x.summary() and "3090" not in x.summary()
    assert y.stationary and z.stationary
    assert y.transient is not None and y.transient.effect < 0.05
    assert z.transient is None  # its flagged windows open the record: no event


def test_cli_davar_names_the_glitch_of_run4() -> None:
    path = shared_path("imu", "adis_16405_imu4_gyro.npz")
    res = CliRunner().invoke(app, ["davar", str(path), "--axis", "Gyro. X"])
    assert res.exit_code == 0, res.output
    assert "NOT stationary in 200 s windows; transient at t = 4040-4060 s" in res.stdout
    assert "t = 4046.07 s" in res.stdout


def test_adis16405_run4_verdicts_name_their_window() -> None:
    """Audit N9: ADIS16405 run 4, x axis: a glitch at 4046 s raises 200 s windows by 19 %
    (NOT stationary) but 1000 s windows (the report's) by only a few % (stationary within
    10 %).  Both verdicts name their window length, so they do not read as a contradiction."""
    run = fogts.read_run(shared_path("imu", "adis_16405_imu4_gyro.npz"), units="deg/s")
    short = fogts.dynamic_allan(run, axis="Gyro. X", window_s=200, step_s=20).nonstationarity
    long = fogts.dynamic_allan(run, axis="Gyro. X", window_s=1000, step_s=250).nonstationarity
    assert not short.stationary and long.stationary
    assert ": NOT stationary in 200 s windows;" in short.summary()
    assert short.noise_level().startswith("noise level: NOT stationary in 200 s windows (")
    assert "stationary within 10 % in 1000 s windows" in long.summary()
    assert long.noise_level().startswith("noise level: stationary within 10 % in 1000 s "
                                         "windows (DAVAR:")
