"""Gap-robust overlapping Allan deviation: records with missing samples analysed whole.

Sesia, I. & Tavella, P. (2008), "Estimating the Allan variance in the presence of long
periods of missing data and outliers", Metrologia 45(6), S134-S142: the overlapping Allan
variance is the mean of the squared second differences of the phase,

.. math:: \\sigma^2(m\\tau_0) = \\frac{1}{2 m^2 \\tau_0^2 n_v} \\sum_{i \\in V}
          (x_{i+2m} - 2 x_{i+m} + x_i)^2 ,

taken over the set ``V`` of the ``n_v`` terms that can be formed, i.e. whose phase points
are all known; a missing stretch only removes the terms that touch it (NIST SP1065 eq. 11
for ``V`` = every term).  allantools calls this ``gradev``.

* Angle (phase) input: a term is valid when its three phase points are finite, exactly
  Sesia & Tavella's (and ``allantools.gradev``'s) rule.
* Rate input: the phase is the running sum of the rate, so a missing rate sample leaves the
  phase after it unknown by an offset; a term is valid when all ``2m`` rate samples it
  spans are present (its two averages are complete).  Computed from running sums of the
  rate (NaN taken as 0) and of the count of missing samples.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from fogts._typing import FloatArray, IntArray
from fogts._validate import check_positive, to_float_array
from fogts.allan.estimators import EstimatorOutput
from fogts.errors import DataError, InsufficientDataError

__all__ = ["gradev"]


def gradev(data: Any, *, fs_hz: float, m: Any, input: str = "rate"
           ) -> EstimatorOutput:
    """Overlapping Allan deviation of a record with NaN for its missing samples.

    Parameters
    ----------
    data : array_like
        Rate samples (``input="rate"``) or angle in rate-unit x seconds (``"angle"``), NaN
        where a sample is missing.  Infinite values are refused.
    fs_hz : float
        Sample rate of the regular grid.
    m : array_like of int
        Averaging factors (``tau = m / fs_hz``).
    input : {"rate", "angle"}

    Returns
    -------
    EstimatorOutput
        ``kind="oadev"``; ``n`` counts the valid terms at each m (a tau with fewer than two
        has a NaN deviation).

    Examples
    --------
    >>> y = np.random.default_rng(0).normal(size=2000)
    >>> y[500:700] = np.nan
    >>> out = gradev(y, fs_hz=1.0, m=[1, 10])
    >>> out.n.tolist(), bool(0.9 < out.dev[0] < 1.1)
    ([1798, 1762], True)
    """
    fs = check_positive("fs_hz", fs_hz)
    arr = to_float_array(data, "data", min_length=3, allow_nonfinite=True)
    if np.any(np.isinf(arr)):
        raise DataError("data must be finite or NaN (a missing sample); it holds inf")
    if input not in ("rate", "angle"):
        raise DataError(f"input must be one of rate, angle; got {input!r}")
    mm = np.atleast_1d(np.asarray(m, dtype=np.int64))
    if mm.ndim != 1 or mm.size == 0 or np.any(mm < 1):
        raise DataError(f"m must be a non-empty 1-D array of integers >= 1, got {m!r}")
    phase_points = arr.size + 1 if input == "rate" else arr.size
    if np.any(2 * mm >= phase_points):
        raise InsufficientDataError(f"m = {int(mm.max())} needs more than {2 * int(mm.max())} "
                                    f"phase points; the record has {phase_points}")
    devs, counts = (_from_rate(arr, mm) if input == "rate" else _from_angle(arr * fs, mm))
    return EstimatorOutput(kind="oadev", m=mm, tau_s=mm / fs, dev=devs, n=counts)


def _from_rate(y: FloatArray, m: IntArray) -> tuple[FloatArray, IntArray]:
    missing = np.isnan(y)
    filled = np.where(missing, 0.0, y - np.nanmean(y))
    s = np.r_[0.0, np.cumsum(filled)]             # the phase x fs, NaN read as 0
    c = np.r_[0, np.cumsum(missing)]              # missing samples before each point
    devs, counts = np.empty(m.size), np.empty(m.size, dtype=np.int64)
    for i, mi in enumerate(m.tolist()):
        d = s[2 * mi:] - 2.0 * s[mi:-mi] + s[:-2 * mi]
        valid = (c[2 * mi:] - c[:-2 * mi]) == 0
        devs[i], counts[i] = _deviation(d[valid], mi)
    return devs, counts


def _from_angle(x: FloatArray, m: IntArray) -> tuple[FloatArray, IntArray]:
    devs, counts = np.empty(m.size), np.empty(m.size, dtype=np.int64)
    for i, mi in enumerate(m.tolist()):
        d = x[2 * mi:] - 2.0 * x[mi:-mi] + x[:-2 * mi]
        devs[i], counts[i] = _deviation(d[np.isfinite(d)], mi)
    return devs, counts


def _deviation(d: FloatArray, m: int) -> tuple[float, int]:
    """sqrt(sum d^2 / (2 n)) / m: the deviation in rate units (d is phase x fs)."""
    n = int(d.size)
    if n < 2:
        return float("nan"), n
    return float(np.sqrt(np.dot(d, d) / (2.0 * n)) / m), n
