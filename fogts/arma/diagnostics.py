"""Residual and identification diagnostics of ARMA candidates, in one namespace.

* :mod:`fogts.arma.correlation`: lag products, sample ACF and PACF of long series;
* :mod:`fogts.arma.whiteness`: rho_a,2, rho_ax,3 (the drift paper's eqs. 11 and 12), the
  Ljung-Box test and the white verdict of one candidate's residuals;
* :mod:`fogts.arma.roots`: AR and MA roots, stationarity and invertibility;
* :mod:`fogts.arma.redundancy`: nearly cancelling roots, a common AR/MA factor within
  sampling uncertainty, insignificant coefficients;
* :mod:`fogts.arma.identification`: the Box-Jenkins reading of the data's ACF and PACF.
"""

from __future__ import annotations

from fogts.arma.correlation import autocorrelation, lag_products, partial_autocorrelation
from fogts.arma.identification import (
    CUTOFF_MAX_LAG,
    CUTOFF_STEP,
    OUTLIER_Z,
    Correlogram,
    CorrelogramPattern,
    correlogram,
)
from fogts.arma.redundancy import (
    NEAR_CANCEL_TOL,
    RedundancyFlag,
    common_factor,
    common_factor_z,
    insignificant_terms,
    near_cancellations,
    resultant,
)
from fogts.arma.roots import Roots, arma_roots
from fogts.arma.whiteness import (
    BAND_Z,
    LB_ALPHA,
    CorrelationCheck,
    LjungBoxLag,
    ResidualDiagnostics,
    ljung_box,
    residual_diagnostics,
    rho_a2,
    rho_ax3,
)

__all__ = ["BAND_Z", "CUTOFF_MAX_LAG", "CUTOFF_STEP", "LB_ALPHA", "NEAR_CANCEL_TOL", "OUTLIER_Z",
           "CorrelationCheck", "Correlogram", "CorrelogramPattern", "LjungBoxLag", "RedundancyFlag",
           "ResidualDiagnostics", "Roots", "arma_roots", "autocorrelation", "common_factor",
           "common_factor_z", "correlogram", "insignificant_terms", "lag_products", "ljung_box",
           "near_cancellations", "partial_autocorrelation", "residual_diagnostics", "resultant",
           "rho_a2", "rho_ax3"]
