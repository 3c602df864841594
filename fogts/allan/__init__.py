"""Allan-family analysis: tau grids, phase-based estimators, confidence, noise terms.

Public entry point: :func:`allan_deviation` (-> :class:`AllanResult` or
:class:`AllanResultSet`).  The estimators are in :mod:`fogts.allan.estimators` (on the
kernels of :mod:`fogts.allan.kernels`); noise identification, EDF and chi-squared intervals
in :mod:`fogts.allan.noise_identification`, :mod:`fogts.allan.edf` and
:mod:`fogts.allan.confidence`; the dynamic Allan variance in :mod:`fogts.allan.dynamic`.
"""

from __future__ import annotations

from fogts.allan.api import allan_deviation
from fogts.allan.bias import totdev_bias
from fogts.allan.estimators import (
    ESTIMATORS,
    EstimatorOutput,
    adev,
    hdev,
    mdev,
    oadev,
    ohdev,
    totdev,
)
from fogts.allan.result import AllanResult, AllanResultSet
from fogts.allan.taus import KINDS, DroppedTau, TauGrid, tau_grid

__all__ = ["ESTIMATORS", "KINDS", "AllanResult", "AllanResultSet", "DroppedTau", "EstimatorOutput",
           "TauGrid", "adev", "allan_deviation", "hdev", "mdev", "oadev", "ohdev", "tau_grid",
           "totdev", "totdev_bias"]
