"""Does a four-position record support an azimuth?  The Earth-rate check (amplitude against
Omega cos L, with its standard uncertainty) and the no-usable-azimuth rule."""

from __future__ import annotations

import math

import numpy as np
import pytest

from fogts.startup.northfind import four_position
from fogts.startup.northfind_checks import (
    AZIMUTH_Z95,
    SCALE_TOLERANCE,
    amplitude_stderr,
    azimuth_usable,
    scale_consistent,
)
from fogts.units import earth_rate_component

LAT = 45.0
PSI = 30.0


def _rates(*, lat: float = LAT, scale: float = 1.0, noise: float = 0.3, n: int = 60,
           seed: int = 0, bias: float = 1.2) -> dict[int, np.ndarray]:
    """deg/h samples of a gyro at ``lat`` with scale factor ``scale``."""
    om = earth_rate_component(lat, axis="north")
    rng = np.random.default_rng(seed)
    return {k: scale * om * math.cos(math.radians(PSI + k)) + bias
            + noise * rng.standard_normal(n) for k in (0, 90, 180, 270)}


def test_amplitude_stderr_matches_the_scatter_of_the_amplitude() -> None:
    # 600 records with 1 deg/h white noise, 60 samples a position: the predicted
    # u(A) = sigma_m / sqrt(2) must match the spread of A.  The sample standard deviation of
    # 600 values is within 3 * 1/sqrt(2 * 600) = 9 % of the truth, so 12 % is a bound that
    # a correct formula passes and a factor sqrt(2) error fails.
    # Equal position times switch the drift term off (a slope fitted to white noise would
    # add its conservative share), leaving the standard error of the means alone.
    amps, predicted = [], []
    same_time = dict.fromkeys((0, 90, 180, 270), 0.0)
    for seed in range(600):
        res = four_position(_rates(noise=1.0, seed=seed), latitude_deg=LAT,
                            position_time_s=same_time)
        amps.append(res.amplitude_deg_h)
        predicted.append(res.amplitude_stderr_deg_h)
    assert np.std(amps, ddof=1) == pytest.approx(np.median(predicted), rel=0.12)
    assert np.median(predicted) == pytest.approx(1.0 / math.sqrt(60) / math.sqrt(2), rel=0.05)


def test_amplitude_stderr_adds_bias_variation_and_radial_drift() -> None:
    assert amplitude_stderr(0.3, 0.4, 0.0) == pytest.approx(math.sqrt(0.125))
    assert amplitude_stderr(0.0, 0.0, -0.2) == pytest.approx(0.2)
    rates = _rates(noise=0.0)
    t = np.arange(240.0)
    for i, k in enumerate((0, 90, 180, 270)):
        rates[k] = rates[k] + 0.002 * t[60 * i: 60 * (i + 1)]     # linear bias drift
    res = four_position(rates, latitude_deg=LAT)
    # position centres 30, 90, 150, 210 s: the drift moves (dx, dy)/2 by
    # r (t0 - t180)/2 = -0.12 and r (t270 - t90)/2 = 0.12 deg/h; its radial part is taken
    # along the measured azimuth (the true one is unknown to the estimator)
    psi = math.radians(res.azimuth_deg)
    radial = -0.12 * math.cos(psi) + 0.12 * math.sin(psi)
    assert res.amplitude_stderr_deg_h == pytest.approx(abs(radial), rel=1e-9)
    measured = res.amplitude_deg_h - earth_rate_component(LAT, axis="north")
    assert measured == pytest.approx(radial, rel=0.05)   # first order: the true error


def test_a_healthy_record_is_consistent_and_usable() -> None:
    res = four_position(_rates(), latitude_deg=LAT)
    assert res.scale_consistent and res.azimuth_usable and res.exit_code == 0
    assert res.scale_warning is None
    text = res.summary()
    assert f"azimuth ψ = {res.azimuth_deg:.4f}° ± {res.sigma_deg:.4f}°" in text
    assert "Earth-rate check: ratio" in text and "is consistent with 1" in text
    d = res.to_dict()
    assert d["scale_consistent"] is True and d["azimuth_usable"] is True
    assert d["scale_warning"] is None
    assert d["scale_check_limits"] == pytest.approx([1 / math.sqrt(2), math.sqrt(2)])
    assert d["scale_check_stderr"] == pytest.approx(
        d["amplitude_stderr_deg_h"] / d["earth_rate_h_deg_h"])


@pytest.mark.parametrize(("declared", "factor", "cause", "unit_hint"), [
    ("deg/s", 1.0, "a ratio of about 3600 is deg/s vs deg/h", "deg/h or arcsec/s, not deg/s"),
    ("deg/h", 3600.0, "a ratio of about 0.0002778 is deg/s vs deg/h", "deg/s, not deg/h"),
    ("rad/s", 3600.0, "a ratio of about 57.3 is rad vs deg", "deg/s, not rad/s"),
    ("deg/s", 3600.0 * 180 / math.pi, "a ratio of about 0.01745 is rad vs deg",
     "rad/s, not deg/s"),
])
def test_a_wrong_rate_unit_is_named(declared: str, factor: float, cause: str,
                                    unit_hint: str) -> None:
    # the samples are in the unit of ``factor`` deg/h (deg/h / factor), declared ``declared``
    rates = {k: v / factor for k, v in _rates().items()}
    res = four_position(rates, latitude_deg=LAT, units=declared)
    assert not res.scale_consistent and res.exit_code == 1
    assert res.scale_warning is not None
    assert cause in res.scale_warning and unit_hint in res.scale_warning
    assert "(check units)" in res.scale_warning
    assert "Earth-rate check failed" in res.summary()
    assert res.to_dict()["scale_warning"] == res.scale_warning


def test_a_unit_fogts_does_not_know_is_named_by_its_factor() -> None:
    rates = {k: v * math.pi / 180 for k, v in _rates().items()}   # rad/h, declared deg/h
    res = four_position(rates, latitude_deg=LAT)
    assert res.scale_warning is not None
    assert "rad vs deg: the rates are probably in a unit 57.3 times larger than deg/h" \
        in res.scale_warning


def test_a_wrong_latitude_is_named_with_the_latitude_that_fits() -> None:
    res = four_position(_rates(), latitude_deg=89.0)
    assert not res.scale_consistent and res.exit_code == 1
    assert res.scale_warning is not None
    assert "it matches the horizontal Earth rate at latitude ±45." in res.scale_warning
    assert "check latitude_deg (or units, or the gyro's scale factor)" in res.scale_warning


def test_an_amplitude_above_the_full_earth_rate_blames_units_or_scale() -> None:
    res = four_position(_rates(lat=0.0, scale=3.0, noise=0.01), latitude_deg=0.0)
    assert res.scale_warning is not None
    assert "no latitude explains it: check units or the gyro's scale factor" in res.scale_warning


def test_scale_factor_tolerance_and_its_uncertainty() -> None:
    # within the factor-sqrt(2) band: a scale error of 1.3 is tolerated
    assert four_position(_rates(scale=1.3, noise=0.01), latitude_deg=LAT).scale_consistent
    # outside it with a tiny uncertainty: flagged
    assert not four_position(_rates(scale=1.6, noise=0.01), latitude_deg=LAT).scale_consistent
    # the band edges and the 3-sigma margin
    assert scale_consistent(SCALE_TOLERANCE * 1.001, 0.0) is False
    assert scale_consistent(1.6, 0.07) is True        # 1.6 - 3 * 0.07 = 1.39 < sqrt(2)
    assert scale_consistent(1.6, 0.06) is False
    assert scale_consistent(0.5, 0.07) is True        # 0.5 + 0.21 = 0.71 > 1/sqrt(2)
    assert scale_consistent(0.5, 0.06) is False
    assert scale_consistent(1.0, math.nan) is True


def test_no_usable_azimuth_when_the_interval_spans_a_half_circle() -> None:
    # 120 deg/h of white noise, 60 samples a position, against Omega cos L = 10.6 deg/h:
    # the ARW term alone is 120/sqrt(60)/(sqrt(2) * 10.6) rad = 59 deg
    res = four_position(_rates(noise=120.0, seed=3), latitude_deg=LAT)
    assert AZIMUTH_Z95 * res.sigma_deg >= 90.0
    assert not res.azimuth_usable and res.exit_code == 1
    text = res.summary()
    assert "no usable azimuth: 1σ = " in text and "azimuth ψ =" not in text
    assert "spans a half circle or more" in text
    d = res.to_dict()
    assert d["azimuth_usable"] is False and "azimuth_deg" in d
    assert res._view_headline().startswith("no usable azimuth")


def test_the_half_circle_rule() -> None:
    limit = 90.0 / AZIMUTH_Z95                        # 45.9 deg
    assert azimuth_usable(limit * 0.999) and not azimuth_usable(limit * 1.001)
    assert not azimuth_usable(math.nan) and not azimuth_usable(math.inf)
