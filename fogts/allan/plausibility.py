"""Are the fitted N and B those of a real gyro?  A guard against a wrong rate unit.

fogts assumes deg/h when a recording names no unit.  Read in the wrong unit, every
coefficient is off by the unit ratio (57.3 between deg/s and rad/s, 3600 between deg/h and
deg/s, 206265 between deg/h and rad/s), and the numbers stop looking like any gyro: an
XSens MEMS recorded in rad/s and read as deg/h gives N = 1.1e-5 deg/sqrt(h), below the
best strategic-grade gyro.  :func:`check_plausibility` compares N (angle random walk) and
B (bias instability) with the span of real gyros and, when they fall outside it, says
which input unit would put them inside.

The grades (:data:`GRADES`, N in deg/sqrt(h), B in deg/h) are the usual ranges, widened
by about a factor of two at each end:

* strategic and navigation-grade RLG/FOG: e.g. Honeywell GG1320AN (ARW 0.0035 deg/sqrt(h),
  bias stability 0.0035 deg/h), HG9900 (0.002 deg/sqrt(h), 0.003 deg/h); strategic iFOGs
  reach ARW ~1e-4 deg/sqrt(h) (Lefevre, *The Fiber-Optic Gyroscope*, 2nd ed., 2014);
* tactical FOG/RLG: KVH DSP-1750 (0.012 deg/sqrt(h), 0.05 deg/h), Northrop Grumman
  LN-200 (0.07 deg/sqrt(h), 1 deg/h), Honeywell HG1700 (0.125-0.3 deg/sqrt(h), 1 deg/h);
* industrial MEMS: ADIS16495 (0.09 deg/sqrt(h), 0.8 deg/h), Sensonor STIM300
  (0.15 deg/sqrt(h), 0.5 deg/h), ADIS16405 (2 deg/sqrt(h), 25 deg/h);
* consumer MEMS: InvenSense MPU-6050 (0.005 deg/s/sqrt(Hz) = 0.3 deg/sqrt(h)), Bosch
  BMI055 (0.014 deg/s/sqrt(Hz) = 0.84 deg/sqrt(h)), bias instability up to ~1000 deg/h.

The grade table follows Groves, *Principles of GNSS, Inertial, and Multisensor
Integrated Navigation Systems*, 2nd ed. (2013), sec. 4.4, and Passaro et al. (2017),
"Gyroscope technology and applications: a review in the industrial perspective",
Sensors 17(10), 2284, Table 1; the device figures are from the manufacturers' datasheets.
The envelope is deliberately wide: a real recording can be noisier than its datasheet
(vibration, quantisation), so only values far outside any gyro are called implausible.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import pandas as pd

from fogts.errors import DataError
from fogts.units import RATE_UNITS, parse_rate_unit, to_deg_per_hour_factor

__all__ = ["GRADES", "Grade", "PlausibilityReport", "check_plausibility"]


@dataclass(frozen=True)
class Grade:
    """A class of gyros and the ranges of N (deg/sqrt(h)) and B (deg/h) it spans."""

    name: str
    n_range: tuple[float, float]
    b_range: tuple[float, float]

    def holds(self, n: float | None, b: float | None) -> bool:
        return (n is None or self.n_range[0] <= n <= self.n_range[1]) and \
            (b is None or self.b_range[0] <= b <= self.b_range[1])

    def distance(self, n: float | None, b: float | None) -> float:
        """Log10 distance of (N, B) from the middle of the grade (for ranking units)."""
        total = 0.0
        for value, (lo, hi) in ((n, self.n_range), (b, self.b_range)):
            if value is not None:
                total += abs(math.log10(value) - 0.5 * (math.log10(lo) + math.log10(hi)))
        return total


#: Gyro grades, strategic FOG to consumer MEMS (sources in the module docstring).
GRADES: tuple[Grade, ...] = (
    Grade("strategic/navigation-grade FOG or RLG", (5e-5, 0.01), (5e-5, 0.02)),
    Grade("tactical-grade FOG or RLG", (0.005, 0.6), (0.01, 10.0)),
    Grade("industrial MEMS", (0.05, 4.0), (0.2, 100.0)),
    Grade("consumer MEMS", (0.1, 20.0), (1.0, 2000.0)),
)


@dataclass(frozen=True)
class PlausibilityReport:
    """The verdict on (N, B) and, when implausible, the units that would fix it.

    Attributes
    ----------
    verdict : str
        ``"plausible"``, ``"implausible"`` or ``"not checked"`` (neither N nor B fitted).
    n, b : float or None
        N in deg/sqrt(h) and B in deg/h as fitted (None: not fitted or fitted to zero).
    units : str
        The rate unit the data were read in.
    grades : tuple of str
        Grades (:data:`GRADES`) that hold the values.
    alternatives : tuple of dict
        For an implausible result: each other unit whose rescaled N and B land inside a
        grade, best first, as ``{"units", "N", "B", "grade"}``.
    """

    verdict: str
    n: float | None
    b: float | None
    units: str
    grades: tuple[str, ...]
    alternatives: tuple[dict[str, Any], ...]

    @property
    def message(self) -> str:
        """One line for a ``warning:``."""
        if self.verdict != "implausible":
            return f"N and B are {self.verdict}" + (f" ({self.grades[0]})" if self.grades
                                                   else "")
        shown = " and ".join(v for v in (_fmt("N", self.n, "deg/sqrt(h)"),
                                         _fmt("B", self.b, "deg/h")) if v)
        text = (f"{shown} lie outside every real gyro (strategic FOG to consumer MEMS) for a "
                f"rate in {self.units}")
        if not self.alternatives:
            return text + "; check the input unit and the data"
        fixes = []
        for alt in self.alternatives:
            values = " and ".join(v for v in (_fmt("N", alt["N"], "deg/sqrt(h)"),
                                              _fmt("B", alt["B"], "deg/h")) if v)
            fixes.append(f"if the input was {alt['units']}, {values}, typical of a "
                         f"{alt['grade']}")
        return f"{text}; {'; '.join(fixes)} (pass --units)"

    def to_dict(self) -> dict[str, Any]:
        return {"verdict": self.verdict, "N": self.n, "B": self.b, "units": self.units,
                "grades": list(self.grades), "alternatives": [dict(a) for a in self.alternatives],
                "message": self.message}

    def to_frame(self) -> pd.DataFrame:
        """One row per alternative unit (empty when plausible)."""
        return pd.DataFrame(list(self.alternatives), columns=["units", "N", "B", "grade"])

    def summary(self) -> str:
        return self.message


def _fmt(name: str, value: float | None, unit: str) -> str:
    return "" if value is None else f"{name} = {value:.3g} {unit}"


def _usable(name: str, value: float | None) -> float | None:
    if value is None:
        return None
    v = float(value)
    if math.isnan(v) or v < 0:
        raise DataError(f"{name} must be a non-negative number or None, got {value!r}")
    return v if v > 0 else None


def _grades_of(n: float | None, b: float | None) -> tuple[Grade, ...]:
    return tuple(g for g in GRADES if g.holds(n, b))


def check_plausibility(n: float | None, b: float | None, *, units: str) -> PlausibilityReport:
    """Compare N (deg/sqrt(h)) and B (deg/h) with the span of real gyros.

    Parameters
    ----------
    n, b : float or None
        Angle random walk and bias instability as fitted by :func:`fogts.fit_noise`
        (deg/h-based units).  None or 0 (a term not fitted, or fitted to zero) is left
        out of the judgement.
    units : str
        The rate unit the data were read in (one of :data:`fogts.units.RATE_UNITS`).

    Returns
    -------
    PlausibilityReport
        When implausible, the other units that would make (N, B) plausible, best first
        (closest, in log10, to the middle of a grade).

    Raises
    ------
    DataError
        A negative or NaN value, or an unknown unit.

    Examples
    --------
    >>> rep = check_plausibility(1.09e-5, 5.0e-5, units="deg/h")   # rad/s read as deg/h
    >>> rep.verdict, [(a["units"], round(a["N"], 3)) for a in rep.alternatives]
    ('implausible', [('deg/s', 0.039), ('rad/s', 2.248)])
    >>> check_plausibility(0.012, 0.05, units="deg/h").verdict      # a KVH DSP-1750
    'plausible'
    """
    unit = parse_rate_unit(units)
    n_v, b_v = _usable("N", n), _usable("B", b)
    if n_v is None and b_v is None:
        return PlausibilityReport("not checked", None, None, unit, (), ())
    held = _grades_of(n_v, b_v)
    if held:
        return PlausibilityReport("plausible", n_v, b_v, unit, tuple(g.name for g in held), ())
    return PlausibilityReport("implausible", n_v, b_v, unit, (),
                              _alternatives(n_v, b_v, unit))


def _alternatives(n: float | None, b: float | None, unit: str) -> tuple[dict[str, Any], ...]:
    """Other input units under which (N, B) fall inside a grade, best first."""
    found = []
    for other in RATE_UNITS:
        if other == unit:
            continue
        scale = to_deg_per_hour_factor(other) / to_deg_per_hour_factor(unit)
        n2 = None if n is None else n * scale
        b2 = None if b is None else b * scale
        grades = _grades_of(n2, b2)
        if grades:
            best = min(grades, key=lambda g: g.distance(n2, b2))
            found.append(({"units": other, "N": n2, "B": b2, "grade": best.name},
                          best.distance(n2, b2)))
    return tuple(f for f, _ in sorted(found, key=lambda item: item[1]))
