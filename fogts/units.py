"""Angular-rate, angle and specific-force units, and the Earth-rate component.

Internally fogts analyses rate in the unit it was read in; this module converts between
the four rate units a gyro engineer meets: deg/h, deg/s, rad/s and arcsec/s.  The noise
coefficients of IEEE Std 952-1997 are reported in deg/h-based units (see DESIGN.md), so
:func:`to_deg_per_hour_factor` is the bridge used by :mod:`fogts.allan.noise`.

Accelerometers measure specific force in m/s^2, g, mg or ug (:data:`ACCEL_UNITS`; one g is
standard gravity, 9.80665 m/s^2 exactly: CGPM 1901, ISO 80000-3).  Their terms are reported
as users of accelerometer datasheets expect (:data:`ACCEL_TERM_UNIT`): velocity random walk
in m/s/sqrt(h), bias instability in ug, acceleration random walk in m/s/h^1.5; SI gives the
noise density in m/s^2/sqrt(Hz) (= m/s/sqrt(s)) and the random walk in m/s^3/sqrt(Hz), the
units of Kalibr's ``accelerometer_noise_density`` and ``accelerometer_random_walk``.
:func:`parse_sensor_unit` accepts either family and :func:`quantity_of` tells them apart.
"""

from __future__ import annotations

import math
import re
from typing import Literal, get_args

import numpy as np

from fogts._validate import check_positive
from fogts.choices import OUTPUT_UNITS
from fogts.errors import DataError

__all__ = ["ACCEL_TERM_SI_FACTOR", "ACCEL_TERM_SI_UNIT", "ACCEL_TERM_UNIT", "ACCEL_UNITS",
           "EARTH_RATE_RAD_S", "QUANTITIES", "RATE_UNITS", "STANDARD_GRAVITY_MPS2",
           "TERM_DEG_UNIT", "TERM_SI_FACTOR", "TERM_SI_UNIT", "AccelUnit", "Quantity",
           "RateUnit", "base_unit_factor", "convert_rate", "convert_sensor",
           "earth_rate_component", "parse_accel_unit", "parse_duration", "parse_rate_unit",
           "parse_sensor_unit", "quantity_of", "si_unit", "term_in_units", "term_unit",
           "to_deg_per_hour_factor"]

RateUnit = Literal["deg/h", "deg/s", "rad/s", "arcsec/s"]
RATE_UNITS: tuple[str, ...] = get_args(RateUnit)

AccelUnit = Literal["m/s^2", "g", "mg", "ug"]
ACCEL_UNITS: tuple[str, ...] = get_args(AccelUnit)

#: What a sensor axis measures: angular rate (gyro) or specific force (accelerometer).
Quantity = Literal["rate", "accel"]
QUANTITIES: tuple[str, ...] = get_args(Quantity)

#: Standard gravity in m/s^2 (exact by definition: 3rd CGPM 1901; ISO 80000-3), the g of
#: the accelerometer units g, mg and ug.
STANDARD_GRAVITY_MPS2 = 9.80665

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

#: One unit of specific force in m/s^2.
_TO_MPS2: dict[str, float] = {"m/s^2": 1.0, "g": STANDARD_GRAVITY_MPS2,
                              "mg": STANDARD_GRAVITY_MPS2 * 1e-3,
                              "ug": STANDARD_GRAVITY_MPS2 * 1e-6}

#: The engineering unit of each accelerometer term (the specific-force analogues of
#: IEEE 952's degree units): Q velocity quantization in m/s, N velocity random walk in
#: m/s/sqrt(h), B bias instability in ug, K acceleration random walk in m/s/h^1.5, R
#: acceleration ramp in m/s/h^2.
ACCEL_TERM_UNIT: dict[str, str] = {"Q": "m/s", "N": "m/s/sqrt(h)", "B": "ug",
                                   "K": "m/s/h^1.5", "R": "m/s/h^2"}
#: Multiply an accelerometer term in :data:`ACCEL_TERM_UNIT` by this factor to get SI
#: (:data:`ACCEL_TERM_SI_UNIT`): 1 m/s/sqrt(h) = 1 m/s / sqrt(3600 s) = (1/60) m/s/sqrt(s);
#: 1 ug = 9.80665e-6 m/s^2; 1 m/s/h^1.5 = 1 m/s / (3600 s)^1.5; 1 m/s/h^2 = 1 m/s / (3600 s)^2.
ACCEL_TERM_SI_FACTOR: dict[str, float] = {
    "Q": 1.0,
    "N": 1.0 / math.sqrt(_S_PER_H),
    "B": _TO_MPS2["ug"],
    "K": 1.0 / _S_PER_H**1.5,
    "R": 1.0 / _S_PER_H**2,
}
#: The SI unit of each accelerometer term: N as a noise density in m/s^2/sqrt(Hz)
#: (= m/s/sqrt(s), Kalibr's ``accelerometer_noise_density``), K in m/s^3/sqrt(Hz)
#: (= m/s^2.5, Kalibr's ``accelerometer_random_walk``).
ACCEL_TERM_SI_UNIT: dict[str, str] = {"Q": "m/s", "N": "m/s^2/sqrt(Hz)", "B": "m/s^2",
                                      "K": "m/s^3/sqrt(Hz)", "R": "m/s^3"}

_ACCEL_ALIASES: dict[str, str] = {
    "m/s^2": "m/s^2", "m/s2": "m/s^2", "m/s**2": "m/s^2", "m/s/s": "m/s^2", "mps2": "m/s^2",
    "m/s²": "m/s^2", "ms2": "m/s^2", "ms^-2": "m/s^2", "m s^-2": "m/s^2", "m_s2": "m/s^2",
    "g": "g", "g0": "g", "mg": "mg", "milli-g": "mg", "ug": "ug", "µg": "ug", "μg": "ug",
    "micro-g": "ug", "microg": "ug",
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


def parse_accel_unit(unit: str, name: str = "units") -> str:
    """Return the canonical spelling of a specific-force unit (``m/s^2``, ``g``, ``mg``,
    ``ug``; aliases such as ``mps2``, ``m/s2``, ``µg``), case-insensitively except that
    ``mg``/``ug`` are never read as grams.

    Examples
    --------
    >>> parse_accel_unit("mps2"), parse_accel_unit("µg")
    ('m/s^2', 'ug')
    """
    key = str(unit).strip().lower()
    if key not in _ACCEL_ALIASES:
        raise DataError(f"{name} must be one of {', '.join(ACCEL_UNITS)}, got {unit!r}")
    return _ACCEL_ALIASES[key]


def parse_sensor_unit(unit: str, name: str = "units") -> str:
    """A rate unit (:func:`parse_rate_unit`) or a specific-force unit
    (:func:`parse_accel_unit`), canonically spelt.

    Examples
    --------
    >>> parse_sensor_unit("dps"), parse_sensor_unit("G")
    ('deg/s', 'g')
    """
    key = str(unit).strip().lower()
    if key in _ALIASES:
        return _ALIASES[key]
    if key in _ACCEL_ALIASES:
        return _ACCEL_ALIASES[key]
    raise DataError(f"{name} must be a rate unit ({', '.join(RATE_UNITS)}) or a specific-force "
                    f"unit ({', '.join(ACCEL_UNITS)}), got {unit!r}")


def quantity_of(unit: str) -> str:
    """``"rate"`` for an angular-rate unit, ``"accel"`` for a specific-force unit.

    Examples
    --------
    >>> quantity_of("deg/s"), quantity_of("mg")
    ('rate', 'accel')
    """
    return "accel" if parse_sensor_unit(unit) in _TO_MPS2 else "rate"


def base_unit_factor(unit: str) -> float:
    """Multiply a value in ``unit`` by this to get the unit the terms are computed from:
    deg/h for a rate (:func:`to_deg_per_hour_factor`), m/s^2 for a specific force.

    Examples
    --------
    >>> base_unit_factor("deg/s"), base_unit_factor("mg")
    (3600.0, 0.00980665)
    """
    canonical = parse_sensor_unit(unit)
    return _TO_MPS2[canonical] if canonical in _TO_MPS2 else _TO_DEG_PER_HOUR[canonical]


def si_unit(unit: str) -> str:
    """The SI unit of a sensor unit's quantity: rad/s or m/s^2.

    Examples
    --------
    >>> si_unit("deg/h"), si_unit("g")
    ('rad/s', 'm/s^2')
    """
    return "m/s^2" if quantity_of(unit) == "accel" else "rad/s"


def convert_sensor(x: np.ndarray | float, from_unit: str, to_unit: str) -> np.ndarray | float:
    """Convert a rate or a specific force between units of the same quantity.

    Examples
    --------
    >>> round(float(convert_sensor(1.0, "g", "m/s^2")), 5)
    9.80665
    """
    if quantity_of(from_unit) != quantity_of(to_unit):
        raise DataError(f"cannot convert {from_unit!r} to {to_unit!r}: one is an angular rate "
                        "and the other a specific force")
    factor = base_unit_factor(from_unit) / base_unit_factor(to_unit)
    return x * factor if isinstance(x, np.ndarray) else float(x) * factor


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


def term_in_units(name: str, value: float, units: str, quantity: str = "rate") -> float:
    """An IEEE-952 term given in fogts' engineering units (degree units for a gyro,
    :data:`ACCEL_TERM_UNIT` for an accelerometer), in ``units`` (``"deg"`` or ``"si"``).

    Examples
    --------
    >>> f"{term_in_units('N', 0.15, 'si'):.4e}"   # 0.15 deg/sqrt(h) in rad/s/sqrt(Hz)
    '4.3633e-05'
    >>> f"{term_in_units('N', 0.06, 'si', 'accel'):.4e}"   # 0.06 m/s/sqrt(h) in m/s^2/sqrt(Hz)
    '1.0000e-03'
    """
    if _output_units(units) != "si":
        return float(value)
    table = ACCEL_TERM_SI_FACTOR if _quantity(quantity) == "accel" else TERM_SI_FACTOR
    return float(value) * table[name]


def term_unit(name: str, units: str, quantity: str = "rate") -> str:
    """The unit of term ``name`` in ``units`` (``"deg"`` or ``"si"``) for a ``quantity``
    (``"rate"``: a gyro; ``"accel"``: an accelerometer).

    Examples
    --------
    >>> term_unit("K", "deg"), term_unit("K", "si")
    ('deg/h^1.5', 'rad/s^2/sqrt(Hz)')
    >>> term_unit("N", "deg", "accel"), term_unit("B", "deg", "accel")
    ('m/s/sqrt(h)', 'ug')
    """
    si = _output_units(units) == "si"
    if _quantity(quantity) == "accel":
        return (ACCEL_TERM_SI_UNIT if si else ACCEL_TERM_UNIT)[name]
    return (TERM_SI_UNIT if si else TERM_DEG_UNIT)[name]


def _quantity(quantity: str) -> str:
    if quantity not in QUANTITIES:
        raise DataError(f"quantity must be one of {', '.join(QUANTITIES)}; got {quantity!r}")
    return quantity


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
