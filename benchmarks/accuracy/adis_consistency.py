"""Six ADIS16405 recordings: is the spread of each noise estimate across the runs consistent
with its reported standard errors?  WLS, GMWM and ML side by side (issue 15).

The data are the six static runs ``../shared/data/imu/adis_16405_imu{1..6}_gyro.npz`` of
the same sensor model (1e6 samples x 3 axes at 100 Hz, deg/s; ``../shared/data/README.md``),
read with ``units="deg/s"`` as the other ADIS16405 tests do.  Each axis of each run goes
through the default Allan analysis of ``fogts allan`` (:func:`fogts.pipeline.analyse_allan_axis`:
raw data, oadev at octave taus, 68.3 % intervals) with ``method`` ``"wls"`` (the default
fit), ``"gmwm"`` and ``"ml"`` (the record itself, decimated to block means by
``decimate="auto"``: at most 4096 blocks, 245 samples each here; :mod:`fogts.allan.ml`).

For each axis, term (N, B, K) and method, with :math:`x_i` and :math:`s_i` the estimate and
standard error of run :math:`i` over the runs where the term is measured,

.. math::

    \\bar x_w = \\frac{\\sum x_i / s_i^2}{\\sum 1 / s_i^2}, \\qquad
    \\chi^2 = \\sum_i \\frac{(x_i - \\bar x_w)^2}{s_i^2}

on ``k - 1`` degrees of freedom (5 when all six runs measure the term), with the p-value
``P(chi2_{k-1} > chi2)`` (scipy.stats.chi2; the standard test of the homogeneity of
independent estimates, e.g. Cochran 1954, *Biometrics* 10(1), 101-129, the Q statistic).
A term a run reports only as an upper limit (fitted at zero, dropped, or z < 2:
:attr:`fogts.allan.noise_model.NoiseTerm.is_limit`) is listed as such and left out.
``sqrt(chi2 / dof)`` is the factor by which the standard errors would have to grow for
the spread to be typical (the Birge ratio).

Run: ``python -m benchmarks.accuracy.adis_consistency [--methods wls,gmwm,ml] [--axes X,Y,Z]
[--runs 1,2,3,4,5,6] [--workers 2]``; prints the markdown tables kept in tests/README.md.
The CI test ``tests/test_adis_consistency.py`` reruns one axis with WLS and GMWM.
"""

from __future__ import annotations

import argparse
import math
import os
import time
import warnings
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
from scipy.stats import chi2 as chi2_dist

from benchmarks.accuracy.roundtrip import run_jobs

ROOT = Path(__file__).resolve().parents[2]
#: ``../shared/data`` beside the repository (``FOGTS_SHARED_DATA`` overrides, as in tests).
SHARED_DATA = Path(os.environ.get("FOGTS_SHARED_DATA", ROOT.parent / "shared" / "data"))
RUNS = (1, 2, 3, 4, 5, 6)
AXES = ("X", "Y", "Z")
METHODS = ("wls", "gmwm", "ml")
TERMS = ("N", "B", "K")
LABEL = {"wls": "WLS", "gmwm": "GMWM", "ml": "ML"}


def adis_path(run: int) -> Path:
    """The ``.npz`` file of ADIS16405 run ``run`` (1..6) under ``../shared/data/imu``."""
    return SHARED_DATA / "imu" / f"adis_16405_imu{run}_gyro.npz"


@dataclass(frozen=True)
class Consistency:
    """The chi-square test of k independent estimates of one quantity.

    Attributes
    ----------
    k : int
        Number of estimates used (measured values with a finite, positive standard error).
    mean, mean_se : float
        Inverse-variance weighted mean and its standard error ``(sum 1/s_i^2)^-1/2``.
    chi2 : float
        ``sum (x_i - mean)^2 / s_i^2``.
    dof : int
        ``k - 1``.
    p_value : float
        ``P(chi2_dof > chi2)``; NaN when ``k < 2``.
    """

    k: int
    mean: float
    mean_se: float
    chi2: float
    dof: int
    p_value: float

    @property
    def birge(self) -> float:
        """``sqrt(chi2 / dof)``: the factor the standard errors would need for the spread."""
        return math.sqrt(self.chi2 / self.dof) if self.dof > 0 else math.nan


def consistency(values: Sequence[float], stderrs: Sequence[float]) -> Consistency:
    """The chi-square consistency of independent estimates ``values`` with standard errors
    ``stderrs`` (module docstring; entries with a non-finite or non-positive standard
    error are left out)."""
    x = np.asarray(values, dtype=np.float64)
    s = np.asarray(stderrs, dtype=np.float64)
    keep = np.isfinite(x) & np.isfinite(s) & (s > 0)
    x, s = x[keep], s[keep]
    if x.size == 0:
        return Consistency(0, math.nan, math.nan, math.nan, 0, math.nan)
    w = 1.0 / s**2
    mean = float(np.sum(w * x) / np.sum(w))
    stat = float(np.sum(w * (x - mean) ** 2))
    dof = int(x.size - 1)
    p = float(chi2_dist.sf(stat, dof)) if dof > 0 else math.nan
    return Consistency(int(x.size), mean, float(1.0 / math.sqrt(np.sum(w))), stat, dof, p)


def fit_run(run_no: int, axes: Sequence[str] = AXES,
            methods: Sequence[str] = METHODS) -> dict[str, Any]:
    """Read run ``run_no`` and fit each of ``axes`` (X, Y, Z) with each of ``methods``:
    ``{"run", "rows"}``, one row per axis, method and term (value, stderr, whether a
    limit, the 95 % upper limit, the analysis' wall time and the fitted model)."""
    from fogts.allan.noise_compare import model_label
    from fogts.io.reader import read_run
    from fogts.pipeline import AllanSettings, analyse_allan_axis

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # the reader's and the fits' warnings are not news
        run = read_run(adis_path(run_no), units="deg/s")
        rows: list[dict[str, Any]] = []
        for name in axes:
            i = AXES.index(name)
            for method in methods:
                t0 = time.perf_counter()
                model = analyse_allan_axis(run, i, AllanSettings(method=method)).model
                seconds = time.perf_counter() - t0
                assert model is not None
                for t in TERMS:
                    term = model[t]
                    rows.append({"run": run_no, "axis": name, "method": method, "term": t,
                                 "value": float(term.value), "stderr": float(term.stderr),
                                 "limit": bool(term.is_limit),
                                 "upper": float(model.upper_limit(t)) if term.is_limit
                                 else math.nan, "seconds": seconds,
                                 "model": model_label(model)})
    return {"run": run_no, "rows": rows}


def study(runs: Sequence[int] = RUNS, axes: Sequence[str] = AXES,
          methods: Sequence[str] = METHODS, workers: int | None = 1) -> list[dict[str, Any]]:
    """Every row of :func:`fit_run` for ``runs`` (one process per run when ``workers > 1``)."""
    jobs = [(r, tuple(axes), tuple(methods)) for r in runs]
    return [row for done in run_jobs(fit_run, jobs, workers) for row in done["rows"]]


def summarise(rows: Sequence[dict[str, Any]]) -> dict[tuple[str, str, str], Consistency]:
    """:func:`consistency` per (axis, term, method) over the runs that measure the term."""
    out: dict[tuple[str, str, str], Consistency] = {}
    keys = dict.fromkeys((r["axis"], r["term"], r["method"]) for r in rows)
    for key in keys:
        sel = [r for r in rows if (r["axis"], r["term"], r["method"]) == key and not r["limit"]]
        out[key] = consistency([r["value"] for r in sel], [r["stderr"] for r in sel])
    return out


def _axes_terms_methods(rows: Sequence[dict[str, Any]]
                        ) -> tuple[list[str], list[str], list[str], list[int]]:
    def order(field: str, ref: Sequence[Any]) -> list[Any]:
        seen = {r[field] for r in rows}
        return [v for v in ref if v in seen]

    return (order("axis", AXES), order("term", TERMS), order("method", METHODS),
            order("run", RUNS))


def _verdict(c: Consistency) -> str:
    if c.dof < 1:
        return "–"
    return f"{c.chi2:.3g} ({c.dof}) / {c.p_value:.2g}"


def markdown(rows: Sequence[dict[str, Any]]) -> str:
    """The summary table (weighted mean, chi2 (dof) / p and the Birge ratio per method, side
    by side), then every run's estimate, then the fit times."""
    axes, terms, methods, runs = _axes_terms_methods(rows)
    summary = summarise(rows)
    names = [LABEL[m] for m in methods]
    head = ["axis", "term"]
    for n in names:
        head += [f"{n} mean ± se (k)", f"{n} χ² (dof) / p", f"{n} √(χ²/dof)"]
    lines = ["| " + " | ".join(head) + " |", "|---|---|" + "---:|" * (len(head) - 2)]
    for a in axes:
        for t in terms:
            cells = [a, t]
            for m in methods:
                c = summary[(a, t, m)]
                cells += [f"{c.mean:.4g} ± {c.mean_se:.2g} ({c.k})" if c.k else "all limits",
                          _verdict(c), f"{c.birge:.2g}" if c.dof else "–"]
            lines.append("| " + " | ".join(cells) + " |")
    lines += ["", "| axis | term | method | " + " | ".join(f"run {r}" for r in runs) + " |",
              "|---|---|---|" + "---:|" * len(runs)]
    for a in axes:
        for t in terms:
            for m in methods:
                cells = []
                for r in runs:
                    hit = [x for x in rows if (x["run"], x["axis"], x["term"], x["method"])
                           == (r, a, t, m)]
                    cells.append(_cell(hit[0]) if hit else "")
                lines.append(f"| {a} | {t} | {LABEL[m]} | " + " | ".join(cells) + " |")
    lines += ["", "| method | analysis time per axis (s; Allan curve + fit): median / max "
              "| models chosen |", "|---|---:|---|"]
    for m in methods:
        fits = {(r["run"], r["axis"]): (r["seconds"], r["model"]) for r in rows
                if r["method"] == m}
        secs = [s for s, _ in fits.values()]
        models = sorted({mod for _, mod in fits.values()})
        counts = [f"{mod} ({sum(1 for _, x in fits.values() if x == mod)})" for mod in models]
        lines.append(f"| {LABEL[m]} | {np.median(secs):.2f} / {np.max(secs):.2f} | "
                     + ", ".join(counts) + " |")
    return "\n".join(lines) + "\n"


def _cell(row: dict[str, Any]) -> str:
    if row["limit"]:
        return f"< {row['upper']:.3g}"
    se = row["stderr"]
    usable = math.isfinite(se) and se > 0
    return f"{row['value']:.4g} ± {se:.2g}" + ("" if usable else " (left out)")


def _names(text: str, allowed: Sequence[Any], what: str, cast: type = str) -> list[Any]:
    out = [cast(v.strip()) for v in text.split(",") if v.strip()]
    bad = [v for v in out if v not in allowed]
    if bad or not out:
        raise SystemExit(f"error: --{what} must be from {','.join(map(str, allowed))}, "
                         f"got {text!r}")
    return out


def main(argv: list[str] | None = None) -> int:
    p = argparse.ArgumentParser(description=(__doc__ or "").split("\n")[0])
    p.add_argument("--runs", default="1,2,3,4,5,6", help="runs (default 1,2,3,4,5,6)")
    p.add_argument("--axes", default="X,Y,Z", help="axes (default X,Y,Z)")
    p.add_argument("--methods", default="wls,gmwm,ml", help="methods (default wls,gmwm,ml)")
    p.add_argument("--workers", type=int, default=1, help="processes (default 1)")
    args = p.parse_args(argv)
    runs = _names(args.runs, RUNS, "runs", int)
    axes = _names(args.axes, AXES, "axes")
    methods = _names(args.methods, METHODS, "methods")
    missing = [str(adis_path(r)) for r in runs if not adis_path(r).exists()]
    if missing:
        raise SystemExit(f"error: reference data not found: {', '.join(missing)} (the "
                         "../shared/data folder is absent; set FOGTS_SHARED_DATA)")
    t0 = time.perf_counter()
    rows = study(runs, axes, methods, workers=args.workers)
    print(markdown(rows))
    print(f"({time.perf_counter() - t0:.0f} s of wall time, {args.workers} process(es))")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
