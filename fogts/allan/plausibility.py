"""Are the fitted N and B those of a real gyro?  A check of the rate unit.

A recording whose column names carry no unit is read as deg/h (``Run.units_source ==
"assumed"``).  If it was really in rad/s, every Allan deviation, and so every IEEE-952
coefficient, comes out 206 265 times too small; in deg/s, 3600 times.  The noise fit cannot
notice: the curve has the same shape in every unit.  What can notice is a comparison with
the range real gyros span.  :func:`check_plausibility` places the angle random walk N
(deg/sqrt(h)) and the bias instability B (deg/h), as :mod:`fogts.allan.noise` reports them
(IEEE Std 952-1997 Annex C; DESIGN.md "Definitions"), in the table of gyro grades of
:mod:`fogts.allan.gyro_grades`, and when they fit none it says which other rate unit of
:data:`fogts.units.RATE_UNITS` would make them fit.  A change of rate unit multiplies N and
B by the same factor (the ratio of the units' deg/h factors,
:func:`fogts.units.to_deg_per_hour_factor`), so the pair moves along the diagonal of the
(log N, log B) plane.

Limits of the check
    The grades overlap along the diagonal, so a factor of 57 (rad/s vs deg/s) or of 3600
    (deg/s vs deg/h) often moves a pair from one grade to another rather than out of the
    envelope.  An industrial MEMS gyro in deg/s read as deg/h (ADIS16405: N 6.4e-4,
    B 9e-3) looks like a navigation-grade FOG or RLG; the check cannot tell the two apart
    from N and B.  The report lists such other plausible units (``also_plausible_units``,
    ``ambiguous``) so that a caller which knows the unit was only assumed can say so.  A
    rad/s recording read as deg/h (factor 206 265), the common mistake, is caught for every
    gyro with N below 6 deg/sqrt(h): its N lands below the envelope.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any, Literal

import numpy as np
import pandas as pd

from fogts.allan.gyro_grades import (
    B_ENVELOPE,
    GRADE_BY_KEY,
    GYRO_GRADES,
    N_ENVELOPE,
    GyroGrade,
    grade_table,
    grades_of,
)
from fogts.allan.terms import TERM_UNIT
from fogts.errors import DataError
from fogts.units import RATE_UNITS, parse_rate_unit, to_deg_per_hour_factor

__all__ = ["B_ENVELOPE", "GYRO_GRADES", "N_ENVELOPE", "GyroGrade", "PlausibilityReport",
           "UnitAlternative", "check_plausibility", "grade_table"]

Verdict = Literal["plausible", "implausible", "not checked"]
#: A coefficient as callers hold it (None: the term was not fitted).
Coefficient = float | int | np.floating[Any] | np.integer[Any] | None

N_UNIT = TERM_UNIT["N"]
B_UNIT = TERM_UNIT["B"]


@dataclass(frozen=True)
class UnitAlternative:
    """N and B as they would be if the input had been in another rate unit.

    Attributes
    ----------
    units : str
        The other rate unit.
    factor : float
        N and B are multiplied by this (deg/h factor of ``units`` over that of the unit the
        values were read in).
    N, B : float or None
        Rescaled values (None where the term was not fitted).
    plausible : bool
        Whether the rescaled pair lies in a grade.
    grades : tuple of str
        The grades holding it, closest to a grade's middle first.
    distance : float
        Distance to the middle of the first of ``grades`` (0 middle, 1 edge; NaN if none).
    """

    units: str
    factor: float
    N: float | None
    B: float | None
    plausible: bool
    grades: tuple[str, ...]
    distance: float

    @property
    def same_scale(self) -> bool:
        """True when this unit gives the same numbers (deg/h and arcsec/s)."""
        return math.isclose(self.factor, 1.0, rel_tol=1e-12)

    def to_dict(self) -> dict[str, Any]:
        return {"units": self.units, "factor": self.factor, "N": self.N, "B": self.B,
                "plausible": self.plausible, "grades": list(self.grades),
                "distance": _json_float(self.distance)}


@dataclass(frozen=True)
class PlausibilityReport:
    """Whether a fitted N and B fit a real gyro, and which rate unit would make them fit.

    Attributes
    ----------
    verdict : {"plausible", "implausible", "not checked"}
        ``"not checked"`` when neither N nor B is available (not fitted or zero).
    N, B : float or None
        The values judged, deg/sqrt(h) and deg/h as read in ``units``; None when not
        available (``N_status``/``B_status`` say why).
    N_status, B_status : str
        ``"used"``, ``"not fitted"`` (None given) or ``"zero"`` (fitted to zero).
    units : str
        The rate unit the recording was read in (canonical spelling).
    grades : tuple of str
        Keys of :data:`GYRO_GRADES` holding the values, closest to a grade's middle first.
    distance : float
        Distance of the values to the middle of the first grade (NaN if none).
    reason : str
        Why the verdict (which value lies outside which bound).
    alternatives : tuple of UnitAlternative
        The values rescaled to every other unit of :data:`fogts.units.RATE_UNITS`, in that
        order (empty when not checked).
    notes : tuple of str
        What the check was based on (a value missing or zero).
    """

    verdict: Verdict
    N: float | None
    B: float | None
    N_status: str
    B_status: str
    units: str
    grades: tuple[str, ...]
    distance: float
    reason: str
    alternatives: tuple[UnitAlternative, ...]
    notes: tuple[str, ...] = ()

    # ------------------------------------------------------------------ derived
    @property
    def judged_on(self) -> tuple[str, ...]:
        """The values the verdict rests on: ``("N", "B")``, ``("N",)``, ``("B",)`` or ()."""
        return tuple(n for n, v in (("N", self.N), ("B", self.B)) if v is not None)

    def _plausible_others(self) -> tuple[str, ...]:
        alts = sorted((a.distance, i, a.units) for i, a in enumerate(self.alternatives)
                      if a.plausible and not a.same_scale)
        return tuple(u for _, _, u in alts)

    @property
    def suggested_units(self) -> tuple[str, ...]:
        """When implausible: the units that would make the values plausible, best first
        (closest to the middle of a grade); else ()."""
        return self._plausible_others() if self.verdict == "implausible" else ()

    @property
    def also_plausible_units(self) -> tuple[str, ...]:
        """When plausible: other units (with other numbers) that would be plausible too,
        best first; else ()."""
        return self._plausible_others() if self.verdict == "plausible" else ()

    @property
    def ambiguous(self) -> bool:
        """Plausible, but plausible in another rate unit too: N and B cannot confirm the
        unit (worth saying when the unit was assumed rather than read from the file)."""
        return bool(self.also_plausible_units)

    def alternative(self, units: str) -> UnitAlternative:
        """The values rescaled to ``units`` (any spelling :func:`parse_rate_unit` accepts)."""
        key = parse_rate_unit(units, "units")
        for alt in self.alternatives:
            if alt.units == key:
                return alt
        others = ", ".join(a.units for a in self.alternatives) or "none (not checked)"
        raise DataError(f"units must be a unit other than the one the values were read in "
                        f"({self.units}); alternatives are: {others}; got {units!r}")

    @property
    def message(self) -> str:
        """One line for a CLI to print after ``"warning: "`` (meant for the implausible
        and ambiguous cases, but defined for every verdict)."""
        read = f"(input read as {self.units}{_judged_note(self)})"
        they, them = ("it", "it") if len(self.judged_on) == 1 else ("they", "them")
        if self.verdict == "not checked":
            return f"the unit plausibility was not checked: {self.reason} {read}"
        if self.verdict == "plausible":
            verb = "is" if len(self.judged_on) == 1 else "are"
            text = (f"{_values_text(self.N, self.B)} {read} {verb} typical of "
                    f"{_grades_phrase(self.grades)}")
            if self.ambiguous:
                text += f"; {they} would also be plausible if the input was " + "; or ".join(
                    _alt_text(group) for group in self._groups(self.also_plausible_units))
            return text
        text = f"{self.reason} {read}"
        if self.suggested_units:
            text += "; if the input was " + "; if ".join(
                _alt_text(group) for group in self._groups(self.suggested_units))
        else:
            text += ("; no other rate unit (" + ", ".join(a.units for a in self.alternatives)
                     + f") makes {them} plausible: check the recording's scale factor")
        return text + "; set the rate unit explicitly (units=)"

    def _groups(self, units: tuple[str, ...]) -> list[list[UnitAlternative]]:
        """``units`` grouped by scale factor (deg/h and arcsec/s give the same numbers)."""
        groups: list[list[UnitAlternative]] = []
        for alt in (self.alternative(u) for u in units):
            for group in groups:
                if math.isclose(group[0].factor, alt.factor, rel_tol=1e-12):
                    group.append(alt)
                    break
            else:
                groups.append([alt])
        return groups

    # ------------------------------------------------------------------ exports
    def to_dict(self) -> dict[str, Any]:
        """JSON-safe dict with stable keys (NaN becomes None)."""
        return {
            "verdict": self.verdict,
            "units": self.units,
            "N": {"value": self.N, "unit": N_UNIT, "status": self.N_status},
            "B": {"value": self.B, "unit": B_UNIT, "status": self.B_status},
            "judged_on": list(self.judged_on),
            "grades": list(self.grades),
            "distance": _json_float(self.distance),
            "reason": self.reason,
            "message": self.message,
            "suggested_units": list(self.suggested_units),
            "also_plausible_units": list(self.also_plausible_units),
            "alternatives": [a.to_dict() for a in self.alternatives],
            "envelope": {"N": list(N_ENVELOPE), "B": list(B_ENVELOPE)},
            "notes": list(self.notes),
        }

    def to_frame(self) -> pd.DataFrame:
        """One row per rate unit: the unit read first, then the alternatives."""
        rows = [{"units": self.units, "role": "as read", "factor": 1.0, "N": self.N,
                 "B": self.B, "plausible": self.verdict == "plausible",
                 "grades": ", ".join(self.grades), "distance": self.distance}]
        for a in self.alternatives:
            role = ("suggested" if a.units in self.suggested_units else
                    "also plausible" if a.units in self.also_plausible_units else
                    "same numbers" if a.same_scale else "alternative")
            rows.append({"units": a.units, "role": role, "factor": a.factor, "N": a.N,
                         "B": a.B, "plausible": a.plausible, "grades": ", ".join(a.grades),
                         "distance": a.distance})
        frame = pd.DataFrame(rows).set_index("units")
        return frame.astype({"N": np.float64, "B": np.float64})

    def summary(self) -> str:
        lines = [f"unit plausibility: {self.verdict} (N, B read as {self.units}; "
                 f"envelope N {N_ENVELOPE[0]:g}..{N_ENVELOPE[1]:g} {N_UNIT}, "
                 f"B {B_ENVELOPE[0]:g}..{B_ENVELOPE[1]:g} {B_UNIT})",
                 f"  {self.reason}"]
        if self.verdict == "not checked":
            return "\n".join(lines)
        lines.append(f"  {'units':<9}{'N':>11}  {'B':>11}  verdict")
        rows = [(self.units, self.N, self.B, self.verdict == "plausible", self.grades, "")]
        rows += [(a.units, a.N, a.B, a.plausible, a.grades,
                  " (same numbers)" if a.same_scale else "") for a in self.alternatives]
        for units, n, b, ok, grades, extra in rows:
            verdict = ("plausible: " + ", ".join(grades)) if ok else "implausible"
            lines.append(f"  {units:<9}{_fmt_opt(n):>11}  {_fmt_opt(b):>11}  {verdict}{extra}")
        if self.suggested_units:
            lines.append("  suggested units, best first: " + ", ".join(self.suggested_units))
        if self.also_plausible_units:
            lines.append("  also plausible in: " + ", ".join(self.also_plausible_units)
                         + " (N and B cannot confirm the unit)")
        lines += [f"  note: {n}" for n in self.notes]
        return "\n".join(lines)


# --------------------------------------------------------------------------- helpers


def _json_float(x: float) -> float | None:
    return x if math.isfinite(x) else None


def _fmt(x: float) -> str:
    return f"{x:.3g}"


def _fmt_opt(x: float | None) -> str:
    return "-" if x is None else f"{x:.4g}"


def _a(label: str) -> str:
    return ("an " if label[0].lower() in "aeiou" else "a ") + label


def _values_text(N: float | None, B: float | None) -> str:
    parts = []
    if N is not None:
        parts.append(f"N = {_fmt(N)} {N_UNIT}")
    if B is not None:
        parts.append(f"B = {_fmt(B)} {B_UNIT}")
    return " and ".join(parts)


def _grades_phrase(keys: tuple[str, ...]) -> str:
    return " or ".join(_a(GRADE_BY_KEY[k].label) for k in keys)


def _alt_text(group: list[UnitAlternative]) -> str:
    alt = group[0]
    values = ", ".join(f"{n} = {_fmt(v)} {u}" for n, v, u in
                       (("N", alt.N, N_UNIT), ("B", alt.B, B_UNIT)) if v is not None)
    names = " or ".join(a.units for a in group)
    return f"{names}: {values}, typical of {_grades_phrase(alt.grades)}"


def _judged_note(report: PlausibilityReport) -> str:
    missing = [(n, s) for n, s in (("N", report.N_status), ("B", report.B_status))
               if s != "used"]
    if not missing or not report.judged_on:
        return ""
    name, status = missing[0]
    why = "not fitted" if status == "not fitted" else "fitted to zero"
    return f"; {name} {why}, judged on {report.judged_on[0]} alone"


def _check_value(name: str, value: Any) -> tuple[float | None, str]:
    """(value or None, status) for one coefficient; None and 0 mean 'not available'."""
    if value is None:
        return None, "not fitted"
    if isinstance(value, bool) or not isinstance(value, int | float | np.integer | np.floating):
        raise DataError(f"{name} must be a number >= 0 or None, got {value!r}")
    v = float(value)
    if not math.isfinite(v) or v < 0:
        raise DataError(f"{name} must be a finite number >= 0 ({TERM_UNIT[name]}) or None, "
                        f"got {value!r}; pass None for a term that was not fitted, 0 for one "
                        "fitted to zero")
    if v == 0.0:
        return None, "zero"
    return v, "used"


def _side(value: float, bounds: tuple[float, float]) -> int:
    return -1 if value < bounds[0] else 1 if value > bounds[1] else 0


#: For values below (-1) and above (+1) the envelope: the word, the bound's comparison and
#: index, and the grade that stays inside.
_BEYOND = {-1: ("below", ">=", 0, "even strategic-grade FOG and RLG"),
           1: ("above", "<=", 1, "even consumer MEMS")}


def _reason(N: float | None, B: float | None) -> str:
    """Why (N, B) is in no grade."""
    parts = [text for text in (_beyond_text(N, B, side) for side in (-1, 1)) if text]
    if parts:
        return "; ".join(parts)
    # both inside the envelope, but no grade holds both
    assert N is not None and B is not None
    n_grades = [g.key for g in GYRO_GRADES if g.contains(N, None)]
    b_grades = [g.key for g in GYRO_GRADES if g.contains(None, B)]
    return (f"N = {_fmt(N)} {N_UNIT} (a {'/'.join(n_grades)}-grade value) and "
            f"B = {_fmt(B)} {B_UNIT} (a {'/'.join(b_grades)}-grade value) fit no single "
            "gyro grade")


def _beyond_text(N: float | None, B: float | None, side: int) -> str:
    """The values on one ``side`` of the envelope and the bound they cross ("" if none)."""
    out = [(n, v, b) for n, v, b in (("N", N, N_ENVELOPE), ("B", B, B_ENVELOPE))
           if v is not None and _side(v, b) == side]
    if not out:
        return ""
    word, op, end, inside = _BEYOND[side]
    values = " and ".join(f"{n} = {_fmt(v)} {TERM_UNIT[n]}" for n, v, _ in out)
    limits = ", ".join(f"{n} {op} {b[end]:g} {TERM_UNIT[n]}" for n, _, b in out)
    verb = "is" if len(out) == 1 else "are"
    return f"{values} {verb} {word} any real gyro ({inside} stay at {limits})"


# --------------------------------------------------------------------------- entry point


# Long only by its numpydoc docstring (parameters, notes, examples).
def check_plausibility(N: Coefficient, B: Coefficient, *, units: str) -> PlausibilityReport:
    """Compare a fitted N and B with the range real gyros span; suggest the rate unit.

    Parameters
    ----------
    N : float or None
        Angle random walk in deg/sqrt(h), as :func:`fogts.allan.noise.fit_noise` reports it
        (IEEE Std 952-1997 Annex C: N = C_-1/60 with the rate in deg/h).  None when the term
        was not fitted, 0 when it was fitted to zero: the check then rests on B alone.
    B : float or None
        Bias instability in deg/h (B = C_0 / :data:`~fogts.allan.terms.B_PLATEAU`), same
        conventions.
    units : str
        The rate unit the recording was read in (``deg/h``, ``deg/s``, ``rad/s``,
        ``arcsec/s`` or an alias :func:`fogts.units.parse_rate_unit` accepts).

    Returns
    -------
    PlausibilityReport
        ``verdict`` "plausible" if one grade of :data:`GYRO_GRADES` holds the values,
        "implausible" if none does, "not checked" if neither value is available; the
        values rescaled to every other rate unit, and ``suggested_units``.

    Raises
    ------
    DataError
        If N or B is negative, NaN, infinite or not a number, or ``units`` is unknown.

    Notes
    -----
    A change of rate unit from ``units`` to ``u`` multiplies N and B by
    ``to_deg_per_hour_factor(u) / to_deg_per_hour_factor(units)``.  Suggested units are
    those whose rescaled values lie in a grade, ordered by the distance to the middle of
    that grade in log space (RMS over N and B of the offset in units of the grade's
    half-width).  The grade table and its sources are in :mod:`fogts.allan.gyro_grades`.

    Examples
    --------
    An XSens gyro recorded in rad/s but read as deg/h (``cont_imu1_gyro_x.npz``):

    >>> r = check_plausibility(1.089e-5, 5.031e-5, units="deg/h")
    >>> r.verdict, r.suggested_units
    ('implausible', ('deg/s', 'rad/s'))
    >>> round(r.alternative("rad/s").N, 3), r.alternative("rad/s").grades
    (2.246, ('industrial', 'consumer'))

    The ADIS16405 read in its true unit, deg/s:

    >>> r = check_plausibility(2.31, 33.7, units="deg/s")
    >>> r.verdict, r.grades
    ('plausible', ('consumer', 'industrial'))
    """
    unit = parse_rate_unit(units, "units")
    n, n_status = _check_value("N", N)
    b, b_status = _check_value("B", B)
    statuses = {"not fitted": "was not fitted", "zero": "was fitted to zero"}
    notes = tuple(f"{name} {statuses[s]}; judged on {other} alone"
                  for name, s, other, v in (("N", n_status, "B", b), ("B", b_status, "N", n))
                  if s != "used" and v is not None)
    if n is None and b is None:
        reason = (f"N {statuses[n_status]} and B {statuses[b_status]}, so there is nothing "
                  "to compare with real gyros")
        return PlausibilityReport(
            verdict="not checked", N=None, B=None, N_status=n_status, B_status=b_status,
            units=unit, grades=(), distance=math.nan, reason=reason, alternatives=(),
            notes=notes)

    grades, distance = grades_of(n, b)
    if grades:
        verdict: Verdict = "plausible"
        verb = "lies" if n is None or b is None else "lie"
        reason = (f"{_values_text(n, b)} {verb} in the range of: "
                  + ", ".join(GRADE_BY_KEY[k].label for k in grades))
    else:
        verdict = "implausible"
        reason = _reason(n, b)

    base = to_deg_per_hour_factor(unit)
    alternatives = []
    for other in RATE_UNITS:
        if other == unit:
            continue
        factor = to_deg_per_hour_factor(other) / base
        an = None if n is None else n * factor
        bn = None if b is None else b * factor
        alt_grades, alt_distance = grades_of(an, bn)
        alternatives.append(UnitAlternative(
            units=other, factor=factor, N=an, B=bn, plausible=bool(alt_grades),
            grades=alt_grades, distance=alt_distance))
    return PlausibilityReport(
        verdict=verdict, N=n, B=b, N_status=n_status, B_status=b_status, units=unit,
        grades=grades, distance=distance, reason=reason, alternatives=tuple(alternatives),
        notes=notes)
