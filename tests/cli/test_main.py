"""CLI shell tests: --version, info, one-line errors with exit code 2 and no traceback."""

from __future__ import annotations

import json
import re
import subprocess
import sys
from pathlib import Path

import pytest
from typer.testing import CliRunner

from fogts._version import __version__
from fogts.cli import app, main
from tests.conftest import shared_path

runner = CliRunner()


def _run_main(args: list[str], capsys: pytest.CaptureFixture[str]) -> tuple[int, str, str]:
    with pytest.raises(SystemExit) as exc:
        main(args)
    out, err = capsys.readouterr()
    return int(exc.value.code or 0), out, err


def test_version(capsys: pytest.CaptureFixture[str]) -> None:
    code, out, _ = _run_main(["--version"], capsys)
    assert code == 0 and out.strip() == f"fogts {__version__}"


def test_info_fog_file_json(tmp_path: Path) -> None:
    target = tmp_path / "info.json"
    res = runner.invoke(app, ["info", str(shared_path("fog", "fog_0917.txt")), "--json",
                              str(target)])
    assert res.exit_code == 0, res.output
    info = json.loads(target.read_text())
    assert set(info) >= {"source", "n", "fs_hz", "duration_s", "columns", "units", "axes",
                         "gaps", "jitter", "stats"}
    assert info["n"] == 6110 and info["columns"] == ["time", "fog", "T"]
    assert info["axes"] == ["fog"] and info["units"] == "deg/h"
    assert "sample rate 100.029 Hz (from mean of jittered steps)" in res.output


def test_info_json_to_stdout_is_pure_json() -> None:
    res = runner.invoke(app, ["info", str(shared_path("fog", "fog_0917.txt")), "--json", "-"])
    assert res.exit_code == 0
    assert json.loads(res.stdout)["n"] == 6110


def test_info_json_gives_each_axis_its_unit(tmp_path: Path) -> None:
    """A gyro + accelerometer record: ``units`` is the gyro's, ``axis_units`` each axis'."""
    path = tmp_path / "imu.csv"
    rows = "".join(f"{i / 100},{0.1 * (i % 3)},{9.8 + 0.01 * (i % 5)}\n" for i in range(500))
    path.write_text("time,gyro_z_deg_s,acc_z_mps2\n" + rows)
    res = runner.invoke(app, ["info", str(path), "--json", "-"])
    assert res.exit_code == 0, res.output
    info = json.loads(res.stdout)
    assert info["axes"] == ["gyro_z_deg_s", "acc_z_mps2"] and info["units"] == "deg/s"
    assert info["axis_units"] == ["deg/s", "m/s^2"]


def test_info_mpu6050_reports_irregular_sampling() -> None:
    res = runner.invoke(app, ["info", str(shared_path("imu",
                                                      "mpu6050_gyro_temp_converted.csv.gz"))])
    assert res.exit_code == 0
    assert "IRREGULAR" in res.stdout
    assert "warning: " in res.stderr and "[deg/s]" in res.stdout


def test_info_says_burst_logged_steps_are_not_gaps(tmp_path: Path) -> None:
    """The MPU6050's 13,397 long steps are the bursts' pattern: info says so (text and
    JSON, ``gaps.burst_logged``), in the data-quality warning's words, and counts no gaps
    (as allan counts no missing time); its warning is that of ``allan``."""
    from fogts.io.timebase import burst_logging_text

    path = shared_path("imu", "mpu6050_gyro_temp_converted.csv.gz")
    out = tmp_path / "i.json"
    res = runner.invoke(app, ["info", str(path), "--json", str(out)])
    assert res.exit_code == 0, res.stderr
    line = next(ln for ln in res.stdout.splitlines() if ln.startswith("time base"))
    assert line.startswith("time base   IRREGULAR (time stamps logged in bursts, jitter")
    assert "13397 step(s) longer than 0.0151 s (longest 0.4969 s), the bursts' pattern, " \
           "not gaps: no time is counted as missing;" in line and "gap(s)" not in line
    assert res.stderr.strip() == f"warning: {path}: {burst_logging_text(99.31713767)}"
    gaps = json.loads(out.read_text())["gaps"]
    assert gaps["burst_logged"] is True and gaps["count"] == 13397


def test_info_is_deterministic(tmp_path: Path) -> None:
    f = tmp_path / "a.csv"
    f.write_text("time,rate\n0,1\n0.1,2\n0.2,0.5\n0.3,1.5\n")
    a = runner.invoke(app, ["info", str(f), "--json", "-"]).stdout
    b = runner.invoke(app, ["info", str(f), "--json", "-"]).stdout
    assert a == b


@pytest.mark.parametrize(("content", "args", "message"), [
    (None, [], "error: file not found"),
    ("", [], "is empty"),
    ("time,rate\n0,1\n0.1,x\n0.2,3\n", [], "non-numeric value 'x'"),
    ("rate\n1\n2\n3\n", [], "no time column found"),
    ("rate\n1\n2\n3\n", ["--fs", "-10"], "error: --fs must be a finite number > 0, got -10.0"),
    ("time,fog\n0,1\n0.1,2\n0.2,3\n", ["--rate-column", "rate"],
     "rate column 'rate' not found; columns are: time, fog"),
    ("time,rate\n0,1\n0.1,2\n0.2,3\n", ["--units", "mph"], "units must be one of"),
    ("time,rate\n0,1\n0.1,2\n0.05,3\n", [], "'time' is decreasing at data row 2"),
    ("time,rate\n0,1,5\n0.1,2\n0.2,3\n", [], "data row 1 (line 2) has 3 cells (0, 1, 5) "
     "but the header names 2 columns (time, rate); fogts never drops a value"),
])
def test_info_errors_one_line_exit_2(tmp_path: Path, content: str | None, args: list[str],
                                     message: str) -> None:
    f = tmp_path / "in.csv"
    if content is not None:
        f.write_text(content)
    res = runner.invoke(app, ["info", str(f), *args])
    assert res.exit_code == 2
    lines = res.stderr.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("error: ")
    assert message in lines[0]
    assert "Traceback" not in res.output


def test_usage_error_is_one_line(capsys: pytest.CaptureFixture[str]) -> None:
    code, _out, err = _run_main(["info", "--bogus", "x"], capsys)
    assert code == 2
    assert err.strip().splitlines() == ["error: No such option: --bogus (see 'fogts info --help')"]


def test_missing_argument(capsys: pytest.CaptureFixture[str]) -> None:
    code, _, err = _run_main(["info"], capsys)
    assert code == 2 and err.startswith("error: Missing argument")


def test_debug_shows_traceback(tmp_path: Path) -> None:
    f = tmp_path / "empty.csv"
    f.write_text("")
    res = subprocess.run([sys.executable, "-m", "fogts", "--debug", "info", str(f)],
                         capture_output=True, text=True, check=False)
    assert res.returncode != 0 and "Traceback" in res.stderr


def test_console_script_no_traceback(tmp_path: Path) -> None:
    f = tmp_path / "bin.csv"
    f.write_bytes(b"\x00\x01" * 100)
    res = subprocess.run([sys.executable, "-m", "fogts", "info", str(f)], capture_output=True,
                         text=True, check=False)
    assert res.returncode == 2
    assert res.stderr.strip().startswith("error: ") and "Traceback" not in res.stderr


def _cli_args(kwargs: dict[str, object]) -> list[str]:
    names = {"rate_column": "--rate-column", "time_column": "--time-column",
             "temperature_column": "--temperature-column", "fs_hz": "--fs", "units": "--units",
             "nan": "--nan"}
    args: list[str] = []
    for key, value in kwargs.items():
        args += [names[key], str(value)]
    return args


def _hostile_cases() -> list[tuple[str, str | bytes, dict[str, object]]]:
    from tests.io.test_reader import HOSTILE

    return [(name, content, kwargs) for name, content, kwargs, _, _ in HOSTILE]


@pytest.mark.parametrize(("name", "content", "kwargs"), _hostile_cases(),
                         ids=[c[0] for c in _hostile_cases()])
def test_hostile_corpus_through_cli(tmp_path: Path, name: str, content: str | bytes,
                                    kwargs: dict[str, object],
                                    capsys: pytest.CaptureFixture[str]) -> None:
    f = tmp_path / name
    if isinstance(content, bytes):
        f.write_bytes(content)
    else:
        f.write_text(content)
    code, out, err = _run_main(["info", str(f), *_cli_args(kwargs)], capsys)
    assert code == 2, out + err
    lines = err.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("error: "), err
    assert "Traceback" not in out + err


#: The only ways the word "seed" may appear in the help, the README and the report: the
#: random seed of a simulation (``--seed``, "Random seed ...", "30 seeds", "script and seed").
_DATA_SEED = re.compile(r"--seed\b|random seed|\d+ seeds\b|script and seed|\bseed \d+;",
                        re.IGNORECASE)


def _stray_seeds(text: str) -> list[str]:
    return [ln.strip() for ln in text.splitlines()
            if "seed" in _DATA_SEED.sub("", ln).lower()]


def test_help_and_readme_name_only_data_generation_seeds() -> None:
    """User-facing text describes each method by its own name and references (README,
    "Methods and references"), not by internal labels such as "seed 000"."""
    from fogts.cli import COMMANDS

    helps = [runner.invoke(app, ["--help"]).stdout]
    helps += [runner.invoke(app, [c, "--help"]).stdout for c in COMMANDS]
    helps += [runner.invoke(app, ["simulate", sub, "--help"]).stdout
              for sub in ("noise", "startup")]
    assert all(h.startswith("\n Usage: fogts") or "Usage: fogts" in h for h in helps)
    readme = (Path(__file__).resolve().parents[2] / "README.md").read_text(encoding="utf-8")
    assert "## Methods and references" in readme
    assert _stray_seeds("\n".join(helps)) == []
    assert _stray_seeds(readme) == []


def test_help_keeps_brackets_and_reflows_paragraphs() -> None:
    """The help is rendered as markdown: a JSON shape in square brackets stays literal (rich
    markup ate ``[one such document per axis]``) and each docstring paragraph reflows to
    the terminal width instead of breaking where the source line ends."""
    select = " ".join(runner.invoke(app, ["select", "--help"]).stdout.split())
    assert '{"axes": [one such document per axis]}' in select
    allan = runner.invoke(app, ["allan", "--help"]).stdout
    assert '{"inputs": [one such object per file], "summary"}' in " ".join(allan.split())
    lines = [ln.strip() for ln in allan.splitlines()]
    assert not any(ln in ("standard", "--spec,") for ln in lines)   # no orphaned line ends
    thermal = runner.invoke(app, ["simulate", "noise", "--help"]).stdout
    assert "T*dT=a," in thermal and "T*dT=0.4," in thermal   # no "*" taken as emphasis
