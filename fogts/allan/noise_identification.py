"""Noise identification: the dominant power-law noise at each averaging factor.

Per averaging factor ``m``, the power-law exponent ``alpha`` of the rate ("frequency")
spectrum :math:`S_y(f) \\propto f^\\alpha` (NIST SP1065, W. J. Riley, *Handbook of Frequency
Stability Analysis*, 2008, section 5.2), rounded to one of ``2`` (white PM: quantization
noise Q), ``1`` (flicker PM), ``0`` (white FM: angle random walk N), ``-1`` (flicker FM:
bias instability B) or ``-2`` (random-walk FM: rate random walk K).  The method that found
it is reported as:

* ``"acf"``: the lag-1 autocorrelation method of W. J. Riley and C. A. Greenhall,
  "Power law noise identification using the lag 1 autocorrelation", 18th EFTF (2004),
  applied to the rate averaged over non-overlapping blocks of ``m`` samples.
* ``"b1"``: when fewer than 30 decimated phase points remain, Barnes' B1 bias ratio
  (standard variance / Allan variance, SP1065 section 5.2), supplemented by
* ``"rn"``: the ratio R(n) = Mod sigma^2 / sigma^2 (SP1065 section 5.2), which the B1
  ratio needs to separate white PM, flicker PM and white FM.
* A change away from white FM (``alpha = 0``) at the next shorter tau is accepted only
  when it is significant given the estimate's sampling error (:data:`CHANGE_Z` standard
  errors: ``2/sqrt(N)`` for the ACF's ``p``, ``sqrt(2/(N-1))`` for ``log B1``); otherwise
  white FM is kept, so white rate noise is not given chance types at the longest taus.
* ``"none"``: nothing could be identified at this tau (fewer than 4 averaged points, or
  a constant series); the alpha of the nearest identified tau is used instead (white FM,
  ``alpha = 0``, if there is none).
"""

from __future__ import annotations

import itertools
import math
from collections.abc import Sequence

import numpy as np
import numpy.typing as npt
import pandas as pd

from fogts._typing import FloatArray, IntArray
from fogts._validate import check_choice, check_positive, to_float_array
from fogts.allan._checks import check_m
from fogts.allan.decimated import (
    DecimatedSums,
    acf_alpha_from_sums,
    acf_estimate,
    decimated_sums,
    detrended_lag1,
)
from fogts.allan.estimators import phase_deviations, phase_from_rate
from fogts.allan.taus import KINDS

__all__ = ["ACF_MIN_POINTS", "ALPHAS", "ALPHA_METHODS", "B1_MIN_POINTS", "CHANGE_Z", "acf_orders",
           "identify_noise", "identify_with_methods"]

#: Fewest decimated phase points (``n // m + 1``) for the lag-1 autocorrelation method;
#: SP1065 section 5.2 and Riley & Greenhall (2004) ask for "at least about 30".
ACF_MIN_POINTS = 30
#: Fewest averaged rate values for the B1 ratio (below it the point is ``"none"``).
B1_MIN_POINTS = 4
#: A change of the identified type from one tau to the next is accepted when the estimate
#: departs from the previous type by at least this many of its standard errors (about
#: 0.3 % two-sided per tau under the previous type).
CHANGE_Z = 3.0
#: The values of ``alpha_method``.
ALPHA_METHODS: tuple[str, ...] = ("acf", "b1", "rn", "neighbours", "none")
#: The power-law exponents that are identified (frequency-noise convention).
ALPHAS: tuple[int, ...] = (2, 1, 0, -1, -2)


def _lag1(c: FloatArray) -> float:
    """Lag-1 autocorrelation of a zero-mean series (Riley & Greenhall 2004, eq. 2);
    NaN for a constant series."""
    den = float(np.dot(c, c))
    if not den > 0.0:
        return math.nan
    return float(np.dot(c[:-1], c[1:])) / den


def _acf_alpha(xd: FloatArray, d_max: int) -> tuple[float, float]:
    """Riley & Greenhall (2004) lag-1 ACF noise estimate for frequency data, and its
    standard error (:func:`~fogts.allan.decimated.acf_stderr`): the reference
    implementation, on the decimated phase itself.

    :func:`identify_with_methods` computes the same estimate from sums
    (:func:`fogts.allan.decimated.acf_alpha_from_sums`), which the overlapping Allan kernel
    collects in its own pass; the tests compare the two.

    ``xd`` is the phase decimated by m (``N + 1`` points), so ``z = diff(xd)`` are the N
    rates averaged over blocks of m (the scale ``1/m`` does not matter).  A least-squares
    line is removed from ``z`` (a linear rate drift,
    :func:`~fogts.allan.decimated.detrended_lag1`); the series is then differenced until
    ``delta = r1 / (1 + r1)`` falls below 0.25 (stationary) or ``d_max`` differences are
    taken, and ``p = -2 (delta + d)`` estimates alpha (``theta = 0`` for frequency data).
    """
    n = xd.size - 1
    series = [np.diff(xd)]
    zbar = (float(xd[-1]) - float(xd[0])) / n
    series[0] -= zbar

    def lag1_of(d: int) -> tuple[float, int]:
        if d == 0:
            z = series[0]
            if n < 3:
                return math.nan, n
            return detrended_lag1(n, float(xd[0]), float(xd[-1]), float(np.sum(xd[1:])),
                                  float(z[0]), float(z[-1]), float(np.dot(z, z)),
                                  float(np.dot(z[:-1], z[1:]))), n
        # differencing the detrended series = differencing z, up to a constant that the
        # centring removes
        w = np.diff(series[-1])
        series.append(w)
        if w.size < 2:
            return math.nan, w.size
        w -= w.mean()
        return _lag1(w), w.size
    return acf_estimate(lag1_of, d_max)


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


def _significant_change(held: int | None, p: float, se: float) -> int:
    """The rounded ACF estimate ``p``, unless ``held`` (the type at the next shorter tau)
    is white FM (alpha = 0) and ``p`` differs from it by less than :data:`CHANGE_Z`
    standard errors: then ``held``.

    The noise type changes slowly with tau, and the estimate at a longer tau rests on fewer
    averaged values; a change of type is accepted only where the estimate's own sampling
    uncertainty (:func:`~fogts.allan.decimated.acf_stderr`) makes it significant (:data:`CHANGE_Z`).  On white rate
    noise this removes the chance +-1 types at the last ACF taus (30-125 averaged values,
    where the standard error of ``p`` is 0.2-0.4)."""
    alpha = int(np.clip(np.rint(p), -2, 2))
    if held == 0 and alpha != held and abs(p - held) < CHANGE_Z * se:
        return held
    return alpha


def _b1_type(z: FloatArray, oavar: float, held: int | None = None) -> int:
    """B1 ratio decision (SP1065 section 5.2): -2, -1, 0, or 2 for "phase noise" (which the
    B1 ratio cannot split; R(n) does).

    With ``held`` (the type at the next shorter tau) white FM, that type is kept unless the
    B1 ratio departs from the value it expects by more than :data:`CHANGE_Z` standard errors of ``log B1``, ``sqrt(2 / (n - 1))`` (the sample
    variance of ``n`` values; the Allan variance in the denominator, from the whole
    record, is the better determined of the two)."""
    n = z.size
    b1 = float(np.var(z, ddof=1)) / oavar
    # mu (AVAR ~ tau**mu) of RWFM, FFM, WFM and the PM types; decision boundaries are the
    # geometric means of adjacent expected values.
    expected = [(-2, _b1_expected(n, 1)), (-1, _b1_expected(n, 0)), (0, _b1_expected(n, -1)),
                (2, _b1_expected(n, -2))]
    if held == 0 and b1 > 0.0:
        log_ratio = math.log(b1 / _b1_expected(n, -1))  # white FM: AVAR ~ 1/tau
        if abs(log_ratio) < CHANGE_Z * math.sqrt(2.0 / (n - 1)):
            return held
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


def acf_orders(kind: str) -> int:
    """Largest number of differences of the block-averaged rate the lag-1 ACF method takes
    for ``kind``: 2 for the Hadamard family, 1 otherwise (Riley & Greenhall 2004 count on
    the phase: ``d_max`` 3 and 2)."""
    return 2 if kind in ("hdev", "ohdev") else 1


def identify_with_methods(y: FloatArray, m: IntArray, kind: str,
                          oavar_given: FloatArray | None = None, *,
                          phase: FloatArray | None = None,
                          sums: Sequence[DecimatedSums | None] | None = None
                          ) -> tuple[IntArray, tuple[str, ...]]:
    """Alpha and the method that found it (:data:`ALPHA_METHODS`) at every averaging factor.

    ``oavar_given`` (aligned with ``m``) are known overlapping Allan variances, reused for
    the B1 ratio instead of recomputing them (as
    :func:`fogts.allan.confidence.confidence_table` does for ``kind="oadev"``).  ``phase``
    (``phase_from_rate(y)``) and ``sums`` (aligned with ``m``, of at least
    :func:`acf_orders` orders; :func:`fogts.allan.estimators.estimate_with_sums`) are reused
    when given instead of being computed again.
    """
    d_max = acf_orders(kind)
    n = y.size
    x = phase_from_rate(y) if phase is None else phase
    alpha = np.zeros(m.size, dtype=np.int64)
    methods = ["none"] * m.size
    b1_idx: list[int] = []
    held: int | None = None
    for i in np.argsort(m, kind="stable").tolist():
        blocks = n // int(m[i])
        if blocks + 1 >= ACF_MIN_POINTS:
            got = sums[i] if sums is not None else None
            p, se = acf_alpha_from_sums(got if got is not None
                                        else decimated_sums(x, int(m[i]), d_max), d_max)
            if math.isfinite(p):
                alpha[i] = _significant_change(held, p, se)
                methods[i] = "acf"
                held = int(alpha[i])
        elif blocks >= B1_MIN_POINTS:
            b1_idx.append(i)
    if b1_idx:
        mb = m[b1_idx]
        if oavar_given is not None:
            oavar = np.asarray(oavar_given, dtype=np.float64)[b1_idx]
        else:
            oavar = phase_deviations("oadev", x, mb) ** 2
        pm_idx: list[int] = []
        for i, mi, av in zip(b1_idx, mb.tolist(), oavar.tolist(), strict=True):
            if not av > 0.0:
                continue
            xd = x[: (n // mi) * mi + 1 : mi]
            alpha[i] = _b1_type(np.diff(xd) / mi, av, held)
            methods[i] = "b1"
            held = int(alpha[i])
            if alpha[i] == 2 and 3 * mi <= n:
                pm_idx.append(i)
        if pm_idx:
            mp = m[pm_idx]
            mvar = phase_deviations("mdev", x, mp) ** 2
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
    _smooth_isolated(alpha, methods)
    return alpha, tuple(methods)


def _smooth_isolated(alpha: IntArray, methods: list[str]) -> None:
    """An identification that jumps by two or more types at one tau while both neighbours
    agree is taken from the neighbours (``"neighbours"``), in place.  The power-law type
    changes slowly with tau; a lone jump (white PM amid white FM, say) is a chance value of
    the lag-1 autocorrelation, and its EDF would give that one point an interval many times
    tighter than its neighbours' (Stable32 likewise reads the noise type over a
    neighbourhood)."""
    for i in range(1, alpha.size - 1):
        left, right = int(alpha[i - 1]), int(alpha[i + 1])
        if left == right and abs(int(alpha[i]) - left) >= 2 \
                and methods[i - 1] != "none" and methods[i + 1] != "none":
            alpha[i] = left
            methods[i] = "neighbours"


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
        :func:`fogts.allan.confidence.confidence_table` to see which method found each
        value.

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
    mm = check_m(m)
    return identify_with_methods(arr, mm, kind)[0]
