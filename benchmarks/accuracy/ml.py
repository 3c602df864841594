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


def _ml_gm(model: Any) -> dict[str, tuple[float, bool]]:
    """The ML fit's single Gauss-Markov term (value, covered), NaN unless it chose one."""
    gms: tuple[Any, ...] = model.ml.gauss_markov if model.ml is not None else ()
    truth = _truths("white + RW + GM")
    if len(gms) != 1:
        return {"GM sigma": (math.nan, False), "GM T_c": (math.nan, False)}
    g = gms[0]
    pairs = {"GM sigma": (float(g.sigma), float(g.sigma_stderr)),
             "GM T_c": (float(g.t_c), float(g.t_c_stderr))}
    return {key: (v, abs(math.log(truth[key] / v)) <= se / v)
            for key, (v, se) in pairs.items()}


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


def one_run(case: str, seed: int, fs_hz: float, duration: str) -> dict[str, Any]:
    """Simulate one record and fit it with each method."""
    from fogts.allan import allan_deviation
    from fogts.simulate.gyro import simulate_gyro

    truth = _truths(case)
    run = simulate_gyro(CASES[case], fs_hz=fs_hz, duration_s=duration, rng=seed)
    curve = allan_deviation(run, taus="octave")
    out: dict[str, Any] = {"case": case, "seed": seed}
    for method in METHODS:
        t0 = time.perf_counter()
        model = _fit(method, run, curve, fs_hz)
        out[f"{method}_s"] = time.perf_counter() - t0
        gm = (_gm_estimate(model) if method == "gmwm" else
              _ml_gm(model) if method == "ml" else {})
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
    return out


def study(*, seeds: int, fs_hz: float = 100.0, duration: str = "3h",
          workers: int | None = 1) -> dict[str, dict[str, dict[str, float]]]:
    """Per case and term: ``{method: median |rel err|, method_cov: coverage}``."""
    jobs = [(c, FIRST_SEED + s, fs_hz, duration) for c in CASES for s in range(seeds)]
    runs = run_jobs(one_run, jobs, workers)
    summary: dict[str, dict[str, dict[str, float]]] = {}
    for case in CASES:
        rows = [r for r in runs if r["case"] == case]
        summary[case] = {}
        for t, true in _truths(case).items():
            cell: dict[str, float] = {"truth": true}
            for method in METHODS:
                if f"{t}|{method}" not in rows[0]:
                    continue
                vals = np.array([r[f"{t}|{method}"][0] for r in rows])
                cell[method] = float(np.nanmedian(np.abs(vals / true - 1.0)))
                cell[f"{method}_cov"] = float(np.mean([r[f"{t}|{method}"][1] for r in rows]))
            cell["ml_se"] = float(np.nanmedian([r[f"{t}|ml|se"] for r in rows]))
            summary[case][t] = cell
        models = [r.get("ml_model", "") for r in rows]
        summary[case]["_fits"] = {
            **{f"{m}_s": float(np.median([r[f"{m}_s"] for r in rows])) for m in METHODS},
            "ml_flicker": float(np.mean(["B" in m.split(" + ") for m in models])),
        }
    return summary


def markdown(summary: dict[str, dict[str, dict[str, float]]], *, seeds: int,
             fs_hz: float, duration: str) -> str:
    lines = [f"ML beside WLS and GMWM: {seeds} seeds per case, {duration} at {fs_hz:g} Hz. "
             "Median |relative error| (ML/WLS ratio), 68.3 % interval coverage, and ML's "
             "median relative standard error (observed information).", "",
             "| case | term | WLS error | GMWM error | ML error | ML/WLS | WLS cov. "
             "| GMWM cov. | ML cov. | ML se |", "|---|---|---:|---:|---:|---:|---:|---:|---:|---:|"]
    for case, terms in summary.items():
        for t, c in terms.items():
            if t == "_fits":
                continue
            wls = c.get("wls", math.nan)
            ratio = c["ml"] / wls if wls > 0 else math.nan
            lines.append(f"| {case} | {t} | {_pct(wls)} | {_pct(c['gmwm'])} | "
                         f"{_pct(c['ml'])} | {ratio:.2f} | {_pct(c.get('wls_cov', math.nan), 0)}"
                         f" | {_pct(c['gmwm_cov'], 0)} | {_pct(c['ml_cov'], 0)} | "
                         f"{_pct(c['ml_se'])} |")
    lines += ["", "| case | ML chose the flicker model | median fit (s): WLS / GMWM / ML |",
              "|---|---:|---:|"]
    for case, terms in summary.items():
        f = terms["_fits"]
        lines.append(f"| {case} | {_pct(f['ml_flicker'], 0)} | {f['wls_s']:.2f} / "
                     f"{f['gmwm_s']:.2f} / {f['ml_s']:.2f} |")
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
