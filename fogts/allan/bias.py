"""Noise-dependent bias of the total variance (Howe 1999)."""

from __future__ import annotations

import math

import numpy as np
import numpy.typing as npt

from fogts._typing import FloatArray
from fogts._validate import check_int
from fogts.allan._checks import check_alpha, check_m, check_totdev_m

__all__ = ["totdev_bias"]

# TOTVAR bias (Howe 1999, Table 1; NIST SP1065, total variance with eq. 25): E[TOTVAR] / AVAR =
# 1 - a tau/T, a = 1/(3 ln 2) for flicker FM and 3/4 for random-walk FM (0 otherwise).
_TOTVAR_BIAS_A: dict[int, float] = {-1: 1.0 / (3.0 * math.log(2.0)), -2: 0.75}


def totdev_bias(alpha: npt.ArrayLike, m: npt.ArrayLike, n_phase: int) -> FloatArray:
    """Bias ratio ``E[TOTVAR] / AVAR`` of the total variance, by noise type.

    TOTVAR is unbiased for white PM, flicker PM and white FM noise, and low for flicker FM
    and random-walk FM: ``B = 1 - a tau/T`` with ``a = 1/(3 ln 2) = 0.481`` (flicker FM,
    ``alpha = -1``) and ``a = 3/4`` (random-walk FM, ``alpha = -2``), ``tau/T = m /
    (n_phase - 1)`` (D. A. Howe, "Total variance explained", Proc. 1999 Joint Meeting
    EFTF/IEEE IFCS, pp. 1093-1099, Table 1; NIST SP1065, total variance, eq. 25).
    Dividing TOTVAR by ``B`` (the deviation by ``sqrt(B)``) gives the bias-corrected total
    deviation that Stable32 reports when it has identified a noise type at the point (its
    octave files with confidence intervals); its all-tau files without intervals are
    uncorrected.

    Parameters
    ----------
    alpha, m : int or array_like of int
        Power-law exponents of the rate spectrum (2..-2) and averaging factors, broadcast
        against each other.
    n_phase : int
        Phase points of the record (rate samples + 1).

    Returns
    -------
    ndarray
        ``B`` per point (1-D): 1 for ``alpha >= 0``, below 1 for ``alpha = -1, -2``.

    Raises
    ------
    DataError
        Non-integer or out-of-range ``alpha`` or ``m``, or ``n_phase < 2``.
    InsufficientDataError
        An ``m`` above ``(n_phase - 1) / 2`` (no totdev there).

    Examples
    --------
    >>> totdev_bias([0, -1, -2], 100, 1001).round(4).tolist()
    [1.0, 0.9519, 0.925]
    """
    n = check_int("n_phase", n_phase, minimum=2)
    a_arr, m_arr = np.broadcast_arrays(check_alpha(alpha, "totdev"), check_m(m))
    check_totdev_m(m_arr, n)
    a = np.array([_TOTVAR_BIAS_A.get(int(v), 0.0) for v in a_arr.ravel()], dtype=np.float64)
    return np.asarray(1.0 - a * m_arr.ravel() / (n - 1.0), dtype=np.float64)
