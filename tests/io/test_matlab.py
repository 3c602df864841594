"""MATLAB ``.mat`` input: v5 written by scipy.io.savemat, v7.3 written as MATLAB lays it out
(HDF5 with a 512-byte user block holding the text header, matrices stored transposed)."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
import scipy.io

from fogts.errors import DataError
from fogts.io.reader import read_run
from tests.conftest import shared_path

FS = 100.0
N = 2_000


def _gyro(seed: int = 3) -> np.ndarray:
    return np.random.default_rng(seed).standard_normal((N, 3))


def test_v5_matrix_columns_are_axes_and_fs_is_read(tmp_path: Path) -> None:
    gyro, acc = _gyro(), _gyro(4)
    path = tmp_path / "imu.mat"
    scipy.io.savemat(path, {"gyroReading": gyro, "accReading": acc, "fs": FS,
                            "calib": np.eye(3)})
    run = read_run(path, units="deg/s")
    # accReading is recognised as the accelerometer: three more axes after the gyro's
    assert run.axes == ("gyroReading_0", "gyroReading_1", "gyroReading_2",
                        "accReading_0", "accReading_1", "accReading_2")
    assert run.fs_hz == pytest.approx(FS, rel=1e-15)
    np.testing.assert_array_equal(run.rate, np.hstack([gyro, acc]))  # read, not computed
    assert run.units == "deg/s"
    assert run.axis_units[:3] == ("deg/s",) * 3
    gyro_only = read_run(path, units="deg/s", accel_column=[])
    np.testing.assert_array_equal(gyro_only.rate, gyro)


def test_v5_struct_fields_and_a_time_vector(tmp_path: Path) -> None:
    gyro = _gyro()
    t = np.arange(N) / 50.0
    path = tmp_path / "log.mat"
    scipy.io.savemat(path, {"imu": {"t": t, "gyro": gyro[:, 0]}})
    run = read_run(path, units="rad/s")
    assert run.axes == ("imu.gyro",)
    assert run.fs_hz == pytest.approx(50.0, rel=1e-9)
    np.testing.assert_array_equal(run.rate, gyro[:, 0])


def test_channels_by_samples_matrix_is_turned_round(tmp_path: Path) -> None:
    gyro = _gyro()
    path = tmp_path / "wide.mat"
    scipy.io.savemat(path, {"gyro": gyro.T, "fs": FS})
    run = read_run(path, units="deg/s")
    np.testing.assert_array_equal(run.rate, gyro)


def _write_v73(path: Path, variables: dict[str, np.ndarray]) -> None:
    import h5py

    with h5py.File(path, "w", userblock_size=512) as h5:
        for key, value in variables.items():
            h5.create_dataset(key, data=np.asarray(value).T)   # MATLAB is column-major
    header = b"MATLAB 7.3 MAT-file, Platform: GLNXA64, Created on: Tue Nov 24 2026 HDF5 schema 1.00 ."
    with path.open("r+b") as fh:
        fh.write(header.ljust(128, b" "))


def test_v73_hdf5_file(tmp_path: Path) -> None:
    gyro = _gyro()
    path = tmp_path / "v73.mat"
    _write_v73(path, {"gyroReading": gyro, "fs": np.array([[FS]])})
    run = read_run(path, units="deg/s")
    assert run.axes == ("gyroReading_0", "gyroReading_1", "gyroReading_2")
    assert run.fs_hz == pytest.approx(FS, rel=1e-15)
    np.testing.assert_array_equal(run.rate, gyro)


def test_not_a_mat_file_and_no_numeric_data(tmp_path: Path) -> None:
    fake = tmp_path / "fake.mat"
    fake.write_bytes(b"\x00\x01 not matlab" * 20)
    with pytest.raises(DataError, match="is not a MATLAB .mat file"):
        read_run(fake)
    empty = tmp_path / "names.mat"
    scipy.io.savemat(empty, {"label": "gyro run"})
    with pytest.raises(DataError, match="holds no numeric vector or matrix; variables are: label"):
        read_run(empty)


def test_oversized_mat_is_refused(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    path = tmp_path / "imu.mat"
    scipy.io.savemat(path, {"gyro": _gyro(), "fs": FS})
    monkeypatch.setenv("FOGTS_MAX_INPUT_BYTES", "1K")
    with pytest.raises(DataError, match="larger than the input limit"):
        read_run(path)


def test_ch104_reads_directly() -> None:
    path = shared_path("imu", "ch104.mat")
    with pytest.raises(DataError, match="no time column found .* no sample rate given; pass "
                                        "fs_hz="):
        read_run(path)  # the file stores no sample rate: the error says what to pass
    run = read_run(path, units="deg/s", fs_hz=100.0)
    assert run.axes == ("gyroReading_0", "gyroReading_1", "gyroReading_2",
                        "accReading_0", "accReading_1", "accReading_2")
    # accReading's mean vector is 1.007 long: g (within GRAVITY_TOLERANCE of 1 g, 9.8 % of
    # the next candidate m/s^2)
    assert run.axis_units == ("deg/s",) * 3 + ("g",) * 3
    assert run.accel_units_source == "gravity magnitude"
    assert run.n == 321_253
