"""Angular-rate and angle units, and the Earth-rate component.

Internally fogts analyses rate in the unit it was read in; this module converts between
the four rate units a gyro engineer meets: deg/h, deg/s, rad/s and arcsec/s.  The noise
coefficients of IEEE Std 952-1997 are reported in deg/h-based units (see DESIGN.md), so
:func:`to_deg_per_hour_factor` is the bridge used by :mod:`fogts.allan.noise`.
"""

from __future__ import annotations

import math
import re
from typing import Literal, get_args

import numpy as np

from fogts._validate import check_positive
from fogts.errors import DataError

__all__ = ["EARTH_RATE_RAD_S", "RATE_UNITS", "RateUnit", "convert_rate", "earth_rate_component",
           "parse_duration", "parse_rate_unit", "to_deg_per_hour_factor"]

RateUnit = Literal["deg/h", "deg/s", "rad/s", "arcsec/s"]
RATE_UNITS: tuple[str, ...] = get_args(RateUnit)

#: Earth's sidereal rotation rate in rad/s (WGS-84 value, 7.292115e-5 rad/s).
EARTH_RATE_RAD_S = 7.292115e-5

# One unit of each expressed in deg/h.
_TO_DEG_PER_HOUR: dict[str, float] = {
    "deg/h": 1.0,
    "deg/s": 3600.0,
    "rad/s": 3600.0 * 180.0 / math.pi,
    "arcsec/s": 1.0,  # 1 arcsec/s = (1/3600) deg/s = 1 deg/h
}

_ALIASES: dict[str, str] = {
    "deg/h": "deg/h", "deg/hr": "deg/h", "dph": "deg/h", "°/h": "deg/h", "degh": "deg/h",
    "deg/s": "deg/s", "dps": "deg/s", "°/s": "deg/s", "degs": "deg/s", "deg/sec": "deg/s",
    "rad/s": "rad/s", "rps": "rad/s", "rad/sec": "rad/s",
    "arcsec/s": "arcsec/s", "asec/s": "arcsec/s", '"/s': "arcsec/s",
}


def parse_rate_unit(unit: str, name: str = "units") -> str:
    """Return the canonical spelling of a rate unit.

    Accepts the canonical names ``deg/h``, ``deg/s``, ``rad/s``, ``arcsec/s`` and common
    aliases (``dph``, ``dps``, ``deg/hr``, ...), case-insensitively.

    Examples
    --------
    >>> parse_rate_unit("DPS")
    'deg/s'
    """
    key = str(unit).strip().lower()
    if key not in _ALIASES:
        raise DataError(f"{name} must be one of {', '.join(RATE_UNITS)}, got {unit!r}")
    return _ALIASES[key]


def to_deg_per_hour_factor(unit: str) -> float:
    """Multiply a rate in ``unit`` by this factor to get deg/h.

    Examples
    --------
    >>> to_deg_per_hour_factor("deg/s")
    3600.0
    """
    return _TO_DEG_PER_HOUR[parse_rate_unit(unit)]


def convert_rate(x: np.ndarray | float, from_unit: str, to_unit: str) -> np.ndarray | float:
    """Convert an angular rate between units.

    Examples
    --------
    >>> round(float(convert_rate(1.0, "rad/s", "deg/s")), 6)
    57.29578
    """
    factor = to_deg_per_hour_factor(from_unit) / to_deg_per_hour_factor(to_unit)
    if isinstance(x, np.ndarray):
        return x * factor
    return float(x) * factor


def earth_rate_component(latitude_deg: float, *, unit: str = "deg/h",
                         axis: Literal["vertical", "north"] = "vertical") -> float:
    """Earth-rate component sensed by a static gyro axis.

    The vertical (up) axis senses Ω·sin(φ); a level north-pointing axis senses Ω·cos(φ),
    with Ω = 7.292115e-5 rad/s (WGS-84).  Subtract it from a static test's mean rate.

    Parameters
    ----------
    latitude_deg : float
        Geodetic latitude in degrees, in [-90, 90].
    unit : str
        Output rate unit.
    axis : {"vertical", "north"}
        Which component.

    Examples
    --------
    >>> round(earth_rate_component(90.0), 4)   # at the pole the vertical axis sees all of it
    15.0411
    """
    lat = float(latitude_deg)
    if not math.isfinite(lat) or not -90.0 <= lat <= 90.0:
        raise DataError(f"latitude_deg must be in [-90, 90], got {latitude_deg!r}")
    if axis not in ("vertical", "north"):
        raise DataError(f"axis must be one of vertical, north; got {axis!r}")
    trig = math.sin if axis == "vertical" else math.cos
    omega_deg_h = float(convert_rate(EARTH_RATE_RAD_S, "rad/s", unit))
    return omega_deg_h * trig(math.radians(lat))


# Durations
_DURATION_UNITS = {"ms": 1e-3, "s": 1.0, "sec": 1.0, "secs": 1.0, "second": 1.0,
                   "seconds": 1.0, "min": 60.0, "mins": 60.0, "minute": 60.0, "minutes": 60.0,
                   "h": 3600.0, "hr": 3600.0, "hrs": 3600.0, "hour": 3600.0, "hours": 3600.0,
                   "d": 86400.0, "day": 86400.0, "days": 86400.0}
_DURATION_PART = re.compile(r"\s*([0-9]*\.?[0-9]+(?:[eE][-+]?[0-9]+)?)\s*([a-zA-Z]*)")


def parse_duration(text: str | float, name: str = "duration") -> float:
    """Parse a duration such as ``"3h"``, ``"90min"``, ``"600s"``, ``"1d"`` or ``"1h30min"``.

    A bare number is seconds.  Units: ms, s/sec, min, h/hr, d/day (and their plurals);
    ``m`` is refused as ambiguous (minutes or metres?).

    Returns
    -------
    float
        The duration in seconds (> 0).

    Examples
    --------
    >>> parse_duration("3h"), parse_duration("90min"), parse_duration("1h30min")
    (10800.0, 5400.0, 5400.0)
    """
    if isinstance(text, int | float) and not isinstance(text, bool):
        return check_positive(name, text)
    s = str(text).strip()
    pos, total, parts = 0, 0.0, 0
    while pos < len(s):
        match = _DURATION_PART.match(s, pos)
        if match is None or match.end() == pos:
            break
        value, unit = float(match.group(1)), match.group(2).lower()
        if unit == "":
            if parts or match.end() != len(s):
                break
            unit = "s"
        if unit not in _DURATION_UNITS:
            raise DataError(f"{name} has an unknown unit {match.group(2)!r} in {text!r}; use "
                            "ms, s, min, h or d, e.g. 3h, 90min, 600s, 1d")
        total += value * _DURATION_UNITS[unit]
        parts += 1
        pos = match.end()
    if parts == 0 or s[pos:].strip():
        raise DataError(f"{name} must look like 3h, 90min, 600s, 1d or a number of seconds; "
                        f"got {text!r}")
    if not math.isfinite(total) or total <= 0:
        raise DataError(f"{name} must be > 0, got {text!r}")
    return total
