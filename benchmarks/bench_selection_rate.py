"""ARMA selection hit rate: how often ``select_arma`` ranks the true model first.

Data: the five candidate orders (AR(1), AR(2), AR(3), ARMA(1,1), ARMA(2,1)) with clearly
identified coefficients, n = 10^4, 50 seeds each (``--quick``: 5), simulated with
``scipy.signal.lfilter`` after a 2000-sample burn-in.  Figures:

* ``fogts``: the true order is rank 1 of ``select_arma`` (AIC among candidates with white
  residuals, the full fogts rule), per model and overall; the rate on the first 20 seeds
  (the size of the unit test) is in the details;
* ``fogts, AIC only``: the same fits ranked by AIC alone (no whiteness gate), to show what
  the gate changes;
* peer: statsmodels' own ``ARIMA(order=(p,0,q), trend="n").fit()`` on the standardised series,
  lowest AIC, on the first 10 seeds (``--quick``: 1); its time against ``select_arma`` on the
  same series (ratio = statsmodels seconds / fogts seconds, fogts doing all the diagnostics
  too), and the largest AIC shortfall of fogts against it (must stay <= 0.05);
* a FOG drift model fitted to a 10 Hz, 3 h record,
  x_t = -0.2699 x_{t-1} - 0.002968 x_{t-2} + a_t + 0.277 a_{t-1}, whose AR and MA roots
  nearly cancel (108,000 samples, 10 seeds; ``--quick``: 2): how often the ARMA(2,1) fit is
  flagged for near-cancelling roots and how often a one-parameter model is selected;
* AR(1) data, phi = 0.6, n = 2000, 100 seeds (``--quick``: 5): how often ARMA(2,1) is
  selected by ``select_arma`` and by statsmodels' ``trend="c"`` AIC loop on the same series.

Run: ``python -m benchmarks.bench_selection_rate [--quick] [--seeds N] [--out FILE.md]``.
"""

from __future__ import annotations

import argparse
import math
import time
import warnings
from pathlib import Path
from typing import Any

import numpy as np

from benchmarks.metric import Metric, accuracy_metric, speed_metric
from benchmarks.render import render_markdown
from benchmarks.timing import LoadProbe

TRUE_MODELS: dict[str, tuple[list[float], list[float]]] = {
    "AR(1)": ([0.6], []),
    "AR(2)": ([0.5, 0.3], []),
    "AR(3)": ([0.5, -0.3, 0.2], []),
    "ARMA(1,1)": ([0.6], [0.4]),
    "ARMA(2,1)": ([0.5, 0.2], [0.5]),
}
#: A fitted FOG drift ARMA(2,1) whose AR and MA roots nearly cancel (AR, MA coefficients).
NEAR_CANCELLING = ([-0.2699, -0.002968], [0.277])
N = 10_000
N_NEAR_CANCELLING = 108_000
#: AR(1) over-selection study: series length and seeds (``--quick``: 5 seeds).
AR1_N = 2000
AR1_SEEDS = 100
SUITE = "selection_rate"


def simulate(ar: list[float], ma: list[float], n: int, seed: int, scale: float = 1.0
             ) -> np.ndarray:
    from scipy.signal import lfilter

    e = np.random.default_rng(seed).standard_normal(n + 2000) * scale
    return np.asarray(lfilter(np.r_[1.0, ma], np.r_[1.0, -np.asarray(ar)], e)[2000:])


def statsmodels_select(x: np.ndarray) -> dict[str, float]:
    """AIC of every candidate from statsmodels' own fit on x / std(x), in x's units."""
    from statsmodels.tsa.arima.model import ARIMA

    from fogts.arma.fit import model_name
    from fogts.arma.select import DEFAULT_FIVE

    s = float(np.std(x))
    out = {}
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        for p, q in DEFAULT_FIVE:
            res = ARIMA(x / s, order=(p, 0, q), trend="n").fit()
            out[model_name(p, q)] = float(res.aic) + 2.0 * x.size * math.log(s)
    return out


def _near_cancellation_metrics(n_drift: int) -> list[Metric]:
    """Over ``n_drift`` seeds of :data:`NEAR_CANCELLING`: how often its ARMA(2,1) fit is
    flagged for near-cancelling roots, and how often a one-parameter model is selected.

    (The metric ids and titles keep the names of the stored baseline.)
    """
    from fogts.arma import select_arma
    from fogts.errors import FogtsWarning

    flagged = low = 0
    chosen: list[str] = []
    for seed in range(n_drift):
        x = simulate(*NEAR_CANCELLING, N_NEAR_CANCELLING, seed, scale=1e-3)
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", FogtsWarning)
            sel = select_arma(x)
        flagged += bool(sel["ARMA(2,1)"].flagged("near_cancellation"))
        best = sel.best
        chosen.append(best.model if best is not None else "none")
        low += best is not None and best.p + best.q == 1
    return [
        accuracy_metric(
            f"accuracy.seed_paper_arma21.flagged.n=108000.seeds={n_drift}",
            "published FOG drift ARMA(2,1) (nearly cancelling roots): near-cancellation flagged on the ARMA(2,1) fit",
            value=flagged / n_drift, better="higher", unit="fraction", suite=SUITE,
            details={"selected": chosen}),
        accuracy_metric(
            f"accuracy.seed_paper_arma21.low_order.n=108000.seeds={n_drift}",
            f"published FOG drift ARMA(2,1) (nearly cancelling roots): a one-parameter model selected (selected: "
            f"{', '.join(chosen)})", value=low / n_drift, better="higher", unit="fraction",
            suite=SUITE, abs_tolerance=0.2, details={"selected": chosen}),
    ]

def _over_selection_metrics(n_seeds: int) -> list[Metric]:
    """AR(1) data (phi = 0.6, n = 2000, seeds 0..n_seeds-1): how often ARMA(2,1) is selected
    by ``select_arma`` and by statsmodels' ``ARIMA(order, trend="c").fit()`` AIC loop on the
    same series, and on how many seeds ``select_arma`` ranked an ARMA(2,1) with a lower AIC
    down (a possible common AR/MA factor, or an MA root on the unit circle)."""
    from statsmodels.tsa.arima.model import ARIMA

    from fogts.arma import select_arma
    from fogts.arma.select import DEFAULT_FIVE
    from fogts.arma.verdict import ranks_down

    fogts_picks: list[int] = []
    sm_picks: list[int] = []
    ranked_down: list[int] = []
    for seed in range(n_seeds):
        x = simulate([0.6], [], AR1_N, seed)
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            sel = select_arma(x)
            aics = {(p, q): float(ARIMA(x, order=(p, 0, q), trend="c").fit().aic)
                    for p, q in DEFAULT_FIVE}
        best = sel.best
        if best is not None and best.model == "ARMA(2,1)":
            fogts_picks.append(seed)
        if min(aics, key=aics.__getitem__) == (2, 1):
            sm_picks.append(seed)
        arma21 = sel["ARMA(2,1)"]
        if best is not None and ranks_down(arma21) and arma21.aic < best.aic:
            ranked_down.append(seed)
    details = {"fogts_seeds": fogts_picks, "statsmodels_seeds": sm_picks,
               "ranked_down_seeds": ranked_down}
    return [
        accuracy_metric(
            f"accuracy.ar1_over_selection.fogts.n=2000.seeds={n_seeds}",
            f"AR(1) phi = 0.6, n = 2000: ARMA(2,1) selected by select_arma (statsmodels' "
            f"trend=\"c\" AIC loop: {len(sm_picks)} of {n_seeds}; ranked down for a possible "
            f"common factor or an MA root on the unit circle: {len(ranked_down)})",
            value=len(fogts_picks) / n_seeds,
            better="lower", unit="fraction", suite=SUITE, abs_tolerance=0.05, details=details),
        accuracy_metric(
            f"accuracy.ar1_over_selection.statsmodels.n=2000.seeds={n_seeds}",
            "AR(1) phi = 0.6, n = 2000: ARMA(2,1) selected by statsmodels' trend=\"c\" AIC loop",
            value=len(sm_picks) / n_seeds, better="lower", unit="fraction", suite=SUITE,
            abs_tolerance=0.05, details=details),
    ]


def metrics(quick: bool, seeds: int | None = None) -> list[Metric]:
    from fogts.arma import select_arma
    from fogts.errors import FogtsWarning

    n_seeds = seeds if seeds is not None else (5 if quick else 50)
    n_peer = min(n_seeds, 1 if quick else 10)
    n_drift = 2 if quick else 10
    out: list[Metric] = []
    hits: dict[str, int] = {}
    hits20: dict[str, int] = {}
    hits_aic: dict[str, int] = {}
    hits_peer: dict[str, int] = {}
    t_fogts = t_peer = c_fogts = c_peer = 0.0
    probe = LoadProbe()
    shortfall = -math.inf
    nonconv = 0
    for name, (ar, ma) in TRUE_MODELS.items():
        hits[name] = hits20[name] = hits_aic[name] = hits_peer[name] = 0
        for seed in range(n_seeds):
            x = simulate(ar, ma, N, seed)
            x = x - x.mean()
            c0, t0 = time.process_time(), time.perf_counter()
            with warnings.catch_warnings():
                warnings.simplefilter("ignore", FogtsWarning)
                sel = select_arma(x)
            dt, dc = time.perf_counter() - t0, time.process_time() - c0
            best = sel.best
            ok = best is not None and best.model == name
            hits[name] += ok
            hits20[name] += ok and seed < 20
            fitted = [c for c in sel.candidates if c.ok]
            nonconv += sum(not c.converged for c in fitted)
            hits_aic[name] += min(fitted, key=lambda c: c.aic).model == name
            if seed < n_peer:
                c0, t0 = time.process_time(), time.perf_counter()
                aics = statsmodels_select(x)
                t_peer += time.perf_counter() - t0
                c_peer += time.process_time() - c0
                t_fogts += dt
                c_fogts += dc
                hits_peer[name] += min(aics, key=aics.__getitem__) == name
                shortfall = max(shortfall, *(c.aic - aics[c.model] for c in fitted))
        details: dict[str, Any] = {
            "seeds": n_seeds, "n": N, "true_ar": ar, "true_ma": ma,
            "rate_first_20_seeds": hits20[name] / min(20, n_seeds),
            "rate_aic_only": hits_aic[name] / n_seeds,
            f"rate_statsmodels_aic_{n_peer}_seeds": hits_peer[name] / n_peer}
        out.append(accuracy_metric(
            f"accuracy.selection_rate.{name}.n=1e4.seeds={n_seeds}",
            f"{name} ranked first by select_arma, n = 10^4, {n_seeds} seeds (AIC only: "
            f"{hits_aic[name] / n_seeds:.0%}; statsmodels AIC, {n_peer} seeds: "
            f"{hits_peer[name] / n_peer:.0%})",
            value=hits[name] / n_seeds, better="higher", unit="fraction", suite=SUITE,
            abs_tolerance=0.1, details=details))
    total = sum(hits.values()) / (n_seeds * len(TRUE_MODELS))
    out.append(accuracy_metric(
        f"accuracy.selection_rate.all.n=1e4.seeds={n_seeds}",
        f"all five models: true order ranked first ({n_seeds} seeds each; fits that did not "
        f"converge: {nonconv})", value=total, better="higher", unit="fraction", suite=SUITE,
        abs_tolerance=0.05,
        details={"aic_only": sum(hits_aic.values()) / (n_seeds * len(TRUE_MODELS)),
                 "statsmodels_aic": sum(hits_peer.values()) / (n_peer * len(TRUE_MODELS)),
                 "not_converged_fits": nonconv}))
    out.append(speed_metric(
        f"speed.select_arma.n=1e4.series={n_peer * len(TRUE_MODELS)}",
        f"select_arma (5 fits + all diagnostics) vs statsmodels ARIMA.fit loop, n = 10^4, "
        f"{n_peer * len(TRUE_MODELS)} series; max AIC shortfall of fogts {shortfall:+.2g}",
        fogts_s=t_fogts, peer_s=t_peer, peer="statsmodels ARIMA.fit", suite=SUITE,
        fogts_cpu_s=c_fogts, peer_cpu_s=c_peer, other_load=probe.other_load(),
        noise={"rounds": 1}, details={"max_aic_shortfall": shortfall}))
    out.append(accuracy_metric(
        f"accuracy.selection.aic_shortfall.n=1e4.series={n_peer * len(TRUE_MODELS)}",
        "largest AIC of a fogts fit minus statsmodels' (standardised series); <= 0.05 required",
        value=max(shortfall, 0.0), better="lower", unit="AIC units", suite=SUITE,
        abs_tolerance=0.05))
    return (out + _near_cancellation_metrics(n_drift)
            + _over_selection_metrics(5 if quick else AR1_SEEDS))


def main(argv: list[str] | None = None) -> int:
    p = argparse.ArgumentParser(description=(__doc__ or "").split("\n")[0])
    p.add_argument("--quick", action="store_true", help="5 seeds per model instead of 50")
    p.add_argument("--seeds", type=int, help="seeds per model (overrides --quick)")
    p.add_argument("--out", type=Path, help="also write the markdown table here")
    args = p.parse_args(argv)
    text = render_markdown({"metrics": metrics(args.quick, args.seeds), "quick": args.quick})
    print(text)
    if args.out:
        args.out.write_text(text)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
