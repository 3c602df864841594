"""One-step-ahead prediction with a fitted ARMA model, and the noise it removes.

The drift paper (Fig. 5) closes its modelling with a one-step prediction of the drift: the
predicted x_t given x_1..x_{t-1}, the residual a_t = x_t - predicted, and how much of the
drift the model explains.  Two ways to get it:

* on the series the model was fitted to: predicted = observed - innovations, where the
  innovations are the exact Kalman one-step forecast errors of the Gaussian likelihood.  This
  is exactly statsmodels' ``ARIMA(...).fit().get_prediction()`` (dynamic=False) predicted mean,
  including the first samples (which use only the stationary covariance); see
  :func:`one_step_prediction`;
* on new data (another run of the same gyro): the ARMA recursion
  a_t = x_t - sum phi_i x_{t-i} - sum theta_j a_{t-j} run with
  ``scipy.signal.lfilter(phi(B), theta(B), x)`` from zero pre-sample values (conditional
  prediction; it equals the exact one after a start-up of a few 1/(1 - |root|) samples); see
  :func:`predict_arma`.

The variance removed is ``1 - var(residual) / var(observed)`` (population variances): the
fraction of the drift's power the one-step prediction accounts for.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any

import numpy as np
import pandas as pd

from fogts._typing import ArrayLike1D, FloatArray
from fogts._validate import pandas_index, to_float_array
from fogts.arma.correlation import lag_products
from fogts.errors import DataError

__all__ = ["Prediction", "one_step_prediction", "predict_arma", "prediction_summary", "variance"]


@dataclass(frozen=True)
class Prediction:
    """Observed series, its one-step-ahead prediction and the residual (drift paper, Fig. 5).

    What :meth:`Candidate.predict <fogts.arma.candidate.Candidate.predict>` and
    :func:`predict_arma` return.

    Attributes
    ----------
    model : str
        The model that predicted, e.g. ``"AR(1)"``.
    observed, predicted, residual : ndarray of float64
        ``residual = observed - predicted``.
    index : pandas.Index or None
        The input Series' index (``to_frame()`` uses it).
    time : ndarray of float64 or None
        Time of each sample in seconds, when known.
    method : str
        ``"exact"`` (Kalman innovations of the fit) or ``"conditional"`` (lfilter from zero
        pre-sample values).
    """

    model: str
    observed: FloatArray = field(repr=False)
    predicted: FloatArray = field(repr=False)
    residual: FloatArray = field(repr=False)
    index: pd.Index | None = field(default=None, repr=False)
    time: FloatArray | None = field(default=None, repr=False)
    method: str = "exact"

    @property
    def n(self) -> int:
        return int(self.observed.size)

    @property
    def variance_observed(self) -> float:
        return variance(self.observed)

    @property
    def variance_residual(self) -> float:
        return variance(self.residual)

    @property
    def variance_removed(self) -> float:
        """``1 - var(residual) / var(observed)``: the fraction of variance the prediction removes."""
        return float(self.to_dict()["variance_removed"])

    def to_frame(self) -> pd.DataFrame:
        """Columns ``time`` (if known), ``observed``, ``predicted``, ``residual``; the input's
        index if it was a Series, else the sample number."""
        cols: dict[str, Any] = {}
        if self.time is not None:
            cols["time"] = self.time
        cols.update(observed=self.observed, predicted=self.predicted, residual=self.residual)
        index = self.index if self.index is not None else pd.RangeIndex(self.n, name="sample")
        return pd.DataFrame(cols, index=index)

    def to_dict(self) -> dict[str, Any]:
        """Summary numbers only (the series themselves go to CSV via ``to_frame``)."""
        return prediction_summary(self.observed, self.residual, model=self.model,
                                  method=self.method)

    def summary(self) -> str:
        return (f"one-step prediction with {self.model} ({self.method}), n = {self.n}: "
                f"std {math.sqrt(self.variance_observed):.4g} -> "
                f"{math.sqrt(self.variance_residual):.4g}, "
                f"{100 * self.variance_removed:.1f} % of the variance removed")


def variance(v: FloatArray) -> float:
    """Population variance, ``np.var(v)``, without its series-length temporary (the squared
    deviations summed block by block, :func:`fogts.arma.correlation.lag_products`).

    Examples
    --------
    >>> variance(np.array([1.0, 2.0, 3.0, 4.0]))
    1.25
    """
    return float(lag_products(v, 0, center=float(v.mean()))[0]) / v.shape[0]


def prediction_summary(observed: FloatArray, innovations: FloatArray, *, model: str,
                       method: str = "exact") -> dict[str, Any]:
    """:meth:`Prediction.to_dict` of the prediction ``observed - innovations``, without
    forming it (no series-length array): the variances of the observed series and of the
    innovations, and the fraction ``1 - var(residual) / var(observed)`` removed."""
    vo, vr = variance(observed), variance(innovations)
    return {"model": model, "method": method, "n": int(observed.size),
            "variance_observed": vo, "variance_residual": vr,
            "variance_removed": 1.0 - vr / vo if vo > 0 else math.nan,
            "std_observed": math.sqrt(vo), "std_residual": math.sqrt(vr)}


def one_step_prediction(observed: Any, innovations: Any, *, model: str = "",
                        index: pd.Index | None = None, time: Any = None) -> Prediction:
    """Prediction from a fit's innovations: ``predicted = observed - innovations``.

    Parameters
    ----------
    observed : array_like or Series
        The fitted series x_t.
    innovations : array_like
        The fit's one-step forecast errors a_t (exact Kalman innovations), same length.
    model : str
        Name of the model, for the record.
    index : pandas.Index, optional
        Index to keep (taken from ``observed`` if it is a Series).
    time : array_like, optional
        Time in seconds of each sample.

    Returns
    -------
    Prediction

    Examples
    --------
    >>> p = one_step_prediction([1.0, 2.0, 3.0], [1.0, 0.5, 0.5], model="AR(1)")
    >>> p.predicted.tolist()
    [0.0, 1.5, 2.5]
    """
    if index is None:
        index = pandas_index(observed)
    x = to_float_array(observed, "observed", min_length=1)
    a = to_float_array(innovations, "innovations", min_length=1)
    if a.shape != x.shape:
        raise DataError(f"innovations must have the same length as observed ({x.shape[0]}), "
                        f"got {a.shape[0]}")
    t = _time_axis(time, x, "observed")
    if index is not None and len(index) != x.shape[0]:
        raise DataError(f"index must have the same length as observed ({x.shape[0]}), got "
                        f"{len(index)}")
    return Prediction(model=model, observed=x, predicted=x - a, residual=a.copy(), index=index,
                      time=t, method="exact")


def predict_arma(x: ArrayLike1D, *, ar: Any = (), ma: Any = (), model: str = "",
                 time: Any = None) -> Prediction:
    """Conditional one-step prediction of new data with given ARMA coefficients.

    The innovations are a_t = theta(B)^{-1} phi(B) x_t, run by ``scipy.signal.lfilter`` from
    zero pre-sample values (Box, Jenkins & Reinsel, *Time Series Analysis*, sec. 7.1.4,
    conditional sum of squares); predicted = x - a.

    Parameters
    ----------
    x : array_like or Series
        The (demeaned) series to predict; a Series keeps its index.
    ar, ma : array_like
        phi_1..phi_p and theta_1..theta_q in statsmodels' sign convention,
        x_t = phi_1 x_{t-1} + ... + a_t + theta_1 a_{t-1} + ...; the MA part must be
        invertible.
    model, time
        As in :func:`one_step_prediction`: the model's name and the time of each sample.

    Returns
    -------
    Prediction

    Examples
    --------
    >>> p = predict_arma([1.0, 2.0, 4.0], ar=[0.5])
    >>> p.predicted.tolist()
    [0.0, 0.5, 1.0]
    """
    from scipy.signal import lfilter

    index = pandas_index(x)
    arr = to_float_array(x, "x", min_length=1)
    phi = np.atleast_1d(np.asarray(ar, dtype=np.float64))
    theta = np.atleast_1d(np.asarray(ma, dtype=np.float64))
    if not (np.all(np.isfinite(phi)) and np.all(np.isfinite(theta))):
        raise DataError(f"ar and ma must be finite, got ar={phi.tolist()}, ma={theta.tolist()}")
    if theta.size and float(np.max(np.abs(np.roots(np.r_[1.0, theta])))) >= 1.0:
        raise DataError(f"ma={theta.tolist()} is not invertible (an MA root on or inside the "
                        "unit circle): the one-step prediction would diverge")
    a = lfilter(np.r_[1.0, -phi], np.r_[1.0, theta], arr)
    t = _time_axis(time, arr, "x")
    return Prediction(model=model, observed=arr, predicted=arr - a, residual=np.asarray(a),
                      index=index, time=t, method="conditional")


def _time_axis(time: Any, x: FloatArray, name: str) -> FloatArray | None:
    """``time`` as float64, checked to be as long as the series ``x`` (called ``name``)."""
    t = None if time is None else to_float_array(time, "time", min_length=1)
    if t is not None and t.shape != x.shape:
        raise DataError(f"time must have the same length as {name} ({x.shape[0]}), got "
                        f"{t.shape[0]}")
    return t
