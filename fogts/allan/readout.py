"""Read an Allan-deviation curve by eye, as a program: regions A-D, minimum, slopes, read-offs.

The log-log curve of an optical gyro is read in four regions (IEEE Std 952-1997 Annex C):

* A: the single-sample noise at the shortest tau;
* B: the falling part that averaging removes (ARW has slope -1/2, quantization -1);
* C: the minimum, giving the optimal averaging time and the noise floor (the
  bias-instability point: B = sigma_min / the estimator's flicker plateau factor,
  :data:`~fogts.allan.terms.FLICKER_PLATEAU`, 0.664 for the Allan variance), found only
  where the curve is flat within the points' intervals around the minimum;
* D: the rise from slow drift (rate random walk +1/2, rate ramp +1).

:func:`read_curve` returns the minimum with its confidence interval, the log-log slope of
every segment, the regions B-D found from the curve itself, and, when the fitted term
lines are given, the tau range where each term dominates.  A curve still falling at its
last trusted tau has no floor, and the read-out says so instead of dividing its lowest
point by the plateau factor.  :func:`fogts.allan.readoff.slope_readoff` gives the classic
graphical N, K and B (IEEE 952 Annex C; MATLAB's ``allanvar`` example), which the noise
fit reports beside its answer for comparison.
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Collection
from dataclasses import dataclass
from typing import Any

import numpy as np
import pandas as pd

from fogts._typing import FloatArray
from fogts.allan.terms import B_PLATEAU, TERM_SLOPE, flicker_plateau
from fogts.errors import DataError, InsufficientDataError
from fogts.tables import Column, Table, fields_dict
from fogts.units import convert_sensor

__all__ = ["MIN_EDF_FOR_MINIMUM", "CurveReadout", "DominantRange", "read_curve"]


@dataclass(frozen=True)
class DominantRange:
    """A contiguous tau range where one fitted term is the largest contribution;
    ``measured`` is False for a term the fit reports as an upper limit (its line is the
    fitted value, which the data do not distinguish from zero); ``extrapolated`` is True for
    a range that leaves the taus the terms were fitted over (the fitted lines extended)."""

    term: str
    tau_from_s: float
    tau_to_s: float
    slope: float
    measured: bool = True
    extrapolated: bool = False

    def to_dict(self) -> dict[str, Any]:
        return fields_dict(self, tau_from_s="tau_from", tau_to_s="tau_to")


#: Points with fewer equivalent degrees of freedom (68 % CI wider than about +-25 %) are
#: not trusted as the curve's minimum: at the longest taus a chance low point would win.
MIN_EDF_FOR_MINIMUM = 10.0


@dataclass(frozen=True)
class CurveReadout:
    """Read-outs of one Allan-deviation curve.

    Attributes
    ----------
    tau_min_s, dev_min : float
        The lowest trusted point of the curve (optimal averaging time and noise floor):
        the lowest among the points with at least ``min_edf`` degrees of freedom.
    dev_min_ci : tuple of float
        Its confidence interval ``(low, high)`` at level ``confidence``.
    confidence : float
    bias_instability_floor : float
        ``dev_min / plateau``: the flicker-floor estimate of B (IEEE 952 Annex C), in the
        curve's rate unit; NaN when the curve has no floor (``floor_note``) or the
        estimator has no plateau factor.
    segment_tau_s : ndarray, shape (k, 2)
        Start and end tau of each segment between consecutive points.
    segment_slope : ndarray, shape (k,)
        d log sigma / d log tau of each segment.
    regions : dict
        ``{"A": (tau, tau), "B": (from, to), "C": (from, to) or None, "D": (from, to) or
        None}``: A is the first point; B the falling part down to region C; C the floor: the
        contiguous points around the minimum whose deviation lies inside the minimum's
        interval (None when the curve is still falling at its last trusted tau); D the rise
        above that interval after C.
    dominant : tuple of DominantRange
        Where each fitted term dominates (empty without term curves).
    kind : str
        The estimator (its flicker plateau factor converts the floor to B).
    plateau : float
        The estimator's flicker-FM plateau factor (:data:`~fogts.allan.terms.FLICKER_PLATEAU`;
        NaN when none is established).
    min_edf : float or None
        The EDF a point needs to be the minimum (None: no EDF given, every point counts).
    lower_points : tuple of (tau_s, dev, edf)
        Points below the minimum left out for their EDF below ``min_edf``.
    minimum_note : str
        Says how the minimum was chosen when the EDF rule mattered ("" otherwise).
    floor_note : str
        Why the curve has no floor ("" when it has one).
    fit_tau_s : (float, float) or None
        The first and last tau the term lines of ``dominant`` were fitted over, when that is
        part of the curve (the ranges beyond it are marked extrapolated).
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
    kind: str = "oadev"
    plateau: float = B_PLATEAU
    min_edf: float | None = None
    lower_points: tuple[tuple[float, float, float], ...] = ()
    minimum_note: str = ""
    floor_note: str = ""
    fit_tau_s: tuple[float, float] | None = None

    @property
    def floor_found(self) -> bool:
        """Whether the curve has a floor (region C) at its minimum."""
        return not self.floor_note

    def floor_text(self, units: str = "") -> str:
        """The floor's B estimate (``floor/plateau = value``) or why there is none: the
        one wording of the table, the JSON and the report."""
        unit = f" {units}" if units else ""
        if self.floor_note:
            return self.floor_note
        if not math.isfinite(self.plateau):
            return (f"the floor is not converted to B: no flicker-FM plateau factor is "
                    f"established for {self.kind}")
        return f"floor/{self.plateau:.4g} = {self.bias_instability_floor:.4g}{unit}"

    def to_frame(self) -> pd.DataFrame:
        """One row per segment: tau_from, tau_to, slope."""
        return pd.DataFrame({"tau_from": self.segment_tau_s[:, 0],
                             "tau_to": self.segment_tau_s[:, 1], "slope": self.segment_slope})

    def to_dict(self) -> dict[str, Any]:
        floor = self.bias_instability_floor
        return {
            "minimum": {"tau": self.tau_min_s, "dev": self.dev_min,
                        "ci_low": self.dev_min_ci[0], "ci_high": self.dev_min_ci[1],
                        "confidence": self.confidence,
                        "bias_instability_floor": floor if math.isfinite(floor) else None,
                        "kind": self.kind,
                        "plateau_factor": self.plateau if math.isfinite(self.plateau) else None,
                        "min_edf": self.min_edf, "note": self.minimum_note or None,
                        "lower_points": [{"tau": t, "dev": v, "edf": e}
                                         for t, v, e in self.lower_points],
                        "floor_found": self.floor_found, "floor": self.floor_text()},
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
        note = f"; {self.minimum_note}" if self.minimum_note else ""
        rows: list[tuple[str, str, str]] = [
            ("minimum", f"{self.tau_min_s:.4g} s",
             f"{self.dev_min:.4g} [{lo:.4g}, {hi:.4g}]{unit}{note}; "
             + ("no floor (see region C)" if self.floor_note else self.floor_text(units)))]
        # "region B" (IEEE 952 Annex C's letters), not "(B)": beside "B dominates" a bare B
        # reads as the bias-instability term
        for name, label in (("B", "falling (region B)"), ("C", "floor (region C)"),
                            ("D", "rising (region D)")):
            span = self.regions.get(name)
            if span is not None:
                rows.append((label, f"{span[0]:.4g} .. {span[1]:.4g} s", ""))
            elif name == "C" and self.floor_note:
                rows.append((label, "none", self.floor_note))
        for d in self.dominant:
            taus = f"{d.tau_from_s:.4g} .. {d.tau_to_s:.4g} s"
            beyond = ""
            if d.extrapolated and self.fit_tau_s is not None:
                beyond = (f"; beyond the fit range {self.fit_tau_s[0]:.4g} .. "
                          f"{self.fit_tau_s[1]:.4g} s the fitted lines are extrapolated")
            if d.measured:
                rows.append((f"{d.term} dominates", taus, f"slope {d.slope:+g}{beyond}"))
            else:
                rows.append((f"{d.term} line largest", taus, f"slope {d.slope:+g}; {d.term} is "
                             f"not measured (an upper limit): its fitted line, not a finding"
                             f"{beyond}"))
        return Table.build(f"curve of {axis}" if axis else "curve read-outs",
                           (Column("read-out", numeric=False), Column("tau", numeric=False),
                            Column("value", numeric=False, wrap=True)), rows,
                           caption=f"minimum with its {100 * self.confidence:.1f} % interval")

    def summary(self) -> str:
        return self.table().to_text()

    def in_unit(self, unit: str, to_unit: str) -> CurveReadout:
        """The read-outs with the deviations (minimum, its interval, the floor estimate, the
        lower points) converted from the curve's ``unit`` to ``to_unit``
        (:func:`fogts.units.convert_sensor`), e.g. for a points table shown in SI units;
        taus, slopes and regions stay."""
        if to_unit == unit:
            return self
        scale = float(convert_sensor(1.0, unit, to_unit))
        lo, hi = self.dev_min_ci
        return dataclasses.replace(self, dev_min=self.dev_min * scale,
                                   dev_min_ci=(lo * scale, hi * scale),
                                   bias_instability_floor=self.bias_instability_floor * scale,
                                   lower_points=tuple((t, v * scale, e)
                                                      for t, v, e in self.lower_points))


# Over 80 lines by its numpydoc docstring; the floor is _regions'.
def read_curve(tau_s: Any, dev: Any, ci_low: Any = None, ci_high: Any = None, *,
               confidence: float = 0.683, edf: Any = None,
               min_edf: float = MIN_EDF_FOR_MINIMUM,
               term_curves: dict[str, Any] | None = None,
               limits: Collection[str] = (), kind: str = "oadev",
               fit_tau_s: tuple[float, float] | None = None) -> CurveReadout:
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
        among the points with ``edf >= min_edf`` only (all points if none qualify), and
        the read-out says so when a lower point was left out.
    min_edf : float
        See ``edf``.
    term_curves : dict of str to array_like, optional
        Each fitted term's own sigma(tau) at ``tau_s`` (e.g. from a NoiseModel).
    limits : collection of str
        The terms of ``term_curves`` the fit reports as upper limits: their ranges are
        marked not measured (:attr:`DominantRange.measured`).
    kind : str
        The estimator: its flicker plateau factor (:func:`~fogts.allan.terms.flicker_plateau`)
        converts the floor to B.
    fit_tau_s : (float, float), optional
        The first and last tau the ``term_curves`` were fitted over: a dominant range that
        leaves them is marked :attr:`DominantRange.extrapolated`.

    Notes
    -----
    Region C, the floor, holds the contiguous points around the minimum whose deviation lies
    inside the minimum's interval (a point below it is not floor).  The curve has no floor
    when it is still falling at its last trusted tau: it ends below the minimum's interval
    without having risen above it (its last point lies below the interval and no point after
    the minimum above it; so when every point after the minimum lies below), or the minimum
    is the last point and the point before it lies above its interval.  The minimum is then
    where the trusted points end, not where the curve levels out, and ``minimum / plateau``
    would overstate B (IEEE 952 Annex C reads B on the flat bottom of the curve).  The
    ending decides, not any low point on the way: a low low-EDF point followed by one back
    inside the interval is scatter on the floor.  And a curve that rose above the interval
    after the minimum (region D) has turned up there, so a last low point at a few EDF
    after the rise is scatter too, not a continued fall.

    Examples
    --------
    >>> import numpy as np
    >>> tau = np.logspace(-1, 3, 9)
    >>> r = read_curve(tau, np.sqrt(1 / tau + tau / 100))
    >>> round(r.tau_min_s, 1), bool(r.regions["B"][0] == tau[0])
    (10.0, True)
    >>> read_curve(tau, 1 / np.sqrt(tau)).floor_note
    'no floor: the curve is still falling at its last trusted tau (1000 s)'
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
    lo = np.where(np.isfinite(lo), lo, d)
    hi = np.where(np.isfinite(hi), hi, d)
    trusted = np.ones(t.size, dtype=bool)
    e = np.full(t.size, np.nan)
    minimum_note = ""
    if edf is not None:
        e = np.asarray(edf, dtype=np.float64)[ok]
        trusted = np.isfinite(e) & (e >= min_edf)
        if not trusted.any():
            trusted[:] = True
            minimum_note = (f"no point has EDF >= {min_edf:g}: the minimum is the lowest of "
                            "all points")
    i_min = int(np.argmin(np.where(trusted, d, np.inf)))
    lower = tuple((float(t[i]), float(d[i]), float(e[i])) for i in range(t.size)
                  if not trusted[i] and d[i] < d[i_min])
    if lower:
        minimum_note = (f"the lowest point with EDF >= {min_edf:g} (lower points at "
                        f"{', '.join(f'{p[0]:.4g}' for p in lower)} s have EDF < {min_edf:g})")
    slopes = np.diff(np.log(d)) / np.diff(np.log(t))
    segments = np.column_stack([t[:-1], t[1:]])
    regions, floor_note = _regions(t, d, lo, hi, i_min)
    dominant = _dominant_ranges(t, ok, term_curves, set(limits), fit_tau_s) if term_curves \
        else ()
    plateau = flicker_plateau(kind)
    floor = float(d[i_min] / plateau) if not floor_note else math.nan
    return CurveReadout(float(t[i_min]), float(d[i_min]), (float(lo[i_min]), float(hi[i_min])),
                        float(confidence), floor, segments, slopes, regions, dominant,
                        kind=kind, plateau=plateau,
                        min_edf=float(min_edf) if edf is not None else None,
                        lower_points=lower, minimum_note=minimum_note, floor_note=floor_note,
                        fit_tau_s=fit_tau_s if dominant else None)


def _regions(t: FloatArray, d: FloatArray, lo: FloatArray, hi: FloatArray, i_min: int
             ) -> tuple[dict[str, tuple[float, float] | None], str]:
    """Regions A-D and, when the curve has no floor, why (see :func:`read_curve`'s Notes).

    Region C: contiguous points around the minimum whose deviation lies inside its
    interval (not below it: a point below the minimum's interval is not floor)."""
    flat = (d >= lo[i_min]) & (d <= hi[i_min])
    a = i_min
    while a > 0 and flat[a - 1]:
        a -= 1
    b = i_min
    while b < t.size - 1 and flat[b + 1]:
        b += 1
    after = d[i_min + 1:]
    # the curve ends below the floor without rising first (Notes), or its minimum is its
    # last point, reached falling
    falling = (bool(after.size) and bool(after[-1] < lo[i_min])
               and not bool(np.any(after > hi[i_min]))) or (
        not after.size and a == i_min and i_min > 0)
    first = (float(t[0]), float(t[0]))
    if falling:
        note = (f"no floor: the curve is still falling at its last trusted tau "
                f"({t[i_min]:.4g} s)")
        below = t[i_min + 1:][after < lo[i_min]]
        if below.size == after.size and after.size:
            note += (f"; the points beyond it ({t[i_min + 1]:.4g} .. {t[-1]:.4g} s) lie below "
                     "the minimum's interval")
        elif after.size:
            note += (f"; the curve ends below the minimum's interval (point"
                     f"{'s' if below.size > 1 else ''} at "
                     f"{', '.join(f'{v:.4g}' for v in below)} s)")
        return {"A": first, "B": (float(t[0]), float(t[-1])), "C": None, "D": None}, note
    rises = b < t.size - 1 and d[b + 1] > hi[i_min]
    return {
        "A": first,
        "B": (float(t[0]), float(t[a])) if a > 0 else None,
        "C": (float(t[a]), float(t[b])),
        "D": (float(t[b]), float(t[-1])) if rises else None,
    }, ""


def _dominant_ranges(t: FloatArray, ok: np.ndarray, term_curves: dict[str, Any],
                     limits: set[str], fit_tau_s: tuple[float, float] | None = None
                     ) -> tuple[DominantRange, ...]:
    lo, hi = fit_tau_s if fit_tau_s is not None else (0.0, math.inf)
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
                ranges.append(DominantRange(
                    name, float(t[start]), float(t[i - 1]), TERM_SLOPE.get(name, float("nan")),
                    measured=name not in limits,
                    extrapolated=bool(t[start] < lo * (1 - 1e-9) or t[i - 1] > hi * (1 + 1e-9))))
            start = i
    return tuple(ranges)

