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

The records and tables are those of :mod:`benchmarks.accuracy.ml` with WLS and GMWM only.

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

from benchmarks.accuracy.roundtrip import GRADES

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


def _gm_estimate(model: Any, method: str = "gmwm") -> dict[str, tuple[float, bool]]:
    """The fit's single Gauss-Markov term (value, covered) from ``model.gmwm`` or
    ``model.ml`` (``method``), NaN if it did not choose exactly one."""
    summary = getattr(model, method)
    gms: tuple[Any, ...] = summary.gauss_markov if summary is not None else ()
    truth = _truths("white + RW + GM")
    if len(gms) != 1:
        return {"GM sigma": (math.nan, False), "GM T_c": (math.nan, False)}
    g = gms[0]
    pairs = {"GM sigma": (float(g.sigma), float(g.sigma_stderr)),
             "GM T_c": (float(g.t_c), float(g.t_c_stderr))}
    return {key: (v, abs(math.log(truth[key] / v)) <= se / v)
            for key, (v, se) in pairs.items()}


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
    from benchmarks.accuracy.ml import markdown, study  # the one study; here WLS and GMWM

    t0 = time.perf_counter()
    summary = study(seeds=args.seeds, fs_hz=args.fs, duration=args.duration,
                    workers=args.workers, methods=METHODS)
    print(markdown(summary, seeds=args.seeds, fs_hz=args.fs, duration=args.duration,
                   methods=METHODS))
    print(f"({time.perf_counter() - t0:.0f} s of wall time)")
    if args.time:
        t = time_gmwm()
        print(f"1e6 samples: allan_deviation {t['allan_s']:.2f} s, "
              f"fit_noise(method='gmwm') {t['gmwm_s']:.2f} s")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
