"""B, the flicker floor, is measured only where the data reach a floor or show it at two
trusted points (NoiseTerm.no_floor, fogts.allan.noise_selection.floorless_flicker): a B
that rests on one trusted point where the curve is still falling is an upper limit,
whatever its z, as the curve read-out beside it declines to read B there."""

from __future__ import annotations

import warnings

import numpy as np
import pytest

import fogts
from fogts.allan.noise_model import Z_MEASURED
from fogts.errors import UnidentifiableTermWarning
from tests.allan.noise_cases import avar, make_result, quiet_fit
from tests.conftest import shared_path

#: N = 2 deg/sqrt(h) and B = 400 deg/h on 8 octave taus from 0.01 s (a 5 s record at
#: 100 Hz): B's line is the largest from 0.32 s on; the exact curve still falls there.
TAU = 0.01 * 2.0 ** np.arange(8)
EXACT = np.sqrt(avar(TAU, N=2.0, B=400.0))
#: B dominates at 0.32, 0.64 and 1.28 s; only the first has EDF >= 10.
ONE_TRUSTED = np.array([4000.0, 2000.0, 1000.0, 500.0, 250.0, 60.0, 9.0, 4.0])
#: The same taus, every point trusted.
ALL_TRUSTED = np.array([4000.0, 2000.0, 1000.0, 500.0, 250.0, 120.0, 60.0, 30.0])


def test_b_at_one_trusted_point_on_a_falling_curve_is_an_upper_limit() -> None:
    with pytest.warns(UnidentifiableTermWarning, match=r"noise term B \(bias instability\) is "
                      r"fitted with z\(C²\) = 2\.\d\d, but it dominates the fitted sigma\^2 at "
                      r"1 point with EDF >= 10 and the curve is still falling at its last "
                      r"trusted tau \(0\.32 s\): .* treat its value as an upper limit"):
        model = fogts.fit_noise(make_result(TAU, EXACT, edf=ONE_TRUSTED))
    b = model["B"]
    # the fit finds the true B, significantly (z >= 2): only the floor rule makes it a limit
    assert b.status == "fitted" and b.z_score >= Z_MEASURED and b.low_edf_taus == ()
    assert b.value == pytest.approx(400.0, rel=1e-3)
    assert b.is_limit
    assert b.no_floor == "no floor: the curve is still falling at its last trusted tau (0.32 s)"
    assert b.limit_reason == b.no_floor
    d = model.to_dict()["terms"]["B"]
    assert d["measured"] is False and d["limit_reason"] == b.no_floor
    text = " ".join(model.term_table().to_text().split())
    assert f"< {model.upper_limit('B'):.3g} (95 % upper limit; no floor" in text
    assert "B: only a limit whatever its z, because the curve has no floor" in text
    assert not model["N"].is_limit


def test_b_at_several_trusted_points_stays_measured_on_a_falling_curve() -> None:
    """The last point lowered by 30 %: the read-out finds no floor, but B dominates at three
    trusted points, whose bend measures it."""
    dev = EXACT.copy()
    dev[-1] *= 0.7
    model = quiet_fit(make_result(TAU, dev, edf=ALL_TRUSTED))
    assert any(name == "B" and "no floor" in note for name, note in model.readoff.notes)
    b = model["B"]
    assert not b.is_limit and b.no_floor == "" and b.limit_reason == ""


def test_b_on_a_curve_with_a_floor_stays_measured() -> None:
    model = quiet_fit(make_result(TAU, EXACT, edf=ALL_TRUSTED))
    assert not any(name == "B" for name, _ in model.readoff.notes)
    assert not model["B"].is_limit and model["B"].no_floor == ""


def _adis_x(seconds: float | None, run: int = 1) -> fogts.AllanResult:
    data = np.load(shared_path("imu", f"adis_16405_imu{run}_gyro.npz"))
    rate = data["gyro_deg_s"][:, 0]
    fs = float(data["fs_hz"])
    if seconds is not None:
        rate = rate[: int(seconds * fs)]
    return fogts.allan_deviation(rate, fs_hz=fs, units="deg/s")


def test_the_first_5_s_of_adis_run_1_bound_b_instead_of_measuring_it() -> None:
    """The audit's case: 5 s "measured" B = 424 +- 88 deg/h (z = 2.4), the whole 2.8 h
    record 33.7 +- 2.8; now B is a limit, which the whole record's value satisfies."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        short = fogts.fit_noise(_adis_x(5.0))
        whole = fogts.fit_noise(_adis_x(None))
    b, full = short["B"], whole["B"]
    assert b.z_score >= Z_MEASURED and b.is_limit and b.no_floor.startswith("no floor")
    assert not full.is_limit and full.value < short.upper_limit("B")
    assert abs(b.value - full.value) > 3 * b.stderr   # the 5 s value was wrong, not scattered


def test_adis_run_3_x_keeps_its_b_where_its_last_low_edf_points_fall() -> None:
    """The read-out finds no floor (the points at 1311 and 2621 s, EDF 9 and 4, lie below the
    minimum's interval), but B dominates at five trusted points and stays measured, near the
    other runs' 27-45 deg/h."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        model = fogts.fit_noise(_adis_x(None, run=3))
    assert any(name == "B" and "no floor" in note for name, note in model.readoff.notes)
    b = model["B"]
    assert not b.is_limit and b.no_floor == "" and 27.0 < b.value < 45.0
