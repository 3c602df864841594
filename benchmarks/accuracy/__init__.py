"""Accuracy reports on simulated data with known truth (``benchmarks/accuracy``).

* :mod:`benchmarks.accuracy.roundtrip`: noise coefficients -> ``simulate_gyro`` ->
  ``allan_deviation`` -> ``fit_noise`` -> coefficients, by sensor grade.
* :mod:`benchmarks.accuracy.gauss_markov`: interval coverage when bias instability is a
  Gauss–Markov sum (an independent simulator in the test code), not ideal flicker.
* :mod:`benchmarks.accuracy.gmwm`, :mod:`benchmarks.accuracy.ml`: the GMWM and ML fits
  beside WLS on the same records.
* :mod:`benchmarks.accuracy.adis_consistency`: six real ADIS16405 recordings, the spread of
  each term across them against its standard errors (chi-square), WLS, GMWM and ML.

``metrics(quick)`` is the entry point of the benchmark runner (``python -m benchmarks``).
"""

from __future__ import annotations

from benchmarks.metric import Metric


def metrics(quick: bool = False) -> list[Metric]:
    from benchmarks.accuracy.gauss_markov import metrics as gauss_markov
    from benchmarks.accuracy.roundtrip import metrics as roundtrip

    return roundtrip(quick) + gauss_markov(quick)
