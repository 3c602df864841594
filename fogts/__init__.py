"""fogts: fibre-optic-gyro drift analysis.

Allan-variance analysis with IEEE-952 noise terms, ARMA model selection with residual
diagnostics, and the models built on them (simulation, dynamic Allan variance, Kalman
filtering, temperature compensation, north seeking).

Public names are imported lazily (PEP 562), so ``import fogts`` and the command line start
fast; ``from fogts import allan_deviation`` works as usual.

Examples
--------
>>> import numpy as np, fogts
>>> x = np.random.default_rng(0).normal(size=20_000)
>>> res = fogts.allan_deviation(x, fs_hz=100.0)
>>> round(float(res.dev[0] * np.sqrt(res.tau_s[0] * 100.0)), 1)  # white noise: sigma(tau0)
1.0
"""

from __future__ import annotations

import importlib
from typing import TYPE_CHECKING, Any

from fogts._version import __version__

#: Defining module -> the public names it provides, imported on first use by ``__getattr__``.
_MODULE_NAMES: dict[str, str] = {
    # errors
    "fogts.errors": "FogtsError DataError InsufficientDataError ModelFitError FogtsWarning",
    # reading and preparing
    "fogts.io.run": "Run SamplingReport MissingReport",
    "fogts.io.reader": "read_run",
    "fogts.preprocess.hygiene": "assess_run DataQuality",
    "fogts.preprocess.glitches": "detect_glitches GlitchReport",
    "fogts.preprocess.gaps": "find_gaps GapReport",
    "fogts.allan.plausibility": "check_plausibility PlausibilityReport",
    "fogts.preprocess.prepare": "prepare Prepared",
    "fogts.units": "convert_rate earth_rate_component",
    # Allan analysis
    "fogts.allan.api": "allan_deviation",
    "fogts.allan.result": "AllanResult AllanResultSet",
    "fogts.allan.taus": "tau_grid TauGrid",
    "fogts.allan.confidence": "confidence_table",
    "fogts.allan.bias": "totdev_bias",
    "fogts.allan.noise": "fit_noise",
    "fogts.allan.ml": "fit_noise_ml",
    "fogts.allan.noise_model": "NoiseModel",
    "fogts.allan.noise_term": "NoiseTerm",
    "fogts.allan.readout": "read_curve CurveReadout",
    "fogts.allan.curve_input": "read_curve_file",
    "fogts.allan.compare": "compare_allan AllanComparison",
    "fogts.allan.dynamic": "dynamic_allan",
    "fogts.allan.dynamic_result": "DynamicAllanResult",
    # ARMA
    "fogts.arma.fit": "fit_arma",
    "fogts.arma.fit_result": "ArmaFit",
    "fogts.arma.select": "select_arma",
    "fogts.arma.selection": "Selection",
    "fogts.arma.candidate": "Candidate",
    "fogts.arma.predict": "Prediction",
    "fogts.arma.identification": "correlogram",
    # models built on the results
    "fogts.simulate.gyro": "simulate_gyro",
    "fogts.simulate.arma_series": "simulate_arma",
    "fogts.simulate.noise_spec": "NoiseSpec",
    "fogts.simulate.bootstrap": "bootstrap_noise NoiseBootstrap",
    "fogts.arma.spec": "ArmaSpec",
    "fogts.startup.simulator": "simulate_startup",
    "fogts.preprocess.filters": "lowpass moving_average FilterResult",
    "fogts.startup.emd": "separate_trend TrendSplit",
    "fogts.startup.kalman.api": "arma_kalman",
    "fogts.startup.kalman.result": "KalmanResult",
    "fogts.startup.thermal_fit": "fit_thermal",
    "fogts.startup.thermal_model": "ThermalModel",
    "fogts.startup.compensation": "compensate bias_stability",
    "fogts.startup.startup_workflow": "startup_compensation",
    "fogts.startup.northfind": "four_position NorthFinding",
    "fogts.startup.northfind_simulation": "simulate_startup_positions StartupPositions",
    # tooling
    "fogts.batch.runner": "run_batch",
    "fogts.report.html": "build_report write_report",
}
#: Public name -> defining module.
_EXPORTS: dict[str, str] = {
    name: module for module, names in _MODULE_NAMES.items() for name in names.split()
}

__all__ = ["__version__", *sorted(_EXPORTS)]


#: Submodules reachable as attributes (``fogts.plots.plot_allan``) without an import.
_SUBMODULES = {name: f"fogts.{name}" for name in
               ("allan", "arma", "io", "preprocess", "report", "simulate", "startup", "units")}
_SUBMODULES.update(plots="fogts.report.plots", hygiene="fogts.preprocess.hygiene")


def __getattr__(name: str) -> Any:
    if name in _SUBMODULES:
        return importlib.import_module(_SUBMODULES[name])
    module = _EXPORTS.get(name)
    if module is None:
        raise AttributeError(f"module 'fogts' has no attribute {name!r}")
    value = getattr(importlib.import_module(module), name)
    globals()[name] = value
    return value


def __dir__() -> list[str]:
    return sorted(__all__)


if TYPE_CHECKING:  # the names of _MODULE_NAMES, static for type checkers and IDEs
    from fogts import allan, arma, io, preprocess, report, simulate, startup, units
    from fogts.allan.api import allan_deviation
    from fogts.allan.bias import totdev_bias
    from fogts.allan.compare import AllanComparison, compare_allan
    from fogts.allan.confidence import confidence_table
    from fogts.allan.curve_input import read_curve_file
    from fogts.allan.dynamic import dynamic_allan
    from fogts.allan.dynamic_result import DynamicAllanResult
    from fogts.allan.ml import fit_noise_ml
    from fogts.allan.noise import fit_noise
    from fogts.allan.noise_model import NoiseModel
    from fogts.allan.noise_term import NoiseTerm
    from fogts.allan.plausibility import PlausibilityReport, check_plausibility
    from fogts.allan.readout import CurveReadout, read_curve
    from fogts.allan.result import AllanResult, AllanResultSet
    from fogts.allan.taus import TauGrid, tau_grid
    from fogts.arma.candidate import Candidate
    from fogts.arma.fit import fit_arma
    from fogts.arma.fit_result import ArmaFit
    from fogts.arma.identification import correlogram
    from fogts.arma.predict import Prediction
    from fogts.arma.select import select_arma
    from fogts.arma.selection import Selection
    from fogts.arma.spec import ArmaSpec
    from fogts.batch.runner import run_batch
    from fogts.errors import (
        DataError,
        FogtsError,
        FogtsWarning,
        InsufficientDataError,
        ModelFitError,
    )
    from fogts.io.reader import read_run
    from fogts.io.run import MissingReport, Run, SamplingReport
    from fogts.preprocess import hygiene
    from fogts.preprocess.filters import FilterResult, lowpass, moving_average
    from fogts.preprocess.gaps import GapReport, find_gaps
    from fogts.preprocess.glitches import GlitchReport, detect_glitches
    from fogts.preprocess.hygiene import DataQuality, assess_run
    from fogts.preprocess.prepare import Prepared, prepare
    from fogts.report import plots
    from fogts.report.html import build_report, write_report
    from fogts.simulate.arma_series import simulate_arma
    from fogts.simulate.bootstrap import NoiseBootstrap, bootstrap_noise
    from fogts.simulate.gyro import simulate_gyro
    from fogts.simulate.noise_spec import NoiseSpec
    from fogts.startup.compensation import bias_stability, compensate
    from fogts.startup.emd import TrendSplit, separate_trend
    from fogts.startup.kalman.api import arma_kalman
    from fogts.startup.kalman.result import KalmanResult
    from fogts.startup.northfind import NorthFinding, four_position
    from fogts.startup.northfind_simulation import StartupPositions, simulate_startup_positions
    from fogts.startup.simulator import simulate_startup
    from fogts.startup.startup_workflow import startup_compensation
    from fogts.startup.thermal_fit import fit_thermal
    from fogts.startup.thermal_model import ThermalModel
    from fogts.units import convert_rate, earth_rate_component
