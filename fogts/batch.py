"""Many runs at once: the info, Allan and ARMA analyses of every file, on a local process pool
or on an existing Dask distributed cluster.

One summary row per run and axis, one JSON document per run.  The design goals:

* **a bad file never stops the batch** - its analysis error becomes a row with
  ``status="error"`` and the message in ``error``;
* **interruption is harmless** - every output (the per-run JSON, the summary) is written
  atomically (temporary file + rename), so an interrupted batch never leaves a truncated file;
  the summary is refreshed while the batch runs;
* **resumable** - with ``resume=True`` a run whose per-run JSON already exists is not run again:
  its rows are read back from that JSON, so the final summary has every run exactly once;
* **pluggable** - the per-file analysis is any picklable callable
  ``analysis(path, options) -> RunOutcome`` (default :func:`analyze_file`).

Scheduling is delegated: :class:`concurrent.futures.ProcessPoolExecutor` locally, or a Dask
``distributed.Client`` when a scheduler address is given (optional extra ``fogts[dask]``).

Examples
--------
>>> import numpy as np, tempfile, pathlib
>>> d = pathlib.Path(tempfile.mkdtemp())
>>> rng = np.random.default_rng(0)
>>> for i in range(2):
...     _ = np.savetxt(d / f"run{i}.csv", np.c_[np.arange(3000) / 10, rng.normal(size=3000)],
...                    delimiter=",", header="time,rate", comments="")
>>> res = run_batch([str(d / "*.csv")], summary_path=d / "summary.csv", workers=1)
>>> res.n_ok, res.n_error
(2, 0)
>>> sorted(res.to_frame().columns[:4])
['axis', 'file', 'fs_hz', 'n']
"""

from __future__ import annotations

import glob
import hashlib
import json
import math
import os
import time
import uuid
import warnings
from collections.abc import Callable, Iterable, Iterator, Sequence
from dataclasses import asdict, dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Any, Literal

import numpy as np
import pandas as pd

from fogts._validate import check_choice, check_int
from fogts.errors import DataError, DataQualityWarning
from fogts.io.missing import NAN_POLICIES
from fogts.preprocess.hygiene import GAP_POLICIES
from fogts.report.text import error_message, warning_texts

if TYPE_CHECKING:
    from fogts.io.run import Run
    from fogts.pipeline import AxisAllan, AxisSelection
    from fogts.preprocess.hygiene import DataQuality

__all__ = [
    "SUMMARY_COLUMNS",
    "BatchOptions",
    "BatchProgress",
    "BatchResult",
    "RunOutcome",
    "analyze_file",
    "error_message",
    "expand_patterns",
    "run_batch",
    "run_key",
]

#: Columns of the summary table, in order (one row per run and axis).
SUMMARY_COLUMNS: tuple[str, ...] = (
    "file", "axis", "n", "fs_hz", "units", "units_source", "n_gaps", "n_glitches",
    "N", "N_stderr", "B", "B_stderr", "K", "K_stderr",
    "selected", "aic", "white", "status", "error", "json",
)

#: Version of the per-run JSON layout (bumped on incompatible changes).
RUN_JSON_VERSION = 2

AllanKind = Literal["adev", "oadev", "mdev", "hdev", "ohdev", "totdev"]
_KINDS = ("adev", "oadev", "mdev", "hdev", "ohdev", "totdev")
_TAU_SPECS = ("octave", "decade", "dense", "all")
_CRITERIA = ("aic", "bic", "hqic", "aicc")


# --------------------------------------------------------------------------- records


@dataclass(frozen=True)
class BatchOptions:
    """What to read and how to analyse each file (picklable; sent to every worker).

    Attributes
    ----------
    rate_column, time_column, temperature_column, fs_hz, units
        Input options, as for :func:`fogts.io.reader.read_run` (``rate_column`` may hold several
        comma-separated names).
    kind : str
        Allan estimator (``oadev`` by default).
    taus : str
        Tau grid (``octave``, ``decade``, ``dense``, ``all``).
    detrend : int or None
        Polynomial order removed before the ARMA selection (None: mean removal only).
    decimate : int or None
        Block-averaging factor applied before the ARMA selection.
    criterion : str
        Ranking criterion of the ARMA selection.
    select : bool
        Run the ARMA selection (``False`` gives info and Allan only).
    nan : str
        Empty/NaN/inf cells: ``error``, ``drop`` or ``interpolate`` (see
        :func:`fogts.io.reader.read_run`).
    gaps : str
        Gaps in the time base: ``warn``, ``error``, ``split`` or ``ignore`` (see
        :func:`fogts.preprocess.hygiene.assess_run`).
    """

    rate_column: str | None = None
    time_column: str | None = None
    temperature_column: str | None = None
    fs_hz: float | None = None
    units: str | None = None
    kind: str = "oadev"
    taus: str = "octave"
    detrend: int | None = None
    decimate: int | None = None
    criterion: str = "aic"
    select: bool = True
    nan: str = "error"
    gaps: str = "warn"

    def __post_init__(self) -> None:
        check_choice("kind", self.kind, _KINDS)
        check_choice("taus", self.taus, _TAU_SPECS)
        check_choice("criterion", self.criterion, _CRITERIA)
        check_choice("nan", self.nan, NAN_POLICIES)
        check_choice("gaps", self.gaps, GAP_POLICIES)
        if self.detrend is not None:
            check_int("detrend", self.detrend, minimum=0, maximum=10)
        if self.decimate is not None:
            check_int("decimate", self.decimate, minimum=1)

    def to_dict(self) -> dict[str, Any]:
        return asdict(self)


@dataclass(frozen=True)
class RunOutcome:
    """The result of analysing one file.

    Attributes
    ----------
    file : str
        The file as matched by the pattern.
    status : str
        ``"ok"`` if every axis was analysed, else ``"error"``.
    error : str
        The first error message ("" when ok).
    rows : tuple of dict
        Summary rows, one per axis (one row with an empty axis if the file could not be read).
    document : dict
        The per-run JSON document (JSON-safe).
    persist : bool
        Whether the outcome is a property of the file (written as per-run JSON, so that
        ``resume`` skips it) rather than of the infrastructure (a worker that died).
    """

    file: str
    status: str
    error: str
    rows: tuple[dict[str, Any], ...]
    document: dict[str, Any] = field(default_factory=dict)
    persist: bool = True

    def to_dict(self) -> dict[str, Any]:
        return {"file": self.file, "status": self.status, "error": self.error,
                "rows": [dict(r) for r in self.rows]}


@dataclass(frozen=True)
class BatchProgress:
    """Progress of a batch, passed to the ``progress`` callback after each finished run."""

    total: int
    done: int
    failed: int
    skipped: int
    last_file: str | None = None

    @property
    def remaining(self) -> int:
        return self.total - self.done


@dataclass(frozen=True)
class BatchResult:
    """What a batch did.

    Attributes
    ----------
    rows : tuple of dict
        The summary rows (columns :data:`SUMMARY_COLUMNS`), sorted by file and axis.
    files : tuple of str
        Every matched file, in order.
    summary_path : Path
    json_dir : Path
    n_skipped : int
        Runs read back from existing per-run JSON (``resume``).
    interrupted : bool
        True if the batch stopped before every run finished.
    seconds : float
        Wall-clock time.
    backend : str
        ``"serial"``, ``"process-pool"`` or ``"dask"``.
    """

    rows: tuple[dict[str, Any], ...]
    files: tuple[str, ...]
    summary_path: Path
    json_dir: Path
    n_skipped: int = 0
    interrupted: bool = False
    seconds: float = 0.0
    backend: str = "serial"

    @property
    def n_files(self) -> int:
        return len(self.files)

    @property
    def n_ok(self) -> int:
        """Runs (files) with every axis ok."""
        return len(self._status_by_file()) - self.n_error

    @property
    def n_error(self) -> int:
        """Runs (files) with at least one failed axis."""
        return sum(1 for s in self._status_by_file().values() if s == "error")

    def _status_by_file(self) -> dict[str, str]:
        status: dict[str, str] = {}
        for r in self.rows:
            if r["status"] == "error" or r["file"] not in status:
                status[r["file"]] = r["status"]
        return status

    def to_frame(self) -> pd.DataFrame:
        return _rows_frame(self.rows)

    def to_dict(self) -> dict[str, Any]:
        return {"files": len(self.files), "ok": self.n_ok, "error": self.n_error,
                "skipped": self.n_skipped, "interrupted": self.interrupted,
                "backend": self.backend, "summary": str(self.summary_path),
                "json_dir": str(self.json_dir), "rows": [dict(r) for r in self.rows]}

    def summary(self) -> str:
        done = len(self._status_by_file())
        lines = [f"batch ({self.backend}): {done} of {self.n_files} run(s) done, "
                 f"{self.n_ok} ok, {self.n_error} failed, {self.n_skipped} resumed from JSON, "
                 f"{self.seconds:.1f} s",
                 f"summary  {self.summary_path}", f"per-run  {self.json_dir}"]
        if self.interrupted:
            lines.append("interrupted: rerun with --resume to finish")
        return "\n".join(lines)


# --------------------------------------------------------------------------- helpers


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
    for suffix in (".gz", ".csv", ".tsv", ".txt", ".dat", ".parquet", ".pq", ".npy", ".npz"):
        if base.lower().endswith(suffix) and len(base) > len(suffix):
            base = base[: -len(suffix)]
    safe = "".join(c if c.isalnum() or c in "-_." else "_" for c in base)[:80]
    return f"{safe}-{digest}.json"


def _blank_row(file: str, axis: str = "") -> dict[str, Any]:
    row: dict[str, Any] = dict.fromkeys(SUMMARY_COLUMNS, None)
    row.update(file=file, axis=axis, status="ok", error="")
    return row


def _error_outcome(file: str, message: str, *, persist: bool,
                   document: dict[str, Any] | None = None) -> RunOutcome:
    row = _blank_row(file)
    row.update(status="error", error=message)
    doc = document if document is not None else _document(file, "error", message, {}, [], [])
    doc["rows"] = [row]
    return RunOutcome(file=file, status="error", error=message, rows=(row,), document=doc,
                      persist=persist)


def _document(file: str, status: str, error: str, info: dict[str, Any],
              axes: list[dict[str, Any]], warn: list[str]) -> dict[str, Any]:
    from fogts._version import __version__

    return {"version": RUN_JSON_VERSION, "fogts": __version__, "file": file, "status": status,
            "error": error, "info": info, "allan": None, "select": [], "axes": axes,
            "warnings": warn, "rows": []}


def _finite(v: Any) -> float | None:
    try:
        f = float(v)
    except (TypeError, ValueError):
        return None
    return f if math.isfinite(f) else None


# --------------------------------------------------------------------------- the analysis


def _analyze_axis(run: Run, quality: DataQuality, axis: int, options: BatchOptions
                  ) -> tuple[dict[str, Any], AxisAllan, AxisSelection | None]:
    """The pipeline's Allan analysis and ARMA selection of one axis -> (row fields, the
    two results)."""
    from fogts.pipeline import (
        AllanSettings,
        SelectSettings,
        analyse_allan_axis,
        analyse_selection,
    )

    fields: dict[str, Any] = {}
    # one thread per analysis: the parallelism is across files
    allan = analyse_allan_axis(run, axis, AllanSettings(kind=options.kind, taus=options.taus,
                                                        workers=1))
    if allan.model is not None:
        for term in allan.model.terms:
            if term.name in ("N", "B", "K"):
                fields[term.name] = _finite(term.value)
                fields[f"{term.name}_stderr"] = _finite(term.stderr)
    selection = None
    if options.select:
        selection = analyse_selection(run, quality, axis, SelectSettings(
            detrend=options.detrend, decimate=options.decimate, criterion=options.criterion,
            stationarity=False), file=run.source)
        fields.update(_selection_fields(selection.selection))
    return fields, allan, selection


def _selection_fields(sel: Any) -> dict[str, Any]:
    """``selected``, ``aic`` and ``white`` of the selected candidate.

    Raises ModelFitError (an error row) if every candidate failed.
    """
    best = sel.best
    return {"selected": best.model, "aic": _finite(best.aic), "white": bool(best.white)}


def analyze_file(file: str, options: BatchOptions) -> RunOutcome:
    """Read one file and analyse every axis (the default batch analysis).

    Never raises for a problem with the file: it returns an outcome with ``status="error"``
    and the message.  An axis that fails gives an error row for that axis only.
    """
    from fogts.pipeline import AllanAnalysis, ReadSettings, load
    from fogts.report.text import run_info, to_jsonable

    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        try:
            run, quality = load(file, ReadSettings(
                rate_column=options.rate_column, time_column=options.time_column,
                temperature_column=options.temperature_column, fs_hz=options.fs_hz,
                units=options.units, nan=options.nan, gaps=options.gaps))
            for line in quality.warnings():  # named after the file by warning_texts' caller
                warnings.warn(f"{Path(file).name}: {line}", DataQualityWarning, stacklevel=1)
            info = {**run_info(run), "data_quality": quality.to_dict()}
        except Exception as exc:
            msg = error_message(exc)
            doc = _document(file, "error", msg, {}, [], warning_texts(caught))
            doc["options"] = options.to_dict()
            return _error_outcome(file, msg, persist=True, document=doc)

        rows: list[dict[str, Any]] = []
        axes_doc: list[dict[str, Any]] = []
        allan_axes: list[AxisAllan] = []
        selections: list[dict[str, Any]] = []
        for i, name in enumerate(run.axes):
            row = _blank_row(file, name)
            row.update(n=run.n, fs_hz=run.fs_hz, units=run.units,
                       units_source=run.units_source,
                       n_gaps=run.sampling.n_gaps if run.sampling is not None else 0,
                       n_glitches=quality.glitch_count(name))
            axis_doc: dict[str, Any] = {"axis": name, "status": "ok", "error": ""}
            try:
                fields, allan, selection = _analyze_axis(run, quality, i, options)
                row.update(fields)
                allan_axes.append(allan)
                if selection is not None:
                    selections.append(selection.to_dict())
            except Exception as exc:
                msg = error_message(exc)
                row.update(status="error", error=msg)
                axis_doc.update(status="error", error=msg)
            rows.append(row)
            axes_doc.append(axis_doc)
    errors = [r["error"] for r in rows if r["status"] == "error"]
    status = "error" if errors else "ok"
    doc = _document(file, status, errors[0] if errors else "", info, axes_doc,
                    warning_texts(caught))
    if allan_axes:
        doc["allan"] = AllanAnalysis(run=run, quality=quality, axes=tuple(allan_axes)).to_dict()
    doc["select"] = selections
    doc["options"] = options.to_dict()
    doc["rows"] = rows
    doc = to_jsonable(doc)
    return RunOutcome(file=file, status=status, error=errors[0] if errors else "",
                      rows=tuple(doc["rows"]), document=doc)


def _safe_call(analysis: Callable[[str, BatchOptions], RunOutcome], file: str,
               options: BatchOptions) -> RunOutcome:
    """Run ``analysis``; an exception escaping it becomes an error outcome."""
    try:
        return analysis(file, options)
    except Exception as exc:
        return _error_outcome(file, error_message(exc), persist=True)


# --------------------------------------------------------------------------- executors


def _serial(jobs: list[str], analysis: Callable[[str, BatchOptions], RunOutcome],
            options: BatchOptions) -> Iterator[RunOutcome]:
    for file in jobs:
        yield _safe_call(analysis, file, options)


def _process_pool(jobs: list[str], analysis: Callable[[str, BatchOptions], RunOutcome],
                  options: BatchOptions, workers: int) -> Iterator[RunOutcome]:
    import multiprocessing as mp
    from concurrent.futures import FIRST_COMPLETED, Future, ProcessPoolExecutor, wait

    # forkserver: workers fork from a clean server that has the heavy imports preloaded
    # (fork from a process with threads, e.g. a progress bar, is unsafe).
    ctx = mp.get_context("forkserver")
    ctx.set_forkserver_preload(["fogts.batch", "fogts.io.reader", "fogts.preprocess.prepare", "fogts.allan",
                                "fogts.arma"])
    pool = ProcessPoolExecutor(max_workers=workers, mp_context=ctx)
    pending: dict[Future[RunOutcome], str] = {}
    try:
        for file in jobs:
            pending[pool.submit(_safe_call, analysis, file, options)] = file
        while pending:
            done, _ = wait(pending, return_when=FIRST_COMPLETED)
            for fut in done:
                file = pending.pop(fut)
                try:
                    yield fut.result()
                except Exception as exc:  # the worker died (BrokenProcessPool) or unpicklable
                    yield _error_outcome(file, f"worker failed: {error_message(exc)}",
                                         persist=False)
    finally:
        pool.shutdown(wait=True, cancel_futures=True)


def _dask(jobs: list[str], analysis: Callable[[str, BatchOptions], RunOutcome],
          options: BatchOptions, scheduler: str, timeout_s: float) -> Iterator[RunOutcome]:
    try:
        from distributed import Client, as_completed
    except ImportError:
        raise DataError("scheduler requires Dask distributed: pip install 'fogts[dask]'"
                        ) from None
    try:
        client = Client(scheduler, timeout=timeout_s, set_as_default=False)
    except (OSError, TimeoutError, ValueError) as exc:
        raise DataError(f"cannot connect to the Dask scheduler at {scheduler!r}: "
                        f"{error_message(exc)}") from None
    try:
        token = uuid.uuid4().hex[:12]  # keys unique to this batch on a shared cluster
        futures = {client.submit(_safe_call, analysis, f, options, pure=False,
                                 key=f"fogts-batch-{token}-{i}-{run_key(f)}"): f
                   for i, f in enumerate(jobs)}
        for fut in as_completed(list(futures), loop=client.loop):
            file = futures[fut]
            try:
                yield fut.result()
            except Exception as exc:  # a worker was lost, or the task could not be sent
                yield _error_outcome(file, f"worker failed: {error_message(exc)}",
                                     persist=False)
            finally:
                fut.release()
    finally:
        client.close()


# --------------------------------------------------------------------------- the batch


def _rows_frame(rows: Iterable[dict[str, Any]]) -> pd.DataFrame:
    frame = pd.DataFrame(list(rows), columns=list(SUMMARY_COLUMNS))
    for col in ("n",):
        frame[col] = frame[col].astype("Int64")
    for col in ("fs_hz", "N", "N_stderr", "B", "B_stderr", "K", "K_stderr", "aic"):
        frame[col] = pd.to_numeric(frame[col], errors="coerce").astype(np.float64)
    frame["white"] = frame["white"].astype("boolean")
    frame["error"] = frame["error"].fillna("")
    return frame


def _load_resumed(path: Path, file: str) -> RunOutcome | None:
    """The outcome stored in a per-run JSON, or None if it is unusable."""
    try:
        doc = json.loads(path.read_text(encoding="utf-8"))
        rows = doc["rows"]
        if doc.get("version") != RUN_JSON_VERSION or not rows:
            return None
    except (OSError, ValueError, KeyError, TypeError):
        return None
    fixed = []
    for r in rows:
        row = _blank_row(file)
        row.update({k: r.get(k) for k in SUMMARY_COLUMNS if k in r})
        row["file"] = file
        fixed.append(row)
    status = "error" if any(r["status"] == "error" for r in fixed) else "ok"
    return RunOutcome(file=file, status=status, error=str(doc.get("error") or ""),
                      rows=tuple(fixed), document=doc)


def _default_json_dir(summary_path: Path) -> Path:
    name = summary_path.name
    for suffix in (".gz", ".csv", ".tsv", ".txt", ".parquet", ".pq"):
        if name.lower().endswith(suffix):
            name = name[: -len(suffix)]
    return summary_path.with_name(f"{name}_runs")


def run_batch(
    patterns: Sequence[str],
    *,
    summary_path: str | os.PathLike[str],
    json_dir: str | os.PathLike[str] | None = None,
    workers: int | None = None,
    scheduler: str | None = None,
    resume: bool = False,
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
        No file matches, ``workers`` < 1, or the scheduler cannot be reached.
    """
    from fogts.io.paths import check_outputs
    from fogts.io.writer import write_frame_atomic, write_text_atomic
    from fogts.report.text import json_dumps

    t0 = time.perf_counter()
    options = options if options is not None else BatchOptions()
    summary = Path(summary_path)
    if not summary.name.lower().endswith((".csv", ".csv.gz", ".tsv", ".txt", ".parquet", ".pq")):
        raise DataError(f"summary_path must end in .csv, .csv.gz, .tsv, .txt or .parquet; got "
                        f"{summary.name!r}")
    if workers is not None:
        workers = check_int("workers", workers, minimum=1)
    files = expand_patterns(patterns)
    jdir = Path(json_dir) if json_dir is not None else _default_json_dir(summary)
    check_outputs({"summary_path": summary}, {"patterns": files})
    jdir.mkdir(parents=True, exist_ok=True)
    check_outputs({f"per-run JSON of {f!r}": jdir / run_key(f) for f in files},
                  {"patterns": files})

    outcomes: dict[str, RunOutcome] = {}
    skipped = 0
    if resume:
        for f in files:
            got = _load_resumed(jdir / run_key(f), f)
            if got is not None:
                outcomes[f] = got
                skipped += 1
    jobs = [f for f in files if f not in outcomes]

    def rows() -> list[dict[str, Any]]:
        out: list[dict[str, Any]] = []
        for f in files:
            if f in outcomes:
                for r in outcomes[f].rows:
                    out.append({**r, "json": run_key(f) if outcomes[f].persist else None})
        return out

    def failed() -> int:
        return sum(1 for o in outcomes.values() if o.status == "error")

    def write_summary() -> None:
        write_frame_atomic(summary, _rows_frame(rows()))

    def report(last: str | None) -> None:
        if progress is not None:
            progress(BatchProgress(total=len(files), done=len(outcomes), failed=failed(),
                                   skipped=skipped, last_file=last))

    if scheduler:
        backend = "dask"
        stream = _dask(jobs, analysis, options, scheduler, connect_timeout_s)
    elif (workers or os.cpu_count() or 1) == 1 or len(jobs) <= 1:
        backend = "serial"
        stream = _serial(jobs, analysis, options)
    else:
        backend = "process-pool"
        stream = _process_pool(jobs, analysis, options,
                               min(workers or os.cpu_count() or 1, len(jobs)))

    report(None)
    interrupted = False
    last_write = time.monotonic()
    try:
        for outcome in stream:
            if outcome.persist:
                write_text_atomic(jdir / run_key(outcome.file), json_dumps(outcome.document)
                                  + "\n")
            outcomes[outcome.file] = outcome
            report(outcome.file)
            if time.monotonic() - last_write >= refresh_s:
                write_summary()
                last_write = time.monotonic()
    except KeyboardInterrupt:
        interrupted = True
    finally:
        if hasattr(stream, "close"):
            stream.close()
        write_summary()
    return BatchResult(rows=tuple(rows()), files=tuple(files), summary_path=summary,
                       json_dir=jdir, n_skipped=skipped, interrupted=interrupted,
                       seconds=time.perf_counter() - t0, backend=backend)
