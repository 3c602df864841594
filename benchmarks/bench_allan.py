"""Allan-family speed and memory against allantools, measured in the same run.

Figures (ratio = allantools seconds / fogts seconds, > 1 means fogts is faster):

* ``fogts.allan.oadev`` against ``allantools.oadev(y, rate=fs, data_type="freq", taus=...)``
  on 10^7 white+random-walk rate samples and 100 log-spaced taus (same taus for both),
  with the default thread pool and with one thread; the largest relative difference of
  the deviations (must be <= 1e-9);
* ``fogts.allan_deviation`` (oadev) on the same data and taus, with its default confidence
  intervals (noise identification, EDF, chi-squared) and without (``confidence=None``),
  each with the default thread pool and with one thread, against the same
  ``allantools.oadev``; and the share of the time the intervals add (one thread, CPU time);
* the time of one read of the input array (``numpy.sum``) in the same rounds, and each
  estimator's time per tau (one thread) as a multiple of it: oadev and ohdev on the 10^7
  samples and 100 taus, every kind on the octave taus below (the memory-bound limit of a
  pass over the data);
* peak extra memory of each call (tracemalloc, numpy allocations included) as a multiple of
  the input array;
* every estimator (adev, oadev, mdev, hdev, ohdev, totdev) on 10^6 samples, octave taus,
  one thread (allantools has one);
* in a full run (or with ``--huge``): the end-to-end time on a 10^8-sample ``.npy``
  (about 800 MB) of ``read_run`` + ``allan_deviation`` (with confidence intervals), and of
  the whole ``fogts allan`` command, against ``numpy.load`` + ``allantools.oadev`` on the
  same octave taus; each side runs once in a fresh interpreter, timed by its wall and its
  own CPU time (:func:`benchmarks.timing.run_child`), and the command's peak resident
  memory is given as a multiple of the 800 MB input; and the whole ``fogts report
  --decimate 100`` on the same file (wall time and peak memory, no peer: no other tool
  writes such a report).

The machine is shared, so the contenders are timed in rotating rounds and the best wall and
CPU time of each is kept (:func:`benchmarks.timing.measure`); the load average is printed
with the table.  The default-thread oadev is a ``parallel`` figure (see
:mod:`benchmarks.compare`); its single-threaded sibling is the 1-thread oadev.

Run: ``python -m benchmarks.bench_allan [--quick | --huge]``; the table is written to
``benchmarks/results/allan.md``.
"""

from __future__ import annotations

import argparse
import functools
import gc
import importlib.util
import os
import shutil
import sys
import tempfile
import tracemalloc
from collections.abc import Callable
from pathlib import Path
from typing import Any

import numpy as np

from benchmarks.metric import Metric, accuracy_metric, speed_metric
from benchmarks.render import measured_markdown, write_table
from benchmarks.timing import ChildRun, Timing, measure, run_child, speed_from

RESULTS = Path(__file__).resolve().parent / "results" / "allan.md"
FS_HZ = 100.0
N_FULL, N_QUICK, N_HUGE = 10_000_000, 1_000_000, 100_000_000
N_TAUS_FULL, N_TAUS_QUICK = 100, 30


def gyro_rate(n: int, seed: int = 0) -> np.ndarray:
    """White rate noise plus a small rate random walk and a bias (float64)."""
    rng = np.random.default_rng(seed)
    y = rng.normal(0.0, 0.1, n)
    y += np.cumsum(rng.normal(0.0, 1e-4, n))
    y += 12.0
    return y


def log_taus(n: int, count: int, fs_hz: float) -> np.ndarray:
    """``count`` distinct log-spaced taus (whole samples) up to oadev's largest m."""
    from fogts.allan.taus import max_m

    top = max_m("oadev", n)
    k = count
    while True:
        m = np.unique(np.rint(np.geomspace(1, top, k)).astype(np.int64))
        if m.size >= count or k > 50 * count:
            break
        k += 1
    return m[-count:] / fs_hz if m.size > count else m / fs_hz


def peak_extra_bytes(fn: Callable[[], Any]) -> int:
    """Peak memory allocated during ``fn()`` (tracemalloc sees numpy's allocations)."""
    gc.collect()
    tracemalloc.start()
    try:
        out = fn()
        _, peak = tracemalloc.get_traced_memory()
    finally:
        tracemalloc.stop()
    del out
    return int(peak)


def per_tau_metric(timing: Timing, name: str, read: str, taus: int, id: str, title: str
                   ) -> Metric:
    """``name``'s time per tau as a multiple of the time of ``read`` (one pass over the
    input), from best CPU times (single-threaded; the wall-time multiple is in details)."""
    cpu = timing.cpu[name] / taus / timing.cpu[read]
    wall = timing.wall[name] / taus / timing.wall[read]
    return accuracy_metric(id, title, value=cpu, better="lower", unit="x one array read",
                           tolerance=0.25, details={
                               "wall_multiple": wall, "taus": taus,
                               "seconds": timing.wall[name], "cpu_seconds": timing.cpu[name],
                               "read_seconds": timing.wall[read],
                               "read_cpu_seconds": timing.cpu[read]})


def _oadev_metrics(quick: bool) -> list[Metric]:
    import allantools

    from fogts.allan import allan_deviation
    from fogts.allan.estimators import oadev, ohdev

    n = N_QUICK if quick else N_FULL
    count = N_TAUS_QUICK if quick else N_TAUS_FULL
    y = gyro_rate(n)
    taus = log_taus(n, count, FS_HZ)
    m = np.rint(taus * FS_HZ).astype(np.int64)
    m_h = m[m <= (n - 1) // 3]
    tag = f"n=1e{round(np.log10(n))}"

    ours = oadev(y, fs_hz=FS_HZ, m=m)
    ref = allantools.oadev(y, rate=FS_HZ, data_type="freq", taus=taus)
    assert np.array_equal(np.rint(ref[0] * FS_HZ).astype(np.int64), m), "tau sets differ"
    assert np.array_equal(ref[3].astype(np.int64), ours.n), "term counts differ"
    rel = float(np.max(np.abs(ours.dev / ref[1] - 1.0)))

    def peer_call() -> Any:
        return allantools.oadev(y, rate=FS_HZ, data_type="freq", taus=taus)

    def api(confidence: float | None, workers: int | None) -> Callable[[], Any]:
        return lambda: allan_deviation(y, fs_hz=FS_HZ, taus=taus, confidence=confidence,
                                       workers=workers)

    timing = measure({"fogts": lambda: oadev(y, fs_hz=FS_HZ, m=m),
                      "fogts 1 thread": lambda: oadev(y, fs_hz=FS_HZ, m=m, workers=1),
                      "ohdev 1 thread": lambda: ohdev(y, fs_hz=FS_HZ, m=m_h, workers=1),
                      "api ci": api(0.683, None), "api ci 1 thread": api(0.683, 1),
                      "api": api(None, None), "api 1 thread": api(None, 1),
                      "read": lambda: np.sum(y),
                      "peer": peer_call}, repeat=3, min_total_s=3.0 if quick else 0.0)
    mem_ours = peak_extra_bytes(lambda: oadev(y, fs_hz=FS_HZ, m=m))
    mem_one = peak_extra_bytes(lambda: oadev(y, fs_hz=FS_HZ, m=m, workers=1))
    mem_at = peak_extra_bytes(peer_call)
    threads = os.cpu_count() or 1
    size = f"{n:.0e}".replace("+0", "").replace("+", "")
    speed, acc = speed_from, accuracy_metric
    title = f"oadev, {size} samples, {m.size} taus"
    api_title = f"allan_deviation (oadev), {size} samples, {m.size} taus"
    ci_share = timing.cpu["api ci 1 thread"] / timing.cpu["api 1 thread"] - 1.0
    return [
        speed(timing, f"speed.oadev.{tag}", f"{title}, {threads} threads", peer="allantools",
              parallel=threads > 1, details={"taus": int(m.size), "threads": threads}),
        speed(timing, f"speed.oadev.1thread.{tag}", f"{title}, 1 thread", peer="allantools",
              ours="fogts 1 thread", details={"taus": int(m.size), "threads": 1}),
        speed(timing, f"speed.allan_deviation_ci.{tag}", f"{api_title}, with CIs, {threads} "
              "threads", peer="allantools", ours="api ci", parallel=threads > 1),
        speed(timing, f"speed.allan_deviation_ci.1thread.{tag}", f"{api_title}, with CIs, "
              "1 thread", peer="allantools", ours="api ci 1 thread"),
        speed(timing, f"speed.allan_deviation_no_ci.{tag}", f"{api_title}, no CIs, {threads} "
              "threads", peer="allantools", ours="api", parallel=threads > 1),
        speed(timing, f"speed.allan_deviation_no_ci.1thread.{tag}", f"{api_title}, no CIs, "
              "1 thread", peer="allantools", ours="api 1 thread"),
        acc(f"share.allan_deviation_ci.{tag}", f"{api_title}: CPU time the CIs add (noise id, "
            "EDF, chi-squared), 1 thread", value=ci_share, better="lower", unit="of no-CI time",
            abs_tolerance=0.05, details={"wall_share": timing.wall["api ci 1 thread"]
                                         / timing.wall["api 1 thread"] - 1.0}),
        per_tau_metric(timing, "fogts 1 thread", "read", int(m.size),
                       f"per_tau.oadev.{tag}", f"oadev time per tau / one read of the "
                       f"{size} samples, 1 thread"),
        per_tau_metric(timing, "ohdev 1 thread", "read", int(m_h.size),
                       f"per_tau.ohdev.{tag}", f"ohdev time per tau / one read of the "
                       f"{size} samples, 1 thread"),
        acc(f"accuracy.oadev_vs_allantools.{tag}", f"{title}: largest relative difference "
            "to allantools", value=rel, better="lower", abs_tolerance=1e-9),
        acc(f"memory.oadev.{tag}", f"oadev peak extra memory, {threads} threads",
            value=mem_ours / y.nbytes, better="lower", unit="x input",
            details={"bytes": mem_ours}),
        acc(f"memory.oadev.1thread.{tag}", "oadev peak extra memory, 1 thread",
            value=mem_one / y.nbytes, better="lower", unit="x input", details={"bytes": mem_one}),
        acc(f"memory.allantools_oadev.{tag}", "allantools.oadev peak extra memory",
            value=mem_at / y.nbytes, better="lower", unit="x input", details={"bytes": mem_at}),
    ]


def _all_kinds_metrics(quick: bool) -> list[Metric]:
    import allantools

    from fogts.allan.estimators import ESTIMATORS
    from fogts.allan.taus import tau_grid

    n = N_QUICK // 10 if quick else N_QUICK
    y = gyro_rate(n, seed=1)
    out: list[Metric] = []
    for kind, fn in ESTIMATORS.items():
        grid = tau_grid("octave", fs_hz=FS_HZ, n_samples=n, kind=kind)
        peer = getattr(allantools, kind)
        res = fn(y, fs_hz=FS_HZ, m=grid.m)
        ref = peer(y, rate=FS_HZ, data_type="freq", taus=grid.tau_s)
        rel = float(np.max(np.abs(res.dev / ref[1] - 1.0)))
        # one thread, like allantools (the thread pool is measured by speed.oadev.n=1e7)
        timing = measure(
            {"fogts": functools.partial(fn, y, fs_hz=FS_HZ, m=grid.m, workers=1),
             "read": functools.partial(np.sum, y),
             "peer": functools.partial(peer, y, rate=FS_HZ, data_type="freq",
                                       taus=grid.tau_s)},
            repeat=5, min_total_s=0.5 if quick else 2.0)
        out.append(speed_from(
            timing, f"speed.{kind}.octave.n={n}", f"{kind}, {n:,} samples, {grid.m.size} "
            f"octave taus, 1 thread (max rel. diff {rel:.1e})", peer="allantools",
            details={"max_rel_diff": rel}))
        out.append(per_tau_metric(timing, "fogts", "read", int(grid.m.size),
                                  f"per_tau.{kind}.octave.n={n}", f"{kind} time per tau / "
                                  f"one read of the {n:,} samples, 1 thread"))
    return out


def _write_npy(path: Path, n: int, seed: int = 7) -> None:
    """Write an ``n``-sample rate ``.npy`` in blocks (never two copies in memory)."""
    arr = np.lib.format.open_memmap(path, mode="w+", dtype=np.float64, shape=(n,))
    rng = np.random.default_rng(seed)
    block = 10_000_000
    level = 0.0
    for s in range(0, n, block):
        e = min(s + block, n)
        walk = np.cumsum(rng.normal(0.0, 1e-4, e - s)) + level
        level = float(walk[-1])
        arr[s:e] = rng.normal(0.0, 0.1, e - s) + walk + 12.0
    arr.flush()
    del arr


def _has_allan_command() -> bool:
    from fogts.cli import app

    return any((c.name or getattr(c.callback, "__name__", "")) in ("allan", "allan_cmd")
               for c in app.registered_commands)


def _huge_metrics() -> list[Metric]:
    """End to end on a 1e8-sample .npy, each side in a fresh interpreter: wall and CPU
    time (the child's own), and the peak memory of the `fogts allan` command as a multiple
    of the input (the goal: at most 3x)."""
    from fogts.allan.taus import tau_grid

    folder = Path(tempfile.mkdtemp(prefix="fogts-bench-allan-"))
    root = str(Path(__file__).resolve().parents[1])
    env = {**os.environ, "PYTHONPATH": os.pathsep.join(
        [root, *filter(None, [os.environ.get("PYTHONPATH")])])}
    out: list[Metric] = []
    try:
        path = folder / "rate_1e8.npy"
        _write_npy(path, N_HUGE)
        taus = tau_grid("octave", fs_hz=FS_HZ, n_samples=N_HUGE, kind="oadev").tau_s
        peer_code = ("import sys, numpy as np, allantools; y = np.load(sys.argv[1]); "
                     f"allantools.oadev(y, rate={FS_HZ}, data_type='freq', "
                     f"taus=np.array({taus.tolist()!r}))")
        peer = _checked_child([sys.executable, "-c", peer_code, str(path)], env, root)
        api_code = ("import sys; from fogts.io.reader import read_run; "
                    "from fogts.allan import allan_deviation; "
                    f"r = read_run(sys.argv[1], fs_hz={FS_HZ}); "
                    "res = allan_deviation(r, kind='oadev', taus='octave')")
        api = _checked_child([sys.executable, "-c", api_code, str(path)], env, root)
        label = "np.load+allantools.oadev"
        out.append(speed_metric(
            "speed.allan_deviation_end_to_end.n=1e8", f"1e8-sample .npy (800 MB), "
            f"{taus.size} octave taus: read_run + allan_deviation (oadev with noise id, EDF "
            "and CIs)", fogts_s=api.wall_s, peer_s=peer.wall_s, peer=label,
            fogts_cpu_s=api.cpu_s, peer_cpu_s=peer.cpu_s, parallel=True))
        if _has_allan_command():
            cmd = [sys.executable, "-m", "fogts", "allan", str(path), "--fs", str(FS_HZ),
                   "--units", "deg/h", "--json", str(folder / "out.json")]
            cli = _checked_child(cmd, env, root)
            out.append(speed_metric(
                "speed.allan_cli_end_to_end.n=1e8", "1e8-sample .npy: the whole `fogts allan` "
                "command (read, oadev, CIs, noise fit, JSON)", fogts_s=cli.wall_s,
                peer_s=peer.wall_s, peer=label, fogts_cpu_s=cli.cpu_s, peer_cpu_s=peer.cpu_s,
                parallel=True))
            out.append(accuracy_metric(
                "memory.allan_cli_end_to_end.n=1e8", "1e8-sample .npy: peak RSS of the whole "
                "`fogts allan` command", value=cli.max_rss_bytes / (8 * N_HUGE),
                better="lower", unit="x input", tolerance=0.25,
                details={"max_rss_bytes": cli.max_rss_bytes}))
        out += _report_metrics(path, folder, env, root)
    finally:
        shutil.rmtree(folder, ignore_errors=True)
    return out


def _report_metrics(path: Path, folder: Path, env: dict[str, str], root: str) -> list[Metric]:
    """`fogts report --decimate 100` on the 1e8-sample file, in a fresh interpreter: wall
    time (CPU in the details) and peak memory as a multiple of the input (goals: 30 s, 3x)."""
    cmd = [sys.executable, "-m", "fogts", "report", str(path), "--fs", str(FS_HZ),
           "--units", "deg/h", "--decimate", "100", "-o", str(folder / "report.html"), "-q"]
    run = _checked_child(cmd, env, root)
    return [
        accuracy_metric(
            "time.report_cli_end_to_end.n=1e8", "1e8-sample .npy: the whole `fogts report "
            "--decimate 100` (Allan chain on all samples, the ARMA selection on the 1e6 block "
            "means, dynamic Allan deviation, figures, HTML): wall time (no peer)",
            value=run.wall_s, better="lower", unit="s", tolerance=0.5,
            details={"cpu_s": run.cpu_s}),
        accuracy_metric(
            "memory.report_cli_end_to_end.n=1e8", "1e8-sample .npy: peak RSS of the whole "
            "`fogts report --decimate 100`", value=run.max_rss_bytes / (8 * N_HUGE),
            better="lower", unit="x input", tolerance=0.25,
            details={"max_rss_bytes": run.max_rss_bytes}),
    ]


def _checked_child(cmd: list[str], env: dict[str, str], cwd: str) -> ChildRun:
    run = run_child(cmd, env=env, cwd=cwd)
    if run.exit_code != 0:
        raise RuntimeError(f"{' '.join(cmd[:4])} ... exited with {run.exit_code}")
    return run


def metrics(quick: bool, huge: bool | None = None) -> list[Metric]:
    """Measure and return the figures (the runner's entry point); the 1e8-sample end to end
    is part of every full run unless ``huge=False``."""
    out = _oadev_metrics(quick)
    out += _all_kinds_metrics(quick)
    if (not quick) if huge is None else huge:
        out += _huge_metrics()
    return out


def main(argv: list[str] | None = None) -> int:
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--quick", action="store_true", help="1e6 samples and 30 taus")
    p.add_argument("--huge", action="store_true", default=None,
                   help="also time the end-to-end analysis of a 1e8-sample .npy (~800 MB) "
                        "with --quick (a full run always does)")
    p.add_argument("--out", type=Path, default=None,
                   help=f"write the markdown table here (default {RESULTS} for a full run)")
    args = p.parse_args(argv)
    if importlib.util.find_spec("allantools") is None:
        print("error: allantools is not installed", file=sys.stderr)
        return 2
    text = measured_markdown(lambda: metrics(args.quick, huge=args.huge),
                                    quick=args.quick)
    print(text)
    write_table(text, args.out if args.out is not None
                       else (None if args.quick else RESULTS))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
