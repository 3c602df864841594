"""Allan-family estimators of rate data, phase-based and vectorised (numpy kernels).

The rate ``y`` (any unit, ``n`` samples at ``fs_hz``) is integrated once to the "phase"
(angle) ``x_k = sum_{j<k} y_j / fs``, ``k = 0..n`` (``N = n + 1`` points; NIST SP1065
section 5.2), and every statistic is formed from differences of ``x``
(:mod:`fogts.allan.kernels`):

* ``adev``   non-overlapping Allan deviation, SP1065 eq. 7 on the phase decimated by m;
* ``oadev``  overlapping Allan deviation, SP1065 eq. 11 (the default of fogts);
* ``mdev``   modified Allan deviation, SP1065 eq. 14;
* ``hdev``   non-overlapping Hadamard deviation, SP1065 eq. 18 on the decimated phase;
* ``ohdev``  overlapping Hadamard deviation, SP1065 eq. 20;
* ``totdev`` total deviation, SP1065 eq. 25 (phase extended by reflection at both ends).

Results are in the unit of ``y``.  allantools equivalent:
``allantools.oadev(y, rate=fs_hz, data_type="freq", taus=m / fs_hz)``; Stable32 gives the
same numbers for frequency data.  Different taus run on a thread pool (numpy and BLAS
release the GIL).
"""

from __future__ import annotations

import os
import textwrap
from collections.abc import Callable
from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass
from typing import Any, TypeVar

import numpy as np
import numpy.typing as npt

from fogts import progress
from fogts._typing import FloatArray, IntArray
from fogts._validate import check_int, check_positive, checked_sum, to_float_array
from fogts.allan.decimated import (
    COLLECT_BELOW_M,
    DecimatedSums,
    SumsCollector,
    decimated_sums,
)
from fogts.allan.kernels import (
    NORMALISATION,
    SHARED_WALK_BELOW,
    given_up_buffer,
    hook_sees_chunks,
    phase_from_angle,
    phase_from_rate,
    ss_mod,
    ss_second,
    ss_second_lags,
    ss_third,
    ss_total,
)
from fogts.allan.taus import MIN_TERMS, n_terms
from fogts.errors import DataError

__all__ = ["ESTIMATORS", "EstimatorOutput", "PhasedEstimate", "adev", "estimate_from_angle",
           "estimate_with_sums", "hdev", "mdev", "oadev", "ohdev", "phase_deviations",
           "phase_from_rate", "thread_count", "totdev"]

#: Below this many (terms x taus) the thread pool costs more than it saves.
_PARALLEL_MIN_WORK = 4_000_000

SumOfSquares = Callable[[FloatArray, int, int], float]


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


@dataclass(frozen=True)
class PhasedEstimate:
    """An :class:`EstimatorOutput` with the phase it was computed from and, per averaging
    factor, the sums of the decimated phase that the noise identification needs.

    Attributes
    ----------
    output : EstimatorOutput
        The deviations.
    phase : ndarray of float64
        The phase (:func:`~fogts.allan.kernels.phase_from_rate`), ``n + 1`` points.
    sums : tuple of DecimatedSums or None
        Aligned with ``output.m``; None where fewer than 3 blocks of m samples fit
        (:mod:`fogts.allan.decimated`).
    """

    output: EstimatorOutput
    phase: FloatArray
    sums: tuple[DecimatedSums | None, ...]


def _decimated(kernel: SumOfSquares) -> SumOfSquares:
    """The kernel at lag 1 on the phase decimated by m (the non-overlapping estimators)."""
    def sumsq(x: FloatArray, mi: int, ti: int) -> float:
        return kernel(x[::mi], 1, ti)
    return sumsq


def _total(x: FloatArray, mi: int, ti: int) -> float:
    return ss_total(x, mi)


#: Per kind, the sum of squares of ``terms`` terms at averaging factor ``m`` of the phase.
_SUM_OF_SQUARES: dict[str, SumOfSquares] = {
    "adev": _decimated(ss_second), "oadev": ss_second, "mdev": ss_mod,
    "hdev": _decimated(ss_third), "ohdev": ss_third, "totdev": _total,
}


def thread_count(workers: int | None, n_taus: int, work: int) -> int:
    """Threads to spread ``n_taus`` taus over: ``workers`` when given (at most one a
    tau), else all cores once the ``work`` (terms summed over the taus) pays for a pool."""
    if workers is not None:
        return min(check_int("workers", workers, minimum=1), max(n_taus, 1))
    if work < _PARALLEL_MIN_WORK or n_taus < 2:
        return 1
    return max(1, min(os.cpu_count() or 1, n_taus))


def _prepare(kind: str, y: Any, fs_hz: float, m: npt.ArrayLike
             ) -> tuple[FloatArray, float, IntArray, IntArray, float]:
    """The rate (checked finite), sample rate, averaging factors, terms and the rate's mean
    (from the checking pass: :func:`fogts._validate.checked_sum`)."""
    fs = check_positive("fs_hz", fs_hz)
    arr = to_float_array(y, "y", min_length=2, allow_nonfinite=True)
    mean = checked_sum(arr, "y") / arr.size
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
    return arr, fs, mm, terms, mean


def _run(kind: str, y: Any, fs_hz: float, m: npt.ArrayLike, workers: int | None,
         angle: FloatArray | None = None) -> EstimatorOutput:
    """Estimator ``kind`` at every averaging factor, the taus spread over ``workers``;
    ``angle`` (the integral of ``y``, one point more) gives the phase directly."""
    return _run_phased(kind, y, fs_hz, m, workers, angle).output


def _one_tau(kind: str, x: FloatArray, mi: int, ti: int, d_max: int | None
             ) -> tuple[float, DecimatedSums | None]:
    """The deviation at averaging factor ``mi`` (``ti`` terms) of the phase ``x`` and, with
    ``d_max``, the decimated sums of orders up to ``d_max``: from the overlapping Allan
    kernel's own blocks where it forms them (:class:`SumsCollector`), else by a pass over
    the decimated phase (:func:`decimated_sums`)."""
    sumsq, norm = _SUM_OF_SQUARES[kind], NORMALISATION[kind]
    sums = None
    if d_max == 1 and kind == "oadev" and mi < COLLECT_BELOW_M and hook_sees_chunks(mi, ti):
        collector = SumsCollector(x, mi)
        total = ss_second(x, mi, ti, collector.add)
        sums = collector.result()
    else:
        total = sumsq(x, mi, ti)
        if d_max is not None and (x.size - 1) // mi >= 3:
            sums = decimated_sums(x, mi, d_max)
    return float(np.sqrt(total / norm(mi, ti))), sums


def phase_deviations(kind: str, x: FloatArray, m: IntArray) -> FloatArray:
    """The deviations of :data:`ESTIMATORS` ``[kind]`` at the averaging factors ``m`` (each
    with at least 2 terms) of the phase ``x`` of :func:`phase_from_rate` (``n + 1``
    points), on one thread, for a caller that holds the phase already.

    Examples
    --------
    >>> y = np.random.default_rng(0).normal(size=1000)
    >>> got = phase_deviations("mdev", phase_from_rate(y), np.array([1, 10]))
    >>> bool(np.array_equal(got, mdev(y, fs_hz=1.0, m=[1, 10]).dev))
    True
    """
    terms = n_terms(kind, m, x.size - 1)
    return np.array([_one_tau(kind, x, int(mi), int(ti), None)[0]
                     for mi, ti in zip(m.tolist(), terms.tolist(), strict=True)])


def _shared_walk(x: FloatArray, m: IntArray, terms: IntArray, d_max: int | None
                 ) -> list[tuple[float, DecimatedSums | None]]:
    """:func:`_one_tau` of ``oadev`` at several small averaging factors, in one walk over the
    phase (:func:`~fogts.allan.kernels.ss_second_lags`; the same sums)."""
    collectors = [SumsCollector(x, int(mi)) if d_max == 1 and mi < COLLECT_BELOW_M else None
                  for mi in m.tolist()]
    totals = ss_second_lags(x, m.tolist(), terms.tolist(),
                            [c.add if c is not None else None for c in collectors])
    norm = NORMALISATION["oadev"]
    out: list[tuple[float, DecimatedSums | None]] = []
    for mi, ti, total, col in zip(m.tolist(), terms.tolist(), totals, collectors, strict=True):
        sums = (col.result() if col is not None else decimated_sums(x, mi, d_max)
                if d_max is not None and (x.size - 1) // mi >= 3 else None)
        out.append((float(np.sqrt(total / norm(mi, ti))), sums))
    return out


def _jobs(kind: str, m: IntArray, terms: IntArray, workers: int) -> list[list[int]]:
    """The taus (indices) each job of the pool computes, largest jobs first: the small
    ``oadev`` lags in ``workers`` shared walks over the phase
    (:data:`~fogts.allan.kernels.SHARED_WALK_BELOW`), every other tau alone."""
    shared = [i for i, (mi, ti) in enumerate(zip(m.tolist(), terms.tolist(), strict=True))
              if kind == "oadev" and mi < SHARED_WALK_BELOW and hook_sees_chunks(mi, ti)]
    if len(shared) < 2:
        shared = []
    alone = set(shared)
    singles = [[i] for i in np.argsort(-terms, kind="stable").tolist() if i not in alone]
    return [g for g in (shared[w::workers] for w in range(workers)) if g] + singles


def _run_phased(kind: str, y: Any, fs_hz: float, m: npt.ArrayLike, workers: int | None,
                angle: FloatArray | None = None, d_max: int | None = None) -> PhasedEstimate:
    """:func:`_run`, keeping the phase and, with ``d_max``, the decimated sums."""
    arr, fs, mm, terms, mean = _prepare(kind, y, fs_hz, m)
    if angle is not None and angle.shape != (arr.size + 1,):
        raise DataError(f"angle must have one point more than the rate ({arr.size + 1}), "
                        f"got shape {angle.shape}")
    if angle is None:  # in the rate's own buffer when the caller gave it up (phase_in_place)
        x = phase_from_rate(arr, mean=mean, out=given_up_buffer(arr))
    else:
        x = phase_from_angle(angle, fs)
    nw = thread_count(workers, mm.size, int(terms.sum()))

    def job(idx: list[int]) -> list[tuple[float, DecimatedSums | None]]:
        if len(idx) > 1:
            return _shared_walk(x, mm[idx], terms[idx], d_max)
        return [_one_tau(kind, x, int(mm[idx[0]]), int(terms[idx[0]]), d_max)]

    tick = progress.ticker(f"{kind}: {mm.size} taus", mm.size)
    jobs = _jobs(kind, mm, terms, nw)
    found: dict[int, tuple[float, DecimatedSums | None]] = {}
    # Largest jobs first so that the pool ends evenly; progress is reported from this
    # thread as the results arrive in order.
    with ThreadPoolExecutor(max_workers=nw) as pool:
        results = map(job, jobs) if nw == 1 else pool.map(job, jobs)
        for idx, got in zip(jobs, results, strict=True):
            for i, one in zip(idx, got, strict=True):  # a tick per tau, also in a shared walk
                found[i] = one
                tick(len(found))
    res = [found[i] for i in range(mm.size)]
    out = EstimatorOutput(kind=kind, m=mm, tau_s=mm / fs,
                          dev=np.asarray([r[0] for r in res], dtype=np.float64), n=terms)
    return PhasedEstimate(output=out, phase=x, sums=tuple(r[1] for r in res))


def estimate_with_sums(kind: str, y: npt.ArrayLike, *, fs_hz: float, m: npt.ArrayLike,
                       d_max: int, workers: int | None = None) -> PhasedEstimate:
    """Estimator ``kind`` of the rate ``y``, with its phase and the decimated sums of orders
    up to ``d_max`` that the lag-1 ACF noise identification needs
    (:mod:`fogts.allan.decimated`), taken in the same pass as the deviation for ``oadev``.

    The deviations equal those of :data:`ESTIMATORS` (the same kernels, summed in the same
    order).

    Examples
    --------
    >>> y = np.random.default_rng(0).normal(size=1000)
    >>> est = estimate_with_sums("oadev", y, fs_hz=1.0, m=[1, 10], d_max=1)
    >>> bool(np.allclose(est.output.dev, oadev(y, fs_hz=1.0, m=[1, 10]).dev, rtol=1e-12))
    True
    >>> [s.blocks for s in est.sums], est.phase.size
    ([1000, 100], 1001)
    """
    if kind not in _SUM_OF_SQUARES:
        raise DataError(f"kind must be one of {', '.join(_SUM_OF_SQUARES)}; got {kind!r}")
    return _run_phased(kind, y, fs_hz, m, workers, d_max=check_int("d_max", d_max, minimum=0))


def estimate_from_angle(kind: str, angle: npt.ArrayLike, *, fs_hz: float, m: npt.ArrayLike,
                        workers: int | None = None) -> EstimatorOutput:
    """Estimator ``kind`` (one of :data:`ESTIMATORS`) of an angle record, used as the phase.

    ``angle`` holds ``n + 1`` angles in rate-unit x seconds (deg for a rate in deg/s); the
    deviations are in the rate unit and equal those of the rate ``diff(angle) fs`` up to
    rounding, without forming that difference (:func:`~fogts.allan.kernels.phase_from_angle`).

    Examples
    --------
    >>> y = np.random.default_rng(0).normal(size=1000)
    >>> theta = np.r_[0.0, np.cumsum(y)] / 10.0
    >>> a, b = estimate_from_angle("oadev", theta, fs_hz=10.0, m=[1, 10]), oadev(y, fs_hz=10.0, m=[1, 10])
    >>> bool(np.allclose(a.dev, b.dev, rtol=1e-12, atol=0)), a.n.tolist() == b.n.tolist()
    (True, True)
    """
    theta = to_float_array(angle, "angle", min_length=3)
    fs = check_positive("fs_hz", fs_hz)
    if kind not in _SUM_OF_SQUARES:
        raise DataError(f"kind must be one of {', '.join(_SUM_OF_SQUARES)}; got {kind!r}")
    return _run(kind, np.diff(theta) * fs, fs, m, workers, angle=theta)


_Estimator = TypeVar("_Estimator", bound=Callable[..., EstimatorOutput])

_SHARED_SECTIONS = """\
Parameters
----------
y : array_like
    Rate samples (any unit; the deviation has the same unit).
fs_hz : float
    Sample rate.
m : array_like of int
    Averaging factors, ``tau = m / fs_hz``, each with at least two terms: {m_rule}
    (:func:`fogts.allan.taus.tau_grid` builds such grids).
workers : int, optional
    {workers}

Returns
-------
EstimatorOutput

"""


def _documented(m_rule: str, workers: str = "Threads to spread the taus over (default: all "
                "cores for large inputs).") -> Callable[[_Estimator], _Estimator]:
    """Insert the Parameters and Returns sections the six estimators share before their
    Examples section (indented as that section)."""
    def decorate(fn: _Estimator) -> _Estimator:
        doc = fn.__doc__ or ""
        at = doc.index("Examples\n")
        start = doc.rindex("\n", 0, at) + 1
        sections = _SHARED_SECTIONS.format(m_rule=m_rule, workers=workers)
        fn.__doc__ = doc[:start] + textwrap.indent(sections, doc[start:at]) + doc[start:]
        return fn
    return decorate


@_documented("``m <= n / 3``")
def adev(y: npt.ArrayLike, *, fs_hz: float, m: npt.ArrayLike,
         workers: int | None = None) -> EstimatorOutput:
    r"""Non-overlapping Allan deviation of rate data.

    .. math:: \sigma_y^2(\tau) = \frac{1}{2 (M-2) \tau^2} \sum_{i=1}^{M-2}
              (x_{i+2} - 2 x_{i+1} + x_i)^2

    on the phase (the once-integrated rate) decimated by m
    (``M = floor((N-1)/m) + 1`` points), NIST SP1065 eq. 7.

    Examples
    --------
    >>> out = adev(np.random.default_rng(0).normal(size=1000), fs_hz=1.0, m=[1, 10])
    >>> out.n.tolist(), bool(0.9 < out.dev[0] < 1.1)
    ([999, 99], True)
    """
    return _run("adev", y, fs_hz, m, workers)


@_documented("``m <= (n - 1) / 2``")
def oadev(y: npt.ArrayLike, *, fs_hz: float, m: npt.ArrayLike,
          workers: int | None = None) -> EstimatorOutput:
    r"""Overlapping Allan deviation of rate data (the fogts default).

    .. math:: \sigma_y^2(m\tau_0) = \frac{1}{2 m^2 \tau_0^2 (N-2m)} \sum_{i=1}^{N-2m}
              (x_{i+2m} - 2 x_{i+m} + x_i)^2

    NIST SP1065 eq. 11, with the phase ``x`` the once-integrated rate.
    Same as ``allantools.oadev(y, rate=fs_hz, data_type="freq", taus=m / fs_hz)``.

    Examples
    --------
    >>> y = np.random.default_rng(0).normal(size=1000)
    >>> out = oadev(y, fs_hz=10.0, m=[1, 10, 100])
    >>> out.tau_s.tolist(), out.n.tolist()
    ([0.1, 1.0, 10.0], [999, 981, 801])
    """
    return _run("oadev", y, fs_hz, m, workers)


@_documented("``m <= n / 3``", workers="Threads (default 1: each worker needs a running-sum "
             "array as large as the input).")
def mdev(y: npt.ArrayLike, *, fs_hz: float, m: npt.ArrayLike,
         workers: int | None = 1) -> EstimatorOutput:
    r"""Modified Allan deviation of rate data.

    .. math:: \mathrm{Mod}\,\sigma_y^2(m\tau_0) = \frac{1}{2 m^2 (m\tau_0)^2 (N-3m+1)}
              \sum_{j=1}^{N-3m+1} \Big[\sum_{i=j}^{j+m-1} (x_{i+2m} - 2x_{i+m} + x_i)\Big]^2

    NIST SP1065 eq. 14.

    Examples
    --------
    >>> y = np.random.default_rng(0).normal(size=100_000)     # white rate noise
    >>> ratio = mdev(y, fs_hz=1.0, m=[10]).dev / oadev(y, fs_hz=1.0, m=[10]).dev
    >>> bool(abs(ratio[0] - np.sqrt(101 / 200)) < 0.02)    # MVAR/AVAR = (m^2+1)/(2m^2)
    True
    """
    return _run("mdev", y, fs_hz, m, workers)


@_documented("``m <= n / 4``")
def hdev(y: npt.ArrayLike, *, fs_hz: float, m: npt.ArrayLike,
         workers: int | None = None) -> EstimatorOutput:
    r"""Non-overlapping Hadamard deviation of rate data.

    .. math:: H\sigma_y^2(\tau) = \frac{1}{6 \tau^2 (M-3)} \sum_{i=1}^{M-3}
              (x_{i+3} - 3x_{i+2} + 3x_{i+1} - x_i)^2

    on the phase decimated by m, NIST SP1065 eq. 18.

    Examples
    --------
    >>> hdev(np.random.default_rng(0).normal(size=1000), fs_hz=1.0, m=[1, 10]).n.tolist()
    [998, 98]
    """
    return _run("hdev", y, fs_hz, m, workers)


@_documented("``m <= (n - 1) / 3``")
def ohdev(y: npt.ArrayLike, *, fs_hz: float, m: npt.ArrayLike,
          workers: int | None = None) -> EstimatorOutput:
    r"""Overlapping Hadamard deviation of rate data.

    .. math:: H\sigma_y^2(m\tau_0) = \frac{1}{6 m^2 \tau_0^2 (N-3m)} \sum_{i=1}^{N-3m}
              (x_{i+3m} - 3x_{i+2m} + 3x_{i+m} - x_i)^2

    NIST SP1065 eq. 20.

    Examples
    --------
    >>> out = ohdev(np.random.default_rng(0).normal(size=1000), fs_hz=1.0, m=[1, 10])
    >>> out.n.tolist()
    [998, 971]
    """
    return _run("ohdev", y, fs_hz, m, workers)


@_documented("``m <= n / 2``, tau up to half the record")
def totdev(y: npt.ArrayLike, *, fs_hz: float, m: npt.ArrayLike,
           workers: int | None = None) -> EstimatorOutput:
    r"""Total deviation of rate data.

    .. math:: \mathrm{Tot}\,\sigma_y^2(m\tau_0) = \frac{1}{2 (m\tau_0)^2 (N-2)}
              \sum_{i=2}^{N-1} (x^*_{i-m} - 2x_i + x^*_{i+m})^2

    NIST SP1065 eq. 25, where ``x*`` extends the phase by reflection at both ends,
    ``x*_{1-j} = 2x_1 - x_{1+j}`` and ``x*_{N+j} = 2x_N - x_{N-j}``.  No bias correction
    is applied (as Stable32's TOTDEV for Allan-type output and allantools; see
    :func:`fogts.allan.bias.totdev_bias`).

    Examples
    --------
    >>> out = totdev(np.random.default_rng(0).normal(size=1000), fs_hz=1.0, m=[1, 500])
    >>> out.tau_s.tolist(), out.n.tolist()     # tau up to half the record, N - 2 terms
    ([1.0, 500.0], [999, 999])
    """
    return _run("totdev", y, fs_hz, m, workers)


#: Estimator functions by name.
ESTIMATORS: dict[str, Callable[..., EstimatorOutput]] = {
    "adev": adev, "oadev": oadev, "mdev": mdev, "hdev": hdev, "ohdev": ohdev,
    "totdev": totdev,
}
