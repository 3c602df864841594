"""What a result was measured with: the machine, the library versions and the commit."""

from __future__ import annotations

import os
import platform
import subprocess
from importlib import metadata
from pathlib import Path
from typing import Any

#: The checkout being measured (the folder that holds ``fogts/`` and ``benchmarks/``).
ROOT = Path(__file__).resolve().parents[1]

#: BLAS threads of the suites, unless the environment sets them: one, so a single-threaded
#: figure is single-threaded on both sides (its CPU time is then its work) and an idle BLAS
#: pool cannot spin on a loaded 2-core machine.  (Not OMP_NUM_THREADS: pyarrow sizes its
#: own thread pool from it, and its readers are measured multi-threaded.)
BLAS_ENV = {"OPENBLAS_NUM_THREADS": "1", "MKL_NUM_THREADS": "1"}

#: fogts and every library a suite measures against.
LIBRARIES = ("fogts", "numpy", "scipy", "pandas", "statsmodels", "allantools", "pyarrow",
             "matplotlib", "dask", "distributed")


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


def load_average() -> list[float] | None:
    """The 1, 5 and 15 minute load averages, rounded (None where the OS has none)."""
    load = os.getloadavg() if hasattr(os, "getloadavg") else None
    return [round(v, 2) for v in load] if load else None


def machine_info() -> dict[str, Any]:
    """CPU, cores, memory, OS, Python, BLAS threads and the load average at the start."""
    return {"cpu": _cpu_model(), "cores": os.cpu_count(), "memory_gib": _memory_gib(),
            "platform": platform.platform(), "python": platform.python_version(),
            "blas_threads": {k: os.environ.get(k, v) for k, v in BLAS_ENV.items()},
            "loadavg_at_start": load_average()}


def library_versions() -> dict[str, str | None]:
    """Versions of fogts and of every library a suite measures against."""
    out: dict[str, str | None] = {}
    for dist in LIBRARIES:
        try:
            out[dist] = metadata.version(dist)
        except metadata.PackageNotFoundError:
            out[dist] = None
    return out


def git_commit() -> str | None:
    """The checked-out commit, with ``+dirty`` if ``fogts/`` or ``benchmarks/`` has changes."""
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
