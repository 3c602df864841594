"""Read an Allan-deviation curve the way seed 001 does: regions A-D, minimum, slopes.

Seed 001 (a review of Allan-variance studies of optical gyros) reads the log-log curve in
four regions:

* A: the single-sample noise at the shortest tau;
* B: the falling part that averaging removes (ARW has slope -1/2, quantization -1);
* C: the minimum, giving the optimal averaging time and the noise floor (the
  bias-instability point; IEEE Std 952-1997 Annex C: B = sigma_min / 0.664 for flicker);
* D: the rise from slow drift (rate random walk +1/2, rate ramp +1).

:func:`read_curve` returns the minimum with its confidence interval, the log-log slope of
every segment, the regions B-D found from the curve itself, and, when the fitted term
lines are given, the tau range where each term dominates.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np
import pandas as pd

from fogts._typing import FloatArray
from fogts.allan.terms import B_PLATEAU
from fogts.errors import DataError, InsufficientDataError

__all__ = ["CurveReadout", "DominantRange", "read_curve"]

#: Power-law slopes of sigma(tau) for the IEEE-952 terms (IEEE Std 952-1997, Annex C).
TERM_SLOPES: dict[str, float] = {"Q": -1.0, "N": -0.5, "B": 0.0, "K": 0.5, "R": 1.0}


@dataclass(frozen=True)
class DominantRange:
    """A contiguous tau range where one fitted term is the largest contribution."""

    term: str
    tau_from_s: float
    tau_to_s: float
    slope: float

    def to_dict(self) -> dict[str, Any]:
        return {"term": self.term, "tau_from": self.tau_from_s, "tau_to": self.tau_to_s,
                "slope": self.slope}


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
        ``dev_min / 0.664``: the flicker-floor estimate of B (IEEE 952 Annex C), in the
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

    def summary(self) -> str:
        lo, hi = self.dev_min_ci
        lines = [f"minimum: sigma = {self.dev_min:.4g} [{lo:.4g}, {hi:.4g}] at tau = "
                 f"{self.tau_min_s:.4g} s ({100 * self.confidence:.1f} % CI); "
                 f"floor/0.664 = {self.bias_instability_floor:.4g}"]
        for name, span in self.regions.items():
            if span is not None:
                lines.append(f"region {name}: tau {span[0]:.4g} .. {span[1]:.4g} s")
        for d in self.dominant:
            lines.append(f"{d.term} dominates tau {d.tau_from_s:.4g} .. {d.tau_to_s:.4g} s "
                         f"(slope {d.slope:+g})")
        return "\n".join(lines)


#: Points with fewer equivalent degrees of freedom (68 % CI wider than about +-25 %) are
#: not trusted as the curve's minimum: at the longest taus a chance low point would win.
MIN_EDF_FOR_MINIMUM = 10.0


def read_curve(tau_s: Any, dev: Any, ci_low: Any = None, ci_high: Any = None, *,
               confidence: float = 0.683, edf: Any = None,
               min_edf: float = MIN_EDF_FOR_MINIMUM,
               term_curves: dict[str, Any] | None = None) -> CurveReadout:
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
    dominant = _dominant_ranges(t, ok, term_curves) if term_curves else ()
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


def _dominant_ranges(t: FloatArray, ok: np.ndarray, term_curves: dict[str, Any]
                     ) -> tuple[DominantRange, ...]:
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
                                            TERM_SLOPES.get(name, float("nan"))))
            start = i
    return tuple(ranges)
