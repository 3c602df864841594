"""CLI tests of ``fogts simulate`` and ``fogts davar`` (typer CliRunner on fogts.cli.app)."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pandas as pd
import pytest
from typer.testing import CliRunner

from fogts.cli import app
from fogts.io.reader import read_run
from fogts.simulate.gyro import NoiseSpec

runner = CliRunner()


def _simulate(tmp_path: Path, *args: str, name: str = "sim.csv") -> Path:
    out = tmp_path / name
    res = runner.invoke(app, ["simulate", "noise", *args, "-o", str(out)])
    assert res.exit_code == 0, res.output
    return out


def test_simulate_csv_with_sidecar(tmp_path: Path) -> None:
    out = _simulate(tmp_path, "--fs", "10", "--duration", "10min", "--N", "0.01", "--B", "0.02",
                    "--K", "0.1", "--R", "1", "--Q", "0.5", "--markov", "0.1,5",
                    "--sine", "0.05,0.2", "--arma", "ar=0.5;sigma2=1e-4", "--bias", "8",
                    "--seed", "7")
    run = read_run(out)
    assert run.n == 6000 and run.fs_hz == pytest.approx(10.0) and run.axes == ("rate",)
    assert run.columns == ("time", "rate") and run.units == "deg/h"
    side = json.loads(Path(str(out) + ".json").read_text())
    assert side["seed"] == 7 and side["n"] == 6000 and side["fs_hz"] == 10.0
    assert side["noise"]["N"]["value"] == 0.01 and side["noise"]["T_c"]["value"] == 5.0
    assert side["noise"]["Omega_0"]["value"] == 0.05 and side["arma"]["ar"] == [0.5]
    spec = NoiseSpec.from_any(side)  # the sidecar feeds straight back into NoiseSpec
    assert spec == NoiseSpec(Q=0.5, N=0.01, B=0.02, K=0.1, R=1, q_c=0.1, T_c=5,
                             Omega_0=0.05, f_0=0.2, bias=8)
    np.testing.assert_allclose(side["closed_form"]["dev"],
                               spec.adev(side["closed_form"]["tau"]), rtol=1e-12)
    # same seed -> byte-identical output
    again = _simulate(tmp_path, "--fs", "10", "--duration", "10min", "--N", "0.01", "--B",
                      "0.02", "--K", "0.1", "--R", "1", "--Q", "0.5", "--markov", "0.1,5",
                      "--sine", "0.05,0.2", "--arma", "ar=0.5;sigma2=1e-4", "--bias", "8",
                      "--seed", "7", name="again.csv")
    assert again.read_bytes() == out.read_bytes()


def test_simulate_parquet_axes_temperature_and_units(tmp_path: Path) -> None:
    out = _simulate(tmp_path, "--fs", "5", "--duration", "20min", "--N", "0.01", "--axes", "3",
                    "--temperature-profile", "warmup:20,30,5min", "--thermal", "T=0.1,dT=5",
                    "--units", "deg/s", "--seed", "1", "--decimals", "6", name="sim.parquet")
    frame = pd.read_parquet(out)
    assert list(frame.columns) == ["time", "rate_x", "rate_y", "rate_z", "temperature"]
    run = read_run(out, units="deg/s")
    assert run.n == 6000 and run.n_axes == 3 and run.temperature is not None
    assert run.temperature[0] == 20.0
    # the thermal drift (~2-3 deg/h = ~7e-4 deg/s) shows in the mean rate
    assert np.mean(run.rate) == pytest.approx(np.mean(0.1 * run.temperature) / 3600, rel=0.05)
    side = json.loads(Path(str(out) + ".json").read_text())
    assert side["temperature_profile"]["kind"] == "warmup"
    assert side["thermal_coefficients"] == {"T": 0.1, "dT": 5.0}
    assert side["units"] == "deg/s" and side["decimals"] == 6


def test_simulate_from_json_and_random_seed(tmp_path: Path) -> None:
    noise = tmp_path / "noise.json"
    noise.write_text(json.dumps({"noise": {"N": {"value": 0.002, "unit": "deg/sqrt(h)"},
                                           "B": {"value": 0.01}}}))
    out = _simulate(tmp_path, "--duration", "60s", "--from-json", str(noise), "--K", "0.3")
    side = json.loads(Path(str(out) + ".json").read_text())
    assert side["noise"]["N"]["value"] == 0.002 and side["noise"]["B"]["value"] == 0.01
    assert side["noise"]["K"]["value"] == 0.3
    assert isinstance(side["seed"], int) and side["seed"] >= 0  # a fresh seed is recorded
    res = runner.invoke(app, ["simulate", "noise", "--duration", "60s", "--from-json", str(noise),
                              "--K", "0.3", "--seed", str(side["seed"]), "-o",
                              str(tmp_path / "replay.csv")])
    assert res.exit_code == 0
    assert (tmp_path / "replay.csv").read_bytes() == out.read_bytes()


@pytest.mark.parametrize("args, message", [
    (["--duration", "3parsecs"], "--duration has an unknown unit 'parsecs'"),
    (["--duration", "10s", "--markov", "1"], "--markov must be two numbers 'q_c,T_c'"),
    (["--duration", "10s", "--sine", "a,b"], "--sine must be two numbers"),
    (["--duration", "10s", "--thermal", "T:1"], "--thermal must look like"),
    (["--duration", "10s", "--thermal", "T=1"], "need a temperature profile"),
    (["--duration", "10s", "--temperature-profile", "hot"], "temperature profile must be"),
    (["--duration", "10s", "--arma", "ar=2;sigma2=1"], "AR part is not stationary"),
    (["--duration", "10s", "--N", "-1"], "must be >= 0"),
    (["--duration", "10s", "--decimals", "20"], "--decimals must be in 0..15"),
    (["--duration", "10s", "--flicker", "pink"], "'pink' is not one of 'markov', 'kasdin'. (see 'fogts simulate noise --help')"),
    (["--duration", "10s", "--units", "mph"], "units must be one of"),
    (["--duration", "10s", "--fs", "0"], "--fs must be a finite number > 0"),
    (["--duration", "10s", "--sine", "1,80"], "below the Nyquist frequency"),
])
def test_simulate_bad_input(tmp_path: Path, args: list[str], message: str) -> None:
    res = runner.invoke(app, ["simulate", "noise", *args, "-o", str(tmp_path / "x.csv")])
    assert res.exit_code == 2
    assert message in res.output + res.stderr
    assert "Traceback" not in res.output + res.stderr
    assert not (tmp_path / "x.csv").exists()


def test_simulate_bad_output_and_json(tmp_path: Path) -> None:
    res = runner.invoke(app, ["simulate", "noise", "--duration", "10s", "-o", str(tmp_path / "x.xlsx")])
    assert res.exit_code == 2 and "--output must end in .csv" in res.stderr
    res = runner.invoke(app, ["simulate", "noise", "--duration", "10s", "-o",
                              str(tmp_path / "missing" / "x.csv")])
    assert res.exit_code == 2 and "missing' does not exist; create it first" in res.stderr
    bad = tmp_path / "bad.json"
    bad.write_text("{not json")
    res = runner.invoke(app, ["simulate", "noise", "--duration", "10s", "--from-json", str(bad), "-o",
                              str(tmp_path / "x.csv")])
    assert res.exit_code == 2 and "is not valid JSON" in res.stderr


# --------------------------------------------------------------------------- davar
@pytest.fixture
def step_file(tmp_path: Path) -> Path:
    y = np.random.default_rng(2).normal(size=24_000) * 0.1
    y[12_000:] *= 2.0  # the level doubles at t = 1200 s
    path = tmp_path / "step.csv"
    pd.DataFrame({"time": np.arange(y.size) / 10.0, "rate": y}).to_csv(path, index=False)
    return path


def test_davar_json_contract_and_plot(step_file: Path, tmp_path: Path) -> None:
    target, plot = tmp_path / "davar.json", tmp_path / "davar.png"
    res = runner.invoke(app, ["davar", str(step_file), "--window", "200s", "--step", "20s",
                              "--json", str(target), "--plot", str(plot)])
    assert res.exit_code == 0, res.output
    doc = json.loads(target.read_text())
    assert {"input", "kind", "window_s", "step_s", "taus", "times", "dev",
            "nonstationarity"} <= set(doc)
    # fs comes from the time column (10 Hz to ~1e-13), so window_s is 200 s to rounding
    assert doc["input"] == str(step_file) and doc["window_s"] == pytest.approx(200.0)
    assert len(doc["dev"]) == len(doc["times"]) == 111 and len(doc["dev"][0]) == len(doc["taus"])
    ns = doc["nonstationarity"]
    assert ns["stationary"] is False and abs(ns["change_time"] - 1200.0) <= 20.0
    assert plot.stat().st_size > 10_000
    assert "NOT stationary" in res.stdout


def test_davar_json_to_stdout_and_seed_window(step_file: Path) -> None:
    res = runner.invoke(app, ["davar", str(step_file), "--window", "201s", "--step", "1min",
                              "--taus", "0.1,1,10", "--json", "-"])
    assert res.exit_code == 0
    doc = json.loads(res.stdout)
    assert doc["taus"] == pytest.approx([0.1, 1.0, 10.0])
    assert doc["window_s"] == pytest.approx(201.0) and doc["step_s"] == pytest.approx(60.0)


def test_davar_multi_axis(tmp_path: Path) -> None:
    out = _simulate(tmp_path, "--fs", "10", "--duration", "20min", "--N", "0.01", "--axes", "3",
                    "--seed", "3")
    target = tmp_path / "d.json"
    res = runner.invoke(app, ["davar", str(out), "--window", "2min", "--step", "1min",
                              "--json", str(target)])
    assert res.exit_code == 0, res.output
    doc = json.loads(target.read_text())
    assert doc["axes"] == ["rate_x", "rate_y", "rate_z"] and len(doc["curves"]) == 3
    assert all(c["nonstationarity"]["stationary"] for c in doc["curves"])
    res = runner.invoke(app, ["davar", str(out), "--window", "2min", "--step", "1min",
                              "--axis", "1", "--json", "-"])
    assert res.exit_code == 0 and json.loads(res.stdout)["axis"] == "rate_y"


@pytest.mark.parametrize("args, message", [
    (["--window", "two minutes"], "--window must look like 3h"),
    (["--step", "-5s"], "--step must look like"),
    (["--window", "1d"], "longer than the record"),
    (["--taus", "x,y"], "--taus must be octave, decade, dense, all or taus in seconds"),
    (["--kind", "theo1"], "Invalid value for '--kind': 'theo1' is not one of 'adev'"),
    (["--plot", "out.gif"], "--plot must end in .png, .svg or .pdf"),
    (["--axis", "q"], "axis 'q' not found"),
])
def test_davar_bad_input(step_file: Path, tmp_path: Path, args: list[str],
                         message: str) -> None:
    args = [str(tmp_path / a) if a.endswith(".gif") else a for a in args]
    res = runner.invoke(app, ["davar", str(step_file), *args])
    assert res.exit_code == 2
    assert message in res.stderr and "Traceback" not in res.output + res.stderr


def test_davar_missing_file(tmp_path: Path) -> None:
    res = runner.invoke(app, ["davar", str(tmp_path / "nope.csv")])
    assert res.exit_code == 2 and res.stderr.startswith("error: ")


@pytest.mark.parametrize(("args", "says", "keyword"), [
    (["davar", "{file}", "--window", "1000s"],
     "--window 1000 s (10000 samples) is longer than the record", "window_s"),
    (["davar", "{file}", "--window", "0.2s"], "--window 0.2 s is 2 sample(s) at 10 Hz", "window_s"),
    (["davar", "{file}", "--window", "20s", "--step", "0s"], "--step must be > 0", "step_s"),
    (["simulate", "noise", "-o", "{out}", "--axes", "0"], "--axes must be >= 1, got 0", "n_axes"),
])
def test_errors_name_the_option_typed(tmp_path: Path, args: list[str], says: str,
                                      keyword: str) -> None:
    # audit2: these errors named the library's keyword (window_s=1e+09 s, n_axes must be ...)
    file = _simulate(tmp_path, "--fs", "10", "--duration", "5min", "--N", "0.01")
    out = tmp_path / "new.csv"
    res = runner.invoke(app, [a.format(file=file, out=out) for a in args])
    assert res.exit_code == 2, res.output
    lines = [ln for ln in res.stderr.splitlines() if ln.startswith("error: ")]
    assert len(lines) == 1 and says in lines[0] and keyword not in lines[0], res.stderr
    assert not out.exists()


def test_from_json_warns_of_a_term_the_fit_only_bounds_unless_it_is_given(
        tmp_path: Path) -> None:
    # audit2: an allan JSON's K given as '< 1.34' was simulated at its fitted 0.787 silently
    doc = tmp_path / "allan.json"
    doc.write_text(json.dumps({"noise": {
        "N": {"value": 0.05, "upper_limit_95": None},
        "K": {"value": 0.7872, "upper_limit_95": 1.345}}}))
    out = tmp_path / "a.csv"
    res = runner.invoke(app, ["simulate", "noise", "-o", str(out), "--from-json", str(doc),
                              "--duration", "1min", "--seed", "1"])
    assert res.exit_code == 0, res.output
    assert "warning: the fit did not measure K = 0.7872 (its 95 % upper limit is 1.345)" \
        in res.stderr
    out2 = tmp_path / "b.csv"
    res = runner.invoke(app, ["simulate", "noise", "-o", str(out2), "--from-json", str(doc),
                              "--K", "0.3", "--duration", "1min", "--seed", "1"])
    assert res.exit_code == 0, res.output
    assert "did not measure" not in res.stderr
    assert json.loads((tmp_path / "b.csv.json").read_text())["noise"]["K"]["value"] == 0.3


def test_a_stray_argument_to_simulate_noise_is_named(tmp_path: Path) -> None:
    """audit2 N14: ``simulate noise out.csv`` said only that --output is missing; the error
    names the stray argument and what the command takes, and writes nothing."""
    from tests.conftest import error_output

    out = tmp_path / "out.csv"
    res = runner.invoke(app, ["simulate", "noise", str(out), "--N", "0.1"])
    assert res.exit_code == 2 and not out.exists()
    assert error_output(res.stderr) == (
        f"error: unexpected argument(s) '{out}': fogts simulate noise takes no positional "
        "argument; missing option '--output' / '-o'. (see 'fogts simulate noise --help')")
    res = runner.invoke(app, ["simulate", "noise", "-o", str(out), "stray"])
    assert res.exit_code == 2 and "(stray)" in res.stderr and not out.exists()
    res = runner.invoke(app, ["filter", "x.csv", "y.csv"])
    assert res.exit_code == 2 and "unexpected argument(s) 'y.csv': fogts filter takes only " \
        "FILE; missing option" in res.stderr
