"""ROS bag input: bags written here with rosbags' own writers and message serialiser."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from fogts.errors import DataError
from fogts.io.reader import read_run

rosbags = pytest.importorskip("rosbags", reason="rosbags is a dependency of fogts")

FS = 200.0
N = 600


def _samples(seed: int = 7) -> tuple[np.ndarray, np.ndarray]:
    rng = np.random.default_rng(seed)
    return 1e-3 * rng.standard_normal((N, 3)), 9.81 + 1e-2 * rng.standard_normal((N, 3))


def _imu_message(store: object, i: int, gyro: np.ndarray, accel: np.ndarray,
                 t0_ns: int) -> object:
    types = store.types  # type: ignore[attr-defined]
    Imu, Header, Time = (types["sensor_msgs/msg/Imu"], types["std_msgs/msg/Header"],
                         types["builtin_interfaces/msg/Time"])
    Vector3, Quaternion = types["geometry_msgs/msg/Vector3"], types["geometry_msgs/msg/Quaternion"]
    stamp = t0_ns + round(i * 1e9 / FS)
    cov = np.zeros(9)
    fields = Header.__dataclass_fields__  # a ROS 1 header also has a sequence number
    header = Header(stamp=Time(sec=stamp // 10**9, nanosec=stamp % 10**9), frame_id="imu",
                    **({"seq": i} if "seq" in fields else {}))
    return Imu(header=header,
               orientation=Quaternion(x=0.0, y=0.0, z=0.0, w=1.0), orientation_covariance=cov,
               angular_velocity=Vector3(x=gyro[i, 0], y=gyro[i, 1], z=gyro[i, 2]),
               angular_velocity_covariance=cov,
               linear_acceleration=Vector3(x=accel[i, 0], y=accel[i, 1], z=accel[i, 2]),
               linear_acceleration_covariance=cov)


def _write_ros2(path: Path, topics: tuple[str, ...] = ("/imu",)) -> tuple[np.ndarray, np.ndarray]:
    from rosbags.rosbag2 import Writer
    from rosbags.typesys import Stores, get_typestore

    store = get_typestore(Stores.ROS2_HUMBLE)
    gyro, accel = _samples()
    t0 = 1_732_400_000 * 10**9
    with Writer(path, version=8) as writer:
        for topic in topics:
            conn = writer.add_connection(topic, "sensor_msgs/msg/Imu", typestore=store)
            for i in range(N):
                msg = _imu_message(store, i, gyro, accel, t0)
                writer.write(conn, t0 + i, store.serialize_cdr(msg, "sensor_msgs/msg/Imu"))
    return gyro, accel


def _write_ros1(path: Path) -> tuple[np.ndarray, np.ndarray]:
    from rosbags.rosbag1 import Writer
    from rosbags.typesys import Stores, get_typestore

    store = get_typestore(Stores.ROS1_NOETIC)
    gyro, accel = _samples(8)
    t0 = 1_732_400_000 * 10**9
    with Writer(path) as writer:
        conn = writer.add_connection("/imu/data", "sensor_msgs/msg/Imu", typestore=store)
        for i in range(N):
            msg = _imu_message(store, i, gyro, accel, t0)
            writer.write(conn, t0 + i, store.serialize_ros1(msg, "sensor_msgs/msg/Imu"))
    return gyro, accel


def test_ros2_bag_gives_three_rate_axes_in_rad_s(tmp_path: Path) -> None:
    gyro, accel = _write_ros2(tmp_path / "bag")
    run = read_run(tmp_path / "bag")
    assert run.axes == ("angular_velocity_x", "angular_velocity_y", "angular_velocity_z",
                        "linear_acceleration_x", "linear_acceleration_y",
                        "linear_acceleration_z")
    assert run.units == "rad/s" and run.units_source == "file metadata"
    # the message fixes m/s^2 for linear_acceleration: three accelerometer axes
    assert run.axis_units == ("rad/s",) * 3 + ("m/s^2",) * 3
    assert run.accel_units_source == "file metadata"
    assert run.fs_hz == pytest.approx(FS, rel=1e-9)
    np.testing.assert_array_equal(run.rate, np.hstack([gyro, accel]))  # read, not computed
    assert run.time[0] == 0.0
    # The storage file names the same bag.
    db3 = next((tmp_path / "bag").glob("*.db3"))
    np.testing.assert_array_equal(read_run(db3).rate[:, :3], gyro)


def test_ros1_bag(tmp_path: Path) -> None:
    gyro, _ = _write_ros1(tmp_path / "run.bag")
    run = read_run(tmp_path / "run.bag")
    np.testing.assert_array_equal(run.rate[:, :3], gyro)
    assert run.fs_hz == pytest.approx(FS, rel=1e-9)


def test_several_imu_topics_need_a_topic(tmp_path: Path) -> None:
    gyro, _ = _write_ros2(tmp_path / "two", topics=("/imu0", "/imu1"))
    with pytest.raises(DataError, match=r"several IMU topics \(/imu0, /imu1\); choose one "
                                        r"with topic=NAME$"):
        read_run(tmp_path / "two")
    np.testing.assert_array_equal(read_run(tmp_path / "two", topic="/imu1").rate[:, :3], gyro)
    with pytest.raises(DataError, match="topic '/cam' is not an IMU topic .* IMU topics are: "
                                        "/imu0, /imu1"):
        read_run(tmp_path / "two", topic="/cam")


def test_topic_on_a_non_bag_is_refused(tmp_path: Path) -> None:
    csv = tmp_path / "r.csv"
    csv.write_text("time,rate\n0,1\n0.1,2\n0.2,1\n")
    with pytest.raises(DataError, match="topic is for ROS bags; .* is not one"):
        read_run(csv, topic="/imu")


def test_cli_reads_a_ros2_bag(tmp_path: Path) -> None:
    from typer.testing import CliRunner

    from fogts.cli import app

    _write_ros2(tmp_path / "bag")
    res = CliRunner().invoke(app, ["info", str(tmp_path / "bag")])
    assert res.exit_code == 0, res.stderr
    assert "angular_velocity_x" in res.stdout and "rad/s" in res.stdout
