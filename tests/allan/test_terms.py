"""Tests for fogts.allan.terms: the IEEE-952 term table, C_n conversions, term names."""

from __future__ import annotations

import math

import numpy as np
import pytest

from fogts.allan.terms import (
    B_PLATEAU,
    TERM_SLOPE,
    TERMS,
    TO_SECONDS,
    c_from_terms,
    from_seconds,
    parse_terms,
    terms_from_c,
)
from fogts.errors import DataError

#: Published coefficients C_n and the terms quoted beside them (DESIGN.md "Definitions").
PAPER_C = {-2: 1.1754e-5, -1: 1.0228e-2, 0: 3.835e-3, 1: 1.196e-3, 2: 1.827e-4}
PAPER_TERMS = {"N": 1.704e-4, "B": 5.776e-3, "K": 0.1243, "R": 0.9303, "Q": 6.786e-6}


# --------------------------------------------------------------------------- the table


def test_the_table_holds_slopes_units_and_read_off_factors() -> None:
    """IEEE 952 Annex C: slopes n/2, hour conversions, and read-off taus at which a term's
    own Allan-deviation line equals its coefficient in deg/h-and-seconds units."""
    assert TERM_SLOPE == {"Q": -1.0, "N": -0.5, "B": 0.0, "K": 0.5, "R": 1.0}
    assert TO_SECONDS == pytest.approx({"Q": 1.0, "N": 60.0, "B": 1.0, "K": 1 / 60,
                                        "R": 1 / 3600}, rel=1e-15)
    for name in ("N", "K"):
        info = TERMS[name]
        assert info.allan_root * info.readoff_tau_s ** info.slope == pytest.approx(1.0)
        assert from_seconds(name, info.seconds_factor) == pytest.approx(1.0, rel=1e-15)
    assert all(math.isnan(TERMS[n].readoff_tau_s) for n in ("Q", "B", "R"))
    assert TERMS["B"].allan_root == B_PLATEAU == pytest.approx(0.664)
    assert TERMS["Q"].description == "quantization"


# --------------------------------------------------------------------------- conversions


def test_published_coefficients_convert() -> None:
    """DESIGN.md: the published C_n give the quoted N, B, K, R, Q.

    With the DESIGN.md factors, B, K and Q agree with the published values at their
    quoted 4 significant digits.  R = 3600 sqrt(2) * 1.827e-4 = 0.93016 -> '0.9302' vs the
    quoted 0.9303: C_2 is quoted to 4 digits only, and the quoted R maps back onto it
    (0.9303 -> C_2 = 1.8273e-4 -> '1.827e-04').  N = 1.0228e-2 / 60 = 1.70467e-4 -> '1.705e-04'
    vs the quoted 1.704e-4: no consistent factor reproduces it (the quoted N maps back to
    C_-1 = 1.0224e-2, not 1.0228e-2), so the paper's N carries a 4e-4 relative slip; we
    check it at that tolerance.
    """
    t = terms_from_c(PAPER_C)
    for name in ("B", "K", "Q"):
        assert f"{t[name]:.4g}" == f"{PAPER_TERMS[name]:.4g}", name
    assert t["R"] == pytest.approx(PAPER_TERMS["R"], rel=2e-4)
    assert f"{c_from_terms({'R': PAPER_TERMS['R']})[2]:.4g}" == f"{PAPER_C[2]:.4g}"
    assert t["N"] == pytest.approx(PAPER_TERMS["N"], rel=5e-4)
    assert c_from_terms({"N": PAPER_TERMS["N"]})[-1] == pytest.approx(1.0224e-2, rel=1e-12)
    # every other quoted term maps back onto its quoted C_n
    back = c_from_terms({k: v for k, v in PAPER_TERMS.items() if k != "N"})
    for power in (-2, 0, 1, 2):
        assert f"{back[power]:.4g}" == f"{PAPER_C[power]:.4g}"


def test_conversion_round_trip_and_names() -> None:
    t = terms_from_c({"N": 0.6, "K": 0.01})
    assert t == pytest.approx({"N": 0.01, "K": 0.6 * math.sqrt(3) * 0.01 / 0.6 * 60})
    assert c_from_terms(terms_from_c(PAPER_C)) == pytest.approx(PAPER_C, rel=1e-14)


@pytest.mark.parametrize(("func", "arg", "match"), [
    (terms_from_c, {3: 1.0}, "coefficient key must be a term name"),
    (terms_from_c, {"X": 1.0}, "coefficient key must be a term name"),
    (terms_from_c, {True: 1.0}, "coefficient key must be a term name"),
    (terms_from_c, {-1: -1.0}, r"C coefficient -1 must be a finite number >= 0, got -1.0"),
    (terms_from_c, {"N": float("nan")}, "must be a finite number >= 0"),
    (c_from_terms, {"K": -2.0}, r"term 'K' must be a finite number >= 0, got -2.0"),
])
def test_conversion_errors(func: object, arg: dict, match: str) -> None:
    with pytest.raises(DataError, match=match):
        func(arg)  # type: ignore[operator]


# --------------------------------------------------------------------------- names


def test_parse_terms() -> None:
    assert parse_terms(" r, q ,N") == ("Q", "N", "R")
    assert parse_terms(("K",)) == ("K",)


# --------------------------------------------------------------------------- accelerometers


def test_accelerometer_table_shares_the_gyro_laws() -> None:
    """Same powers and Allan constants as IEEE 952; only names, units and the hour scaling
    differ (the coefficient is in m/s^2 and seconds)."""
    from fogts.allan.terms import ACCEL_TERMS, TERMS

    for name, row in ACCEL_TERMS.items():
        assert (row.power, row.allan_root) == (TERMS[name].power, TERMS[name].allan_root)
    # N = 60 C_-1 (m/s/sqrt(s) -> m/s/sqrt(h)); B = C_0 / 0.664 / 9.80665e-6 (ug);
    # K = 60^3 sqrt(3) C_1 (m/s^2.5 -> m/s/h^1.5); R = 60^4 sqrt(2) C_2; Q = C_-2 / sqrt(3)
    c = {-2: 1e-4, -1: 1e-3, 0: 2e-4, 1: 5e-6, 2: 1e-8}
    t = terms_from_c(c, "accel")
    assert t["N"] == pytest.approx(0.06, rel=1e-14)
    assert t["B"] == pytest.approx(2e-4 / 0.664 / 9.80665e-6, rel=1e-14)
    assert t["K"] == pytest.approx(216_000 * math.sqrt(3) * 5e-6, rel=1e-14)
    assert t["R"] == pytest.approx(60**4 * math.sqrt(2) * 1e-8, rel=1e-14)
    assert t["Q"] == pytest.approx(1e-4 / math.sqrt(3), rel=1e-14)
    back = c_from_terms(t, "accel")
    assert all(back[k] == pytest.approx(v, rel=1e-14) for k, v in c.items())
    assert ACCEL_TERMS["N"].description == "velocity random walk"
    assert ACCEL_TERMS["K"].description == "acceleration random walk"


def test_unknown_quantity() -> None:
    from fogts.allan.terms import term_rows

    with pytest.raises(DataError, match="quantity must be one of rate, accel; got 'mag'"):
        term_rows("mag")


@pytest.mark.parametrize("kind", ["adev", "oadev", "mdev", "hdev", "ohdev", "totdev"])
def test_flicker_plateau_factors_match_simulated_flicker(kind: str) -> None:
    """Flicker (bias-instability) noise of B = 1 deg/h, 12 h at 10 Hz (seed 5): each
    estimator's deviation at tau = 1 .. 30 s (m >= 10, where MVAR's ratio has reached its
    large-m limit to 0.2 %) is FLICKER_PLATEAU[kind].  Tolerance: three times the largest
    standard error of ln(dev) among those points, 1/sqrt(2 edf) (chi-squared, NIST SP1065
    sec. 5.3); the four points are correlated, so their mean is held to the single worst
    point's scatter.  The 0.664 of the Allan variance is outside it for mdev (-19 %) and
    hdev/ohdev (-10 %)."""
    import warnings

    from fogts.allan import allan_deviation
    from fogts.allan.terms import B_PLATEAU, flicker_plateau
    from fogts.simulate.gyro import NoiseSpec, simulate_gyro

    run = simulate_gyro(NoiseSpec.from_any({"B": 1.0}), fs_hz=10, duration_s=12 * 3600, rng=5)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        res = allan_deviation(run, kind=kind, taus=[1.0, 3.0, 10.0, 30.0])
    tol = 3 * float(np.max(1 / np.sqrt(2 * res.edf)))
    log_ratio = np.log(res.dev / flicker_plateau(kind))
    assert abs(float(np.mean(log_ratio))) < tol
    if kind in ("mdev", "hdev", "ohdev"):
        assert abs(float(np.mean(np.log(res.dev / B_PLATEAU)))) > tol
