"""Benchmark the seed-004 start-up tools: EMD, steady-state Kalman, thermal fit, north seeking.

Every time is reported as a ratio against a peer measured in the same run (these machines
are shared and noisy):

* EMD of 10^5 samples (trend + ARMA noise): fogts' own sifting vs PyEMD's ``EMD`` (the
  Apache-2.0 ``EMD-signal`` package, if installed; skipped otherwise).  Both use cubic
  splines; the IMF counts are printed beside the times.
* Kalman filter + smoother of an ARMA(2,1) + white noise series: fogts' steady-state path
  (DARE + lfilter, exact over the transient) vs statsmodels' ``SARIMAX(...,
  measurement_error=True).smooth`` with the same parameters; the largest difference of the
  smoothed series is printed too.
* Thermal fit (GLS with AR(4) errors) of a 1 h cold start vs plain OLS on the same design.

Run ``python benchmarks/bench_emd_kalman.py`` (or ``--quick`` for a smoke run); the table is
written to ``benchmarks/results/emd_kalman.md``.
"""

from __future__ import annotations

import argparse
import time
from collections.abc import Callable
from pathlib import Path
from typing import Any

import numpy as np
from scipy.signal import lfilter


def _best(fn: Callable[[], Any], repeat: int) -> tuple[float, Any]:
    best, out = float("inf"), None
    for _ in range(repeat):
        t0 = time.perf_counter()
        out = fn()
        best = min(best, time.perf_counter() - t0)
    return best, out


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="small sizes, one repeat")
    args = ap.parse_args()
    n_emd = 20_000 if args.quick else 100_000
    n_kf = 20_000 if args.quick else 1_000_000
    repeat = 1 if args.quick else 3
    rows: list[tuple[str, str, str, str]] = []

    # ---- EMD
    from fogts.emd import emd, separate_trend

    rng = np.random.default_rng(4)
    t = np.arange(n_emd, dtype=float)
    x = 3.0 * (1 - np.exp(-t / (n_emd / 6))) + 0.5 * t / n_emd + 0.3 * lfilter(
        [1.0, 0.3], [1.0, -0.5], rng.standard_normal(n_emd))
    t_f, res = _best(lambda: emd(x), repeat)
    split = separate_trend(x, fs_hz=1.0)
    try:
        from PyEMD import EMD as PyEMD  # Apache-2.0 peer

        peer = PyEMD(spline_kind="cubic")
        t_p, imfs_p = _best(lambda: peer.emd(x), repeat)
        rows.append((f"EMD, n = {n_emd:,}", f"{t_f:.2f} s ({res.n_imfs} IMFs, k = {split.k})",
                     f"PyEMD {t_p:.2f} s ({len(imfs_p)} rows)", f"{t_p / t_f:.2f}x"))
    except ImportError:
        rows.append((f"EMD, n = {n_emd:,}", f"{t_f:.2f} s ({res.n_imfs} IMFs)",
                     "PyEMD not installed", "-"))

    # ---- Kalman
    from statsmodels.tsa.statespace.sarimax import SARIMAX

    from fogts.kalman import arma_kalman

    ar, ma, s2, h = (1.2, -0.3), (0.4,), 0.04, 0.25
    drift = lfilter([1.0, ma[0]], [1.0, -ar[0], -ar[1]], rng.normal(0, np.sqrt(s2), n_kf))
    y = drift + rng.normal(0, np.sqrt(h), n_kf)
    params = {"ar.L1": ar[0], "ar.L2": ar[1], "ma.L1": ma[0], "sigma2": s2}
    t_k, kf = _best(lambda: arma_kalman(y, params, measurement_noise=h, method="steady-state",
                                        demean=False), repeat)
    model = SARIMAX(y, order=(2, 0, 1), trend="n", measurement_error=True)
    t_s, ref = _best(lambda: model.smooth([ar[0], ar[1], ma[0], h, s2]), 1)
    diff = float(np.max(np.abs(np.asarray(kf.smoothed) - ref.smoothed_state[0])))
    rows.append((f"Kalman filter+smoother ARMA(2,1), n = {n_kf:,}",
                 f"{t_k:.3f} s (steady-state, transient {kf.n_transient})",
                 f"SARIMAX.smooth {t_s:.2f} s (max abs diff {diff:.1e})", f"{t_s / t_k:.1f}x"))

    # ---- thermal fit
    import statsmodels.api as sm

    from fogts.simulate_startup import simulate_startup
    from fogts.thermal import design_matrix, fit_thermal, temperature_rate

    sim = simulate_startup(rng=4)
    temp = sim.run.temperature
    assert temp is not None
    t_g, _ = _best(lambda: fit_thermal(sim.run.rate, temp, fs_hz=1.0), repeat)
    X = design_matrix(temp, temperature_rate(temp, fs_hz=1.0), ("T*dT", "T2", "T", "dT2", "dT", "1"))
    t_o, _ = _best(lambda: sm.OLS(sim.run.rate, X).fit(), repeat)
    rows.append(("thermal fit, 1 h at 1 Hz", f"{t_g * 1e3:.1f} ms (GLS, AR(4) errors)",
                 f"OLS {t_o * 1e3:.2f} ms", f"{t_o / t_g:.2f}x"))

    lines = ["| task | fogts | peer | peer time / fogts time |", "|---|---|---|---|"]
    lines += [f"| {a} | {b} | {c} | {d} |" for a, b, c, d in rows]
    text = "\n".join(lines)
    print(text)
    if not args.quick:
        out = Path(__file__).resolve().parent / "results" / "emd_kalman.md"
        out.parent.mkdir(parents=True, exist_ok=True)
        out.write_text("# EMD / Kalman / thermal benchmark\n\n" + text + "\n")


if __name__ == "__main__":
    main()
