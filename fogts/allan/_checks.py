"""Argument checks shared by noise identification, EDF and bias: averaging factors ``m``
and power-law exponents ``alpha`` as int64 arrays, with errors that name the argument."""

from __future__ import annotations

from typing import Any

import numpy as np

from fogts._typing import IntArray
from fogts.errors import DataError, InsufficientDataError

__all__ = ["check_alpha", "check_m", "check_totdev_m"]


def _int_array(name: str, value: Any, allowed: str) -> IntArray:
    """``value`` as an int64 array (at least 1-D) if every element is a whole number."""
    arr = np.atleast_1d(np.asarray(value))
    if arr.dtype.kind not in "iuf":
        raise DataError(f"{name} must hold {allowed}, got dtype {arr.dtype}")
    if arr.dtype.kind == "f":
        whole = np.isfinite(arr) & (arr == np.round(arr))
        if not whole.all():
            raise DataError(f"{name} must hold {allowed}, got {float(arr[~whole][0])!r}")
    return arr.astype(np.int64)


def check_m(m: Any) -> IntArray:
    """Averaging factors: a non-empty 1-D array of integers >= 1."""
    arr = np.atleast_1d(np.asarray(m))
    if arr.ndim != 1 or arr.size == 0:
        raise DataError(f"m must be a non-empty 1-D array of averaging factors, got shape "
                        f"{arr.shape}")
    out = _int_array("m", arr, "integers >= 1")
    if np.any(out < 1):
        raise DataError(f"m must hold integers >= 1, got {int(out[out < 1][0])}")
    return out


def check_alpha(alpha: Any, kind: str) -> IntArray:
    """Power-law exponents for which the EDF of ``kind`` is defined."""
    out = _int_array("alpha", alpha, "integers")
    # The variance converges for alpha + 2d > 1 (Greenhall & Riley 2003, section 2); the
    # SP1065 totdev table covers alpha in [-2, 2].
    lowest = -4 if kind in ("hdev", "ohdev") else -2
    outside = (out > 2) | (out < lowest)
    if np.any(outside):
        raise DataError(f"alpha must be an integer in [{lowest}, 2] for kind={kind!r}, "
                        f"got {int(out[outside][0])}")
    return out


def check_totdev_m(m: IntArray, n: int) -> None:
    """Raise unless every ``m`` leaves a totdev (``2 m <= n_phase - 1``)."""
    too_big = 2 * m > n - 1
    if np.any(too_big):
        raise InsufficientDataError(f"m={int(m[too_big].flat[0])} is too large for totdev with "
                                    f"n_phase={n}: needs 2*m <= n_phase - 1 = {n - 1}")

