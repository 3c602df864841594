"""Angle input: records of angle increments (delta-theta per sample) or integrated angle.

Many FOGs and IMUs log the angle turned in each sample period (``dtheta``,
``delta_angle``) or the running angle (``angle_deg``, ``theta``) rather than the rate.
:func:`input_kind` tells the three apart by name; :func:`to_rate` turns the columns into the
:class:`~fogts.io.run.Run`'s rate and keeps the angle itself (``Run.angle``), which the Allan
estimators use as the phase (:func:`fogts.allan.estimators.estimate_from_angle`), so that
an angle record is never differenced and integrated back:

* ``increment``: rate = dtheta x fs; angle = [0, cumsum(dtheta)] (n + 1 points);
* ``angle``: rate = diff(theta) x fs (n - 1 samples, timed at the end of each step);
  angle = theta - theta_0.

The unit: an angle unit (deg, rad, arcsec) makes the rate that unit per second.
"""

from __future__ import annotations

import re
from collections.abc import Sequence

import numpy as np

from fogts._typing import FloatArray
from fogts.choices import INPUT_KINDS
from fogts.errors import DataError

__all__ = ["ANGLE_UNIT_RATE", "input_kind", "is_angle_name", "rate_unit_of_angle", "to_rate"]

_INCREMENT_PREFIXES = ("dtheta", "d_theta", "delta_angle", "delta_theta", "dangle",
                       "angle_increment", "angle_inc", "delta_ang")
_ANGLE_PREFIXES = ("angle", "theta", "integrated_angle")
#: An angle unit and the rate unit of its derivative.
ANGLE_UNIT_RATE = {"deg": "deg/s", "rad": "rad/s", "arcsec": "arcsec/s"}
_ANGLE_HINTS = (("arcsec", "arcsec"), ("deg", "deg"), ("rad", "rad"))


def _norm(name: str) -> str:
    return re.sub(r"[\s.\-()\[\]/]+", "_", name.strip().lower()).strip("_")


def _kind_of_name(name: str) -> str | None:
    n = _norm(name.rsplit(".", 1)[-1])
    if n.startswith(_INCREMENT_PREFIXES):
        return "increment"
    if n.startswith(_ANGLE_PREFIXES) and not n.startswith("angular"):
        return "angle"
    return None


def is_angle_name(name: str) -> bool:
    """Whether a column name says angle or angle increment (``dtheta``, ``delta_angle_x``,
    ``angle_deg``, ``theta``).

    Examples
    --------
    >>> [is_angle_name(n) for n in ("dtheta_x", "angle_deg", "angular_rate", "gyro")]
    [True, True, False, False]
    """
    return _kind_of_name(name) is not None


def input_kind(given: str | None, names: Sequence[str]) -> str:
    """``given`` (checked), else the kind the names say (all must agree), else ``"rate"``.

    Examples
    --------
    >>> input_kind(None, ["dtheta_x", "dtheta_y"]), input_kind(None, ["gyro"])
    ('increment', 'rate')
    """
    if given is not None:
        if given not in INPUT_KINDS:
            raise DataError(f"input must be one of {', '.join(INPUT_KINDS)}; got {given!r}")
        return given
    kinds = {_kind_of_name(n) or "rate" for n in names}
    if len(kinds) > 1:
        raise DataError(f"the columns {', '.join(names)} mix {', '.join(sorted(kinds))}; "
                        "read them separately or pass input=")
    return kinds.pop() if kinds else "rate"


def rate_unit_of_angle(given: str | None, names: Sequence[str]) -> str | None:
    """The rate unit of an angle record: ``given`` as an angle unit (``deg`` -> ``deg/s``),
    else an angle unit at the end of a name (``angle_deg``, ``dtheta_rad``), else None."""
    if given is not None:
        return ANGLE_UNIT_RATE.get(given.strip().lower())
    for name in names:
        n = _norm(name)
        for hint, unit in _ANGLE_HINTS:
            if n.endswith("_" + hint) or f"_{hint}_" in n:
                return ANGLE_UNIT_RATE[unit]
    return None


def to_rate(kind: str, columns: list[FloatArray], fs_hz: float
            ) -> tuple[list[FloatArray], FloatArray | None]:
    """The rate columns and the angle (``(n + 1,)`` or ``(n + 1, k)``, from 0) of a record of
    ``kind``; rates pass through with no angle."""
    if kind == "rate":
        return columns, None
    if kind == "increment":
        angles = [np.r_[0.0, np.cumsum(c)] for c in columns]
        rates = [c * fs_hz for c in columns]
    else:
        angles = [c - c[0] for c in columns]
        rates = [np.diff(c) * fs_hz for c in columns]
    angle = angles[0] if len(angles) == 1 else np.column_stack(angles)
    return rates, np.ascontiguousarray(angle, dtype=np.float64)
