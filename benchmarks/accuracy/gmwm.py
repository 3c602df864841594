"""Round-trip accuracy of the GMWM noise fit against the WLS fit (issue 15).

The three grades of :mod:`benchmarks.accuracy.roundtrip` (navigation FOG, tactical FOG,
MEMS: white + flicker + rate random walk, ``simulate_gyro``'s default Markov-sum flicker)
and a fourth case, white + rate random walk + one first-order Gauss-Markov process
(``q_c``, ``T_c``; no flicker, so its B has no truth and the GM's sigma and T_c are
compared instead), 3 h at 100 Hz.  Each record goes through ``allan_deviation`` (oadev,
octave taus) and ``fit_noise`` with ``method="wls"`` and ``method="gmwm"``.  Reported per
case, term and method: the median absolute relative error and how often the 68.3 %
interval covers the truth (a dropped term counts as covered when its interval,
``[0, upper limit]``, holds the truth).

Run: ``python -m benchmarks.accuracy.gmwm --seeds 10`` (one process unless ``--workers``);
``--time`` also times ``fit_noise(method="gmwm")`` on a 1e6-sample record.
"""

from __future__ import annotations

import argparse
import math
import time
import warnings
from typing import Any

import numpy as np

from benchmarks.accuracy.roundtrip import FIRST_SEED, GRADES, run_jobs

#: white + rate random walk + one Gauss-Markov process (sigma = q_c sqrt(T_c / 2) = 0.3 deg/h)
GM_CASE: dict[str, float] = {"N": 0.01, "K": 1.0, "q_c": 0.3 / math.sqrt(15.0), "T_c": 30.0}
CASES: dict[str, dict[str, float]] = {**GRADES, "white + RW + GM": GM_CASE}
METHODS = ("wls", "gmwm")


def _truths(case: str) -> dict[str, float]:
    truth = CASES[case]
    if "q_c" not in truth:
        return dict(truth)
    return {"N": truth["N"], "K": truth["K"],
            "GM sigma": truth["q_c"] * math.sqrt(truth["T_c"] / 2.0), "GM T_c": truth["T_c"]}


def _gm_estimate(model: Any) -> dict[str, tuple[float, bool]]:
    """The GMWM fit's single GM (value, covered), NaN if it did not choose exactly one."""
    gms: tuple[Any, ...] = model.gmwm.gauss_markov if model.gmwm is not None else ()
    truth = _truths("white + RW + GM")
    if len(gms) != 1:
        return {"GM sigma": (math.nan, False), "GM T_c": (math.nan, False)}
    g = gms[0]
    pairs = {"GM sigma": (float(g.sigma), float(g.sigma_stderr)),
             "GM T_c": (float(g.t_c), float(g.t_c_stderr))}
    return {key: (v, abs(math.log(truth[key] / v)) <= se / v)
            for key, (v, se) in pairs.items()}


def one_run(case: str, seed: int, fs_hz: float, duration: str) -> dict[str, Any]:
    """Simulate one record and fit it with each method."""
    from fogts.allan import allan_deviation
    from fogts.allan.noise import fit_noise
    from fogts.simulate.gyro import simulate_gyro

    truth = _truths(case)
    run = simulate_gyro(CASES[case], fs_hz=fs_hz, duration_s=duration, rng=seed)
    curve = allan_deviation(run, taus="octave")
    out: dict[str, Any] = {"case": case, "seed": seed}
    for method in METHODS:
        t0 = time.perf_counter()
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            model = fit_noise(curve, method=method)  # type: ignore[arg-type]
        out[f"{method}_s"] = time.perf_counter() - t0
        for t in truth:
            if t.startswith("GM"):
                if method == "gmwm":
                    out[f"{t}|{method}"] = _gm_estimate(model)[t]
                continue
            term = model[t]
            out[f"{t}|{method}"] = (term.value, bool(term.ci_low <= truth[t] <= term.ci_high))
        if method == "gmwm" and model.gmwm is not None:
            out["model"] = model.gmwm.model
            out["j_ok"] = model.gmwm.consistent
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
            summary[case][t] = cell
        summary[case]["_fits"] = {
            "j_ok": float(np.mean([r.get("j_ok", False) for r in rows])),
            "wls_s": float(np.median([r["wls_s"] for r in rows])),
            "gmwm_s": float(np.median([r["gmwm_s"] for r in rows])),
        }
    return summary


def markdown(summary: dict[str, dict[str, dict[str, float]]], *, seeds: int,
             fs_hz: float, duration: str) -> str:
    lines = [f"GMWM vs WLS: {seeds} seeds per case, {duration} at {fs_hz:g} Hz, oadev octave "
             "taus. Median |relative error| and 68.3 % interval coverage.", "",
             "| case | term | WLS error | GMWM error | GMWM/WLS | WLS coverage "
             "| GMWM coverage |", "|---|---|---:|---:|---:|---:|---:|"]
    for case, terms in summary.items():
        for t, c in terms.items():
            if t == "_fits":
                continue
            wls = c.get("wls", math.nan)
            ratio = c["gmwm"] / wls if wls > 0 else math.nan
            lines.append(f"| {case} | {t} | {_pct(wls)} | {_pct(c['gmwm'])} | "
                         f"{ratio:.2f} | {_pct(c.get('wls_cov', math.nan), 0)} | "
                         f"{_pct(c['gmwm_cov'], 0)} |")
    lines += ["", "| case | GMWM J test accepts | median WLS fit (s) | median GMWM fit (s) |",
              "|---|---:|---:|---:|"]
    for case, terms in summary.items():
        f = terms["_fits"]
        lines.append(f"| {case} | {_pct(f['j_ok'], 0)} | {f['wls_s']:.2f} | "
                     f"{f['gmwm_s']:.2f} |")
    return "\n".join(lines) + "\n"


def _pct(v: float, digits: int = 1) -> str:
    return "–" if math.isnan(v) else f"{100 * v:.{digits}f} %"


def time_gmwm(n: int = 1_000_000, fs_hz: float = 100.0) -> dict[str, float]:
    """Wall time of ``allan_deviation`` and of ``fit_noise(method="gmwm")`` on ``n``
    samples of the tactical grade (median of three)."""
    from fogts.allan import allan_deviation
    from fogts.allan.noise import fit_noise
    from fogts.simulate.gyro import simulate_gyro

    run = simulate_gyro(GRADES["tactical FOG"], fs_hz=fs_hz, duration_s=n / fs_hz, rng=7)
    t0 = time.perf_counter()
    curve = allan_deviation(run, taus="octave")
    t_allan = time.perf_counter() - t0
    fits = []
    for _ in range(3):
        t0 = time.perf_counter()
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            fit_noise(curve, method="gmwm")
        fits.append(time.perf_counter() - t0)
    return {"allan_s": t_allan, "gmwm_s": float(np.median(fits))}


def main(argv: list[str] | None = None) -> int:
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--seeds", type=int, default=10, help="seeds per case (default 10)")
    p.add_argument("--fs", type=float, default=100.0)
    p.add_argument("--duration", default="3h")
    p.add_argument("--workers", type=int, default=1, help="processes (default 1)")
    p.add_argument("--time", action="store_true", help="also time gmwm on 1e6 samples")
    args = p.parse_args(argv)
    t0 = time.perf_counter()
    summary = study(seeds=args.seeds, fs_hz=args.fs, duration=args.duration,
                    workers=args.workers)
    print(markdown(summary, seeds=args.seeds, fs_hz=args.fs, duration=args.duration))
    print(f"({time.perf_counter() - t0:.0f} s of wall time)")
    if args.time:
        t = time_gmwm()
        print(f"1e6 samples: allan_deviation {t['allan_s']:.2f} s, "
              f"fit_noise(method='gmwm') {t['gmwm_s']:.2f} s")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
