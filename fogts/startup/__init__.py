"""The start-up drift domain: a FOG's output in its first minutes to hours after switch-on,
when the temperature settles.

EMD trend separation (:mod:`~fogts.startup.emd`), the Kalman filter built from a selected
ARMA model (:mod:`~fogts.startup.kalman`), the temperature-drift model and its compensation
(:mod:`~fogts.startup.thermal`), four-position north seeking
(:mod:`~fogts.startup.northfind`) and the start-up simulator
(:mod:`~fogts.startup.simulator`).
"""

from __future__ import annotations

from fogts.startup.emd import TrendSplit, separate_trend
from fogts.startup.kalman import KalmanResult, arma_kalman
from fogts.startup.northfind import (
    NorthFinding,
    StartupPositions,
    four_position,
    simulate_startup_positions,
)
from fogts.startup.simulator import simulate_startup
from fogts.startup.thermal import (
    ThermalModel,
    bias_stability,
    compensate,
    fit_thermal,
    startup_compensation,
)

__all__ = [
    "KalmanResult",
    "NorthFinding",
    "StartupPositions",
    "ThermalModel",
    "TrendSplit",
    "arma_kalman",
    "bias_stability",
    "compensate",
    "fit_thermal",
    "four_position",
    "separate_trend",
    "simulate_startup",
    "simulate_startup_positions",
    "startup_compensation",
]
