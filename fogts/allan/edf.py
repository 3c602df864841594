"""Equivalent degrees of freedom (EDF) of Allan-family variance estimates.

An estimate with ``edf`` equivalent degrees of freedom is distributed as
:math:`\\sigma^2 \\chi^2_{edf} / edf` (NIST SP1065 section 5.3), and the edf depends on the
power-law noise (``alpha``, :mod:`fogts.allan.noise_identification`) at that tau:

* Allan, modified Allan and Hadamard families: C. A. Greenhall and W. J. Riley,
  "Uncertainty of stability variances based on finite differences", 35th PTTI (2003),
  section 5 (cases 1-4), with the generalized autocovariances of their eqs. 7-10 summed
  term by term up to ``J = 100`` and Tables 1-3 beyond;
* total deviation: the SP1065 section 5.3 approximations.
"""

from __future__ import annotations

import math

import numpy as np
import numpy.typing as npt

from fogts._typing import FloatArray
from fogts._validate import check_choice, check_int
from fogts.allan._checks import check_alpha, check_m, check_totdev_m
from fogts.allan.taus import KINDS
from fogts.errors import InsufficientDataError

__all__ = ["edf_for"]

# Per estimator: (order of the phase difference d, modified?, overlapped?)  Greenhall &
# Riley (2003) section 2: F = 1 for the modified variance, F = m for the unmodified ones;
# S = m for overlapped estimators, S = 1 for non-overlapped ones.
_FAMILY: dict[str, tuple[int, bool, bool]] = {
    "adev": (2, False, False),
    "oadev": (2, False, True),
    "mdev": (2, True, True),
    "hdev": (3, False, False),
    "ohdev": (3, False, True),
}

_J_MAX = 100  # Greenhall & Riley (2003), section 5: largest sum evaluated term by term.

# Greenhall & Riley (2003), Table 1 (modified variances, F = 1): (a0, a1) by (alpha, d).
_TABLE1: dict[tuple[int, int], tuple[float, float]] = {
    (2, 1): (2 / 3, 1 / 3), (2, 2): (7 / 9, 1 / 2), (2, 3): (22 / 25, 2 / 3),
    (1, 1): (0.840, 0.345), (1, 2): (0.997, 0.616), (1, 3): (1.141, 0.843),
    (0, 1): (1.079, 0.368), (0, 2): (1.033, 0.607), (0, 3): (1.184, 0.848),
    (-1, 2): (1.048, 0.534), (-1, 3): (1.180, 0.816),
    (-2, 2): (1.302, 0.535), (-2, 3): (1.175, 0.777),
    (-3, 3): (1.194, 0.703),
    (-4, 3): (1.489, 0.702),
}
# Table 2 (unmodified variances, F = m): (a0, a1) by (alpha, d); the alpha = 2 row is the
# exact formula of case 4, implemented in _edf_white_pm_unmodified.
_TABLE2: dict[tuple[int, int], tuple[float, float]] = {
    (1, 1): (78.6, 25.2), (1, 2): (790.0, 410.0), (1, 3): (9950.0, 6520.0),
    (0, 1): (2 / 3, 1 / 6), (0, 2): (2 / 3, 1 / 3), (0, 3): (7 / 9, 1 / 2),
    (-1, 2): (0.852, 0.375), (-1, 3): (0.997, 0.617),
    (-2, 2): (1.079, 0.368), (-2, 3): (1.033, 0.607),
    (-3, 3): (1.053, 0.553),
    (-4, 3): (1.302, 0.535),
}
# Table 3 (unmodified variances, alpha = 1): (b0, b1) by d, sz(0; m, 1, d) ~ b0 + b1 ln m.
_TABLE3: dict[int, tuple[float, float]] = {1: (6.0, 4.0), 2: (15.23, 12.0), 3: (47.8, 40.0)}

# NIST SP1065 section 5.3, total variance: edf = b * (T / tau) - c, by alpha.
_TOTDEV_BC: dict[int, tuple[float, float]] = {0: (1.50, 0.0), -1: (1.17, 0.22),
                                              -2: (0.93, 0.36)}


def _sw(t: FloatArray, alpha: int) -> FloatArray:
    """Generalized autocovariance of the power-law process w (Greenhall & Riley 2003,
    eq. 7), up to a constant factor per alpha (it cancels in the EDF)."""
    a = np.abs(t)
    if alpha % 2 == 0:
        p = 3 - alpha  # 2 -> |t|, 0 -> |t|^3, -2 -> |t|^5, -4 -> |t|^7
        sign = -1.0 if alpha in (2, -2) else 1.0
        return sign * a**p
    lg = np.log(np.where(a > 0, a, 1.0))
    p = 3 - alpha  # 1 -> t^2 ln|t|, -1 -> t^4 ln|t|, -3 -> t^6 ln|t|
    sign = -1.0 if alpha == -1 else 1.0
    return sign * a**p * lg


def _sx_flicker_pm(t: FloatArray, f: float) -> FloatArray:
    """``sx(t; F, 1) = F^2 [2 sw(t) - sw(t - 1/F) - sw(t + 1/F)]`` with ``sw = t^2 ln|t|``,
    evaluated without cancellation for large F (the case alpha = 1, F = m).

    For ``|t| > 4/F`` the central second difference is summed as its series,
    ``sx = -[2 ln|t| + 3 - 4 sum_{k>=2} (2k-3)!/(2k)! (h/t)^(2k-2)]`` with ``h = 1/F``
    (exact Taylor expansion; 14 terms reach double precision for ``(h/t)^2 < 1/16``).
    """
    h = 1.0 / f
    a = np.abs(t)
    far = a > 4.0 * h
    out = np.empty_like(t)
    near = ~far
    if np.any(near):
        tn = t[near]
        out[near] = f * f * (2.0 * _sw(tn, 1) - _sw(tn - h, 1) - _sw(tn + h, 1))
    if np.any(far):
        af = a[far]
        u = (h / af) ** 2
        series = np.zeros_like(af)
        coef_power = np.ones_like(af)
        for k in range(2, 16):
            coef_power = coef_power * u
            series += math.factorial(2 * k - 3) / math.factorial(2 * k) * coef_power
        out[far] = -(2.0 * np.log(af) + 3.0 - 4.0 * series)
    return out


def _sx(t: FloatArray, f: float, alpha: int) -> FloatArray:
    """Generalized autocovariance of x (Greenhall & Riley 2003, eq. 8); ``f = inf`` gives
    the limit ``sw(t; alpha + 2)``."""
    if math.isinf(f):
        return _sw(t, alpha + 2)
    if alpha == 1 and f > 1.0:
        return _sx_flicker_pm(t, f)
    h = 1.0 / f
    return f * f * (2.0 * _sw(t, alpha) - _sw(t - h, alpha) - _sw(t + h, alpha))


def _sz(t: FloatArray, f: float, alpha: int, d: int) -> FloatArray:
    """Generalized autocovariance of the d-th difference z (Greenhall & Riley 2003, eq. 9):
    ``sum_k (-1)^k C(2d, d+k) sx(t + k)``."""
    out = np.zeros_like(t)
    for k in range(-d, d + 1):
        out += (-1.0) ** k * math.comb(2 * d, d + k) * _sx(t + k, f, alpha)
    return out


def _basic_sum(j: float, mm: float, s: float, f: float, alpha: int, d: int
               ) -> tuple[float, float]:
    """Greenhall & Riley (2003) eq. 10,
    ``sz(0)^2 + 2 sum_{j=1}^{J-1} (1 - j/M) sz(j/S)^2 + (1 - J/M) sz(J/S)^2``, and
    ``sz(0)^2`` (the normalisation of its case 1-3 EDFs); ``sz`` is evaluated at the
    ``J + 1`` lags in one call."""
    jj = int(j)
    lags = np.arange(0, jj + 1, dtype=np.float64)
    sz = _sz(lags / s, f, alpha, d)
    idx, szj = lags[1:jj], sz[1:jj]
    sz0, szJ = float(sz[0]), float(sz[jj])
    total = sz0 * sz0 + 2.0 * float(np.sum((1.0 - idx / mm) * szj * szj)) \
        + (1.0 - jj / mm) * szJ * szJ
    return total, sz0 * sz0


def _normalised_sum(j: float, mm: float, s: float, f: float, alpha: int, d: int,
                    count: float) -> float:
    """``basic_sum / (count sz(0)^2)``: the inverse EDF of Greenhall & Riley (2003) cases
    1-3 when the sum is evaluated term by term."""
    total, sz0_squared = _basic_sum(j, mm, s, f, alpha, d)
    return total / (count * sz0_squared)


def _edf_white_pm_unmodified(d: int, s: int, mm: float) -> float:
    """Case 4 of Greenhall & Riley (2003) (alpha = 2, F = m), summed exactly.

    For white PM the d-th differences at lag m are correlated only at lags that are
    multiples of m, with correlation ``rho_k = (-1)^k C(2d, d+k) / C(2d, d)``; with M terms
    at stride m/S, ``1/edf = sum_{|k| < min(M/S, d+1)} (M - |k| S) rho_k^2 / M^2``.  For
    ``M/S > d`` this is the paper's ``(a0 - a1 r^-1) / M`` with ``a0 = C(4d,2d)/C(2d,d)^2``
    and ``a1 = d/2``.
    """
    c0 = math.comb(2 * d, d)
    r = mm / s
    total = 0.0
    for k in range(-d, d + 1):
        if abs(k) < r:
            total += (mm - abs(k) * s) * (math.comb(2 * d, d + k) / c0) ** 2
    return mm * mm / total


def _greenhall_edf(alpha: int, d: int, m: int, modified: bool, overlapped: bool, n: int,
                   *, j_max: int = _J_MAX) -> float:
    """EDF of one (alpha, d, m, F, S, N) by the algorithm of Greenhall & Riley (2003),
    section 5 (cases 1-4)."""
    f = 1.0 if modified else float(m)
    s = float(m) if overlapped else 1.0
    length = m / f + m * d  # L: span of the filter on the phase samples
    mm = 1.0 + math.floor(s * (n - length) / m)  # M: number of summands
    j = min(mm, (d + 1) * s)
    r = mm / s
    if modified:  # case 1: F = 1, any alpha
        if j <= j_max:
            inv = _normalised_sum(j, mm, s, 1.0, alpha, d, mm)
        elif r > d + 1:
            a0, a1 = _TABLE1[(alpha, d)]
            inv = (a0 - a1 / r) / r
        else:
            mp = j_max / r
            inv = _normalised_sum(j_max, j_max, mp, 1.0, alpha, d, j_max)
        return 1.0 / inv
    if alpha == 2:  # case 4
        return _edf_white_pm_unmodified(d, int(s), mm)
    if alpha == 1:  # case 3
        if j <= j_max:
            inv = _normalised_sum(j, mm, s, float(m), 1, d, mm)
        else:
            b0, b1 = _TABLE3[d]
            norm = (b0 + b1 * math.log(m)) ** 2
            if r > d + 1:
                a0, a1 = _TABLE2[(1, d)]
                inv = (a0 - a1 / r) / (norm * r)
            else:
                mp = j_max / r
                inv = _basic_sum(j_max, j_max, mp, mp, 1, d)[0] / (norm * j_max)
        return 1.0 / inv
    # case 2: F = m, alpha <= 0
    if j <= j_max:
        fp = float(m) if m * (d + 1) <= j_max else math.inf
        inv = _normalised_sum(j, mm, s, fp, alpha, d, mm)
    elif r > d + 1:
        a0, a1 = _TABLE2[(alpha, d)]
        inv = (a0 - a1 / r) / r
    else:
        mp = j_max / r
        inv = _normalised_sum(j_max, j_max, mp, math.inf, alpha, d, j_max)
    return 1.0 / inv



def _edf_totdev(alpha: int, m: int, n: int) -> float:
    """Total-deviation EDF (NIST SP1065 section 5.3).

    FM noises: ``edf = b (T/tau) - c`` with ``T/tau = N/m`` (N phase points) and (b, c) =
    (1.50, 0) white FM, (1.17, 0.22) flicker FM, (0.93, 0.36) random-walk FM.  PM noises,
    for which SP1065 gives no TOTVAR coefficients, use the simple Allan-variance EDF
    approximations of SP1065 section 5.3 (Howe, Allan & Barnes 1981):
    ``(N+1)(N-2m) / (2(N-m))`` for white PM and
    ``exp(sqrt(ln((N-1)/(2m)) ln((2m+1)(N-1)/4)))`` for flicker PM (what Stable32 reports).
    """
    if alpha in _TOTDEV_BC:
        b, c = _TOTDEV_BC[alpha]
        return b * n / m - c
    if alpha == 2:
        return (n + 1.0) * (n - 2.0 * m) / (2.0 * (n - m))
    return math.exp(math.sqrt(math.log((n - 1.0) / (2.0 * m))
                              * math.log((2.0 * m + 1.0) * (n - 1.0) / 4.0)))


def edf_for(kind: str, alpha: npt.ArrayLike, m: npt.ArrayLike, n_phase: int) -> FloatArray:
    """Equivalent degrees of freedom of an Allan-family variance estimate.

    Greenhall & Riley (2003) "Uncertainty of stability variances based on finite
    differences" for the Allan (d = 2), modified Allan (d = 2, F = 1) and Hadamard (d = 3)
    families, overlapped (S = m) or not (S = 1); NIST SP1065 section 5.3 approximations for
    ``totdev``.

    Parameters
    ----------
    kind : {"adev", "oadev", "mdev", "hdev", "ohdev", "totdev"}
        Estimator.
    alpha : int or array_like of int
        Power-law exponent of the rate spectrum: 2..-2 (down to -4 for the Hadamard family).
    m : int or array_like of int
        Averaging factors; broadcast against ``alpha``.
    n_phase : int
        Number of phase points, i.e. rate samples + 1.

    Returns
    -------
    ndarray
        EDF per point (1-D).

    Raises
    ------
    DataError
        Unknown ``kind``, non-integer or out-of-range ``alpha`` or ``m``.
    InsufficientDataError
        An ``m`` the record is too short for (fewer phase points than the estimator's span).

    Examples
    --------
    >>> edf_for("oadev", 0, [1, 10, 100], 1001).round(2).tolist()
    [782.03, 135.07, 12.81]
    >>> edf_for("totdev", -2, 10, 1001).round(3).tolist()
    [92.733]
    """
    kind = check_choice("kind", kind, KINDS)
    n = check_int("n_phase", n_phase, minimum=2)
    a_arr, m_arr = np.broadcast_arrays(check_alpha(alpha, kind), check_m(m))
    out = np.empty(a_arr.shape, dtype=np.float64)
    if kind == "totdev":
        check_totdev_m(m_arr, n)
    for i, (ai, mi) in enumerate(zip(a_arr.tolist(), m_arr.tolist(), strict=True)):
        if kind == "totdev":
            out[i] = _edf_totdev(ai, mi, n)
            continue
        d, modified, overlapped = _FAMILY[kind]
        span = (1 if not modified else mi) + mi * d
        if span > n:
            raise InsufficientDataError(
                f"m={mi} is too large for {kind} with n_phase={n}: the estimator spans "
                f"{span} phase points")
        out[i] = _greenhall_edf(ai, d, mi, modified, overlapped, n)
    return out
