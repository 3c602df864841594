"""Interval coverage of the noise fit when bias instability is a Gauss–Markov sum, not 1/f.

The round-trip study (:mod:`.roundtrip`) simulates with ``simulate_gyro``, whose bias
instability is the ideal flat flicker the five-term model assumes.  Here the records come
from an independent simulator written in the test code
(``tests/allan/gauss_markov_sum.py``): white rate noise N, five first-order Gauss–Markov
processes with correlation times 1..3000 s (log-spaced, equal variances) scaled to the
grade's flicker-equivalent B, and a rate random walk K.  Its exact Allan curve departs from
the five-term curve by up to ~1 % (ripple and roll-off), which is the model misfit the
fit's intervals must account for.  B's truth is the flicker-equivalent level defined in
that module; N and K are the simulator's parameters.

For the tactical FOG and MEMS grades of :mod:`.roundtrip`, 3 h at 100 Hz, 40 seeds each:
``allan_deviation`` (oadev, octave taus, 68.3 %) -> ``fit_noise`` (default five terms,
WLS).  Reported per grade and term: how often the 68.3 % interval covers the truth (ideal
0.683; with 40 seeds its binomial sd is 0.074), the median relative error and bias, and per
grade how often a Q (which the simulator does not contain) is fitted, and how often it is
fitted without a warning.

Run: ``python -m benchmarks.accuracy.gauss_markov [--seeds 40]``; the markdown table goes
to ``benchmarks/results/accuracy_gauss_markov.md``.
"""

from __future__ import annotations

import argparse
import time
import warnings
from pathlib import Path
from typing import Any

import numpy as np

from benchmarks.accuracy.roundtrip import GRADES, TERMS, UNITS, run_jobs
from benchmarks.metric import Metric, accuracy_metric

STUDY_GRADES = ("tactical FOG", "MEMS")
FIRST_SEED = 7000
FS_HZ, DURATION_S = 100.0, 10_800.0
RESULTS = Path(__file__).resolve().parents[1] / "results" / "accuracy_gauss_markov.md"


def one_run(grade: str, seed: int, method: str = "wls") -> dict[str, Any]:
    """Simulate one Gauss–Markov-sum record, fit it, and record coverage and Q."""
    from fogts.allan import allan_deviation
    from fogts.allan.noise import fit_noise
    from tests.allan.gauss_markov_sum import GaussMarkovGyro

    truth = GRADES[grade]
    gyro = GaussMarkovGyro(N=truth["N"], B=truth["B"], K=truth["K"])
    rate = gyro.simulate(fs_hz=FS_HZ, duration_s=DURATION_S, seed=seed)
    curve = allan_deviation(rate, fs_hz=FS_HZ, taus="octave", units="deg/h")
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        model = fit_noise(curve, method=method)  # type: ignore[arg-type]
    q = model["Q"]
    out: dict[str, Any] = {
        "grade": grade, "seed": seed, "model_error": model.model_error,
        "q_fitted": q.status == "fitted" and not q.is_limit,
        "q_warned": any(" Q " in str(w.message) or "quantization" in str(w.message)
                        for w in caught)}
    for t in TERMS:
        term = model[t]
        out[t] = {"value": term.value,
                  "covered": bool(term.ci_low <= truth[t] <= term.ci_high)}
    return out


def study(*, seeds: int, method: str = "wls", workers: int | None = None,
          grades: tuple[str, ...] = STUDY_GRADES) -> dict[str, dict[str, Any]]:
    """Coverage, error and bias per grade and term; Q counts per grade."""
    jobs = [(g, FIRST_SEED + 100 * i + s, method) for i, g in enumerate(grades)
            for s in range(seeds)]
    runs = run_jobs(one_run, jobs, workers)
    summary: dict[str, dict[str, Any]] = {}
    for grade in grades:
        rows = [r for r in runs if r["grade"] == grade]
        truth = GRADES[grade]
        summary[grade] = {
            "q_fitted": int(sum(r["q_fitted"] for r in rows)),
            "q_unwarned": int(sum(r["q_fitted"] and not r["q_warned"] for r in rows)),
            "seeds": len(rows)}
        for t in TERMS:
            rel = np.array([r[t]["value"] for r in rows]) / truth[t] - 1.0
            summary[grade][t] = {
                "truth": truth[t], "coverage": float(np.mean([r[t]["covered"] for r in rows])),
                "error": float(np.median(np.abs(rel))), "bias": float(np.median(rel))}
    return summary


def markdown(summary: dict[str, dict[str, Any]], *, seeds: int, method: str,
             seconds: float) -> str:
    lines = [
        f"Gauss–Markov-sum bias instability: {seeds} seeds per grade, 3 h at 100 Hz, "
        "independent simulator (`tests/allan/gauss_markov_sum.py`) -> `allan_deviation` "
        f"(oadev, octave taus) -> `fit_noise` (five terms, {method}); {seconds:.0f} s of "
        "wall time.",
        "",
        "| grade | term | truth | 68 % CI coverage | median abs. error | median bias |",
        "|---|---|---:|---:|---:|---:|",
    ]
    for grade, s in summary.items():
        for t in TERMS:
            lines.append(f"| {grade} | {t} | {s[t]['truth']:g} {UNITS[t]} | "
                         f"**{100 * s[t]['coverage']:.0f} %** | {100 * s[t]['error']:.1f} % | "
                         f"{100 * s[t]['bias']:+.1f} % |")
    lines += ["", "| grade | Q fitted (no Q simulated) | ... of them without a warning |",
              "|---|---:|---:|"]
    for grade, s in summary.items():
        lines.append(f"| {grade} | {s['q_fitted']} / {s['seeds']} | {s['q_unwarned']} |")
    lines.append("")
    return "\n".join(lines)


def metrics(quick: bool = False) -> list[Metric]:
    """Benchmark-runner entry point: |coverage - 0.683| per grade and term."""
    seeds = 8 if quick else 40
    summary = study(seeds=seeds)
    out: list[Metric] = []
    for grade, s in summary.items():
        key = grade.lower().replace(" ", "_")
        for t in TERMS:
            out.append(accuracy_metric(
                f"accuracy.gauss_markov_coverage.{key}.{t}.seeds={seeds}",
                f"{grade} {t} (Gauss–Markov-sum B): |68.3 % CI coverage - 0.683|",
                value=abs(s[t]["coverage"] - 0.683), better="lower", abs_tolerance=0.1,
                details=s[t]))
    return out


def main(argv: list[str] | None = None) -> int:
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--seeds", type=int, default=40, help="seeds per grade (default 40)")
    p.add_argument("--method", default="wls", choices=("wls", "gls"))
    p.add_argument("--workers", type=int, default=None, help="processes (default: all CPUs)")
    p.add_argument("--out", type=Path, default=RESULTS, help=f"markdown output ({RESULTS})")
    args = p.parse_args(argv)
    t0 = time.perf_counter()
    summary = study(seeds=args.seeds, method=args.method, workers=args.workers)
    text = markdown(summary, seeds=args.seeds, method=args.method,
                    seconds=time.perf_counter() - t0)
    print(text)
    args.out.parent.mkdir(parents=True, exist_ok=True)
    args.out.write_text(text)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
