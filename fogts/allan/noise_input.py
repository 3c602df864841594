"""The Allan curve a noise fit reads: :func:`read_fit_curve` checks it, returns a FitCurve.

Points with a non-finite or zero deviation are set aside (``excluded``).  Each point needs an
equivalent number of degrees of freedom: the Allan result's (Greenhall's algorithm) or, where
that is missing, IEEE Std 952-1997 C.3's ``N/m - 1`` (the percentage error of sigma is
``1/sqrt(2(N/m - 1))``); ``edf_source`` records which.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

from fogts._typing import FloatArray, IntArray
from fogts.errors import DataError
from fogts.units import parse_sensor_unit

__all__ = ["FITTABLE_KINDS", "FitCurve", "read_fit_curve"]

#: Allan-variance kinds whose expected value follows the IEEE-952 tau laws.  (The modified
#: and Hadamard variances have other constants, so their curves cannot be fitted here.)
FITTABLE_KINDS: tuple[str, ...] = ("adev", "oadev", "totdev")


@dataclass(frozen=True)
class FitCurve:
    """The usable points of one Allan curve, with their EDF and what the covariance needs.

    Attributes
    ----------
    tau, dev, edf : ndarray
        Averaging times (s), deviations and equivalent degrees of freedom of the points
        with a finite, positive deviation.
    edf_source : str
        ``"result"``, ``"ieee952"`` (N/m - 1) or ``"mixed"``.
    units, kind, axis : str
        Canonical rate (or specific-force) unit, Allan kind and axis name of the curve.
    excluded : list of float
        Taus set aside for a non-finite or zero deviation.
    m : ndarray of int or None
        Averaging factors of the usable points (None if not all known).
    n_samples : int or None
    fs_hz : float or None
    ci_low, ci_high : ndarray or None
        The result's confidence bounds of the usable points (None when it has none): the
        slope read-offs judge the floor with the intervals the curve read-out shows.
    """

    tau: FloatArray
    dev: FloatArray
    edf: FloatArray
    edf_source: str
    units: str
    kind: str
    axis: str
    excluded: list[float]
    m: IntArray | None
    n_samples: int | None
    fs_hz: float | None
    ci_low: FloatArray | None = None
    ci_high: FloatArray | None = None


def read_fit_curve(res: Any) -> FitCurve:
    """Check an Allan result (or a duck-typed equivalent) and take its usable points.

    Raises
    ------
    DataError
        A multi-axis result; missing attributes; a kind whose tau laws differ; malformed
        arrays; a usable point without an EDF.
    """
    kind, units, tau, dev = _checked_arrays(res)
    n = tau.size
    given = _attr_array(res, "edf", n)
    m_all = _attr_array(res, "m", n)
    n_samples = getattr(res, "n_samples", None)
    edf = given.copy()
    missing_edf = ~(np.isfinite(edf) & (edf > 0))
    if np.any(missing_edf) and n_samples is not None:
        # IEEE Std 952-1997 C.3: %error of sigma = 1/sqrt(2(N/m - 1)), i.e. edf = N/m - 1
        edf[missing_edf] = np.maximum(float(n_samples) / m_all[missing_edf] - 1.0, 1.0)
    ok = np.isfinite(dev) & (dev > 0)
    excluded = [float(t) for t in tau[~ok]]
    usable = np.isfinite(edf) & (edf > 0)
    if not np.all(usable[ok]):
        bad = float(tau[ok & ~usable][0])
        raise DataError(f"allan_result has no usable edf at tau = {bad:.6g} s (and no "
                        "n_samples and m to fall back on IEEE 952's N/m - 1)")
    from_result = np.isfinite(given[ok]) & (given[ok] > 0)
    source = ("result" if np.all(from_result) else "ieee952" if not np.any(from_result)
              else "mixed")
    fs = getattr(res, "fs_hz", None)
    m_ok = m_all[ok]
    have_m = bool(np.all(np.isfinite(m_ok)) and np.all(m_ok >= 1))
    return FitCurve(tau=tau[ok], dev=dev[ok], edf=edf[ok], edf_source=source, units=units,
                    kind=kind, axis=str(getattr(res, "axis", "")), excluded=excluded,
                    m=m_ok.astype(np.int64) if have_m else None,
                    n_samples=int(n_samples) if n_samples is not None else None,
                    fs_hz=float(fs) if fs is not None and float(fs) > 0 else None,
                    ci_low=_bound(res, "ci_low", n, ok), ci_high=_bound(res, "ci_high", n, ok))


def _bound(res: Any, name: str, n: int, ok: np.ndarray) -> FloatArray | None:
    """The usable points' confidence bound ``name`` of ``res``; None if it has none."""
    value = getattr(res, name, None)
    values = np.asarray(value, dtype=np.float64) if value is not None else None
    if values is None or values.shape != (n,) or not np.any(np.isfinite(values[ok])):
        return None
    return values[ok]


def _checked_arrays(res: Any) -> tuple[str, str, FloatArray, FloatArray]:
    """``(kind, units, tau, dev)`` of a single fittable curve with a valid tau grid."""
    if hasattr(res, "curves") and not hasattr(res, "dev"):
        axes = ", ".join(map(str, getattr(res, "axes", ())))
        raise DataError(f"allan_result is a multi-axis result set (axes: {axes}); fit one "
                        "curve at a time, e.g. [fit_noise(c) for c in result.curves]")
    missing = [a for a in ("tau_s", "dev", "units", "kind") if not hasattr(res, a)]
    if missing:
        raise DataError(f"allan_result must be an AllanResult (with tau_s, dev, units, "
                        f"kind); {type(res).__name__} lacks {', '.join(missing)}")
    kind = str(res.kind)
    if kind not in FITTABLE_KINDS:
        raise DataError(f"allan_result.kind must be one of {', '.join(FITTABLE_KINDS)} (the "
                        f"IEEE-952 tau laws hold for the Allan variance), got {kind!r}")
    units = parse_sensor_unit(str(res.units), "allan_result.units")
    tau = np.asarray(res.tau_s, dtype=np.float64)
    dev = np.asarray(res.dev, dtype=np.float64)
    if tau.ndim != 1 or tau.shape != dev.shape:
        raise DataError(f"allan_result.tau_s and .dev must be 1-D of equal length, got "
                        f"shapes {tau.shape} and {dev.shape}")
    if not np.all(np.isfinite(tau) & (tau > 0)):
        raise DataError("allan_result.tau_s must be finite and > 0")
    if np.any(np.diff(tau) <= 0):
        raise DataError("allan_result.tau_s must be strictly increasing")
    return kind, units, tau, dev


def _attr_array(res: Any, name: str, n: int) -> FloatArray:
    value = getattr(res, name, None)
    if value is None:
        return np.full(n, np.nan)
    arr = np.asarray(value, dtype=np.float64)
    if arr.shape != (n,):
        raise DataError(f"allan_result.{name} must have the shape of tau_s ({n},), got "
                        f"{arr.shape}")
    return arr
