"""ARMA candidate selection on long records: fogts against statsmodels (and R), in one run.

Data, demeaned and divided by its standard deviation (the "standardised series" every
contender gets); the five candidates are AR(1), AR(2), AR(3), ARMA(1,1) and ARMA(2,1):

* ``identified``: x_t = 1.2 x_{t-1} - 0.5 x_{t-2} + a_t + 0.4 a_{t-1} (seed 2024);
* ``nearly white`` (full run only): a FOG drift model fitted to a 10 Hz, 3 h record,
  x_t = -0.2699 x_{t-1} - 0.002968 x_{t-2} + a_t + 0.277 a_{t-1}, whose AR root nearly
  cancels the MA root - the hard case: ARMA(1,1) and ARMA(2,1) are nearly redundant and their
  likelihoods have several maxima (fogts then tries extra starts).

Speed figures (ratio = peer seconds / fogts seconds, > 1 means fogts is faster):

* ``fogts.arma.select.select_arma`` (five exact-ML fits + all residual diagnostics) and the
  five ``fogts.arma.fit.fit_arma`` fits alone, against statsmodels'
  ``ARIMA(x, order=(p,0,q), trend="n").fit()`` in a loop over the five candidates
  (n = 1e6; quick: 2e4);
* if R is installed (``Rscript`` with the Debian packages r-base-core and r-cran-forecast):
  against R's ``arima(y, order, include.mean=FALSE, method="ML")`` over the five candidates
  and against ``forecast::auto.arima(y, d=0, max.p=3, max.q=1, stepwise=FALSE,
  allowmean=FALSE, approximation=FALSE)``; R's time is its own ``system.time`` (elapsed,
  and user + system for the CPU-time ratio);
* at n = 1e7 (full run only): the time of ``select_arma`` and its peak extra memory
  (tracemalloc, numpy arrays included) as a multiple of the input; there is no peer (the
  statsmodels loop is too slow at that size);
* the typical gyro record at n = 1e8 (full run only): white noise (sd 0.1) plus a rate
  random walk (increments 1e-4, seed 900107) through ``select_arma``, once, under
  tracemalloc: its wall and CPU time, its peak extra memory and whether all five candidates
  were fitted (no peer: 800 MB of input);
* the same record end to end (full run only): the whole ``fogts select`` command on it as a
  ``.npy``, in a fresh interpreter: wall and CPU time and peak RSS as a multiple of the
  input (:mod:`benchmarks.arma_cli`).

Accuracy figures, from the same fits: the largest |parameter difference| to statsmodels
(acceptance: 1e-4, compared where both reach the same optimum), the largest AIC excess of
fogts over statsmodels and over R (acceptance: <= 0.05; negative means fogts found a higher
likelihood), whether the AIC ranking is the same as statsmodels' (1 = yes) and whether it is
the ranking by the best likelihood either tool found.  On the nearly white series statsmodels
stops early on the flat ridge of the nearly redundant ARMA(1,1)/ARMA(2,1) (its gradient there
is far from zero; Newton from its point climbs to fogts' optimum), so its ranking can differ;
the per-candidate AIC differences are printed under the table.

The statsmodels loop takes minutes, so it runs once; fogts runs before and after it and the
best wall and CPU time are kept (the machine is shared; the load average is printed with
the table).

Run: ``python -m benchmarks.bench_arma [--quick]``; a full run writes
``benchmarks/results/arma.md``.
"""

from __future__ import annotations

import argparse
import gc
import shutil
import subprocess
import sys
import tempfile
import tracemalloc
import warnings
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from benchmarks.arma_cli import cli_metrics
from benchmarks.metric import Metric, accuracy_metric, speed_metric
from benchmarks.render import measured_markdown, write_table
from benchmarks.timing import LoadProbe, timed_once

RESULTS = Path(__file__).resolve().parent / "results" / "arma.md"
R_SCRIPT = Path(__file__).resolve().parent / "r_arima.R"
CANDIDATES = [(1, 0), (2, 0), (3, 0), (1, 1), (2, 1)]
NAMES = ["AR(1)", "AR(2)", "AR(3)", "ARMA(1,1)", "ARMA(2,1)"]
SEED = 2024
QUICK_N = 20_000
NOTES: list[str] = []   # per-candidate AIC differences, printed under the table
WHAT = "5 candidates + diagnostics (select_arma)"


DATASETS = {
    "identified": ([1.0, 0.4], [1.0, -1.2, 0.5]),
    "nearly white": ([1.0, 0.277], [1.0, 0.2699, 0.002968]),
}


def series(n: int, seed: int = SEED, kind: str = "identified") -> np.ndarray:
    """A standardised ARMA(2,1) test series (see DATASETS)."""
    from scipy.signal import lfilter

    b, a = DATASETS[kind]
    e = np.random.default_rng(seed).standard_normal(n + 1000)
    x = lfilter(b, a, e)[1000:]
    x -= x.mean()
    x /= x.std()
    return np.ascontiguousarray(x)


def _select(x: np.ndarray) -> Any:
    """fogts' whole selection: five exact-ML fits and every diagnostic."""
    from fogts.arma.select import select_arma

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return select_arma(x)


def _fogts_fits(x: np.ndarray) -> list[Any]:
    from fogts.arma.fit import fit_arma

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return [fit_arma(x, p, q) for p, q in CANDIDATES]


def _statsmodels_fits(x: np.ndarray) -> list[Any]:
    from statsmodels.tsa.arima.model import ARIMA

    out = []
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        for p, q in CANDIDATES:
            out.append(ARIMA(x, order=(p, 0, q), trend="n").fit())
    return out


def _timed(fn: Any, *args: Any) -> tuple[float, float, Any]:
    """``(wall, cpu, result)`` of one call (after a garbage collection)."""
    gc.collect()
    return timed_once(lambda: fn(*args))


def _run_r(x: np.ndarray, auto: bool) -> dict[str, Any] | None:
    """R's arima(method="ML") over the five candidates (and auto.arima); None without R."""
    rscript = shutil.which("Rscript")
    if rscript is None:
        return None
    with tempfile.TemporaryDirectory() as tmp:
        path = Path(tmp) / "y.f64"
        x.astype("<f8").tofile(path)
        cmd = [rscript, str(R_SCRIPT), str(path), str(x.size)] + (["auto"] if auto else [])
        res = subprocess.run(cmd, capture_output=True, text=True, check=False, timeout=7200)
    if res.returncode != 0:
        print(f"R failed: {res.stderr.strip()[-500:]}", file=sys.stderr)
        return None
    out: dict[str, Any] = {"fits": {}}
    for line in res.stdout.splitlines():
        tok = line.split()
        if not tok:
            continue
        if tok[0] == "fit":
            p, q = int(tok[1]), int(tok[2])
            out["fits"][(p, q)] = {"seconds": float(tok[3]), "llf": float(tok[4]),
                                   "aic": float(tok[5]), "coef": [float(v) for v in tok[6:]]}
        elif tok[0] == "total_arima":
            out["arima_seconds"] = float(tok[1])
        elif tok[0] == "cpu_total_arima":
            out["arima_cpu_seconds"] = float(tok[1])
        elif tok[0] == "auto_cpu":
            out["auto_cpu_seconds"] = float(tok[1])
        elif tok[0] == "auto":
            out["auto"] = {"seconds": float(tok[1]), "p": int(tok[2]), "q": int(tok[3]),
                           "aic": float(tok[4])}
    return out


def _label(n: int) -> str:
    return f"n=1e{round(np.log10(n))}" if n == 10 ** round(np.log10(n)) else f"n={n}"


@dataclass
class _Run:
    """fogts (timed before and after the peer, best kept) against the statsmodels loop."""

    select_s: float
    select_cpu_s: float
    fits_s: float
    fits_cpu_s: float
    statsmodels_s: float
    statsmodels_cpu_s: float
    other_load: float | None
    selection: Any
    fits: list[Any]
    statsmodels: list[Any]
    n: int

    @property
    def timing(self) -> dict[str, Any]:
        """The :func:`speed_metric` keywords every figure of this run shares: parallel
        where the fits' long passes may use the worker thread (:mod:`fogts.arma.worker`)."""
        from fogts.arma.worker import THREAD_MIN

        return {"other_load": self.other_load, "noise": {"rounds": 1},
                "parallel": self.n >= THREAD_MIN}


def _run_against_statsmodels(x: np.ndarray, lab: str) -> _Run:
    """Time ``select_arma``, the five fits and the statsmodels loop (once: it takes minutes)."""
    _select(x[:5000])                                    # warms imports and caches
    _fogts_fits(x[:5000])
    probe = LoadProbe()
    t_sel1, c_sel1, sel = _timed(_select, x)
    t_fit1, c_fit1, fits = _timed(_fogts_fits, x)
    print(f"  fogts at {lab}: select {t_sel1:.2f} s, five fits {t_fit1:.2f} s; "
          "statsmodels loop running ...", file=sys.stderr)
    t_sm, c_sm, sm = _timed(_statsmodels_fits, x)
    t_sel2, c_sel2, _ = _timed(_select, x)
    t_fit2, c_fit2, _ = _timed(_fogts_fits, x)
    return _Run(select_s=min(t_sel1, t_sel2), select_cpu_s=min(c_sel1, c_sel2),
                fits_s=min(t_fit1, t_fit2), fits_cpu_s=min(c_fit1, c_fit2),
                statsmodels_s=t_sm, statsmodels_cpu_s=c_sm, other_load=probe.other_load(),
                selection=sel, fits=fits, statsmodels=sm, n=int(x.size))


def _speed_vs_statsmodels(run: _Run, lab: str, key: str) -> list[Metric]:
    per_candidate = {name: round(float(r.mle_retvals.get("iterations", -1)), 0)
                     for name, r in zip(NAMES, run.statsmodels, strict=True)}
    return [
        speed_metric(
            f"speed.arma.select_vs_statsmodels.{key}",
            f"ARMA selection, {lab}: {WHAT} vs the ARIMA(...).fit() loop",
            fogts_s=run.select_s, peer_s=run.statsmodels_s, peer="statsmodels",
            fogts_cpu_s=run.select_cpu_s, peer_cpu_s=run.statsmodels_cpu_s, **run.timing),
        speed_metric(
            f"speed.arma.fits_vs_statsmodels.{key}",
            f"ARMA exact ML, {lab}: 5 fit_arma fits vs the ARIMA(...).fit() loop",
            fogts_s=run.fits_s, peer_s=run.statsmodels_s, peer="statsmodels",
            fogts_cpu_s=run.fits_cpu_s, peer_cpu_s=run.statsmodels_cpu_s,
            details={"statsmodels_iterations": per_candidate}, **run.timing),
    ]


def _accuracy_vs_statsmodels(run: _Run, n: int, lab: str, key: str) -> list[Metric]:
    """Parameter and AIC differences, and the rankings (AIC on the standardised series)."""
    dpar, excess = 0.0, -np.inf
    for f, r in zip(run.fits, run.statsmodels, strict=True):
        aic_f = f.aic - 2 * n * np.log(f.scale)
        excess = max(excess, aic_f - r.aic)
        if abs(aic_f - r.aic) < 2e-3:                    # the same optimum
            dpar = max(dpar, float(np.max(np.abs(np.r_[f.ar, f.ma] - r.params[:-1]))))
    aic_f = [f.aic - 2 * n * np.log(f.scale) for f in run.fits]
    aic_s = [float(r.aic) for r in run.statsmodels]
    rank_f = [NAMES[i] for i in np.argsort(aic_f)]
    rank_s = [NAMES[i] for i in np.argsort(aic_s)]
    rank_best = [NAMES[i] for i in np.argsort(np.minimum(aic_f, aic_s))]
    NOTES.append(f"{lab}: AIC(fogts) - AIC(statsmodels) per candidate: "
                 + ", ".join(f"{nm} {a - b:+.3g}" for nm, a, b in
                             zip(NAMES, aic_f, aic_s, strict=True))
                 + f"; ranking fogts {' < '.join(rank_f)}; statsmodels {' < '.join(rank_s)}.")
    return [
        accuracy_metric(
            f"accuracy.arma.param_diff_vs_statsmodels.{key}",
            f"ARMA {lab}: largest |parameter difference| to statsmodels (acceptance 1e-4)",
            value=dpar, better="lower", abs_tolerance=1e-5),
        accuracy_metric(
            f"accuracy.arma.aic_excess_vs_statsmodels.{key}",
            f"ARMA {lab}: largest AIC excess of fogts over statsmodels (acceptance <= 0.05)",
            value=float(excess), better="lower", abs_tolerance=0.01),
        accuracy_metric(
            f"accuracy.arma.same_ranking_as_statsmodels.{key}",
            f"ARMA {lab}: same AIC ranking as statsmodels (1 = yes)",
            value=float(rank_f == rank_s), better="higher",
            details={"fogts": rank_f, "statsmodels": rank_s}),
        accuracy_metric(
            f"accuracy.arma.ranking_by_best_llf.{key}",
            f"ARMA {lab}: fogts' ranking equals the ranking by the best likelihood either tool "
            "found (1 = yes)",
            value=float(rank_f == rank_best), better="higher", details={"best": rank_best}),
    ]


def _against_r(x: np.ndarray, run: _Run, n: int, lab: str, key: str) -> list[Metric]:
    """Speed against R's arima loop and auto.arima, and the AIC and parameter differences."""
    r = _run_r(x, auto=True)
    if r is None:
        print("  R not found (Rscript): R figures skipped", file=sys.stderr)
        return []
    out = [speed_metric(
        f"speed.arma.select_vs_r_arima.{key}",
        f"ARMA selection, {lab}: {WHAT} vs R arima(method=\"ML\") over the 5 candidates",
        fogts_s=run.select_s, peer_s=r["arima_seconds"], peer="R arima",
        fogts_cpu_s=run.select_cpu_s, peer_cpu_s=r.get("arima_cpu_seconds"), **run.timing)]
    if "auto" in r:
        auto = r["auto"]
        out.append(speed_metric(
            f"speed.arma.select_vs_auto_arima.{key}",
            f"ARMA selection, {lab}: {WHAT} vs forecast::auto.arima(max.p=3, max.q=1, "
            "stepwise=FALSE, approximation=FALSE)",
            fogts_s=run.select_s, peer_s=auto["seconds"], peer="auto.arima",
            fogts_cpu_s=run.select_cpu_s, peer_cpu_s=r.get("auto_cpu_seconds"),
            details={"auto_arima_choice": f"ARMA({auto['p']},{auto['q']})"}, **run.timing))
    excess_r = max(f.aic - 2 * n * np.log(f.scale) - r["fits"][(f.p, f.q)]["aic"]
                   for f in run.fits)
    dpar_r = max(float(np.max(np.abs(np.r_[f.ar, f.ma] - r["fits"][(f.p, f.q)]["coef"])))
                 for f in run.fits)
    out.append(accuracy_metric(
        f"accuracy.arma.aic_excess_vs_r.{key}",
        f"ARMA {lab}: largest AIC excess of fogts over R arima(method=\"ML\") (acceptance <= 0.05)",
        value=float(excess_r), better="lower", abs_tolerance=0.01))
    out.append(accuracy_metric(
        f"accuracy.arma.param_diff_vs_r.{key}",
        f"ARMA {lab}: largest |parameter difference| to R arima(method=\"ML\")",
        value=dpar_r, better="lower", abs_tolerance=1e-4))
    print(f"  fogts selects {run.selection.best.model}; R auto.arima selects "
          f"{r.get('auto', {}).get('p')},{r.get('auto', {}).get('q')}", file=sys.stderr)
    return out


def _comparison_metrics(n: int, kind: str = "identified",
                        with_r: bool = True) -> list[Metric]:
    """fogts against statsmodels (and R, if ``with_r`` and installed) on one series."""
    x = series(n, kind=kind)
    lab = _label(n) + ("" if kind == "identified" else ", " + kind)
    key = _label(n) + ("" if kind == "identified" else "." + kind.replace(" ", "_"))
    run = _run_against_statsmodels(x, lab)
    out = _speed_vs_statsmodels(run, lab, key) + _accuracy_vs_statsmodels(run, n, lab, key)
    return out + (_against_r(x, run, n, lab, key) if with_r else [])


def _huge_metrics(n: int) -> list[Metric]:
    """select_arma at n = 1e7: CPU time (best of 2) and peak extra memory (tracemalloc).

    There is no peer to take a ratio against, so the figure is the CPU time of this process
    (single-threaded BLAS: its work, which machine load barely changes); the wall time is
    in the details.
    """
    x = series(n)
    _select(x[:5000])                                    # warms imports and caches
    t1, c1, _ = _timed(_select, x)
    t2, c2, _ = _timed(_select, x)
    gc.collect()
    tracemalloc.start()
    _select(x)
    _, peak = tracemalloc.get_traced_memory()
    tracemalloc.stop()
    lab = _label(n)
    return [
        accuracy_metric(
            f"time.arma.select.{lab}", f"ARMA {lab}: select_arma CPU time (no peer)",
            value=min(c1, c2), better="lower", unit="s CPU", tolerance=0.5,
            details={"wall_s": min(t1, t2)}),
        accuracy_metric(
            f"memory.arma.select.{lab}", f"ARMA {lab}: select_arma peak extra memory",
            value=peak / x.nbytes, better="lower", unit="x input", tolerance=0.25),
    ]


def white_plus_random_walk(n: int, seed: int = 900107) -> np.ndarray:
    """White rate noise (sd 0.1) plus a rate random walk (increments 1e-4), in place."""
    r = np.random.default_rng(seed)
    x = r.standard_normal(n)      # the recipe 0.1*w + cumsum(1e-4*v), without temporaries
    x *= 0.1
    walk = r.standard_normal(n)
    walk *= 1e-4
    np.cumsum(walk, out=walk)
    x += walk
    return x


def _white_rw_metrics(n: int) -> list[Metric]:
    """select_arma once on white + rate random walk at n: time, peak memory, all five fitted.

    Run once under tracemalloc (a second pass would double an already long run); the CPU
    time is this process's (single-threaded BLAS), the wall time is in the details.
    """
    x = white_plus_random_walk(n)
    _select(x[:5000])                                    # warms imports and caches
    gc.collect()
    tracemalloc.start()
    wall, cpu, sel = _timed(_select, x)
    _, peak = tracemalloc.get_traced_memory()
    tracemalloc.stop()
    lab = _label(n)
    fitted = sum(c.ok for c in sel.candidates)
    NOTES.append(f"white + rate random walk, {lab}: selected {sel.best.model}; "
                 + ", ".join(f"{c.model} AIC {c.aic:.1f}" if c.ok else f"{c.model} failed"
                             for c in sel.candidates) + ".")
    return [
        accuracy_metric(
            f"time.arma.select_white_rw.{lab}",
            f"ARMA white + rate random walk {lab}: select_arma CPU time (no peer)",
            value=cpu, better="lower", unit="s CPU", tolerance=0.5, details={"wall_s": wall}),
        accuracy_metric(
            f"memory.arma.select_white_rw.{lab}",
            f"ARMA white + rate random walk {lab}: select_arma peak extra memory",
            value=peak / x.nbytes, better="lower", unit="x input", tolerance=0.25),
        accuracy_metric(
            f"accuracy.arma.white_rw_fitted.{lab}",
            f"ARMA white + rate random walk {lab}: candidates fitted (of 5)",
            value=float(fitted), better="higher", abs_tolerance=0.0),
    ]


def metrics(quick: bool) -> list[Metric]:
    """Measure and return the figures (the runner's entry point)."""
    out = _comparison_metrics(QUICK_N if quick else 1_000_000)
    if not quick:
        out += _comparison_metrics(1_000_000, kind="nearly white", with_r=False)
        out += _huge_metrics(10_000_000)
        out += _white_rw_metrics(100_000_000)
        out += cli_metrics(100_000_000, white_plus_random_walk, "n=1e8")
    return out


def main(argv: list[str] | None = None) -> int:
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--quick", action="store_true",
                   help="n = 2e4 against statsmodels (and R), no 1e7 run")
    p.add_argument("--out", type=Path, default=None,
                   help=f"write the markdown table here (default {RESULTS} for a full run)")
    args = p.parse_args(argv)
    text = measured_markdown(
        lambda: metrics(args.quick), quick=args.quick,
        how="fogts is timed before and after the peer, best kept")
    text += "".join(f"\n- {note}" for note in NOTES) + ("\n" if NOTES else "")
    r_version = _r_version()
    if r_version:
        text += f"R: {r_version}.\n"
    print(text)
    write_table(text, args.out if args.out is not None
                       else (None if args.quick else RESULTS))
    return 0


def _r_version() -> str | None:
    rscript = shutil.which("Rscript")
    if rscript is None:
        return None
    res = subprocess.run([rscript, "-e", "cat(R.version.string, ';forecast',"
                          " format(packageVersion('forecast')))"], capture_output=True,
                         text=True, check=False)
    return res.stdout.strip() or None


if __name__ == "__main__":
    raise SystemExit(main())
