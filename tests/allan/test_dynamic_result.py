"""Tests of the dynamic Allan deviation's result texts (fogts.allan.dynamic_result)."""

from __future__ import annotations

import numpy as np

from fogts.allan.dynamic import dynamic_allan
from fogts.io.reader import read_run


def test_summary_gives_the_window_and_step_in_samples_too() -> None:
    """audit2 N16: at 99.3171 Hz a 60 s window is 5959 samples, 59.9997 s; the summary
    says so, so the reader sees why it is not 60 s."""
    fs = 99.3171
    run = read_run(np.random.default_rng(3).standard_normal(30_000), fs_hz=fs, units="deg/h")
    res = dynamic_allan(run, window_s=60.0, step_s=20.0)
    first = res.summary().splitlines()[0]
    assert res.window_n == 5959 and res.step_n == 1986
    assert f"windows of {5959 / fs:g} s (5959 samples) every {1986 / fs:g} s (1986 samples) " \
           "over 30000 samples at 99.3171 Hz" in first
    assert "59.9997 s (5959 samples)" in first
