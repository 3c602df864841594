"""fogts: fibre-optic-gyro drift analysis.

Allan-variance analysis with IEEE-952 noise terms, ARMA model selection with residual
diagnostics, and the models built on them (simulation, dynamic Allan variance, Kalman
filtering, temperature compensation, north seeking).
"""

from __future__ import annotations

__version__ = "0.1.0"

from fogts.errors import (
    DataError,
    FogtsError,
    FogtsWarning,
    InsufficientDataError,
    ModelFitError,
)
from fogts.run import Run

__all__ = [
    "DataError",
    "FogtsError",
    "FogtsWarning",
    "InsufficientDataError",
    "ModelFitError",
    "Run",
    "__version__",
]
