"""ARMA modelling of gyro drift: fit, diagnostics, selection, prediction.

``select_arma(prepared)`` fits the candidates AR(1), AR(2), AR(3), ARMA(1,1), ARMA(2,1) by
exact maximum likelihood, checks their residuals (rho_a,2, rho_ax,3, Ljung-Box) and ranks
them; ``selection.best.predict()`` gives the one-step-ahead prediction.

The modules follow the ARMA drift-modelling method for FOGs that their docstrings call "the
drift paper": low-order candidates, the residual checks of its eqs. 11-12 (rho_a,2 and
rho_ax,3) and a one-step prediction (its Fig. 5).
"""

from __future__ import annotations

from fogts.arma.diagnostics import (
    Correlogram,
    ResidualDiagnostics,
    Roots,
    arma_roots,
    correlogram,
    ljung_box,
    residual_diagnostics,
    rho_a2,
    rho_ax3,
)
from fogts.arma.fit import ArmaFit, fit_arma
from fogts.arma.predict import Prediction, one_step_prediction, predict_arma
from fogts.arma.select import (
    CRITERIA,
    DEFAULT_FIVE,
    Candidate,
    Selection,
    parse_candidates,
    select_arma,
)
from fogts.arma.spec import ArmaSpec

__all__ = ["CRITERIA", "DEFAULT_FIVE", "ArmaFit", "ArmaSpec", "Candidate", "Correlogram",
           "Prediction", "ResidualDiagnostics", "Roots", "Selection", "arma_roots", "correlogram",
           "fit_arma", "ljung_box", "one_step_prediction", "parse_candidates", "predict_arma",
           "residual_diagnostics", "rho_a2", "rho_ax3", "select_arma"]
