"""Tau grids for the Allan family: octave, decade, dense (k per decade), all, or explicit.

A grid is a set of integer averaging factors ``m`` (``tau = m / fs``).  Each estimator can
only be evaluated where it has at least two terms, so the largest usable ``m`` depends on
the estimator and the record length (see :func:`n_terms`).  Named grids stop at that
largest ``m``; explicit taus outside the usable range are kept in :attr:`TauGrid.dropped`
with the reason, never discarded silently.

Term counts follow NIST SP1065 (Riley 2008): with ``N = n + 1`` phase points made from
``n`` rate samples,

========  ============================  ==================
kind      terms                         SP1065 equation
========  ============================  ==================
adev      ``floor((N - 1) / m) - 1``    eq. 7 (decimated)
oadev     ``N - 2m``                    eq. 11
mdev      ``N - 3m + 1``                eq. 14
hdev      ``floor((N - 1) / m) - 2``    eq. 18 (decimated)
ohdev     ``N - 3m``                    eq. 20
totdev    ``N - 2`` (``m <= n / 2``)    eq. 25
========  ============================  ==================

These are also Stable32's ``#`` column and allantools' ``ns``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any, Literal, get_args

import numpy as np
import numpy.typing as npt

from fogts._typing import FloatArray, IntArray
from fogts._validate import check_choice, check_int, check_positive
from fogts.choices import KINDS, Kind
from fogts.errors import DataError, InsufficientDataError

#: The named tau grids of :func:`tau_grid`.
GridName = Literal["octave", "decade", "dense", "all"]
GRID_NAMES: tuple[str, ...] = get_args(GridName)

__all__ = ["GRID_NAMES", "KINDS", "DroppedTau", "GridName", "Kind", "TauGrid", "max_m", "n_terms",
           "tau_grid"]

#: Fewest terms an estimate needs (allantools drops ``ns <= 1``; so does fogts).
MIN_TERMS = 2


@dataclass(frozen=True)
class DroppedTau:
    """A requested tau that could not be computed, and why.

    Kept in a result's ``dropped`` field, so that no requested tau disappears silently.

    Attributes
    ----------
    tau_s : float
        The tau as requested (seconds).
    m : int
        The averaging factor it rounds to, ``round(tau_s * fs_hz)``.
    reason : str
        Human-readable reason (too few terms, below one sample, duplicate, ...).
    """

    tau_s: float
    m: int
    reason: str

    def to_dict(self) -> dict[str, Any]:
        return {"tau": self.tau_s, "m": self.m, "reason": self.reason}


@dataclass(frozen=True)
class TauGrid:
    """Averaging factors to evaluate one estimator at.

    Attributes
    ----------
    m : ndarray of int64
        Unique, sorted averaging factors (>= 1), every one computable for ``kind``.
    tau_s : ndarray of float64
        ``m / fs_hz``: the taus actually used.
    dropped : tuple of DroppedTau
        Requested taus that cannot be computed.
    spec : str
        ``"octave"``, ``"decade"``, ``"dense"``, ``"all"`` or ``"explicit"``.
    kind : str
        The estimator the grid was checked against.
    fs_hz : float
    n_samples : int
        Number of rate samples the grid was built for.
    notes : tuple of str
        Other changes made to the request (rounding of explicit taus to whole samples).
    """

    m: IntArray
    tau_s: FloatArray
    dropped: tuple[DroppedTau, ...]
    spec: str
    kind: str
    fs_hz: float
    n_samples: int
    notes: tuple[str, ...] = ()

    def __len__(self) -> int:
        return int(self.m.size)

    def to_dict(self) -> dict[str, Any]:
        return {"spec": self.spec, "kind": self.kind, "fs_hz": self.fs_hz,
                "n_samples": self.n_samples, "m": self.m.tolist(), "tau": self.tau_s.tolist(),
                "dropped": [d.to_dict() for d in self.dropped], "notes": list(self.notes)}


def n_terms(kind: str, m: npt.ArrayLike, n_samples: int) -> IntArray:
    """Number of terms (squared differences) the estimator sums at each averaging factor.

    Parameters
    ----------
    kind : {"adev", "oadev", "mdev", "hdev", "ohdev", "totdev"}
    m : array_like of int
        Averaging factors (>= 1).
    n_samples : int
        Number of rate samples ``n``; the phase has ``N = n + 1`` points.

    Returns
    -------
    ndarray of int64
        The term count (Stable32's ``#``), clipped at 0.  For ``totdev`` the count is
        ``N - 2`` where ``m <= n / 2`` and 0 beyond (SP1065 defines TOTDEV up to half the
        record length).

    Examples
    --------
    >>> n_terms("oadev", [1, 10, 100], 1000).tolist()
    [999, 981, 801]
    >>> n_terms("adev", [1, 2, 3], 1000).tolist()
    [999, 499, 332]
    """
    kind = check_choice("kind", kind, KINDS)
    mm = np.asarray(m, dtype=np.int64)
    n_phase = int(n_samples) + 1
    if kind == "adev":
        out = (n_phase - 1) // mm - 1
    elif kind == "oadev":
        out = n_phase - 2 * mm
    elif kind == "mdev":
        out = n_phase - 3 * mm + 1
    elif kind == "hdev":
        out = (n_phase - 1) // mm - 2
    elif kind == "ohdev":
        out = n_phase - 3 * mm
    else:  # totdev
        out = np.where(mm <= n_samples // 2, n_phase - 2, 0)
    return np.maximum(np.asarray(out, dtype=np.int64), 0)


def max_m(kind: str, n_samples: int) -> int:
    """Largest averaging factor with at least two terms (0 if none).

    Examples
    --------
    >>> max_m("oadev", 1000), max_m("adev", 1000), max_m("totdev", 1000)
    (499, 333, 500)
    """
    kind = check_choice("kind", kind, KINDS)
    n = int(n_samples)
    limits = {
        "adev": n // (MIN_TERMS + 1),           # n // m - 1 >= 2
        "oadev": (n + 1 - MIN_TERMS) // 2,      # n + 1 - 2m >= 2
        "mdev": (n + 2 - MIN_TERMS) // 3,       # n + 2 - 3m >= 2
        "hdev": n // (MIN_TERMS + 2),           # n // m - 2 >= 2
        "ohdev": (n + 1 - MIN_TERMS) // 3,      # n + 1 - 3m >= 2
        "totdev": n // 2 if n - 1 >= MIN_TERMS else 0,
    }
    return max(int(limits[kind]), 0)


def _named_m(spec: str, top: int, per_decade: int) -> IntArray:
    """Averaging factors of a named grid, from 1 up to ``top``."""
    if spec == "all":
        return np.arange(1, top + 1, dtype=np.int64)
    if spec == "octave":
        return (2 ** np.arange(int(math.log2(top)) + 1)).astype(np.int64)
    if spec == "decade":
        # Stable32's decade spacing 1, 2, 4, 10, 20, 40, ... (as allantools).
        decades = 10 ** np.arange(int(math.log10(top)) + 1, dtype=np.int64)
        m = (decades[:, None] * np.array([1, 2, 4], dtype=np.int64)).ravel()
        return m[m <= top]
    # dense: per_decade log-spaced points per decade, rounded to whole samples.
    k = np.arange(math.floor(per_decade * math.log10(top) + 1e-9) + 1)
    m = np.unique(np.rint(10.0 ** (k / per_decade)).astype(np.int64))
    return m[m <= top]


def tau_grid(
    spec: str | npt.ArrayLike,
    *,
    fs_hz: float,
    n_samples: int,
    kind: str = "oadev",
    per_decade: int = 20,
) -> TauGrid:
    """Build the averaging factors at which to evaluate one Allan-family estimator.

    Parameters
    ----------
    spec : {"octave", "decade", "dense", "all"} or array_like of float
        ``"octave"``: m = 1, 2, 4, 8, ...; ``"decade"``: m = 1, 2, 4, 10, 20, 40, ...
        (Stable32's spacing); ``"dense"``: ``per_decade`` log-spaced m per decade;
        ``"all"``: every m.  Named grids run from m = 1 to the largest m with at least two
        terms for ``kind`` (:func:`max_m`).  An array gives taus in seconds; each is
        rounded to the nearest whole number of samples ``m = round(tau * fs_hz)``.
    fs_hz : float
        Sample rate of the rate data.
    n_samples : int
        Number of rate samples.
    kind : {"adev", "oadev", "mdev", "hdev", "ohdev", "totdev"}
        The estimator, which sets the usable range of m.
    per_decade : int
        Points per decade of the ``"dense"`` grid.

    Returns
    -------
    TauGrid
        Explicit taus that cannot be computed (m = 0, fewer than two terms, duplicates
        after rounding) are listed in ``dropped`` with the reason.

    Raises
    ------
    DataError
        Unknown grid name, non-positive or non-finite taus, bad ``fs_hz``/``per_decade``.
    InsufficientDataError
        No tau at all can be computed.

    Examples
    --------
    >>> g = tau_grid("octave", fs_hz=1.0, n_samples=1000, kind="oadev")
    >>> g.m.tolist()
    [1, 2, 4, 8, 16, 32, 64, 128, 256]
    >>> g = tau_grid([0.1, 1.0, 1.04, 900.0], fs_hz=1.0, n_samples=1000)
    >>> g.m.tolist(), [d.m for d in g.dropped]
    ([1], [0, 1, 900])
    """
    kind = check_choice("kind", kind, KINDS)
    fs = check_positive("fs_hz", fs_hz)
    n = check_int("n_samples", n_samples, minimum=1)
    per_decade = check_int("per_decade", per_decade, minimum=1)
    top = max_m(kind, n)

    if isinstance(spec, str):
        spec = check_choice("taus", spec, GRID_NAMES)
        if top < 1:
            raise InsufficientDataError(
                f"{kind} needs more samples: {n} rate sample(s) give no averaging factor "
                f"with at least {MIN_TERMS} terms")
        m = _named_m(spec, top, per_decade)
        return TauGrid(m=m, tau_s=m / fs, dropped=(), spec=spec, kind=kind, fs_hz=fs,
                       n_samples=n)

    return _explicit_grid(spec, fs=fs, n=n, kind=kind, top=top)


def _explicit_grid(spec: Any, *, fs: float, n: int, kind: str, top: int) -> TauGrid:
    try:
        taus = np.asarray(spec, dtype=np.float64)
    except (TypeError, ValueError):
        raise DataError(f"taus must be one of {', '.join(GRID_NAMES)} or an array of taus "
                        f"in seconds, got {spec!r}") from None
    if taus.ndim == 0:
        taus = taus.reshape(1)
    if taus.ndim != 1 or taus.size == 0:
        raise DataError(f"taus must be a non-empty 1-D array of taus in seconds, got shape "
                        f"{taus.shape}")
    bad = ~np.isfinite(taus) | (taus <= 0)
    if bad.any():
        raise DataError(f"taus must be finite and > 0 seconds, got {float(taus[bad][0])!r} at "
                        f"position {int(np.argmax(bad))}")
    order = np.argsort(taus, kind="stable")
    raw = taus * fs
    m_all = np.rint(raw).astype(np.int64)
    dropped: list[DroppedTau] = []
    kept: dict[int, float] = {}
    terms = n_terms(kind, np.maximum(m_all, 1), n)
    for i in order:
        tau, mi = float(taus[i]), int(m_all[i])
        if mi < 1:
            dropped.append(DroppedTau(tau, mi, f"tau is below half a sample period "
                                               f"(tau * fs = {raw[i]:.3g} rounds to m = 0)"))
        elif mi > top:
            if kind == "totdev" and terms[i] == 0:
                why = (f"totdev is defined for tau <= T/2 (m <= {n // 2} with {n} "
                       "samples)")
            else:
                why = (f"{kind} has only {int(terms[i])} term(s) at m = {mi} with {n} "
                       f"samples; at least {MIN_TERMS} are needed (largest m is {top})")
            dropped.append(DroppedTau(tau, mi, why))
        elif mi in kept:
            dropped.append(DroppedTau(tau, mi, f"duplicate: rounds to the same m = {mi} as "
                                               f"tau = {kept[mi]:.6g} s"))
        else:
            kept[mi] = tau
    notes: list[str] = []
    moved = np.abs(raw - m_all) > 1e-9 * np.maximum(np.abs(raw), 1.0)
    moved &= m_all >= 1
    if moved.any():
        shift = float(np.max(np.abs(raw[moved] - m_all[moved]))) / fs
        notes.append(f"{int(moved.sum())} explicit tau(s) rounded to the nearest whole "
                     f"number of samples (largest change {shift:.3g} s)")
    if not kept:
        reasons = "; ".join(f"tau={d.tau_s:g}: {d.reason}" for d in dropped[:3])
        raise InsufficientDataError(f"none of the requested taus can be computed for {kind} "
                                    f"with {n} samples at {fs:g} Hz ({reasons})")
    m = np.array(sorted(kept), dtype=np.int64)
    return TauGrid(m=m, tau_s=m / fs, dropped=tuple(dropped), spec="explicit", kind=kind,
                   fs_hz=fs, n_samples=n, notes=tuple(notes))
