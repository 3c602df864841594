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


def test_a_given_unit_over_a_unit_the_file_states_warns(tmp_path: Path) -> None:
    """``gyro_x_deg_s`` read with units='deg/h': the given unit is used, and a warning shows
    the column's; the same unit spelt otherwise ('dps') and a file that states no unit are
    silent."""
    import warnings

    from fogts.errors import DataQualityWarning

    rows = ["t,gyro_x_deg_s"] + [f"{i / 10},{(-1) ** i * 0.1}" for i in range(20)]
    path = write_file(tmp_path, "m.csv", "\n".join(rows))
    with pytest.warns(DataQualityWarning) as caught:
        run = read_run(path, units="deg/h")
    assert run.units == "deg/h" and run.units_source == "given"
    assert [str(w.message) for w in caught] == [
        f"{path}: units = deg/h (given) overrides the unit the file states, deg/s (from the "
        "column name 'gyro_x_deg_s'); the given unit is used"]
    plain = write_file(tmp_path, "p.csv", "\n".join(r.replace("gyro_x_deg_s", "rate")
                                                    for r in rows))
    with warnings.catch_warnings():
        warnings.simplefilter("error", DataQualityWarning)
        assert read_run(path, units="dps").units == "deg/s"
        assert read_run(plain, units="rad/s").units == "rad/s"


def test_a_given_unit_over_the_sidecar_unit_reads_plainly(tmp_path: Path) -> None:
    """The warning names the sidecar in plain words (audit2: 'from the its fogts sidecar')."""
    import json

    from fogts.errors import DataQualityWarning

    path = write_file(tmp_path, "s.csv", "\n".join(
        ["time,rate"] + [f"{i / 10},{(-1) ** i * 0.1}" for i in range(20)]))
    path.with_name("s.csv.json").write_text(json.dumps(
        {"generator": "fogts 0.1.0 simulate noise", "units": "deg/h"}))
    with pytest.warns(DataQualityWarning) as caught:
        run = read_run(path, units="deg/s")
    assert run.units == "deg/s"
    assert [str(w.message) for w in caught] == [
        f"{path}: units = deg/s (given) overrides the unit the file states, deg/h (from the "
        "fogts sidecar); the given unit is used"]
