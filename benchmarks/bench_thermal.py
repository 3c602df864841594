"""Thermal coefficient recovery: simulate cold starts with known coefficients, fit, compare.

``fogts.startup.simulator.simulate_startup`` makes a 1 h, 1 Hz cold start (temperature rising
to steady state with its rate peaking near 0.05 degC/s, a drift following the thermal model
D = a·T·ΔT + b·T² + c·T + d·ΔT² + e·ΔT + f with the default coefficients, AR(1) drift noise
and white noise).  ``fogts.startup.thermal_fit.fit_thermal`` (GLS with AR(4) errors) fits the model back.
Per coefficient, over the seeds:

* the median |est - true| in units of the fit's standard error (about 0.67 for an honest
  fit with honest errors);
* how often the truth lies within 2 standard errors (ideal 95.4 %);

and, over all seeds, the median RMS error of the recovered drift curve D(T, ΔT) against the
true drift (relative to the drift's standard deviation) and the median bias-stability
improvement (before / after compensation, 10 s averages).  T, T² and T·ΔT are strongly
collinear over a warm-up, so single coefficients carry large standard errors (their relative
errors are often several times the value); the drift curve itself is what is recovered well.

Run: ``python -m benchmarks.bench_thermal [--quick]`` (quick: 10 seeds, full: 100).
"""

from __future__ import annotations

import argparse
import warnings

import numpy as np

from benchmarks.metric import Metric, accuracy_metric
from benchmarks.render import render_markdown

FIRST_SEED = 500


def study(seeds: int) -> dict[str, dict[str, float]]:
    """Per coefficient: median |error|/SE and 2-SE coverage; drift-curve error; improvement."""
    from fogts.startup import bias_stability, compensate, fit_thermal
    from fogts.startup.simulator import simulate_startup

    z: dict[str, list[float]] = {}
    curve: list[float] = []
    improvement: list[float] = []
    for seed in range(FIRST_SEED, FIRST_SEED + seeds):
        sim = simulate_startup(rng=seed)
        run = sim.run
        assert run.temperature is not None
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            model = fit_thermal(run.rate, run.temperature, fs_hz=run.fs_hz, units=run.units)
        for term, true in sim.coefficients.items():
            if term in model.coefficients:
                se = model.stderr[term]
                z.setdefault(term, []).append(abs(model.coefficients[term] - true) / se)
        fitted = model.predict(run.temperature, fs_hz=run.fs_hz)
        curve.append(float(np.sqrt(np.mean((fitted - sim.drift) ** 2)) / np.std(sim.drift)))
        before = bias_stability(run.rate, fs_hz=run.fs_hz, units=run.units).value
        after = bias_stability(compensate(run, model).rate, fs_hz=run.fs_hz,
                               units=run.units).value
        improvement.append(before / after)
    out = {t: {"median_z": float(np.median(v)),
               "coverage_2se": float(np.mean(np.array(v) <= 2))} for t, v in z.items()}
    out["_improvement"] = {"median": float(np.median(improvement))}
    out["_curve"] = {"median": float(np.median(curve))}
    return out


def metrics(quick: bool) -> list[Metric]:
    """Measure and return the figures (the runner's entry point)."""
    seeds = 10 if quick else 100
    res = study(seeds)
    tag = f"seeds={seeds}"
    out: list[Metric] = []
    for term, s in res.items():
        if term.startswith("_"):
            continue
        out.append(accuracy_metric(
            f"accuracy.thermal.{term}.z.{tag}", f"thermal {term}: median |error| / std. error "
            f"({seeds} cold starts)", value=s["median_z"], better="lower", unit="SE",
            abs_tolerance=0.1))
        out.append(accuracy_metric(
            f"accuracy.thermal.{term}.coverage.{tag}", f"thermal {term}: share of seeds within "
            "2 std. errors", value=s["coverage_2se"], better="higher", abs_tolerance=0.05))
    out.append(accuracy_metric(
        f"accuracy.thermal.drift_curve.{tag}", f"thermal drift curve D(T, dT): median RMS error "
        f"/ std of the true drift ({seeds} cold starts)", value=res["_curve"]["median"],
        better="lower", unit="rel", abs_tolerance=0.01))
    out.append(accuracy_metric(
        f"accuracy.thermal.improvement.{tag}", f"bias stability before / after thermal "
        f"compensation, median of {seeds} cold starts", value=res["_improvement"]["median"],
        better="higher", unit="x"))
    return out


def main(argv: list[str] | None = None) -> int:
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--quick", action="store_true", help="10 seeds instead of 100")
    args = p.parse_args(argv)
    print(render_markdown({"metrics": metrics(args.quick), "quick": args.quick}))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
