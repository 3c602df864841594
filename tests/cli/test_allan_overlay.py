"""`fogts allan` with several inputs (overlay) and the curve read-out in its output."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pandas as pd
import pytest
from typer.testing import CliRunner

from fogts.cli import app
from tests.conftest import error_output

runner = CliRunner()


def _record(path: Path, scale: float, seed: int, n: int = 40_000, fs: float = 20.0) -> Path:
    rng = np.random.default_rng(seed)
    x = scale * rng.normal(size=n) + np.cumsum(rng.normal(scale=scale * 2e-3, size=n))
    pd.DataFrame({"time": np.arange(n) / fs, "rate": x}).to_csv(path, index=False)
    return path


@pytest.fixture
def two_gyros(tmp_path: Path) -> tuple[Path, Path]:
    return _record(tmp_path / "good.csv", 1.0, 1), _record(tmp_path / "bad.csv", 3.0, 2)


def test_overlay_json_has_one_entry_per_input(two_gyros: tuple[Path, Path],
                                              tmp_path: Path) -> None:
    js, png, csv = tmp_path / "o.json", tmp_path / "o.png", tmp_path / "o.csv"
    res = runner.invoke(app, ["allan", *map(str, two_gyros), "--json", str(js), "--plot",
                              str(png), "--csv", str(csv)])
    assert res.exit_code == 0, res.output
    payload = json.loads(js.read_text())
    assert [e["input"]["source"] for e in payload["inputs"]] == [str(p) for p in two_gyros]
    good, bad = payload["inputs"]
    for entry in (good, bad):
        assert {"input", "kind", "units", "points", "noise", "curve"} <= set(entry)
    # the noisier gyro sits higher: N scales with the white-noise level (3x)
    ratio = bad["noise"]["N"]["value"] / good["noise"]["N"]["value"]
    assert ratio == pytest.approx(3.0, rel=0.05)
    assert png.stat().st_size > 10_000
    table = pd.read_csv(csv)
    assert list(table.columns[:2]) == ["source", "axis"] and table["source"].nunique() == 2


def test_single_file_curve_readout(two_gyros: tuple[Path, Path]) -> None:
    res = runner.invoke(app, ["allan", str(two_gyros[0]), "--json", "-"])
    assert res.exit_code == 0
    payload = json.loads(res.stdout)
    assert "inputs" not in payload  # one input keeps the DESIGN.md contract
    curve = payload["curve"]
    devs = [p["dev"] for p in payload["points"]]
    assert curve["minimum"]["dev"] == min(devs)
    assert curve["minimum"]["ci_low"] <= curve["minimum"]["dev"] <= curve["minimum"]["ci_high"]
    assert curve["regions"]["A"][0] == payload["points"][0]["tau"]
    assert curve["dominant"][0]["term"] == "N" and curve["dominant"][0]["slope"] == -0.5
    assert "curve of rate" in res.stderr  # tables go to stderr when JSON goes to stdout


def test_overlay_bad_second_file(two_gyros: tuple[Path, Path], tmp_path: Path) -> None:
    res = runner.invoke(app, ["allan", str(two_gyros[0]), str(tmp_path / "missing.csv"),
                              "--json", str(tmp_path / "x.json")])
    assert res.exit_code == 2
    assert error_output(res.stderr).startswith("error: file not found")
    assert not (tmp_path / "x.json").exists()
