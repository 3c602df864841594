"""Every sliding window's Allan-family deviation, for the dynamic Allan analysis.

For the overlapping estimators (``oadev``, ``mdev``, ``ohdev``) every window's sum of
squared differences is a difference of one running sum over the whole record, so each
tau costs O(n) however many windows overlap (:func:`cumsum_devs`): the squared second
(third) differences of the once-integrated phase (:func:`fogts.allan.kernels.
phase_from_rate`) are accumulated in cache-sized chunks and the running sum is sampled
only at the window edges.  :func:`kernel_devs` instead calls the estimator of
:mod:`fogts.allan.estimators` on each window (O(n T / step) per tau; it serves every
kind, and is the reference the fast path is tested against).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from concurrent.futures import ThreadPoolExecutor

import numpy as np

from fogts import progress
from fogts._typing import FloatArray, IntArray
from fogts.allan.estimators import ESTIMATORS, thread_count
from fogts.allan.kernels import (
    NORMALISATION,
    phase_from_rate,
    second_difference,
    ss_second,
    ss_third,
    third_difference,
)

__all__ = ["CUMSUM_KINDS", "cumsum_devs", "kernel_devs"]

#: Kinds with an O(n)-per-tau running-sum implementation.
CUMSUM_KINDS: tuple[str, ...] = ("oadev", "mdev", "ohdev")
_CHUNK = 1 << 16

SquaredTerms = Callable[[int, int], FloatArray]
BlockSum = Callable[[int, int], float]
Difference = Callable[[FloatArray, int, int, int, FloatArray, FloatArray], FloatArray]


def kernel_devs(y: FloatArray, *, kind: str, m: IntArray, starts: IntArray, win_n: int,
                fs: float) -> FloatArray:
    """The estimator of :mod:`fogts.allan.estimators` on every window, ``(n_win, n_tau)``."""
    fn = ESTIMATORS[kind]
    out = np.empty((starts.size, m.size), dtype=np.float64)
    tick = progress.ticker(f"dynamic {kind}: {starts.size} windows", starts.size)
    with progress.reporting(None):  # one step per window, not per tau of each window
        for i, s in enumerate(starts.tolist()):
            out[i] = fn(y[s:s + win_n], fs_hz=fs, m=m, workers=1).dev
            tick(i + 1)
    return out


def cumsum_devs(y: FloatArray, *, kind: str, m: IntArray, terms: IntArray,
                starts: IntArray) -> FloatArray:
    """Every window's deviation from one pass over the record per tau (O(n) per tau).

    Window ``i`` covers rate samples ``[s_i, s_i + L)``, i.e. phase points
    ``x[s_i .. s_i + L]``; its terms are the global terms ``s_i .. s_i + terms - 1`` of
    the whole record's phase (the phase offset cancels in every difference).  The squared
    terms are summed between consecutive window edges (``numpy.add.reduceat``) and each
    window's sum is a difference of the running sum of those few block sums.  The
    normalisations are those of the estimators (:data:`fogts.allan.kernels.NORMALISATION`).
    """
    x = phase_from_rate(y)
    squared, normalisation = _SQUARED_TERMS[kind], NORMALISATION[kind]
    kernel = _BLOCK_KERNELS.get(kind)

    def column(j: int) -> FloatArray:
        mj, tj = int(m[j]), int(terms[j])
        if kernel is None:  # mdev's pieces extend m - 1 terms: at least m terms each
            sums = _window_sums(squared(x, mj), starts, tj, chunk=max(_CHUNK, mj))
        else:
            sums = _window_sums(squared(x, mj), starts, tj, chunk=_CHUNK,
                                block_sum=_kernel_block(kernel, x, mj))
        return np.sqrt(np.maximum(sums, 0.0) / normalisation(mj, tj))

    out = np.empty((starts.size, m.size), dtype=np.float64)
    tick = progress.ticker(f"dynamic {kind}: {m.size} taus", m.size)
    # Each tau is independent, so threads change no sum; numpy releases the GIL in the
    # chunk passes.  Progress is reported from this thread as the columns arrive in order.
    workers = thread_count(None, m.size, int(terms.sum()))
    with ThreadPoolExecutor(max_workers=workers) as pool:
        columns = map(column, range(m.size)) if workers == 1 else pool.map(column,
                                                                           range(m.size))
        for j, values in enumerate(columns):
            out[:, j] = values
            tick(j + 1)
    return out


def _squared(difference: Difference) -> Callable[[FloatArray, int], SquaredTerms]:
    """Squared terms ``difference(x, m)^2`` for any range ``[c0, c1)`` of term indices,
    computed in two buffers that are reused from one range to the next."""
    def at_lag(x: FloatArray, m: int) -> SquaredTerms:
        buffers = [np.empty(0), np.empty(0)]

        def terms(c0: int, c1: int) -> FloatArray:
            k = c1 - c0
            if buffers[0].size < k:
                buffers[:] = [np.empty(k), np.empty(k)]
            a = difference(x, m, c0, c1, buffers[0][:k], buffers[1][:k])
            return np.multiply(a, a, out=a)
        return terms
    return at_lag


def _mod_sq(x: FloatArray, m: int) -> SquaredTerms:
    """(sum_{i=j}^{j+m-1} v_i)^2 with v the second differences, for j in [c0, c1)."""
    def terms(c0: int, c1: int) -> FloatArray:
        hi = c1 + m - 1
        v = second_difference(x, m, c0, hi, np.empty(hi - c0), np.empty(hi - c0))
        run = np.empty(v.size + 1)
        run[0] = 0.0
        np.cumsum(v, out=run[1:])
        s = run[m:] - run[:-m]
        return np.square(s, out=s)
    return terms


_SQUARED_TERMS: dict[str, Callable[[FloatArray, int], SquaredTerms]] = {
    "oadev": _squared(second_difference), "ohdev": _squared(third_difference),
    "mdev": _mod_sq,
}

#: The estimators' sum-of-squares kernels, ``kernel(x, lag, terms)`` over the terms
#: ``0..terms-1`` of ``x``: a block of terms ``[lo, hi)`` is the kernel on ``x[lo:]``.
#: (mdev's kernel integrates all of ``x`` it is given, so it is not used per block.)
_BLOCK_KERNELS: dict[str, Callable[[FloatArray, int, int], float]] = {
    "oadev": ss_second, "ohdev": ss_third,
}


def _kernel_block(kernel: Callable[[FloatArray, int, int], float], x: FloatArray,
                  m: int) -> BlockSum:
    """The sum of the squared terms ``[lo, hi)`` at lag ``m`` by the estimator's kernel."""
    return lambda lo, hi: kernel(x[lo:], m, hi - lo)


def _window_sums(sq: SquaredTerms, starts: IntArray, count: int, *, chunk: int,
                 block_sum: BlockSum | None = None) -> FloatArray:
    """``sum(t[s : s + count])`` for every start ``s`` of the squared terms ``t``.

    The window edges cut the terms into blocks; each block is summed once, and a window's
    sum is the sum of the block sums it spans (a difference of their running sum: a few
    thousand numbers, so no precision is lost to a long running sum).  Runs of short
    blocks are summed by ``reduceat`` over cache-sized pieces that end on an edge; a block
    of at least ``chunk`` terms is summed alone, by ``block_sum`` when given (the
    estimator's kernel, which writes no squared terms), else ``chunk`` terms at a time.
    """
    edges = _sorted_unique(np.concatenate([starts, starts + count]))
    block = np.empty(edges.size - 1)
    for b0, b1 in _pieces(edges, chunk):
        lo, hi = int(edges[b0]), int(edges[b1])
        if b1 == b0 + 1 and hi - lo >= chunk:
            block[b0] = block_sum(lo, hi) if block_sum is not None \
                else math.fsum(float(sq(c, min(c + chunk, hi)).sum())
                               for c in range(lo, hi, chunk))
        else:
            block[b0:b1] = np.add.reduceat(sq(lo, hi), edges[b0:b1] - lo)
    run = np.concatenate([[0.0], np.cumsum(block)])
    i0 = np.searchsorted(edges, starts)
    i1 = np.searchsorted(edges, starts + count)
    return run[i1] - run[i0]


def _pieces(edges: IntArray, chunk: int) -> list[tuple[int, int]]:
    """The blocks between ``edges`` grouped into pieces ``(b0, b1)``: each block of at least
    ``chunk`` terms alone, the others in runs of consecutive blocks about ``chunk`` long."""
    cut = np.searchsorted(edges, edges[0] + chunk * np.arange(1, (edges[-1] - edges[0])
                                                              // chunk + 2))
    long = np.flatnonzero(np.diff(edges) >= chunk)
    bounds = _sorted_unique(np.concatenate([[0], np.minimum(cut, edges.size - 1),
                                            [edges.size - 1], long, long + 1]))
    return list(zip(bounds[:-1].tolist(), bounds[1:].tolist(), strict=True))


def _sorted_unique(v: IntArray) -> IntArray:
    v = np.sort(v)
    keep = np.empty(v.size, dtype=np.bool_)
    keep[:1] = True
    np.not_equal(v[1:], v[:-1], out=keep[1:])
    return v[keep]
