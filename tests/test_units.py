"""Tests for fogts.units."""

from __future__ import annotations

import math

import numpy as np
import pytest

from fogts.errors import DataError
from fogts.units import (
    EARTH_RATE_RAD_S,
    convert_rate,
    earth_rate_component,
    parse_rate_unit,
    to_deg_per_hour_factor,
)


def test_conversion_factors() -> None:
    assert to_deg_per_hour_factor("deg/h") == 1.0
    assert to_deg_per_hour_factor("deg/s") == 3600.0
    assert to_deg_per_hour_factor("arcsec/s") == 1.0
    assert to_deg_per_hour_factor("rad/s") == pytest.approx(206264.80624709636)


def test_convert_roundtrip_array() -> None:
    x = np.array([1.0, -2.0, 3.5])
    back = convert_rate(convert_rate(x, "deg/s", "rad/s"), "rad/s", "deg/s")
    np.testing.assert_allclose(back, x, rtol=1e-15)
    assert convert_rate(1.0, "rad/s", "deg/s") == pytest.approx(180 / math.pi)


def test_earth_rate() -> None:
    # 7.292115e-5 rad/s = 15.0410686 deg/h; at 45 deg the vertical component is / sqrt(2)
    assert earth_rate_component(90) == pytest.approx(15.041068, rel=1e-7)
    assert earth_rate_component(45) == pytest.approx(15.041068 / math.sqrt(2), rel=1e-7)
    assert earth_rate_component(0, axis="north") == pytest.approx(15.041068, rel=1e-7)
    assert earth_rate_component(30, unit="rad/s") == pytest.approx(EARTH_RATE_RAD_S / 2)


def test_unit_aliases() -> None:
    assert parse_rate_unit(" DPH ") == "deg/h"
    assert parse_rate_unit("rad/sec") == "rad/s"


def test_bad_unit() -> None:
    with pytest.raises(DataError, match="units must be one of deg/h, deg/s, rad/s, arcsec/s, "
                                        "got 'mph'"):
        parse_rate_unit("mph")


@pytest.mark.parametrize("lat", [91.0, -90.5, float("nan")])
def test_bad_latitude(lat: float) -> None:
    with pytest.raises(DataError, match=r"latitude_deg must be in \[-90, 90\]"):
        earth_rate_component(lat)


def test_bad_axis() -> None:
    with pytest.raises(DataError, match="axis must be one of vertical, north; got 'east'"):
        earth_rate_component(10.0, axis="east")  # type: ignore[arg-type]


# --------------------------------------------------------------------------- accelerometers

def test_accelerometer_si_factors_from_first_principles() -> None:
    """Each factor rebuilt from its definition: an hour is 3600 s, one g is standard gravity
    9.80665 m/s^2 exactly (3rd CGPM 1901), so 1 m/s/sqrt(h) = 1/60 m/s/sqrt(s), 1 ug =
    9.80665e-6 m/s^2, 1 m/s/h^1.5 = 1/216000 m/s^2.5, 1 m/s/h^2 = 1/12960000 m/s^3."""
    from fogts.units import ACCEL_TERM_SI_FACTOR, STANDARD_GRAVITY_MPS2, term_in_units

    assert STANDARD_GRAVITY_MPS2 == 9.80665
    expected = {"Q": 1.0, "N": 1 / 60, "B": 9.80665e-6, "K": 1 / 216_000, "R": 1 / 12_960_000}
    for name, value in expected.items():
        assert ACCEL_TERM_SI_FACTOR[name] == pytest.approx(value, rel=1e-15)
        assert term_in_units(name, 2.0, "si", "accel") == pytest.approx(2 * value, rel=1e-15)
        assert term_in_units(name, 2.0, "deg", "accel") == 2.0


def test_accelerometer_units_and_conversions() -> None:
    from fogts.units import base_unit_factor, convert_sensor, parse_sensor_unit, quantity_of

    assert [parse_sensor_unit(u) for u in ("mps2", "m/s²", "G", "mg", "µg", "dps")] == \
        ["m/s^2", "m/s^2", "g", "mg", "ug", "deg/s"]
    assert quantity_of("ug") == "accel" and quantity_of("rad/s") == "rate"
    assert base_unit_factor("mg") == pytest.approx(9.80665e-3, rel=1e-15)
    assert convert_sensor(1000.0, "mg", "g") == pytest.approx(1.0, rel=1e-15)
    assert convert_sensor(1.0, "g", "ug") == pytest.approx(1e6, rel=1e-15)


def test_accelerometer_unit_errors() -> None:
    from fogts.units import convert_sensor, parse_accel_unit, parse_sensor_unit, term_unit

    with pytest.raises(DataError, match=r"accel_units must be one of m/s\^2, g, mg, ug, got "
                                        "'kg'"):
        parse_accel_unit("kg", "accel_units")
    with pytest.raises(DataError, match=r"units must be a rate unit \(deg/h, .*\) or a "
                                        r"specific-force unit \(m/s\^2, .*\), got 'psi'"):
        parse_sensor_unit("psi")
    with pytest.raises(DataError, match="cannot convert 'g' to 'rad/s'"):
        convert_sensor(1.0, "g", "rad/s")
    with pytest.raises(DataError, match="quantity must be one of rate, accel; got 'mag'"):
        term_unit("N", "si", "mag")
