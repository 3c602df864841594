"""Timing fogts against its peer in the same run, on a shared and noisy machine.

* Each contender is timed in rotating rounds and its best wall and CPU time kept
  (:func:`measure`); fast calls get more rounds (``min_total_s``).  Noise only adds time,
  so the minimum over the rounds discards most of what other processes took.
* CPU time is the process time of the call (all threads of this process).  For a
  single-threaded call it does not grow while the process waits for a core, so a ratio of
  CPU times hardly moves with machine load; the comparison against a baseline relies on it
  (:mod:`benchmarks.compare`).
* :class:`LoadProbe` records how many cores *other* processes kept busy while a figure was
  timed, which decides whether a parallel figure's wall-time ratio can be judged.
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
import time
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

from benchmarks.metric import DEFAULT_TOLERANCE, Metric, speed_metric


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
        """Average number of cores other processes kept busy since the probe was made."""
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
        """Number of rounds every contender was timed in."""
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
            fns[name]()  # the result is dropped at once: no two results alive together
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


@dataclass(frozen=True)
class ChildRun:
    """One command run in a child process: its wall time, its own CPU time (user +
    system, from ``os.wait4``), its peak resident memory (``ru_maxrss``) and exit code."""

    wall_s: float
    cpu_s: float
    max_rss_bytes: int
    exit_code: int


#: Runs ``argv[1:]`` as its own child, output discarded, and prints that child's wall time,
#: CPU time, ``ru_maxrss`` (KiB) and exit code as JSON (see :func:`run_child`).
_LAUNCHER = """
import json, os, sys, time
t0 = time.perf_counter()
pid = os.fork()
if pid == 0:
    null = os.open(os.devnull, os.O_WRONLY)
    os.dup2(null, 1)
    os.dup2(null, 2)
    os.execvp(sys.argv[1], sys.argv[1:])
_, status, u = os.wait4(pid, 0)
print(json.dumps([time.perf_counter() - t0, u.ru_utime + u.ru_stime, u.ru_maxrss,
                  os.waitstatus_to_exitcode(status)]))
"""


def run_child(cmd: list[str], *, env: dict[str, str] | None = None,
              cwd: str | None = None) -> ChildRun:
    """Run ``cmd`` once (its output discarded) and measure it (:class:`ChildRun`).

    The command is started by a small launcher interpreter rather than by this process:
    Linux keeps a forked child's peak resident set (``ru_maxrss``) across ``execve``, so a
    child of this process would report at least this process's own peak (2.4 GB for a
    ``python -c pass`` started from a suite holding a 2.4 GB array), while the launcher's
    child starts from the launcher's few tens of MB.
    """
    out = subprocess.run([sys.executable, "-c", _LAUNCHER, *cmd], env=env, cwd=cwd,
                         capture_output=True, text=True, check=True)
    wall, cpu, maxrss_kib, code = json.loads(out.stdout)
    return ChildRun(float(wall), float(cpu), int(maxrss_kib) * 1024, int(code))


def speed_from(timing: Timing, id: str, title: str, *, peer: str, peer_key: str = "peer",
               ours: str = "fogts", parallel: bool = False, suite: str = "",
               tolerance: float = DEFAULT_TOLERANCE,
               details: dict[str, Any] | None = None) -> Metric:
    """A :func:`~benchmarks.metric.speed_metric` from a :class:`Timing` (``ours`` against
    ``peer_key``)."""
    return speed_metric(id, title, fogts_s=timing.wall[ours], peer_s=timing.wall[peer_key],
                        peer=peer, fogts_cpu_s=timing.cpu[ours],
                        peer_cpu_s=timing.cpu[peer_key], parallel=parallel,
                        other_load=timing.other_load, noise=timing.noise(ours, peer_key),
                        suite=suite, tolerance=tolerance, details=details)
