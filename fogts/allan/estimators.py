"""Allan-family estimators of rate data, phase-based and vectorised (numpy kernels).

The rate ``y`` (any unit, ``n`` samples at ``fs_hz``) is integrated once to the "phase"
(angle) ``x_k = sum_{j<k} y_j / fs``, ``k = 0..n`` (``N = n + 1`` points; seed 000 eq. 3
and NIST SP1065 section 5.2), and every statistic is formed from differences of ``x``:

* ``adev``   non-overlapping Allan deviation, SP1065 eq. 7 on the phase decimated by m;
* ``oadev``  overlapping Allan deviation, SP1065 eq. 11 (the default of fogts);
* ``mdev``   modified Allan deviation, SP1065 eq. 14;
* ``hdev``   non-overlapping Hadamard deviation, SP1065 eq. 18 on the decimated phase;
* ``ohdev``  overlapping Hadamard deviation, SP1065 eq. 20;
* ``totdev`` total deviation, SP1065 eq. 25 (phase extended by reflection at both ends).

Results are in the unit of ``y``.  allantools equivalent:
``allantools.oadev(y, rate=fs_hz, data_type="freq", taus=m / fs_hz)``; Stable32 gives the
same numbers for frequency data.

Implementation notes
--------------------
* The mean of ``y`` is removed before integrating.  Every statistic here is exactly
  invariant to a constant added to ``y`` (a linear phase ramp is annihilated by the second
  and third differences and preserved by the totdev reflection), so this changes nothing
  mathematically, but it keeps the phase small and avoids the cancellation that a large
  bias (Earth rate, a gyro offset) would otherwise cause.
* The phase is kept in units of "rate x sample"; ``1 / fs`` cancels between the phase and
  ``tau = m / fs``, so no scaling pass is needed: e.g. OADEV^2 = sum(v^2) / (2 m^2 n)
  with ``v`` the second difference of the unscaled phase.
* Sums of squares are accumulated over cache-sized chunks with preallocated buffers and
  ``np.dot``: the only large array is the phase itself (one copy of the input); ``mdev``
  also needs one running-sum array per worker thread.
* Different taus run on a thread pool (numpy and BLAS release the GIL).
"""

from __future__ import annotations

import os
from collections.abc import Callable
from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass
from typing import Any

import numpy as np
import numpy.typing as npt

from fogts._typing import FloatArray, IntArray
from fogts._validate import check_int, check_positive, to_float_array
from fogts.allan.taus import MIN_TERMS, n_terms
from fogts.errors import DataError

__all__ = [
    "ESTIMATORS",
    "EstimatorOutput",
    "adev",
    "hdev",
    "mdev",
    "oadev",
    "ohdev",
    "phase_from_rate",
    "totdev",
]

#: Elements per chunk of the sum-of-squares loops (256 KiB of float64: stays in L2).
CHUNK = 1 << 15
#: Largest block handed to one ``np.dot``: OpenBLAS multithreads ``ddot`` above 10,000
#: elements, which is slower than one thread for cache-sized blocks and collapses on a
#: loaded machine (measured: 3 us at 8,192 elements, 2 ms at 10,001).
DOT_BLOCK = 8192
#: Below this many (terms x taus) the thread pool costs more than it saves.
_PARALLEL_MIN_WORK = 4_000_000


@dataclass(frozen=True)
class EstimatorOutput:
    """Deviations of one estimator at a set of averaging factors.

    Attributes
    ----------
    kind : str
        Estimator name.
    m : ndarray of int64
        Averaging factors.
    tau_s : ndarray of float64
        ``m / fs_hz``.
    dev : ndarray of float64
        The deviation at each tau, in the unit of the input rate.
    n : ndarray of int64
        Number of terms summed (Stable32's ``#``, allantools' ``ns``).
    """

    kind: str
    m: IntArray
    tau_s: FloatArray
    dev: FloatArray
    n: IntArray

    @property
    def avar(self) -> FloatArray:
        """The variance, ``dev ** 2``."""
        return self.dev**2


# ---------------------------------------------------------------------------------------
# Phase


def phase_from_rate(y: FloatArray) -> FloatArray:
    """Integrate the mean-removed rate once: ``x_0 = 0``, ``x_k = sum_{j<k} (y_j - mean)``.

    The result (``n + 1`` points) is the phase in units of rate x sample period, i.e. the
    angle times ``fs``; seed 000 eq. 3 and SP1065 eq. 4 integrate the same way.

    Examples
    --------
    >>> phase_from_rate(np.array([1.0, 3.0, 2.0])).tolist()
    [0.0, -1.0, 0.0, 0.0]
    """
    n = y.size
    x = np.empty(n + 1, dtype=np.float64)
    x[0] = 0.0
    mean = float(np.mean(y))
    buf = np.empty(min(CHUNK, max(n, 1)), dtype=np.float64)
    carry = 0.0
    for s in range(0, n, CHUNK):
        e = min(s + CHUNK, n)
        b = buf[: e - s]
        np.subtract(y[s:e], mean, out=b)
        seg = x[s + 1 : e + 1]
        np.cumsum(b, out=seg)
        if carry != 0.0:
            seg += carry
        carry = float(seg[-1])
    return x


def _sumsq(v: FloatArray) -> float:
    """``sum(v**2)`` by single-threaded BLAS dot products over blocks of :data:`DOT_BLOCK`."""
    if v.size <= DOT_BLOCK:
        return float(np.dot(v, v))
    total = 0.0
    for s in range(0, v.size, DOT_BLOCK):
        w = v[s : s + DOT_BLOCK]
        total += float(np.dot(w, w))
    return total


# ---------------------------------------------------------------------------------------
# Sum-of-squares kernels on the (unscaled) phase.  Each returns sum(v_i^2) over i < terms.


def _ss_second(p: FloatArray, lag: int, terms: int) -> float:
    """``sum (p[i+2L] - 2 p[i+L] + p[i])^2``, ``i < terms`` (SP1065 eqs. 7 and 11).

    Written as ``v_i = d_{i+L} - d_i`` with the lag-L first difference
    ``d_j = p_{j+L} - p_j`` (both differences are small, so this is also the accurate way
    round).  Each ``d`` block is computed once: for ``L`` below the chunk size a block of
    ``d`` covers the chunk plus ``L``; for larger ``L`` the index range is walked in
    lanes ``r, r+L, r+2L, ...`` so that the ``d`` block of one step is the ``d_i`` of the
    next.  Two ufunc passes and one dot per element.
    """
    k = min(CHUNK, terms)
    total = 0.0
    if lag < k:
        dbuf = np.empty(k + lag, dtype=np.float64)
        vbuf = np.empty(k, dtype=np.float64)
        for s in range(0, terms, k):
            e = min(s + k, terms)
            w = e - s
            d = dbuf[: w + lag]
            np.subtract(p[s + lag : e + 2 * lag], p[s : e + lag], out=d)
            v = vbuf[:w]
            np.subtract(d[lag:], d[:w], out=v)
            total += _sumsq(v)
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


def _ss_third(p: FloatArray, lag: int, terms: int) -> float:
    """``sum (p[i+3L] - 3 p[i+2L] + 3 p[i+L] - p[i])^2``, ``i < terms`` (SP1065 eqs. 18, 20)."""
    c = min(CHUNK, terms)
    a = np.empty(c, dtype=np.float64)
    b = np.empty(c, dtype=np.float64)
    total = 0.0
    for s in range(0, terms, c):
        e = min(s + c, terms)
        k = e - s
        va, vb = a[:k], b[:k]
        np.subtract(p[s + 3 * lag : e + 3 * lag], p[s:e], out=va)
        np.subtract(p[s + 2 * lag : e + 2 * lag], p[s + lag : e + lag], out=vb)
        vb *= 3.0
        va -= vb
        total += _sumsq(va)
    return total


def _ss_mod(x: FloatArray, m: int, terms: int) -> float:
    """``sum_j (sum_{i=j}^{j+m-1} (x[i+2m] - 2x[i+m] + x[i]))^2``, ``j < terms`` (SP1065 eq. 14).

    The inner moving sum is a difference of the running sum ``V`` of the second
    differences ``v`` (which are small), not a third difference of a doubly integrated
    phase, so it keeps full precision.
    """
    nv = x.size - 2 * m                      # number of second differences
    run = np.empty(nv + 1, dtype=np.float64)  # V[0] = 0, V[k] = sum_{i<k} v_i
    run[0] = 0.0
    c = min(CHUNK, nv)
    a = np.empty(c, dtype=np.float64)
    b = np.empty(c, dtype=np.float64)
    carry = 0.0
    for s in range(0, nv, c):
        e = min(s + c, nv)
        k = e - s
        va, vb = a[:k], b[:k]
        np.subtract(x[s + 2 * m : e + 2 * m], x[s + m : e + m], out=va)
        np.subtract(x[s + m : e + m], x[s:e], out=vb)
        va -= vb
        seg = run[s + 1 : e + 1]
        np.cumsum(va, out=seg)
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


def _ss_total(x: FloatArray, m: int) -> float:
    """``sum_{i=1}^{N-2} (x*[i-m] - 2 x[i] + x*[i+m])^2`` (SP1065 eq. 25, 0-based)."""
    npts = x.size
    terms = npts - 2
    c = min(CHUNK, terms)
    a = np.empty(c, dtype=np.float64)
    b = np.empty(c, dtype=np.float64)
    ra = np.empty(c, dtype=np.float64)
    rb = np.empty(c, dtype=np.float64)
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


# ---------------------------------------------------------------------------------------
# Drivers


def _workers(workers: int | None, n_taus: int, work: int) -> int:
    if workers is not None:
        return min(check_int("workers", workers, minimum=1), max(n_taus, 1))
    if work < _PARALLEL_MIN_WORK or n_taus < 2:
        return 1
    return max(1, min(os.cpu_count() or 1, n_taus))


def _prepare(kind: str, y: Any, fs_hz: float, m: npt.ArrayLike
             ) -> tuple[FloatArray, float, IntArray, IntArray]:
    fs = check_positive("fs_hz", fs_hz)
    arr = to_float_array(y, "y", min_length=2)
    mm = np.asarray(m)
    if mm.ndim == 0:
        mm = mm.reshape(1)
    if mm.ndim != 1 or mm.size == 0:
        raise DataError(f"m must be a non-empty 1-D array of averaging factors, got shape "
                        f"{mm.shape}")
    if not np.issubdtype(mm.dtype, np.integer):
        if not (np.issubdtype(mm.dtype, np.floating) and np.all(np.isfinite(mm))
                and np.all(mm == np.rint(mm))):
            raise DataError(f"m must hold whole numbers (averaging factors), got {mm[:5]!r}")
    mm = mm.astype(np.int64)
    if np.any(mm < 1):
        raise DataError(f"m must be >= 1, got {int(mm[np.argmax(mm < 1)])}")
    terms = n_terms(kind, mm, arr.size)
    short = terms < MIN_TERMS
    if short.any():
        bad = int(mm[np.argmax(short)])
        raise DataError(f"m = {bad} gives {int(terms[np.argmax(short)])} term(s) for {kind} "
                        f"with {arr.size} samples; at least {MIN_TERMS} are needed (build "
                        "the grid with fogts.allan.taus.tau_grid, which drops such taus)")
    return arr, fs, mm, terms


def _run(kind: str, y: Any, fs_hz: float, m: npt.ArrayLike, workers: int | None,
         sumsq: Callable[[FloatArray, int, int], float], norm: Callable[[int, int], float]
         ) -> EstimatorOutput:
    arr, fs, mm, terms = _prepare(kind, y, fs_hz, m)
    x = phase_from_rate(arr)
    nw = _workers(workers, mm.size, int(terms.sum()))

    def one(i: int) -> float:
        mi, ti = int(mm[i]), int(terms[i])
        return float(np.sqrt(sumsq(x, mi, ti) / norm(mi, ti)))

    if nw == 1:
        devs = [one(i) for i in range(mm.size)]
    else:
        # Largest jobs first so that the pool ends evenly.
        order = np.argsort(-terms, kind="stable")
        with ThreadPoolExecutor(max_workers=nw) as pool:
            res = dict(zip(order.tolist(), pool.map(one, order.tolist()), strict=True))
        devs = [res[i] for i in range(mm.size)]
    return EstimatorOutput(kind=kind, m=mm, tau_s=mm / fs,
                           dev=np.asarray(devs, dtype=np.float64), n=terms)


def adev(y: npt.ArrayLike, *, fs_hz: float, m: npt.ArrayLike,
         workers: int | None = None) -> EstimatorOutput:
    r"""Non-overlapping Allan deviation of rate data.

    .. math:: \sigma_y^2(\tau) = \frac{1}{2 (M-2) \tau^2} \sum_{i=1}^{M-2}
              (x_{i+2} - 2 x_{i+1} + x_i)^2

    on the phase decimated by m (``M = floor((N-1)/m) + 1`` points), NIST SP1065 eq. 7;
    the phase is the once-integrated rate (seed 000 eq. 3).

    Parameters
    ----------
    y : array_like
        Rate samples (any unit; the deviation has the same unit).
    fs_hz : float
        Sample rate.
    m : array_like of int
        Averaging factors, ``tau = m / fs_hz``; each must give at least two terms
        (see :func:`fogts.allan.taus.tau_grid`).
    workers : int, optional
        Threads to spread the taus over (default: all cores for large inputs).

    Returns
    -------
    EstimatorOutput

    Examples
    --------
    >>> y = np.random.default_rng(0).normal(size=1000)
    >>> out = adev(y, fs_hz=1.0, m=[1, 10])
    >>> out.n.tolist(), bool(0.9 < out.dev[0] < 1.1)
    ([999, 99], True)
    """
    def sumsq(x: FloatArray, mi: int, ti: int) -> float:
        return _ss_second(x[::mi], 1, ti)

    return _run("adev", y, fs_hz, m, workers, sumsq, lambda mi, ti: 2.0 * mi * mi * ti)


def oadev(y: npt.ArrayLike, *, fs_hz: float, m: npt.ArrayLike,
          workers: int | None = None) -> EstimatorOutput:
    r"""Overlapping Allan deviation of rate data (the fogts default).

    .. math:: \sigma_y^2(m\tau_0) = \frac{1}{2 m^2 \tau_0^2 (N-2m)} \sum_{i=1}^{N-2m}
              (x_{i+2m} - 2 x_{i+m} + x_i)^2

    NIST SP1065 eq. 11, with the phase ``x`` the once-integrated rate (seed 000 eq. 3).
    Same as ``allantools.oadev(y, rate=fs_hz, data_type="freq", taus=m / fs_hz)``.

    Parameters
    ----------
    y : array_like
        Rate samples (any unit; the deviation has the same unit).
    fs_hz : float
        Sample rate.
    m : array_like of int
        Averaging factors (at least two terms each: ``m <= (n - 1) / 2``).
    workers : int, optional
        Threads to spread the taus over.

    Returns
    -------
    EstimatorOutput

    Examples
    --------
    >>> y = np.random.default_rng(0).normal(size=1000)
    >>> out = oadev(y, fs_hz=10.0, m=[1, 10, 100])
    >>> out.tau_s.tolist(), out.n.tolist()
    ([0.1, 1.0, 10.0], [999, 981, 801])
    """
    return _run("oadev", y, fs_hz, m, workers, _ss_second,
                lambda mi, ti: 2.0 * mi * mi * ti)


def mdev(y: npt.ArrayLike, *, fs_hz: float, m: npt.ArrayLike,
         workers: int | None = 1) -> EstimatorOutput:
    r"""Modified Allan deviation of rate data.

    .. math:: \mathrm{Mod}\,\sigma_y^2(m\tau_0) = \frac{1}{2 m^2 (m\tau_0)^2 (N-3m+1)}
              \sum_{j=1}^{N-3m+1} \Big[\sum_{i=j}^{j+m-1} (x_{i+2m} - 2x_{i+m} + x_i)\Big]^2

    NIST SP1065 eq. 14.

    Parameters
    ----------
    y : array_like
        Rate samples.
    fs_hz : float
        Sample rate.
    m : array_like of int
        Averaging factors (``m <= n / 3``).
    workers : int, optional
        Threads (default 1: each worker needs a running-sum array as large as the input).

    Returns
    -------
    EstimatorOutput

    Examples
    --------
    >>> y = np.random.default_rng(0).normal(size=1000)
    >>> mdev(y, fs_hz=1.0, m=[1, 10]).n.tolist()
    [999, 972]
    """
    return _run("mdev", y, fs_hz, m, workers, _ss_mod,
                lambda mi, ti: 2.0 * float(mi) ** 4 * ti)


def hdev(y: npt.ArrayLike, *, fs_hz: float, m: npt.ArrayLike,
         workers: int | None = None) -> EstimatorOutput:
    r"""Non-overlapping Hadamard deviation of rate data.

    .. math:: H\sigma_y^2(\tau) = \frac{1}{6 \tau^2 (M-3)} \sum_{i=1}^{M-3}
              (x_{i+3} - 3x_{i+2} + 3x_{i+1} - x_i)^2

    on the phase decimated by m, NIST SP1065 eq. 18.

    Parameters
    ----------
    y : array_like
        Rate samples.
    fs_hz : float
        Sample rate.
    m : array_like of int
        Averaging factors (``m <= n / 4``).
    workers : int, optional
        Threads to spread the taus over.

    Returns
    -------
    EstimatorOutput

    Examples
    --------
    >>> y = np.random.default_rng(0).normal(size=1000)
    >>> hdev(y, fs_hz=1.0, m=[1, 10]).n.tolist()
    [998, 98]
    """
    def sumsq(x: FloatArray, mi: int, ti: int) -> float:
        return _ss_third(x[::mi], 1, ti)

    return _run("hdev", y, fs_hz, m, workers, sumsq, lambda mi, ti: 6.0 * mi * mi * ti)


def ohdev(y: npt.ArrayLike, *, fs_hz: float, m: npt.ArrayLike,
          workers: int | None = None) -> EstimatorOutput:
    r"""Overlapping Hadamard deviation of rate data.

    .. math:: H\sigma_y^2(m\tau_0) = \frac{1}{6 m^2 \tau_0^2 (N-3m)} \sum_{i=1}^{N-3m}
              (x_{i+3m} - 3x_{i+2m} + 3x_{i+m} - x_i)^2

    NIST SP1065 eq. 20.

    Parameters
    ----------
    y : array_like
        Rate samples.
    fs_hz : float
        Sample rate.
    m : array_like of int
        Averaging factors (``m <= (n - 1) / 3``).
    workers : int, optional
        Threads to spread the taus over.

    Returns
    -------
    EstimatorOutput

    Examples
    --------
    >>> y = np.random.default_rng(0).normal(size=1000)
    >>> ohdev(y, fs_hz=1.0, m=[1, 10]).n.tolist()
    [998, 971]
    """
    return _run("ohdev", y, fs_hz, m, workers, _ss_third,
                lambda mi, ti: 6.0 * mi * mi * ti)


def totdev(y: npt.ArrayLike, *, fs_hz: float, m: npt.ArrayLike,
           workers: int | None = None) -> EstimatorOutput:
    r"""Total deviation of rate data.

    .. math:: \mathrm{Tot}\,\sigma_y^2(m\tau_0) = \frac{1}{2 (m\tau_0)^2 (N-2)}
              \sum_{i=2}^{N-1} (x^*_{i-m} - 2x_i + x^*_{i+m})^2

    NIST SP1065 eq. 25, where ``x*`` extends the phase by reflection at both ends,
    ``x*_{1-j} = 2x_1 - x_{1+j}`` and ``x*_{N+j} = 2x_N - x_{N-j}``.  No bias correction
    is applied (as Stable32's TOTDEV for Allan-type output and allantools).

    Parameters
    ----------
    y : array_like
        Rate samples.
    fs_hz : float
        Sample rate.
    m : array_like of int
        Averaging factors (``m <= n / 2``: tau up to half the record).
    workers : int, optional
        Threads to spread the taus over.

    Returns
    -------
    EstimatorOutput

    Examples
    --------
    >>> y = np.random.default_rng(0).normal(size=1000)
    >>> totdev(y, fs_hz=1.0, m=[1, 500]).n.tolist()
    [999, 999]
    """
    def sumsq(x: FloatArray, mi: int, ti: int) -> float:
        return _ss_total(x, mi)

    return _run("totdev", y, fs_hz, m, workers, sumsq, lambda mi, ti: 2.0 * mi * mi * ti)


#: Estimator functions by name.
ESTIMATORS: dict[str, Callable[..., EstimatorOutput]] = {
    "adev": adev, "oadev": oadev, "mdev": mdev, "hdev": hdev, "ohdev": ohdev,
    "totdev": totdev,
}
