"""fogts.report.text: JSON-safe conversion, deterministic JSON and the ``fogts info`` text."""

from __future__ import annotations

import numpy as np
import pandas as pd

from fogts.io.reader import read_run
from fogts.report.text import (
    axes_rows,
    info_text,
    json_dumps,
    run_info,
    time_base_verdict,
    to_jsonable,
)


def test_json_helpers_and_info_text() -> None:
    assert to_jsonable({"a": np.float64("nan"), "b": np.arange(2)}) == {"a": None, "b": [0, 1]}
    assert json_dumps({"x": 1.5}, indent=None) == '{"x": 1.5}'
    run = read_run(np.random.default_rng(0).normal(size=100), fs_hz=10.0)
    info = run_info(run)
    assert info["n"] == 100 and "samples     100" in info_text(info)


def _imu_frame() -> pd.DataFrame:
    rng = np.random.default_rng(3)
    n = 2000
    return pd.DataFrame({"time": np.arange(n) / 100.0, "gyro_x": rng.normal(size=n),
                         "acc_x": 0.01 * rng.normal(size=n), "acc_y": 0.01 * rng.normal(size=n),
                         "acc_z": 1.0 + 0.01 * rng.normal(size=n)})


def test_accelerometer_axes_are_not_listed_as_rate_axes() -> None:
    """A gyro-and-accelerometer file (as CH104's gyroReading/accReading): the accelerometer
    axes are listed with their own unit (g from the gravity magnitude, |mean| = 1), not
    under "rate axes" in the assumed deg/h."""
    run = read_run(_imu_frame())
    assert run.unit_of("acc_z") == "g"
    rows = axes_rows(run_info(run), run.accel_units_source)
    assert rows == [("rate axes", "gyro_x  [deg/h]"),
                    ("accel axes", "acc_x, acc_y, acc_z  [g] (unit from gravity magnitude)")]
    text = info_text(run_info(run), run.accel_units_source)
    assert "rate axes   gyro_x  [deg/h]" in text
    assert "accel axes  acc_x, acc_y, acc_z  [g]" in text
    # the JSON payload alone (its axis_units) groups the axes the same way
    alone = info_text(run_info(run))
    assert "rate axes   gyro_x  [deg/h]" in alone and "accel axes  acc_x, acc_y, acc_z  [g]" in alone
    assert "rate axes   gyro_x, acc_x" not in alone


def test_an_irregular_time_base_says_why() -> None:
    """"IRREGULAR: 0 gap(s) ..." (the real FOG file, jitter 4.1 % of the step) did not say
    which number made it irregular; the reason is now given beside the numbers."""
    rng = np.random.default_rng(1)
    n = 500
    jittery = pd.DataFrame({"time": np.arange(n) / 100.0 + rng.uniform(0, 0.001, n),
                            "rate_deg_h": rng.normal(size=n)})
    info = run_info(read_run(jittery))
    assert info["jitter"]["relative"] > 0.01 and info["gaps"]["count"] == 0
    assert time_base_verdict(info) == "IRREGULAR (jitter >= 1 % of the step)"
    assert "time base   IRREGULAR (jitter >= 1 % of the step): 0 gap(s)" in info_text(info)
    t = np.arange(n) / 100.0
    t[300:] += 1.0  # one 1 s gap, steps otherwise exact
    gappy = pd.DataFrame({"time": t, "rate_deg_h": rng.normal(size=n)})
    info = run_info(read_run(gappy))
    assert time_base_verdict(info).startswith("IRREGULAR (gaps")
    regular = pd.DataFrame({"time": np.arange(n) / 100.0, "rate_deg_h": rng.normal(size=n)})
    assert time_base_verdict(run_info(read_run(regular))) == "regular"


def test_the_duration_of_a_record_with_gaps_gives_the_span_too() -> None:
    """audit2: a 3 h record missing 600 s printed "duration 2.83 h (10200 s)" alone; the
    samples' time stays ``duration_s`` and the stamps' span is given beside it."""
    from fogts.report.text import duration_line, time_span_s

    rng = np.random.default_rng(2)
    t = np.arange(1000) / 10.0
    t[600:] += 60.0  # 60 s missing after 60 s
    run = read_run(pd.DataFrame({"time": t, "rate_deg_h": rng.normal(size=t.size)}))
    info = run_info(run)
    assert abs(info["duration_s"] - 100.0) < 1e-9 and abs(info["span_s"] - 160.0) < 1e-9
    assert abs(time_span_s(run) - 160.0) < 1e-9
    assert duration_line(info) == ("1.67 min (100 s) of samples; the time stamps span "
                                   "2.67 min (160 s)")
    assert "duration    1.67 min (100 s) of samples; the time stamps span" in info_text(info)
    regular = run_info(read_run(rng.normal(size=1000), fs_hz=10.0))
    assert regular["span_s"] == regular["duration_s"] and duration_line(regular) == "1.67 min (100 s)"


def test_info_says_what_the_rate_columns_held() -> None:
    """A column of angle increments (``dtheta_deg``) is read as increments and analysed as
    the rate increment x fs: ``info`` listed it as a rate axis in deg/s, and its statistics
    (those of the rate) under the column's name, without a word of the conversion."""
    rng = np.random.default_rng(5)
    frame = pd.DataFrame({"time": np.arange(400) / 100.0,
                          "dtheta_deg": 1e-4 * rng.standard_normal(400)})
    run = read_run(frame)
    info = run_info(run)
    assert info["input"] == "increment" and run.units == "deg/s"
    assert axes_rows(info) == [("rate axes", "dtheta_deg  [deg/s] (the columns hold angle "
                                             "increments: rate = increment x fs)")]
    assert np.isclose(info["stats"]["dtheta_deg"]["std"],
                      100.0 * frame["dtheta_deg"].std(ddof=1), rtol=1e-12)
    angle = run_info(read_run(frame.assign(dtheta_deg=frame["dtheta_deg"].cumsum()),
                              input="angle", units="deg/s"))
    assert angle["input"] == "angle"
    assert axes_rows(angle)[0][1].endswith("(the columns hold an angle: rate = its "
                                           "difference x fs)")
    plain = run_info(read_run(frame.rename(columns={"dtheta_deg": "rate_deg_s"})))
    assert plain["input"] == "rate" and axes_rows(plain) == [("rate axes", "rate_deg_s  [deg/s]")]


def test_gaps_phrase_says_burst_logged_steps_are_not_gaps() -> None:
    """Burst-logged stamps: the long steps are the bursts' pattern, not gaps (the
    data-quality warning's words); the verdict names the bursts, not gaps."""
    from fogts.report.text import gaps_phrase, time_base_verdict

    info = {"gaps": {"count": 3, "max_s": 0.5, "threshold_s": 0.015, "burst_logged": True},
            "jitter": {"regular": False, "relative": 0.2}}
    text = gaps_phrase(info, lambda v: f"{v:.4g}")
    assert text == ("3 step(s) longer than 0.015 s (longest 0.5 s), the bursts' pattern, not "
                    "gaps: no time is counted as missing")
    assert time_base_verdict(info) == ("IRREGULAR (time stamps logged in bursts, jitter >= "
                                       "1 % of the step)")
    info["gaps"]["burst_logged"] = False
    assert gaps_phrase(info, str) == "3 gap(s) longer than 0.015 s (longest 0.5 s)"
    assert time_base_verdict(info).startswith("IRREGULAR (gaps, ")
