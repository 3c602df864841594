"""Sums of squared phase differences, the numerical core of the Allan-family estimators.

The rate ``y`` is integrated once to the "phase" (angle) ``x_k = sum_{j<k} y_j``
(:func:`phase_from_rate`, NIST SP1065 eq. 4) and every estimator is a normalised sum of
squared differences of ``x`` (SP1065 eqs. 7, 11, 14, 18, 20, 25).

* The mean of ``y`` is removed before integrating.  Every statistic is exactly invariant
  to a constant added to ``y`` (a linear phase ramp is annihilated by the second and third
  differences and preserved by the totdev reflection), and a small phase avoids the
  cancellation a large bias (Earth rate, a gyro offset) would cause.
* The phase is kept in units of "rate x sample": ``1 / fs`` cancels between the phase and
  ``tau = m / fs``, so e.g. OADEV^2 = sum(v^2) / (2 m^2 n) with ``v`` the second difference
  of the unscaled phase (:data:`NORMALISATION`).
* Sums of squares are accumulated over cache-sized chunks with preallocated buffers and
  ``np.dot``: the only large array is the phase itself (one copy of the input); ``mdev``
  also needs one running-sum array per call.
"""

from __future__ import annotations

from collections.abc import Callable, Iterator, Sequence
from concurrent.futures import ThreadPoolExecutor
from contextlib import contextmanager
from contextvars import ContextVar

import numpy as np

from fogts._typing import FloatArray
from fogts._validate import forget_sum

__all__ = ["CHUNK", "DOT_BLOCK", "HALVES_FROM", "NORMALISATION", "SHARED_WALK_BELOW", "ChunkHook",
           "given_up_buffer", "hook_sees_chunks", "phase_from_rate", "phase_in_place",
           "second_difference", "ss_mod", "ss_second", "ss_second_lags", "ss_third", "ss_total",
           "third_difference"]

#: Within :func:`phase_in_place`: the rates given up, each with the buffer whose tail it is.
_GIVEN_UP: ContextVar[list[tuple[FloatArray, FloatArray]] | None] = \
    ContextVar("fogts_phase_in_place", default=None)

#: Called by :func:`ss_second` with each chunk ``s, e`` of terms, its first differences
#: ``d_j`` (``j`` in ``[s, e + L)``) and second differences ``v_i`` (``i`` in ``[s, e)``).
ChunkHook = Callable[[int, int, FloatArray, FloatArray], None]

#: Elements per chunk of the sum-of-squares loops (256 KiB of float64: stays in L2).
CHUNK = 1 << 15
#: From this many samples on, :func:`phase_from_rate` integrates the two halves of the rate
#: on two threads (below it the one-thread integration costs under 0.2 s).
HALVES_FROM = 1 << 24
#: Largest block handed to one ``np.dot``: OpenBLAS multithreads ``ddot`` above 10,000
#: elements, which is slower than one thread for cache-sized blocks and collapses on a
#: loaded machine.
DOT_BLOCK = 8192


def phase_from_angle(theta: FloatArray, fs_hz: float) -> FloatArray:
    """The phase of :func:`phase_from_rate` taken from an angle record directly.

    ``theta`` (``n + 1`` points, angle in rate-unit x seconds, e.g. deg for a rate in
    deg/s) is the integral of the rate, so no rate is formed by differencing:
    ``x_k = (theta_k - theta_0) fs - k mean`` with ``mean = (theta_n - theta_0) fs / n``,
    the same line removed as :func:`phase_from_rate` removes (NIST SP1065 sec. 5.2: phase
    data enter the Allan estimators as they are).

    Examples
    --------
    >>> phase_from_angle(np.array([0.0, 1.0, 4.0, 6.0]), 1.0).tolist()
    [0.0, -1.0, 0.0, 0.0]
    """
    n = theta.size - 1
    scaled = (theta - theta[0]) * fs_hz
    mean = float(scaled[-1]) / n
    return scaled - mean * np.arange(n + 1, dtype=np.float64)


def phase_from_rate(y: FloatArray, *, mean: float | None = None,
                    out: FloatArray | None = None) -> FloatArray:
    """Integrate the mean-removed rate once: ``x_0 = 0``, ``x_k = sum_{j<k} (y_j - mean)``.

    The result (``n + 1`` points) is the phase in units of rate x sample period, i.e. the
    angle times ``fs``, integrated as in NIST SP1065 eq. 4.  ``mean`` is
    ``float(numpy.mean(y))``, computed here unless the caller has it.  From
    :data:`HALVES_FROM` samples on, the two halves are integrated at once on two threads
    and the first half's end is then added to the second (:func:`_integrate_halves`); the
    split depends on ``n`` only, so the phase is the same on any number of cores.  ``out``
    (``n + 1`` float64, C-contiguous) receives the phase; it may be the buffer whose tail
    ``out[1:]`` is ``y`` itself (:func:`given_up_buffer`): each chunk of ``y`` is read
    before its phase is written over it, so the values are the same.

    Examples
    --------
    >>> phase_from_rate(np.array([1.0, 3.0, 2.0])).tolist()
    [0.0, -1.0, 0.0, 0.0]
    >>> buf = np.array([0.0, 1.0, 3.0, 2.0])   # the rate in buf[1:], integrated in place
    >>> phase_from_rate(buf[1:], out=buf) is buf, buf.tolist()
    (True, [0.0, -1.0, 0.0, 0.0])
    """
    n = y.size
    x = np.empty(n + 1, dtype=np.float64) if out is None else out
    x[0] = 0.0
    if mean is None:
        mean = float(np.mean(y))
    if n < HALVES_FROM:
        _integrate(y, mean, x[1:])
    else:
        _integrate_halves(y, mean, x[1:])
    return x


@contextmanager
def phase_in_place(rate: FloatArray) -> Iterator[bool]:
    """Within this context the estimators form the phase of ``rate`` in the memory that
    holds it (:func:`given_up_buffer`), when ``rate`` is the tail ``buf[1:]`` of a writeable
    float64 buffer ``buf`` one point longer, as the ``.npy`` reader leaves it
    (:func:`fogts.io.arrays.npy_table`); yields whether it is.

    ``rate`` is then overwritten by its phase: for a caller that owns ``rate`` and reads it
    no more (``fogts allan`` on a file it read itself), so that at 10^8 samples no second
    800 MB array is allocated and touched.  The phase is the same, bit for bit.

    Examples
    --------
    >>> buf = np.array([0.0, 1.0, 3.0, 2.0])
    >>> with phase_in_place(buf[1:]) as spare:
    ...     got = given_up_buffer(buf[1:])
    >>> spare, got is buf, given_up_buffer(buf[1:]) is None
    (True, True, True)
    """
    spare = _buffer_of(rate)
    token = _GIVEN_UP.set([(rate, spare)] if spare is not None else [])
    try:
        yield spare is not None
    finally:
        _GIVEN_UP.reset(token)


def given_up_buffer(y: FloatArray) -> FloatArray | None:
    """The buffer of ``n + 1`` points whose tail is ``y``, when ``y`` (or a view of the same
    memory) was given up by :func:`phase_in_place`; None otherwise, and for every later call
    (it is handed out once).  Its sum recorded by :func:`fogts._validate.note_sum` is
    forgotten: the values are about to change."""
    given = _GIVEN_UP.get()
    if not given:
        return None
    for k, (rate, buf) in enumerate(given):
        if (y.dtype == np.float64 and y.ndim == 1 and y.size + 1 == buf.size
                and y.flags.c_contiguous and _address(y) == _address(buf) + buf.itemsize):
            del given[k]
            forget_sum(rate)
            forget_sum(y)
            return buf
    return None


def _address(a: np.ndarray) -> int:
    return int(a.__array_interface__["data"][0])


def _buffer_of(rate: FloatArray) -> FloatArray | None:
    """The array that owns ``rate``'s memory when it is a writeable C-contiguous float64
    buffer of exactly one point more, ``rate`` its tail; else None."""
    if not isinstance(rate, np.ndarray) or rate.ndim != 1 or not rate.flags.c_contiguous:
        return None
    base = rate
    while isinstance(base.base, np.ndarray):
        base = base.base
    if (base is rate or base.dtype != np.float64 or base.ndim != 1 or base.size != rate.size + 1
            or not base.flags.c_contiguous or not base.flags.writeable or rate.dtype != np.float64
            or _address(rate) != _address(base) + base.itemsize):
        return None
    return base


def _integrate(y: FloatArray, mean: float, out: FloatArray) -> float:
    """``out[k] = sum_{j<=k} (y_j - mean)`` in chunks of :data:`CHUNK` (each cumulated in
    the cache, then the running total added); returns the total."""
    n = y.size
    buf = np.empty(min(CHUNK, max(n, 1)), dtype=np.float64)
    carry = 0.0
    for s in range(0, n, CHUNK):
        e = min(s + CHUNK, n)
        b = buf[: e - s]
        np.subtract(y[s:e], mean, out=b)
        seg = out[s:e]
        np.cumsum(b, out=seg)
        if carry != 0.0:
            seg += carry
        carry = float(seg[-1])
    return carry


def _integrate_halves(y: FloatArray, mean: float, out: FloatArray) -> None:
    """:func:`_integrate` of the first half (a whole number of chunks: the same values)
    and, at the same time, of the second half from zero; the first half's total is then
    added to the second, in two pieces on the two threads.

    The second half differs from the one-thread integration in the last bits (the total
    is added once more); the phase differences the estimators form agree to about
    ``1e-16 |x| / |y|`` relative.  Each thread writes the pages it later reads, and the
    integration (a chain of dependent additions) runs at twice the speed.
    """
    n = y.size
    half = max(CHUNK, (n // 2) // CHUNK * CHUNK)
    with ThreadPoolExecutor(max_workers=2) as pool:
        second = pool.submit(_integrate, y[half:], mean, out[half:])
        carry = _integrate(y[:half], mean, out[:half])
        second.result()
        mid = half + (n - half) // 2
        pieces = [out[half:mid], out[mid:]]
        list(pool.map(lambda p: np.add(p, carry, out=p), pieces))


def second_difference(x: FloatArray, lag: int, c0: int, c1: int, out: FloatArray,
                      tmp: FloatArray) -> FloatArray:
    """``out[i - c0] = (x[i+2L] - x[i+L]) - (x[i+L] - x[i])`` for ``c0 <= i < c1``.

    Both inner differences are small, so this is the accurate way round; ``out`` and
    ``tmp`` hold ``c1 - c0`` elements, ``out`` is returned.
    """
    np.subtract(x[c0 + 2 * lag : c1 + 2 * lag], x[c0 + lag : c1 + lag], out=out)
    np.subtract(x[c0 + lag : c1 + lag], x[c0:c1], out=tmp)
    out -= tmp
    return out


def third_difference(x: FloatArray, lag: int, c0: int, c1: int, out: FloatArray,
                     tmp: FloatArray) -> FloatArray:
    """``out[i - c0] = (x[i+3L] - x[i]) - 3 (x[i+2L] - x[i+L])`` for ``c0 <= i < c1``."""
    np.subtract(x[c0 + 3 * lag : c1 + 3 * lag], x[c0:c1], out=out)
    np.subtract(x[c0 + 2 * lag : c1 + 2 * lag], x[c0 + lag : c1 + lag], out=tmp)
    tmp *= 3.0
    out -= tmp
    return out


def _chunk_buffers(count: int, number: int) -> tuple[int, list[FloatArray]]:
    """The chunk length for ``count`` elements and ``number`` float64 buffers of it."""
    c = min(CHUNK, count)
    return c, [np.empty(c, dtype=np.float64) for _ in range(number)]


#: ``numpy.vecdot`` (numpy 2): the BLAS dot product of every row in one call.
_VECDOT = getattr(np, "vecdot", None)


def _sumsq(v: FloatArray) -> float:
    """``sum(v**2)`` by single-threaded BLAS dot products over blocks of :data:`DOT_BLOCK`,
    added in order.  The whole blocks go to one ``numpy.vecdot`` call where numpy has it:
    its rows are the same ``ddot`` calls as ``numpy.dot`` of each block (the same values),
    with one Python call instead of one per block."""
    if v.size <= DOT_BLOCK:
        return float(np.dot(v, v))
    total = 0.0
    whole = v.size // DOT_BLOCK * DOT_BLOCK
    if _VECDOT is not None:
        rows = v[:whole].reshape(-1, DOT_BLOCK)
        for d in _VECDOT(rows, rows).tolist():
            total += d
    else:
        for s in range(0, whole, DOT_BLOCK):
            w = v[s : s + DOT_BLOCK]
            total += float(np.dot(w, w))
    if whole < v.size:
        w = v[whole:]
        total += float(np.dot(w, w))
    return total


#: Lags below this are walked together by :func:`ss_second_lags`: its window of the phase
#: (``CHUNK + 2 lag`` points) and the two blocks stay in a 2 MiB L2 cache.
SHARED_WALK_BELOW = 8192


def hook_sees_chunks(lag: int, terms: int) -> bool:
    """Whether :func:`ss_second` at ``lag`` over ``terms`` terms hands its chunks to a hook
    (``lag`` below the chunk size; otherwise it walks lanes of stride ``lag``)."""
    return lag < min(CHUNK, terms)


def ss_second(p: FloatArray, lag: int, terms: int, hook: ChunkHook | None = None) -> float:
    """``sum (p[i+2L] - 2 p[i+L] + p[i])^2``, ``i < terms`` (SP1065 eqs. 7 and 11).

    Written as ``v_i = d_{i+L} - d_i`` with the lag-L first difference
    ``d_j = p_{j+L} - p_j`` (the values of :func:`second_difference`).  Each ``d`` block is
    computed once: for ``L`` below the chunk size a block of ``d`` covers the chunk plus
    ``L``; for larger ``L`` the index range is walked in lanes ``r, r+L, r+2L, ...`` so that
    the ``d`` block of one step is the ``d_i`` of the next.  Two ufunc passes and one dot
    per element.  ``hook`` (:data:`ChunkHook`) sees every chunk's blocks when ``L`` is below
    the chunk size, in order (:class:`fogts.allan.decimated.SumsCollector` takes the noise
    identification's sums from them); it is ignored otherwise.
    """
    k = min(CHUNK, terms)
    total = 0.0
    if hook_sees_chunks(lag, terms):
        dbuf = np.empty(k + lag, dtype=np.float64)
        vbuf = np.empty(k, dtype=np.float64)
        for s in range(0, terms, k):
            total += _second_chunk(p, lag, s, min(s + k, terms), dbuf, vbuf, hook)
        return total
    prev_buf = np.empty(k, dtype=np.float64)
    cur_buf = np.empty(k, dtype=np.float64)
    for r in range(0, min(lag, terms), k):
        w = min(k, lag - r, terms - r)
        prev = prev_buf[:w]
        np.subtract(p[r + lag : r + lag + w], p[r : r + w], out=prev)  # d[r : r+w]
        s = r
        while s < terms:
            w = min(w, terms - s)
            cur = cur_buf[:w]
            np.subtract(p[s + 2 * lag : s + 2 * lag + w], p[s + lag : s + lag + w], out=cur)
            v = prev_buf[:w]
            np.subtract(cur, v, out=v)
            total += _sumsq(v)
            prev_buf, cur_buf = cur_buf, prev_buf  # d[s+L : s+L+w] is the next d_i block
            s += lag
    return total


def _second_chunk(p: FloatArray, lag: int, s: int, e: int, dbuf: FloatArray, vbuf: FloatArray,
                  hook: ChunkHook | None) -> float:
    """The sum of squares of :func:`ss_second` over the terms ``[s, e)``: the ``d`` block
    ``[s, e + L)`` and ``v`` block ``[s, e)`` formed in ``dbuf`` and ``vbuf``."""
    w = e - s
    d = dbuf[: w + lag]
    np.subtract(p[s + lag : e + 2 * lag], p[s : e + lag], out=d)
    v = vbuf[:w]
    np.subtract(d[lag:], d[:w], out=v)
    total = _sumsq(v)
    if hook is not None:
        hook(s, e, d, v)
    return total


def ss_second_lags(p: FloatArray, lags: Sequence[int], terms: Sequence[int],
                   hooks: Sequence[ChunkHook | None]) -> list[float]:
    """:func:`ss_second` at several lags in one walk over ``p``, chunk by chunk.

    Every lag must hand its chunks to a hook (:func:`hook_sees_chunks`).  At each chunk
    the phase window ``[s, s + CHUNK + 2 max(lags))`` is read from memory by the first lag
    and from cache by the others, so the lags share one read of the phase instead of one
    each.  The blocks, their order and hence every sum are those of :func:`ss_second`.
    """
    top = max(lags)
    k = min(CHUNK, max(terms))
    dbuf = np.empty(k + top, dtype=np.float64)
    vbuf = np.empty(k, dtype=np.float64)
    totals = [0.0] * len(lags)
    for s in range(0, max(terms), CHUNK):
        for i, (lag, count, hook) in enumerate(zip(lags, terms, hooks, strict=True)):
            if s < count:
                e = min(s + min(CHUNK, count), count)
                totals[i] += _second_chunk(p, lag, s, e, dbuf, vbuf, hook)
    return totals


def ss_third(p: FloatArray, lag: int, terms: int) -> float:
    """``sum (p[i+3L] - 3 p[i+2L] + 3 p[i+L] - p[i])^2``, ``i < terms`` (SP1065 eqs. 18, 20)."""
    c, (a, b) = _chunk_buffers(terms, 2)
    total = 0.0
    for s in range(0, terms, c):
        e = min(s + c, terms)
        total += _sumsq(third_difference(p, lag, s, e, a[: e - s], b[: e - s]))
    return total


def ss_mod(x: FloatArray, m: int, terms: int) -> float:
    """``sum_j (sum_{i=j}^{j+m-1} (x[i+2m] - 2x[i+m] + x[i]))^2``, ``j < terms`` (SP1065 eq. 14).

    The inner moving sum is a difference of the running sum ``V`` of the second
    differences ``v`` (which are small), not a third difference of a doubly integrated
    phase, so it keeps full precision.
    """
    nv = x.size - 2 * m                      # number of second differences
    run = np.empty(nv + 1, dtype=np.float64)  # V[0] = 0, V[k] = sum_{i<k} v_i
    run[0] = 0.0
    c, (a, b) = _chunk_buffers(nv, 2)
    carry = 0.0
    for s in range(0, nv, c):
        e = min(s + c, nv)
        seg = run[s + 1 : e + 1]
        np.cumsum(second_difference(x, m, s, e, a[: e - s], b[: e - s]), out=seg)
        if carry != 0.0:
            seg += carry
        carry = float(seg[-1])
    total = 0.0
    c = min(CHUNK, terms)
    for s in range(0, terms, c):
        e = min(s + c, terms)
        va = a[: e - s]
        np.subtract(run[s + m : e + m], run[s:e], out=va)
        total += _sumsq(va)
    return total


def _reflected(x: FloatArray, k0: int, k1: int, out: FloatArray) -> FloatArray:
    """``x*[k0:k1]`` of the reflection-extended phase of SP1065 eq. 25 (0-based).

    ``x*[-j] = 2 x[0] - x[j]`` and ``x*[N-1+j] = 2 x[N-1] - x[N-1-j]`` for ``j >= 1``;
    returns a view of ``x`` when no reflection is involved, else fills ``out``.
    """
    npts = x.size
    if k0 >= 0 and k1 <= npts:
        return x[k0:k1]
    res = out[: k1 - k0]
    pos = 0
    if k0 < 0:  # left reflection, k in [k0, min(k1, 0))
        hi = min(k1, 0)
        cnt = hi - k0
        np.subtract(2.0 * x[0], x[-hi + 1 : -k0 + 1][::-1], out=res[:cnt])
        pos = cnt
    lo, hi = max(k0, 0), min(k1, npts)
    if hi > lo:  # plain phase
        res[pos : pos + hi - lo] = x[lo:hi]
        pos += hi - lo
    if k1 > npts:  # right reflection, k in [max(k0, N), k1) -> index 2(N-1) - k
        lo = max(k0, npts)
        top = 2 * (npts - 1)
        np.subtract(2.0 * x[-1], x[top - k1 + 1 : top - lo + 1][::-1], out=res[pos:])
    return res


def ss_total(x: FloatArray, m: int) -> float:
    """``sum_{i=1}^{N-2} (x*[i-m] - 2 x[i] + x*[i+m])^2`` (SP1065 eq. 25, 0-based)."""
    npts = x.size
    terms = npts - 2
    c, (a, b, ra, rb) = _chunk_buffers(terms, 4)
    total = 0.0
    for s in range(1, terms + 1, c):
        e = min(s + c, terms + 1)
        k = e - s
        va, vb = a[:k], b[:k]
        mid = x[s:e]
        np.subtract(_reflected(x, s - m, e - m, ra), mid, out=va)
        np.subtract(_reflected(x, s + m, e + m, rb), mid, out=vb)
        va += vb
        total += _sumsq(va)
    return total


def _second_norm(m: int, terms: int) -> float:
    return 2.0 * m * m * terms


def _third_norm(m: int, terms: int) -> float:
    return 6.0 * m * m * terms


def _mod_norm(m: int, terms: int) -> float:
    return 2.0 * float(m) ** 4 * terms


#: Per kind, the divisor that turns the sum of squares of ``terms`` terms at averaging
#: factor ``m`` (unscaled phase) into the variance: ``2 m^2 terms`` for the Allan and total
#: variances, ``6 m^2 terms`` for the Hadamard variances, ``2 m^4 terms`` for the modified
#: Allan variance (its inner sum of m second differences).
NORMALISATION: dict[str, Callable[[int, int], float]] = {
    "adev": _second_norm, "oadev": _second_norm, "totdev": _second_norm,
    "hdev": _third_norm, "ohdev": _third_norm, "mdev": _mod_norm,
}
