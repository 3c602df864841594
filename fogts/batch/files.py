"""The files of a batch: the inputs its patterns match, where each run's JSON goes, and the
runs a resumed batch reads back from that JSON."""

from __future__ import annotations

import glob
import hashlib
import json
import os
from collections.abc import Sequence
from pathlib import Path

from fogts.batch.documents import RUN_JSON_VERSION, blank_row
from fogts.batch.records import SUMMARY_COLUMNS, RunOutcome
from fogts.errors import DataError

__all__ = ["default_json_dir", "expand_patterns", "load_resumed", "run_key"]

_INPUT_SUFFIXES = (".gz", ".csv", ".tsv", ".txt", ".dat", ".parquet", ".pq", ".npy", ".npz")
_SUMMARY_SUFFIXES = (".gz", ".csv", ".tsv", ".txt", ".parquet", ".pq")


def expand_patterns(patterns: Sequence[str]) -> list[str]:
    """Files matching shell-style ``patterns`` (``**`` recurses), de-duplicated, in order.

    A pattern without wildcards names a file directly.  Directories are ignored.

    Raises
    ------
    DataError
        If no pattern is given or nothing matches.
    """
    if not patterns:
        raise DataError("patterns must name at least one file or glob pattern, got none")
    seen: set[str] = set()
    files: list[str] = []
    for pattern in patterns:
        matches = sorted(glob.glob(pattern, recursive=True)) if glob.has_magic(pattern) \
            else [pattern]
        for m in matches:
            if os.path.isdir(m):
                continue
            real = os.path.realpath(m)
            if real not in seen:
                seen.add(real)
                files.append(os.path.normpath(m))
    if not files:
        raise DataError(f"no file matches {', '.join(repr(p) for p in patterns)}")
    return files


def run_key(file: str) -> str:
    """File name of a run's JSON: ``<name>-<8 hex digits of its absolute path>.json``.

    Two files with the same name in different folders get different keys.
    """
    real = os.path.realpath(file)
    digest = hashlib.sha1(real.encode("utf-8", "surrogateescape")).hexdigest()[:8]
    base = Path(file).name
    for suffix in _INPUT_SUFFIXES:
        if base.lower().endswith(suffix) and len(base) > len(suffix):
            base = base[: -len(suffix)]
    safe = "".join(c if c.isalnum() or c in "-_." else "_" for c in base)[:80]
    return f"{safe}-{digest}.json"


def default_json_dir(summary_path: Path) -> Path:
    """``<summary name>_runs`` beside the summary table."""
    name = summary_path.name
    for suffix in _SUMMARY_SUFFIXES:
        if name.lower().endswith(suffix):
            name = name[: -len(suffix)]
    return summary_path.with_name(f"{name}_runs")


def load_resumed(path: Path, file: str) -> RunOutcome | None:
    """The outcome stored in the per-run JSON ``path`` of ``file``, or None if that JSON is
    missing, unreadable, of another layout version or without rows."""
    try:
        doc = json.loads(path.read_text(encoding="utf-8"))
        rows = doc["rows"]
        if doc.get("version") != RUN_JSON_VERSION or not rows:
            return None
    except (OSError, ValueError, KeyError, TypeError):
        return None
    fixed = []
    for r in rows:
        row = blank_row(file)
        row.update({k: r.get(k) for k in SUMMARY_COLUMNS if k in r})
        row["file"] = file
        fixed.append(row)
    status = "error" if any(r["status"] == "error" for r in fixed) else "ok"
    return RunOutcome(file=file, status=status, error=str(doc.get("error") or ""),
                      rows=tuple(fixed), document=doc)
