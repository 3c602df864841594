"""`fogts filter` (Kalman method): output table, JSON, plot and one-line errors."""

from __future__ import annotations

import json
import re
from pathlib import Path

import numpy as np
import pandas as pd
import pytest
from scipy.signal import lfilter
from typer.testing import CliRunner

from fogts.cli import app
from tests.conftest import error_output

runner = CliRunner()


@pytest.fixture
def ar_file(tmp_path: Path) -> Path:
    rng = np.random.default_rng(6)
    drift = lfilter([1.0], [1.0, -0.9], rng.normal(0, 0.2, 1500))
    y = drift + rng.normal(0, 0.5, drift.size)
    path = tmp_path / "gyro.csv"
    pd.DataFrame({"time": np.arange(y.size) * 0.1, "rate": y}).to_csv(path, index=False)
    return path


def test_filter_fixed_model_writes_table_json_and_plot(ar_file: Path, tmp_path: Path) -> None:
    out, js, png = tmp_path / "f.csv", tmp_path / "f.json", tmp_path / "f.png"
    res = runner.invoke(app, ["filter", str(ar_file), "--model", "AR(1)", "--measurement-noise",
                              "0.25", "-o", str(out), "--json", str(js), "--plot", str(png)])
    assert res.exit_code == 0, res.output
    frame = pd.read_csv(out)
    assert list(frame.columns) == ["time", "observed", "filtered", "smoothed", "predicted"]
    assert len(frame) == 1500
    assert frame["filtered"].std() < frame["observed"].std()
    payload = json.loads(js.read_text())
    assert payload["method"] == "kalman" and payload["kalman"]["model"] == "AR(1)"
    assert payload["kalman"]["measurement_noise"] == 0.25
    assert png.stat().st_size > 1000
    assert "x_t = " in res.output and "Kalman filter" in res.output


def test_filter_auto_runs_the_selection(ar_file: Path, tmp_path: Path) -> None:
    res = runner.invoke(app, ["filter", str(ar_file), "-o", str(tmp_path / "a.parquet"),
                              "--json", "-"])
    assert res.exit_code == 0, res.output
    payload = json.loads(res.stdout)
    assert payload["model"]["model"] in ("AR(1)", "AR(2)", "AR(3)", "ARMA(1,1)", "ARMA(2,1)")
    assert payload["kalman"]["measurement_noise_source"] == "estimated"
    assert (tmp_path / "a.parquet").exists()


@pytest.mark.parametrize(("args", "message"), [
    (["--method", "wiener"], "'wiener' is not one of 'kalman', 'iir', 'moving-average'"),
    (["--model", "AR(9)"], "model must be one of auto"),
    (["--measurement-noise", "lots"], "--measurement-noise must be 'estimate' or a variance"),
    (["--measurement-noise", "-1"], "--measurement-noise must be a finite number >= 0"),
])
def test_filter_bad_options(ar_file: Path, tmp_path: Path, args: list[str], message: str) -> None:
    res = runner.invoke(app, ["filter", str(ar_file), "-o", str(tmp_path / "x.csv"), *args])
    assert res.exit_code == 2
    lines = error_output(res.stderr).splitlines()
    assert len(lines) == 1 and lines[0].startswith("error: ") and message in lines[0], res.stderr


@pytest.mark.parametrize("args, message", [
    (["--cutoff", "3"],
     r"--method kalman does not use --cutoff \(--cutoff applies to --method iir\)"),
    (["--compare-allan"], r"--method kalman does not use --compare-allan \(--compare-allan "
                          r"applies to --method iir or moving-average\)"),
    (["--method", "iir", "--cutoff", "1", "--model", "AR(1)", "--window", "2"],
     r"--method iir does not use --model, --window \(--model applies to --method kalman; "
     r"--window applies to --method moving-average\)"),
    (["--method", "moving-average", "--window", "1", "--order", "2", "--measurement-noise",
      "0.1"], r"--method moving-average does not use --measurement-noise, --order"),
])
def test_options_of_another_method_are_refused(ar_file: Path, tmp_path: Path, args: list[str],
                                               message: str) -> None:
    """An option of another --method was silently ignored (``--method kalman --cutoff 3``
    exited 0); it is refused with the one-line error and nothing is written."""
    out = tmp_path / "f.csv"
    res = runner.invoke(app, ["filter", str(ar_file), "-o", str(out), *args])
    assert res.exit_code == 2
    line = error_output(res.stderr)
    assert re.search(message, line) and line.endswith("drop it or change --method")
    assert not out.exists()


def test_kalman_text_states_the_rate_unit(ar_file: Path, tmp_path: Path) -> None:
    """The Kalman summary prints sigma2, H and the std of the series without a unit; the
    drift-model line above it states the rate unit they are in."""
    res = runner.invoke(app, ["filter", str(ar_file), "--model", "AR(1)", "--units", "deg/s",
                              "-o", str(tmp_path / "f.csv")])
    assert res.exit_code == 0, res.output
    assert "[rate in deg/s; sigma2 and H in (deg/s)^2]" in res.stdout


@pytest.mark.parametrize(("args", "says"), [
    (["--method", "iir", "--cutoff", "80"], "--cutoff must be below the Nyquist frequency 5 Hz"),
    (["--method", "iir", "--cutoff", "-1"], "--cutoff must be a finite number > 0, got -1.0"),
    (["--method", "moving-average", "--window", "0"],
     "--window must be a finite number > 0, got 0.0"),
    (["--measurement-noise", "-1"], "--measurement-noise must be a finite number >= 0, got -1.0"),
])
def test_filter_errors_name_the_option_typed(ar_file: Path, tmp_path: Path, args: list[str],
                                             says: str) -> None:
    # audit2: they named the library's keywords cutoff_hz and window_s
    out = tmp_path / "o.csv"
    res = runner.invoke(app, ["filter", str(ar_file), "-o", str(out), *args])
    assert res.exit_code == 2, res.output
    lines = error_output(res.stderr).splitlines()
    assert len(lines) == 1 and lines[0].startswith("error: ") and says in lines[0]
    assert not any(k in lines[0] for k in ("cutoff_hz", "window_s", "measurement_noise"))
    assert not out.exists()


def test_the_negligible_noise_note_names_the_option(tmp_path: Path) -> None:
    """The Kalman note on a negligible estimated measurement noise advises giving one: in
    filter as its option --measurement-noise (printed and in the JSON), never as the
    library's keyword (it said 'give measurement_noise to smooth')."""
    data = Path(__file__).resolve().parents[2] / "data" / "startup_cold_1hz.csv"
    js = tmp_path / "f.json"
    res = runner.invoke(app, ["filter", str(data), "-o", str(tmp_path / "f.csv"),
                              "--json", str(js)])
    assert res.exit_code == 0, res.output
    advice = "; give --measurement-noise (a variance in (rate unit)^2) to smooth"
    note = [ln for ln in res.stdout.splitlines() if "is negligible (H = " in ln]
    assert len(note) == 1 and note[0].endswith("so the filter follows the data" + advice)
    notes = json.loads(js.read_text())["kalman"]["notes"]
    assert len(notes) == 1 and notes[0].endswith(advice)
    assert "measurement_noise" not in res.stdout
