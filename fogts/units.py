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
from fogts.choices import OUTPUT_UNITS
from fogts.errors import DataError

__all__ = ["EARTH_RATE_RAD_S", "RATE_UNITS", "TERM_DEG_UNIT", "TERM_SI_FACTOR", "TERM_SI_UNIT", "RateUnit",
           "convert_rate", "earth_rate_component", "parse_duration", "parse_rate_unit",
           "term_in_units", "term_unit", "to_deg_per_hour_factor"]

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

#: One degree in radians, and one arcsecond.
_RAD_PER_DEG = math.pi / 180.0
_S_PER_H = 3600.0

#: Multiply an IEEE-952 term in fogts' degree units (IEEE Std 952-1997 Annex C: Q in arcsec,
#: N in deg/sqrt(h), B in deg/h, K in deg/h^1.5, R in deg/h^2) by this factor to get SI:
#: N as a rate noise density in rad/s/sqrt(Hz) (= rad/sqrt(s), the angle random walk), B in
#: rad/s, K as a rate random walk in rad/s^2/sqrt(Hz) (= rad/s^1.5), R in rad/s^2, Q in rad.
#: Each factor is the degree-to-radian factor times the hours-to-seconds power of the unit:
#: deg/sqrt(h) = (pi/180) rad / sqrt(3600 s); deg/h^1.5 = (pi/180) rad / (3600 s)^1.5.  These
#: are the units of Kalibr's ``gyroscope_noise_density`` and ``gyroscope_random_walk``
#: (Kalibr wiki, "IMU Noise Model").
TERM_SI_FACTOR: dict[str, float] = {
    "Q": _RAD_PER_DEG / _S_PER_H,          # arcsec -> rad
    "N": _RAD_PER_DEG / math.sqrt(_S_PER_H),
    "B": _RAD_PER_DEG / _S_PER_H,
    "K": _RAD_PER_DEG / _S_PER_H**1.5,
    "R": _RAD_PER_DEG / _S_PER_H**2,
}
#: The SI unit of each term (see :data:`TERM_SI_FACTOR`).
TERM_SI_UNIT: dict[str, str] = {"Q": "rad", "N": "rad/s/sqrt(Hz)", "B": "rad/s",
                                "K": "rad/s^2/sqrt(Hz)", "R": "rad/s^2"}
#: The degree unit of each term (IEEE Std 952-1997; DESIGN.md).
TERM_DEG_UNIT: dict[str, str] = {"Q": "arcsec", "N": "deg/sqrt(h)", "B": "deg/h",
                                  "K": "deg/h^1.5", "R": "deg/h^2"}

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


def term_in_units(name: str, value: float, units: str) -> float:
    """An IEEE-952 term given in fogts' degree units, in ``units`` (``"deg"`` or ``"si"``).

    Examples
    --------
    >>> f"{term_in_units('N', 0.15, 'si'):.4e}"   # 0.15 deg/sqrt(h) in rad/s/sqrt(Hz)
    '4.3633e-05'
    """
    return float(value) * (TERM_SI_FACTOR[name] if _output_units(units) == "si" else 1.0)


def term_unit(name: str, units: str) -> str:
    """The unit of term ``name`` in ``units`` (``"deg"`` or ``"si"``).

    Examples
    --------
    >>> term_unit("K", "deg"), term_unit("K", "si")
    ('deg/h^1.5', 'rad/s^2/sqrt(Hz)')
    """
    return (TERM_SI_UNIT if _output_units(units) == "si" else TERM_DEG_UNIT)[name]


def _output_units(units: str) -> str:
    if units not in OUTPUT_UNITS:
        raise DataError(f"units must be one of {', '.join(OUTPUT_UNITS)}; got {units!r}")
    return units


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
