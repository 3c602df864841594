"""The curve read-outs of `fogts allan` and `fogts curve` on the recordings where they
contradicted the fit or the points: the minimum's EDF rule said aloud, no floor where the
curve is still falling, B and K read-offs not given where the curve does not support them
and flagged where they lie outside the fit, and the estimator's own flicker plateau."""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

import pytest
from typer.testing import CliRunner

from fogts.cli import app
from tests.conftest import shared_path

runner = CliRunner()


def _json(args: list[Any]) -> tuple[dict[str, Any], str]:
    """The JSON (stdout) and the tables (stderr) of one command."""
    res = runner.invoke(app, [str(a) for a in args] + ["--json", "-"])
    assert res.exit_code == 0, res.stderr
    return json.loads(res.stdout), res.stderr


def test_the_minimum_says_it_skipped_lower_low_edf_points() -> None:
    """ADIS16405 run 1, X: the minimum 0.006133 at 655.4 s is the lowest point with EDF >=
    10; 1310.72 s is lower (0.005213) with EDF 7.2, and the read-out says so."""
    doc, text = _json(["allan", shared_path("imu", "adis_16405_imu1_gyro.npz"), "--axis", "0"])
    minimum = doc["curve"]["minimum"]
    assert minimum["tau"] == pytest.approx(655.36)
    assert minimum["min_edf"] == 10.0
    lower = {round(p["tau"], 2): p for p in minimum["lower_points"]}
    assert 1310.72 in lower and lower[1310.72]["edf"] < 10
    assert lower[1310.72]["dev"] < minimum["dev"]
    note = ("the lowest point with EDF >= 10 (lower points at 1311, 2621 s have EDF < 10)")
    assert minimum["note"] == note
    assert note.split(" (")[0] in text and "have EDF < 10)" in text
    # its floor is flat (the points after it come back inside its interval): B is read,
    # inside the fit's interval, so nothing is flagged
    assert minimum["floor_found"] is True
    b = doc["noise_fit"]["readoff"]["B"]
    assert b["supported"] is True and b["fit_check"] is None


@pytest.mark.parametrize(("case", "last_trusted"), [("imar", "655.4"), ("fog", "5.119")])
def test_a_curve_still_falling_has_no_floor_and_no_b_readoff(case: str,
                                                              last_trusted: str) -> None:
    """iMAR (SMAC curve) and the FOG record keep falling past their lowest trusted point:
    no region C, no floor/0.664, no B read-off (they printed 'floor (region C) 327.7 ..
    5243 s' and B = 0.3807 deg/h against the fit's B < 0.129; '5.119 .. 20.47 s' and
    B = 0.08774 against B < 0.0489)."""
    if case == "imar":
        args = ["curve", shared_path("allan_curves", "smac_avar", "imar_av.csv"),
                "--units", "rad/s", "--channel", "Gyro. X"]
    else:
        args = ["allan", shared_path("fog", "fog_0917.txt")]
    doc, text = _json(args)
    curve = doc["curve"]
    why = f"no floor: the curve is still falling at its last trusted tau ({last_trusted} s)"
    assert curve["regions"]["C"] is None and curve["regions"]["D"] is None
    assert curve["minimum"]["floor_found"] is False
    assert curve["minimum"]["bias_instability_floor"] is None
    assert curve["minimum"]["floor"].startswith(why)
    b = doc["noise_fit"]["readoff"]["B"]
    assert b["supported"] is False and b["note"].startswith(why)
    assert f"B not read ({why}" in text and "floor/0.664" not in text
    assert "none" in text.split("floor (region C)")[1].split("\n")[0]


def test_a_b_readoff_above_the_fits_upper_limit_is_flagged() -> None:
    """LN-200, X: the curve is flat within its intervals at the minimum, so B is read
    (0.08207 deg/h), but it lies above the fit's 95 % upper limit (0.0606): said in words,
    with both numbers."""
    doc, text = _json(["curve", shared_path("allan_curves", "smac_avar", "ln200_av.csv"),
                       "--units", "rad/s", "--channel", "Gyro. X"])
    b = doc["noise_fit"]["readoff"]["B"]
    limit = doc["noise"]["B"]["upper_limit_95"]
    assert b["supported"] is True and b["value"] == pytest.approx(0.08207, rel=1e-3)
    assert b["value"] > limit
    check = (f"it lies above the fit's 95 % upper limit B < {limit:.4g} deg/h: the read-off "
             "and the fit disagree")
    assert b["fit_check"] == check
    assert f"B = {b['value']:.4g} deg/h (minimum / 0.664; {check})" in text


def test_a_k_readoff_from_low_edf_points_is_not_read() -> None:
    """ADIS16405 run 4, X, decimated by 100: the segment nearest +1/2 ends on points with
    EDF below 10 (it printed K = 98.74 deg/h^1.5 from them)."""
    doc, text = _json(["allan", shared_path("imu", "adis_16405_imu4_gyro.npz"),
                       "--decimate", "100", "--axis", "0"])
    k = doc["noise_fit"]["readoff"]["K"]
    assert k["supported"] is False and "rests on points with EDF" in k["note"]
    assert k["value"] > 0  # the number stays in the JSON (the contract), marked unsupported
    assert f"K not read ({k['note']})" in text and "K = " not in text.split("slope read-offs")[1]


@pytest.mark.parametrize(("kind", "plateau"), [("oadev", "0.664"), ("mdev", "0.5454"),
                                               ("hdev", "0.5981")])
def test_the_floor_uses_the_estimators_plateau(tmp_path: Path, kind: str,
                                                plateau: str) -> None:
    """Flicker noise of B = 1 deg/h: every estimator's floor read-out gives about 1 (it gave
    0.8075 for mdev and 0.8816 for hdev with 0.664).  Tolerance: the minimum's own 68.3 %
    interval, three times over (the minimum is the lowest of several plateau points, so it
    sits about one half-width low)."""
    out = tmp_path / "flk.csv"
    res = runner.invoke(app, ["simulate", "noise", "-o", str(out), "--fs", "10", "--duration",
                              "6h", "--B", "1", "--seed", "5"])
    assert res.exit_code == 0, res.stderr
    doc, text = _json(["allan", out, "--kind", kind, "--taus", "decade"])
    minimum = doc["curve"]["minimum"]
    assert minimum["plateau_factor"] == pytest.approx(float(plateau), rel=1e-3)
    assert f"floor/{plateau} = " in text
    half = (minimum["ci_high"] - minimum["ci_low"]) / 2 / minimum["dev"]
    assert abs(minimum["bias_instability_floor"] - 1.0) < 3 * half


def test_the_report_prints_the_same_readout_words(tmp_path: Path) -> None:
    """ADIS16405 run 4 in the HTML report (its X axis printed 'K = 101.6 deg/h^1.5 (+1/2
    line at tau = 3 s)' from the 655 -> 1311 s segment, EDF 12.6 and 7.2, against the fit's
    K < 69.8): the report's sentence is the model's own (describe_readoff)."""
    import html
    import re

    out = tmp_path / "r.html"
    res = runner.invoke(app, ["report", str(shared_path("imu", "adis_16405_imu4_gyro.npz")),
                              "--decimate", "100", "-o", str(out)])
    assert res.exit_code in (0, 1), res.stderr
    sentences = [html.unescape(s) for s in re.findall(r"slope read-offs[^<]*", out.read_text())]
    assert len(sentences) == 3
    assert ("K not read (the +1/2 segment 655.4 .. 1311 s rests on points with EDF 12.6 and "
            "7.17, fewer than the 10 a trusted point needs)") in sentences[0]
    assert "K = " not in sentences[0]
    assert "(minimum / 0.664; it lies outside the fit's 68.3 % interval " in sentences[0]


def test_the_b_readoff_and_the_curve_readout_share_the_floor() -> None:
    """iMAR's SMAC curve carries 95.4 % bounds: the B read-off judges the floor with those
    intervals, as the curve read-out does (with 68.3 % intervals from the EDF, the Z axis had
    a floor in the table but 'B not read' in the read-off sentence).  Z has no floor either
    way now: past its minimum (655.4 s, 95.4 % interval 9.8e-7 .. 1.86e-6 rad/s) the curve
    ends two octaves lower, 5.6e-7 at 2621 and 5243 s, below that interval (it read a floor
    while only one of the later points had to lie below)."""
    doc, _ = _json(["curve", shared_path("allan_curves", "smac_avar", "imar_av.csv"),
                    "--units", "rad/s"])
    found = [(a["curve"]["minimum"]["floor_found"], a["noise_fit"]["readoff"]["B"]["supported"])
             for a in doc["axes"]]
    assert found == [(False, False), (False, False), (False, False)]
    z = doc["axes"][2]["curve"]["minimum"]
    assert z["tau"] == pytest.approx(655.36) and z["confidence"] == pytest.approx(0.954)
    assert z["floor"].endswith("the curve ends below the minimum's interval (points at "
                               "2621, 5243 s)")
