"""Accuracy reports on simulated data with known truth (``benchmarks/accuracy``).

* :mod:`benchmarks.accuracy.roundtrip`: noise coefficients -> ``simulate_gyro`` ->
  ``allan_deviation`` -> ``fit_noise`` -> coefficients, by sensor grade.

``metrics(quick)`` is the entry point of the benchmark runner (``python -m benchmarks``).
"""

from __future__ import annotations

from benchmarks.metric import Metric


def metrics(quick: bool = False) -> list[Metric]:
    from benchmarks.accuracy.roundtrip import metrics as roundtrip

    return roundtrip(quick)
