"""`fogts allan` on the two real records where the audit found a term or a floor read from
points with too few degrees of freedom (EDF < 10, the read-outs' threshold):

* the first 5 s of ADIS16405 run 1, X axis: the curve ends below its minimum's interval, so
  the read-out finds no floor (it read 'floor (region C) 0.32 .. 0.64 s' and B = 476 deg/h);
* the 655 s MPU6050 record, Y axis: R dominates only at 82 and 165 s (EDF 7.5 and 3.0), so
  it is an upper limit everywhere (it printed 'R 265 ± 35.1 deg/h^2' as measured).
"""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

import numpy as np
import pandas as pd
import pytest
from typer.testing import CliRunner

from fogts.cli import app
from tests.conftest import shared_path

runner = CliRunner()


def _json(args: list[Any]) -> tuple[dict[str, Any], str]:
    """The JSON (stdout) and the tables and warnings (stderr) of one command."""
    res = runner.invoke(app, [str(a) for a in args] + ["--json", "-"])
    assert res.exit_code == 0, res.stderr
    return json.loads(res.stdout), res.stderr


def _cell(text: str, first: str, column: int) -> str:
    """Column ``column`` of the table row whose first cell is ``first``, its wrapped lines
    joined (rich draws a row over several lines when a cell wraps)."""
    parts: list[str] = []
    for line in text.splitlines():
        cells = line.split("│")[1:-1]
        if not cells:
            if parts:
                break
            continue
        if cells[0].strip() == first:
            parts = [cells[column].strip()]
        elif parts and not cells[0].strip():
            parts.append(cells[column].strip())
        elif parts:
            break
    return " ".join(p for p in parts if p)


def test_a_5_s_adis_record_has_no_floor(tmp_path: Path) -> None:
    """N1: 500 samples at 100 Hz; the minimum (0.32 s, 0.0878 [0.0768, 0.105] deg/s) is
    followed by 0.0847 (inside) and 0.0618 at 1.28 s (below): the curve is still falling."""
    data = np.load(shared_path("imu", "adis_16405_imu1_gyro.npz"))
    path = tmp_path / "short5s.csv"
    pd.DataFrame({"time_s": np.arange(500) / 100.0,
                  "gyro_deg_s": data["gyro_deg_s"][:500, 0]}).to_csv(path, index=False)
    doc, text = _json(["allan", path])
    text = " ".join(text.split())
    curve = doc["axes"][0]["curve"]
    minimum = curve["minimum"]
    assert minimum["tau"] == pytest.approx(0.32)
    assert minimum["dev"] == pytest.approx(0.087803, rel=1e-4)
    assert minimum["ci_low"] == pytest.approx(0.076813, rel=1e-4)
    last = doc["axes"][0]["points"][-1]
    assert last["tau"] == pytest.approx(1.28) and last["dev"] < minimum["ci_low"]
    assert minimum["floor_found"] is False and minimum["bias_instability_floor"] is None
    why = ("no floor: the curve is still falling at its last trusted tau (0.32 s); the curve "
           "ends below the minimum's interval (point at 1.28 s)")
    assert minimum["floor"] == why
    assert curve["regions"]["C"] is None and curve["regions"]["D"] is None
    assert curve["regions"]["B"] == [pytest.approx(0.01), pytest.approx(1.28)]
    readoff = doc["axes"][0]["noise_fit"]["readoff"]["B"]
    assert readoff["supported"] is False and readoff["note"] == why
    assert "floor/0.664" not in text and "B = 476" not in text
    assert f"B not read ({why})" in text


def test_a_655_s_mpu6050_rate_ramp_is_only_an_upper_limit() -> None:
    """N2: R (z = 3.8) dominates the fitted sigma^2 only at 82.48 and 165 s, EDF 7.53 and
    2.97: an upper limit in the table, the JSON and the read-out, with the reason."""
    doc, text = _json(["allan", shared_path("imu", "mpu6050_gyro_temp_converted.csv.gz"),
                       "--rate-column", "gyro_y_deg_s"])
    axis = doc["axes"][0]
    edf = {round(p["tau"], 2): p["edf"] for p in axis["points"]}
    assert edf[82.48] < 10 and edf[164.97] < 10 and edf[41.24] >= 10
    r = axis["noise"]["R"]
    assert r["status"] == "fitted" and r["z"] >= 2 and r["value"] > 0
    assert r["measured"] is False
    assert r["limit_reason"] == ("R dominates only at tau 82.48 .. 165 s, where the points "
                                 "have EDF < 10")
    assert r["upper_limit_95"] == pytest.approx(
        (r["value"]**2 + 2 * 1.6448536269514722 * r["value"] * r["stderr"]) ** 0.5)
    assert axis["noise"]["N"]["measured"] is True
    assert axis["noise_si"]["R"]["upper_limit_95"] is not None
    limit = f"{r['upper_limit_95']:.3g}"
    assert _cell(text, "R", -1) == (f"< {limit} (95 % upper limit; R dominates only at tau "
                                    "82.48 .. 165 s, where the points have EDF < 10)")
    assert _cell(text, "R line largest", 1) == "82.48 .. 165 s"
    assert _cell(text, "R line largest", 2).startswith("slope +1; R is not measured (an "
                                                       "upper limit)")
    assert _cell(text, "R dominates", 1) == ""  # no such read-out row
    assert "R: only a limit whatever its z" in " ".join(text.split())
    ranges = {d["term"]: d for d in axis["curve"]["dominant"]}
    assert ranges["R"]["measured"] is False and ranges["N"]["measured"] is True
    assert any("noise term R (rate ramp, slope +1) dominates the fitted sigma^2 only at tau "
               "82.48, 165 s, where the points have EDF < 10 (7.53, 2.97)" in w
               for w in axis["noise_fit"]["warnings"])
