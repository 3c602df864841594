"""The benchmark suites, and running them into one result document.

Result document (``python -m benchmarks --out``)::

    {"schema": 2, "date": ISO-8601 UTC, "quick": bool, "machine": {...}, "versions": {...},
     "git": commit or null, "seconds": wall time, "jobs": suites run at once,
     "suites": {name: {"status": "ok"|"failed"|"missing", "seconds", "error"}},
     "metrics": [metric, ...]}

with the metrics described in :mod:`benchmarks.metric`.  Each suite runs in its own Python
process, so one suite's imports, caches or memory peak do not affect another, and a crash
is reported as that suite's failure.
"""

from __future__ import annotations

import datetime as _dt
import importlib
import json
import os
import subprocess
import sys
import tempfile
import time
from collections.abc import Callable
from concurrent.futures import ThreadPoolExecutor, as_completed
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from benchmarks.environment import BLAS_ENV, ROOT, git_commit, library_versions, machine_info
from benchmarks.metric import Metric

SCHEMA = 2

Status = dict[str, Any]


@dataclass(frozen=True)
class Suite:
    """A benchmark suite: ``module:function`` called as ``function(quick) -> list[Metric]``."""

    name: str
    target: str
    description: str
    module: str = ""  # the measured module, if ``target`` is an adapter of it

    def load(self) -> Callable[[bool], list[Metric]]:
        """The suite's ``metrics(quick)`` function."""
        module, _, func = self.target.partition(":")
        return getattr(importlib.import_module(module), func)  # type: ignore[no-any-return]

    def module_path(self) -> Path:
        """The module's file (``x.py`` or ``x/__init__.py``)."""
        base = ROOT.joinpath(*(self.module or self.target.partition(":")[0]).split("."))
        package = base / "__init__.py"
        return package if package.exists() else base.with_suffix(".py")


#: Every suite, in the order they run.  A suite module exposes ``metrics(quick) -> list``
#: of :func:`~benchmarks.metric.speed_metric` / :func:`~benchmarks.metric.accuracy_metric`
#: dicts, and runs alone as ``python -m benchmarks.<module>``.
SUITES: tuple[Suite, ...] = (
    Suite("allan", "benchmarks.bench_allan:metrics",
          "oadev and every estimator against allantools; memory"),
    Suite("arma", "benchmarks.bench_arma:metrics",
          "select_arma against the statsmodels ARIMA loop"),
    Suite("davar", "benchmarks.bench_davar:metrics",
          "dynamic Allan deviation against looping allantools.oadev"),
    Suite("progress", "benchmarks.bench_progress:metrics",
          "cost of the progress reports: disabled, stubbed out, and the rich bar"),
    Suite("simulate", "benchmarks.bench_simulate:metrics",
          "simulate_gyro speed and memory, against allantools' Kasdin noise"),
    Suite("io", "benchmarks.bench_io:metrics",
          "read_run on CSV, .csv.gz, Parquet and .npy against pandas, pyarrow and numpy"),
    Suite("noise_fit", "benchmarks.bench_noise_fit:metrics",
          "noise-coefficient fit speed and accuracy"),
    Suite("selection_rate", "benchmarks.bench_selection_rate:metrics",
          "ARMA selection hit rate by true model"),
    Suite("alpha_id", "benchmarks.bench_alpha_id:metrics",
          "noise identification and confidence intervals against allantools"),
    Suite("emd_kalman", "benchmarks.bench_emd_kalman:metrics",
          "EMD, steady-state Kalman filter and thermal fit speed"),
    Suite("thermal", "benchmarks.bench_thermal:metrics",
          "thermal coefficient recovery on simulated cold starts"),
    Suite("accuracy", "benchmarks.accuracy:metrics",
          "noise-coefficient round trip by sensor grade (benchmarks/accuracy)"),
)


def suite_named(name: str) -> Suite:
    """The suite called ``name`` (KeyError if there is none)."""
    for s in SUITES:
        if s.name == name:
            return s
    raise KeyError(name)


def run_suite(suite: Suite, quick: bool, timeout_s: float | None) -> tuple[Status, list[Metric]]:
    """Run one suite in a fresh interpreter; return (status record, metrics)."""
    if not suite.module_path().exists():
        return {"status": "missing", "seconds": 0.0,
                "error": f"{suite.module_path().relative_to(ROOT)} does not exist"}, []
    fd, out = tempfile.mkstemp(prefix=f"bench-{suite.name}-", suffix=".json")
    os.close(fd)
    cmd = [sys.executable, "-m", "benchmarks", "--child", suite.name, "--child-out", out]
    if quick:
        cmd.append("--quick")
    t0 = time.perf_counter()
    env = {**BLAS_ENV, **os.environ, "PYTHONPATH": os.pathsep.join(
        [str(ROOT), *filter(None, [os.environ.get("PYTHONPATH")])])}
    try:
        res = subprocess.run(cmd, cwd=ROOT, env=env, capture_output=True, text=True,
                             timeout=timeout_s, check=False, stdin=subprocess.DEVNULL)
        seconds = time.perf_counter() - t0
        if res.returncode != 0:
            tail = (res.stderr or res.stdout).strip().splitlines()[-15:]
            return {"status": "failed", "seconds": seconds,
                    "error": f"exit code {res.returncode}: " + "\n".join(tail)}, []
        metrics = json.loads(Path(out).read_text())
    except subprocess.TimeoutExpired:
        return {"status": "failed", "seconds": time.perf_counter() - t0,
                "error": f"timed out after {timeout_s:.0f} s"}, []
    finally:
        Path(out).unlink(missing_ok=True)
    for m in metrics:
        m["suite"] = suite.name
    return {"status": "ok", "seconds": seconds, "error": ""}, metrics


def run_in_this_process(name: str, quick: bool, out: str) -> int:
    """Measure suite ``name`` here and write its metrics as JSON to ``out`` (the child's job)."""
    metrics = suite_named(name).load()(quick)
    Path(out).write_text(json.dumps(metrics, allow_nan=True))
    return 0


def _results(suites: list[Suite], *, quick: bool, timeout_s: float | None,
             log: Callable[[str], None], jobs: int) -> dict[str, tuple[Status, list[Metric]]]:
    """Run every suite, ``jobs`` at once; log one line as each one ends."""
    def report(suite: Suite, status: Status, metrics: list[Metric]) -> None:
        if status["status"] == "ok":
            log(f"== {suite.name}: {len(metrics)} figure(s) in {status['seconds']:.1f} s "
                f"({suite.description})")
        else:
            log(f"== {suite.name}: {status['status'].upper()}: {status['error']}")

    results: dict[str, tuple[Status, list[Metric]]] = {}
    if jobs <= 1:
        for suite in suites:
            log(f"-- {suite.name} ...")
            results[suite.name] = run_suite(suite, quick, timeout_s)
            report(suite, *results[suite.name])
        return results
    with ThreadPoolExecutor(max_workers=jobs) as pool:
        futures = {pool.submit(run_suite, s, quick, timeout_s): s for s in suites}
        for fut in as_completed(futures):
            suite = futures[fut]
            results[suite.name] = fut.result()
            report(suite, *results[suite.name])
    return results


def run_suites(suites: list[Suite], *, quick: bool, timeout_s: float | None,
               log: Callable[[str], None], jobs: int = 1) -> dict[str, Any]:
    """Run ``suites`` and return the full result document.

    ``jobs`` > 1 runs that many suites at once (each in its own process).  The suites then
    share the machine, which makes speed ratios noisier: use it for smoke runs
    (``--quick`` in CI), not for the reference result.
    """
    t0 = time.perf_counter()
    doc: dict[str, Any] = {
        "schema": SCHEMA,
        "date": _dt.datetime.now(_dt.UTC).replace(microsecond=0).isoformat(),
        "quick": quick, "machine": machine_info(), "versions": library_versions(),
        "git": git_commit(), "seconds": 0.0, "suites": {}, "metrics": [],
    }
    results = _results(suites, quick=quick, timeout_s=timeout_s, log=log, jobs=jobs)
    for suite in suites:  # the document lists the suites in their fixed order
        status, metrics = results[suite.name]
        doc["suites"][suite.name] = status
        doc["metrics"].extend(metrics)
    doc["jobs"] = jobs
    doc["seconds"] = time.perf_counter() - t0
    return doc


def merge_results(base: dict[str, Any], new: dict[str, Any]) -> dict[str, Any]:
    """``base`` with the suites of ``new`` replaced (metrics, status); header from ``new``.

    Raises ValueError if one is a quick run and the other is not.
    """
    if bool(base.get("quick")) != bool(new.get("quick")):
        raise ValueError("cannot merge a quick run with a full run")
    replaced = set(new.get("suites", {}))
    out = dict(new)
    out["suites"] = {**{k: v for k, v in base.get("suites", {}).items() if k not in replaced},
                     **new.get("suites", {})}
    out["metrics"] = ([m for m in base.get("metrics", []) if m.get("suite") not in replaced]
                      + list(new.get("metrics", [])))
    out["seconds"] = float(base.get("seconds", 0.0)) + float(new.get("seconds", 0.0))
    out["merged_from"] = [base.get("date"), new.get("date")]
    return out
