"""`fogts select` end to end on a long white + rate-random-walk ``.npy`` (part of the ARMA
suite, :mod:`benchmarks.bench_arma`).

The whole command - read, prepare (mean, ADF/KPSS), ACF/PACF, the five exact-ML fits, the
residual checks, the prediction summary and the JSON - runs once in a fresh interpreter.
Its wall time, its CPU time (user + system, from ``os.wait4``: the child's own) and its
peak resident memory (the child's ``ru_maxrss``) are reported; the memory as a multiple of
the input file's float64 data (issue 14's goal: at most 3x).  There is no peer: no other
tool selects an exact-ML ARMA model on 800 MB in one command.
"""

from __future__ import annotations

import os
import shutil
import sys
import tempfile
from pathlib import Path

import numpy as np

from benchmarks.metric import Metric, accuracy_metric
from benchmarks.timing import run_child

__all__ = ["cli_metrics", "run_select"]


def run_select(path: Path, out: Path) -> tuple[float, float, int, int]:
    """Run ``python -m fogts select PATH --fs 100 --json OUT -q`` in a fresh interpreter
    (this checkout first on its path): wall seconds, CPU seconds, peak RSS in bytes and
    the exit code."""
    root = str(Path(__file__).resolve().parents[1])
    env = {**os.environ, "PYTHONPATH": os.pathsep.join(
        [root, *filter(None, [os.environ.get("PYTHONPATH")])])}
    cmd = [sys.executable, "-m", "fogts", "select", str(path), "--fs", "100",
           "--json", str(out), "-q"]
    run = run_child(cmd, env=env, cwd=root)
    return run.wall_s, run.cpu_s, run.max_rss_bytes, run.exit_code


def cli_metrics(n: int, make: object, label: str) -> list[Metric]:
    """`fogts select` on ``make(n)`` (a float64 series) saved as ``.npy``: time and peak
    memory (see the module docstring)."""
    folder = Path(tempfile.mkdtemp(prefix="fogts-bench-select-"))
    try:
        path = folder / "rate.npy"
        np.save(path, make(n))  # type: ignore[operator]
        wall, cpu, rss, code = run_select(path, folder / "out.json")
    finally:
        shutil.rmtree(folder, ignore_errors=True)
    nbytes = 8 * n
    return [
        accuracy_metric(
            f"time.arma.select_cli_white_rw.{label}",
            f"`fogts select` white + rate random walk {label} (.npy, {nbytes / 1e6:.0f} MB): "
            "wall time (no peer)", value=wall, better="lower", unit="s", tolerance=0.5,
            details={"cpu_s": cpu, "exit_code": code}),
        accuracy_metric(
            f"memory.arma.select_cli_white_rw.{label}",
            f"`fogts select` white + rate random walk {label}: peak RSS",
            value=rss / nbytes, better="lower", unit="x input", tolerance=0.25,
            details={"max_rss_bytes": rss}),
    ]
