"""Sums of the block-averaged rate that the lag-1 autocorrelation noise identification needs.

At averaging factor ``m`` the rate averaged over ``N = n // m`` non-overlapping blocks is,
up to the factor ``1/m``, the first difference ``z_k = xd_{k+1} - xd_k`` of the phase
decimated by ``m``, ``xd_k = x_{km}`` (NIST SP1065 section 5.2; W. J. Riley and
C. A. Greenhall, "Power law noise identification using the lag 1 autocorrelation", 18th
EFTF, 2004).  The method needs, of ``z`` and of its first ``d_max`` differences, only a
handful of sums: count, sum of squares, lag-1 sum of products, first and last value; and
``sum_{k>=1} xd_k`` for the linear trend.  :class:`DecimatedSums` holds them, and
:func:`acf_alpha_from_sums` turns them into the estimate ``p = -2 (delta + d)`` of
:func:`fogts.allan.noise_identification.identify_with_methods` without building ``z``.

The sums are collected in two ways, with the same floating-point values of ``z`` and of
its differences as the reference (``numpy.diff`` of the strided phase):

* :func:`decimated_sums` walks the decimated phase in cache-sized chunks (any estimator);
* :class:`SumsCollector` takes them from the blocks of lag-m first and second differences
  that the overlapping Allan kernel (:func:`fogts.allan.kernels.ss_second`) forms anyway:
  ``z_k`` is its ``d_{km}`` and the first difference of ``z`` its ``v_{km}``, so the noise
  identification costs a few strided dot products over data already in cache.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np

from fogts._typing import FloatArray

__all__ = ["COLLECT_BELOW_M", "GATHER_FROM_M", "DecimatedSums", "OrderSums", "SumsCollector",
           "acf_alpha_from_sums", "acf_estimate", "acf_stderr", "decimated_sums",
           "detrended_lag1"]

#: Decimated points per chunk of :func:`decimated_sums` (256 KiB of float64).
_CHUNK = 1 << 15


@dataclass
class OrderSums:
    """Sums of one series ``w_0 .. w_{count-1}`` (``z`` or one of its differences).

    Attributes
    ----------
    count : int
        Number of values.
    sumsq : float
        ``sum w_t^2``.
    lag1 : float
        ``sum_{t < count-1} w_t w_{t+1}``.
    first, last : float
        ``w_0`` and ``w_{count-1}``.
    """

    count: int
    sumsq: float = 0.0
    lag1: float = 0.0
    first: float = math.nan
    last: float = math.nan

    def centred(self, mean: float) -> tuple[float, float]:
        """``sum (w - mean)^2`` and ``sum (w_t - mean)(w_{t+1} - mean)`` from the raw sums
        (the values' own sum is ``count * mean``)."""
        total = self.count * mean
        sq = self.sumsq - 2.0 * mean * total + self.count * mean * mean
        ends = self.first + self.last
        lag = self.lag1 - mean * (2.0 * total - ends) + (self.count - 1) * mean * mean
        return sq, lag


@dataclass
class DecimatedSums:
    """What the lag-1 ACF identification needs of the phase decimated by ``m``.

    Attributes
    ----------
    m : int
        Averaging factor.
    blocks : int
        ``N = n // m``: the decimated phase has ``N + 1`` points.
    xd_first, xd_last : float
        ``x_0`` and ``x_{Nm}``.
    xd_sum : float
        ``sum_{k=1}^{N} x_{km}``.
    orders : list of OrderSums
        Sums of ``z`` (order 0) and of its first, second ... differences.
    """

    m: int
    blocks: int
    xd_first: float
    xd_last: float
    xd_sum: float = 0.0
    orders: list[OrderSums] = field(default_factory=list)


def _new_sums(x: FloatArray, m: int, d_max: int) -> DecimatedSums:
    blocks = (x.size - 1) // m
    return DecimatedSums(m=m, blocks=blocks, xd_first=float(x[0]),
                         xd_last=float(x[blocks * m]),
                         orders=[OrderSums(count=blocks - k) for k in range(d_max + 1)])


def _add_segment(acc: OrderSums, w: FloatArray, own: int, start: int) -> None:
    """Add the values ``w[:own]`` (global indices ``start ..``) and their lag-1 products with
    the next value (``w[own]`` when present) to ``acc``."""
    if own <= 0:
        return
    head = w[:own]
    # einsum, not np.dot: OpenBLAS threads a ddot this long, and on a busy host the thread
    # hand-offs cost ~6x the CPU of the whole Allan computation (measured at 1e7 samples)
    acc.sumsq += float(np.einsum("i,i->", head, head))
    pairs = min(own, w.size - 1, acc.count - 1 - start)
    if pairs > 0:
        acc.lag1 += float(np.einsum("i,i->", w[:pairs], w[1 : pairs + 1]))
    if start == 0:
        acc.first = float(w[0])
    if start + own == acc.count:
        acc.last = float(w[own - 1])


def decimated_sums(x: FloatArray, m: int, d_max: int) -> DecimatedSums:
    """The sums of the phase ``x`` decimated by ``m`` and of ``z = diff(x[::m])`` and its
    first ``d_max`` differences, in chunks of :data:`_CHUNK` decimated points.

    Examples
    --------
    >>> s = decimated_sums(np.array([0.0, 1.0, 3.0, 2.0, 2.0]), 1, 1)
    >>> s.blocks, s.xd_sum, s.orders[0].sumsq, s.orders[0].lag1, s.orders[1].sumsq
    (4, 8.0, 6.0, 0.0, 11.0)
    """
    out = _new_sums(x, m, d_max)
    n_blocks = out.blocks
    xd = x[: n_blocks * m + 1 : m]
    out.xd_sum = 0.0
    bufs = [np.empty(min(_CHUNK, n_blocks) + d_max + 1) for _ in range(d_max + 1)]
    for a in range(0, n_blocks, _CHUNK):
        b = min(a + _CHUNK, n_blocks)
        hi = min(b + d_max + 1, n_blocks)  # z indices [a, hi): the owned ones and d_max more
        w = np.subtract(xd[a + 1 : hi + 1], xd[a:hi], out=bufs[0][: hi - a])
        out.xd_sum += float(np.sum(xd[a + 1 : b + 1]))
        for k, acc in enumerate(out.orders):
            if k:
                w = np.subtract(w[1:], w[:-1], out=bufs[k][: w.size - 1])
            _add_segment(acc, w, min(b, acc.count) - a, a)
    return out


#: From this averaging factor on, :class:`SumsCollector` copies the decimated phase out of
#: each chunk (one strided copy; ``n / m`` values kept) instead of forming the sums per
#: chunk (a few numpy calls on ``CHUNK / m`` values, whose overhead then dominates).
GATHER_FROM_M = 8
#: Below this averaging factor the overlapping Allan kernel hands its chunks to a
#: :class:`SumsCollector`; from it on, :func:`decimated_sums` reads the ``n / m`` decimated
#: points afterwards, which touches few enough cache lines to cost less than the calls
#: per chunk (a strided read of every 128th value is about 1/40 of a read of the array).
COLLECT_BELOW_M = 128


class SumsCollector:
    """:class:`DecimatedSums` of order 0 and 1, taken from the blocks of the overlapping
    Allan kernel at lag ``m`` (:func:`fogts.allan.kernels.ss_second`).

    The kernel calls :meth:`add` once per chunk of terms ``[s, e)`` with the first
    differences ``d_j = x_{j+m} - x_j`` for ``j`` in ``[s, e + m)`` and the second differences
    ``v_i = d_{i+m} - d_i`` for ``i`` in ``[s, e)``; the decimated ``z_k`` is ``d_{km}`` and the
    first difference of ``z`` is ``v_{km}`` (the same floating-point operations).  Chunks
    must come in order of ``s`` and cover the terms ``[0, n + 1 - 2m)`` of a phase ``x`` of
    ``n + 1`` points.  From ``m =`` :data:`GATHER_FROM_M` on, the decimated phase points of
    each chunk (in cache) are copied out instead and summed by :func:`decimated_sums` at the
    end, which forms the same ``z`` from them.
    """

    def __init__(self, x: FloatArray, m: int) -> None:
        self._sums = _new_sums(x, m, 1)
        self._x = x
        self._carry = math.nan  # v at the last multiple of m of the previous chunk
        self._xd = np.empty(self._sums.blocks + 1) if m >= GATHER_FROM_M else None

    def add(self, s: int, e: int, d: FloatArray, v: FloatArray) -> None:
        """Take the multiples of ``m`` among the terms ``[s, e)`` (and, in the last chunk, the
        ``z`` beyond the last term)."""
        m, sums = self._sums.m, self._sums
        z_acc, w_acc = sums.orders
        j0 = -(-s // m) * m  # first multiple of m at or after s
        k0 = j0 // m
        # z_k for k in [k0, z_end): the owned ones are those with km < e, except that the
        # last chunk also owns the z up to k = N - 1, which lie in its d block
        last_chunk = e >= self._x.size - 2 * m
        z_end = z_acc.count if last_chunk else min(-(-e // m), z_acc.count)
        if self._xd is not None:
            top = z_end + 1 if last_chunk else z_end
            self._xd[k0:top] = self._x[j0 : top * m : m]
            return
        if z_end <= k0:
            return
        zs = d[j0 - s :: m]
        _add_segment(z_acc, zs, z_end - k0, k0)
        sums.xd_sum += float(np.sum(self._x[j0 + m : z_end * m + 1 : m]))
        w_end = min(-(-e // m), w_acc.count)
        if w_end <= k0:
            return
        ws = v[j0 - s :: m][: w_end - k0]
        if math.isfinite(self._carry):
            w_acc.lag1 += self._carry * float(ws[0])
        _add_segment(w_acc, ws, ws.size, k0)
        self._carry = float(ws[-1])

    def result(self) -> DecimatedSums:
        """The sums, once every chunk was added."""
        if self._xd is None:
            return self._sums
        out = decimated_sums(self._xd, 1, 1)
        out.m = self._sums.m
        return out


def acf_stderr(n: int) -> float:
    """Standard error of ``p = -2 (delta + d)`` from the lag-1 autocorrelation of ``n``
    values: ``2 / sqrt(n)``.

    The lag-1 autocorrelation of ``n`` independent values has standard deviation
    ``1/sqrt(n)`` (Bartlett; the precision Riley & Greenhall 2004 quote for the method),
    and ``delta = r1 / (1 + r1)`` has slope 1 at ``r1 = 0``, so this is the standard error
    of ``p`` when the previous type (the one under test) is white FM.  For the other types
    it is no error bound (near white PM the slope is larger), and their changes are taken
    as the estimate rounds, as Stable32 takes them.
    """
    return 2.0 / math.sqrt(n)


def detrended_lag1(n: int, xd_first: float, xd_last: float, xd_sum: float, c0: float,
                   cl: float, sq: float, lag: float) -> float:
    """Lag-1 autocorrelation of ``z = diff(xd)`` (``n`` values) after a least-squares line is
    removed, from sums of the centred ``c = z - zbar``: ``sq = sum c^2``,
    ``lag = sum c_t c_{t+1}``, ``c0``, ``cl`` its first and last value, and of the decimated
    phase ``xd`` (``n + 1`` points) its ends and ``xd_sum = sum_{s>=1} xd_s``.

    With ``u_t = t - (n-1)/2``, ``b = sum(u c) / sum(u^2)``, ``sum(e^2) = sum(c^2) -
    b^2 sum(u^2)`` and ``sum(e_t e_t+1) = sum(c_t c_t+1) - b [2 sum(u c) - c_N-1 u_N-1 -
    c_N-1 - c_0 u_0 + c_0] + b^2 [sum(u^2) - u_N-1^2 - u_N-1]``, where
    ``sum(u c) = sum(t z_t) - zbar n (n-1)/2`` and ``sum(t z_t) = n xd_n - xd_sum``
    (Riley & Greenhall 2004 remove a linear frequency drift first).  NaN when the series is
    too short or constant.
    """
    stt = n * (n * n - 1.0) / 12.0
    if n < 3 or not stt > 0.0:
        return math.nan
    zbar = (xd_last - xd_first) / n
    suc = n * xd_last - xd_sum - zbar * n * (n - 1.0) / 2.0
    b = suc / stt
    u0, ul = -(n - 1.0) / 2.0, (n - 1.0) / 2.0
    den = sq - b * b * stt
    num = (lag - b * (2.0 * suc - cl * ul - cl - c0 * u0 + c0) + b * b * (stt - ul * ul - ul))
    if not den > 0.0 or not math.isfinite(num):
        return math.nan
    return num / den


def acf_estimate(lag1_of: Callable[[int], tuple[float, int]], d_max: int
                 ) -> tuple[float, float]:
    """Riley & Greenhall (2004) estimate ``p = -2 (delta + d)`` of alpha for frequency data
    and its standard error (:func:`acf_stderr`).

    ``lag1_of(d)`` gives the lag-1 autocorrelation ``r1`` of the ``d``-th difference of the
    block averages (order 0 detrended, the others centred) and the number of values it
    rests on, for ``d = 0, 1, ...`` in turn; the series is differenced while
    ``delta = r1 / (1 + r1) >= 0.25`` and ``d < d_max``.  NaN, NaN when an ``r1`` is NaN.
    """
    d = 0
    while True:
        r1, count = lag1_of(d)
        if not math.isfinite(r1):
            return math.nan, math.nan
        delta = r1 / (1.0 + r1)
        if delta < 0.25 or d >= d_max:
            return -2.0 * (delta + d), acf_stderr(count)
        d += 1


def acf_alpha_from_sums(sums: DecimatedSums, d_max: int) -> tuple[float, float]:
    """:func:`acf_estimate` from the sums alone: the same steps as the reference
    :func:`fogts.allan.noise_identification._acf_alpha` on the decimated phase, with the
    centred sums formed from the raw ones (:meth:`OrderSums.centred`).

    Examples
    --------
    >>> x = np.r_[0.0, np.cumsum(np.random.default_rng(2).standard_normal(4000))]
    >>> p, se = acf_alpha_from_sums(decimated_sums(x, 4, 1), 1)
    >>> round(p), round(se, 4)
    (0, 0.0632)
    """
    def lag1_of(d: int) -> tuple[float, int]:
        w = sums.orders[d]
        if d == 0:
            zbar = (sums.xd_last - sums.xd_first) / sums.blocks
            sq, lag = w.centred(zbar)
            return detrended_lag1(sums.blocks, sums.xd_first, sums.xd_last, sums.xd_sum,
                                  w.first - zbar, w.last - zbar, sq, lag), w.count
        if w.count < 2:
            return math.nan, w.count
        # the differences of the centred z equal those of z; their mean telescopes
        below = sums.orders[d - 1]
        sq, lag = w.centred((below.last - below.first) / w.count)
        return (lag / sq if sq > 0.0 else math.nan), w.count
    return acf_estimate(lag1_of, d_max)
