"""The result of :func:`fogts.startup.kalman.arma_kalman`: :class:`KalmanResult`."""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any

import numpy as np
import pandas as pd

from fogts._typing import FloatArray

__all__ = ["KalmanResult"]


@dataclass(frozen=True)
class KalmanResult:
    """Kalman filter and smoother output for an ARMA drift model.

    Attributes
    ----------
    observed, filtered, smoothed, predicted : ndarray or pandas.Series
        The input; E[x_t | y_..t]; E[x_t | all y]; E[y_t | y_..t-1].  Same index as the input.
    innovations : ndarray
        y_t - predicted_t.
    model : str
        Model name, e.g. ``"ARMA(2,1)"``.
    ar, ma : tuple of float
    sigma2 : float
        Drift innovation variance.
    measurement_noise : float
        H, the white measurement-noise variance used.
    measurement_noise_source : str
        ``"estimated"`` or ``"given"``.
    method : str
        ``"exact"`` or ``"steady-state"`` (what was run).
    n_transient : int
        Samples filtered exactly before switching to the steady gain (n for ``"exact"``).
    steady_gain : tuple of float
        Steady filtered gain K_f = P Z'/F.
    innovation_variance : float
        Steady F = Z P Z' + H.
    loglike : float
        Gaussian log-likelihood of the observations under the model.
    mean : float
        Mean removed before filtering and added back (0 if ``demean=False``).
    notes : tuple of str
    """

    observed: Any = field(repr=False)
    filtered: Any = field(repr=False)
    smoothed: Any = field(repr=False)
    predicted: Any = field(repr=False)
    innovations: FloatArray = field(repr=False)
    model: str
    ar: tuple[float, ...]
    ma: tuple[float, ...]
    sigma2: float
    measurement_noise: float
    measurement_noise_source: str
    method: str
    n_transient: int
    steady_gain: tuple[float, ...]
    innovation_variance: float
    loglike: float
    mean: float
    notes: tuple[str, ...] = ()

    @property
    def n(self) -> int:
        return int(np.asarray(self.observed).size)

    def to_frame(self) -> pd.DataFrame:
        """Columns observed, filtered, smoothed, predicted (input index kept)."""
        index = self.observed.index if isinstance(self.observed, pd.Series) else None
        return pd.DataFrame({"observed": np.asarray(self.observed),
                             "filtered": np.asarray(self.filtered),
                             "smoothed": np.asarray(self.smoothed),
                             "predicted": np.asarray(self.predicted)}, index=index)

    def variance_reduction(self) -> dict[str, float]:
        """Sample variance of the observed, filtered and smoothed series."""
        return {k: float(np.var(np.asarray(getattr(self, k)), ddof=1))
                for k in ("observed", "filtered", "smoothed")}

    def to_dict(self) -> dict[str, Any]:
        return {"model": self.model, "ar": list(self.ar), "ma": list(self.ma),
                "sigma2": self.sigma2, "measurement_noise": self.measurement_noise,
                "measurement_noise_source": self.measurement_noise_source,
                "method": self.method, "n": self.n, "n_transient": self.n_transient,
                "steady_gain": list(self.steady_gain),
                "innovation_variance": self.innovation_variance, "loglike": self.loglike,
                "mean": self.mean, "variance": self.variance_reduction(),
                "notes": list(self.notes)}

    def summary(self) -> str:
        v = self.variance_reduction()
        how = ("exact" if self.method == "exact" else
               f"steady-state gain after an exact transient of {self.n_transient} samples")
        lines = [f"Kalman filter, {self.model} drift + white measurement noise, n = {self.n} "
                 f"({how})",
                 f"  sigma2 = {self.sigma2:.6g}  H = {self.measurement_noise:.6g} "
                 f"({self.measurement_noise_source})  steady gain = "
                 + ", ".join(f"{g:.4g}" for g in self.steady_gain),
                 f"  std: observed {math.sqrt(v['observed']):.6g}  filtered "
                 f"{math.sqrt(v['filtered']):.6g}  smoothed {math.sqrt(v['smoothed']):.6g}",
                 f"  log-likelihood {self.loglike:.6f}"]
        lines += [f"  note: {n}" for n in self.notes]
        return "\n".join(lines)
