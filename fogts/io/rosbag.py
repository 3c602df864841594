"""ROS 1 and ROS 2 bags: ``sensor_msgs/Imu`` messages as a recording, through ``rosbags``.

A ROS 1 bag is one ``.bag`` file; a ROS 2 bag is a directory with ``metadata.yaml`` and its
``.db3`` (SQLite) or ``.mcap`` storage (either the directory or its storage file may be
given).  Each ``sensor_msgs/Imu`` message gives one sample: its header stamp (the time
base, in seconds from the first message), ``angular_velocity`` x, y, z (the rate axes) and
``linear_acceleration`` x, y, z.  The message definition fixes the units: rad/s and m/s^2
(ROS REP 103, "Standard Units of Measure and Coordinate Conventions"), so the rate unit is
known without a guess.  A bag with several IMU topics needs ``topic``.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np
import pandas as pd

from fogts.errors import DataError
from fogts.io.limits import max_input_bytes
from fogts.io.table import Table

__all__ = ["IMU_TYPES", "is_ros2_bag", "rosbag_table"]

#: Message types read (ROS 1 and ROS 2 spellings).
IMU_TYPES = frozenset({"sensor_msgs/msg/Imu", "sensor_msgs/Imu"})
_AXES = ("x", "y", "z")


def is_ros2_bag(path: Path) -> bool:
    """A ROS 2 bag directory, or the storage file of one."""
    folder = path if path.is_dir() else path.parent
    return (folder / "metadata.yaml").is_file() and (path.is_dir()
                                                     or path.suffix in (".db3", ".mcap"))


def rosbag_table(path: Path, topic: str | None = None) -> Table:
    """The IMU messages of a ROS 1 or ROS 2 bag as a Table (see the module docstring)."""
    bag = path.parent if path.suffix in (".db3", ".mcap") else path
    _check_size(bag)
    try:
        from rosbags.highlevel import AnyReader
    except ImportError:  # pragma: no cover - rosbags is a dependency
        raise DataError("reading ROS bags needs the rosbags package (pip install rosbags)") \
            from None
    try:
        with AnyReader([bag]) as reader:
            connections = _imu_connections(reader, bag, topic)
            stamps, gyro, accel = _read_messages(reader, connections)
    except DataError:
        raise
    except Exception as exc:  # rosbags raises its own error types per storage plugin
        raise DataError(f"cannot read ROS bag {str(bag)!r}: {exc}") from None
    if stamps.size == 0:
        raise DataError(f"ROS bag {str(bag)!r} has no message on topic "
                        f"{connections[0].topic!r}")
    order = np.argsort(stamps, kind="stable")
    first_ns = int(stamps[order][0])
    # Integer nanoseconds from the first stamp: epoch seconds in float64 would keep only
    # ~0.2 us, which is jitter on a kHz IMU.
    frame = pd.DataFrame({"time": (stamps[order] - first_ns) / 1e9})
    for i, axis in enumerate(_AXES):
        frame[f"angular_velocity_{axis}"] = gyro[order, i]
    for i, axis in enumerate(_AXES):
        frame[f"linear_acceleration_{axis}"] = accel[order, i]
    comments = (f"topic {connections[0].topic}; first header stamp {first_ns // 10**9}."
                f"{first_ns % 10**9:09d} s",)
    return Table(frame, str(bag), None, comments, None, None, True, sidecar_unit="rad/s",
                 accel_unit="m/s^2")


def _check_size(bag: Path) -> None:
    files = [p for p in bag.iterdir() if p.is_file()] if bag.is_dir() else [bag]
    if sum(p.stat().st_size for p in files) > max_input_bytes():
        raise DataError(f"{str(bag)!r} is larger than the input limit; oversized input is "
                        "refused (set FOGTS_MAX_INPUT_BYTES to raise it)")


def _imu_connections(reader: Any, bag: Path, topic: str | None) -> list[Any]:
    imu = [c for c in reader.connections if c.msgtype in IMU_TYPES]
    topics = sorted({c.topic for c in imu})
    if not topics:
        found = ", ".join(sorted({f"{c.topic} ({c.msgtype})" for c in reader.connections}))
        raise DataError(f"ROS bag {str(bag)!r} has no sensor_msgs/Imu topic; topics are: "
                        f"{found or '(none)'}")
    if topic is None and len(topics) > 1:
        raise DataError(f"ROS bag {str(bag)!r} has several IMU topics ({', '.join(topics)}); "
                        "choose one with topic=NAME")
    chosen = topics[0] if topic is None else topic
    if chosen not in topics:
        raise DataError(f"topic {topic!r} is not an IMU topic of {str(bag)!r}; IMU topics "
                        f"are: {', '.join(topics)}")
    return [c for c in imu if c.topic == chosen]


def _read_messages(reader: Any, connections: list[Any]
                   ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Header stamps (integer ns), angular velocities and accelerations."""
    stamps: list[int] = []
    gyro: list[tuple[float, float, float]] = []
    accel: list[tuple[float, float, float]] = []
    for connection, _, raw in reader.messages(connections=connections):
        msg = reader.deserialize(raw, connection.msgtype)
        stamp = msg.header.stamp
        stamps.append(int(stamp.sec) * 1_000_000_000 + int(stamp.nanosec))
        w, a = msg.angular_velocity, msg.linear_acceleration
        gyro.append((w.x, w.y, w.z))
        accel.append((a.x, a.y, a.z))
    return (np.asarray(stamps, dtype=np.int64),
            np.asarray(gyro, dtype=np.float64).reshape(-1, 3),
            np.asarray(accel, dtype=np.float64).reshape(-1, 3))
