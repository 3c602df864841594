"""fogts.io.writer: atomic writes of text and frames."""

from __future__ import annotations

from pathlib import Path

import pandas as pd
import pytest

from fogts.errors import DataError
from fogts.io.writer import atomic_path, write_frame_atomic, write_text_atomic


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
