"""Round-trip accuracy of the maximum-likelihood noise fit beside WLS and GMWM (issue 15).

The cases of :mod:`benchmarks.accuracy.gmwm` (the three grades of
:mod:`benchmarks.accuracy.roundtrip`, white + flicker + rate random walk, and white + rate
random walk + one Gauss-Markov process), 3 h at 100 Hz.  Each record is fitted by
``fit_noise(allan_deviation(run, taus="octave"), method=...)`` with ``"wls"`` and
``"gmwm"``, and by ``fit_noise_ml(run.rate, fs)`` (defaults: ``decimate="auto"``, at most
4096 block means, B as a Markov-sum flicker or 1..3 Gauss-Markov terms by BIC).  Reported
per case, term and method: the median absolute relative error and the 68.3 % coverage.

Run: ``python -m benchmarks.accuracy.ml --seeds 10 [--time]``; ``--time`` also times
``fit_noise_ml`` on 1e6 samples of the tactical grade.
"""

from __future__ import annotations

import argparse
import math
import time
import warnings
from typing import Any

import numpy as np

from benchmarks.accuracy.gmwm import CASES, _gm_estimate, _truths
from benchmarks.accuracy.roundtrip import FIRST_SEED, GRADES, run_jobs

METHODS = ("wls", "gmwm", "ml")


def _ml_gm_se(model: Any) -> dict[str, float]:
    gms: tuple[Any, ...] = model.ml.gauss_markov if model.ml is not None else ()
    if len(gms) != 1:
        return {"GM sigma": math.nan, "GM T_c": math.nan}
    g = gms[0]
    return {"GM sigma": g.sigma_stderr / g.sigma, "GM T_c": g.t_c_stderr / g.t_c}


def _fit(method: str, run: Any, curve: Any, fs_hz: float) -> Any:
    from fogts.allan.ml import fit_noise_ml
    from fogts.allan.noise import fit_noise

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        if method == "ml":
            return fit_noise_ml(run.rate, fs_hz, units=run.units)
        return fit_noise(curve, method=method)  # type: ignore[arg-type]


def one_run(case: str, seed: int, fs_hz: float, duration: str,
            methods: tuple[str, ...] = METHODS) -> dict[str, Any]:
    """Simulate one record and fit it with each of ``methods``."""
    from fogts.allan import allan_deviation
    from fogts.simulate.gyro import simulate_gyro

    truth = _truths(case)
    run = simulate_gyro(CASES[case], fs_hz=fs_hz, duration_s=duration, rng=seed)
    curve = allan_deviation(run, taus="octave")
    out: dict[str, Any] = {"case": case, "seed": seed}
    for method in methods:
        t0 = time.perf_counter()
        model = _fit(method, run, curve, fs_hz)
        out[f"{method}_s"] = time.perf_counter() - t0
        gm = _gm_estimate(model, method) if method in ("gmwm", "ml") else {}
        for t in truth:
            if t.startswith("GM"):
                if gm:
                    out[f"{t}|{method}"] = gm[t]
                if method == "ml":
                    out[f"{t}|ml|se"] = _ml_gm_se(model)[t]
                continue
            term = model[t]
            out[f"{t}|{method}"] = (term.value, bool(term.ci_low <= truth[t] <= term.ci_high))
            out[f"{t}|{method}|se"] = term.stderr / term.value if term.value > 0 else math.nan
        if method == "ml" and model.ml is not None:
            out["ml_model"] = model.ml.model
        if method == "gmwm" and model.gmwm is not None:
            out["j_ok"] = model.gmwm.consistent
    return out


def study(*, seeds: int, fs_hz: float = 100.0, duration: str = "3h", workers: int | None = 1,
          methods: tuple[str, ...] = METHODS) -> dict[str, dict[str, dict[str, float]]]:
    """Per case and term: ``{method: median |rel err|, method_cov: coverage}`` (and ML's
    median relative standard error); per case ``_fits``: median fit times, how often the
    GMWM J test accepts and ML chose the flicker model."""
    jobs = [(c, FIRST_SEED + s, fs_hz, duration, methods) for c in CASES for s in range(seeds)]
    runs = run_jobs(one_run, jobs, workers)
    summary: dict[str, dict[str, dict[str, float]]] = {}
    for case in CASES:
        rows = [r for r in runs if r["case"] == case]
        summary[case] = {}
        for t, true in _truths(case).items():
            cell: dict[str, float] = {"truth": true}
            for method in methods:
                if f"{t}|{method}" not in rows[0]:
                    continue
                vals = np.array([r[f"{t}|{method}"][0] for r in rows])
                cell[method] = float(np.nanmedian(np.abs(vals / true - 1.0)))
                cell[f"{method}_cov"] = float(np.mean([r[f"{t}|{method}"][1] for r in rows]))
            if "ml" in methods:
                cell["ml_se"] = float(np.nanmedian([r[f"{t}|ml|se"] for r in rows]))
            summary[case][t] = cell
        fits = {f"{m}_s": float(np.median([r[f"{m}_s"] for r in rows])) for m in methods}
        if "gmwm" in methods:
            fits["j_ok"] = float(np.mean([r.get("j_ok", False) for r in rows]))
        if "ml" in methods:
            models = [r.get("ml_model", "") for r in rows]
            fits["ml_flicker"] = float(np.mean(["B" in m.split(" + ") for m in models]))
        summary[case]["_fits"] = fits
    return summary


_LABEL = {"wls": "WLS", "gmwm": "GMWM", "ml": "ML"}


def markdown(summary: dict[str, dict[str, dict[str, float]]], *, seeds: int,
             fs_hz: float, duration: str, methods: tuple[str, ...] = METHODS) -> str:
    """The study's tables: per case and term each method's median |relative error| (and its
    ratio to WLS's), 68.3 % coverage, and ML's median relative standard error."""
    names = [_LABEL[m] for m in methods]
    others = [m for m in methods if m != "wls"]
    head = (["case", "term"] + [f"{n} error" for n in names]
            + [f"{_LABEL[m]}/WLS" for m in others] + [f"{n} cov." for n in names]
            + (["ML se"] if "ml" in methods else []))
    lines = [f"{' beside '.join(reversed(names))}: {seeds} seeds per case, {duration} at "
             f"{fs_hz:g} Hz. Median |relative error|, its ratio to WLS's, 68.3 % interval "
             "coverage" + (", and ML's median relative standard error (observed "
                           "information)." if "ml" in methods else "."), "",
             "| " + " | ".join(head) + " |", "|---|---|" + "---:|" * (len(head) - 2)]
    for case, terms in summary.items():
        for t, c in terms.items():
            if t == "_fits":
                continue
            wls = c.get("wls", math.nan)
            cells = ([_pct(c.get(m, math.nan)) for m in methods]
                     + [f"{c.get(m, math.nan) / wls:.2f}" if wls > 0 else "–" for m in others]
                     + [_pct(c.get(f"{m}_cov", math.nan), 0) for m in methods]
                     + ([_pct(c["ml_se"])] if "ml" in methods else []))
            lines.append(f"| {case} | {t} | " + " | ".join(cells) + " |")
    lines += ["", "| case | median fit (s): " + " / ".join(names)
              + (" | GMWM J test accepts" if "gmwm" in methods else "")
              + (" | ML chose the flicker model" if "ml" in methods else "") + " |",
              "|---|---:|" + ("---:|" if "gmwm" in methods else "")
              + ("---:|" if "ml" in methods else "")]
    for case, terms in summary.items():
        f = terms["_fits"]
        row = f"| {case} | " + " / ".join(f"{f[f'{m}_s']:.2f}" for m in methods)
        row += f" | {_pct(f['j_ok'], 0)}" if "gmwm" in methods else ""
        row += f" | {_pct(f['ml_flicker'], 0)}" if "ml" in methods else ""
        lines.append(row + " |")
    return "\n".join(lines) + "\n"


def _pct(v: float, digits: int = 1) -> str:
    return "–" if math.isnan(v) else f"{100 * v:.{digits}f} %"


def time_ml(n: int = 1_000_000, fs_hz: float = 100.0) -> dict[str, float]:
    """Wall time of ``fit_noise_ml`` on ``n`` samples of the tactical grade (median of
    three)."""
    from fogts.allan.ml import fit_noise_ml
    from fogts.simulate.gyro import simulate_gyro

    run = simulate_gyro(GRADES["tactical FOG"], fs_hz=fs_hz, duration_s=n / fs_hz, rng=7)
    fits = []
    for _ in range(3):
        t0 = time.perf_counter()
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            fit_noise_ml(run.rate, fs_hz)
        fits.append(time.perf_counter() - t0)
    return {"ml_s": float(np.median(fits)), "ml_max_s": float(np.max(fits))}


def main(argv: list[str] | None = None) -> int:
    p = argparse.ArgumentParser(description=(__doc__ or "").split("\n")[0])
    p.add_argument("--seeds", type=int, default=10, help="seeds per case (default 10)")
    p.add_argument("--fs", type=float, default=100.0)
    p.add_argument("--duration", default="3h")
    p.add_argument("--workers", type=int, default=1, help="processes (default 1)")
    p.add_argument("--time", action="store_true", help="also time ml on 1e6 samples")
    args = p.parse_args(argv)
    t0 = time.perf_counter()
    if args.seeds > 0:
        summary = study(seeds=args.seeds, fs_hz=args.fs, duration=args.duration,
                        workers=args.workers)
        print(markdown(summary, seeds=args.seeds, fs_hz=args.fs, duration=args.duration))
        print(f"({time.perf_counter() - t0:.0f} s of wall time)")
    if args.time:
        t = time_ml()
        print(f"1e6 samples: fit_noise_ml {t['ml_s']:.2f} s (median of 3; max "
              f"{t['ml_max_s']:.2f} s)")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
