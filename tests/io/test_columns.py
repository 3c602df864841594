"""fogts.io.columns: rate, time and temperature columns by name or as given; the rate unit."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from fogts.io.reader import read_run
from tests.io.files import csv_text, write_file


def test_three_axis_file(tmp_path: Path) -> None:
    rng = np.random.default_rng(3)
    rows = ["t,gyro_x,gyro_y,gyro_z,temp"] + [
        f"{i / 100},{rng.normal()},{rng.normal()},{rng.normal()},30" for i in range(20)]
    run = read_run(write_file(tmp_path, "xyz.csv", "\n".join(rows)))
    assert run.axes == ("gyro_x", "gyro_y", "gyro_z")
    assert run.rate.shape == (20, 3)
    assert run.fs_hz == pytest.approx(100.0)


def test_explicit_columns_and_fs_override(tmp_path: Path) -> None:
    run = read_run(write_file(tmp_path, "a.csv", csv_text()), rate_column="T", time_column="time",
                   fs_hz=12.5, temperature_column="rate")
    assert run.axes == ("T",) and run.fs_hz == 12.5
    assert run.sampling is not None and run.sampling.fs_source == "given"


def test_units_option_and_default() -> None:
    assert read_run(np.arange(5.0), fs_hz=1).units == "deg/h"
    assert read_run(np.arange(5.0), fs_hz=1, units="DPS").units == "deg/s"
