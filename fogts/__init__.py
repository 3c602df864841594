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

# public name -> defining module
_EXPORTS: dict[str, str] = {
    # errors
    "FogtsError": "fogts.errors", "DataError": "fogts.errors",
    "InsufficientDataError": "fogts.errors", "ModelFitError": "fogts.errors",
    "FogtsWarning": "fogts.errors",
    # reading and preparing
    "Run": "fogts.io.run", "SamplingReport": "fogts.io.run",
    "read_run": "fogts.io.reader", "MissingReport": "fogts.io.run",
    "assess_run": "fogts.preprocess.hygiene", "DataQuality": "fogts.preprocess.hygiene",
    "detect_glitches": "fogts.preprocess.glitches", "GlitchReport": "fogts.preprocess.glitches",
    "find_gaps": "fogts.preprocess.gaps", "GapReport": "fogts.preprocess.gaps",
    "check_plausibility": "fogts.allan.plausibility",
    "PlausibilityReport": "fogts.allan.plausibility",
    "prepare": "fogts.preprocess.prepare", "Prepared": "fogts.preprocess.prepare",
    "convert_rate": "fogts.units", "earth_rate_component": "fogts.units",
    # Allan analysis
    "allan_deviation": "fogts.allan.api",
    "AllanResult": "fogts.allan.result", "AllanResultSet": "fogts.allan.result",
    "tau_grid": "fogts.allan.taus", "TauGrid": "fogts.allan.taus",
    "confidence_table": "fogts.allan.confidence", "totdev_bias": "fogts.allan.confidence",
    "fit_noise": "fogts.allan.noise", "NoiseModel": "fogts.allan.noise",
    "NoiseTerm": "fogts.allan.noise",
    "read_curve": "fogts.allan.readout", "CurveReadout": "fogts.allan.readout",
    "compare_allan": "fogts.allan.compare", "AllanComparison": "fogts.allan.compare",
    "dynamic_allan": "fogts.allan.dynamic", "DynamicAllanResult": "fogts.allan.dynamic",
    # ARMA
    "fit_arma": "fogts.arma.fit", "ArmaFit": "fogts.arma.fit",
    "select_arma": "fogts.arma.select", "Selection": "fogts.arma.select",
    "Candidate": "fogts.arma.select", "Prediction": "fogts.arma.predict",
    "correlogram": "fogts.arma.diagnostics",
    # models built on the results
    "simulate_gyro": "fogts.simulate.gyro", "simulate_arma": "fogts.simulate.arma_series",
    "NoiseSpec": "fogts.simulate.noise_spec", "ArmaSpec": "fogts.arma.spec",
    "simulate_startup": "fogts.startup.simulator",
    "lowpass": "fogts.preprocess.filters", "moving_average": "fogts.preprocess.filters",
    "FilterResult": "fogts.preprocess.filters",
    "separate_trend": "fogts.startup.emd", "TrendSplit": "fogts.startup.emd",
    "arma_kalman": "fogts.startup.kalman", "KalmanResult": "fogts.startup.kalman",
    "fit_thermal": "fogts.startup.thermal_fit", "ThermalModel": "fogts.startup.thermal_model",
    "compensate": "fogts.startup.compensation", "bias_stability": "fogts.startup.compensation",
    "startup_compensation": "fogts.startup.startup_workflow",
    "four_position": "fogts.startup.northfind", "NorthFinding": "fogts.startup.northfind",
    "simulate_startup_positions": "fogts.startup.northfind_simulation", "StartupPositions": "fogts.startup.northfind_simulation",
    # tooling
    "run_batch": "fogts.batch", "build_report": "fogts.report.html",
    "write_report": "fogts.report.html",
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


if TYPE_CHECKING:  # static names for type checkers and IDEs
    from fogts import allan, arma, io, preprocess, report, simulate, startup, units
    from fogts.allan.api import allan_deviation
    from fogts.allan.compare import AllanComparison, compare_allan
    from fogts.allan.confidence import confidence_table, totdev_bias
    from fogts.allan.dynamic import DynamicAllanResult, dynamic_allan
    from fogts.allan.noise import NoiseModel, NoiseTerm, fit_noise
    from fogts.allan.plausibility import PlausibilityReport, check_plausibility
    from fogts.allan.readout import CurveReadout, read_curve
    from fogts.allan.result import AllanResult, AllanResultSet
    from fogts.allan.taus import TauGrid, tau_grid
    from fogts.arma.diagnostics import correlogram
    from fogts.arma.fit import ArmaFit, fit_arma
    from fogts.arma.predict import Prediction
    from fogts.arma.select import Candidate, Selection, select_arma
    from fogts.arma.spec import ArmaSpec
    from fogts.batch import run_batch
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
    from fogts.preprocess.hygiene import (
        DataQuality,
        GapReport,
        GlitchReport,
        assess_run,
        detect_glitches,
        find_gaps,
    )
    from fogts.preprocess.prepare import Prepared, prepare
    from fogts.report import plots
    from fogts.report.html import build_report, write_report
    from fogts.simulate.arma_series import simulate_arma
    from fogts.simulate.gyro import simulate_gyro
    from fogts.simulate.noise_spec import NoiseSpec
    from fogts.startup.compensation import bias_stability, compensate
    from fogts.startup.emd import TrendSplit, separate_trend
    from fogts.startup.kalman import KalmanResult, arma_kalman
    from fogts.startup.northfind import NorthFinding, four_position
    from fogts.startup.northfind_simulation import StartupPositions, simulate_startup_positions
    from fogts.startup.simulator import simulate_startup
    from fogts.startup.startup_workflow import startup_compensation
    from fogts.startup.thermal_fit import fit_thermal
    from fogts.startup.thermal_model import ThermalModel
    from fogts.units import convert_rate, earth_rate_component
