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

Modules: :mod:`~fogts.batch.records` (options, outcomes, progress, result),
:mod:`~fogts.batch.documents` (the per-run JSON), :mod:`~fogts.batch.files` (patterns, run
keys, resumed runs), :mod:`~fogts.batch.analysis` (the default per-file analysis),
:mod:`~fogts.batch.executors` (serial, process pool, Dask) and :mod:`~fogts.batch.runner`
(:func:`run_batch`).

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

from fogts.batch.analysis import analyze_file
from fogts.batch.documents import RUN_JSON_VERSION
from fogts.batch.files import expand_patterns, run_key
from fogts.batch.records import (
    SUMMARY_COLUMNS,
    BatchOptions,
    BatchProgress,
    BatchResult,
    RunOutcome,
)
from fogts.batch.runner import run_batch
from fogts.report.text import error_message

__all__ = [
    "RUN_JSON_VERSION",
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
