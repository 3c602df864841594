"""Chi-squared confidence intervals of Allan-family deviations, one per point of a curve.

An Allan-family variance estimate with ``edf`` equivalent degrees of freedom is distributed
as :math:`\\sigma^2 \\chi^2_{edf} / edf`, so its confidence interval follows from the edf,
and the edf depends on the dominant power-law noise at that tau.  :func:`confidence_table`
does the three steps of NIST SP1065 (W. J. Riley, *Handbook of Frequency Stability
Analysis*, 2008) for every point of a curve:

1. noise identification (SP1065 section 5.2; :mod:`fogts.allan.noise_identification`);
2. EDF (SP1065 section 5.3; Greenhall & Riley 2003; :mod:`fogts.allan.edf`);
3. the chi-squared interval at a chosen confidence (SP1065 section 5.3,
   :math:`\\sigma^2 \\cdot edf / \\chi^2`, with :func:`scipy.stats.chi2.ppf`):
   :func:`chi2_interval`.

:func:`fogts.allan.allan_deviation` uses it for every curve.  :func:`totdev_bias`
(:mod:`fogts.allan.bias`) gives the noise-dependent bias of the total variance (Howe 1999),
which Stable32 divides out of its TOTDEV at flicker and random-walk FM points.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
import numpy.typing as npt
import pandas as pd

from fogts._typing import FloatArray, IntArray
from fogts._validate import (
    check_choice,
    check_fraction,
    check_positive,
    finite_or_none,
    to_float_array,
)
from fogts.allan._checks import check_m
from fogts.allan.decimated import DecimatedSums
from fogts.allan.distributions import chi2_ppf
from fogts.allan.edf import edf_for
from fogts.allan.noise_identification import identify_with_methods
from fogts.allan.taus import KINDS
from fogts.errors import DataError

__all__ = ["ChiSquaredInterval", "ConfidenceTable", "chi2_interval", "confidence_table",
           "curve_table"]


@dataclass(frozen=True)
class ChiSquaredInterval:
    """A chi-squared confidence interval of deviations (it unpacks as ``low, high``).

    Attributes
    ----------
    low, high : ndarray
        Lower and upper limits, in the unit of the deviation, same shape as the input.
    confidence : float
        The two-sided confidence level, e.g. 0.683.
    """

    low: FloatArray
    high: FloatArray
    confidence: float

    def __iter__(self) -> Any:
        """Unpack as ``low, high``."""
        return iter((self.low, self.high))

    def to_dict(self) -> dict[str, Any]:
        """JSON-safe dict ``{"confidence", "low", "high"}`` (NaN stays NaN -> null in JSON)."""
        return {"confidence": self.confidence, "low": np.asarray(self.low).tolist(),
                "high": np.asarray(self.high).tolist()}


@dataclass(frozen=True)
class ConfidenceTable:
    """Noise type, EDF and confidence interval of every tau of one deviation curve.

    Attributes
    ----------
    kind : str
        The estimator: ``adev``, ``oadev``, ``mdev``, ``hdev``, ``ohdev`` or ``totdev``.
    confidence : float
        Two-sided confidence level of ``ci_low`` / ``ci_high``.
    fs_hz : float
        Sample rate of the rate series.
    n_samples : int
        Number of rate samples (the phase has ``n_samples + 1`` points).
    tau_s : ndarray
        Averaging times ``m / fs_hz``.
    m : ndarray of int64
        Averaging factors.
    dev : ndarray
        The deviations the interval is built around.
    alpha : ndarray of int64
        Power-law exponent of the rate spectrum used for the EDF (2, 1, 0, -1, -2).
    alpha_method : tuple of str
        How each alpha was found: ``"acf"``, ``"b1"``, ``"rn"`` or ``"none"`` (taken from the
        nearest identified tau; see :mod:`fogts.allan.noise_identification`).
    edf : ndarray
        Equivalent degrees of freedom.
    ci_low, ci_high : ndarray
        Confidence limits of the deviation.
    """

    kind: str
    confidence: float
    fs_hz: float
    n_samples: int
    tau_s: FloatArray
    m: IntArray
    dev: FloatArray
    alpha: IntArray
    alpha_method: tuple[str, ...]
    edf: FloatArray
    ci_low: FloatArray
    ci_high: FloatArray

    def to_frame(self) -> pd.DataFrame:
        """One row per tau: ``tau, m, dev, alpha, alpha_method, edf, ci_low, ci_high``."""
        return pd.DataFrame({
            "tau": self.tau_s, "m": self.m, "dev": self.dev, "alpha": self.alpha,
            "alpha_method": list(self.alpha_method), "edf": self.edf,
            "ci_low": self.ci_low, "ci_high": self.ci_high,
        })

    def to_dict(self) -> dict[str, Any]:
        """JSON-safe dict with stable keys; non-finite numbers become ``None``."""
        points = [{"tau": finite_or_none(t), "m": int(m), "dev": finite_or_none(d), "alpha": int(a),
                   "alpha_method": meth, "edf": finite_or_none(e), "ci_low": finite_or_none(lo), "ci_high": finite_or_none(hi)}
                  for t, m, d, a, meth, e, lo, hi in zip(
                      self.tau_s, self.m, self.dev, self.alpha, self.alpha_method, self.edf,
                      self.ci_low, self.ci_high, strict=True)]
        return {"kind": self.kind, "confidence": self.confidence, "fs_hz": self.fs_hz,
                "n_samples": self.n_samples, "points": points}

    def summary(self) -> str:
        """A plain-text table of the intervals."""
        lines = [f"{self.kind} confidence intervals at {100 * self.confidence:.1f} % "
                 f"({self.n_samples} samples at {self.fs_hz:g} Hz)",
                 f"{'tau_s':>12} {'m':>9} {'alpha':>5} {'id':>4} {'edf':>11} "
                 f"{'ci_low':>12} {'dev':>12} {'ci_high':>12}"]
        for i in range(self.m.size):
            lines.append(f"{self.tau_s[i]:12.5g} {self.m[i]:9d} {self.alpha[i]:5d} "
                         f"{self.alpha_method[i]:>4} {self.edf[i]:11.5g} "
                         f"{self.ci_low[i]:12.5g} {self.dev[i]:12.5g} {self.ci_high[i]:12.5g}")
        return "\n".join(lines)



def chi2_interval(dev: npt.ArrayLike, edf: npt.ArrayLike,
                  confidence: float = 0.683) -> ChiSquaredInterval:
    """Two-sided chi-squared confidence interval of a deviation (NIST SP1065 section 5.3).

    ``low = dev * sqrt(edf / chi2.ppf((1 + c) / 2, edf))`` and
    ``high = dev * sqrt(edf / chi2.ppf((1 - c) / 2, edf))``.

    Parameters
    ----------
    dev : array_like
        Deviations (>= 0; NaN propagates).
    edf : array_like
        Equivalent degrees of freedom (> 0; NaN propagates); broadcast against ``dev``.
    confidence : float
        Two-sided confidence level in (0, 1); 0.683 is "one sigma".

    Returns
    -------
    ChiSquaredInterval
        ``low``, ``high`` (broadcast shape) and ``confidence``; unpacks as ``low, high``.

    Examples
    --------
    >>> lo, hi = chi2_interval(0.29223, 782.03)
    >>> round(float(lo), 4), round(float(hi), 4)
    (0.2851, 0.2999)
    """
    c = check_fraction("confidence", confidence)
    d = np.asarray(dev, dtype=np.float64)
    e = np.asarray(edf, dtype=np.float64)
    if np.any(d < 0) or np.any(np.isinf(d)):
        bad = d[(d < 0) | np.isinf(d)].flat[0]
        raise DataError(f"dev must be finite and >= 0 (NaN allowed), got {float(bad)!r}")
    if np.any(e <= 0) or np.any(np.isinf(e)):
        bad = e[(e <= 0) | np.isinf(e)].flat[0]
        raise DataError(f"edf must be finite and > 0 (NaN allowed), got {float(bad)!r}")
    try:
        d, e = np.broadcast_arrays(d, e)
    except ValueError:
        raise DataError(f"dev and edf must broadcast, got shapes {d.shape} and "
                        f"{e.shape}") from None
    lower_tail = (1.0 - c) / 2.0
    low = d * np.sqrt(e / chi2_ppf(1.0 - lower_tail, e))
    high = d * np.sqrt(e / chi2_ppf(lower_tail, e))
    return ChiSquaredInterval(low=np.asarray(low, dtype=np.float64),
                              high=np.asarray(high, dtype=np.float64), confidence=c)


def confidence_table(y: npt.ArrayLike | pd.Series, *, fs_hz: float, kind: str,
                     m: npt.ArrayLike, dev: npt.ArrayLike,
                     confidence: float = 0.683) -> ConfidenceTable:
    """Noise identification, EDF and chi-squared interval for every point of a curve.

    Runs :func:`~fogts.allan.noise_identification.identify_noise` (lag-1 ACF, B1 / R(n) fallback), :func:`edf_for`
    (Greenhall & Riley 2003; SP1065 for totdev) and :func:`chi2_interval`.

    Parameters
    ----------
    y : array_like or pandas.Series
        The rate series the deviations were computed from.
    fs_hz : float
        Sample rate.
    kind : {"adev", "oadev", "mdev", "hdev", "ohdev", "totdev"}
        Estimator of ``dev``.
    m : array_like of int
        Averaging factors of the curve.
    dev : array_like
        The deviations at ``m`` (same length).
    confidence : float
        Two-sided confidence level, default 0.683.

    Returns
    -------
    ConfidenceTable

    Raises
    ------
    DataError
        Bad ``kind``, ``fs_hz``, ``confidence``, ``m`` or ``dev``, or ``m`` and ``dev`` of
        different lengths.
    InsufficientDataError
        ``y`` shorter than 2 samples, or an ``m`` too large for the estimator.

    Examples
    --------
    >>> import numpy as np
    >>> import allantools
    >>> y = np.random.default_rng(7).standard_normal(10_000)
    >>> m = np.array([1, 10, 100])
    >>> dev = allantools.oadev(y, rate=1.0, data_type="freq", taus=m)[1]
    >>> table = confidence_table(y, fs_hz=1.0, kind="oadev", m=m, dev=dev)
    >>> table.alpha.tolist(), table.alpha_method
    ([0, 0, 0], ('acf', 'acf', 'acf'))
    >>> bool(np.all((table.ci_low < dev) & (dev < table.ci_high)))
    True
    """
    kind = check_choice("kind", kind, KINDS)
    fs = check_positive("fs_hz", fs_hz)
    c = check_fraction("confidence", confidence)
    arr = to_float_array(y, "y", min_length=2)
    mm = check_m(m)
    d = np.atleast_1d(np.asarray(dev, dtype=np.float64))
    if d.shape != mm.shape:
        raise DataError(f"dev must have one value per m: got {d.size} values for {mm.size} "
                        "averaging factors")
    if np.any(~np.isfinite(d) | (d < 0)):
        bad = d[~np.isfinite(d) | (d < 0)][0]
        raise DataError(f"dev must be finite and >= 0, got {float(bad)!r}")
    return curve_table(arr, fs_hz=fs, kind=kind, m=mm, dev=d, confidence=c)


def curve_table(y: FloatArray, *, fs_hz: float, kind: str, m: IntArray, dev: FloatArray,
                confidence: float, phase: FloatArray | None = None,
                sums: Sequence[DecimatedSums | None] | None = None) -> ConfidenceTable:
    """:func:`confidence_table` of arguments already checked (float64 rate, int64 ``m``,
    finite ``dev >= 0`` of the same length, ``kind`` and ``confidence`` valid), reusing the
    estimator's phase and decimated sums when given
    (:func:`fogts.allan.estimators.estimate_with_sums`): what
    :func:`fogts.allan.allan_deviation` calls.
    """
    alpha, methods = identify_with_methods(y, m, kind, dev**2 if kind == "oadev" else None,
                                           phase=phase, sums=sums)
    edf = edf_for(kind, alpha, m, y.size + 1)
    interval = chi2_interval(dev, edf, confidence)
    return ConfidenceTable(kind=kind, confidence=confidence, fs_hz=fs_hz,
                           n_samples=int(y.size), tau_s=m / fs_hz, m=m, dev=dev, alpha=alpha,
                           alpha_method=methods, edf=edf, ci_low=interval.low,
                           ci_high=interval.high)
