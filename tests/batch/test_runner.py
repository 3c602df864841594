"""A whole batch: interruption (SIGKILL) then --resume, progress reports, a pluggable
analysis, and argument errors."""

from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import pandas as pd
import pytest
from click.testing import Result
from typer.testing import CliRunner

from fogts.batch import BatchProgress, run_batch
from fogts.cli import app
from fogts.errors import DataError
from tests.batch.cases import check_summary, fake_analysis

runner = CliRunner()


@pytest.mark.slow
def _finished(jdir: Path) -> list[Path]:
    """The per-run JSON files written so far: pathlib's glob also matches the hidden
    temporary file of a write in progress (``.run.json.XXXX.tmp.json``, renamed onto its
    name when complete), which a SIGKILL leaves behind half written."""
    return [p for p in jdir.glob("*.json") if not p.name.startswith(".")]


def test_kill_midway_then_resume(files: Path, tmp_path: Path,
                                 pool_run: tuple[Path, Result]) -> None:
    """SIGKILL a batch after a few runs, then --resume: every run once, none lost."""
    out = tmp_path / "summary.csv"
    jdir = tmp_path / "json"
    cmd = [sys.executable, "-m", "fogts", "batch", str(files / "*.csv"), "-o", str(out),
           "--json-dir", str(jdir), "--workers", "2"]
    proc = subprocess.Popen(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL,
                            stdin=subprocess.DEVNULL, start_new_session=True)
    try:
        deadline = time.monotonic() + 120
        while time.monotonic() < deadline and proc.poll() is None:
            if jdir.exists() and len(_finished(jdir)) >= 3:
                break
            time.sleep(0.02)
        assert proc.poll() is None, "the batch finished before it could be interrupted"
        os.killpg(proc.pid, signal.SIGKILL)  # the batch and its workers, no clean-up at all
    finally:
        proc.wait(timeout=30)
    done_before = sorted(p.name for p in _finished(jdir))
    assert 3 <= len(done_before) < 20
    for p in _finished(jdir):  # whatever exists is complete (atomic writes)
        assert json.loads(p.read_text())["rows"]
    if out.exists():  # a partial summary is a complete CSV of finished runs
        partial = pd.read_csv(out)
        assert set(partial["json"]) <= set(done_before)

    res = runner.invoke(app, ["batch", str(files / "*.csv"), "-o", str(out), "--json-dir",
                              str(jdir), "--resume", "--workers", "2"])
    assert res.exit_code == 1, res.output
    assert f"{len(done_before)} resumed from JSON" in res.output
    frame = pd.read_csv(out)
    check_summary(frame, files)
    assert sorted(p.name for p in _finished(jdir)) == sorted(frame["json"])
    # resumed and fresh rows agree with an uninterrupted batch, row for row
    reference = pd.read_csv(pool_run[0] / "summary.csv")
    pd.testing.assert_frame_equal(frame.drop(columns="json"),
                                  reference.drop(columns="json"), check_exact=False,
                                  rtol=1e-12)


def test_pluggable_analysis_serial_and_progress(files: Path, tmp_path: Path) -> None:
    seen: list[BatchProgress] = []
    res = run_batch([str(files / "*.csv")], summary_path=tmp_path / "s.csv", workers=1,
                    analysis=fake_analysis, progress=seen.append)
    assert res.backend == "serial" and res.n_ok == 17 and res.n_error == 3
    msgs = [r["error"] for r in res.rows if r["status"] == "error"]
    assert all(m.startswith("internal error (RuntimeError): boom in bad_") for m in msgs)
    assert seen[0].done == 0 and seen[-1].done == 20 and seen[-1].failed == 3
    assert seen[-1].remaining == 0
    frame = res.to_frame()
    assert len(frame) == 20 and "17 ok, 3 failed" in res.summary()
    assert res.to_dict()["ok"] == 17



def test_resume_removes_the_temporaries_a_killed_batch_left(files: Path, tmp_path: Path) -> None:
    # a SIGKILL mid-write leaves the writer's hidden temporary beside a run's JSON and the
    # summary; --resume deletes them (that pattern only) before the workers start
    from fogts.batch.files import run_key

    jdir = tmp_path / "j"
    summary = tmp_path / "s.csv"
    first = run_batch([str(files / "*.csv")], summary_path=summary, json_dir=jdir,
                      analysis=fake_analysis, workers=1)
    one = first.files[0]
    stale = [jdir / f".{run_key(one)}.k3x9q2ab.tmp.json", tmp_path / ".s.csv.a1b2c3d4.tmp.csv"]
    for p in stale:
        p.write_text('{"rows": [')           # half written
    kept = [jdir / ".notes.json", jdir / f".{run_key(one)}.json.bak"]
    for p in kept:
        p.write_text("mine")
    again = run_batch([str(files / "*.csv")], summary_path=summary, json_dir=jdir,
                      analysis=fake_analysis, workers=1, resume=True, overwrite=True)
    assert again.n_skipped == 20 and not any(p.exists() for p in stale)
    assert all(p.read_text() == "mine" for p in kept)

def test_bad_arguments(files: Path, tmp_path: Path) -> None:
    with pytest.raises(DataError, match=r"summary_path must end in \.csv.*got 'out\.xlsx'"):
        run_batch([str(files / "*.csv")], summary_path=tmp_path / "out.xlsx")
    with pytest.raises(DataError, match="workers must be >= 1, got 0"):
        run_batch([str(files / "*.csv")], summary_path=tmp_path / "s.csv", workers=0)
    with pytest.raises(DataError, match=r"summary_path '.*s\.csv': the folder '.*no' does not exist"):
        run_batch([str(files / "*.csv")], summary_path=tmp_path / "no" / "s.csv",
                  json_dir=tmp_path / "j", analysis=fake_analysis, workers=1)


def test_cli_errors_are_one_line(tmp_path: Path) -> None:
    res = runner.invoke(app, ["batch", str(tmp_path / "none*.csv"), "-o",
                              str(tmp_path / "s.csv")])
    assert res.exit_code == 2
    assert "error: no file matches" in res.output and "Traceback" not in res.output
