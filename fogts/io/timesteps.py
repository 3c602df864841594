"""The statistics of a long time base's steps in one cache-resident pass, without the array
of steps.

:func:`fogts.io.timebase.time_base` needs of the steps ``dt = diff(t - t[0])`` their
minimum (strictly increasing time), maximum (gaps, the long steps of burst logging), median
and mean (the sample rate) and, when there is no gap, their standard deviation (the
jitter).  As vectorised numpy calls that is a copy of the time column, the array of steps
and about ten passes over them.  :func:`summarise_steps` forms the shifted time and the
steps block by block instead; each block of steps lives in the cache while its minimum,
maximum, sum and two counts are taken, and the jitter is a second such pass
(:func:`step_deviation`).

The values are those of the numpy formulas bit for bit: the blocks are the nodes of
numpy's pairwise summation (:func:`pairwise_fold`; ``numpy.add.reduce`` of a contiguous
float64 array halves it, at a multiple of 8, until a part has 128 values or fewer), so the
sums of the blocks, added as numpy adds its halves, are ``numpy.sum`` of the whole array;
the median is the counted candidate of :func:`fogts.io.timebase.median_step`.  When the
candidate is not the median, or the steps have gaps, the caller forms the array of steps
and takes the general path.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass
from typing import TypeVar

import numpy as np

from fogts._typing import FloatArray

__all__ = ["HALVES_FROM", "LEAF", "StepSummary", "pairwise_fold", "pairwise_fold_halves",
           "step_deviation", "summarise_steps"]

#: Largest block of :func:`pairwise_fold` (512 KiB of float64: stays in the L2 cache).
LEAF = 1 << 16
#: numpy's pairwise summation splits at a multiple of this (its unrolling).
_UNROLL = 8

_T = TypeVar("_T")


def pairwise_fold(start: int, stop: int, leaf: Callable[[int, int], _T],
                  combine: Callable[[_T, _T], _T]) -> _T:
    """``leaf(s, e)`` of the nodes of at most :data:`LEAF` values of numpy's pairwise
    summation of ``[start, stop)``, in order, folded by ``combine`` as numpy adds its halves.

    A ``leaf`` that returns ``numpy.sum`` of its block and ``combine = operator.add`` give
    ``numpy.sum`` of the whole range bit for bit (numpy's ``pairwise_sum``, from which a
    node of more than 128 values is the sum of its halves split at ``n // 2`` rounded down
    to a multiple of 8).

    Examples
    --------
    >>> import operator
    >>> x = np.random.default_rng(0).standard_normal(300_001) * 1e3
    >>> pairwise_fold(0, x.size, lambda s, e: float(np.sum(x[s:e])), operator.add) == float(np.sum(x))
    True
    """
    n = stop - start
    if n <= LEAF:
        return leaf(start, stop)
    half = n // 2
    half -= half % _UNROLL
    return combine(pairwise_fold(start, start + half, leaf, combine),
                   pairwise_fold(start + half, stop, leaf, combine))


#: From this many values on, :func:`pairwise_fold_halves` folds the two halves on two threads.
HALVES_FROM = 1 << 20


def pairwise_fold_halves(start: int, stop: int, make_leaf: Callable[[], Callable[[int, int], _T]],
                         combine: Callable[[_T, _T], _T]) -> _T:
    """:func:`pairwise_fold` with the two halves of the top node on two threads (from
    :data:`HALVES_FROM` values on), each with its own ``make_leaf()``: the same nodes
    folded in the same order, so the same result, bit for bit.  numpy releases the GIL in
    the blocks' ufuncs and reductions, so a free core halves the time."""
    n = stop - start
    if n < HALVES_FROM:
        return pairwise_fold(start, stop, make_leaf(), combine)
    half = n // 2
    half -= half % _UNROLL
    with ThreadPoolExecutor(max_workers=1) as pool:
        left = pool.submit(pairwise_fold, start, start + half, make_leaf(), combine)
        right = pairwise_fold(start + half, stop, make_leaf(), combine)
        return combine(left.result(), right)


@dataclass(frozen=True)
class StepSummary:
    """What one pass found of the ``count`` steps of a time base.

    Attributes
    ----------
    count : int
        Number of steps (one less than the stamps).
    smallest, longest : float
        Their minimum and maximum (NaN if a time stamp is NaN).
    total : float
        ``numpy.sum`` of the steps (the mean is ``total / count``, as ``numpy.mean``).
    guess : float
        The median candidate of :func:`fogts.io.timebase.median_step` (from a strided
        sample of about 1000 steps).
    below, at_or_below : int
        Steps ``< guess`` and ``<= guess``.
    """

    count: int
    smallest: float
    longest: float
    total: float
    guess: float
    below: int
    at_or_below: int

    @property
    def mean(self) -> float:
        """``numpy.mean`` of the steps."""
        return self.total / self.count

    def median(self) -> float | None:
        """``numpy.median`` of the steps when the candidate is it, else None."""
        n = self.count
        ks = [n // 2 - 1, n // 2] if n % 2 == 0 else [n // 2]
        if self.below <= ks[0] and ks[-1] < self.at_or_below:
            return self.guess
        return None


_Partial = tuple[float, float, float, int, int]


def summarise_steps(raw: FloatArray, origin: float | None) -> tuple[FloatArray, StepSummary]:
    """The time base ``raw - origin`` (a new array; ``raw`` itself when ``origin`` is None)
    and the :class:`StepSummary` of its steps, in one pass of blocks in the cache.

    ``raw`` is 1-D float64 with at least ``2 * LEAF`` values.  Each step is formed as
    ``numpy.diff`` forms it from the shifted time, so every statistic equals its numpy
    formula on ``numpy.diff(raw - origin)`` bit for bit.
    """
    n = raw.size - 1
    time = raw if origin is None else np.empty_like(raw)
    at = np.arange(0, n, n // 1024)
    if origin is None:
        sample = raw[at + 1] - raw[at]
    else:
        sample = (raw[at + 1] - origin) - (raw[at] - origin)
    sample.sort()
    first_k = n // 2 - 1 if n % 2 == 0 else n // 2
    guess = float(sample[first_k * sample.size // n])

    def make_leaf() -> Callable[[int, int], _Partial]:
        buf = np.empty(LEAF, dtype=np.float64)  # one per thread
        flags = np.empty(LEAF, dtype=bool)

        def leaf(s: int, e: int) -> _Partial:
            # time[e] is written by this block and the next alike (the same value)
            seg = time[s : e + 1]
            if origin is not None:
                np.subtract(raw[s : e + 1], origin, out=seg)
            d = np.subtract(seg[1:], seg[:-1], out=buf[: e - s])
            mark = flags[: e - s]
            below = int(np.count_nonzero(np.less(d, guess, out=mark)))
            at_or_below = int(np.count_nonzero(np.less_equal(d, guess, out=mark)))
            return float(np.sum(d)), float(d.min()), float(d.max()), below, at_or_below

        return leaf

    def combine(a: _Partial, b: _Partial) -> _Partial:
        # min/max of Python floats would drop a NaN that numpy's propagate: keep it
        lo = a[1] if math.isnan(a[1]) or a[1] <= b[1] else b[1]
        hi = a[2] if math.isnan(a[2]) or a[2] >= b[2] else b[2]
        return a[0] + b[0], lo, hi, a[3] + b[3], a[4] + b[4]

    with np.errstate(invalid="ignore", over="ignore"):  # inf stamps: the caller refuses them
        total, smallest, longest, below, at_or_below = pairwise_fold_halves(0, n, make_leaf,
                                                                            combine)
    return time, StepSummary(n, smallest, longest, total, guess, below, at_or_below)


def step_deviation(time: FloatArray, mean: float) -> float:
    """``numpy.std(numpy.diff(time))`` bit for bit, ``mean`` being ``numpy.mean`` of the
    steps: the squared deviations summed block by block in the cache (numpy forms
    ``d - mean``, squares it and sums, over the whole array)."""
    n = time.size - 1

    def make_leaf() -> Callable[[int, int], float]:
        buf = np.empty(min(LEAF, n), dtype=np.float64)

        def leaf(s: int, e: int) -> float:
            d = np.subtract(time[s + 1 : e + 1], time[s:e], out=buf[: e - s])
            d -= mean
            np.multiply(d, d, out=d)
            return float(np.sum(d))

        return leaf

    return math.sqrt(pairwise_fold_halves(0, n, make_leaf, lambda a, b: a + b) / n)
