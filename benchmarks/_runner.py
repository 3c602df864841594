"""The benchmark runner: every suite, one JSON result, a markdown table, and ``--compare``.

Result format (``--out``)::

    {"schema": 2, "date": ISO-8601 UTC, "quick": bool, "machine": {...}, "versions": {...},
     "git": commit or null, "seconds": wall time,
     "suites": {name: {"status": "ok"|"failed"|"missing", "seconds", "error"}},
     "metrics": [{"id", "suite", "title", "kind": "speed"|"accuracy", "value", "unit",
                  "better": "higher"|"lower", "tolerance", "abs_tolerance",
                  "seconds": {name: s}, "details": {...},
                  # speed figures only:
                  "cpu_value", "cpu_seconds": {name: s}, "parallel": bool,
                  "other_load": cores, "noise": {"rounds", "spread_wall", "spread_cpu"}}]}

* A **speed** metric's value is a ratio measured in one run: peer seconds / fogts seconds
  (higher is better), from the best wall time of each side.  ``cpu_value`` is the same
  ratio from the best CPU times (process time of the calls).  Absolute seconds are stored
  and shown, never compared.  ``other_load`` is how many cores other processes kept busy
  while the figure was timed (``/proc/stat``); ``noise`` the spread of the ratio over the
  timed rounds (information only: it does not widen the tolerance).
* An **accuracy** metric is an error (lower is better) or a rate (higher is better) measured
  on simulated data with fixed seeds (the same value on every run of the same code), or a
  memory multiple, or a CPU time without a peer.
* Metric ids carry the problem size (``speed.oadev.n=1e7``), so a ``--quick`` run and a full
  run never compare figures of different sizes.

``--compare OLD`` flags a metric whose figure got worse than OLD's by more than its
tolerance (10 % relative by default, and more than ``abs_tolerance`` absolute), and a metric
of OLD that is missing now; it exits 1 if anything is flagged.  The machine is shared, so
which figure of a speed metric is compared follows one rule (:func:`compared_values`):

* **single-threaded** figures (both sides run on one thread; the suites run with one BLAS
  thread) are compared on the **CPU-time ratio**.  A single-threaded call's CPU time does not
  grow while the process waits for a core, so the ratio stays within a few per cent under a
  load that moves the wall-time ratio by 30-50 %; a slower fogts function still shows fully.
* **parallel** figures (a side may use several threads: oadev with its default thread pool,
  pyarrow's readers) depend on free cores.  They are compared on the wall-time ratio only if
  other processes kept at most ``FREE_LOAD`` (0.25) cores busy while each of the two runs
  timed them; otherwise they are shown but not judged (``not judged (busy)``).  Their CPU
  time is no substitute: threads sharing one core spend less CPU time than threads running
  side by side (measured: totdev's CPU-time ratio 2.2 idle, 3.1 with a core taken).  Every
  parallel figure has a single-threaded sibling that is always judged on CPU time
  (``speed.oadev.1thread``, ``speed.read_run.csv_1thread``,
  ``speed.read_run.parquet_1thread``).
* Each side is timed in rotating rounds and its best time kept (:func:`measure`); fast
  calls get more rounds (``min_total_s``).
* A suite with a flagged speed figure is measured again (``--confirm`` times, default 2) and
  the measurement closest to OLD is kept, so a slowdown must show in every measurement to be
  reported; accuracy figures are deterministic and are not re-measured.

Each suite runs in its own Python process, so one suite's imports, caches or memory peak do
not affect another, and a crash is reported as that suite's failure.
"""

from __future__ import annotations

import argparse
import datetime as _dt
import importlib
import json
import os
import platform
import subprocess
import sys
import tempfile
import time
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import Any

SCHEMA = 2
DEFAULT_TOLERANCE = 0.10
ROOT = Path(__file__).resolve().parents[1]

Metric = dict[str, Any]


# --------------------------------------------------------------------------- metric helpers


#: A parallel figure is compared on wall time only if, in both runs, other processes kept
#: at most this many cores busy on average while it was timed (see :func:`compare`).
FREE_LOAD = 0.25


def speed_metric(id: str, title: str, *, fogts_s: float, peer_s: float, peer: str,
                 suite: str = "", tolerance: float = DEFAULT_TOLERANCE,
                 fogts_cpu_s: float | None = None, peer_cpu_s: float | None = None,
                 parallel: bool = False, other_load: float | None = None,
                 noise: dict[str, Any] | None = None,
                 details: dict[str, Any] | None = None) -> Metric:
    """A speed figure: ``peer_s / fogts_s`` ("x faster than the peer"; higher is better).

    ``fogts_cpu_s`` / ``peer_cpu_s`` are the CPU times of the same calls (process time, all
    threads); their ratio is ``cpu_value``.  ``parallel`` says that a contender may use more
    than one thread; ``other_load`` is the number of cores other processes kept busy while
    the figure was timed; ``noise`` holds the spread of the ratio over the timed rounds.
    """
    cpu_value = (peer_cpu_s / fogts_cpu_s if fogts_cpu_s is not None and peer_cpu_s is not None
                 and fogts_cpu_s > 0 else None)
    return {"id": id, "suite": suite, "title": title, "kind": "speed",
            "value": peer_s / fogts_s if fogts_s > 0 else float("nan"),
            "cpu_value": cpu_value, "parallel": bool(parallel),
            "other_load": None if other_load is None else round(float(other_load), 3),
            "unit": f"x vs {peer}", "better": "higher", "tolerance": tolerance,
            "abs_tolerance": 0.0, "seconds": {"fogts": fogts_s, peer: peer_s},
            "cpu_seconds": ({} if cpu_value is None else {"fogts": fogts_cpu_s, peer: peer_cpu_s}),
            "noise": noise or {}, "details": details or {}}


def accuracy_metric(id: str, title: str, *, value: float, better: str, unit: str = "",
                    suite: str = "", tolerance: float = DEFAULT_TOLERANCE,
                    abs_tolerance: float = 0.0, details: dict[str, Any] | None = None) -> Metric:
    """An accuracy figure (an error: ``better="lower"``; a rate: ``better="higher"``)."""
    if better not in ("lower", "higher"):
        raise ValueError(f"better must be 'lower' or 'higher', got {better!r}")
    return {"id": id, "suite": suite, "title": title, "kind": "accuracy", "value": value,
            "unit": unit, "better": better, "tolerance": tolerance,
            "abs_tolerance": abs_tolerance, "seconds": {}, "details": details or {}}


# --------------------------------------------------------------------------- timing


def _busy_seconds() -> float | None:
    """CPU seconds all cores spent busy since boot (``/proc/stat``; None elsewhere)."""
    try:
        with open("/proc/stat", encoding="ascii") as fh:
            fields = [int(v) for v in fh.readline().split()[1:9]]
    except (OSError, ValueError):
        return None
    idle = fields[3] + (fields[4] if len(fields) > 4 else 0)  # idle + iowait
    return (sum(fields) - idle) / float(os.sysconf("SC_CLK_TCK"))


class LoadProbe:
    """Cores kept busy by *other* processes during a stretch of this process's work.

    The machine's busy CPU time (``/proc/stat``, steal included) minus this process's own
    CPU time, divided by the wall time: 0 on an idle machine, about 1 when one core is taken.
    """

    def __init__(self) -> None:
        self.busy0 = _busy_seconds()
        self.cpu0 = time.process_time()
        self.wall0 = time.perf_counter()

    def other_load(self) -> float | None:
        busy1 = _busy_seconds()
        wall = time.perf_counter() - self.wall0
        if busy1 is None or self.busy0 is None or wall <= 0:
            return None
        own = time.process_time() - self.cpu0
        return max(0.0, (busy1 - self.busy0 - own) / wall)


@dataclass
class Timing:
    """Best wall and CPU time of each contender over ``rounds`` rotating rounds.

    ``rounds_s[name]`` holds every round's ``(wall, cpu)`` pair; ``other_load`` is the
    :class:`LoadProbe` reading over the whole measurement.
    """

    wall: dict[str, float]
    cpu: dict[str, float]
    rounds_s: dict[str, list[tuple[float, float]]]
    other_load: float | None

    @property
    def rounds(self) -> int:
        return min((len(v) for v in self.rounds_s.values()), default=0)

    def noise(self, ours: str, peer: str) -> dict[str, Any]:
        """Spread of the per-round ratio ``peer / ours`` (max / min - 1), wall and CPU."""
        out: dict[str, Any] = {"rounds": self.rounds}
        for k, clock in ((0, "wall"), (1, "cpu")):
            r = [b[k] / a[k] for a, b in zip(self.rounds_s[ours], self.rounds_s[peer],
                                            strict=False) if a[k] > 0]
            out[f"spread_{clock}"] = round(max(r) / min(r) - 1.0, 4) if r and min(r) > 0 \
                else None
        return out


def measure(fns: dict[str, Callable[[], Any]], *, repeat: int = 3, min_total_s: float = 0.0,
            max_repeat: int = 50) -> Timing:
    """Time several calls in rotating order; keep the best wall and CPU time of each.

    Round ``i`` starts with the ``i``-th function, so every contender sees the same machine
    load on average, and the minimum discards the time lost to other processes (noise only
    adds time).  At least ``repeat`` rounds are timed, more (up to ``max_repeat``) until the
    rounds took ``min_total_s`` in all, which steadies fast calls.  CPU time is the process
    time (all threads of this process): for a single-threaded call it does not grow while
    the process waits for a core, which makes it far less sensitive to load than wall time.
    """
    names = list(fns)
    rounds: dict[str, list[tuple[float, float]]] = {n: [] for n in names}
    probe = LoadProbe()
    total = 0.0
    i = 0
    while i < repeat or (total < min_total_s and i < max_repeat):
        for k in range(len(names)):
            name = names[(i + k) % len(names)]
            c0, t0 = time.process_time(), time.perf_counter()
            fns[name]()
            dt, dc = time.perf_counter() - t0, time.process_time() - c0
            total += dt
            rounds[name].append((dt, dc))
        i += 1
    return Timing(wall={n: min(w for w, _ in v) for n, v in rounds.items()},
                  cpu={n: min(c for _, c in v) for n, v in rounds.items()},
                  rounds_s=rounds, other_load=probe.other_load())


def timed_once(fn: Callable[[], Any]) -> tuple[float, float, Any]:
    """``(wall, cpu, result)`` of one call (for calls too slow to repeat)."""
    c0, t0 = time.process_time(), time.perf_counter()
    out = fn()
    return time.perf_counter() - t0, time.process_time() - c0, out


def speed_from(timing: Timing, id: str, title: str, *, peer: str, peer_key: str = "peer",
               ours: str = "fogts", parallel: bool = False, suite: str = "",
               tolerance: float = DEFAULT_TOLERANCE,
               details: dict[str, Any] | None = None) -> Metric:
    """A :func:`speed_metric` from a :class:`Timing` (``ours`` against ``peer_key``)."""
    return speed_metric(id, title, fogts_s=timing.wall[ours], peer_s=timing.wall[peer_key],
                        peer=peer, fogts_cpu_s=timing.cpu[ours],
                        peer_cpu_s=timing.cpu[peer_key], parallel=parallel,
                        other_load=timing.other_load, noise=timing.noise(ours, peer_key),
                        suite=suite, tolerance=tolerance, details=details)


def best_time(fn: Callable[[], Any], *, repeat: int = 3, warmup: int = 0) -> float:
    """Smallest wall time of ``repeat`` calls of ``fn`` (after ``warmup`` untimed calls)."""
    for _ in range(warmup):
        fn()
    return measure({"fn": fn}, repeat=repeat).wall["fn"]


def paired_times(fogts_fn: Callable[[], Any], peer_fn: Callable[[], Any], *, repeat: int = 3,
                 min_total_s: float = 0.0, max_repeat: int = 50) -> tuple[float, float]:
    """Best wall times of ``fogts_fn`` and ``peer_fn``, measured alternately (:func:`measure`)."""
    t = measure({"fogts": fogts_fn, "peer": peer_fn}, repeat=repeat, min_total_s=min_total_s,
                max_repeat=max_repeat)
    return t.wall["fogts"], t.wall["peer"]


def interleaved_times(fns: dict[str, Callable[[], Any]], *, repeat: int = 3,
                      min_total_s: float = 0.0, max_repeat: int = 50) -> dict[str, float]:
    """Best wall time of each of several calls, measured in rotating order (:func:`measure`)."""
    return measure(fns, repeat=repeat, min_total_s=min_total_s, max_repeat=max_repeat).wall


# --------------------------------------------------------------------------- suites


@dataclass(frozen=True)
class Suite:
    """A benchmark suite: ``module:function`` called as ``function(quick) -> list[Metric]``."""

    name: str
    target: str
    description: str
    module: str = ""  # the measured module, if ``target`` is an adapter of it

    def load(self) -> Callable[[bool], list[Metric]]:
        module, _, func = self.target.partition(":")
        return getattr(importlib.import_module(module), func)  # type: ignore[no-any-return]

    def module_path(self) -> Path:
        """The module's file (``x.py`` or ``x/__init__.py``)."""
        base = ROOT.joinpath(*(self.module or self.target.partition(":")[0]).split("."))
        package = base / "__init__.py"
        return package if package.exists() else base.with_suffix(".py")


#: Every suite, in the order they run.  A suite module exposes ``metrics(quick) -> list``
#: of :func:`speed_metric` / :func:`accuracy_metric` dicts, and runs alone as a script.
SUITES: tuple[Suite, ...] = (
    Suite("allan", "benchmarks.bench_allan:metrics",
          "oadev and every estimator against allantools; memory"),
    Suite("arma", "benchmarks.bench_arma:metrics",
          "select_arma against the statsmodels ARIMA loop"),
    Suite("davar", "benchmarks.bench_davar:metrics",
          "dynamic Allan deviation against looping allantools.oadev"),
    Suite("simulate", "benchmarks.bench_simulate:metrics",
          "simulate_gyro speed and memory, against allantools' Kasdin noise"),
    Suite("io", "benchmarks.bench_io:metrics",
          "read_run MB/s on CSV and Parquet against pandas"),
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


# --------------------------------------------------------------------------- machine


def _cpu_model() -> str:
    try:
        for line in Path("/proc/cpuinfo").read_text().splitlines():
            if line.lower().startswith("model name"):
                return line.split(":", 1)[1].strip()
    except OSError:
        pass
    return platform.processor() or platform.machine()


def _memory_gib() -> float | None:
    try:
        for line in Path("/proc/meminfo").read_text().splitlines():
            if line.startswith("MemTotal:"):
                return round(int(line.split()[1]) / 2**20, 1)
    except (OSError, ValueError):
        pass
    return None


#: BLAS threads of the suites, unless the environment sets them: one, so a single-threaded
#: figure is single-threaded on both sides (its CPU time is then its work) and an idle BLAS
#: pool cannot spin on a loaded 2-core machine.  (Not OMP_NUM_THREADS: pyarrow sizes its
#: own thread pool from it, and its readers are measured multi-threaded.)
BLAS_ENV = {"OPENBLAS_NUM_THREADS": "1", "MKL_NUM_THREADS": "1"}


def machine_info() -> dict[str, Any]:
    """CPU, cores, memory, OS, Python, BLAS threads and the load average at the start."""
    load = os.getloadavg() if hasattr(os, "getloadavg") else None
    return {"cpu": _cpu_model(), "cores": os.cpu_count(), "memory_gib": _memory_gib(),
            "platform": platform.platform(), "python": platform.python_version(),
            "blas_threads": {k: os.environ.get(k, v) for k, v in BLAS_ENV.items()},
            "loadavg_at_start": [round(v, 2) for v in load] if load else None}


def library_versions() -> dict[str, str | None]:
    """Versions of fogts and of every library a suite measures against."""
    from importlib import metadata

    out: dict[str, str | None] = {}
    for dist in ("fogts", "numpy", "scipy", "pandas", "statsmodels", "allantools", "pyarrow",
                 "matplotlib", "dask", "distributed"):
        try:
            out[dist] = metadata.version(dist)
        except metadata.PackageNotFoundError:
            out[dist] = None
    return out


def _git_commit() -> str | None:
    try:
        res = subprocess.run(["git", "-C", str(ROOT), "rev-parse", "HEAD"], capture_output=True,
                             text=True, timeout=10, check=False)
    except (OSError, subprocess.SubprocessError):
        return None
    commit = res.stdout.strip()
    if res.returncode != 0 or not commit:
        return None
    dirty = subprocess.run(["git", "-C", str(ROOT), "status", "--porcelain", "--",
                            "fogts", "benchmarks"], capture_output=True, text=True,
                           timeout=10, check=False).stdout.strip()
    return commit + ("+dirty" if dirty else "")


# --------------------------------------------------------------------------- running


def _run_child(suite: Suite, quick: bool, timeout_s: float | None) -> tuple[dict[str, Any],
                                                                           list[Metric]]:
    """Run one suite in a fresh interpreter; return (status record, metrics)."""
    if not suite.module_path().exists():
        return {"status": "missing", "seconds": 0.0,
                "error": f"{suite.module_path().relative_to(ROOT)} does not exist"}, []
    fd, out = tempfile.mkstemp(prefix=f"bench-{suite.name}-", suffix=".json")
    os.close(fd)
    cmd = [sys.executable, "-m", "benchmarks._runner", "--child", suite.name, "--child-out", out]
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


def _child_main(name: str, quick: bool, out: str) -> int:
    suite = next(s for s in SUITES if s.name == name)
    metrics = suite.load()(quick)
    Path(out).write_text(json.dumps(metrics, allow_nan=True))
    return 0


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
        "git": _git_commit(), "seconds": 0.0, "suites": {}, "metrics": [],
    }
    def report(suite: Suite, status: dict[str, Any], metrics: list[Metric]) -> None:
        if status["status"] == "ok":
            log(f"== {suite.name}: {len(metrics)} figure(s) in {status['seconds']:.1f} s "
                f"({suite.description})")
        else:
            log(f"== {suite.name}: {status['status'].upper()}: {status['error']}")

    results: dict[str, tuple[dict[str, Any], list[Metric]]] = {}
    if jobs <= 1:
        for suite in suites:
            log(f"-- {suite.name} ...")
            results[suite.name] = _run_child(suite, quick, timeout_s)
            report(suite, *results[suite.name])
    else:
        from concurrent.futures import ThreadPoolExecutor, as_completed

        with ThreadPoolExecutor(max_workers=jobs) as pool:
            futures = {pool.submit(_run_child, s, quick, timeout_s): s for s in suites}
            for fut in as_completed(futures):
                suite = futures[fut]
                results[suite.name] = fut.result()
                report(suite, *results[suite.name])
    for suite in suites:  # the document lists the suites in their fixed order
        status, metrics = results[suite.name]
        doc["suites"][suite.name] = status
        doc["metrics"].extend(metrics)
    doc["jobs"] = jobs
    doc["seconds"] = time.perf_counter() - t0
    return doc


# --------------------------------------------------------------------------- comparing


def _worse_by(new: float, old: float, better: str) -> float:
    """Relative change in the bad direction (positive = worse)."""
    if old == 0:
        return float("inf") if (new > 0 if better == "lower" else new < 0) else 0.0
    change = (new - old) / abs(old)
    return -change if better == "higher" else change


def compared_values(new: Metric, old: Metric) -> tuple[float, float, str]:
    """The two figures ``--compare`` sets against each other, and the basis used.

    * accuracy figure: its ``value`` (``"value"``);
    * single-threaded speed figure: the CPU-time ratio ``cpu_value`` (``"cpu"``);
    * parallel speed figure: the wall-time ratio when other processes kept at most
      :data:`FREE_LOAD` cores busy in both runs (``"wall"``: the cores were free), else
      ``"busy"``: not judged.  (Its CPU time is no substitute: threads that share one core
      spend less CPU time than threads running side by side, so the CPU-time ratio moves
      with the load too.)  Every parallel figure has a single-threaded sibling.
    * a stored result without CPU times (older schema): the wall ratio (``"wall"``).
    """
    if new.get("kind") != "speed":
        return new["value"], old["value"], "value"
    if new.get("parallel") or old.get("parallel"):
        loads = (new.get("other_load"), old.get("other_load"))
        if all(isinstance(x, int | float) and _is_number(x) and x <= FREE_LOAD for x in loads):
            return new["value"], old["value"], "wall"
        return new["value"], old["value"], "busy"
    cpu_new, cpu_old = new.get("cpu_value"), old.get("cpu_value")
    if not (isinstance(cpu_new, int | float) and isinstance(cpu_old, int | float)
            and _is_number(cpu_new) and _is_number(cpu_old)):
        return new["value"], old["value"], "wall"
    return float(cpu_new), float(cpu_old), "cpu"


def compare_row(m: Metric, o: Metric | None) -> dict[str, Any]:
    """One comparison row for new metric ``m`` against old metric ``o`` (see :func:`compare`)."""
    row: dict[str, Any] = {"id": m["id"], "title": m["title"], "unit": m.get("unit", ""),
                           "new": m["value"], "old": None if o is None else o["value"],
                           "change": None, "basis": ""}
    if o is None:
        row["verdict"] = "new"
        return row
    new_v, old_v, basis = compared_values(m, o)
    row.update(new=new_v, old=old_v, basis=basis)
    if not _is_number(new_v) or not _is_number(old_v):
        row["verdict"] = "not comparable"
        return row
    worse = _worse_by(float(new_v), float(old_v), m["better"])
    row["change"] = worse
    if basis == "busy":
        row["verdict"] = "not judged (busy)"
        return row
    tol = float(m.get("tolerance", DEFAULT_TOLERANCE))
    abs_tol = float(m.get("abs_tolerance", 0.0))
    row["tolerance"] = tol
    if worse > tol and abs(float(new_v) - float(old_v)) > abs_tol:
        row["verdict"] = "REGRESSION"
    else:
        row["verdict"] = "better" if worse < -tol else "ok"
    return row


def compare(new: dict[str, Any], old: dict[str, Any]) -> list[dict[str, Any]]:
    """One row per metric of either document: ``{id, title, old, new, change, basis, verdict}``.

    ``old``/``new`` are the figures compared (:func:`compared_values`; ``basis`` says which).
    ``verdict`` is ``ok``, ``better``, ``REGRESSION``, ``MISSING`` (in old, not in new: the
    figure is no longer measured), ``new``, ``not measured`` (its suite did not run, or the
    runs differ in ``quick``), ``not comparable`` (a NaN value) or ``not judged (busy)`` (a
    parallel figure timed while other processes held a core).
    """
    old_by = {m["id"]: m for m in old.get("metrics", [])}
    new_by = {m["id"]: m for m in new.get("metrics", [])}
    rows = [compare_row(m, old_by.get(mid)) for mid, m in new_by.items()]
    quick = bool(new.get("quick"))
    ran = set(new.get("suites", {}))
    for mid, o in old_by.items():
        if mid not in new_by:
            # Only a figure that the same kind of run (quick or full) of the same suite
            # measured before can go missing; suites left out with --only are not measured.
            measured = bool(old.get("quick")) == quick and (not ran or o.get("suite") in ran)
            rows.append({"id": mid, "title": o["title"], "unit": o.get("unit", ""),
                         "old": o["value"], "new": None, "change": None, "basis": "",
                         "verdict": "MISSING" if measured else "not measured"})
    return rows


def _is_number(v: Any) -> bool:
    return (isinstance(v, int | float) and not isinstance(v, bool) and v == v
            and v not in (float("inf"), float("-inf")))


def merge_best(doc: dict[str, Any], again: list[Metric], old: dict[str, Any]) -> None:
    """Fold a re-measurement of speed figures into ``doc``, keeping the better measurement.

    "Better" is judged the way :func:`compare` judges against ``old`` (the same basis), so
    a re-measurement can clear a figure that timing noise flagged, but a slowdown that every
    measurement shows stays flagged.  A kept re-measurement is marked ``remeasured``.
    """
    old_by = {m["id"]: m for m in old.get("metrics", [])}
    by_id = {m["id"]: m for m in again}
    for i, m in enumerate(doc["metrics"]):
        n = by_id.get(m["id"])
        o = old_by.get(m["id"])
        if n is None or m["kind"] != "speed" or o is None:
            continue
        cur_row, cand_row = compare_row(m, o), compare_row(n, o)
        cur, cand = cur_row["change"], cand_row["change"]
        if cand_row["verdict"] == "not judged (busy)" and cur_row["verdict"] != cand_row["verdict"]:
            continue  # a busy re-measurement does not replace a judged one
        if cand is not None and (cur is None or cand < cur):
            doc["metrics"][i] = {**n, "details": {**n.get("details", {}), "remeasured": True}}


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


# --------------------------------------------------------------------------- rendering


def _fmt(v: Any, digits: int = 3) -> str:
    if v is None:
        return "-"
    if isinstance(v, bool):
        return str(v)
    if isinstance(v, int):
        return str(v)
    if isinstance(v, float):
        if v != v:
            return "nan"
        if v == 0:
            return "0"
        if abs(v) >= 1e4 or abs(v) < 1e-3:
            return f"{v:.{digits}g}"
        return f"{v:.{digits}g}" if abs(v) < 1 else f"{v:.{max(digits - 1, 1)}f}".rstrip(
            "0").rstrip(".")
    return str(v)


def _md_escape(text: str) -> str:
    return str(text).replace("|", "\\|").replace("\n", " ")


def script_main(doc: str | None, metrics: Callable[[bool], list[Metric]],
                argv: list[str] | None = None, *, quick_help: str = "smaller problems",
                default_out: Path | None = None) -> int:
    """The command line every single-suite benchmark script shares.

    ``--quick`` passes ``quick=True`` to ``metrics``; the markdown table is printed and
    written to ``--out`` (or, for a full run, ``default_out``).
    """
    p = argparse.ArgumentParser(description=(doc or "").split("\n")[0])
    p.add_argument("--quick", action="store_true", help=quick_help)
    hint = f" (default {default_out} for a full run)" if default_out is not None else ""
    p.add_argument("--out", type=Path, default=None,
                   help=f"also write the markdown table to this file{hint}")
    args = p.parse_args(argv)
    text = measured_markdown(lambda: metrics(args.quick), quick=args.quick)
    print(text)
    write_table(text, args.out if args.out is not None else (None if args.quick else default_out))
    return 0


def measured_markdown(run: Callable[[], list[Metric]], *, quick: bool,
                      how: str = "ratios are paired, best of the rounds") -> str:
    """Run ``run()`` and render its figures with the machine, versions, date and the load
    average at start and end (a single-suite script's table)."""
    start = machine_info()
    figures = run()
    load_end = os.getloadavg() if hasattr(os, "getloadavg") else None
    text = render_markdown({
        "metrics": figures, "quick": quick, "machine": start, "versions": library_versions(),
        "date": time.strftime("%Y-%m-%dT%H:%M:%SZ", time.gmtime())})
    return text + (f"\nLoad average at start {start.get('loadavg_at_start')}, at end "
                   f"{[round(v, 2) for v in load_end] if load_end else None} "
                   f"(the machine is shared; {how}).\n")


def write_table(text: str, target: Path | None) -> None:
    """Write a markdown table to ``target`` (nothing when None)."""
    if target is not None:
        target.parent.mkdir(parents=True, exist_ok=True)
        target.write_text(text if text.endswith("\n") else text + "\n")


def render_markdown(doc: dict[str, Any]) -> str:
    """The result as markdown: a header line (machine, versions, date) and one table per kind."""
    m = doc.get("machine", {})
    v = doc.get("versions", {})
    libs = ", ".join(f"{k} {val}" for k, val in v.items() if val)
    lines: list[str] = []
    if m:
        lines += [f"Measured {doc.get('date', '?')} on {m.get('cpu', '?')} "
                  f"({m.get('cores', '?')} cores, {m.get('memory_gib', '?')} GiB, load average "
                  f"{_fmt((m.get('loadavg_at_start') or [None])[0])} at start), Python "
                  f"{m.get('python', '?')}; {libs}."
                  + (" Quick mode (smaller problems)." if doc.get("quick") else ""), ""]
    elif doc.get("quick"):
        lines += ["Quick mode (smaller problems).", ""]
    speed = [x for x in doc.get("metrics", []) if x["kind"] == "speed"]
    acc = [x for x in doc.get("metrics", []) if x["kind"] == "accuracy"]
    if speed:
        lines += ["| speed | fogts (s) | peer (s) | ratio | CPU-time ratio |",
                  "|---|---:|---:|---:|---:|"]
        for x in speed:
            secs = x.get("seconds", {})
            peer = next((k for k in secs if k != "fogts"), "peer")
            cpu = x.get("cpu_value")
            cpu_cell = "-" if cpu is None else f"{_fmt(cpu)}x"
            title = x["title"] + (" (parallel)" if x.get("parallel") else "")
            lines.append(f"| {_md_escape(title)} | {_fmt(secs.get('fogts'))} | "
                         f"{_fmt(secs.get(peer))} ({_md_escape(peer)}) | "
                         f"**{_fmt(x['value'])}x** | {cpu_cell} |")
        lines.append("")
    if acc:
        lines += ["| accuracy | value | better |", "|---|---:|---|"]
        for x in acc:
            unit = f" {x['unit']}" if x.get("unit") else ""
            lines.append(f"| {_md_escape(x['title'])} | {_fmt(x['value'])}{_md_escape(unit)} "
                         f"| {x['better']} |")
        lines.append("")
    bad = {k: s for k, s in doc.get("suites", {}).items() if s["status"] != "ok"}
    for name, s in bad.items():
        first = s["error"].splitlines()[0] if s.get("error") else ""
        lines.append(f"- suite `{name}`: {s['status']} {_md_escape(first)}")
    return "\n".join(lines).rstrip() + "\n"


def report_bad(rows: list[dict[str, Any]], log: Callable[[str], None]) -> int:
    """Log one line per regressed or missing figure; return how many there are."""
    bad = [r for r in rows if r["verdict"] in ("REGRESSION", "MISSING")]
    for r in bad:
        if r["verdict"] == "MISSING":
            log(f"MISSING {r['id']} ({r['title']}): measured before, not now")
        else:
            log(f"REGRESSION {r['id']} ({r['title']}): {r['basis']} {_fmt(r['old'])} -> "
                f"{_fmt(r['new'])}, worse by {100 * r['change']:.1f} % (tolerance "
                f"{100 * r.get('tolerance', DEFAULT_TOLERANCE):.0f} %)")
    if bad:
        log(f"{len(bad)} figure(s) got worse by more than their tolerance or went missing")
    return len(bad)


def render_comparison(rows: list[dict[str, Any]]) -> str:
    lines = ["| figure | compared | old | new | worse by | verdict |",
             "|---|---|---:|---:|---:|---|"]
    for r in rows:
        change = "-" if r["change"] is None else f"{100 * r['change']:+.1f} %"
        lines.append(f"| {_md_escape(r['title'])} | {r.get('basis', '')} | {_fmt(r['old'])} | "
                     f"{_fmt(r['new'])} | {change} | {r['verdict']} |")
    return "\n".join(lines) + "\n"


def _write_atomic(path: Path, text: str) -> None:
    path.parent.mkdir(parents=True, exist_ok=True)
    fd, tmp = tempfile.mkstemp(prefix=f".{path.name}.", suffix=".tmp", dir=path.parent)
    with os.fdopen(fd, "w", encoding="utf-8") as fh:
        fh.write(text)
    umask = os.umask(0)
    os.umask(umask)
    os.chmod(tmp, 0o666 & ~umask)  # mkstemp makes 0600; a result file is for everyone
    os.replace(tmp, path)


# --------------------------------------------------------------------------- CLI


def _parser() -> argparse.ArgumentParser:
    p = argparse.ArgumentParser(prog="python -m benchmarks", description=__doc__.split("\n")[0])
    p.add_argument("--quick", action="store_true", help="small problems (a CI smoke run)")
    p.add_argument("--out", type=Path, help="write the JSON result here")
    p.add_argument("--md", type=Path, help="write the markdown table here")
    p.add_argument("--compare", type=Path, metavar="OLD_JSON",
                   help="flag figures worse than OLD_JSON's by more than their tolerance; "
                        "exit 1 if any")
    p.add_argument("--confirm", type=int, default=2,
                   help="re-measure a suite with a flagged speed figure up to N times")
    p.add_argument("--only", help="comma-separated suite names (default: all): "
                   + ", ".join(s.name for s in SUITES))
    p.add_argument("--update", type=Path, metavar="JSON",
                   help="start from this result and replace only the suites run now (with "
                        "--only: re-measure one suite of a full result)")
    p.add_argument("--against", type=Path, metavar="NEW_JSON",
                   help="with --compare: compare this stored result instead of running")
    p.add_argument("--render", type=Path, metavar="JSON",
                   help="do not run anything: render JSON as markdown (to --md or stdout)")
    p.add_argument("--timeout", type=float, default=None,
                   help="seconds allowed per suite (default: none; 600 with --quick)")
    p.add_argument("--jobs", type=int, default=1,
                   help="run N suites at once (faster smoke runs; noisier ratios)")
    p.add_argument("--list", action="store_true", help="list the suites and exit")
    p.add_argument("--child", help=argparse.SUPPRESS)
    p.add_argument("--child-out", help=argparse.SUPPRESS)
    return p


def main(argv: list[str] | None = None) -> int:
    """Entry point; returns the exit code (0 ok, 1 regression or failed suite, 2 usage)."""
    args = _parser().parse_args(argv)
    if args.child:
        return _child_main(args.child, args.quick, args.child_out)

    def log(msg: str) -> None:
        print(msg, file=sys.stderr, flush=True)

    if args.list:
        for s in SUITES:
            state = "" if s.module_path().exists() else "  (module missing)"
            print(f"{s.name:<18} {s.description}{state}")
        return 0
    if args.render:
        text = render_markdown(json.loads(args.render.read_text()))
        if args.md:
            _write_atomic(args.md, text)
        else:
            sys.stdout.write(text)
        return 0

    suites = list(SUITES)
    if args.only:
        names = [n.strip() for n in args.only.split(",") if n.strip()]
        unknown = [n for n in names if n not in {s.name for s in SUITES}]
        if unknown:
            log(f"error: unknown suite(s) {', '.join(unknown)}; suites are: "
                f"{', '.join(s.name for s in SUITES)}")
            return 2
        suites = [s for s in SUITES if s.name in names]
    old = json.loads(args.compare.read_text()) if args.compare else None
    timeout = args.timeout if args.timeout is not None else (600.0 if args.quick else None)

    if args.against is not None:
        if old is None:
            log("error: --against needs --compare OLD_JSON")
            return 2
        rows = compare(json.loads(args.against.read_text()), old)
        print(render_comparison(rows))
        return 1 if report_bad(rows, log) else 0

    doc = run_suites(suites, quick=args.quick, timeout_s=timeout, log=log,
                     jobs=max(1, args.jobs))
    if args.update is not None:
        doc = merge_results(json.loads(args.update.read_text()), doc)
    rows = []
    if old is not None:
        rows = compare(doc, old)
        for attempt in range(max(0, args.confirm)):
            flagged = {r["id"] for r in rows if r["verdict"] == "REGRESSION"}
            again = sorted({m["suite"] for m in doc["metrics"]
                            if m["id"] in flagged and m["kind"] == "speed"})
            if not again:
                break
            log(f"== re-measuring {', '.join(again)} (speed regression flagged; attempt "
                f"{attempt + 1} of {args.confirm})")
            for name in again:
                suite = next(s for s in SUITES if s.name == name)
                status, metrics = _run_child(suite, args.quick, timeout)
                if status["status"] == "ok":
                    merge_best(doc, metrics, old)
            rows = compare(doc, old)

    text = render_markdown(doc)
    print(text)
    if args.out:
        _write_atomic(args.out, json.dumps(doc, indent=2, allow_nan=True) + "\n")
    if args.md:
        _write_atomic(args.md, text)
    failed = [n for n, s in doc["suites"].items() if s["status"] == "failed"]
    code = 0
    if failed:
        log(f"FAILED suite(s): {', '.join(failed)}")
        code = 1
    if old is not None:
        print(render_comparison(rows))
        if report_bad(rows, log):
            code = 1
        else:
            log(f"no regression against {args.compare}")
    return code


if __name__ == "__main__":
    raise SystemExit(main())
