"""A batch from start to end: resolve the files and outputs, read back resumed runs,
schedule the others, keep the per-run JSON and the summary table up to date, and report."""

from __future__ import annotations

import os
import time
from collections.abc import Callable, Iterator, Sequence
from pathlib import Path
from typing import Any

from fogts._validate import check_int
from fogts.batch.analysis import analyze_file
from fogts.batch.executors import open_executor
from fogts.batch.files import default_json_dir, expand_patterns, load_resumed, run_key
from fogts.batch.records import (
    BatchOptions,
    BatchProgress,
    BatchResult,
    RunOutcome,
    rows_frame,
)
from fogts.errors import DataError
from fogts.io.paths import check_outputs
from fogts.io.writer import remove_stale_temporaries, write_frame_atomic, write_text_atomic
from fogts.report.text import json_dumps

__all__ = ["run_batch"]

_SUMMARY_SUFFIXES = (".csv", ".csv.gz", ".tsv", ".txt", ".parquet", ".pq")


def run_batch(
    patterns: Sequence[str],
    *,
    summary_path: str | os.PathLike[str],
    json_dir: str | os.PathLike[str] | None = None,
    workers: int | None = None,
    scheduler: str | None = None,
    resume: bool = False,
    overwrite: bool = False,
    options: BatchOptions | None = None,
    analysis: Callable[[str, BatchOptions], RunOutcome] = analyze_file,
    progress: Callable[[BatchProgress], None] | None = None,
    refresh_s: float = 2.0,
    connect_timeout_s: float = 30.0,
) -> BatchResult:
    """Analyse every file matching ``patterns`` and write a summary table.

    Parameters
    ----------
    patterns : sequence of str
        Files or glob patterns (``**`` recurses).
    summary_path : path
        Summary table, ``.csv`` or ``.parquet`` (columns :data:`SUMMARY_COLUMNS`, one row per
        run and axis).  Rewritten atomically while the batch runs and at the end.
    json_dir : path, optional
        Folder of per-run JSON documents (default: ``<summary name>_runs`` beside the summary;
        created if missing).
    workers : int, optional
        Local worker processes (default: the number of CPUs); 1 runs in this process.
    scheduler : str, optional
        Address of a running Dask distributed scheduler (``tcp://host:8786``); the work is
        then sent there instead of to a local pool.  Workers must have fogts installed.
    resume : bool
        Skip runs whose per-run JSON exists (their rows are read back from it).  A run that
        failed because of its file also has a JSON and is skipped; delete that JSON to retry
        it.  Runs lost to a dead worker have none and are retried.
    overwrite : bool
        Replace an existing summary and per-run JSON (:func:`fogts.io.paths.check_outputs`);
        ``resume`` implies it.
    options : BatchOptions, optional
        Input and analysis options.
    analysis : callable
        ``analysis(file, options) -> RunOutcome``; must be picklable (a module-level function).
    progress : callable, optional
        Called with a :class:`BatchProgress` at the start and after each finished run.
    refresh_s : float
        Shortest interval between two rewrites of the summary while running.
    connect_timeout_s : float
        How long to try to reach the Dask scheduler.

    Returns
    -------
    BatchResult

    Raises
    ------
    DataError
        No file matches, ``workers`` < 1, the scheduler cannot be reached, or an output
        exists (without ``overwrite`` or ``resume``).
    """
    t0 = time.perf_counter()
    options = options if options is not None else BatchOptions()
    summary = _summary_path(summary_path)
    if workers is not None:
        workers = check_int("workers", workers, minimum=1)
    files = expand_patterns(patterns)
    jdir = _json_dir(json_dir, summary, files, replace=overwrite or resume)
    state = _BatchState(files, summary, jdir, progress)
    if resume:
        state.resume()
    backend, stream = open_executor(state.jobs(), analysis, options, workers=workers,
                                    scheduler=scheduler, connect_timeout_s=connect_timeout_s)
    interrupted = _collect(stream, state, refresh_s)
    return state.result(backend, interrupted=interrupted, seconds=time.perf_counter() - t0)


def _summary_path(summary_path: str | os.PathLike[str]) -> Path:
    """``summary_path`` as a Path, if it names a table format the summary can be written in."""
    summary = Path(summary_path)
    if not summary.name.lower().endswith(_SUMMARY_SUFFIXES):
        raise DataError(f"summary_path must end in .csv, .csv.gz, .tsv, .txt or .parquet; got "
                        f"{summary.name!r}")
    return summary


def _json_dir(json_dir: str | os.PathLike[str] | None, summary: Path, files: list[str], *,
              replace: bool) -> Path:
    """The folder of the per-run JSON, created; no output may overwrite an input, nor an
    existing file unless ``replace``."""
    jdir = Path(json_dir) if json_dir is not None else default_json_dir(summary)
    check_outputs({"summary_path": summary}, {"patterns": files}, overwrite=replace)
    jdir.mkdir(parents=True, exist_ok=True)
    check_outputs({f"per-run JSON of {f!r}": jdir / run_key(f) for f in files},
                  {"patterns": files}, overwrite=replace)
    return jdir


class _BatchState:
    """The outcomes of a batch so far, and the outputs and progress reports made from them."""

    def __init__(self, files: list[str], summary: Path, json_dir: Path,
                 progress: Callable[[BatchProgress], None] | None) -> None:
        self.files = files
        self.summary = summary
        self.json_dir = json_dir
        self.progress = progress
        self.outcomes: dict[str, RunOutcome] = {}
        self.skipped = 0

    def resume(self) -> None:
        """Take the outcome of every run that has a usable per-run JSON from that JSON."""
        remove_stale_temporaries(self.summary)
        for f in self.files:
            # a batch killed mid-write leaves its hidden temporary file beside the JSON
            remove_stale_temporaries(self.json_dir / run_key(f))
            got = load_resumed(self.json_dir / run_key(f), f)
            if got is not None:
                self.outcomes[f] = got
                self.skipped += 1

    def jobs(self) -> list[str]:
        """The files still to analyse."""
        return [f for f in self.files if f not in self.outcomes]

    def record(self, outcome: RunOutcome) -> None:
        """Keep ``outcome`` (its per-run JSON written if it persists) and report progress."""
        if outcome.persist:
            write_text_atomic(self.json_dir / run_key(outcome.file),
                              json_dumps(outcome.document) + "\n")
        self.outcomes[outcome.file] = outcome
        self.report(outcome.file)

    def report(self, last: str | None) -> None:
        """Call the progress callback, if any (``last``: the run that just finished)."""
        if self.progress is not None:
            failed = sum(1 for o in self.outcomes.values() if o.status == "error")
            self.progress(BatchProgress(total=len(self.files), done=len(self.outcomes),
                                        failed=failed, skipped=self.skipped, last_file=last))

    def rows(self) -> list[dict[str, Any]]:
        """The summary rows of the finished runs, in file order."""
        out: list[dict[str, Any]] = []
        for f in self.files:
            if f in self.outcomes:
                outcome = self.outcomes[f]
                json_name = run_key(f) if outcome.persist else None
                out.extend({**r, "json": json_name} for r in outcome.rows)
        return out

    def write_summary(self) -> None:
        """Rewrite the summary table (atomically)."""
        write_frame_atomic(self.summary, rows_frame(self.rows()))

    def result(self, backend: str, *, interrupted: bool, seconds: float) -> BatchResult:
        return BatchResult(rows=tuple(self.rows()), files=tuple(self.files),
                           summary_path=self.summary, json_dir=self.json_dir,
                           n_skipped=self.skipped, interrupted=interrupted, seconds=seconds,
                           backend=backend)


def _collect(stream: Iterator[RunOutcome], state: _BatchState, refresh_s: float) -> bool:
    """Record every outcome of ``stream``, rewriting the summary at most every ``refresh_s``
    seconds and once at the end; returns whether the batch was interrupted (Ctrl-C)."""
    state.report(None)
    interrupted = False
    last_write = time.monotonic()
    try:
        for outcome in stream:
            state.record(outcome)
            if time.monotonic() - last_write >= refresh_s:
                state.write_summary()
                last_write = time.monotonic()
    except KeyboardInterrupt:
        interrupted = True
    finally:
        if hasattr(stream, "close"):
            stream.close()
        state.write_summary()
    return interrupted
