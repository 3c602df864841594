"""The command line's progress bar (fogts.cli.progress): on a terminal a bar on stderr;
nothing with --json - (stdout is exactly the JSON) or --quiet; --quiet on every long
command.  The commands run in a child process whose stderr is a pseudo-terminal (the
``pty`` module), with the bar's delay set to 0 s by ``FOGTS_PROGRESS_DELAY``."""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from typer.testing import CliRunner

from fogts.cli import app

pty = pytest.importorskip("pty")  # POSIX only
ROOT = Path(__file__).resolve().parents[2]
STAGE = "oadev: "  # the bar's description of the Allan stage ("oadev: 14 taus")


def _run_on_a_terminal(args: list[str]) -> tuple[int, bytes, str]:
    """Run ``fogts ARGS`` with stderr on a pseudo-terminal, stdout on a pipe."""
    master, slave = pty.openpty()
    env = {**os.environ, "FOGTS_PROGRESS_DELAY": "0", "PYTHONPATH": str(ROOT),
           "COLUMNS": "120"}
    proc = subprocess.Popen([sys.executable, "-m", "fogts", *args], stdout=subprocess.PIPE,
                            stderr=slave, env=env, cwd=ROOT)
    os.close(slave)
    err = bytearray()
    while True:
        try:
            chunk = os.read(master, 65536)
        except OSError:  # the child closed the terminal
            break
        if not chunk:
            break
        err += chunk
    out = proc.communicate()[0]
    os.close(master)
    return proc.returncode, out, err.decode("utf-8", "replace")


@pytest.fixture(scope="module")
def record(tmp_path_factory: pytest.TempPathFactory) -> Path:
    path = tmp_path_factory.mktemp("progress") / "white.npy"
    np.save(path, np.random.default_rng(0).normal(size=200_000))
    return path


def test_a_terminal_shows_the_bar_on_stderr(record: Path) -> None:
    code, out, err = _run_on_a_terminal(["allan", str(record), "--fs", "100",
                                         "--units", "deg/h"])
    assert code == 0
    assert STAGE in err and "reading white.npy" in err
    assert STAGE not in out.decode()  # the tables on stdout are untouched


def test_json_to_stdout_has_no_bar(record: Path) -> None:
    code, out, err = _run_on_a_terminal(["allan", str(record), "--fs", "100",
                                         "--units", "deg/h", "--json", "-"])
    assert code == 0
    doc = json.loads(out)  # stdout is exactly the JSON
    assert doc["input"]["n"] == 200_000
    assert STAGE not in err and "reading" not in err  # the text tables only


def test_quiet_suppresses_the_bar(record: Path) -> None:
    code, _, err = _run_on_a_terminal(["allan", str(record), "--fs", "100", "--units",
                                       "deg/h", "--quiet"])
    assert code == 0 and STAGE not in err and "reading" not in err


@pytest.mark.parametrize("command", ["allan", "select", "report", "batch", "davar"])
def test_long_commands_take_quiet(command: str) -> None:
    res = CliRunner().invoke(app, [command, "--help"])
    assert res.exit_code == 0 and "--quiet" in res.stdout


def test_not_a_terminal_no_bar(record: Path) -> None:
    """Under CliRunner stderr is no terminal: the output is what it was without the bar."""
    res = CliRunner().invoke(app, ["select", str(record), "--fs", "100", "--units",
                                   "deg/h", "--decimate", "10"])
    assert res.exit_code in (0, 1), res.stderr
    assert "ARMA:" not in res.stderr and "reading" not in res.stderr


def test_rich_progress_draws_nothing_before_its_delay() -> None:
    from io import StringIO

    from rich.console import Console

    from fogts.cli.progress import RichProgress

    buf = StringIO()
    bar = RichProgress(Console(file=buf, force_terminal=True, width=80), delay_s=60.0)
    bar("stage", 0, 3)
    bar("stage", 3, 3)
    bar.close()
    assert buf.getvalue() == ""
    buf = StringIO()
    bar = RichProgress(Console(file=buf, force_terminal=True, width=80), delay_s=0.0)
    bar.timer.join()  # the bar has started
    bar("reading x", 0, None)
    bar("oadev: 3 taus", 2, 3)
    bar.bar.refresh()
    bar.close()
    assert "oadev: 3 taus" in buf.getvalue() and "2/3" in buf.getvalue()
