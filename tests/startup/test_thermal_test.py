"""The likelihood-ratio test of a temperature dependence (fogts.startup.thermal_test).

Truth comes from simulations: records with a warm-up temperature and no thermal effect
(``simulate_gyro`` with a temperature profile and no ``thermal_coefficients``) must not be
called significant; simulated cold starts (``simulate_startup``, a known thermal drift)
must.  The test's level is 0.001, so five null records reject with probability 0.5 %; a
Monte-Carlo run of 20 null and 20 cold-start records gave 0/20 and 20/20 (smallest null
p 0.02, largest cold-start p 4e-10).
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest
from typer.testing import CliRunner

import fogts
from fogts.cli import app
from fogts.errors import DataError
from fogts.simulate import TemperatureProfile
from fogts.startup.simulator import simulate_startup
from fogts.startup.thermal_test import MIN_SPAN_DEGC, thermal_significance
from tests.conftest import shared_path

ROOT = Path(__file__).resolve().parents[2]


@pytest.mark.parametrize("seed", range(5))
def test_no_thermal_effect_is_not_significant(seed: int) -> None:
    run = fogts.simulate_gyro({"N": 0.002, "B": 0.01, "K": 0.05}, fs_hz=10,
                              duration_s=3 * 3600, rng=700 + seed,
                              temperature=TemperatureProfile.parse("warmup:22,26,15min"))
    res = thermal_significance(run.axis(0), run.temperature, fs_hz=run.fs_hz)
    assert res.testable and not res.significant
    assert res.verdict.startswith("no significant temperature dependence")
    assert res.df == 5 and 0.0 <= res.pvalue <= 1.0


@pytest.mark.parametrize("seed", range(3))
def test_a_cold_start_is_significant(seed: int) -> None:
    sim = simulate_startup(duration_s=3600, fs_hz=1.0, rng=800 + seed)
    res = thermal_significance(sim.run.axis(0), sim.run.temperature, fs_hz=1.0)
    assert res.significant and res.pvalue < 1e-6
    assert res.to_dict()["verdict"].startswith("significant temperature dependence")


def test_a_small_temperature_span_is_not_testable() -> None:
    rng = np.random.default_rng(3)
    temp = 25.0 + 0.2 * np.sin(np.arange(5000) / 500.0)
    res = thermal_significance(rng.normal(size=5000), temp, fs_hz=1.0)
    assert not res.testable and not res.significant
    assert f"less than {MIN_SPAN_DEGC:g} °C" in res.verdict and "nothing to compensate" in res.verdict


def test_bad_input_names_the_lengths() -> None:
    with pytest.raises(DataError, match="same length .* got 100 and 99"):
        thermal_significance(np.zeros(100), np.zeros(99), fs_hz=1.0)


def test_mpu6050_temperature_span_is_too_small() -> None:
    path = shared_path("imu", "mpu6050_gyro_temp_converted.csv.gz")
    with pytest.warns(fogts.errors.DataQualityWarning):
        run = fogts.read_run(path, units="deg/s")
    res = fogts.startup_compensation(run, emd=False)
    assert res.significance is not None and not res.significance.testable
    assert not res.claims_improvement and not res.applied
    assert ("thermal model: fitted, not applied: the temperature spans 0.471 °C, too little "
            "to identify its coefficients") in res.summary()
    assert "not significant" not in res.summary()
    # nothing subtracted: the output rate is the input, bit for bit
    assert np.array_equal(res.to_frame()["compensated"], run.axis(0))
    assert res.after.value == res.before.value


def test_compensate_on_the_example_claims_nothing(tmp_path: Path) -> None:
    out = tmp_path / "c.json"
    res = CliRunner().invoke(app, ["compensate", str(ROOT / "data" / "example_fog_10hz_3h.csv"),
                                   "--json", str(out)])
    assert res.exit_code == 0, res.stderr
    assert res.stdout.startswith("verdict: no significant temperature dependence")
    assert ("thermal model: fitted, not applied: the likelihood-ratio test finds no "
            "significant temperature dependence") in res.stdout
    assert "(nothing compensated)" in res.stdout and "x)" not in res.stdout
    doc = json.loads(out.read_text())
    assert doc["significance"]["significant"] is False
    assert doc["bias_stability"]["improvement_claimed"] is False
    assert doc["applied"] is False
    assert doc["bias_stability"]["after"] == doc["bias_stability"]["before"]


def test_compensate_applies_an_insignificant_model_only_when_asked(tmp_path: Path) -> None:
    example = str(ROOT / "data" / "example_fog_10hz_3h.csv")
    out = tmp_path / "c.json"
    res = CliRunner().invoke(app, ["compensate", example, "--no-emd", "--apply", "always",
                                   "--json", str(out)])
    assert res.exit_code == 0, res.stderr
    doc = json.loads(out.read_text())
    assert doc["applied"] is True and doc["significance"]["significant"] is False
    assert doc["bias_stability"]["after"] != doc["bias_stability"]["before"]
    assert "not claimed as an improvement: the model is not significant" in res.stdout


def test_compensate_refuses_an_unknown_apply_rule() -> None:
    res = CliRunner().invoke(app, ["compensate", str(ROOT / "data" / "example_fog_10hz_3h.csv"),
                                   "--apply", "sometimes"])
    assert res.exit_code == 2
    assert "--apply" in res.stderr and "sometimes" in res.stderr
    assert "significant" in res.stderr and "always" in res.stderr
    assert "Traceback" not in res.stderr
    run = simulate_startup(duration_s=600, rng=1).run
    with pytest.raises(DataError, match=r"apply must be one of 'significant', 'always', "
                                        r"got 'sometimes'"):
        fogts.startup_compensation(run, emd=False, apply="sometimes")  # type: ignore[arg-type]


def test_compensate_on_the_cold_start_is_significant() -> None:
    res = CliRunner().invoke(app, ["compensate", str(ROOT / "data" / "startup_cold_1hz.csv")])
    assert res.exit_code == 0, res.stderr
    assert res.stdout.startswith("verdict: significant temperature dependence")
    assert "(4.3" in res.stdout  # the bias-stability improvement (4.30x) is claimed
