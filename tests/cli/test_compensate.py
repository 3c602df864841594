"""`fogts compensate`: fit, save, re-apply a thermal model; JSON contract; bad input."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pandas as pd
import pytest
from typer.testing import CliRunner

from fogts.cli import app
from fogts.startup.simulator import simulate_startup
from tests.conftest import error_output, shared_path

runner = CliRunner()


def _write(sim_seed: int, ambient: float, path: Path) -> Path:
    sim = simulate_startup(duration_s=1800.0, ambient_degC=ambient, rng=sim_seed)
    pd.DataFrame({"time": sim.run.time, "rate": sim.run.rate,
                  "temperature": sim.run.temperature}).to_csv(path, index=False)
    return path


def test_compensate_json_contract_model_round_trip(tmp_path: Path) -> None:
    src = _write(1, 20.0, tmp_path / "cold.csv")
    out, model, js, png = (tmp_path / "c.csv", tmp_path / "m.json", tmp_path / "c.json",
                           tmp_path / "c.png")
    res = runner.invoke(app, ["compensate", str(src), "--temperature-column", "temperature",
                              "--save-model", str(model), "-o", str(out), "--json", str(js),
                              "--plot", str(png), "--arma-model", "AR(2)"])
    assert res.exit_code == 0, res.output
    payload = json.loads(js.read_text())
    assert set(payload) >= {"input", "emd", "thermal", "bias_stability"}
    assert set(payload["emd"]) >= {"k", "imf_energy"}
    assert set(payload["thermal"]) >= {"terms", "r2"}
    assert set(payload["thermal"]["terms"]["T*dT"]) == {"value", "stderr"}
    bs = payload["bias_stability"]
    assert bs["average_s"] == 10.0 and bs["unit"] == "deg/h" and bs["after"] < bs["before"]
    assert "bias stability (10 s average" in res.output and "D = " in res.output
    frame = pd.read_csv(out)
    assert {"time", "raw", "compensated", "temperature"} <= set(frame.columns)
    assert png.stat().st_size > 1000
    # re-apply the saved model to another run (no fitting), without EMD
    other = _write(2, 22.0, tmp_path / "other.csv")
    res2 = runner.invoke(app, ["compensate", str(other), "--model", str(model), "--json", "-"])
    assert res2.exit_code == 0, res2.output
    p2 = json.loads(res2.stdout)
    assert p2["thermal"]["source"] == str(model) and p2["emd"] is None
    assert p2["thermal"]["terms"] == payload["thermal"]["terms"]


def test_compensate_with_calibration_runs(tmp_path: Path) -> None:
    main = _write(3, 20.0, tmp_path / "a.csv")
    cal = _write(4, 15.0, tmp_path / "b.csv")
    res = runner.invoke(app, ["compensate", str(main), "--no-emd", "--calibration", str(cal),
                              "--json", "-"])
    assert res.exit_code == 0, res.output
    payload = json.loads(res.stdout)
    assert payload["thermal"]["model"]["n"] == 3600
    assert any("fitted on 2 runs" in n for n in payload["notes"])


def test_compensate_real_mpu6050_file_runs(tmp_path: Path) -> None:
    path = shared_path("imu", "mpu6050_gyro_temp_converted.csv.gz")
    res = runner.invoke(app, ["compensate", str(path), "--rate-column", "gyro_z_deg_s",
                              "--no-emd", "--json", "-"])
    assert res.exit_code == 0, res.output
    payload = json.loads(res.stdout)
    assert payload["bias_stability"]["unit"] == "deg/h"
    assert np.isfinite(payload["bias_stability"]["after"])


def test_compensate_bad_input(tmp_path: Path) -> None:
    path = tmp_path / "no_temp.csv"
    pd.DataFrame({"time": np.arange(200.0), "rate": np.random.default_rng(0).normal(size=200)}
                 ).to_csv(path, index=False)
    res = runner.invoke(app, ["compensate", str(path)])
    assert res.exit_code == 2 and "has no temperature column" in res.stderr
    # the option, not read_run's temperature_column= (tests/startup/test_startup_workflow.py)
    assert error_output(res.stderr).endswith("(columns are: time, rate); name it with "
                                             "--temperature-column")
    bad = tmp_path / "bad.json"
    bad.write_text("{not json")
    src = _write(5, 20.0, tmp_path / "s.csv")
    res = runner.invoke(app, ["compensate", str(src), "--model", str(bad)])
    assert res.exit_code == 2 and "is not valid JSON" in res.stderr
    res = runner.invoke(app, ["compensate", str(src), "--model", str(tmp_path / "nope.json")])
    assert res.exit_code == 2 and error_output(res.stderr).startswith("error: ")
    good = tmp_path / "m.json"
    assert runner.invoke(app, ["compensate", str(src), "--no-emd", "--save-model",
                               str(good)]).exit_code == 0
    res = runner.invoke(app, ["compensate", str(src), "--model", str(good), "--calibration",
                              str(src)])
    assert res.exit_code == 2 and "cannot be combined with --model" in res.stderr


@pytest.mark.parametrize("const", [True])
def test_compensate_constant_temperature_says_unidentifiable(tmp_path: Path, const: bool) -> None:
    path = tmp_path / "const.csv"
    rng = np.random.default_rng(1)
    pd.DataFrame({"time": np.arange(600.0), "rate": rng.normal(size=600),
                  "temperature": np.full(600, 25.0)}).to_csv(path, index=False)
    res = runner.invoke(app, ["compensate", str(path), "--no-emd", "--json", "-"])
    assert res.exit_code == 0, res.output
    assert "unidentifiable term(s) left out" in res.stderr
    assert list(json.loads(res.stdout)["thermal"]["terms"]) == ["1"]


def test_one_warm_up_model_is_saved_with_its_note_and_warns_when_reused(tmp_path: Path) -> None:
    """The bundled 20 degC cold start: the six coefficients are jointly significant but each
    insignificant and collinear; the saved model carries the note, and warns on reuse."""
    root = Path(__file__).resolve().parents[2] / "data"
    model = tmp_path / "m.json"
    res = runner.invoke(app, ["compensate", str(root / "startup_cold_1hz.csv"), "--no-emd",
                              "--save-model", str(model)])
    assert res.exit_code == 0, res.output
    warning = [x for x in res.stderr.splitlines() if "not separately identified" in x]
    assert len(warning) == 1 and warning[0].startswith("warning: startup_cold_1hz.csv: ")
    assert "largest variance inflation factor" in warning[0]
    assert "do not reuse it on another ambient or warm-up without a calibration run" in warning[0]
    assert f"saved the thermal model to {model} (with its note: not separately identified" \
        in res.stdout
    assert "x in sample); not claimed as an improvement: in sample only: out of sample " \
        in res.stdout
    saved = json.loads(model.read_text())
    assert saved["identification_note"] in warning[0]
    assert saved["collinearity"]["max_vif"] > saved["collinearity"]["vif_threshold"]
    res2 = runner.invoke(app, ["compensate", str(root / "startup_cold_15c_1hz.csv"), "--model",
                               str(model)])
    assert res2.exit_code == 0, res2.output
    assert ("the thermal model applied here was fitted on another run and saved with this "
            "note: the coefficients are not separately identified") in res2.stderr
    assert "by the given model: out of sample unless it was fitted on this run" in res2.stdout


def test_a_model_that_is_not_significant_is_saved_with_a_warning_and_warns_when_reused(
        tmp_path: Path) -> None:
    """A warm-up with no thermal drift (simulated): the likelihood-ratio test finds nothing;
    --save-model still writes the model, with its note, and one warning line quoting the
    test; --model with that file warns again."""
    from fogts import simulate_gyro
    from fogts.simulate import TemperatureProfile

    run = simulate_gyro({"N": 0.002, "B": 0.01, "K": 0.05}, fs_hz=1, duration_s=3600, rng=700,
                        temperature=TemperatureProfile.parse("warmup:22,26,15min"))
    src = tmp_path / "flat.csv"
    pd.DataFrame({"time": run.time, "rate": run.axis(0),
                  "temperature": run.temperature}).to_csv(src, index=False)
    model, js = tmp_path / "m.json", tmp_path / "c.json"
    res = runner.invoke(app, ["compensate", str(src), "--no-emd", "--save-model", str(model),
                              "--json", str(js)])
    assert res.exit_code == 0, res.output
    doc = json.loads(js.read_text())
    sig = doc["significance"]
    assert sig["testable"] and not sig["significant"]
    warning = [x for x in res.stderr.splitlines() if "not significant" in x]
    assert len(warning) == 1
    assert warning[0].startswith(f"warning: flat.csv: rate: --save-model {model} is saved "
                                 "with its note: the model is not significant (likelihood-ratio")
    assert f"p = {sig['pvalue']:.2g}, chi2 = {sig['statistic']:.3g} on {sig['df']} df" \
        in warning[0]
    saved = json.loads(model.read_text())
    assert saved["identification_note"] in warning[0]
    assert doc["thermal"]["model"]["identification_note"] == saved["identification_note"]
    assert f"saved the thermal model to {model} (with its note: not significant, not for " \
           "reuse on another run)" in res.stdout
    root = Path(__file__).resolve().parents[2] / "data"
    res2 = runner.invoke(app, ["compensate", str(root / "startup_cold_1hz.csv"), "--model",
                               str(model)])
    assert res2.exit_code == 0, res2.output
    assert ("the thermal model applied here was fitted on another run and saved with this "
            "note: the model is not significant (likelihood-ratio test") in res2.stderr


@pytest.mark.parametrize(("args", "says"), [
    (["--average", "-1"], "error: --average must be a finite number > 0, got -1.0"),
    (["--dt-smoothing", "0"], "error: --dt-smoothing must be a finite number > 0, got 0.0"),
])
def test_a_bad_average_or_smoothing_is_refused_first_and_named_as_typed(
        tmp_path: Path, args: list[str], says: str) -> None:
    # audit2: the fit ran first (a collinearity warning came before the error) and the
    # error named average_s / dT_smoothing_s
    src = _write(1, 20.0, tmp_path / "cold.csv")
    res = runner.invoke(app, ["compensate", str(src), "--units", "deg/h", *args])
    assert res.exit_code == 2, res.output
    assert error_output(res.stderr).splitlines() == [says]
    assert "warning" not in res.stderr  # nothing was fitted


def test_the_kalman_note_advises_measurement_noise_and_compensate_takes_it(
        tmp_path: Path) -> None:
    """The Kalman note on a negligible estimated measurement noise names the option
    (printed and in the JSON); given, the variance is the gyro's H and the note is gone."""
    root = Path(__file__).resolve().parents[2] / "data"
    js = tmp_path / "c.json"
    res = runner.invoke(app, ["compensate", str(root / "startup_cold_1hz.csv"),
                              "--json", str(js)])
    assert res.exit_code == 0, res.output
    advice = "; give --measurement-noise (a variance in (rate unit)^2) to smooth"
    note = [ln for ln in res.stdout.splitlines() if "is negligible (H = " in ln]
    assert len(note) == 1 and note[0].endswith("so the filter follows the data" + advice)
    doc = json.loads(js.read_text())
    assert doc["kalman"]["notes"] == doc["notes"][:1] and doc["notes"][0].endswith(advice)
    assert "measurement_noise" not in res.stdout
    res = runner.invoke(app, ["compensate", str(root / "startup_cold_1hz.csv"),
                              "--measurement-noise", "0.01", "--json", str(js), "--overwrite"])
    assert res.exit_code == 0, res.output
    doc = json.loads(js.read_text())
    assert doc["kalman"]["measurement_noise"] == 0.01
    assert doc["kalman"]["measurement_noise_source"] == "given"
    assert "is negligible (H = " not in res.stdout


@pytest.mark.parametrize("args, says", [
    (["--measurement-noise", "x"], "error: --measurement-noise must be 'estimate' or a "
                                   "variance in (rate unit)^2; got 'x'"),
    (["--measurement-noise", "-1"], "error: --measurement-noise must be a finite number >= 0, got -1.0"),
    (["--measurement-noise", "0.01", "--no-emd"],
     "error: --measurement-noise sets the Kalman filter of the EMD rest, which --no-emd "
     "skips: give one or the other"),
    (["--measurement-noise", "0.01", "--model", "MODEL"],
     "error: --measurement-noise sets the Kalman filter of the EMD rest, which --model skips "
     "(nothing is fitted): give one or the other"),
])
def test_bad_measurement_noise_is_refused(tmp_path: Path, args: list[str], says: str) -> None:
    src = _write(1, 20.0, tmp_path / "cold.csv")
    model = tmp_path / "model.json"
    model.write_text("{}")
    args = [str(model) if a == "MODEL" else a for a in args]
    res = runner.invoke(app, ["compensate", str(src), "--units", "deg/h", *args])
    assert res.exit_code == 2, res.output
    assert error_output(res.stderr).splitlines() == [says]
