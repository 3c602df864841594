"""Round-trip accuracy of the noise-term fit: simulate with known coefficients, fit, compare.

For three sensor grades (navigation FOG, tactical FOG, MEMS), ``fogts.simulate_gyro``
makes 3 h records at 100 Hz with known N, B and K (30 seeds each); ``allan_deviation``
(overlapping, octave taus, 68.3 % intervals) and ``fit_noise`` (the default five-term,
EDF-weighted fit) estimate them back.  Reported per grade and term:

* the median absolute relative error of the weighted fit (WLS), and its median signed
  error (bias);
* how often the fit's 68.3 % interval covers the truth (ideal: 68 %);
* the same median error for the unweighted fit (OLS, the traditional least squares on
  sigma^2) and for the IEEE 952 / MATLAB slope read-off (the graphical method).

The grades are chosen so that each of N, B and K dominates the Allan curve over part of
a 3 h record (a term that dominates nowhere cannot be identified by any fit).  The same
study at 5 Hz is the CI test ``tests/test_simulate.py::test_round_trip_*``.

Run: ``python -m benchmarks.accuracy.roundtrip [--quick] [--seeds 30] [--fs 100]``; the
markdown table goes to ``benchmarks/results/accuracy.md`` (``--out`` to change).
"""

from __future__ import annotations

import argparse
import os
import time
import warnings
from collections.abc import Callable
from concurrent.futures import ProcessPoolExecutor
from pathlib import Path
from typing import Any

import numpy as np

from benchmarks.metric import Metric, accuracy_metric

#: Sensor grades (deg/sqrt(h), deg/h, deg/h^1.5): N -> B crossover near 20-40 s and
#: B -> K near 100-120 s.
GRADES: dict[str, dict[str, float]] = {
    "navigation FOG": {"N": 0.0005, "B": 0.008, "K": 0.05},
    "tactical FOG": {"N": 0.01, "B": 0.15, "K": 1.0},
    "MEMS": {"N": 0.2, "B": 4.0, "K": 25.0},
}
TERMS = ("N", "B", "K")
UNITS = {"N": "deg/sqrt(h)", "B": "deg/h", "K": "deg/h^1.5"}
FIRST_SEED = 1000
RESULTS = Path(__file__).resolve().parents[1] / "results" / "accuracy.md"


def one_run(grade: str, seed: int, fs_hz: float, duration: str) -> dict[str, Any]:
    """Simulate one record, fit it (WLS and OLS) and read the slopes off."""
    from fogts.allan import allan_deviation
    from fogts.allan.noise import fit_noise
    from fogts.simulate.gyro import simulate_gyro

    truth = GRADES[grade]
    run = simulate_gyro(truth, fs_hz=fs_hz, duration_s=duration, rng=seed)
    curve = allan_deviation(run, taus="octave")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # Q and R are (rightly) reported unidentifiable
        wls = fit_noise(curve)
        ols = fit_noise(curve, method="ols")
    out: dict[str, Any] = {"grade": grade, "seed": seed}
    for t in TERMS:
        term = wls[t]
        out[t] = {"wls": term.value, "ols": ols[t].value,
                  "readoff": float(getattr(wls.readoff, t)),
                  "covered": bool(term.ci_low <= truth[t] <= term.ci_high)}
    return out


def run_jobs(fn: Callable[..., dict[str, Any]], jobs: list[tuple[Any, ...]],
             workers: int | None) -> list[dict[str, Any]]:
    """``fn(*job)`` for every job, on a process pool when more than one CPU is used."""
    nproc = workers or os.cpu_count() or 1
    if nproc > 1:
        with ProcessPoolExecutor(max_workers=nproc) as pool:
            return list(pool.map(fn, *zip(*jobs, strict=True)))
    return [fn(*job) for job in jobs]


def study(*, seeds: int, fs_hz: float, duration: str = "3h",
          workers: int | None = None) -> dict[str, dict[str, dict[str, float]]]:
    """Summary per grade and term over ``seeds`` seeds (see the module docstring)."""
    jobs = [(g, FIRST_SEED + s, fs_hz, duration) for g in GRADES for s in range(seeds)]
    runs = run_jobs(one_run, jobs, workers)
    summary: dict[str, dict[str, dict[str, float]]] = {}
    for grade, truth in GRADES.items():
        rows = [r for r in runs if r["grade"] == grade]
        summary[grade] = {}
        for t in TERMS:
            rel = {k: np.array([r[t][k] for r in rows]) / truth[t] - 1.0
                   for k in ("wls", "ols", "readoff")}
            summary[grade][t] = {
                "truth": truth[t],
                "wls": float(np.median(np.abs(rel["wls"]))),
                "bias": float(np.median(rel["wls"])),
                "coverage": float(np.mean([r[t]["covered"] for r in rows])),
                "ols": float(np.median(np.abs(rel["ols"]))),
                "readoff": float(np.median(np.abs(rel["readoff"]))),
            }
    return summary


def markdown(summary: dict[str, dict[str, dict[str, float]]], *, seeds: int, fs_hz: float,
             duration: str, seconds: float) -> str:
    lines = [
        f"Round-trip accuracy: {seeds} seeds per grade, {duration} at {fs_hz:g} Hz, "
        "`simulate_gyro` -> `allan_deviation` (oadev, octave taus) -> `fit_noise` "
        f"(five terms). Median absolute relative error; {seconds:.0f} s of wall time.",
        "",
        "| grade | term | truth | WLS fit (fogts) | WLS median bias | 68 % CI coverage "
        "| OLS fit | slope read-off |",
        "|---|---|---:|---:|---:|---:|---:|---:|",
    ]
    for grade, terms in summary.items():
        for t, s in terms.items():
            lines.append(f"| {grade} | {t} | {s['truth']:g} {UNITS[t]} | "
                         f"**{100 * s['wls']:.1f} %** | {100 * s['bias']:+.1f} % | "
                         f"{100 * s['coverage']:.0f} % | {100 * s['ols']:.1f} % | "
                         f"{100 * s['readoff']:.1f} % |")
    lines.append("")
    return "\n".join(lines)


def metrics(quick: bool = False) -> list[Metric]:
    """Benchmark-runner entry point: WLS median error and CI coverage per grade and term."""
    seeds, fs = (5, 10.0) if quick else (30, 100.0)
    summary = study(seeds=seeds, fs_hz=fs)
    tag = f"fs={fs:g}.seeds={seeds}"
    out: list[Metric] = []
    for grade, terms in summary.items():
        key = grade.lower().replace(" ", "_")
        for t, s in terms.items():
            out.append(accuracy_metric(
                f"accuracy.roundtrip.{key}.{t}.{tag}",
                f"{grade} {t}: median relative error of the WLS fit", value=s["wls"],
                better="lower", unit="rel", abs_tolerance=0.02,
                details={k: v for k, v in s.items() if k != "wls"}))
            out.append(accuracy_metric(
                f"accuracy.roundtrip_coverage.{key}.{t}.{tag}",
                f"{grade} {t}: |68.3 % CI coverage - 0.683|",
                value=abs(s["coverage"] - 0.683), better="lower", abs_tolerance=0.1,
                details={"coverage": s["coverage"]}))
    return out


def main(argv: list[str] | None = None) -> int:
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--quick", action="store_true", help="5 seeds at 10 Hz")
    p.add_argument("--seeds", type=int, default=None, help="seeds per grade (default 30)")
    p.add_argument("--fs", type=float, default=None, help="sample rate (default 100 Hz)")
    p.add_argument("--duration", default="3h")
    p.add_argument("--workers", type=int, default=None, help="processes (default: all CPUs)")
    p.add_argument("--out", type=Path, default=None,
                   help=f"markdown output (default {RESULTS}; not written with --quick)")
    args = p.parse_args(argv)
    seeds = args.seeds or (5 if args.quick else 30)
    fs = args.fs or (10.0 if args.quick else 100.0)
    t0 = time.perf_counter()
    summary = study(seeds=seeds, fs_hz=fs, duration=args.duration, workers=args.workers)
    text = markdown(summary, seeds=seeds, fs_hz=fs, duration=args.duration,
                    seconds=time.perf_counter() - t0)
    print(text)
    out = args.out or (None if args.quick else RESULTS)
    if out is not None:
        out.parent.mkdir(parents=True, exist_ok=True)
        out.write_text(text)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
