"""Does the fitted noise model describe the Allan curve?  Per-tau normalised residuals and
a verdict a user reads.

The normalised residual of the fit at tau_i is its distance from the measured deviation in
units of that point's confidence half-width on the side the fit lies:

    z_i = (fit_i - dev_i) / (ci_high_i - dev_i)   if fit_i > dev_i,
          (fit_i - dev_i) / (dev_i - ci_low_i)    otherwise.

A model that describes the data keeps |z| near 1 (the intervals are 68 %, neighbouring taus
are correlated).  A point with |z| > :data:`MISS_Z` is a miss; a miss is reported when two
neighbouring points miss, or one point misses by more than :data:`SINGLE_MISS_Z` (a chance
excursion that large is very unlikely).  On simulated five-term records |z| stays below 2;
on the real ADIS16405 and XSens curves it reaches 100-270 at the shortest taus.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np

if TYPE_CHECKING:
    from fogts._typing import FloatArray
    from fogts.allan.noise_model import NoiseModel
    from fogts.allan.result import AllanResult

__all__ = ["MISS_Z", "SINGLE_MISS_Z", "FitCheck", "Miss", "check_fit"]

MISS_Z = 3.0  #: a point misses when the fit lies beyond this many CI half-widths
SINGLE_MISS_Z = 5.0  #: ... and a single missing point is reported from this many on


@dataclass(frozen=True)
class Miss:
    """A contiguous tau range where the fit misses the data."""

    tau_from_s: float
    tau_to_s: float
    ratio_min: float
    ratio_max: float
    z_max: float
    cause: str

    def describe(self) -> str:
        where = (f"at tau = {self.tau_from_s:.3g} s" if self.tau_from_s == self.tau_to_s
                 else f"between {self.tau_from_s:.3g} and {self.tau_to_s:.3g} s")
        ratio = (f"{self.ratio_min:.3g}x" if abs(self.ratio_max - self.ratio_min) < 5e-3
                 else f"{self.ratio_min:.3g}-{self.ratio_max:.3g}x")
        return f"the fit is {ratio} the data {where} ({self.cause})"

    def to_dict(self) -> dict[str, Any]:
        return {"tau_from": self.tau_from_s, "tau_to": self.tau_to_s,
                "ratio_min": self.ratio_min, "ratio_max": self.ratio_max,
                "z_max": self.z_max, "cause": self.cause}


@dataclass(frozen=True)
class FitCheck:
    """The verdict on the fit: the normalised residual per tau and the ranges it misses."""

    tau_s: FloatArray
    z: FloatArray
    ratio: FloatArray
    misses: tuple[Miss, ...]
    confidence: float

    @property
    def residual(self) -> FloatArray:
        """The residual of the data from the fit per tau, ``(dev - fit)`` in half-widths of
        the point's interval: ``-z`` (positive where the data lie above the fit)."""
        return -self.z

    @property
    def ok(self) -> bool:
        return not self.misses

    @property
    def verdict(self) -> str:
        if self.ok:
            return self._ok_verdict()
        return ("the five-term model misses the curve: "
                + "; ".join(m.describe() for m in self.misses)
                + f" (beyond {MISS_Z:g} half-widths of the {100 * self.confidence:.1f} % "
                  "intervals); treat the terms there with care")

    def _ok_verdict(self) -> str:
        """No range misses; isolated points beyond :data:`MISS_Z` (but within
        :data:`SINGLE_MISS_Z`) are named, not hidden behind "every point"."""
        size = np.abs(np.nan_to_num(self.z))
        pct = f"{100 * self.confidence:.1f} %"
        worst = int(np.argmax(size))
        outside = int(np.count_nonzero(size > MISS_Z))
        if outside == 0:
            return (f"the fit lies within {MISS_Z:g} half-widths of every point's {pct} "
                    f"interval (largest |z| {size[worst]:.2g})")
        return (f"no tau range misses: the fit lies within {MISS_Z:g} half-widths of the "
                f"{pct} interval at all but {outside} isolated point(s) (largest |z| "
                f"{size[worst]:.2g} at tau = {self.tau_s[worst]:.4g} s; a single point is "
                f"reported as a miss from |z| > {SINGLE_MISS_Z:g})")

    def to_dict(self) -> dict[str, Any]:
        return {"ok": self.ok, "verdict": self.verdict, "miss_z": MISS_Z,
                "misses": [m.to_dict() for m in self.misses],
                "z": self.z.tolist(), "ratio": self.ratio.tolist()}


def _cause(first: int, last: int, n: int) -> str:
    if first == 0:
        return ("shortest taus: quantization, a sampling or anti-alias filter, or a "
                "correlated noise faster than the sample rate")
    if last == n - 1:
        return "longest taus: few averages, or a drift the record is too short to show"
    return "mid taus: a correlated (Markov) term or a bump the five terms cannot draw"


def check_fit(result: AllanResult, model: NoiseModel) -> FitCheck:
    """Compare ``model`` with the curve it was fitted to (see the module docstring)."""
    tau = np.asarray(result.tau_s, dtype=np.float64)
    dev = np.asarray(result.dev, dtype=np.float64)
    fit = np.asarray(model.curve(tau), dtype=np.float64)
    upper = np.asarray(result.ci_high, dtype=np.float64) - dev
    lower = dev - np.asarray(result.ci_low, dtype=np.float64)
    width = np.where(fit > dev, upper, lower)
    with np.errstate(divide="ignore", invalid="ignore"):
        z = np.where(width > 0, (fit - dev) / width, np.nan)
        ratio = fit / dev
    bad = np.abs(np.nan_to_num(z)) > MISS_Z
    misses = []
    i = 0
    while i < tau.size:
        if not bad[i]:
            i += 1
            continue
        j = i
        while j + 1 < tau.size and bad[j + 1] and np.sign(z[j + 1]) == np.sign(z[i]):
            j += 1
        zmax = float(np.max(np.abs(z[i:j + 1])))
        if j > i or zmax > SINGLE_MISS_Z:
            misses.append(Miss(float(tau[i]), float(tau[j]), float(np.min(ratio[i:j + 1])),
                               float(np.max(ratio[i:j + 1])), zmax,
                               _cause(i, j, tau.size)))
        i = j + 1
    return FitCheck(tau_s=tau, z=z, ratio=ratio, misses=tuple(misses),
                    confidence=result.confidence)
