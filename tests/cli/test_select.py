"""``fogts select``: exit codes 0/1/2, the JSON contract, --predict CSV, --plot, no tracebacks."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pandas as pd
import pytest
from scipy.signal import lfilter
from typer.testing import CliRunner

from fogts.cli import app

runner = CliRunner()
CONTRACT_KEYS = {"model", "p", "q", "status", "rank", "aic", "bic", "llf", "sigma2", "params",
                 "bse", "rho_a2", "rho_ax3", "ljung_box", "white", "roots", "warnings"}


def _write(path: Path, x: np.ndarray, fs: float = 10.0, column: str = "rate_deg_s") -> Path:
    pd.DataFrame({"time": np.arange(x.size) / fs, column: x}).to_csv(path, index=False)
    return path


def _arma(ar: list[float], ma: list[float], n: int, seed: int, scale: float = 1e-3) -> np.ndarray:
    e = np.random.default_rng(seed).standard_normal(n + 1000) * scale
    return np.asarray(lfilter(np.r_[1.0, ma], np.r_[1.0, -np.asarray(ar)], e)[1000:])


@pytest.fixture(scope="module")
def ar1_file(tmp_path_factory: pytest.TempPathFactory) -> Path:
    x = _arma([0.6], [], 3000, 1) + 0.02 + 1e-6 * np.arange(3000)
    return _write(tmp_path_factory.mktemp("sel") / "fog.csv", x)


def test_select_ok_writes_json_predict_and_plot(ar1_file: Path, tmp_path: Path) -> None:
    out_json, out_csv, out_png = tmp_path / "s.json", tmp_path / "pred.csv", tmp_path / "s.png"
    res = runner.invoke(app, ["select", str(ar1_file), "--detrend", "1", "--json", str(out_json),
                              "--predict", str(out_csv), "--plot", str(out_png)])
    assert res.exit_code == 0, res.output
    out = res.stdout
    assert "3,000 samples of 'rate_deg_s' at 10 Hz" in out
    assert "removed a polynomial trend of order 1" in out
    assert "ACF/PACF" in out and "PACF cuts off after lag 1" in out
    # the mean is estimated (GLS): the equation is written in y_t = x_t - mean
    assert "y_t = 0." in out and "y_{t-1} + a_t," in out and "y_t = x_t " in out
    assert "verdict   AR(1) describes the drift" in out
    doc = json.loads(out_json.read_text())
    assert {"input", "preprocessing", "candidates", "selected"} <= set(doc)
    assert doc["input"]["file"] == str(ar1_file)
    assert doc["input"]["fs_hz"] == pytest.approx(10.0, rel=1e-12)
    assert doc["preprocessing"]["detrend"]["order"] == 1
    assert doc["candidates"][0]["model"] == doc["selected"]["model"] == "AR(1)"
    for c in doc["candidates"]:
        assert CONTRACT_KEYS <= set(c)
        assert [set(lb) >= {"lag", "q", "pvalue"} for lb in c["ljung_box"]] == [True, True]
    pred = pd.read_csv(out_csv)
    assert list(pred.columns) == ["time", "observed", "predicted", "residual"]
    assert len(pred) == 3000 and pred["time"].iloc[1] == pytest.approx(0.1)
    # on the input's scale: the removed line added back to the data and to the prediction
    rate = pd.read_csv(ar1_file)["rate_deg_s"].to_numpy()
    assert np.allclose(pred["observed"], rate, rtol=0.0, atol=1e-15)
    assert np.allclose(pred["observed"] - pred["predicted"], pred["residual"], rtol=0.0,
                       atol=1e-15)
    assert out_png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


@pytest.mark.parametrize("args", [[], ["--decimate", "3"]])
def test_select_predict_is_on_the_input_scale(ar1_file: Path, tmp_path: Path,
                                              args: list[str]) -> None:
    """The mean removed before the fit is added back to ``observed`` and ``predicted`` (the
    rates as read, block means with --decimate), as ``fogts filter -o`` writes them."""
    out_csv = tmp_path / "pred.csv"
    res = runner.invoke(app, ["select", str(ar1_file), "--candidates", "AR(1)",
                              "--predict", str(out_csv), *args])
    assert res.exit_code in (0, 1), res.output   # 1: the file's slow ramp is left in
    pred = pd.read_csv(out_csv)
    rate = pd.read_csv(ar1_file)["rate_deg_s"].to_numpy()
    k = int(args[1]) if args else 1
    expected = rate[: rate.size // k * k].reshape(-1, k).mean(axis=1)
    # |rate| < 0.03: the mean subtracted and added back moves a value by a few ulp of 0.03
    assert np.allclose(pred["observed"], expected, rtol=0.0, atol=1e-15)
    assert abs(pred["predicted"].mean() - expected.mean()) < 0.1 * expected.std()
    assert np.allclose(pred["observed"] - pred["predicted"], pred["residual"], rtol=0.0,
                       atol=1e-15)


def test_select_json_to_stdout_is_pure_and_deterministic(ar1_file: Path) -> None:
    a = runner.invoke(app, ["select", str(ar1_file), "--detrend", "1", "--json", "-"])
    b = runner.invoke(app, ["select", str(ar1_file), "--detrend", "1", "--json", "-"])
    assert a.exit_code == 0, a.output
    assert json.loads(a.stdout)["selected"]["model"] == "AR(1)"
    assert a.stdout == b.stdout
    assert "verdict" in a.stderr      # the human-readable report moves to stderr


def test_select_not_white_exits_1(tmp_path: Path) -> None:
    f = _write(tmp_path / "ar3.csv", _arma([0.5, -0.3, 0.3], [], 4000, 2))
    res = runner.invoke(app, ["select", str(f), "--candidates", "AR(1),ARMA(1,1)",
                              "--criterion", "bic"])
    assert res.exit_code == 1, res.output
    assert "ranked by BIC" in res.stdout
    assert "No candidate leaves white residuals" in res.stdout
    assert "warning: ar3.csv: rate_deg_s: no candidate leaves white residuals" in res.stderr


def test_select_explosive_exits_1_with_failed_rows(tmp_path: Path) -> None:
    e = np.random.default_rng(0).standard_normal(300)
    f = _write(tmp_path / "boom.csv", lfilter([1.0], [1.0, -1.1], e))
    res = runner.invoke(app, ["select", str(f), "--predict", str(tmp_path / "p.csv"),
                              "--plot", str(tmp_path / "boom.svg")])
    assert res.exit_code == 1, res.output
    assert (tmp_path / "boom.svg").read_text().lstrip().startswith("<?xml")
    assert "failed" in res.stdout and "explosive" in res.stdout
    assert "No candidate could be fitted" in res.stdout
    assert not (tmp_path / "p.csv").exists()
    assert "Traceback" not in res.output


@pytest.mark.parametrize(("args", "message"), [
    (["--candidates", "ARMA(1)"], "error: candidates: 'ARMA(1)' needs two orders"),
    (["--criterion", "aik"], "error: Invalid value for '--criterion': 'aik' is not one of "
                             "'aic', 'bic', 'hqic', 'aicc'."),
    (["--plot", "fig.jpg"], "error: --plot must end in .png, .svg or .pdf"),
    (["--axis", "yaw"], "error: --axis 'yaw' not found; axes are: rate_deg_s"),
    (["--axis", "3"], "error: --axis must be an axis name or an index in -1..0, got 3; "
                      "axes are: rate_deg_s"),
    (["--predict", "out.xlsx"],
     "error: --predict must end in .csv, .csv.gz, .tsv, .txt or .parquet; got 'out.xlsx'"),
])
def test_select_bad_options_exit_2(ar1_file: Path, tmp_path: Path, args: list[str],
                                   message: str) -> None:
    args = [str(tmp_path / a) if a.endswith((".jpg", ".xlsx")) else a for a in args]
    res = runner.invoke(app, ["select", str(ar1_file), *args])
    assert res.exit_code == 2, res.output
    assert message in res.stderr
    assert "Traceback" not in res.output


def test_select_bad_data_exit_2(tmp_path: Path) -> None:
    const = _write(tmp_path / "const.csv", np.full(500, 1.5))
    res = runner.invoke(app, ["select", str(const)])
    assert res.exit_code == 2 and "error: " in res.stderr and "constant" in res.stderr
    short = _write(tmp_path / "short.csv", _arma([0.5], [], 30, 3))
    res = runner.invoke(app, ["select", str(short)])
    assert res.exit_code == 2 and f"error: axis 'rate_deg_s' of {short} is too short for " \
        "ARMA selection: 30 samples" in res.stderr
    res = runner.invoke(app, ["select", str(tmp_path / "missing.csv")])
    assert res.exit_code == 2 and res.stderr.startswith("error: ")
    assert "Traceback" not in res.output


def test_stationarity_line_says_it_tests_the_level(ar1_file: Path, tmp_path: Path) -> None:
    """The terminal prints the ADF/KPSS verdict as a test of the level (the mean), not of the
    noise level; the JSON carries that sentence in ``stationarity.summary`` and in
    ``steps``."""
    out_json = tmp_path / "s.json"
    res = runner.invoke(app, ["select", str(ar1_file), "--detrend", "1", "--json",
                              str(out_json)])
    assert res.exit_code == 0, res.output
    pre = json.loads(out_json.read_text())["preprocessing"]
    sentence = pre["stationarity"]["summary"]
    assert sentence.startswith(f"level: {pre['stationarity']['verdict']} (ADF p")
    assert sentence.endswith("; tests the mean, not the noise level)")
    assert sentence in res.stdout and "stationarity:" not in res.stdout
    assert list(pre["stationarity"])[-1] == "summary"  # added last: the other keys keep order
    assert pre["steps"][-1] == sentence
