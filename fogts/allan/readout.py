"""Read an Allan-deviation curve by eye, as a program: regions A-D, minimum, slopes, read-offs.

The log-log curve of an optical gyro is read in four regions (IEEE Std 952-1997 Annex C):

* A: the single-sample noise at the shortest tau;
* B: the falling part that averaging removes (ARW has slope -1/2, quantization -1);
* C: the minimum, giving the optimal averaging time and the noise floor (the
  bias-instability point: B = sigma_min / :data:`~fogts.allan.terms.B_PLATEAU` for flicker
  noise);
* D: the rise from slow drift (rate random walk +1/2, rate ramp +1).

:func:`read_curve` returns the minimum with its confidence interval, the log-log slope of
every segment, the regions B-D found from the curve itself, and, when the fitted term
lines are given, the tau range where each term dominates.  :func:`slope_readoff` gives the
classic graphical N, K and B (IEEE 952 Annex C; MATLAB's ``allanvar`` example), which the
noise fit reports beside its answer for comparison.
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Callable, Collection
from dataclasses import dataclass
from typing import Any

import numpy as np
import pandas as pd

from fogts._typing import FloatArray
from fogts.allan.terms import B_PLATEAU, TERM_SLOPE, TERMS, from_seconds, term_rows
from fogts.errors import DataError, InsufficientDataError
from fogts.tables import Column, Table, fields_dict
from fogts.units import convert_sensor, term_in_units, term_unit

__all__ = ["CurveReadout", "DominantRange", "SlopeReadoff", "read_curve", "slope_readoff"]


@dataclass(frozen=True)
class DominantRange:
    """A contiguous tau range where one fitted term is the largest contribution;
    ``measured`` is False for a term the fit reports as an upper limit (its line is the
    fitted value, which the data do not distinguish from zero)."""

    term: str
    tau_from_s: float
    tau_to_s: float
    slope: float
    measured: bool = True

    def to_dict(self) -> dict[str, Any]:
        return fields_dict(self, tau_from_s="tau_from", tau_to_s="tau_to")


@dataclass(frozen=True)
class CurveReadout:
    """Read-outs of one Allan-deviation curve.

    Attributes
    ----------
    tau_min_s, dev_min : float
        The lowest point of the curve (optimal averaging time and noise floor).
    dev_min_ci : tuple of float
        Its confidence interval ``(low, high)`` at level ``confidence``.
    confidence : float
    bias_instability_floor : float
        ``dev_min / B_PLATEAU`` (0.664): the flicker-floor estimate of B (IEEE 952 Annex C), in the
        curve's rate unit.
    segment_tau_s : ndarray, shape (k, 2)
        Start and end tau of each segment between consecutive points.
    segment_slope : ndarray, shape (k,)
        d log sigma / d log tau of each segment.
    regions : dict
        ``{"A": (tau, tau), "B": (from, to), "C": (from, to), "D": (from, to) or None}``:
        A is the first point; B the falling part down to region C; C the points whose
        deviation lies inside the minimum's confidence interval (the flat floor); D the
        rise after C.
    dominant : tuple of DominantRange
        Where each fitted term dominates (empty without term curves).
    """

    tau_min_s: float
    dev_min: float
    dev_min_ci: tuple[float, float]
    confidence: float
    bias_instability_floor: float
    segment_tau_s: FloatArray
    segment_slope: FloatArray
    regions: dict[str, tuple[float, float] | None]
    dominant: tuple[DominantRange, ...] = ()

    def to_frame(self) -> pd.DataFrame:
        """One row per segment: tau_from, tau_to, slope."""
        return pd.DataFrame({"tau_from": self.segment_tau_s[:, 0],
                             "tau_to": self.segment_tau_s[:, 1], "slope": self.segment_slope})

    def to_dict(self) -> dict[str, Any]:
        return {
            "minimum": {"tau": self.tau_min_s, "dev": self.dev_min,
                        "ci_low": self.dev_min_ci[0], "ci_high": self.dev_min_ci[1],
                        "confidence": self.confidence,
                        "bias_instability_floor": self.bias_instability_floor},
            "regions": {k: (list(v) if v is not None else None) for k, v in self.regions.items()},
            "dominant": [d.to_dict() for d in self.dominant],
            "segments": [{"tau_from": float(a), "tau_to": float(b), "slope": float(s)}
                         for (a, b), s in zip(self.segment_tau_s, self.segment_slope,
                                              strict=True)],
        }

    def table(self, units: str = "", axis: str = "") -> Table:
        """The read-outs: minimum (with its interval), regions B-D, dominant terms; ``units``
        and ``axis`` name the curve's unit and axis in the cells and the title."""
        lo, hi = self.dev_min_ci
        unit = f" {units}" if units else ""
        rows: list[tuple[str, str, str]] = [
            ("minimum", f"{self.tau_min_s:.4g} s",
             f"{self.dev_min:.4g} [{lo:.4g}, {hi:.4g}]{unit}; "
             f"floor/{B_PLATEAU:g} = {self.bias_instability_floor:.4g}{unit}")]
        # "region B" (IEEE 952 Annex C's letters), not "(B)": beside "B dominates" a bare B
        # reads as the bias-instability term
        for name, label in (("B", "falling (region B)"), ("C", "floor (region C)"),
                            ("D", "rising (region D)")):
            span = self.regions.get(name)
            if span is not None:
                rows.append((label, f"{span[0]:.4g} .. {span[1]:.4g} s", ""))
        for d in self.dominant:
            taus = f"{d.tau_from_s:.4g} .. {d.tau_to_s:.4g} s"
            if d.measured:
                rows.append((f"{d.term} dominates", taus, f"slope {d.slope:+g}"))
            else:
                rows.append((f"{d.term} line largest", taus, f"slope {d.slope:+g}; {d.term} is "
                             "not measured (an upper limit): its fitted line, not a finding"))
        return Table.build(f"curve of {axis}" if axis else "curve read-outs",
                           (Column("read-out", numeric=False), Column("tau", numeric=False),
                            Column("value", numeric=False)), rows,
                           caption=f"minimum with its {100 * self.confidence:.1f} % interval")

    def summary(self) -> str:
        return self.table().to_text()

    def in_unit(self, unit: str, to_unit: str) -> CurveReadout:
        """The read-outs with the deviations (minimum, its interval, the floor estimate)
        converted from the curve's ``unit`` to ``to_unit`` (:func:`fogts.units.convert_sensor`),
        e.g. for a points table shown in SI units; taus, slopes and regions stay."""
        if to_unit == unit:
            return self
        scale = float(convert_sensor(1.0, unit, to_unit))
        lo, hi = self.dev_min_ci
        return dataclasses.replace(self, dev_min=self.dev_min * scale,
                                   dev_min_ci=(lo * scale, hi * scale),
                                   bias_instability_floor=self.bias_instability_floor * scale)


#: Points with fewer equivalent degrees of freedom (68 % CI wider than about +-25 %) are
#: not trusted as the curve's minimum: at the longest taus a chance low point would win.
MIN_EDF_FOR_MINIMUM = 10.0


def read_curve(tau_s: Any, dev: Any, ci_low: Any = None, ci_high: Any = None, *,
               confidence: float = 0.683, edf: Any = None,
               min_edf: float = MIN_EDF_FOR_MINIMUM,
               term_curves: dict[str, Any] | None = None,
               limits: Collection[str] = ()) -> CurveReadout:
    """Read the minimum, segment slopes, regions A-D and dominant-term ranges of a curve.

    Parameters
    ----------
    tau_s, dev : array_like
        Averaging times (increasing) and deviations.
    ci_low, ci_high : array_like, optional
        Confidence bounds per point (default: the point itself).
    confidence : float
        Level of the bounds.
    edf : array_like, optional
        Equivalent degrees of freedom per point.  When given, the minimum is searched
        among the points with ``edf >= min_edf`` only (all points if none qualify).
    min_edf : float
        See ``edf``.
    term_curves : dict of str to array_like, optional
        Each fitted term's own sigma(tau) at ``tau_s`` (e.g. from a NoiseModel).
    limits : collection of str
        The terms of ``term_curves`` the fit reports as upper limits: their ranges are
        marked not measured (:attr:`DominantRange.measured`).

    Examples
    --------
    >>> import numpy as np
    >>> tau = np.logspace(-1, 3, 9)
    >>> r = read_curve(tau, np.sqrt(1 / tau + tau / 100))
    >>> round(r.tau_min_s, 1), bool(r.regions["B"][0] == tau[0])
    (10.0, True)
    """
    t = np.asarray(tau_s, dtype=np.float64)
    d = np.asarray(dev, dtype=np.float64)
    if t.ndim != 1 or t.shape != d.shape:
        raise DataError(f"tau_s and dev must be 1-D arrays of equal length, got shapes "
                        f"{t.shape} and {d.shape}")
    ok = np.isfinite(d) & (d > 0) & np.isfinite(t) & (t > 0)
    if ok.sum() < 2:
        raise InsufficientDataError(f"a curve needs at least 2 finite positive points, got "
                                    f"{int(ok.sum())}")
    if np.any(np.diff(t[ok]) <= 0):
        raise DataError("tau_s must be strictly increasing")
    lo = np.asarray(ci_low, dtype=np.float64)[ok] if ci_low is not None else d[ok]
    hi = np.asarray(ci_high, dtype=np.float64)[ok] if ci_high is not None else d[ok]
    t, d = t[ok], d[ok]
    trusted = np.ones(t.size, dtype=bool)
    if edf is not None:
        e = np.asarray(edf, dtype=np.float64)[ok]
        trusted = np.isfinite(e) & (e >= min_edf)
        if not trusted.any():
            trusted[:] = True
    i_min = int(np.argmin(np.where(trusted, d, np.inf)))
    slopes = np.diff(np.log(d)) / np.diff(np.log(t))
    segments = np.column_stack([t[:-1], t[1:]])
    regions = _regions(t, d, lo, hi, i_min)
    dominant = _dominant_ranges(t, ok, term_curves, set(limits)) if term_curves else ()
    lo_min = float(lo[i_min]) if np.isfinite(lo[i_min]) else float(d[i_min])
    hi_min = float(hi[i_min]) if np.isfinite(hi[i_min]) else float(d[i_min])
    return CurveReadout(float(t[i_min]), float(d[i_min]), (lo_min, hi_min), float(confidence),
                        float(d[i_min] / B_PLATEAU), segments, slopes, regions, dominant)


def _regions(t: FloatArray, d: FloatArray, lo: FloatArray, hi: FloatArray, i_min: int
             ) -> dict[str, tuple[float, float] | None]:
    """Region C: contiguous points around the minimum whose CI overlaps the minimum's."""
    floor_hi = hi[i_min] if np.isfinite(hi[i_min]) else d[i_min]
    flat = d <= floor_hi
    a = i_min
    while a > 0 and flat[a - 1]:
        a -= 1
    b = i_min
    while b < t.size - 1 and flat[b + 1]:
        b += 1
    return {
        "A": (float(t[0]), float(t[0])),
        "B": (float(t[0]), float(t[a])) if a > 0 else None,
        "C": (float(t[a]), float(t[b])),
        "D": (float(t[b]), float(t[-1])) if b < t.size - 1 else None,
    }


def _dominant_ranges(t: FloatArray, ok: np.ndarray, term_curves: dict[str, Any],
                     limits: set[str]) -> tuple[DominantRange, ...]:
    names = list(term_curves)
    stack = np.vstack([np.asarray(term_curves[n], dtype=np.float64)[ok] for n in names])
    stack = np.where(np.isfinite(stack), stack, 0.0)
    winner = np.argmax(stack, axis=0)
    ranges: list[DominantRange] = []
    start = 0
    for i in range(1, t.size + 1):
        if i == t.size or winner[i] != winner[start]:
            name = names[int(winner[start])]
            if stack[winner[start], start:i].max() > 0:
                ranges.append(DominantRange(name, float(t[start]), float(t[i - 1]),
                                            TERM_SLOPE.get(name, float("nan")),
                                            measured=name not in limits))
            start = i
    return tuple(ranges)


# --------------------------------------------------------------------------- slope read-offs


@dataclass(frozen=True)
class SlopeReadoff:
    """The classic graphical read-offs (comparison only; NOT the fitted answer).

    IEEE Std 952-1997 Annex C and MATLAB's ``allanvar`` example: a line of the term's slope
    is drawn through the curve point whose local log-log slope is closest to it; N is that
    -1/2 line at tau = 1 s (divided by 60 for deg/sqrt(h)), K the +1/2 line at tau = 3 s
    (times 60 for deg/h^1.5); B is the minimum deviation / :data:`B_PLATEAU`.

    Attributes
    ----------
    N, K, B : float
        In deg/sqrt(h), deg/h^1.5 and deg/h.
    tau_N_s, tau_K_s, tau_B_s : float
        The curve point each value was read from.
    slope_N, slope_K : float
        The local slope found there (how well the curve shows the -1/2 or +1/2 line).
    """

    N: float
    K: float
    B: float
    tau_N_s: float
    tau_K_s: float
    tau_B_s: float
    slope_N: float
    slope_K: float
    # the read-off points in the curve's own units, for plotting: (tau_s, dev)
    points: tuple[tuple[str, float, float], ...] = ()
    #: "rate" (units of TERMS) or "accel" (units of ACCEL_TERMS)
    quantity: str = "rate"

    def _unit(self, name: str) -> str:
        return term_rows(self.quantity)[name].unit

    def to_dict(self) -> dict[str, Any]:
        return {"method": "slope read-off (IEEE 952 Annex C / MATLAB allanvar example); "
                          "comparison only, not the fit",
                "N": {"value": self.N, "unit": self._unit("N"), "tau": self.tau_N_s,
                      "local_slope": self.slope_N, "read_at_tau": TERMS["N"].readoff_tau_s},
                "K": {"value": self.K, "unit": self._unit("K"), "tau": self.tau_K_s,
                      "local_slope": self.slope_K, "read_at_tau": TERMS["K"].readoff_tau_s},
                "B": {"value": self.B, "unit": self._unit("B"), "tau": self.tau_B_s}}

    def describe(self, number: Callable[[float], str] = lambda v: f"{v:.4g}",
                 units: str = "deg") -> str:
        """The read-offs as one sentence (``number`` formats the values) in ``units``
        (``"deg"``: the term table's engineering units; ``"si"``: :mod:`fogts.units`).

        N or K is given as "not read" when the curve has no segment of its slope
        (:func:`readoff_supported`): a line of slope +1/2 through a flat or falling
        segment reads nothing about rate random walk."""
        def term(name: str) -> str:
            value = term_in_units(name, getattr(self, name), units, self.quantity)
            return f"{name} = {number(value)} {term_unit(name, units, self.quantity)}"

        def line(name: str, sign: str) -> str:
            at = f"{TERMS[name].readoff_tau_s:g}"
            if readoff_supported(self, name):
                return f"{term(name)} ({sign}1/2 line at tau = {at} s)"
            slope, tau = getattr(self, f"slope_{name}"), getattr(self, f"tau_{name}_s")
            return (f"{name} not read (no segment of slope {sign}1/2: the closest, "
                    f"{slope:+.2f}, starts at tau = {tau:.4g} s)")

        return (f"slope read-offs (comparison only, not the fit): {line('N', '-')}, "
                f"{line('K', '+')}, {term('B')} (minimum / {B_PLATEAU:g})")


#: A read-off line of a term's slope reads that term only through a segment whose local
#: slope is nearer to it than to the neighbouring power laws', which lie 1/2 away
#: (IEEE Std 952-1997 Annex C, Table C.1): within 1/4.
READOFF_SLOPE_TOLERANCE = 0.25


def readoff_supported(readoff: SlopeReadoff, name: str) -> bool:
    """Whether the N or K read-off was drawn through a segment of (about) its slope:
    ``|local slope - term slope| <= READOFF_SLOPE_TOLERANCE``; B (the minimum) always is.

    Examples
    --------
    >>> tau = 2.0 ** np.arange(-4, 8)
    >>> r = slope_readoff(tau, 0.6 / np.sqrt(tau), 1.0)
    >>> readoff_supported(r, "N"), readoff_supported(r, "K")
    (True, False)
    """
    if name not in ("N", "K"):
        return True
    slope = float(getattr(readoff, f"slope_{name}"))
    return math.isfinite(slope) and abs(slope - TERM_SLOPE[name]) <= READOFF_SLOPE_TOLERANCE


def slope_readoff(tau: FloatArray, dev: FloatArray, factor: float,
                  edf: FloatArray | None = None, quantity: str = "rate") -> SlopeReadoff:
    """The IEEE 952 Annex C / MATLAB ``allanvar`` read-offs of N, K and B.

    Lines of slope -1/2 (+1/2) through the point whose local log-log slope is closest to it,
    read at tau = 1 s (3 s); B = minimum / :data:`B_PLATEAU`.  The minimum is
    :func:`read_curve`'s: the lowest point among those with at least ``MIN_EDF_FOR_MINIMUM``
    degrees of freedom, so that a last point with two terms that happens to fall low is not
    read as the flicker floor.

    Parameters
    ----------
    tau, dev : ndarray
        The curve (increasing tau, positive deviations).
    factor : float
        Multiplies ``dev`` to give deg/h (m/s^2 for ``quantity="accel"``).
    edf : ndarray, optional
        Equivalent degrees of freedom per point.
    quantity : {"rate", "accel"}
        Gyro (:data:`~fogts.allan.terms.TERMS`) or accelerometer
        (:data:`~fogts.allan.terms.ACCEL_TERMS`) units.

    Returns
    -------
    SlopeReadoff

    Examples
    --------
    >>> tau = 2.0 ** np.arange(-4, 8)
    >>> r = slope_readoff(tau, 0.6 / np.sqrt(tau), 1.0)
    >>> round(r.N, 6), r.slope_N
    (0.01, -0.5)
    """
    logt, logd = np.log10(tau), np.log10(dev)
    slopes = np.diff(logd) / np.diff(logt) if tau.size >= 2 else np.array([math.nan])

    def line(name: str) -> tuple[float, float, float]:
        at, target = TERMS[name].readoff_tau_s, TERM_SLOPE[name]
        if not np.any(np.isfinite(slopes)):
            return math.nan, math.nan, math.nan
        i = int(np.nanargmin(np.abs(slopes - target)))
        b = logd[i] - target * logt[i]
        return float(10 ** (target * math.log10(at) + b)), float(tau[i]), float(slopes[i])

    n_dev, tau_n, slope_n = line("N")
    k_dev, tau_k, slope_k = line("K")
    if tau.size >= 2:
        floor = read_curve(tau, dev, edf=edf)
        b_dev, tau_b = floor.dev_min, floor.tau_min_s
    else:
        b_dev, tau_b = float(dev[0]), float(tau[0])
    return SlopeReadoff(
        N=from_seconds("N", n_dev * factor, quantity),
        K=from_seconds("K", k_dev * factor, quantity),
        B=from_seconds("B", b_dev * factor / B_PLATEAU, quantity), tau_N_s=tau_n, tau_K_s=tau_k, tau_B_s=tau_b,
        slope_N=slope_n, slope_K=slope_k,
        points=(("N", TERMS["N"].readoff_tau_s, n_dev), ("K", TERMS["K"].readoff_tau_s, k_dev),
                ("B", tau_b, b_dev)), quantity=quantity)
