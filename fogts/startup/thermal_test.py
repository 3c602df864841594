"""Is there a temperature dependence to compensate?  A likelihood-ratio test of the thermal
drift model against "no temperature dependence".

A static gyro's drift wanders (bias instability, rate random walk), and a warm-up
temperature is smooth and monotone: an ordinary or AR(p)-GLS regression of the rate on
T, ΔT, T², ... then finds "significant" coefficients in a record with no thermal effect at
all, because a random walk and a smooth ramp are correlated by chance.  The test therefore
puts the wandering into the null model: the rate is a local level (a random walk plus white
noise, Harvey 1989, ch. 2) with or without the thermal regressors,

    y_t = mu_t + x_t' beta + e_t,   mu_t = mu_{t-1} + eta_t,

both fitted by exact maximum likelihood (statsmodels' ``UnobservedComponents``), and
``2 (llf_1 - llf_0)`` is referred to chi-squared with as many degrees of freedom as thermal
regressors (Wilks 1938).  A temperature effect a random walk can imitate at no cost is not
called significant; a warm-up drift that a random walk of the record's own size cannot
follow is.  The data are block-averaged to at most :data:`MAX_BLOCKS` points first
(thermal effects are slow; the average keeps their shape).
"""

from __future__ import annotations

import math
import warnings
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from fogts._typing import FloatArray
from fogts.errors import DataError
from fogts.startup.thermal_model import DEFAULT_DT_SMOOTHING_S, design_matrix, temperature_rate

__all__ = ["MAX_BLOCKS", "MIN_SPAN_DEGC", "ThermalSignificance", "thermal_significance"]

MAX_BLOCKS = 3000  #: block means the test works on, at most
MIN_SPAN_DEGC = 1.0  #: below this span (°C) the coefficients cannot be told from the offset
#: Default significance level: strict, because the null model only approximates the
#: drift's spectrum (flicker noise lies between its white and random-walk parts).
DEFAULT_ALPHA = 0.001


@dataclass(frozen=True)
class ThermalSignificance:
    """The verdict on a temperature dependence, from :func:`thermal_significance`.

    The likelihood-ratio test of a local level with the thermal regressors against one
    without them (module docstring); an untestable record (a span below
    :data:`MIN_SPAN_DEGC`) is never significant and has NaN statistic and p-value.

    Attributes
    ----------
    testable : bool
        False when the temperature span is too small to identify the coefficients.
    significant : bool
        Whether the thermal model improves the likelihood beyond ``alpha``.
    statistic, df, pvalue : float, int, float
        The likelihood-ratio statistic, its degrees of freedom and p-value.
    alpha : float
    span_degC : float
        The temperature span of the record.
    n_blocks, block_s : int, float
        The block means the test used.
    """

    testable: bool
    significant: bool
    statistic: float
    df: int
    pvalue: float
    alpha: float
    span_degC: float
    n_blocks: int
    block_s: float

    @property
    def verdict(self) -> str:
        """The sentence to show first."""
        if not self.testable:
            return (f"temperature spans only {self.span_degC:.3g} °C (less than "
                    f"{MIN_SPAN_DEGC:g} °C): the thermal coefficients cannot be identified; "
                    "nothing to compensate")
        how = self.test_text()
        if self.significant:
            return f"significant temperature dependence ({how})"
        return f"no significant temperature dependence ({how}); nothing to compensate"

    def test_text(self) -> str:
        """The test and its result in a clause: ``likelihood-ratio test against a random-walk
        drift, p = 0.6, chi2 = 3.65 on 5 df`` (a testable record only)."""
        p = f"p = {self.pvalue:.2g}" if self.pvalue >= 1e-6 else "p < 1e-6"
        return (f"likelihood-ratio test against a random-walk drift, {p}, "
                f"chi2 = {self.statistic:.3g} on {self.df} df")

    def to_dict(self) -> dict[str, Any]:
        return {"testable": self.testable, "significant": self.significant,
                "statistic": self.statistic, "df": self.df, "pvalue": self.pvalue,
                "alpha": self.alpha, "span_degC": self.span_degC, "n_blocks": self.n_blocks,
                "block_s": self.block_s, "verdict": self.verdict,
                "method": "likelihood ratio, local-level (random walk + white) errors"}


def _block_means(x: FloatArray, block: int) -> FloatArray:
    n = x.size // block
    return x[: n * block].reshape(n, block).mean(axis=1)


def _local_level_llf(y: FloatArray, exog: FloatArray | None) -> float:
    from statsmodels.tsa.statespace.structural import UnobservedComponents

    model = UnobservedComponents(y, level="llevel", exog=exog)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # convergence chatter of the optimiser
        res = model.fit(disp=False, method="lbfgs", maxiter=500)
    return float(res.llf)


def thermal_significance(rate: Any, temperature: Any, *, fs_hz: float,
                         terms: Sequence[str] = ("T*dT", "T2", "T", "dT2", "dT"),
                         dT_smoothing_s: float | None = DEFAULT_DT_SMOOTHING_S,
                         alpha: float = DEFAULT_ALPHA) -> ThermalSignificance:
    """Test the thermal drift model against "no temperature dependence".

    Parameters
    ----------
    rate, temperature : array_like
        The gyro rate and the temperature (°C), sample by sample.
    fs_hz : float
        Sample rate.
    terms : sequence of str
        The thermal regressors (:data:`fogts.startup.thermal_model.THERMAL_TERMS` without
        the offset "1", which the local level carries).
    dT_smoothing_s : float or None
        Window of the temperature-rate estimate (as in the fit).
    alpha : float
        Significance level.

    Returns
    -------
    ThermalSignificance
    """
    y = np.asarray(rate, dtype=np.float64).ravel()
    temp = np.asarray(temperature, dtype=np.float64).ravel()
    if y.shape != temp.shape or y.size < 20:
        raise DataError(f"rate and temperature must have the same length (at least 20), got "
                        f"{y.size} and {temp.size}")
    terms = [t for t in terms if t != "1"]
    span = float(np.nanmax(temp) - np.nanmin(temp))
    block = max(1, math.ceil(y.size / MAX_BLOCKS))
    yb, tb = _block_means(y, block), _block_means(temp, block)
    fs_block = fs_hz / block
    if span < MIN_SPAN_DEGC:
        return ThermalSignificance(False, False, math.nan, len(terms), math.nan, alpha, span,
                                   yb.size, block / fs_hz)
    dtb = temperature_rate(tb, fs_hz=fs_block, smoothing_s=dT_smoothing_s)
    x = design_matrix(tb, dtb, terms)
    scale = x.std(axis=0)
    x = (x - x.mean(axis=0)) / np.where(scale > 0, scale, 1.0)
    keep = scale > 0
    x = x[:, keep]
    y_scaled = (yb - yb.mean()) / (yb.std() or 1.0)
    llf0 = _local_level_llf(y_scaled, None)
    llf1 = _local_level_llf(y_scaled, x)
    stat = max(0.0, 2.0 * (llf1 - llf0))
    df = int(x.shape[1])
    from scipy.stats import chi2

    p = float(chi2.sf(stat, df))
    return ThermalSignificance(True, p < alpha, stat, df, p, alpha, span, yb.size,
                               block / fs_hz)
