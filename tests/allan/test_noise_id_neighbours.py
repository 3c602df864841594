"""A lone jump of the identified noise type by two or more types, with agreeing neighbours,
is taken from the neighbours (CH104 X: alpha = +2, white PM, at tau = 2.56 s of rate data,
edf 165,021 against 3,762 and 939 beside it).  A jump of one type is left alone: it
would change Stable32's own identifications of the OCXO file (the tests that compare with
Stable32 hold)."""

from __future__ import annotations

import numpy as np

import fogts
from fogts.allan.noise_identification import _smooth_isolated
from tests.conftest import shared_path


def test_a_lone_two_type_jump_is_smoothed_in_place() -> None:
    alpha = np.array([0, 0, 2, 0, -1, 1, -1], dtype=np.int64)
    methods = ["acf"] * 7
    _smooth_isolated(alpha, methods)
    assert alpha.tolist() == [0, 0, 0, 0, -1, -1, -1]
    assert methods[2] == methods[5] == "neighbours" and methods[3] == "acf"


def test_one_type_and_unknown_neighbours_are_left_alone() -> None:
    alpha = np.array([0, 1, 0, 2, 0], dtype=np.int64)
    methods = ["acf", "acf", "acf", "acf", "none"]
    _smooth_isolated(alpha, methods)
    assert alpha.tolist() == [0, 1, 0, 2, 0]


def test_ch104_x_has_no_point_with_an_interval_ten_times_tighter() -> None:
    from scipy.io import loadmat

    gyro = loadmat(shared_path("imu", "ch104.mat"))["gyroReading"]
    run = fogts.read_run(np.asarray(gyro, dtype=np.float64), fs_hz=100.0, units="deg/s")
    res = fogts.allan_deviation(run, axis=0)
    i = int(np.argmin(np.abs(res.tau_s - 2.56)))
    assert res.alpha[i] == 0 and res.alpha_method[i] == "neighbours"
    rel = (res.ci_high - res.ci_low) / res.dev
    inner = rel[1:-1]
    assert np.all(inner * 10 > np.minimum(rel[:-2], rel[2:]))
