"""Empirical mode decomposition (EMD) and trend separation by the IMF mean-energy rule.

The start-up workflow (:mod:`~fogts.startup.startup_workflow`, step 1) splits the gyro
output into intrinsic mode functions (IMFs) and separates the slow, temperature-driven trend
from the fast noise with the *mean-energy* criterion:

    E_i = (1/T) * sum_t imf_i(t)^2

The energies of the noise IMFs fall with the IMF number (each IMF holds about half the
bandwidth of the previous one); the first IMF whose energy *rises again* after falling marks
the start of the trend.  With that IMF numbered k (1-based):

    trend = sum_{i >= k} IMF_i + residue,        rest = sum_{i < k} IMF_i.

The EMD itself is fogts' own sifting (Huang et al., 1998, Proc. R. Soc. Lond. A 454:903):

* extrema are found with vectorised sign changes of the first difference (plateaus resolved
  to their last sample);
* envelopes are ``scipy.interpolate.CubicSpline`` through the maxima and the minima, with
  the end conditions of Rilling, Flandrin & Gonçalves (2003): the first and last extrema are
  mirrored about the end samples, and an end sample that lies outside the nearest extremum
  becomes an envelope point itself, so that the envelopes enclose the signal to its ends;
* sifting stops with Rilling's criterion (G. Rilling, P. Flandrin, P. Gonçalves, "On empirical
  mode decomposition and its algorithms", IEEE-EURASIP NSIP 2003): with the mode amplitude
  a(t) = (e_max - e_min)/2 and the evaluation function sigma(t) = |m(t)| / a(t) of the mean
  envelope m(t), stop when sigma < theta_1 on at least a fraction 1 - alpha of the samples
  and sigma < theta_2 everywhere (theta_1 = 0.05, theta_2 = 0.5, alpha = 0.05), or after
  ``max_sift`` iterations (recorded per IMF);
* decomposition stops when the residue has fewer than two maxima or two minima (it is then
  monotonic or has a single extremum) or after ``max_imfs`` IMFs.

The residue is computed as the signal minus the sum of the IMFs, so the IMFs and residue add
back to the signal to rounding error.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any, Literal, get_args

import numpy as np
import pandas as pd
from scipy.interpolate import CubicSpline

from fogts._typing import ArrayLike1D, BoolArray, FloatArray, IntArray
from fogts._validate import check_choice, check_int, check_positive, pandas_index, to_float_array
from fogts.errors import InsufficientDataError

__all__ = ["EMD_CRITERIA", "EmdResult", "TrendSplit", "emd", "separate_trend"]

EmdCriterion = Literal["energy"]
EMD_CRITERIA: tuple[str, ...] = get_args(EmdCriterion)

#: Rilling et al. (2003) default thresholds.
RILLING_THETA1 = 0.05
RILLING_THETA2 = 0.5
RILLING_ALPHA = 0.05
#: Number of extrema mirrored at each end (Rilling's ``NBSYM``).
N_MIRROR = 2
#: Fewest samples EMD accepts.
MIN_EMD_SAMPLES = 16


@dataclass(frozen=True)
class EmdResult:
    """An empirical mode decomposition ``x = sum_i imfs[i] + residue``.

    What :func:`emd` returns; :func:`separate_trend` groups its IMFs into a trend and a rest.

    Attributes
    ----------
    imfs : ndarray of float64, shape (n_imfs, n)
        The IMFs, fastest first.
    residue : ndarray of float64, shape (n,)
        What is left after the last IMF: ``x - imfs.sum(axis=0)``.
    n_sift : ndarray of int64
        Sifting iterations used for each IMF.
    sift_converged : ndarray of bool
        False where sifting stopped at ``max_sift`` before Rilling's criterion was met.
    n_extrema : ndarray of int64
        Number of local extrema of each IMF.
    stop_reason : str
        Why the decomposition ended.
    """

    imfs: FloatArray
    residue: FloatArray
    n_sift: IntArray
    sift_converged: BoolArray = field(repr=False)
    n_extrema: IntArray
    stop_reason: str

    @property
    def n_imfs(self) -> int:
        return int(self.imfs.shape[0])



@dataclass(frozen=True)
class TrendSplit:
    """EMD trend separation of one series.

    Attributes
    ----------
    imfs : ndarray of float64, shape (n_imfs, n)
        The IMFs, fastest first (IMF 1 is ``imfs[0]``).
    residue : ndarray of float64
        EMD residue.
    imf_energy : ndarray of float64
        Mean energy ``E_i = (1/T) sum imf_i^2`` of each IMF (T = number of samples), in
        (input unit)^2.
    k : int
        1-based number of the first trend IMF: ``trend = sum(imfs[k-1:]) + residue``.
        ``k = n_imfs + 1`` means no IMF belongs to the trend (the trend is the residue).
        A series with fewer than two maxima or minima has no IMF: it is all trend
        (``n_imfs = 0``, ``k = 1``, rest = 0).
    trend, rest : ndarray or pandas.Series
        ``trend + rest == x``; Series with the input's index when the input was a Series.
    fs_hz : float
        Sample rate.
    criterion : str
        How k was chosen (``"energy"`` or ``"given"``).
    imf_mean_period_s : ndarray of float64
        Mean period of each IMF, ``2 n / (n_extrema fs)`` (inf for an IMF without extrema).
    n_sift : ndarray of int64
        Sifting iterations per IMF.
    sift_converged : ndarray of bool
        Whether Rilling's criterion was met for each IMF.
    stop_reason : str
        Why the decomposition ended.
    """

    imfs: FloatArray = field(repr=False)
    residue: FloatArray = field(repr=False)
    imf_energy: FloatArray
    k: int
    trend: Any = field(repr=False)
    rest: Any = field(repr=False)
    fs_hz: float
    criterion: str
    imf_mean_period_s: FloatArray
    n_sift: IntArray
    sift_converged: BoolArray
    stop_reason: str

    @property
    def n_imfs(self) -> int:
        return int(self.imfs.shape[0])

    @property
    def n(self) -> int:
        return int(self.imfs.shape[1])

    def to_frame(self) -> pd.DataFrame:
        """Columns ``time, signal, trend, rest, imf_1 .. imf_K, residue``."""
        trend = np.asarray(self.trend, dtype=float)
        rest = np.asarray(self.rest, dtype=float)
        data: dict[str, Any] = {"time": np.arange(self.n) / self.fs_hz,
                                "signal": trend + rest, "trend": trend, "rest": rest}
        for i in range(self.n_imfs):
            data[f"imf_{i + 1}"] = self.imfs[i]
        data["residue"] = self.residue
        index = self.trend.index if isinstance(self.trend, pd.Series) else None
        return pd.DataFrame(data, index=index)

    def to_dict(self) -> dict[str, Any]:
        """JSON-safe summary (the series themselves are in :meth:`to_frame`)."""
        return {
            "k": int(self.k),
            "n_imfs": self.n_imfs,
            "criterion": self.criterion,
            "imf_energy": [float(v) for v in self.imf_energy],
            "imf_mean_period_s": [float(v) for v in self.imf_mean_period_s],
            "n_sift": [int(v) for v in self.n_sift],
            "sift_converged": [bool(v) for v in self.sift_converged],
            "trend_imfs": list(range(self.k, self.n_imfs + 1)),
            "stop_reason": self.stop_reason,
            "fs_hz": float(self.fs_hz),
            "n": self.n,
        }

    def summary(self) -> str:
        lines = [f"EMD trend separation: {self.n_imfs} IMFs, n = {self.n}, fs = {self.fs_hz:g} Hz"]
        lines.append("  IMF   mean energy    mean period [s]  sifts  role")
        for i in range(self.n_imfs):
            role = "trend" if i + 1 >= self.k else "rest"
            lines.append(f"  {i + 1:>3d}  {self.imf_energy[i]:12.6g}  {self.imf_mean_period_s[i]:15.6g}"
                         f"  {int(self.n_sift[i]):5d}  {role}")
        if self.k <= self.n_imfs:
            lines.append(f"  k = {self.k} ({self.criterion}): trend = IMF {self.k}..{self.n_imfs}"
                         " + residue")
        else:
            lines.append(f"  k = {self.k} ({self.criterion}): trend = residue only")
        return "\n".join(lines)


# --------------------------------------------------------------------------- kernels


def _extrema(x: FloatArray) -> tuple[IntArray, IntArray]:
    """Indices of the local maxima and minima (vectorised; a plateau counts once, at its end)."""
    d = np.diff(x)
    s = np.sign(d)
    if s.size == 0:
        return np.empty(0, np.int64), np.empty(0, np.int64)
    # forward-fill zero slopes with the previous non-zero sign (plateaus)
    nz = s != 0
    if not nz.any():
        return np.empty(0, np.int64), np.empty(0, np.int64)
    idx = np.where(nz, np.arange(s.size), 0)
    np.maximum.accumulate(idx, out=idx)
    s = s[idx]
    s[: int(np.argmax(nz))] = 0.0  # leading plateau: no sign yet
    change = s[1:] * s[:-1] < 0
    pos = np.flatnonzero(change) + 1  # x[pos] is the extremum
    maxima = pos[s[pos - 1] > 0]
    minima = pos[s[pos - 1] < 0]
    return maxima.astype(np.int64), minima.astype(np.int64)


def _mirror(t_ext: IntArray, v_ext: FloatArray, x: FloatArray, *, upper: bool
            ) -> tuple[FloatArray, FloatArray]:
    """Envelope knots with Rilling-style end conditions (mirror about the end samples)."""
    n = x.size
    last = n - 1
    t = t_ext.astype(np.float64)
    v = v_ext
    left_t = -t[:N_MIRROR][::-1]
    left_v = v[:N_MIRROR][::-1]
    right_t = 2.0 * last - t[-N_MIRROR:][::-1]
    right_v = v[-N_MIRROR:][::-1]
    parts_t = [left_t]
    parts_v = [left_v]
    beyond_left = x[0] > v[0] if upper else x[0] < v[0]
    if beyond_left and t[0] > 0:
        parts_t.append(np.array([0.0]))
        parts_v.append(np.array([x[0]]))
    parts_t.append(t)
    parts_v.append(v)
    beyond_right = x[-1] > v[-1] if upper else x[-1] < v[-1]
    if beyond_right and t[-1] < last:
        parts_t.append(np.array([float(last)]))
        parts_v.append(np.array([x[-1]]))
    parts_t.append(right_t)
    parts_v.append(right_v)
    tt = np.concatenate(parts_t)
    vv = np.concatenate(parts_v)
    # mirrored knots can coincide with t = 0 / t = last when an extremum sits at the end
    keep = np.concatenate([[True], np.diff(tt) > 0])
    return tt[keep], vv[keep]


def _envelopes(h: FloatArray, grid: FloatArray) -> tuple[FloatArray, FloatArray, int] | None:
    maxima, minima = _extrema(h)
    if maxima.size < 2 or minima.size < 2:
        return None
    tu, vu = _mirror(maxima, h[maxima], h, upper=True)
    tl, vl = _mirror(minima, h[minima], h, upper=False)
    upper = CubicSpline(tu, vu, bc_type="not-a-knot")(grid)
    lower = CubicSpline(tl, vl, bc_type="not-a-knot")(grid)
    return upper, lower, int(maxima.size + minima.size)


def _sift(r: FloatArray, grid: FloatArray, max_sift: int) -> tuple[FloatArray, int, bool] | None:
    """Sift one IMF out of ``r``; None when ``r`` has too few extrema to hold one."""
    h = r.copy()
    for it in range(1, max_sift + 1):
        env = _envelopes(h, grid)
        if env is None:
            return (h, it - 1, True) if it > 1 else None
        upper, lower, _ = env
        mean = 0.5 * (upper + lower)
        amp = 0.5 * np.abs(upper - lower)
        with np.errstate(divide="ignore", invalid="ignore"):
            sigma = np.where(amp > 0, np.abs(mean) / np.where(amp > 0, amp, 1.0), np.inf)
        if np.mean(sigma > RILLING_THETA1) < RILLING_ALPHA and np.all(sigma < RILLING_THETA2):
            return h, it - 1, True
        h = h - mean
    return h, max_sift, False


def emd(x: ArrayLike1D, *, max_imfs: int | None = None, max_sift: int = 50) -> EmdResult:
    """Empirical mode decomposition of a 1-D series (see the module docstring).

    Parameters
    ----------
    x : array_like or pandas.Series
        The series, at least 16 finite samples.
    max_imfs : int, optional
        Most IMFs to extract (default ``floor(log2(n))``).
    max_sift : int
        Most sifting iterations per IMF (Rilling's criterion usually stops far earlier).

    Returns
    -------
    EmdResult

    Examples
    --------
    >>> import numpy as np
    >>> t = np.arange(2000) / 100.0
    >>> x = np.sin(2 * np.pi * 5 * t) + np.sin(2 * np.pi * 0.3 * t)
    >>> r = emd(x)
    >>> bool(np.allclose(r.imfs.sum(axis=0) + r.residue, x))
    True
    """
    arr = to_float_array(x, "x", min_length=MIN_EMD_SAMPLES)
    n = arr.size
    limit = int(np.log2(n)) if max_imfs is None else check_int("max_imfs", max_imfs, minimum=1)
    max_sift = check_int("max_sift", max_sift, minimum=1)
    if float(np.ptp(arr)) == 0.0:
        raise InsufficientDataError(f"x is constant (every sample equals {arr[0]!r}); "
                                    "EMD needs variation")
    grid = np.arange(n, dtype=np.float64)
    imfs: list[FloatArray] = []
    sifts: list[int] = []
    conv: list[bool] = []
    r = arr.copy()
    stop = f"reached max_imfs = {limit}"
    while len(imfs) < limit:
        out = _sift(r, grid, max_sift)
        if out is None:
            stop = "residue has fewer than two maxima or two minima"
            break
        h, it, ok = out
        imfs.append(h)
        sifts.append(it)
        conv.append(ok)
        r = r - h
    stack = np.array(imfs) if imfs else np.empty((0, n))
    residue = arr - stack.sum(axis=0) if imfs else arr.copy()
    n_ext = np.array([sum(e.size for e in _extrema(h)) for h in stack], dtype=np.int64)
    return EmdResult(imfs=stack, residue=residue, n_sift=np.array(sifts, dtype=np.int64),
                     sift_converged=np.array(conv, dtype=bool), n_extrema=n_ext, stop_reason=stop)


def energy_k(energy: FloatArray) -> int:
    """1-based number of the first IMF whose mean energy rises after having fallen.

    Returns ``len(energy) + 1`` when the energies never rise again after falling (the trend is
    then the residue alone).

    Examples
    --------
    >>> energy_k(np.array([8.0, 4.0, 2.0, 1.0, 3.0, 9.0]))
    5
    """
    e = np.asarray(energy, dtype=float)
    fell = False
    for i in range(1, e.size):
        if e[i] < e[i - 1]:
            fell = True
        elif fell and e[i] > e[i - 1]:
            return i + 1
    return int(e.size) + 1


def separate_trend(x: ArrayLike1D, *, fs_hz: float, criterion: EmdCriterion = "energy",
                   k: int | None = None, max_imfs: int | None = None,
                   max_sift: int = 50) -> TrendSplit:
    """Split a series into a slow trend and a fast rest with EMD.

    Parameters
    ----------
    x : array_like or pandas.Series
        Gyro rate (or temperature) samples.
    fs_hz : float
        Sample rate in Hz (used for the IMF mean periods).
    criterion : {"energy"}
        ``"energy"``: k is the first IMF whose mean energy ``E_i = (1/T) sum imf_i^2``
        starts to rise after falling.
    k : int, optional
        Force the first trend IMF (1-based) instead of applying the criterion.
    max_imfs, max_sift : int
        Passed to :func:`emd`.

    Returns
    -------
    TrendSplit
        ``trend + rest == x``; both keep a Series' index.

    Raises
    ------
    DataError
        Bad ``criterion``, ``fs_hz`` or ``k``.
    InsufficientDataError
        Fewer than 16 samples, or a constant series.

    Examples
    --------
    >>> import numpy as np
    >>> rng = np.random.default_rng(4)
    >>> t = np.arange(4000) / 10.0
    >>> x = 2.0 * (1 - np.exp(-t / 80.0)) + 0.1 * rng.standard_normal(t.size)
    >>> s = separate_trend(x, fs_hz=10.0)
    >>> bool(np.sqrt(np.mean((s.trend - 2.0 * (1 - np.exp(-t / 80.0))) ** 2)) < 0.05)
    True
    """
    fs = check_positive("fs_hz", fs_hz)
    check_choice("criterion", criterion, EMD_CRITERIA)
    index = pandas_index(x)
    arr = to_float_array(x, "x", min_length=MIN_EMD_SAMPLES)
    dec = emd(arr, max_imfs=max_imfs, max_sift=max_sift)
    energy = np.mean(dec.imfs ** 2, axis=1) if dec.n_imfs else np.empty(0)
    if k is None:
        kk = energy_k(energy)
        how: str = criterion
    else:
        kk = check_int("k", k, minimum=1, maximum=dec.n_imfs + 1)
        how = "given"
    trend = dec.imfs[kk - 1:].sum(axis=0) + dec.residue
    rest = dec.imfs[: kk - 1].sum(axis=0) if kk > 1 else np.zeros_like(arr)
    with np.errstate(divide="ignore"):
        period = np.where(dec.n_extrema > 0, 2.0 * arr.size / (np.maximum(dec.n_extrema, 1) * fs),
                          np.inf)
    trend_out: Any = trend
    rest_out: Any = rest
    if index is not None:
        name = getattr(x, "name", None)
        trend_out = pd.Series(trend, index=index, name=f"{name}_trend" if name else "trend")
        rest_out = pd.Series(rest, index=index, name=f"{name}_rest" if name else "rest")
    return TrendSplit(imfs=dec.imfs, residue=dec.residue, imf_energy=energy, k=int(kk),
                      trend=trend_out, rest=rest_out, fs_hz=fs, criterion=how,
                      imf_mean_period_s=period, n_sift=dec.n_sift,
                      sift_converged=dec.sift_converged, stop_reason=dec.stop_reason)
