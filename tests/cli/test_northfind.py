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
