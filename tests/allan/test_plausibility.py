"""Tests for fogts.allan.plausibility: N and B against the range real gyros span.

Reference numbers are datasheet figures (quoted where used) and the published Allan curves
in ``../shared/data/allan_curves`` (SMAC-Group/avar and imu_utils), read with the rough
IEEE 952 read-offs N = adev(1 s)/60 and B = min adev/B_PLATEAU (adev in deg/h).
"""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pandas as pd
import pytest

from fogts.allan.plausibility import PlausibilityReport, check_plausibility
from fogts.allan.terms import B_PLATEAU
from fogts.errors import DataError
from fogts.units import RATE_UNITS, convert_rate, to_deg_per_hour_factor
from tests.conftest import shared_path

# What `fogts allan FILE --json -` fits (wls, default terms) on the shared recordings:
# cont_imu1_gyro_x.npz (XSens MTi-G, really rad/s; no unit in the column name, read as deg/h)
CONT_N, CONT_B = 1.089e-05, 5.031e-05
# adis_16405_imu1_gyro.npz, axes X, Y, Z (ADIS16405, deg/s from the `gyro_deg_s` key)
ADIS_NB = ((2.30632462, 33.65707622), (2.45015247, 36.21819559), (2.32374062, 27.21158998))
DPH_PER_RAD_S = to_deg_per_hour_factor("rad/s")
DPH_PER_DEG_S = to_deg_per_hour_factor("deg/s")


# --------------------------------------------------------------------------- rad/s read as deg/h


def test_rad_s_read_as_deg_h_is_implausible_and_suggests_rad_s() -> None:
    """cont_imu1 (rad/s) read as deg/h gives N = 1.09e-5 deg/sqrt(h)."""
    r = check_plausibility(CONT_N, CONT_B, units="deg/h")
    assert r.verdict == "implausible"
    assert r.grades == ()
    assert "rad/s" in r.suggested_units
    rad = r.alternative("rad/s")
    assert rad.factor == pytest.approx(convert_rate(1.0, "rad/s", "deg/h"), rel=1e-15)
    assert rad.N == pytest.approx(convert_rate(CONT_N, "rad/s", "deg/h"), rel=1e-15)
    assert rad.N == pytest.approx(2.2462, abs=1e-4)          # 1.089e-5 * 206264.8
    assert rad.B == pytest.approx(convert_rate(CONT_B, "rad/s", "deg/h"), rel=1e-15)
    assert rad.plausible and "industrial" in rad.grades
    # XSens MTi-G datasheet: rate noise 0.05 deg/s/sqrt(Hz) -> N = 60 x 0.05 = 3 deg/sqrt(h)
    assert rad.N is not None and 3.0 / 2 < rad.N < 3.0 * 2
    # deg/s lands in the tactical grade (N 0.039, B 0.18: an HG4930-like gyro): N and B
    # alone cannot tell a tactical gyro in deg/s from a MEMS in rad/s, so both are offered
    assert r.suggested_units == ("deg/s", "rad/s")
    assert r.alternative("deg/s").grades == ("tactical",)
    assert not r.alternative("arcsec/s").plausible          # 1 arcsec/s = 1 deg/h
    msg = r.message
    assert msg.startswith("N = 1.09e-05 deg/sqrt(h) and B = 5.03e-05 deg/h are below any "
                          "real gyro (even strategic-grade FOG and RLG stay at N >= 3e-05")
    assert "(input read as deg/h)" in msg
    assert "if rad/s: N = 2.25 deg/sqrt(h), B = 10.4 deg/h, typical of an " \
           "industrial/automotive MEMS gyro" in msg
    assert "\n" not in msg


def test_the_message_names_the_units_keyword() -> None:
    """In Python the implausible verdict names read_run's ``units=`` (the command line's
    ``--units``: tests/cli/test_hygiene.py's ``test_cont_imu1_without_units_warns_and_names_rad_s``)."""
    msg = check_plausibility(CONT_N, CONT_B, units="deg/h").message
    assert msg.endswith("; set the rate unit explicitly (units=)")
    assert "--" not in msg


def test_rad_s_read_as_deg_h_on_n_alone() -> None:
    r = check_plausibility(CONT_N, None, units="deg/h")
    assert r.verdict == "implausible"
    assert r.judged_on == ("N",)
    assert "rad/s" in r.suggested_units
    assert r.notes == ("B was not fitted; judged on N alone",)
    assert "B not fitted, judged on N alone" in r.message


# --------------------------------------------------------------------------- ADIS16405


@pytest.mark.parametrize(("n", "b"), [*ADIS_NB, (2.0, 0.007 * 3600)])  # datasheet: 2, 0.007 deg/s
def test_adis16405_in_deg_s_is_plausible_mems(n: float, b: float) -> None:
    r = check_plausibility(n, b, units="deg/s")
    assert r.verdict == "plausible"
    assert "industrial" in r.grades and set(r.grades) <= {"industrial", "consumer"}
    assert r.suggested_units == ()
    assert "MEMS gyro" in r.message


@pytest.mark.parametrize(("n", "b"), ADIS_NB)
def test_adis16405_read_as_deg_h_is_ambiguous(n: float, b: float) -> None:
    """deg/s read as deg/h (factor 3600) turns the ADIS16405 into N 6.4e-4, B 0.0076..0.01:
    inside the navigation grade (HG9900: N <= 0.002, B <= 0.003; Yazdi 1998 inertial grade
    N < 0.001, B < 0.01).  N and B alone cannot call that implausible, so the check says it
    is plausible and flags the other reading (deg/s, industrial MEMS) instead."""
    r = check_plausibility(n / DPH_PER_DEG_S, b / DPH_PER_DEG_S, units="deg/h")
    assert r.verdict == "plausible"
    assert r.grades == ("navigation",)
    assert r.ambiguous
    assert r.also_plausible_units == ("deg/s",)
    assert r.alternative("deg/s").N == pytest.approx(n, rel=1e-12)
    assert "industrial" in r.alternative("deg/s").grades
    assert "; they would also be plausible if the input was deg/s: N = " in r.message


@pytest.mark.parametrize(("n", "b"), ADIS_NB)
def test_adis16405_read_as_rad_s_is_implausible_and_suggests_deg_s(n: float, b: float) -> None:
    factor = DPH_PER_RAD_S / DPH_PER_DEG_S                  # 57.3
    r = check_plausibility(n * factor, b * factor, units="rad/s")
    assert r.verdict == "implausible"
    assert "above any real gyro" in r.message
    assert "deg/s" in r.suggested_units
    assert r.alternative("deg/s").N == pytest.approx(n, rel=1e-12)
    assert r.alternative("deg/s").B == pytest.approx(b, rel=1e-12)


def test_fog_0917_short_record_b_dropped() -> None:
    """fog_0917.txt (undocumented unit, 61 s, read as deg/h): the fit keeps N = 0.00216
    and drops B.  deg/h is plausible (navigation/tactical FOG); deg/s would be too
    (N = 7.76, a noisy MEMS), so the report is ambiguous and judged on N alone."""
    r = check_plausibility(0.00215656, 0.0, units="deg/h")
    assert r.verdict == "plausible"
    assert r.grades == ("navigation", "tactical")
    assert r.judged_on == ("N",)
    assert r.also_plausible_units == ("deg/s",)
    assert not r.alternative("rad/s").plausible
    assert r.message == (
        "N = 0.00216 deg/sqrt(h) (input read as deg/h; B fitted to zero, judged on N alone) "
        "is typical of a navigation-grade FOG or RLG or a tactical-grade gyro; it would also "
        "be plausible if the input was deg/s: N = 7.76 deg/sqrt(h), typical of an "
        "industrial/automotive MEMS gyro")


# --------------------------------------------------------------------------- published curves


def _read_off(tau: np.ndarray, adev: np.ndarray, units: str) -> tuple[float, float]:
    """N = adev(1 s)/60 (log-log interpolation) and B = min adev/B_PLATEAU, adev in deg/h."""
    dph = adev * to_deg_per_hour_factor(units)
    n = math.exp(float(np.interp(0.0, np.log(tau), np.log(dph)))) / 60.0
    return n, float(dph.min()) / B_PLATEAU


# SMAC-Group/avar: units not documented; inferred from the datasheets (as in
# test_allan_noise): ADIS16405 (file key gyro_deg_s in imudata) deg/s; LN-200 ARW 0.04..0.1
# and iMAR FSAS < 0.1 deg/sqrt(h) only in rad/s; NavChip ~0.2 deg/sqrt(h) in rad/s; KVH 1750
# ARW <= 0.012 deg/sqrt(h), B <= 0.1 deg/h only in deg/s.
SMAC = [("adis", "deg/s", {"industrial", "consumer"}),
        ("navchip", "rad/s", {"industrial", "consumer"}),
        ("kvh1750", "deg/s", {"tactical"}),
        ("ln200", "rad/s", {"tactical"}),
        ("imar", "rad/s", {"tactical"})]


def _smac_channels(sensor: str) -> list[tuple[str, np.ndarray, np.ndarray]]:
    df = pd.read_csv(shared_path("allan_curves", "smac_avar", f"{sensor}_av.csv"), comment="#")
    return [(str(ch), g["tau_s"].to_numpy(), g["adev"].to_numpy())
            for ch, g in df.groupby("channel") if str(ch).startswith("Gyro")]


@pytest.mark.parametrize(("sensor", "units", "expected"), SMAC)
def test_smac_curves_are_plausible_in_their_unit(sensor: str, units: str,
                                                  expected: set[str]) -> None:
    channels = _smac_channels(sensor)
    assert len(channels) == 3
    for channel, tau, adev in channels:
        n, b = _read_off(tau, adev, units)
        r = check_plausibility(n, b, units="deg/h")   # n, b are already in deg/h units
        assert r.verdict == "plausible", (sensor, channel, n, b)
        assert expected & set(r.grades), (sensor, channel, r.grades)


@pytest.mark.parametrize("sensor", ["ln200", "imar", "navchip"])
def test_smac_rad_s_curves_read_as_deg_h_are_implausible(sensor: str) -> None:
    """The common mistake on real FOG and MEMS curves: rad/s data read as deg/h."""
    for channel, tau, adev in _smac_channels(sensor):
        n, b = _read_off(tau, adev, "deg/h")
        r = check_plausibility(n, b, units="deg/h")
        assert r.verdict == "implausible", (sensor, channel)
        assert "below any real gyro" in r.reason
        assert "rad/s" in r.suggested_units


IMU_UTILS = ["16448", "A3", "BMI160", "N3", "gx4", "xsens"]


@pytest.mark.parametrize("sensor", IMU_UTILS)
def test_imu_utils_mems_curves_are_plausible(sensor: str) -> None:
    """imu_utils curves are Allan deviations in deg/h of six MEMS IMUs."""
    folder = ("allan_curves", "imu_utils")
    tau = np.loadtxt(shared_path(*folder, f"data_{sensor}_gyr_t.txt"))
    for axis in "xyz":
        adev = np.loadtxt(shared_path(*folder, f"data_{sensor}_gyr_{axis}.txt"))
        n, b = _read_off(tau, adev, "deg/h")
        r = check_plausibility(n, b, units="deg/h")
        assert r.verdict == "plausible", (sensor, axis, n, b)
        assert {"industrial", "consumer"} & set(r.grades), (sensor, axis, r.grades)


def test_imu_utils_n_matches_its_own_gyr_n() -> None:
    """Cross-check of the read-off: imu_utils' gyr_n (rad/s/sqrt(Hz)) x 206265/60 is the
    same N (xsens, x axis: 1.593e-4 -> 0.548 deg/sqrt(h))."""
    folder = ("allan_curves", "imu_utils")
    tau = np.loadtxt(shared_path(*folder, "data_xsens_gyr_t.txt"))
    n, _ = _read_off(tau, np.loadtxt(shared_path(*folder, "data_xsens_gyr_x.txt")), "deg/h")
    assert n == pytest.approx(1.5929650434021210e-04 * DPH_PER_RAD_S / 60, rel=0.02)


def test_no_single_grade() -> None:
    """Both values inside the envelope, but no grade holds both (navigation N, consumer B)."""
    r = check_plausibility(1e-3, 500.0, units="deg/h")
    assert r.verdict == "implausible"
    assert "fit no single gyro grade" in r.reason
    assert r.suggested_units == ()
    assert "no other rate unit (deg/s, rad/s, arcsec/s) makes them plausible" in r.message


# --------------------------------------------------------------------------- the report


def test_alternatives_cover_every_other_unit_with_units_factors() -> None:
    for unit in RATE_UNITS:
        r = check_plausibility(0.01, 0.05, units=unit)
        assert [a.units for a in r.alternatives] == [u for u in RATE_UNITS if u != unit]
        for a in r.alternatives:
            factor = to_deg_per_hour_factor(a.units) / to_deg_per_hour_factor(unit)
            assert a.factor == pytest.approx(factor, rel=1e-15)
            assert a.N == pytest.approx(0.01 * factor, rel=1e-15)
            assert a.B == pytest.approx(0.05 * factor, rel=1e-15)


def test_same_numbers_unit_is_never_suggested() -> None:
    # deg/h and arcsec/s give the same numbers: one is never "the fix" for the other
    r = check_plausibility(CONT_N, CONT_B, units="arcsec/s")
    assert "deg/h" not in r.suggested_units
    assert r.alternative("deg/h").same_scale
    # read as deg/s, the ADIS is plausible in deg/h and arcsec/s alike: one group in the text
    r = check_plausibility(*ADIS_NB[0], units="deg/s")
    assert r.also_plausible_units == ("deg/h", "arcsec/s")
    assert "if the input was deg/h or arcsec/s: N = 0.000641" in r.message


def test_exports_are_json_safe_and_stable() -> None:
    r = check_plausibility(CONT_N, CONT_B, units="deg/h")
    d = r.to_dict()
    text = json.dumps(d, allow_nan=False, sort_keys=True)
    assert text == json.dumps(check_plausibility(CONT_N, CONT_B, units="deg/h").to_dict(),
                              allow_nan=False, sort_keys=True)
    assert list(d) == ["verdict", "units", "N", "B", "judged_on", "grades", "distance",
                       "reason", "message", "suggested_units", "also_plausible_units",
                       "alternatives", "envelope", "notes"]
    assert d["N"] == {"value": CONT_N, "unit": "deg/sqrt(h)", "status": "used"}
    assert d["distance"] is None
    assert [a["units"] for a in d["alternatives"]] == ["deg/s", "rad/s", "arcsec/s"]
    assert d["alternatives"][2]["distance"] is None
    frame = r.to_frame()
    assert list(frame.index) == ["deg/h", "deg/s", "rad/s", "arcsec/s"]
    assert list(frame["role"]) == ["as read", "suggested", "suggested", "same numbers"]
    assert frame.loc["rad/s", "N"] == pytest.approx(CONT_N * DPH_PER_RAD_S)
    s = r.summary()
    assert s.startswith("unit plausibility: implausible")
    assert "suggested units, best first: deg/s, rad/s" in s


def test_report_is_frozen() -> None:
    r = check_plausibility(0.01, 0.05, units="deg/h")
    assert isinstance(r, PlausibilityReport)
    with pytest.raises(AttributeError, match="cannot assign"):
        r.verdict = "implausible"  # type: ignore[misc]


def test_unit_aliases_and_numpy_values() -> None:
    r = check_plausibility(np.float64(2.3), np.float32(33.0), units="DPS")
    assert r.units == "deg/s"
    assert r.verdict == "plausible"
    assert check_plausibility(0, np.int64(5), units="deg/h").judged_on == ("B",)


# --------------------------------------------------------------------------- edge cases


def test_n_none_judges_on_b() -> None:
    r = check_plausibility(None, 0.05, units="deg/h")
    assert r.verdict == "plausible"
    assert r.judged_on == ("B",)
    assert r.N is None and r.N_status == "not fitted"
    assert r.notes == ("N was not fitted; judged on B alone",)
    assert all(a.N is None for a in r.alternatives)
    assert "(input read as deg/h; N not fitted, judged on B alone) is typical of" in r.message


def test_b_zero_judges_on_n() -> None:
    r = check_plausibility(0.012, 0.0, units="deg/h")
    assert r.verdict == "plausible"
    assert r.judged_on == ("N",)
    assert r.B is None and r.B_status == "zero"
    assert r.notes == ("B was fitted to zero; judged on N alone",)
    assert r.to_dict()["B"] == {"value": None, "unit": "deg/h", "status": "zero"}


@pytest.mark.parametrize(("n", "b", "reason"), [
    (None, None, "N was not fitted and B was not fitted"),
    (0.0, 0.0, "N was fitted to zero and B was fitted to zero"),
    (None, 0, "N was not fitted and B was fitted to zero"),
])
def test_nothing_to_judge_is_not_checked(n: float | None, b: float | None,
                                         reason: str) -> None:
    r = check_plausibility(n, b, units="rad/s")
    assert r.verdict == "not checked"
    assert r.reason.startswith(reason)
    assert r.alternatives == () and r.suggested_units == () and not r.ambiguous
    assert r.message.startswith("the unit plausibility was not checked: ")
    assert r.to_frame().shape[0] == 1
    assert r.summary().count("\n") == 1


@pytest.mark.parametrize(("kwargs", "match"), [
    ({"N": -1.0, "B": 1.0}, r"N must be a finite number >= 0 \(deg/sqrt\(h\)\) or None, "
                            r"got -1\.0"),
    ({"N": 1.0, "B": float("nan")}, r"B must be a finite number >= 0 \(deg/h\) or None, "
                                    r"got nan"),
    ({"N": float("inf"), "B": 1.0}, r"N must be a finite number >= 0 .* got inf"),
    ({"N": 1.0, "B": -0.5}, r"B must be a finite number >= 0 .* got -0\.5"),
    ({"N": "0.1", "B": 1.0}, r"N must be a number >= 0 or None, got '0\.1'"),
    ({"N": True, "B": 1.0}, r"N must be a number >= 0 or None, got True"),
])
def test_bad_values_raise(kwargs: dict[str, object], match: str) -> None:
    with pytest.raises(DataError, match=match):
        check_plausibility(kwargs["N"], kwargs["B"], units="deg/h")  # type: ignore[arg-type]


def test_unknown_unit_raises_listing_the_allowed_ones() -> None:
    with pytest.raises(DataError, match=r"units must be one of deg/h, deg/s, rad/s, "
                                        r"arcsec/s, got 'm/s'"):
        check_plausibility(0.01, 0.05, units="m/s")


def test_alternative_lookup_errors() -> None:
    r = check_plausibility(0.01, 0.05, units="deg/h")
    assert r.alternative("RPS").units == "rad/s"
    with pytest.raises(DataError, match=r"units must be a unit other than the one the values "
                                        r"were read in \(deg/h\); alternatives are: deg/s, "
                                        r"rad/s, arcsec/s; got 'deg/h'"):
        r.alternative("deg/h")
    with pytest.raises(DataError, match=r"units must be one of deg/h, deg/s, rad/s, "
                                        r"arcsec/s, got 'furlong/s'"):
        r.alternative("furlong/s")


def test_shared_data_helper_skips_when_absent(tmp_path: Path,
                                              monkeypatch: pytest.MonkeyPatch) -> None:
    """The curve tests go through conftest.shared_path, which skips with a reason."""
    import tests.conftest as conftest

    monkeypatch.setattr(conftest, "SHARED_DATA", tmp_path / "absent")
    with pytest.raises(pytest.skip.Exception, match="reference data not available"):
        conftest.shared_path("allan_curves", "smac_avar", "adis_av.csv")
