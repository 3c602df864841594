"""``--axis`` of select, compensate and filter (fogts.cli._axes): the default names the
axis it used, ``--axis all`` gives each axis what ``--axis NAME`` gives it alone, figures
and saved models get per-axis names, tables an axis column."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pandas as pd
import pytest
from scipy.signal import lfilter
from typer.testing import CliRunner

from fogts.cli import app
from fogts.cli._axes import axis_path
from fogts.io.reader import read_run
from fogts.startup.simulator import simulate_startup
from tests.conftest import error_output

runner = CliRunner()


@pytest.fixture(scope="module")
def two_axes(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """Two AR(1) drifts (phi 0.9 and 0.5), 10 Hz, named 'gyro x' and 'gyro y'."""
    rng = np.random.default_rng(16)
    cols = {}
    for name, phi in (("gyro x", 0.9), ("gyro y", 0.5)):
        cols[name] = lfilter([1.0], [1.0, -phi], rng.normal(0, 0.2, 1500))
    path = tmp_path_factory.mktemp("axes") / "imu.csv"
    pd.DataFrame({"time": np.arange(1500) * 0.1, **cols}).to_csv(path, index=False)
    return path


def _invoke(args: list[object]) -> tuple[int, str, str]:
    res = runner.invoke(app, [str(a) for a in args])
    return res.exit_code, res.stdout, res.stderr


def test_select_default_names_the_first_axis(two_axes: Path) -> None:
    code, out, err = _invoke(["select", two_axes, "--candidates", "AR(1)"])
    assert code in (0, 1), err
    assert "axis      'gyro x' (default: the first of 2: gyro x, gyro y; choose with --axis " \
           "NAME, INDEX or all)" in out


def test_select_all_is_each_axis_alone(two_axes: Path, tmp_path: Path) -> None:
    pred, png = tmp_path / "pred.csv", tmp_path / "sel.png"
    code, out, err = _invoke(["select", two_axes, "--axis", "all", "--json", tmp_path / "a.json",
                              "--candidates", "AR(1),AR(2)", "--predict", pred, "--plot", png])
    assert code in (0, 1), err
    assert "axes      all 2: gyro x, gyro y" in out
    doc = json.loads((tmp_path / "a.json").read_text())
    assert [a["input"]["axis"] for a in doc["axes"]] == ["gyro x", "gyro y"]
    for k, name in enumerate(("gyro x", "gyro y")):
        code, single, _ = _invoke(["select", two_axes, "--axis", name, "--json", "-",
                                   "--candidates", "AR(1),AR(2)"])
        alone = json.loads(single)
        assert doc["axes"][k]["candidates"] == alone["candidates"]
    # AR(1) phi of each axis: 0.9 and 0.5 within 0.1 (1500 samples: se ~ 0.02)
    phis = [next(c for c in a["candidates"] if c["model"] == "AR(1)")["params"]["ar.L1"]
            for a in doc["axes"]]
    assert phis == pytest.approx([0.9, 0.5], abs=0.1)
    frame = pd.read_csv(pred)
    assert list(frame.columns) == ["axis", "time", "observed", "predicted", "residual"]
    assert frame["axis"].value_counts().to_dict() == {"gyro x": 1500, "gyro y": 1500}
    assert (tmp_path / "sel_gyro_x.png").stat().st_size > 1000
    assert (tmp_path / "sel_gyro_y.png").stat().st_size > 1000 and not png.exists()


def test_filter_all_is_each_axis_alone(two_axes: Path, tmp_path: Path) -> None:
    out_all, out_one = tmp_path / "all.csv", tmp_path / "one.csv"
    code, text, err = _invoke(["filter", two_axes, "--axis", "all", "--method", "iir",
                               "--cutoff", "1", "-o", out_all, "--json", tmp_path / "f.json"])
    assert code == 0, err
    assert "axes      all 2: gyro x, gyro y" in text
    code, _, err = _invoke(["filter", two_axes, "--axis", "1", "--method", "iir",
                            "--cutoff", "1", "-o", out_one])
    assert code == 0, err
    both, one = pd.read_csv(out_all), pd.read_csv(out_one)
    assert list(both.columns) == ["axis", "time", "observed", "filtered"]
    y = both[both["axis"] == "gyro y"].reset_index(drop=True)
    np.testing.assert_allclose(y["filtered"], one["filtered"], rtol=1e-12, atol=1e-15)
    doc = json.loads((tmp_path / "f.json").read_text())
    assert [a["axis"] for a in doc["axes"]] == ["gyro x", "gyro y"]
    code, text, _ = _invoke(["filter", two_axes, "--method", "iir", "--cutoff", "1",
                             "-o", out_one, "--overwrite"])
    assert "axis      'gyro x' (default: the first of 2" in text


def test_compensate_all_fits_a_model_per_axis(tmp_path: Path) -> None:
    sim = simulate_startup(duration_s=1800.0, ambient_degC=20.0, rng=4)
    src = tmp_path / "warm.csv"
    pd.DataFrame({"time": sim.run.time, "a": sim.run.rate, "b": -2.0 * sim.run.rate,
                  "temperature": sim.run.temperature}).to_csv(src, index=False)
    model = tmp_path / "m.json"
    code, _, err = _invoke(["compensate", src, "--axis", "all", "--no-emd", "--rate-column",
                              "a,b", "--save-model",
                              model, "--json", tmp_path / "c.json", "-o", tmp_path / "c.csv"])
    assert code == 0, err
    doc = json.loads((tmp_path / "c.json").read_text())
    assert [a["axis"] for a in doc["axes"]] == ["a", "b"]
    # b = -2 a: every coefficient of b's model is -2 times a's (a linear least-squares fit)
    ta, tb = (doc["axes"][k]["thermal"]["terms"] for k in (0, 1))
    for term, v in ta.items():
        if v["value"] is not None:
            assert tb[term]["value"] == pytest.approx(-2 * v["value"], rel=1e-6, abs=1e-9)
    assert (tmp_path / "m_a.json").exists() and (tmp_path / "m_b.json").exists()
    assert set(pd.read_csv(tmp_path / "c.csv")["axis"]) == {"a", "b"}
    code, _, err = _invoke(["compensate", src, "--axis", "all", "--rate-column", "a,b",
                            "--model", tmp_path / "m_a.json"])
    assert code == 2
    assert error_output(err) == ("error: --model holds the thermal model of one axis: give "
                                 "--axis NAME or INDEX, not --axis all")
    # the per-axis model files are outputs too: an existing one needs --overwrite
    before = (tmp_path / "m_b.json").read_bytes()
    args = ["compensate", src, "--axis", "all", "--no-emd", "--rate-column", "a,b",
            "--save-model", model]
    code, _, err = _invoke(args)
    assert code == 2 and error_output(err).startswith(
        f"error: --save-model (a) '{tmp_path / 'm_a.json'}' already exists; fogts replaces")
    assert (tmp_path / "m_b.json").read_bytes() == before
    code, _, err = _invoke([*args, "--overwrite"])
    assert code == 0, err


def test_axis_paths(tmp_path: Path) -> None:
    rng = np.random.default_rng(0)
    run = read_run(rng.normal(size=(50, 3)), fs_hz=1.0)
    names = [axis_path(tmp_path / "p.csv.gz", run, i, True).name for i in range(3)]
    assert names == [f"p_{a}.csv.gz" for a in run.axes]
    assert axis_path(tmp_path / "p.png", run, 1, False) == tmp_path / "p.png"
    clash = read_run(pd.DataFrame({"g x": rng.normal(size=50), "g.x": rng.normal(size=50)}),
                     fs_hz=1.0, rate_column=["g x", "g.x"])
    assert [axis_path(Path("f.svg"), clash, i, True).name for i in range(2)] == [
        "f_1_g_x.svg", "f_2_g_x.svg"]
