"""Atomic output writes: a reader never sees a half-written file, and a failed write
leaves any previous file intact.  Which names may be written is checked by
:func:`fogts.io.paths.check_outputs`."""

from __future__ import annotations

import os
import tempfile
from collections.abc import Iterator
from contextlib import contextmanager
from glob import escape as glob_escape
from pathlib import Path

import pandas as pd

from fogts.errors import DataError

__all__ = ["atomic_path", "remove_stale_temporaries", "write_frame_atomic", "write_text_atomic"]


@contextmanager
def atomic_path(path: str | os.PathLike[str]) -> Iterator[Path]:
    """Yield a temporary path beside ``path``; move it onto ``path`` only on success.

    A reader never sees a half-written file, and a failure leaves any previous file intact.

    Examples
    --------
    >>> import tempfile, pathlib
    >>> target = pathlib.Path(tempfile.mkdtemp()) / "out.txt"
    >>> with atomic_path(target) as tmp:
    ...     _ = tmp.write_text("done")
    >>> target.read_text()
    'done'
    """
    target = Path(path)
    parent = target.parent if str(target.parent) else Path(".")
    if not parent.is_dir():
        raise DataError(f"output directory does not exist: {str(parent)!r}")
    fd, tmp_name = tempfile.mkstemp(prefix=f".{target.name}.", suffix=".tmp" + target.suffix,
                                    dir=parent)
    os.close(fd)
    tmp = Path(tmp_name)
    try:
        yield tmp
        os.chmod(tmp, _default_file_mode())  # mkstemp makes 0600; use the umask like open()
        os.replace(tmp, target)
    finally:
        if tmp.exists():
            tmp.unlink()


def remove_stale_temporaries(path: str | os.PathLike[str]) -> int:
    """Delete the temporary files :func:`atomic_path` left beside ``path`` when its process
    was killed mid-write (``.NAME.XXXXXXXX.tmp.SUFFIX``: hidden, never renamed onto
    ``path``); returns how many.  Only that pattern is touched; call it where no write to
    ``path`` can be in progress (a resumed batch, before its workers start)."""
    target = Path(path)
    parent = target.parent if str(target.parent) else Path(".")
    stale = [p for p in parent.glob(f".{glob_escape(target.name)}.*.tmp{glob_escape(target.suffix)}")
             if p.is_file() and not p.is_symlink()]
    for p in stale:
        p.unlink(missing_ok=True)
    return len(stale)


def _default_file_mode() -> int:
    umask = os.umask(0)
    os.umask(umask)
    return 0o666 & ~umask


def write_text_atomic(path: str | os.PathLike[str], text: str) -> Path:
    """Write ``text`` (UTF-8) to ``path`` atomically and return the path."""
    with atomic_path(path) as tmp:
        tmp.write_text(text, encoding="utf-8")
    return Path(path)


def write_frame_atomic(path: str | os.PathLike[str], frame: pd.DataFrame) -> Path:
    """Write a DataFrame atomically as CSV (``.csv``, ``.csv.gz``, ``.txt``), tab-separated
    text (``.tsv``) or Parquet (``.parquet``, ``.pq``).

    Floats are written with full (round-trip) precision; the index is not written.
    """
    target = Path(path)
    name = target.name.lower()
    with atomic_path(target) as tmp:
        if name.endswith((".parquet", ".pq")):
            frame.to_parquet(tmp, index=False)
        elif name.endswith((".csv", ".txt", ".csv.gz", ".tsv")):
            sep = "\t" if name.endswith(".tsv") else ","
            frame.to_csv(tmp, index=False, sep=sep,
                         compression="gzip" if name.endswith(".gz") else None)
        else:
            raise DataError(f"output file must end in .csv, .csv.gz, .tsv, .txt or .parquet; "
                            f"got {target.name!r}")
    return target
