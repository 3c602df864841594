"""`fogts northfind`: positions file, four files, thermal model, simulation mode, errors."""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pandas as pd
import pytest
from typer.testing import CliRunner

from fogts.cli import app
from fogts.units import earth_rate_component
from tests.conftest import error_output

runner = CliRunner()
LAT = 32.05
PSI = 123.4


def _rates(noise: float = 0.05, seed: int = 0) -> dict[int, np.ndarray]:
    om = earth_rate_component(LAT, axis="north")
    rng = np.random.default_rng(seed)
    return {p: om * math.cos(math.radians(PSI + p)) + 1.0 + noise * rng.standard_normal(60)
            for p in (0, 90, 180, 270)}


def test_positions_file(tmp_path: Path) -> None:
    r = _rates()
    path = tmp_path / "pos.csv"
    pd.DataFrame({"time": np.arange(240.0), "position_deg": np.repeat([0, 90, 180, 270], 60),
                  "rate": np.concatenate([r[p] for p in (0, 90, 180, 270)])}).to_csv(path, index=False)
    res = runner.invoke(app, ["northfind", str(path), "--latitude", str(LAT), "--json", "-"])
    assert res.exit_code == 0, res.output
    payload = json.loads(res.stdout)
    assert {"azimuth_deg", "sigma_deg", "mean_rates"} <= set(payload)
    assert abs(payload["azimuth_deg"] - PSI) < 4 * payload["sigma_deg"]
    assert set(payload["mean_rates"]) == {"0", "90", "180", "270"}


def test_four_files(tmp_path: Path) -> None:
    r = _rates(noise=1e-6)          # read_run refuses a constant column
    files = []
    for p in (0, 90, 180, 270):
        f = tmp_path / f"p{p}.csv"
        pd.DataFrame({"time": np.arange(60.0), "rate": r[p]}).to_csv(f, index=False)
        files.append(str(f))
    res = runner.invoke(app, ["northfind", *files, "--latitude", str(LAT)])
    assert res.exit_code == 0, res.output
    assert f"azimuth ψ = {PSI:.4f}°" in res.output     # 4 decimals: noise is 1e-6 deg/h


def test_four_files_in_different_units_are_compared_in_one(tmp_path: Path) -> None:
    """audit2: a 90-degree file in deg/s (rate_deg_s) beside three in deg/h was taken as
    deg/h: its mean printed as -0.0009 °/h, the azimuth came out 9° off and the Earth-rate
    check still passed."""
    r = _rates(noise=1e-6)
    files = []
    for p in (0, 90, 180, 270):
        f = tmp_path / f"p{p}.csv"
        column = "rate_deg_s" if p == 90 else "rate_deg_h"
        values = r[p] / 3600.0 if p == 90 else r[p]
        pd.DataFrame({"time": np.arange(60.0), column: values}).to_csv(f, index=False)
        files.append(str(f))
    res = runner.invoke(app, ["northfind", *files, "--latitude", str(LAT)])
    assert res.exit_code == 0, res.output
    assert f"azimuth ψ = {PSI:.4f}°" in res.output
    # and a file at another sample rate is refused, naming both
    slow = tmp_path / "p180_2hz.csv"
    pd.DataFrame({"time": np.arange(60.0) / 2.0, "rate_deg_h": r[180]}).to_csv(slow, index=False)
    res = runner.invoke(app, ["northfind", files[0], files[1], str(slow), files[3],
                              "--latitude", str(LAT)])
    assert res.exit_code == 2
    assert error_output(res.stderr).splitlines() == [
        "error: p180_2hz.csv (position 180) is sampled at 2 Hz, p0.csv (position 0) at 1 Hz; "
        "the four position files must share one sample rate"]


def test_simulation_mode(tmp_path: Path) -> None:
    png = tmp_path / "ns.png"
    res = runner.invoke(app, ["northfind", "--simulate", "20", "--latitude", str(LAT),
                              "--json", str(tmp_path / "s.json"), "--plot", str(png)])
    assert res.exit_code == 0, res.output
    payload = json.loads((tmp_path / "s.json").read_text())
    assert payload["n_trials"] == 20 and payload["compensated"]["rms_deg"] < payload["raw"]["rms_deg"]
    assert "RMS error reduced" in res.output and png.stat().st_size > 1000


@pytest.mark.parametrize(("args", "message"), [
    (["--latitude", "89.5"], "of the pole"),
    (["--latitude", "95"], "error: --latitude must be in [-89, 89] (north finding needs the "
                           "horizontal Earth rate), got 95.0"),
    (["--latitude", "32", "--simulate", "5", "EXTRA"], "--simulate takes no input files"),
    (["--latitude", "32"], "give one positions file or four files"),
])
def test_bad_usage(tmp_path: Path, args: list[str], message: str) -> None:
    r = _rates()
    path = tmp_path / "pos.csv"
    pd.DataFrame({"position_deg": np.repeat([0, 90, 180, 270], 60),
                  "rate": np.concatenate([r[p] for p in (0, 90, 180, 270)])}).to_csv(path, index=False)
    argv = ["northfind"]
    if "EXTRA" in args:
        args = [a if a != "EXTRA" else str(path) for a in args]
    elif "give one" not in message:
        argv.append(str(path))
    res = runner.invoke(app, [*argv, *args, "--fs", "1"])
    assert res.exit_code == 2, res.output
    assert message in res.stderr and error_output(res.stderr).startswith("error: ")


def test_missing_position_and_wrong_file_count(tmp_path: Path) -> None:
    r = _rates()
    path = tmp_path / "pos3.csv"
    pd.DataFrame({"position_deg": np.repeat([0, 90, 270], 60),
                  "rate": np.concatenate([r[p] for p in (0, 90, 270)])}).to_csv(path, index=False)
    res = runner.invoke(app, ["northfind", str(path), "--latitude", "32", "--fs", "1"])
    assert res.exit_code == 2 and "positions 180 are missing" in res.stderr
    res = runner.invoke(app, ["northfind", str(path), str(path), "--latitude", "32", "--fs", "1"])
    assert res.exit_code == 2 and "four files" in res.stderr


def test_a_missing_position_column_is_named_as_such(tmp_path: Path) -> None:
    # audit2: a file without positions said "rate column 'position_deg' not found"
    path = tmp_path / "plain.csv"
    pd.DataFrame({"time": np.arange(240.0), "rate": _rates()[0].repeat(4)}).to_csv(path,
                                                                                 index=False)
    for extra, name in (([], "position_deg"), (["--position-column", "pos"], "pos")):
        res = runner.invoke(app, ["northfind", str(path), "--latitude", "32", *extra])
        assert res.exit_code == 2, res.output
        lines = error_output(res.stderr).splitlines()
        assert lines == [f"error: position column {name!r} (--position-column) not found; "
                         "columns are: time, rate; give one file with the positions in "
                         "degrees, or four files (0, 90, 180, 270 degrees in that order)"]
    res = runner.invoke(app, ["northfind", str(path), "--latitude", "32", "--rate-column", "x"])
    assert res.exit_code == 2 and "rate column 'x' not found" in res.stderr


def test_plot_outside_simulation_is_refused_before_any_output(tmp_path: Path) -> None:
    """--plot with a positions file exited 2 after writing the --json file; the refusal now
    comes first and nothing is written."""
    r = _rates()
    path = tmp_path / "pos.csv"
    pd.DataFrame({"time": np.arange(240.0), "position_deg": np.repeat([0, 90, 180, 270], 60),
                  "rate": np.concatenate([r[p] for p in (0, 90, 180, 270)])}).to_csv(path, index=False)
    out = tmp_path / "n.json"
    res = runner.invoke(app, ["northfind", str(path), "--latitude", str(LAT), "--json", str(out),
                              "--plot", str(tmp_path / "n.png")])
    assert res.exit_code == 2
    assert error_output(res.stderr) == "error: --plot is available in --simulate mode only"
    assert not out.exists()


@pytest.mark.parametrize("args, stray", [
    (["--bias-sigma", "-1"], "--bias-sigma"),
    (["--transition", "5", "--position-column", "pos"], "--transition, --position-column"),
])
def test_simulation_refuses_the_options_of_measured_files(args: list[str], stray: str) -> None:
    """--simulate ignored --bias-sigma (even -1), --transition and --position-column."""
    res = runner.invoke(app, ["northfind", "--simulate", "2", "--latitude", str(LAT), *args])
    assert res.exit_code == 2
    assert error_output(res.stderr) == (
        f"error: --simulate does not use {stray} (options of measured positions files); drop "
        "it or give the files instead of --simulate")


# --- does the record support an azimuth? ------------------------------------------------

def _positions_file(tmp_path: Path, *, scale: float = 1.0, noise: float = 0.05,
                    lat: float = LAT) -> Path:
    om = earth_rate_component(lat, axis="north")
    rng = np.random.default_rng(5)
    rate = np.concatenate([scale * (om * math.cos(math.radians(PSI + p)) + 1.0)
                           + noise * rng.standard_normal(60) for p in (0, 90, 180, 270)])
    path = tmp_path / "pos.csv"
    pd.DataFrame({"time": np.arange(240.0), "position_deg": np.repeat([0, 90, 180, 270], 60),
                  "rate": rate}).to_csv(path, index=False)
    return path


def test_healthy_record_prints_the_azimuth_and_the_earth_rate_check(tmp_path: Path) -> None:
    path = _positions_file(tmp_path)
    res = runner.invoke(app, ["northfind", str(path), "--latitude", str(LAT), "--units", "deg/h",
                              "--json", str(tmp_path / "n.json")])
    assert res.exit_code == 0, res.output
    lines = res.stdout.splitlines()
    assert lines[-3].startswith("  azimuth ψ = ") and "(1σ: ARW " in lines[-3]
    assert lines[-2].startswith("  residual bias ") and "(ratio " in lines[-2]
    assert lines[-1].startswith("  Earth-rate check: ratio ") and "consistent with 1" in lines[-1]
    assert "warning" not in res.stderr
    payload = json.loads((tmp_path / "n.json").read_text())
    assert payload["scale_consistent"] is True and payload["azimuth_usable"] is True
    assert payload["scale_warning"] is None


def test_wrong_unit_warns_names_the_cause_and_exits_1(tmp_path: Path) -> None:
    path = _positions_file(tmp_path)           # deg/h data read as deg/s
    res = runner.invoke(app, ["northfind", str(path), "--latitude", str(LAT), "--units", "deg/s",
                              "--json", str(tmp_path / "n.json")])
    assert res.exit_code == 1, res.output
    warning = [line for line in res.stderr.splitlines() if line.startswith("warning: ")]
    assert len(warning) == 1
    assert "a ratio of about 3600 is deg/s vs deg/h" in warning[0]
    assert "not deg/s (check --units)" in warning[0]
    assert "no usable azimuth: 1σ = " in res.stdout and "azimuth ψ =" not in res.stdout
    assert "Earth-rate check failed" in res.stdout
    payload = json.loads((tmp_path / "n.json").read_text())
    assert payload["scale_consistent"] is False and payload["azimuth_usable"] is False
    assert "deg/s vs deg/h" in payload["scale_warning"] and "azimuth_deg" in payload


def test_wrong_latitude_warns_and_exits_1(tmp_path: Path) -> None:
    path = _positions_file(tmp_path)           # recorded at 32.05 deg
    res = runner.invoke(app, ["northfind", str(path), "--latitude", "70", "--units", "deg/h"])
    assert res.exit_code == 1, res.output
    assert "it matches the horizontal Earth rate at latitude ±32." in res.stderr
    assert "check --latitude (or --units, or the gyro's scale factor)" in res.stderr
    assert "rad vs deg" not in res.stderr


def test_near_the_pole_a_latitude_error_and_rad_vs_deg_are_both_named(tmp_path: Path) -> None:
    # cos 32.05 / cos 89 = 48.6 is within the tolerance of 57.3 (rad vs deg)
    path = _positions_file(tmp_path)
    res = runner.invoke(app, ["northfind", str(path), "--latitude", "89", "--units", "deg/h"])
    assert res.exit_code == 1, res.output
    assert "a ratio of about 57.3 is rad vs deg" in res.stderr
    assert "; or it matches the horizontal Earth rate at latitude ±32." in res.stderr


def test_noise_too_large_for_an_azimuth_exits_1(tmp_path: Path) -> None:
    # 150 deg/h noise against Omega cos L = 12.7 deg/h: the 95 % interval spans > 180 deg
    path = _positions_file(tmp_path, noise=150.0)
    res = runner.invoke(app, ["northfind", str(path), "--latitude", str(LAT), "--units", "deg/h",
                              "--json", "-"])
    assert res.exit_code == 1, res.output
    payload = json.loads(res.stdout)
    assert payload["azimuth_usable"] is False and payload["scale_consistent"] is True
    assert "no usable azimuth" in res.stderr        # the text goes to stderr with --json -
    assert "warning" not in res.stderr


def test_a_thermal_model_saved_with_an_identification_note_warns(tmp_path: Path) -> None:
    path = _positions_file(tmp_path)
    model = {"model": "fogts-thermal-drift", "units": "deg/h", "terms": {
        "T": {"value": 0.0, "stderr": 1.0}, "1": {"value": 0.0, "stderr": 1.0}},
        "identification_note": "the coefficients are not separately identified (test)"}
    (tmp_path / "m.json").write_text(json.dumps(model))
    frame = pd.read_csv(path)
    frame["temperature"] = np.linspace(20.0, 30.0, len(frame))
    frame.to_csv(path, index=False)
    res = runner.invoke(app, ["northfind", str(path), "--latitude", str(LAT), "--thermal-model",
                              str(tmp_path / "m.json"), "--temperature-column", "temperature",
                              "--units", "deg/h"])
    assert res.exit_code == 0, res.output
    assert ("warning: the thermal model applied here was fitted on another run and saved with "
            "this note: the coefficients are not separately identified (test)") in res.stderr
