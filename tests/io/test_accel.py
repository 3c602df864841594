"""Accelerometer columns: names, unit hints, the gravity-magnitude unit, the reader."""

from __future__ import annotations

import numpy as np
import pandas as pd
import pytest

from fogts.errors import DataError
from fogts.io.accel import accel_unit, is_accel_name
from fogts.io.reader import read_run

N = 500


@pytest.mark.parametrize("name", ["acc_x_mps2", "accel_g", "ax", "AZ", "accReading_0",
                                  "linear_acceleration_y", "imu.acc", "accelerometer"])
def test_accelerometer_names(name: str) -> None:
    assert is_accel_name(name)


@pytest.mark.parametrize("name", ["gyro_x", "axis", "x", "temperature", "time_s", "fog"])
def test_other_names(name: str) -> None:
    assert not is_accel_name(name)


@pytest.mark.parametrize(("names", "unit"), [
    (["acc_x_mps2"], "m/s^2"), (["accel_g"], "g"), (["acc_z_mg"], "mg"),
    (["acc_y_ug"], "ug"), (["acc_x_m_s2"], "m/s^2")])
def test_unit_hints(names: list[str], unit: str) -> None:
    assert accel_unit(None, names, [np.zeros(3)]) == (unit, "column name")


@pytest.mark.parametrize(("one_g", "unit"), [(9.80665, "m/s^2"), (1.0, "g"), (1000.0, "mg"),
                                             (1e6, "ug")])
def test_gravity_magnitude_gives_the_unit(one_g: float, unit: str) -> None:
    # a tilted triad: the mean vector still has the length of gravity
    g = one_g * np.array([0.3, -0.2, np.sqrt(1 - 0.13)])
    cols = [np.full(10, v) for v in g]
    assert accel_unit(None, ["ax", "ay", "az"], cols) == (unit, "gravity magnitude")


def test_no_gravity_means_m_s2_assumed() -> None:
    assert accel_unit(None, ["ax"], [np.full(4, 0.3)]) == ("m/s^2", "assumed")


def _imu_frame() -> pd.DataFrame:
    rng = np.random.default_rng(5)
    frame = pd.DataFrame({"time": np.arange(N) / 50.0})
    for c in "xyz":
        frame[f"g{c}"] = rng.normal(size=N)
    for c, mean in zip("xyz", (0.0, 0.0, 1.0), strict=True):
        frame[f"a{c}"] = mean + 1e-3 * rng.normal(size=N)
    return frame


def test_reader_puts_accelerometer_axes_after_the_gyro() -> None:
    run = read_run(_imu_frame(), units="deg/s")
    assert run.axes == ("gx", "gy", "gz", "ax", "ay", "az")
    assert run.axis_units == ("deg/s",) * 3 + ("g",) * 3
    assert run.accel_units_source == "gravity magnitude"
    assert run.unit_of("az") == "g" and run.unit_of(0) == "deg/s"
    given = read_run(_imu_frame(), units="deg/s", accel_units="mg")
    assert given.axis_units[3:] == ("mg",) * 3 and given.accel_units_source == "given"


def test_an_accelerometer_only_file() -> None:
    run = read_run(_imu_frame().drop(columns=["gx", "gy", "gz"]))
    assert run.axes == ("ax", "ay", "az") and run.units == "g"


def test_bad_accel_units() -> None:
    with pytest.raises(DataError, match=r"accel_units must be one of m/s\^2, g, mg, ug, got "
                                        "'furlong'"):
        read_run(_imu_frame(), accel_units="furlong")


def test_a_column_cannot_be_rate_and_accelerometer() -> None:
    with pytest.raises(DataError, match="column 'gx' cannot be both a rate and an "
                                        "accelerometer column"):
        read_run(_imu_frame(), rate_column="gx", accel_column="gx")


def test_unknown_axis_unit() -> None:
    run = read_run(_imu_frame(), units="deg/s")
    with pytest.raises(DataError, match="axis 'q' not found"):
        run.unit_of("q")
