"""Datasheet limits of the IEEE-952 noise terms, and the PASS/FAIL of a fitted model against them.

A datasheet specification is a mapping (read from YAML by ``fogts allan --spec SPEC.yaml``)
of term names to upper limits, in one unit system::

    units: deg      # deg: N in deg/sqrt(h), B in deg/h, K in deg/h^1.5 (IEEE Std 952-1997);
                    # si: rad/s/sqrt(Hz), rad/s, rad/s^2/sqrt(Hz) (fogts.units.TERM_SI_UNIT)
    N: 0.15
    B: 10
    K: 5

``units`` is optional (default ``deg``, with a warning naming the units assumed, as for a
rate column without a unit); at least one of N, B, K (:data:`SPEC_TERMS`) is
required, and every limit must be a finite number > 0.

The decision takes the estimate's uncertainty into account, as the conformity rules of
ISO 14253-1 and JCGM 106:2012 (sec. 8, guarded acceptance and rejection) do: with the
one-sided 95 % bounds of the term,

* **PASS** when the upper bound is at or below the limit (conformity shown);
* **FAIL** when the lower bound is above the limit (non-conformity shown);
* **INCONCLUSIVE** otherwise: the limit lies within the term's uncertainty.

For a measured term the bounds are those of ``a = C^2``, ``a -+ z se(a)`` with
``se(a) = 2 C se(C)`` (the delta method of :mod:`fogts.allan.noise_selection`) and
``z = 1.645``; a term that is only an upper limit (:attr:`fogts.allan.noise_model.NoiseTerm.
is_limit`) has the bounds 0 and its one-sided 95 % upper limit
(:meth:`~fogts.allan.noise_model.NoiseModel.upper_limit`), so it never FAILs: it passes
when even its largest plausible value is within the datasheet.  A measured term without a
standard error is judged by its value alone.
"""

from __future__ import annotations

import math
import warnings
from collections.abc import Mapping
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

from fogts.allan.distributions import norm_ppf
from fogts.choices import OUTPUT_UNITS
from fogts.errors import DataError, DataQualityWarning
from fogts.units import TERM_SI_FACTOR, term_unit

if TYPE_CHECKING:
    from fogts.allan.noise_model import NoiseModel

__all__ = ["SPEC_TERMS", "NoiseSpec", "SpecCheck", "check_spec"]

#: The terms a specification may limit: those of the one-page summary
#: (:mod:`fogts.report.summary`) and of the ``fogts batch`` table.
SPEC_TERMS: tuple[str, ...] = ("N", "B", "K")

#: Level of the one-sided bounds the decision uses (module docstring).
SPEC_LEVEL = 0.95


@dataclass(frozen=True)
class NoiseSpec:
    """Upper limits of noise terms from a datasheet.

    Attributes
    ----------
    limits : tuple of (str, float)
        Term name and limit in ``units``, in the order N, B, K.
    units : str
        ``"deg"`` or ``"si"`` (see the module docstring).
    source : str
        Where the specification came from (a file name), for messages.
    """

    limits: tuple[tuple[str, float], ...]
    units: str = "deg"
    source: str = "spec"

    @classmethod
    def from_mapping(cls, data: Any, source: str = "spec") -> NoiseSpec:
        """Check a parsed specification (a mapping of term names to limits, and an optional
        ``units``) and build the spec; :class:`~fogts.errors.DataError` names what is wrong.
        Without ``units`` the limits are read in degree units, with a
        :class:`~fogts.errors.DataQualityWarning` that names them and how to set the units.

        Examples
        --------
        >>> spec = NoiseSpec.from_mapping({"N": 0.15, "B": 10, "units": "deg"})
        >>> spec.limit_deg("N"), spec.names
        (0.15, ('N', 'B'))
        """
        if not isinstance(data, Mapping):
            raise DataError(f"{source} must be a mapping of noise terms to limits such as "
                            f"'N: 0.15', got {type(data).__name__}: {data!r}"[:300])
        units = data.get("units", "deg")
        if units not in OUTPUT_UNITS:
            raise DataError(f"{source}: units must be one of {', '.join(OUTPUT_UNITS)}; "
                            f"got {units!r}")
        unknown = [str(k) for k in data if k not in (*SPEC_TERMS, "units")]
        if unknown:
            raise DataError(f"{source}: unknown key(s) {', '.join(map(repr, unknown))}; "
                            f"allowed are {', '.join(SPEC_TERMS)} and units")
        limits = tuple((name, _limit(source, name, data[name]))
                       for name in SPEC_TERMS if name in data)
        if not limits:
            raise DataError(f"{source} gives no limit: give at least one of "
                            f"{', '.join(SPEC_TERMS)} (for example 'N: 0.15')")
        if "units" not in data:
            names = [name for name, _ in limits]
            warnings.warn(f"{source}: no units in the spec; assuming deg ("
                          + ", ".join(f"{n} in {term_unit(n, 'deg')}" for n in names)
                          + "); give 'units: deg' or 'units: si' ("
                          + ", ".join(f"{n} in {term_unit(n, 'si')}" for n in names) + ")",
                          DataQualityWarning, stacklevel=2)
        return cls(limits=limits, units=str(units), source=source)

    @property
    def names(self) -> tuple[str, ...]:
        return tuple(name for name, _ in self.limits)

    def limit(self, name: str) -> float:
        """The limit of term ``name`` in the spec's own units."""
        return dict(self.limits)[name]

    def limit_deg(self, name: str) -> float:
        """The limit of term ``name`` in fogts' degree units (:data:`fogts.units.TERM_DEG_UNIT`)."""
        value = self.limit(name)
        return value / TERM_SI_FACTOR[name] if self.units == "si" else value

    def to_dict(self) -> dict[str, Any]:
        return {"source": self.source, "units": self.units,
                "limits": {name: {"value": v, "unit": term_unit(name, self.units)}
                           for name, v in self.limits}}


def _limit(source: str, name: str, value: Any) -> float:
    """A limit as a float.  A string that reads as a number is accepted: YAML 1.1 (PyYAML)
    reads ``5e-5`` (no decimal point) as a string."""
    if isinstance(value, str):
        try:
            value = float(value)
        except ValueError:
            pass
    if isinstance(value, bool) or not isinstance(value, int | float):
        raise DataError(f"{source}: the limit of {name} must be a number, got {value!r}")
    v = float(value)
    if not (math.isfinite(v) and v > 0):
        raise DataError(f"{source}: the limit of {name} must be finite and > 0, got {value!r}")
    return v


@dataclass(frozen=True)
class SpecCheck:
    """One term against its datasheet limit.

    :func:`check_spec` makes one per term of the :class:`NoiseSpec`, fitted or not;
    ``to_dict`` writes ``name`` as ``"term"`` and adds the :attr:`verdict`.

    Attributes
    ----------
    name : str
        The term: ``"N"``, ``"B"`` or ``"K"`` (:data:`SPEC_TERMS`).
    limit_deg : float
        The limit in degree units.
    compared_deg : float or None
        The fitted value, or the 95 % upper limit of a term that is only a limit (None: the
        term was not fitted).
    by_upper_limit : bool
        True when the term is only an upper limit.
    passed : bool or None
        True: PASS, False: FAIL; None when the term was not fitted or the decision is
        inconclusive.
    bounds_deg : tuple of float or None
        The one-sided :data:`SPEC_LEVEL` lower and upper bounds that were compared.
    """

    name: str
    limit_deg: float
    compared_deg: float | None
    by_upper_limit: bool
    passed: bool | None
    bounds_deg: tuple[float, float] | None = None

    @property
    def verdict(self) -> str:
        """``"PASS"``, ``"FAIL"``, ``"INCONCLUSIVE"`` or ``"not fitted"``."""
        if self.passed is None:
            return "not fitted" if self.compared_deg is None else "INCONCLUSIVE"
        return "PASS" if self.passed else "FAIL"

    def to_dict(self) -> dict[str, Any]:
        return {"term": self.name, "limit": self.limit_deg, "compared": self.compared_deg,
                "by_upper_limit": self.by_upper_limit, "verdict": self.verdict,
                "bounds": None if self.bounds_deg is None else list(self.bounds_deg)}


def check_spec(model: NoiseModel, spec: NoiseSpec) -> dict[str, SpecCheck]:
    """Each term of ``spec`` against ``model``: PASS when the term's one-sided 95 % upper
    bound is at or below the limit, FAIL when its lower bound is above it, else
    INCONCLUSIVE (module docstring).

    Examples
    --------
    >>> import numpy as np, fogts
    >>> white = np.random.default_rng(1).normal(size=20000)   # 1 deg/h rms at 10 Hz
    >>> model = fogts.fit_noise(fogts.allan_deviation(white, fs_hz=10.0), terms="N")
    >>> round(model["N"].value, 4)   # sqrt(1/10) / 60 = 0.0053 deg/sqrt(h)
    0.0052
    >>> check_spec(model, NoiseSpec.from_mapping({"N": 0.006, "units": "deg"}))["N"].verdict
    'PASS'
    >>> check_spec(model, NoiseSpec.from_mapping({"N": 0.0052, "units": "deg"}))["N"].verdict
    'INCONCLUSIVE'
    >>> check_spec(model, NoiseSpec.from_mapping({"N": 0.005, "units": "deg"}))["N"].verdict
    'FAIL'
    """
    out = {}
    for name in spec.names:
        limit = spec.limit_deg(name)
        if name not in model.names:
            out[name] = SpecCheck(name, limit, None, False, None)
            continue
        term = model[name]
        compared = model.upper_limit(name, SPEC_LEVEL) if term.is_limit else term.value
        low, high = _bounds(model, name)
        passed = True if high <= limit else (False if low > limit else None)
        out[name] = SpecCheck(name, limit, float(compared), term.is_limit, passed, (low, high))
    return out


def _bounds(model: NoiseModel, name: str) -> tuple[float, float]:
    """The one-sided :data:`SPEC_LEVEL` lower and upper bounds of a term (module docstring)."""
    term = model[name]
    if term.is_limit:
        return 0.0, float(model.upper_limit(name, SPEC_LEVEL))
    if not (math.isfinite(term.stderr) and term.stderr > 0):
        return float(term.value), float(term.value)
    a, spread = term.value**2, 2.0 * float(norm_ppf(SPEC_LEVEL)) * term.value * term.stderr
    return math.sqrt(max(a - spread, 0.0)), math.sqrt(a + spread)
