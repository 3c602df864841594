"""Accelerometer columns: which columns hold specific force, and in which unit.

An IMU file often carries the accelerometer triad beside the gyro triad (``acc_x_mps2``,
``accel_g``, ``ax``, a ROS bag's ``linear_acceleration_x``, CH104's ``accReading``).  Those
columns become further axes of the :class:`~fogts.io.run.Run`, after the rate axes, each
with its unit in ``Run.axis_units``.

The unit comes, in this order, from the ``accel_units`` argument, from a hint in the column
names (``_mps2``, ``_m_s2``, ``_g``, ``_mg``, ``_ug``), or from the size of the mean specific
force: a static accelerometer triad measures gravity, so the length of its mean vector is
9.81 in m/s^2, 1 in g, 1000 in mg and 1e6 in ug (within :data:`GRAVITY_TOLERANCE`); else
m/s^2 is assumed and said so (``Run.accel_units_source``).
"""

from __future__ import annotations

import math
import re
from collections.abc import Sequence

import numpy as np

from fogts._typing import FloatArray
from fogts.io.sources import first_stated
from fogts.units import ACCEL_UNITS, STANDARD_GRAVITY_MPS2

__all__ = ["GRAVITY_TOLERANCE", "accel_unit", "is_accel_name"]

_ACCEL_NAMES = {"ax", "ay", "az", "acc", "accel", "accelerometer", "f_x", "f_y", "f_z",
                "specific_force"}
_ACCEL_PREFIXES = ("acc", "linear_acceleration", "specific_force", "ax_", "ay_", "az_")
#: Unit hints at the end of an accelerometer column's name (normalised: lower case, ``_``).
_ACCEL_HINTS: tuple[tuple[str, str], ...] = (
    ("mps2", "m/s^2"), ("m_s2", "m/s^2"), ("m_s_2", "m/s^2"), ("m_s^2", "m/s^2"),
    ("ms2", "m/s^2"), ("ug", "ug"), ("mg", "mg"), ("g", "g"),
)
#: Relative tolerance of the gravity-magnitude unit inference (a tilted or offset triad
#: still measures |f| = g within a few per cent; the four units are 1000x apart).
GRAVITY_TOLERANCE = 0.15


def _norm(name: str) -> str:
    return re.sub(r"[\s.\-()\[\]/]+", "_", name.strip().lower()).strip("_")


def is_accel_name(name: str) -> bool:
    """Whether a column name says specific force (``acc_x_mps2``, ``accel_g``, ``ax``,
    ``linear_acceleration_x``, ``accReading_0``, a struct field ``imu.acc``).

    Examples
    --------
    >>> [is_accel_name(n) for n in ("acc_x_mps2", "accel_g", "ax", "gyro_x", "axis")]
    [True, True, True, False, False]
    """
    n = _norm(name)
    if "." in name and is_accel_name(name.rsplit(".", 1)[-1]):
        return True
    return n in _ACCEL_NAMES or n.startswith(_ACCEL_PREFIXES)


def _unit_from_names(names: Sequence[str]) -> str | None:
    for name in names:
        n = _norm(name)
        for hint, unit in _ACCEL_HINTS:
            if n.endswith("_" + hint) or f"_{hint}_" in n:
                return unit
    return None


def _unit_from_gravity(columns: Sequence[FloatArray]) -> str | None:
    """The unit in which the mean specific-force vector has the length of gravity."""
    if not columns:
        return None
    length = math.sqrt(sum(float(np.mean(c)) ** 2 for c in columns))
    for unit, one_g in zip(ACCEL_UNITS, (STANDARD_GRAVITY_MPS2, 1.0, 1e3, 1e6), strict=True):
        if abs(length / one_g - 1.0) <= GRAVITY_TOLERANCE:
            return unit
    return None


def accel_unit(given: str | None, names: Sequence[str], columns: Sequence[FloatArray],
               recorded: str | None = None) -> tuple[str, str]:
    """The accelerometer unit and where it came from: ``"given"``, ``"file metadata"``
    (``recorded``: fixed by the format, as a ROS Imu message's m/s^2), ``"column name"``,
    ``"gravity magnitude"`` (the mean vector's length) or ``"assumed"`` (m/s^2).

    Examples
    --------
    >>> import numpy as np
    >>> accel_unit(None, ["ax", "ay", "az"], [np.zeros(3), np.zeros(3), np.ones(3)])
    ('g', 'gravity magnitude')
    """
    return first_stated((given, "given"), (recorded, "file metadata"),
                        (lambda: _unit_from_names(names), "column name"),
                        (lambda: _unit_from_gravity(columns), "gravity magnitude"),
                        default="m/s^2")
