"""Noise-coefficient round trip: the IEEE-952 fit against the slope read-off, by sensor grade.

Every figure compares methods on the *same* simulated curves (fixed seeds), so it is a
ratio measured in one run:

* **White + random walk**: white rate noise N = 0.05 deg/sqrt(h) plus a
  rate random walk K = 10 deg/h^1.5, 100 Hz, 3 h, 30 seeds.  Median absolute relative
  error of N and K for ``fit_noise`` (the default: WLS on the five terms with term selection
  at 5 %; the same without selection, ``significance=None``; WLS on N, K; GLS; OLS) and for
  the classic slope read-off (IEEE 952 Annex C / MATLAB ``allanvar``: -1/2 line at 1 s,
  +1/2 line at 3 s).  Reported as ratios read-off error / fit error (> 1: the fit wins),
  plus how often the 68.3 % intervals cover the truth (ideal 0.683).
* **Sensor grades**: ``fogts.simulate.gyro.simulate_gyro`` records (flicker B as a Markov sum)
  of a navigation FOG, a tactical FOG and a MEMS gyro, 100 Hz, 3 h; median errors of N,
  B, K for the WLS fit and the read-offs (B: minimum / 0.664).

The Allan curves come from ``fogts.allan.allan_deviation`` (octave taus, Greenhall EDF).

Run: ``python -m benchmarks.bench_noise_fit [--quick] [--out benchmarks/results/noise_fit.md]``.
"""

from __future__ import annotations

import math
import sys
import time
import warnings
from typing import Any

import numpy as np

from benchmarks.cli import script_main
from benchmarks.metric import Metric, accuracy_metric
from fogts.allan import allan_deviation
from fogts.allan.noise import fit_noise

FS_HZ = 100.0
N_TRUE, K_TRUE = 0.05, 10.0
GRADES: dict[str, dict[str, float]] = {
    # each grade's N, B and K regions all fall inside 0.01 s .. 3 h
    "navigation FOG": {"N": 0.003, "B": 0.01, "K": 0.01},
    "tactical FOG": {"N": 0.05, "B": 0.5, "K": 1.0},
    "MEMS": {"N": 0.3, "B": 5.0, "K": 20.0},
}
NOMINAL = 0.683


def _fit(res: Any, **kw: Any) -> Any:
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return fit_noise(res, **kw)


def _white_rw(seed: int, n: int) -> np.ndarray:
    rng = np.random.default_rng(seed)
    return (60 * N_TRUE * math.sqrt(FS_HZ) * rng.standard_normal(n)
            + np.cumsum(K_TRUE / 60 / math.sqrt(FS_HZ) * rng.standard_normal(n)))


def white_rw_study(seeds: int, hours: float) -> dict[str, dict[str, float]]:
    """Median |relative error| and 68.3 % coverage per method, over ``seeds`` records."""
    n = int(hours * 3600 * FS_HZ)
    err: dict[str, list[tuple[float, float]]] = {}
    cover: dict[str, list[tuple[bool, bool]]] = {}
    seconds: dict[str, float] = {}
    methods: dict[str, dict[str, Any]] = {
               "WLS, 5 terms": {}, "WLS, 5 terms, no selection": {"significance": None},
               "WLS, N and K": {"terms": "N,K"},
               "GLS, 5 terms": {"method": "gls"},
               "GLS, 5 terms, no selection": {"method": "gls", "significance": None},
               "GLS, N and K": {"method": "gls", "terms": "N,K"},
               "OLS, 5 terms": {"method": "ols"}}
    for seed in range(seeds):
        res = allan_deviation(_white_rw(seed, n), fs_hz=FS_HZ)
        model = None
        for name, kw in methods.items():
            t0 = time.perf_counter()
            model = _fit(res, **kw)
            seconds[name] = seconds.get(name, 0.0) + time.perf_counter() - t0
            n_t, k_t = model["N"], model["K"]
            err.setdefault(name, []).append((n_t.value / N_TRUE - 1, k_t.value / K_TRUE - 1))
            cover.setdefault(name, []).append((n_t.ci_low <= N_TRUE <= n_t.ci_high,
                                               k_t.ci_low <= K_TRUE <= k_t.ci_high))
        assert model is not None
        err.setdefault("slope read-off", []).append((model.readoff.N / N_TRUE - 1,
                                                     model.readoff.K / K_TRUE - 1))
    out: dict[str, dict[str, float]] = {}
    for name, values in err.items():
        e = np.abs(np.array(values))
        row = {"N": float(np.median(e[:, 0])), "K": float(np.median(e[:, 1])),
               "K_max": float(np.max(e[:, 1]))}
        if name in cover:
            c = np.array(cover[name], dtype=float)
            row |= {"cover_N": float(c[:, 0].mean()), "cover_K": float(c[:, 1].mean()),
                    "ms": 1e3 * seconds[name] / seeds}
        out[name] = row
    return out


def grade_study(seeds: int, hours: float) -> dict[str, dict[str, dict[str, float]]]:
    """Per grade: median |relative error| of N, B, K for the WLS fit (default, and without
    term selection: ``"all"``) and the read-offs."""
    from fogts.simulate.gyro import simulate_gyro

    out: dict[str, dict[str, dict[str, float]]] = {}
    for grade, truth in GRADES.items():
        fit_e: list[list[float]] = []
        all_e: list[list[float]] = []
        ro_e: list[list[float]] = []
        for seed in range(seeds):
            run = simulate_gyro(truth, fs_hz=FS_HZ, duration_s=hours * 3600, rng=100 + seed)
            curve = allan_deviation(run)
            model = _fit(curve)
            kept = _fit(curve, significance=None)
            ro = {"N": model.readoff.N, "B": model.readoff.B, "K": model.readoff.K}
            fit_e.append([model[t].value / v - 1 for t, v in truth.items()])
            all_e.append([kept[t].value / v - 1 for t, v in truth.items()])
            ro_e.append([ro[t] / v - 1 for t, v in truth.items()])
        out[grade] = {key: dict(zip(truth, np.median(np.abs(np.array(e)), axis=0).tolist(),
                                    strict=True))
                      for key, e in (("fit", fit_e), ("all", all_e), ("readoff", ro_e))}
    return out


def metrics(quick: bool) -> list[Metric]:
    """The runner's entry point."""
    seeds, hours = (6, 3.0) if quick else (30, 3.0)
    g_seeds = 2 if quick else 8
    wk = white_rw_study(seeds, hours)
    ro = wk["slope read-off"]
    tag = f"seeds={seeds}"
    out: list[Metric] = []
    for name, key in (("WLS, 5 terms", "wls5"), ("WLS, 5 terms, no selection", "wls5_all"),
                      ("WLS, N and K", "wls_nk"), ("GLS, 5 terms", "gls5"),
                      ("GLS, 5 terms, no selection", "gls5_all"), ("OLS, 5 terms", "ols5")):
        row = wk[name]
        for term in ("N", "K"):
            out.append(accuracy_metric(
                f"noise_fit.white_rw.{key}.{term}.readoff_over_fit.{tag}",
                f"{term}: median |error| of the slope read-off / {name} (white + RRW, "
                f"100 Hz, {hours:g} h, {seeds} seeds)",
                value=ro[term] / row[term], better="higher", unit="x",
                details={"fit_median_abs_rel_error": row[term],
                         "readoff_median_abs_rel_error": ro[term]}))
        if name != "OLS, 5 terms":
            for term in ("N", "K"):
                out.append(accuracy_metric(
                    f"noise_fit.white_rw.{key}.{term}.coverage_gap.{tag}",
                    f"{term}: |coverage of the 68.3 % interval - 0.683| ({name})",
                    value=abs(row[f"cover_{term}"] - NOMINAL), better="lower",
                    abs_tolerance=0.1,
                    details={"coverage_K": row["cover_K"], "coverage_N": row["cover_N"]}))
    grades = grade_study(g_seeds, hours)
    for grade, res in grades.items():
        for term in ("N", "B", "K"):
            f, r = res["fit"][term], res["readoff"][term]
            out.append(accuracy_metric(
                f"noise_fit.grade.{grade.replace(' ', '_')}.{term}.readoff_over_fit.seeds={g_seeds}",
                f"{grade}: {term} median |error|, read-off / WLS fit",
                value=r / f, better="higher", unit="x",
                details={"fit": f, "readoff": r}))
            a = res["all"][term]
            out.append(accuracy_metric(
                f"noise_fit.grade.{grade.replace(' ', '_')}.{term}.readoff_over_fit_all.seeds={g_seeds}",
                f"{grade}: {term} median |error|, read-off / WLS fit without term selection",
                value=r / a, better="higher", unit="x",
                details={"fit": a, "readoff": r}))
    _print_details(wk, grades, seeds, g_seeds)
    return out


def _print_details(wk: dict[str, dict[str, float]], grades: dict[str, Any], seeds: int,
                   g_seeds: int) -> None:
    lines = [f"White + RRW, 100 Hz, 3 h, {seeds} seeds (median |relative error|; coverage of "
             "the 68.3 % interval):", "",
             "| method | N error | K error | K worst | N coverage | K coverage | ms/fit |",
             "|---|---:|---:|---:|---:|---:|---:|"]
    for name, row in wk.items():
        cov = (f"{row['cover_N']:.2f} | {row['cover_K']:.2f} | {row['ms']:.0f}"
               if "cover_N" in row else "- | - | -")
        lines.append(f"| {name} | {100 * row['N']:.3f} % | {100 * row['K']:.2f} % | "
                     f"{100 * row['K_max']:.1f} % | {cov} |")
    lines += ["", f"Sensor grades, 100 Hz, 3 h, {g_seeds} seeds (median |relative error|, "
              "WLS fit / without term selection / read-off):", "", "| grade | N | B | K |",
              "|---|---:|---:|---:|"]
    for grade, res in grades.items():
        cells = [f"{100 * res['fit'][t]:.2f} % / {100 * res['all'][t]:.2f} % / "
                 f"{100 * res['readoff'][t]:.2f} %" for t in ("N", "B", "K")]
        lines.append(f"| {grade} ({', '.join(f'{k}={v:g}' for k, v in GRADES[grade].items())})"
                     f" | {' | '.join(cells)} |")
    print("\n".join(lines) + "\n", file=sys.stderr)


def main(argv: list[str] | None = None) -> int:
    return script_main(__doc__, metrics, argv, quick_help="fewer seeds")


if __name__ == "__main__":
    raise SystemExit(main())
