"""The start-up drift domain: a FOG's output in its first minutes to hours after switch-on,
when the temperature settles.

* :mod:`~fogts.startup.emd`: EMD trend separation;
* :mod:`~fogts.startup.kalman`: the Kalman filter built from a selected ARMA model;
* :mod:`~fogts.startup.thermal_model`: the temperature-drift model and the temperature rate;
* :mod:`~fogts.startup.thermal_fit`: its least-squares fit and standard errors;
* :mod:`~fogts.startup.compensation`: thermal compensation of a run and bias stability;
* :mod:`~fogts.startup.thermal_test`: is there a temperature dependence to compensate;
* :mod:`~fogts.startup.thermal_cv`: the out-of-sample gain (held-out runs or time blocks);
* :mod:`~fogts.startup.startup_workflow`: EMD, Kalman, fit and compensation on one run;
* :mod:`~fogts.startup.northfind`: four-position north seeking;
* :mod:`~fogts.startup.northfind_simulation`: north seeking during simulated cold starts;
* :mod:`~fogts.startup.simulator`: the cold-start simulator.
"""

from __future__ import annotations

from fogts.startup.compensation import BiasStability, bias_stability, compensate
from fogts.startup.emd import TrendSplit, separate_trend
from fogts.startup.kalman import KalmanResult, arma_kalman
from fogts.startup.northfind import NorthFinding, angle_error_deg, four_position
from fogts.startup.northfind_simulation import (
    NorthSeekingStudy,
    StartupPositions,
    simulate_north_seeking,
    simulate_startup_positions,
    simulated_calibration,
)
from fogts.startup.simulator import simulate_startup
from fogts.startup.startup_workflow import StartupCompensation, startup_compensation
from fogts.startup.thermal_cv import ThermalCrossValidation, thermal_cross_validation
from fogts.startup.thermal_fit import fit_thermal
from fogts.startup.thermal_model import (
    TERM_LETTERS,
    THERMAL_TERMS,
    ThermalModel,
    design_matrix,
    temperature_rate,
)

__all__ = ["TERM_LETTERS", "THERMAL_TERMS", "BiasStability", "KalmanResult", "NorthFinding",
           "NorthSeekingStudy", "StartupCompensation", "StartupPositions",
           "ThermalCrossValidation", "ThermalModel",
           "TrendSplit", "angle_error_deg", "arma_kalman", "bias_stability", "compensate",
           "design_matrix", "fit_thermal", "four_position", "separate_trend",
           "simulate_north_seeking", "simulate_startup", "simulate_startup_positions",
           "simulated_calibration", "startup_compensation", "temperature_rate",
           "thermal_cross_validation"]
