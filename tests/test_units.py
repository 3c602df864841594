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
