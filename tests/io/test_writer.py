"""fogts.io.writer: atomic writes of text and frames."""

from __future__ import annotations

from pathlib import Path

import pandas as pd
import pytest

from fogts.errors import DataError
from fogts.io.writer import (
    atomic_path,
    remove_stale_temporaries,
    write_frame_atomic,
    write_text_atomic,
)


def test_atomic_write_keeps_old_file_on_failure(tmp_path: Path) -> None:
    target = tmp_path / "out.txt"
    write_text_atomic(target, "old")
    with pytest.raises(RuntimeError), atomic_path(target) as tmp:
        tmp.write_text("half")
        raise RuntimeError("boom")
    assert target.read_text() == "old"
    assert [p.name for p in tmp_path.iterdir()] == ["out.txt"]  # no temp file left


def test_atomic_write_uses_normal_permissions(tmp_path: Path) -> None:
    import os
    import stat

    umask = os.umask(0o022)
    try:
        write_text_atomic(tmp_path / "p.txt", "x")
    finally:
        os.umask(umask)
    assert stat.S_IMODE((tmp_path / "p.txt").stat().st_mode) == 0o644


def test_write_frame_atomic_roundtrip(tmp_path: Path) -> None:
    df = pd.DataFrame({"time": [0.0, 0.1], "rate": [1.0 / 3.0, 2.0]})
    for name in ("a.csv", "a.parquet", "a.csv.gz"):
        write_frame_atomic(tmp_path / name, df)
        back = pd.read_parquet(tmp_path / name) if name.endswith("parquet") else pd.read_csv(
            tmp_path / name)
        pd.testing.assert_frame_equal(back, df)


def test_write_errors(tmp_path: Path) -> None:
    with pytest.raises(DataError, match="output file must end in .csv"):
        write_frame_atomic(tmp_path / "a.xlsx", pd.DataFrame({"a": [1]}))
    with pytest.raises(DataError, match="output directory does not exist"):
        write_text_atomic(tmp_path / "missing" / "a.txt", "x")


def test_remove_stale_temporaries_only_takes_the_writers_pattern(tmp_path: Path) -> None:
    target = tmp_path / "run[1].json"        # glob characters in the name are literal
    stale = [tmp_path / ".run[1].json.abcd1234.tmp.json", tmp_path / ".run[1].json.x_9.tmp.json"]
    others = [tmp_path / ".run1.json.abcd1234.tmp.json", tmp_path / "run[1].json",
              tmp_path / ".run[1].json.abcd1234.tmp.csv", tmp_path / "x.run[1].json.a.tmp.json"]
    for p in stale + others:
        p.write_text("x")
    assert remove_stale_temporaries(target) == 2
    assert not any(p.exists() for p in stale) and all(p.exists() for p in others)
    assert remove_stale_temporaries(target) == 0


def test_a_write_in_progress_is_named_as_remove_stale_temporaries_expects(tmp_path: Path
                                                                           ) -> None:
    target = tmp_path / "s.csv"
    with atomic_path(target) as tmp:
        name = tmp.name
        tmp.write_text("half")
    left = tmp_path / name               # what a kill mid-write would have left
    left.write_text("half")
    assert remove_stale_temporaries(target) == 1 and not left.exists() and target.exists()
