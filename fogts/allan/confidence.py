"""Noise identification, equivalent degrees of freedom and chi-squared confidence intervals.

An Allan-family variance estimate with ``edf`` equivalent degrees of freedom is distributed
as :math:`\\sigma^2 \\chi^2_{edf} / edf`, so its confidence interval follows from the edf,
and the edf depends on the dominant power-law noise at that tau.  This module does the three
steps of NIST SP1065 (W. J. Riley, *Handbook of Frequency Stability Analysis*, 2008):

1. **Noise identification** (SP1065 section 5.2), per averaging factor ``m``: the power-law
   exponent ``alpha`` of the rate ("frequency") spectrum :math:`S_y(f) \\propto f^\\alpha`,
   rounded to one of ``2`` (white PM: quantization noise Q), ``1`` (flicker PM), ``0``
   (white FM: angle random walk N), ``-1`` (flicker FM: bias instability B) or ``-2``
   (random-walk FM: rate random walk K).

   * ``"acf"``: the lag-1 autocorrelation method of W. J. Riley and C. A. Greenhall,
     "Power law noise identification using the lag 1 autocorrelation", 18th EFTF (2004),
     applied to the rate averaged over non-overlapping blocks of ``m`` samples.
   * ``"b1"``: when fewer than 30 decimated phase points remain, Barnes' B1 bias ratio
     (standard variance / Allan variance, SP1065 section 5.2), supplemented by
   * ``"rn"``: the ratio R(n) = Mod sigma^2 / sigma^2 (SP1065 section 5.2), which the B1
     ratio needs to separate white PM, flicker PM and white FM.
   * ``"none"``: nothing could be identified at this tau (fewer than 4 averaged points, or
     a constant series); the alpha of the nearest identified tau is used instead (white FM,
     ``alpha = 0``, if there is none) and the point is marked ``"none"``.

2. **EDF** (SP1065 section 5.3): C. A. Greenhall and W. J. Riley, "Uncertainty of stability
   variances based on finite differences", 35th PTTI (2003) for the Allan, modified Allan
   and Hadamard families; the SP1065 approximations for the total deviation.

3. **Chi-squared interval** at a chosen confidence (SP1065 section 5.3, eq. for
   :math:`\\sigma^2 \\cdot edf / \\chi^2`), with :func:`scipy.stats.chi2.ppf`.

:func:`confidence_table` does all three in one call; :func:`fogts.allan.allan_deviation`
uses it for every curve.  :func:`totdev_bias` gives the noise-dependent bias of the total
variance (Howe 1999), which Stable32 divides out of its TOTDEV at flicker and random-walk
FM points.

Checked against Stable32's MinSigma/MaxSigma columns (PHASE.DAT, OCXO and GPS reference
files: at most 6e-4 relative with Stable32's alpha, except one flicker-PM totdev point at
3.3e-3), Stable32's noise identification (GPS 94 of 96 taus, PHASE.DAT 49 of 49, OCXO 66
of 77; every lag-1-ACF point agrees), ``allantools.edf_greenhall`` (1e-13 relative
typically) and exact white-PM EDFs; see ``tests/test_allan_confidence.py``.
"""

from __future__ import annotations

import itertools
import math
from dataclasses import dataclass
from typing import Any

import numpy as np
import numpy.typing as npt
import pandas as pd
from scipy import stats

from fogts._typing import FloatArray, IntArray
from fogts._validate import check_choice, check_fraction, check_int, check_positive, to_float_array
from fogts.allan.estimators import mdev, oadev, phase_from_rate
from fogts.allan.taus import KINDS
from fogts.errors import DataError, InsufficientDataError

__all__ = [
    "ACF_MIN_POINTS",
    "ALPHA_METHODS",
    "B1_MIN_POINTS",
    "ChiSquaredInterval",
    "ConfidenceTable",
    "chi2_interval",
    "confidence_table",
    "edf_for",
    "identify_noise",
    "totdev_bias",
]

#: Fewest decimated phase points (``n // m + 1``) for the lag-1 autocorrelation method;
#: SP1065 section 5.2 and Riley & Greenhall (2004) ask for "at least about 30".
ACF_MIN_POINTS = 30
#: Fewest averaged rate values for the B1 ratio (below it the point is ``"none"``).
B1_MIN_POINTS = 4
#: The values of ``alpha_method``.
ALPHA_METHODS: tuple[str, ...] = ("acf", "b1", "rn", "none")
#: The power-law exponents that are identified (frequency-noise convention).
ALPHAS: tuple[int, ...] = (2, 1, 0, -1, -2)

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


# =========================================================================== results
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
        nearest identified tau; see the module docstring).
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
        def num(v: float) -> float | None:
            return float(v) if math.isfinite(v) else None

        points = [{"tau": num(t), "m": int(m), "dev": num(d), "alpha": int(a),
                   "alpha_method": meth, "edf": num(e), "ci_low": num(lo), "ci_high": num(hi)}
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


# =========================================================================== validation
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


def _check_m(m: Any) -> IntArray:
    arr = np.atleast_1d(np.asarray(m))
    if arr.ndim != 1 or arr.size == 0:
        raise DataError(f"m must be a non-empty 1-D array of averaging factors, got shape "
                        f"{arr.shape}")
    out = _int_array("m", arr, "integers >= 1")
    if np.any(out < 1):
        raise DataError(f"m must hold integers >= 1, got {int(out[out < 1][0])}")
    return out


def _check_alpha(alpha: Any, kind: str) -> IntArray:
    out = _int_array("alpha", alpha, "integers")
    # The variance converges for alpha + 2d > 1 (Greenhall & Riley 2003, section 2); the
    # SP1065 totdev table covers alpha in [-2, 2].
    lowest = -4 if kind in ("hdev", "ohdev") else -2
    outside = (out > 2) | (out < lowest)
    if np.any(outside):
        raise DataError(f"alpha must be an integer in [{lowest}, 2] for kind={kind!r}, "
                        f"got {int(out[outside][0])}")
    return out


# =========================================================================== identification
def _lag1(c: FloatArray) -> float:
    """Lag-1 autocorrelation of a zero-mean series (Riley & Greenhall 2004, eq. 2);
    NaN for a constant series."""
    den = float(np.dot(c, c))
    if not den > 0.0:
        return math.nan
    return float(np.dot(c[:-1], c[1:])) / den


def _acf_alpha(xd: FloatArray, d_max: int) -> float:
    """Riley & Greenhall (2004) lag-1 ACF noise estimate for frequency data.

    ``xd`` is the phase decimated by m (``N + 1`` points), so ``z = diff(xd)`` are the N
    rates averaged over blocks of m (the scale ``1/m`` does not matter).  A least-squares
    line is removed from ``z`` (a linear rate drift); the series is then differenced until
    ``delta = r1 / (1 + r1)`` falls below 0.25 (stationary) or ``d_max`` differences are
    taken, and ``p = -2 (delta + d)`` estimates alpha (``theta = 0`` for frequency data).

    The detrended lag-1 sums are formed from the sums of the centred series ``c`` (no
    trend array is built): with ``u_t = t - (N-1)/2``, ``b = sum(u c) / sum(u^2)``,
    ``sum(e^2) = sum(c^2) - b^2 sum(u^2)`` and
    ``sum(e_t e_t+1) = sum(c_t c_t+1) - b [2 sum(u c) - c_N-1 u_N-1 - c_N-1 - c_0 u_0 + c_0]
    + b^2 [sum(u^2) - u_N-1^2 - u_N-1]``; ``sum(t z_t) = N xd_N - sum_{s>=1} xd_s``.
    """
    n = xd.size - 1
    z = np.diff(xd)
    zbar = (float(xd[-1]) - float(xd[0])) / n
    z -= zbar
    stt = n * (n * n - 1.0) / 12.0
    if n < 3 or not stt > 0.0:
        return math.nan
    t_z = n * float(xd[-1]) - float(np.sum(xd[1:]))  # sum_t t z_t
    suc = t_z - zbar * n * (n - 1.0) / 2.0  # sum_t u_t c_t = sum_t t c_t (sum c = 0)
    b = suc / stt
    u0, ul = -(n - 1.0) / 2.0, (n - 1.0) / 2.0
    c0, cl = float(z[0]), float(z[-1])
    den = float(np.dot(z, z)) - b * b * stt
    num = (float(np.dot(z[:-1], z[1:])) - b * (2.0 * suc - cl * ul - cl - c0 * u0 + c0)
           + b * b * (stt - ul * ul - ul))
    if not den > 0.0 or not math.isfinite(num):
        return math.nan
    r1 = num / den
    d = 0
    w = z
    while True:
        delta = r1 / (1.0 + r1)
        if delta < 0.25 or d >= d_max:
            return -2.0 * (delta + d)
        # differencing the detrended series = differencing z, up to a constant that the
        # centring removes
        w = np.diff(w)
        if w.size < 2:
            return math.nan
        w -= w.mean()
        r1 = _lag1(w)
        if not math.isfinite(r1):
            return math.nan
        d += 1


def _b1_expected(n: int, mu: int) -> float:
    """Expected B1 ratio for ``n`` averaged values when AVAR ~ tau**mu (SP1065 section 5.2;
    Barnes' bias function, B1(N, r=1, mu) = N (1 - N**mu) / (2 (N - 1) (1 - 2**mu)))."""
    if mu == 0:
        return n * math.log(n) / (2.0 * (n - 1) * math.log(2.0))
    return n * (1.0 - float(n) ** mu) / (2.0 * (n - 1) * (1.0 - 2.0 ** mu))


def _rn_expected(m: int, alpha: int) -> float:
    """Expected R(n) = MVAR / AVAR at averaging factor ``m``.

    White PM: ``1/m`` (SP1065 section 5.2).  Flicker PM: the ratio of the SP1065 flicker-PM
    expressions ``3 ln(256/27) / (8 pi^2)`` and ``(1.038 + 3 ln(2 pi f_h tau)) / (4 pi^2)``
    with the Nyquist bandwidth ``f_h tau = m / 2``.  White FM: ``(m^2 + 1) / (2 m^2)``, the
    exact ratio for white rate noise (1 at m = 1, 1/2 for large m).
    """
    if alpha == 2:
        return 1.0 / m
    if alpha == 1:
        return 3.0 * math.log(256.0 / 27.0) / (2.0 * (1.038 + 3.0 * math.log(math.pi * m)))
    return (m * m + 1.0) / (2.0 * m * m)


def _b1_type(z: FloatArray, oavar: float) -> int:
    """B1 ratio decision (SP1065 section 5.2): -2, -1, 0, or 2 for "phase noise" (which the
    B1 ratio cannot split; R(n) does)."""
    n = z.size
    b1 = float(np.var(z, ddof=1)) / oavar
    # mu (AVAR ~ tau**mu) of RWFM, FFM, WFM and the PM types; decision boundaries are the
    # geometric means of adjacent expected values.
    expected = [(-2, _b1_expected(n, 1)), (-1, _b1_expected(n, 0)), (0, _b1_expected(n, -1)),
                (2, _b1_expected(n, -2))]
    for (a_hi, b_hi), (_, b_lo) in itertools.pairwise(expected):
        if b1 > math.sqrt(b_hi * b_lo):
            return a_hi
    return 2


def _rn_type(m: int, rn: float) -> int:
    """R(n) decision among white PM, flicker PM and white FM (geometric-mean boundaries)."""
    r_wpm, r_fpm, r_wfm = _rn_expected(m, 2), _rn_expected(m, 1), _rn_expected(m, 0)
    if rn < math.sqrt(r_wpm * r_fpm):
        return 2
    if rn < math.sqrt(r_fpm * r_wfm):
        return 1
    return 0


def _identify(y: FloatArray, m: IntArray, kind: str, oavar_given: FloatArray | None = None
              ) -> tuple[IntArray, tuple[str, ...]]:
    """Alpha and the method that found it, at every averaging factor (see the module doc).

    ``oavar_given`` (aligned with ``m``) are known overlapping Allan variances, reused for
    the B1 ratio instead of recomputing them (``confidence_table`` with ``kind="oadev"``).
    """
    d_max = 2 if kind in ("hdev", "ohdev") else 1  # phase d_max 3 / 2, in frequency terms
    n = y.size
    x = phase_from_rate(y)
    alpha = np.zeros(m.size, dtype=np.int64)
    methods = ["none"] * m.size
    b1_idx: list[int] = []
    for i, mi in enumerate(m.tolist()):
        blocks = n // mi
        if blocks + 1 >= ACF_MIN_POINTS:
            p = _acf_alpha(x[: blocks * mi + 1 : mi], d_max)
            if math.isfinite(p):
                alpha[i] = int(np.clip(np.rint(p), -2, 2))
                methods[i] = "acf"
        elif blocks >= B1_MIN_POINTS:
            b1_idx.append(i)
    if b1_idx:
        mb = m[b1_idx]
        if oavar_given is not None:
            oavar = np.asarray(oavar_given, dtype=np.float64)[b1_idx]
        else:
            oavar = oadev(y, fs_hz=1.0, m=mb).dev ** 2
        pm_idx: list[int] = []
        for i, mi, av in zip(b1_idx, mb.tolist(), oavar.tolist(), strict=True):
            if not av > 0.0:
                continue
            xd = x[: (n // mi) * mi + 1 : mi]
            alpha[i] = _b1_type(np.diff(xd) / mi, av)
            methods[i] = "b1"
            if alpha[i] == 2 and 3 * mi <= n:
                pm_idx.append(i)
        if pm_idx:
            mp = m[pm_idx]
            mvar = mdev(y, fs_hz=1.0, m=mp).dev ** 2
            av_of = dict(zip(mb.tolist(), oavar.tolist(), strict=True))
            for i, mi, mv in zip(pm_idx, mp.tolist(), mvar.tolist(), strict=True):
                alpha[i] = _rn_type(mi, mv / av_of[mi])
                methods[i] = "rn"
    known = np.array([meth != "none" for meth in methods])
    if not known.all():
        if known.any():
            logm = np.log(m.astype(np.float64))
            idx = np.flatnonzero(known)
            for i in np.flatnonzero(~known).tolist():
                dist = np.abs(logm[idx] - logm[i]) + 1e-9 * (m[idx] > m[i])  # ties: shorter
                alpha[i] = alpha[idx[int(np.argmin(dist))]]
        else:
            alpha[~known] = 0
    return alpha, tuple(methods)


def identify_noise(y: npt.ArrayLike | pd.Series, m: npt.ArrayLike, *, fs_hz: float,
                   kind: str) -> IntArray:
    """Dominant power-law noise exponent alpha at each averaging factor.

    The rate is averaged over non-overlapping blocks of ``m`` samples (the first difference
    of the phase decimated by ``m``); with at least 30 decimated phase points the lag-1
    autocorrelation method of Riley & Greenhall (2004) is used on the linearly detrended
    averages, otherwise the B1 ratio and R(n) of NIST SP1065 section 5.2.  Alpha is rounded
    and clipped to the five power-law types ``2, 1, 0, -1, -2`` (frequency convention:
    ``S_y(f) ~ f**alpha``; 2 = white PM / quantization, 0 = white FM / angle random walk,
    -1 = flicker FM / bias instability, -2 = random-walk FM / rate random walk).

    Parameters
    ----------
    y : array_like or pandas.Series
        Rate samples (any unit: the result is scale invariant).
    m : array_like of int
        Averaging factors.
    fs_hz : float
        Sample rate (checked; the identification itself depends only on ``m``).
    kind : {"adev", "oadev", "mdev", "hdev", "ohdev", "totdev"}
        Estimator; sets the largest number of differences (2 for the Hadamard family,
        1 otherwise, counted on the rate).

    Returns
    -------
    ndarray of int64
        Alpha per averaging factor.  Where nothing could be identified (fewer than 4
        averaged values) the nearest identified tau's alpha is used; use
        :func:`confidence_table` to see which method found each value.

    Examples
    --------
    >>> import numpy as np
    >>> rng = np.random.default_rng(1)
    >>> white = rng.standard_normal(4096)
    >>> identify_noise(white, [1, 4, 16], fs_hz=100.0, kind="oadev").tolist()
    [0, 0, 0]
    >>> identify_noise(np.cumsum(white), [1, 4, 16], fs_hz=100.0, kind="oadev").tolist()
    [-2, -2, -2]
    """
    kind = check_choice("kind", kind, KINDS)
    check_positive("fs_hz", fs_hz)
    arr = to_float_array(y, "y", min_length=2)
    mm = _check_m(m)
    return _identify(arr, mm, kind)[0]


# =========================================================================== Greenhall EDF
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


def _basic_sum(j: float, mm: float, s: float, f: float, alpha: int, d: int) -> float:
    """Greenhall & Riley (2003) eq. 10:
    ``sz(0)^2 + 2 sum_{j=1}^{J-1} (1 - j/M) sz(j/S)^2 + (1 - J/M) sz(J/S)^2``."""
    jj = int(j)
    idx = np.arange(1, jj, dtype=np.float64)
    szj = _sz(idx / s, f, alpha, d)
    sz0 = float(_sz(np.zeros(1), f, alpha, d)[0])
    szJ = float(_sz(np.array([jj / s]), f, alpha, d)[0])
    return sz0 * sz0 + 2.0 * float(np.sum((1.0 - idx / mm) * szj * szj)) \
        + (1.0 - jj / mm) * szJ * szJ


def _sz0_squared(f: float, alpha: int, d: int) -> float:
    v = float(_sz(np.zeros(1), f, alpha, d)[0])
    return v * v


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
            inv = _basic_sum(j, mm, s, 1.0, alpha, d) / (mm * _sz0_squared(1.0, alpha, d))
        elif r > d + 1:
            a0, a1 = _TABLE1[(alpha, d)]
            inv = (a0 - a1 / r) / r
        else:
            mp = j_max / r
            inv = _basic_sum(j_max, j_max, mp, 1.0, alpha, d) / (
                j_max * _sz0_squared(1.0, alpha, d))
        return 1.0 / inv
    if alpha == 2:  # case 4
        return _edf_white_pm_unmodified(d, int(s), mm)
    if alpha == 1:  # case 3
        if j <= j_max:
            inv = _basic_sum(j, mm, s, float(m), 1, d) / (mm * _sz0_squared(float(m), 1, d))
        else:
            b0, b1 = _TABLE3[d]
            norm = (b0 + b1 * math.log(m)) ** 2
            if r > d + 1:
                a0, a1 = _TABLE2[(1, d)]
                inv = (a0 - a1 / r) / (norm * r)
            else:
                mp = j_max / r
                inv = _basic_sum(j_max, j_max, mp, mp, 1, d) / (norm * j_max)
        return 1.0 / inv
    # case 2: F = m, alpha <= 0
    if j <= j_max:
        fp = float(m) if m * (d + 1) <= j_max else math.inf
        inv = _basic_sum(j, mm, s, fp, alpha, d) / (mm * _sz0_squared(fp, alpha, d))
    elif r > d + 1:
        a0, a1 = _TABLE2[(alpha, d)]
        inv = (a0 - a1 / r) / r
    else:
        mp = j_max / r
        inv = _basic_sum(j_max, j_max, mp, math.inf, alpha, d) / (
            j_max * _sz0_squared(math.inf, alpha, d))
    return 1.0 / inv


def _check_totdev_m(m: IntArray, n: int) -> None:
    """Raise unless every ``m`` leaves a totdev (``2 m <= n_phase - 1``)."""
    too_big = 2 * m > n - 1
    if np.any(too_big):
        raise InsufficientDataError(f"m={int(m[too_big].flat[0])} is too large for totdev with "
                                    f"n_phase={n}: needs 2*m <= n_phase - 1 = {n - 1}")


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
    a_arr, m_arr = np.broadcast_arrays(_check_alpha(alpha, kind), _check_m(m))
    out = np.empty(a_arr.shape, dtype=np.float64)
    if kind == "totdev":
        _check_totdev_m(m_arr, n)
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


# TOTVAR bias (Howe 1999, Table 1; NIST SP1065, total variance with eq. 25): E[TOTVAR] / AVAR =
# 1 - a tau/T, a = 1/(3 ln 2) for flicker FM and 3/4 for random-walk FM (0 otherwise).
_TOTVAR_BIAS_A: dict[int, float] = {-1: 1.0 / (3.0 * math.log(2.0)), -2: 0.75}


def totdev_bias(alpha: npt.ArrayLike, m: npt.ArrayLike, n_phase: int) -> FloatArray:
    """Bias ratio ``E[TOTVAR] / AVAR`` of the total variance, by noise type.

    TOTVAR is unbiased for white PM, flicker PM and white FM noise, and low for flicker FM
    and random-walk FM: ``B = 1 - a tau/T`` with ``a = 1/(3 ln 2) = 0.481`` (flicker FM,
    ``alpha = -1``) and ``a = 3/4`` (random-walk FM, ``alpha = -2``), ``tau/T = m /
    (n_phase - 1)`` (D. A. Howe, "Total variance explained", Proc. 1999 Joint Meeting
    EFTF/IEEE IFCS, pp. 1093-1099, Table 1; NIST SP1065, total variance, eq. 25).  Dividing TOTVAR
    by ``B`` (the deviation by ``sqrt(B)``) gives the bias-corrected total deviation that
    Stable32 reports when it has identified a noise type at the point (its octave files
    with confidence intervals); its all-tau files without intervals are uncorrected.

    Parameters
    ----------
    alpha : int or array_like of int
        Power-law exponent of the rate spectrum, 2..-2.
    m : int or array_like of int
        Averaging factors; broadcast against ``alpha``.
    n_phase : int
        Number of phase points, i.e. rate samples + 1.

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
    a_arr, m_arr = np.broadcast_arrays(_check_alpha(alpha, "totdev"), _check_m(m))
    _check_totdev_m(m_arr, n)
    a = np.array([_TOTVAR_BIAS_A.get(int(v), 0.0) for v in a_arr.ravel()], dtype=np.float64)
    return np.asarray(1.0 - a * m_arr.ravel() / (n - 1.0), dtype=np.float64)


# =========================================================================== intervals
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
    low = d * np.sqrt(e / stats.chi2.ppf(1.0 - lower_tail, e))
    high = d * np.sqrt(e / stats.chi2.ppf(lower_tail, e))
    return ChiSquaredInterval(low=np.asarray(low, dtype=np.float64),
                              high=np.asarray(high, dtype=np.float64), confidence=c)


def confidence_table(y: npt.ArrayLike | pd.Series, *, fs_hz: float, kind: str,
                     m: npt.ArrayLike, dev: npt.ArrayLike,
                     confidence: float = 0.683) -> ConfidenceTable:
    """Noise identification, EDF and chi-squared interval for every point of a curve.

    Runs :func:`identify_noise` (lag-1 ACF, B1 / R(n) fallback), :func:`edf_for`
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
    mm = _check_m(m)
    d = np.atleast_1d(np.asarray(dev, dtype=np.float64))
    if d.shape != mm.shape:
        raise DataError(f"dev must have one value per m: got {d.size} values for {mm.size} "
                        "averaging factors")
    if np.any(~np.isfinite(d) | (d < 0)):
        bad = d[~np.isfinite(d) | (d < 0)][0]
        raise DataError(f"dev must be finite and >= 0, got {float(bad)!r}")
    alpha, methods = _identify(arr, mm, kind, d**2 if kind == "oadev" else None)
    edf = edf_for(kind, alpha, mm, arr.size + 1)
    interval = chi2_interval(d, edf, c)
    return ConfidenceTable(kind=kind, confidence=c, fs_hz=fs, n_samples=int(arr.size),
                           tau_s=mm / fs, m=mm, dev=d, alpha=alpha, alpha_method=methods,
                           edf=edf, ci_low=interval.low, ci_high=interval.high)
