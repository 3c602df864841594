"""The executors: 20 files with 3 bad ones on the local process pool and on a Dask
LocalCluster, and an unreachable scheduler."""

from __future__ import annotations

import json
from pathlib import Path

import pandas as pd
import pytest
from click.testing import Result
from typer.testing import CliRunner

from fogts.batch import run_batch
from fogts.cli import app
from fogts.errors import DataError
from tests.batch.cases import check_summary, fake_analysis

runner = CliRunner()


def test_local_pool_17_ok_3_errors(pool_run: tuple[Path, Result], files: Path) -> None:
    out, res = pool_run
    assert res.exit_code == 1, res.output  # some runs failed: exit 1, the batch completed
    assert "17 ok, 3 failed" in res.output and "process-pool" in res.output
    frame = pd.read_csv(out / "summary.csv")
    check_summary(frame, files)
    docs = sorted((out / "json").glob("*.json"))
    assert len(docs) == 20
    for d in docs:
        doc = json.loads(d.read_text())
        assert doc["status"] in ("ok", "error") and doc["rows"]
    # no temporary file is left behind
    assert not [p for p in out.rglob("*.tmp*")]


@pytest.mark.slow
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
    check_summary(frame, files)
    assert len(list((tmp_path / "summary_runs").glob("*.json"))) == 20


def test_unreachable_scheduler(files: Path, tmp_path: Path) -> None:
    pytest.importorskip("distributed", reason="dask[distributed] not installed")
    with pytest.raises(DataError, match=r"cannot connect to the Dask scheduler at "
                                        r"'tcp://127\.0\.0\.1:9'"):
        run_batch([str(files / "run_00.csv")], summary_path=tmp_path / "s.csv",
                  scheduler="tcp://127.0.0.1:9", connect_timeout_s=1.0,
                  analysis=fake_analysis)
