"""``fogts allan --method wls,gmwm,ml`` (issue 15): the first method is the fit every
existing output carries (the JSON of a single-method run is unchanged), and every
method's terms appear side by side in the JSON (``methods``), the text and the HTML
report; each bad ``--method`` is one error line naming the option and the value."""

from __future__ import annotations

import json
from pathlib import Path

import pytest
from typer.testing import CliRunner

from fogts.cli import app
from fogts.errors import DataError
from fogts.io.reader import read_run
from fogts.report.html import build_report
from tests.cli.conftest import FS, N_TRUE

runner = CliRunner()


def _run(args: list[object], command: str = "allan") -> tuple[int, str, str]:
    res = runner.invoke(app, [command, *[str(a) for a in args]])
    return res.exit_code, res.stdout, res.stderr


#: N and K only: ML's model then has no Gauss-Markov search (a fraction of a second).
COMMON = ["--fs", FS, "--units", "deg/h", "--terms", "N,K"]


@pytest.fixture(scope="module")
def three(gyro_npy: Path, tmp_path_factory: pytest.TempPathFactory
          ) -> tuple[dict[str, object], dict[str, object], str, str]:
    """(JSON of --method wls,gmwm,ml, JSON of --method wls, its text, its stderr)."""
    out = tmp_path_factory.mktemp("json")
    code, stdout, stderr = _run([gyro_npy, *COMMON, "--method", "wls,gmwm,ml",
                                 "--json", out / "three.json"])
    assert code == 0, stderr
    code1, _, err1 = _run([gyro_npy, *COMMON, "--json", out / "one.json"])
    assert code1 == 0, err1
    return (json.loads((out / "three.json").read_text()),
            json.loads((out / "one.json").read_text()), stdout, stderr)


def test_the_primary_fit_is_the_single_method_run(
        three: tuple[dict[str, object], dict[str, object], str, str]) -> None:
    """Every key of the single-method JSON is there with the same content (the same
    computation, so the same numbers); ``methods`` is the one key added (and its
    deprecated top-level copy)."""
    doc, single, _, _ = three
    assert "methods" not in single["axes"][0]  # type: ignore[index]
    axis = dict(doc["axes"][0])  # type: ignore[index]
    methods = axis.pop("methods")
    assert axis == single["axes"][0]  # type: ignore[index]
    assert doc["summary"] == single["summary"]
    assert methods["primary"] == "wls" and methods["order"] == ["wls", "gmwm", "ml"]


def test_the_methods_block_holds_every_fit(
        three: tuple[dict[str, object], dict[str, object], str, str]) -> None:
    """N within 3 % of the truth by each method (40 min at 100 Hz: N's standard error is
    about 0.2 %, so 3 % is over ten of them and catches a unit or factor slip), with a
    standard error; the WLS column is the primary ``noise`` block."""
    doc, _, _, _ = three
    axis = doc["axes"][0]  # type: ignore[index]
    block = axis["methods"]
    assert set(block["terms"]) == {"N", "K"}
    for method in ("wls", "gmwm", "ml"):
        n = block["terms"]["N"][method]
        assert n["measured"] and n["value"] == pytest.approx(N_TRUE, rel=0.03)
        assert 0 < n["stderr"] < 0.01 * N_TRUE
    assert block["terms"]["N"]["wls"]["value"] == pytest.approx(
        axis["noise"]["N"]["value"], rel=1e-15)  # a copy of the same fit
    assert block["models"]["ml"] == "N + K"


def test_the_text_has_the_side_by_side_table(
        three: tuple[dict[str, object], dict[str, object], str, str]) -> None:
    _, _, stdout, stderr = three
    assert "Noise terms of rate by method, side by side" in stdout
    assert "WLS (primary)" in stdout and "GMWM" in stdout and "ML" in stdout
    assert "IEEE-952 noise terms of rate (WLS fit" in stdout  # the primary's own table
    assert "axis 'rate': method" not in stderr  # a second fit's warning names its method


@pytest.mark.parametrize(("value", "shown"), [
    ("nope", "'nope' is not one of 'wls', 'gls', 'ols', 'gmwm', 'ml'."),
    ("wls,nope", "'nope' is not one of 'wls', 'gls', 'ols', 'gmwm', 'ml' (in 'wls,nope'; "
                 "several methods are separated by commas)"),
    ("wls,gmwm,wls", "'wls' is given twice in 'wls,gmwm,wls'; give each method once"),
    (",", "',' names no method; give one or more of 'wls', 'gls', 'ols', 'gmwm', 'ml', "
          "separated by commas"),
    ("wls,,gmwm", "'' is not one of 'wls', 'gls', 'ols', 'gmwm', 'ml' (in 'wls,,gmwm'"),
])
@pytest.mark.parametrize("command", ["allan", "report"])
def test_a_bad_method_is_one_error_line(gyro_npy: Path, tmp_path: Path, value: str,
                                        shown: str, command: str) -> None:
    extra = ["-o", tmp_path / "r.html"] if command == "report" else []
    code, out, err = _run([gyro_npy, "--fs", FS, *extra, "--method", value], command)
    assert code == 2, (out, err)
    lines = err.strip().splitlines()
    assert len(lines) == 1 and "Traceback" not in err
    assert lines[0].startswith(f"error: Invalid value for '--method': {shown}")
    assert not (tmp_path / "r.html").exists()


def test_ml_beside_a_fit_range_is_refused(gyro_npy: Path) -> None:
    code, _, err = _run([gyro_npy, *COMMON, "--method", "wls,ml", "--fit-tau-min", "1"])
    assert code == 2
    assert "--fit-tau-min/--fit-tau-max do not apply to --method 'ml'" in err


def test_the_report_shows_the_methods_side_by_side(gyro_npy: Path) -> None:
    run = read_run(gyro_npy, fs_hz=FS, units="deg/h")
    one = build_report(run, parts=("allan",)).render()
    assert "by method, side by side" not in one
    html = build_report(run, parts=("allan",), methods=("gmwm", "wls")).render()
    assert "Noise terms of rate by method, side by side" in html
    assert "GMWM (primary)" in html and "(GMWM fit of oadev" in html


@pytest.mark.parametrize(("methods", "match"), [
    ((), r"methods must name one or more of wls, gls, ols, gmwm, ml, got \(\)"),
    (("wls", "lsq"), "methods must be one of wls, gls, ols, gmwm, ml; got 'lsq'"),
    (("wls", "gmwm", "wls"), r"methods must name each method once; 'wls' is given twice in "
                             r"\('wls', 'gmwm', 'wls'\)"),
])
def test_build_report_bad_methods(gyro_npy: Path, methods: tuple[str, ...],
                                  match: str) -> None:
    run = read_run(gyro_npy, fs_hz=FS, units="deg/h")
    with pytest.raises(DataError, match=match):
        build_report(run, parts=("allan",), methods=methods)
