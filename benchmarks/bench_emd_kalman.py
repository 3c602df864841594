"""Benchmark the start-up tools: EMD, the steady-state Kalman filter and the thermal fit.

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

Run ``python -m benchmarks.bench_emd_kalman`` (or ``--quick`` for a smoke run); the table is
written to ``benchmarks/results/emd_kalman.md``.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path
from typing import Any

import numpy as np
from scipy.signal import lfilter

from benchmarks.metric import Metric, speed_metric
from benchmarks.render import render_markdown
from benchmarks.timing import LoadProbe, measure, speed_from, timed_once


def _slug_id(task: str, quick: bool) -> str:
    import re

    return "speed.emd_kalman." + re.sub(r"[^a-z0-9]+", "_", task.lower()).strip("_") + (
        ".quick" if quick else "")


def metrics(quick: bool) -> list[Metric]:
    """EMD, Kalman and thermal-fit speed figures (the runner's entry point)."""
    n_emd = 20_000 if quick else 100_000
    n_kf = 20_000 if quick else 1_000_000
    repeat = 1 if quick else 3
    out: list[Metric] = []

    # ---- EMD
    from fogts.startup.emd import emd, separate_trend

    rng = np.random.default_rng(4)
    t = np.arange(n_emd, dtype=float)
    x = 3.0 * (1 - np.exp(-t / (n_emd / 6))) + 0.5 * t / n_emd + 0.3 * lfilter(
        [1.0, 0.3], [1.0, -0.5], rng.standard_normal(n_emd))
    res = emd(x)
    split = separate_trend(x, fs_hz=1.0)
    try:
        from PyEMD import EMD as PyEMD  # Apache-2.0 peer
    except ImportError:
        print("PyEMD not installed: EMD figure skipped", file=sys.stderr)
    else:
        peer = PyEMD(spline_kind="cubic")
        n_rows = len(peer.emd(x))
        timing = measure({"fogts": lambda: emd(x), "peer": lambda: peer.emd(x)},
                                repeat=repeat)
        task = f"EMD, n = {n_emd:,}"
        out.append(speed_from(
            timing, _slug_id(task, quick), f"{task} (fogts: {res.n_imfs} IMFs, k = "
            f"{split.k}; PyEMD: {n_rows} rows)", peer="PyEMD"))

    # ---- Kalman
    from statsmodels.tsa.statespace.sarimax import SARIMAX

    from fogts.startup.kalman import arma_kalman

    ar, ma, s2, h = (1.2, -0.3), (0.4,), 0.04, 0.25
    drift = lfilter([1.0, ma[0]], [1.0, -ar[0], -ar[1]], rng.normal(0, np.sqrt(s2), n_kf))
    y = drift + rng.normal(0, np.sqrt(h), n_kf)
    params = {"ar.L1": ar[0], "ar.L2": ar[1], "ma.L1": ma[0], "sigma2": s2}

    def ours() -> Any:
        return arma_kalman(y, params, measurement_noise=h, method="steady-state", demean=False)

    model = SARIMAX(y, order=(2, 0, 1), trend="n", measurement_error=True)
    probe = LoadProbe()
    kf_t = measure({"fogts": ours}, repeat=repeat)
    t_s, c_s, ref = timed_once(lambda: model.smooth([ar[0], ar[1], ma[0], h, s2]))
    kf = ours()
    diff = float(np.max(np.abs(np.asarray(kf.smoothed) - ref.smoothed_state[0])))
    task = f"Kalman filter+smoother ARMA(2,1), n = {n_kf:,}"
    out.append(speed_metric(
        _slug_id(task, quick), f"{task} (fogts steady-state, transient {kf.n_transient}; "
        f"SARIMAX.smooth max abs diff {diff:.1e})", fogts_s=kf_t.wall["fogts"], peer_s=t_s,
        peer="SARIMAX.smooth", fogts_cpu_s=kf_t.cpu["fogts"], peer_cpu_s=c_s,
        other_load=probe.other_load(), noise={"rounds": 1}, details={"max_abs_diff": diff}))

    # ---- thermal fit
    import statsmodels.api as sm

    from fogts.startup import design_matrix, fit_thermal, temperature_rate
    from fogts.startup.simulator import simulate_startup

    sim = simulate_startup(rng=4)
    temp = sim.run.temperature
    assert temp is not None
    X = design_matrix(temp, temperature_rate(temp, fs_hz=1.0),
                      ("T*dT", "T2", "T", "dT2", "dT", "1"))
    timing = measure({"fogts": lambda: fit_thermal(sim.run.rate, temp, fs_hz=1.0),
                             "peer": lambda: sm.OLS(sim.run.rate, X).fit()},
                            repeat=max(repeat, 3), min_total_s=0.5 if quick else 2.0)
    task = "thermal fit, 1 h at 1 Hz"
    out.append(speed_from(timing, _slug_id(task, quick),
                                 f"{task} (fogts GLS with AR(4) errors; peer plain OLS)",
                                 peer="OLS"))
    return out


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=(__doc__ or "").splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="small sizes, one repeat")
    args = ap.parse_args(argv)
    text = render_markdown({"metrics": metrics(args.quick), "quick": args.quick})
    print(text)
    if not args.quick:
        out = Path(__file__).resolve().parent / "results" / "emd_kalman.md"
        out.parent.mkdir(parents=True, exist_ok=True)
        out.write_text("# EMD / Kalman / thermal benchmark\n\n" + text)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
