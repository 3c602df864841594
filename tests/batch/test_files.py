"""The files of a batch: pattern expansion, run keys, and resuming from per-run JSON."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from fogts.batch import expand_patterns, run_batch, run_key
from fogts.batch.files import default_json_dir
from fogts.errors import DataError
from tests.batch.cases import fake_analysis


def test_resume_ignores_a_corrupt_json(files: Path, tmp_path: Path) -> None:
    first = run_batch([str(files / "run_0*.csv")], summary_path=tmp_path / "s.csv",
                      workers=1, analysis=fake_analysis)
    assert first.n_ok == 10
    victim = first.json_dir / run_key(str(files / "run_04.csv"))
    victim.write_text('{"version": 1, "rows": [')  # as if written by a non-atomic tool
    again = run_batch([str(files / "run_0*.csv")], summary_path=tmp_path / "s.csv",
                      workers=1, analysis=fake_analysis, resume=True)
    assert again.n_skipped == 9 and again.n_ok == 10
    assert json.loads(victim.read_text())["rows"]


def test_run_key_distinguishes_folders(tmp_path: Path) -> None:
    a, b = tmp_path / "a" / "x.csv", tmp_path / "b" / "x.csv"
    assert run_key(str(a)) != run_key(str(b))
    assert run_key(str(a)).startswith("x-") and run_key(str(a)).endswith(".json")


def test_default_json_dir_is_beside_the_summary(tmp_path: Path) -> None:
    assert default_json_dir(tmp_path / "s.csv.gz") == tmp_path / "s_runs"
    assert default_json_dir(tmp_path / "s.parquet") == tmp_path / "s_runs"


def test_expand_patterns(files: Path) -> None:
    got = expand_patterns([str(files / "run_0*.csv"), str(files / "run_01.csv"),
                           str(files)])
    assert len(got) == 10  # duplicates and directories dropped
    with pytest.raises(DataError, match=r"no file matches '.*nothing\*\.csv'"):
        expand_patterns([str(files / "nothing*.csv")])
    with pytest.raises(DataError, match="at least one file"):
        expand_patterns([])
