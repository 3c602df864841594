"""DAVar stationarity with an effect size: "not stationary" needs a significant score and a
change of at least ``min_change`` (10 % by default) of the deviation."""

from __future__ import annotations

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
    assert "stationary within 10 % (the change is significant but only" in ns.summary()
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
