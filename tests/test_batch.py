"""Batch runs: 20 files with 3 bad ones, on the local pool and on a Dask LocalCluster;
interruption (SIGKILL) then --resume; atomic outputs; the per-file analysis is the one the
single-file API gives.

Truth: the good files are white noise of known standard deviation sigma (deg/h) at 10 Hz, so
the angle random walk is N = sigma / sqrt(fs) / 60 deg/sqrt(h) (IEEE Std 952-1997 Annex C;
DESIGN.md conversion).
"""

from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pandas as pd
import pytest
from typer.testing import CliRunner

from fogts.batch import (
    RUN_JSON_VERSION,
    SUMMARY_COLUMNS,
    BatchOptions,
    BatchProgress,
    RunOutcome,
    analyze_file,
    expand_patterns,
    run_batch,
    run_key,
)
from fogts.cli import app
from fogts.errors import DataError

runner = CliRunner()

N_GOOD, FS, SIGMA = 17, 10.0, 0.8
N_SAMPLES = 1200
BAD = {
    "bad_text.csv": ("time,rate\n0.0,1.0\n0.1,oops\n0.2,3.0\n0.3,4.0\n", "non-numeric"),
    "bad_short.csv": ("time,rate\n0.0,1.0\n0.1,2.0\n", "at least"),
    "bad_time.csv": ("time,rate\n" + "".join(f"{(i * 7) % 5}.0,{i}.5\n" for i in range(40)),
                     "time"),
}


def _make_files(folder: Path) -> list[Path]:
    folder.mkdir(parents=True, exist_ok=True)
    paths = []
    for k in range(N_GOOD):
        rng = np.random.default_rng(100 + k)
        t = np.arange(N_SAMPLES) / FS
        rate = 0.3 + rng.normal(0.0, SIGMA, N_SAMPLES)
        p = folder / f"run_{k:02d}.csv"
        np.savetxt(p, np.c_[t, rate], delimiter=",", header="time,rate", comments="",
                   fmt="%.6f")
        paths.append(p)
    for name, (text, _) in BAD.items():
        p = folder / name
        p.write_text(text)
        paths.append(p)
    return sorted(paths)


@pytest.fixture(scope="module")
def files(tmp_path_factory: pytest.TempPathFactory) -> Path:
    folder = tmp_path_factory.mktemp("batch") / "in"
    _make_files(folder)
    return folder


@pytest.fixture(scope="module")
def pool_run(files: Path, tmp_path_factory: pytest.TempPathFactory) -> tuple[Path, object]:
    out = tmp_path_factory.mktemp("pool")
    res = runner.invoke(app, ["batch", str(files / "*.csv"), "-o", str(out / "summary.csv"),
                              "--json-dir", str(out / "json"), "--workers", "2"])
    return out, res


def _check_summary(frame: pd.DataFrame, folder: Path) -> None:
    assert list(frame.columns) == list(SUMMARY_COLUMNS)
    assert len(frame) == 20
    assert frame["file"].is_unique
    assert sorted(Path(f).name for f in frame["file"]) == sorted(
        p.name for p in folder.glob("*.csv"))
    ok, bad = frame[frame["status"] == "ok"], frame[frame["status"] == "error"]
    assert len(ok) == 17 and len(bad) == 3
    for _, row in bad.iterrows():
        expect = BAD[Path(row["file"]).name][1]
        assert expect in str(row["error"]), (row["file"], row["error"])
        assert pd.isna(row["N"])
    assert (ok["error"].fillna("") == "").all()
    assert (ok["n"] == N_SAMPLES).all()
    np.testing.assert_allclose(ok["fs_hz"].astype(float), FS, rtol=1e-9)
    # ARW of white noise: N = sigma / sqrt(fs) / 60; 1200 samples give the fit a few %
    n_true = SIGMA / np.sqrt(FS) / 60.0
    np.testing.assert_allclose(ok["N"].astype(float), n_true, rtol=0.15)
    assert (ok["N_stderr"].astype(float) > 0).all()
    assert ok["selected"].notna().all()
    assert np.isfinite(ok["aic"].astype(float)).all()
    assert ok["white"].notna().all()


def test_local_pool_17_ok_3_errors(pool_run: tuple[Path, object], files: Path) -> None:
    out, res = pool_run
    assert res.exit_code == 1, res.output  # some runs failed: exit 1, the batch completed
    assert "17 ok, 3 failed" in res.output and "process-pool" in res.output
    frame = pd.read_csv(out / "summary.csv")
    _check_summary(frame, files)
    docs = sorted((out / "json").glob("*.json"))
    assert len(docs) == 20
    for d in docs:
        doc = json.loads(d.read_text())
        assert doc["status"] in ("ok", "error") and doc["rows"]
    # no temporary file is left behind
    assert not [p for p in out.rglob("*.tmp*")]


def test_row_equals_single_file_analysis(pool_run: tuple[Path, object], files: Path) -> None:
    """The batch row is exactly what the analysis of that one file gives, in this process."""
    out, _ = pool_run
    frame = pd.read_csv(out / "summary.csv")
    target = files / "run_03.csv"
    row = frame[frame["file"].map(lambda f: Path(f).name) == "run_03.csv"].iloc[0]
    single = analyze_file(str(target), BatchOptions())
    assert single.status == "ok"
    for col in ("N", "N_stderr", "B", "K", "aic"):
        a, b = single.rows[0][col], row[col]
        assert (a is None and pd.isna(b)) or a == pytest.approx(float(b), rel=1e-12), col
    assert single.rows[0]["selected"] == row["selected"]
    doc = json.loads((out / "json" / run_key(str(target))).read_text())
    assert doc["info"]["n"] == N_SAMPLES and doc["select"][0]["candidates"]


def test_run_json_has_the_shape_of_the_allan_and_select_json(pool_run: tuple[Path, object],
                                                             files: Path) -> None:
    """The per-run JSON holds, under "allan" and "select", documents of the same shape as
    ``fogts allan --json`` and ``fogts select --json`` on that file."""
    from typer.testing import CliRunner

    from fogts.cli import app

    out, _ = pool_run
    target = files / "run_03.csv"
    doc = json.loads((out / "json" / run_key(str(target))).read_text())
    cli = {}
    for command in ("allan", "select"):
        path = out / f"{command}.json"
        res = CliRunner().invoke(app, [command, str(target), "--json", str(path)])
        assert res.exit_code in (0, 1), res.stderr
        cli[command] = json.loads(path.read_text())

    def shape(d: object) -> object:
        if isinstance(d, dict):
            return {k: shape(v) for k, v in d.items() if k not in ("stationarity",)}
        if isinstance(d, list):
            return [shape(v) for v in d[:1]]
        return type(d).__name__ if d is not None else None

    assert shape(doc["allan"]) == shape(cli["allan"])
    # the batch skips the stationarity tests (None): the rest of the preparation is alike
    assert set(doc["select"][0]) == set(cli["select"])
    assert doc["select"][0]["candidates"] == cli["select"]["candidates"]


def test_dask_local_cluster(files: Path, tmp_path: Path) -> None:
    distributed = pytest.importorskip("distributed", reason="dask[distributed] not installed "
                                      "(pip install 'fogts[dask]')")
    with distributed.LocalCluster(n_workers=1, threads_per_worker=1, processes=False,
                                  dashboard_address=None) as cluster:
        res = runner.invoke(app, ["batch", str(files / "*.csv"), "-o",
                                  str(tmp_path / "summary.csv"), "--scheduler",
                                  cluster.scheduler_address])
    assert res.exit_code == 1, res.output
    assert "(dask)" in res.output
    frame = pd.read_csv(tmp_path / "summary.csv")
    _check_summary(frame, files)
    assert len(list((tmp_path / "summary_runs").glob("*.json"))) == 20


def test_kill_midway_then_resume(files: Path, tmp_path: Path,
                                 pool_run: tuple[Path, object]) -> None:
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
            if jdir.exists() and len(list(jdir.glob("*.json"))) >= 3:
                break
            time.sleep(0.02)
        assert proc.poll() is None, "the batch finished before it could be interrupted"
        os.killpg(proc.pid, signal.SIGKILL)  # the batch and its workers, no clean-up at all
    finally:
        proc.wait(timeout=30)
    done_before = sorted(p.name for p in jdir.glob("*.json"))
    assert 3 <= len(done_before) < 20
    for p in jdir.glob("*.json"):  # whatever exists is complete (atomic writes)
        assert json.loads(p.read_text())["rows"]
    if out.exists():  # a partial summary is a complete CSV of finished runs
        partial = pd.read_csv(out)
        assert set(partial["json"]) <= set(done_before)

    res = runner.invoke(app, ["batch", str(files / "*.csv"), "-o", str(out), "--json-dir",
                              str(jdir), "--resume", "--workers", "2"])
    assert res.exit_code == 1, res.output
    assert f"{len(done_before)} resumed from JSON" in res.output
    frame = pd.read_csv(out)
    _check_summary(frame, files)
    assert sorted(p.name for p in jdir.glob("*.json")) == sorted(frame["json"])
    # resumed and fresh rows agree with an uninterrupted batch, row for row
    reference = pd.read_csv(pool_run[0] / "summary.csv")
    pd.testing.assert_frame_equal(frame.drop(columns="json"),
                                  reference.drop(columns="json"), check_exact=False,
                                  rtol=1e-12)


# --------------------------------------------------------------------------- engine details


def _fake_analysis(file: str, options: BatchOptions) -> RunOutcome:
    """A picklable stand-in analysis: fails for names containing 'bad'."""
    if "bad" in Path(file).name:
        raise RuntimeError("boom in " + Path(file).name)
    row = dict.fromkeys(SUMMARY_COLUMNS)
    row.update(file=file, axis="rate", n=1, status="ok", error="")
    return RunOutcome(file=file, status="ok", error="", rows=(row,),
                      document={"version": RUN_JSON_VERSION, "rows": [row]})


def test_pluggable_analysis_serial_and_progress(files: Path, tmp_path: Path) -> None:
    seen: list[BatchProgress] = []
    res = run_batch([str(files / "*.csv")], summary_path=tmp_path / "s.csv", workers=1,
                    analysis=_fake_analysis, progress=seen.append)
    assert res.backend == "serial" and res.n_ok == 17 and res.n_error == 3
    msgs = [r["error"] for r in res.rows if r["status"] == "error"]
    assert all(m.startswith("internal error (RuntimeError): boom in bad_") for m in msgs)
    assert seen[0].done == 0 and seen[-1].done == 20 and seen[-1].failed == 3
    assert seen[-1].remaining == 0
    frame = res.to_frame()
    assert len(frame) == 20 and "17 ok, 3 failed" in res.summary()
    assert res.to_dict()["ok"] == 17


def test_resume_ignores_a_corrupt_json(files: Path, tmp_path: Path) -> None:
    first = run_batch([str(files / "run_0*.csv")], summary_path=tmp_path / "s.csv",
                      workers=1, analysis=_fake_analysis)
    assert first.n_ok == 10
    victim = first.json_dir / run_key(str(files / "run_04.csv"))
    victim.write_text('{"version": 1, "rows": [')  # as if written by a non-atomic tool
    again = run_batch([str(files / "run_0*.csv")], summary_path=tmp_path / "s.csv",
                      workers=1, analysis=_fake_analysis, resume=True)
    assert again.n_skipped == 9 and again.n_ok == 10
    assert json.loads(victim.read_text())["rows"]


def test_run_key_distinguishes_folders(tmp_path: Path) -> None:
    a, b = tmp_path / "a" / "x.csv", tmp_path / "b" / "x.csv"
    assert run_key(str(a)) != run_key(str(b))
    assert run_key(str(a)).startswith("x-") and run_key(str(a)).endswith(".json")


def test_expand_patterns(files: Path) -> None:
    got = expand_patterns([str(files / "run_0*.csv"), str(files / "run_01.csv"),
                           str(files)])
    assert len(got) == 10  # duplicates and directories dropped
    with pytest.raises(DataError, match=r"no file matches '.*nothing\*\.csv'"):
        expand_patterns([str(files / "nothing*.csv")])
    with pytest.raises(DataError, match="at least one file"):
        expand_patterns([])


def test_bad_arguments(files: Path, tmp_path: Path) -> None:
    with pytest.raises(DataError, match=r"summary_path must end in \.csv.*got 'out\.xlsx'"):
        run_batch([str(files / "*.csv")], summary_path=tmp_path / "out.xlsx")
    with pytest.raises(DataError, match="workers must be >= 1, got 0"):
        run_batch([str(files / "*.csv")], summary_path=tmp_path / "s.csv", workers=0)
    with pytest.raises(DataError, match="kind must be one of .*; got 'xdev'"):
        BatchOptions(kind="xdev")
    with pytest.raises(DataError, match="criterion must be one of .*; got 'r2'"):
        BatchOptions(criterion="r2")
    with pytest.raises(DataError, match="taus must be one of .*; got 'weekly'"):
        BatchOptions(taus="weekly")
    with pytest.raises(DataError, match="detrend must be <= 10, got 11"):
        BatchOptions(detrend=11)
    with pytest.raises(DataError, match="decimate must be >= 1, got 0"):
        BatchOptions(decimate=0)
    with pytest.raises(DataError, match=r"summary_path '.*s\.csv': the folder '.*no' does not exist"):
        run_batch([str(files / "*.csv")], summary_path=tmp_path / "no" / "s.csv",
                  json_dir=tmp_path / "j", analysis=_fake_analysis, workers=1)


def test_unreachable_scheduler(files: Path, tmp_path: Path) -> None:
    pytest.importorskip("distributed", reason="dask[distributed] not installed")
    with pytest.raises(DataError, match=r"cannot connect to the Dask scheduler at "
                                        r"'tcp://127\.0\.0\.1:9'"):
        run_batch([str(files / "run_00.csv")], summary_path=tmp_path / "s.csv",
                  scheduler="tcp://127.0.0.1:9", connect_timeout_s=1.0,
                  analysis=_fake_analysis)


def test_cli_errors_are_one_line(tmp_path: Path) -> None:
    res = runner.invoke(app, ["batch", str(tmp_path / "none*.csv"), "-o",
                              str(tmp_path / "s.csv")])
    assert res.exit_code == 2
    assert "error: no file matches" in res.output and "Traceback" not in res.output
