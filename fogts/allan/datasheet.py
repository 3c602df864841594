"""Datasheet limits of the IEEE-952 noise terms, and the PASS/FAIL of a fitted model against them.

A datasheet specification is a mapping (read from YAML by ``fogts allan --spec SPEC.yaml``)
of term names to upper limits, in one unit system::

    units: deg      # deg: N in deg/sqrt(h), B in deg/h, K in deg/h^1.5 (IEEE Std 952-1997);
                    # si: rad/s/sqrt(Hz), rad/s, rad/s^2/sqrt(Hz) (fogts.units.TERM_SI_UNIT)
    N: 0.15
    B: 10
    K: 5

``units`` is optional (default ``deg``); at least one of N, B, K (:data:`SPEC_TERMS`) is
required, and every limit must be a finite number > 0.

A term passes when it is at or below its limit: a measured term by its fitted value, a term
that is only an upper limit (:attr:`fogts.allan.noise_model.NoiseTerm.is_limit`) by its
one-sided 95 % upper limit (:meth:`~fogts.allan.noise_model.NoiseModel.upper_limit`), so
that a term the data cannot measure passes only when even its largest plausible value is
within the datasheet.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

from fogts.choices import OUTPUT_UNITS
from fogts.errors import DataError
from fogts.units import TERM_SI_FACTOR, term_unit

if TYPE_CHECKING:
    from fogts.allan.noise_model import NoiseModel

__all__ = ["SPEC_TERMS", "NoiseSpec", "SpecCheck", "check_spec"]

#: The terms a specification may limit: those of the one-page summary
#: (:mod:`fogts.report.summary`) and of the ``fogts batch`` table.
SPEC_TERMS: tuple[str, ...] = ("N", "B", "K")


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
        What was compared: the fitted value, or the 95 % upper limit of a term that is only
        a limit (None: the term was not fitted).
    by_upper_limit : bool
        True when the term is only an upper limit and that limit was compared.
    passed : bool or None
        None when the term was not fitted (nothing to compare).
    """

    name: str
    limit_deg: float
    compared_deg: float | None
    by_upper_limit: bool
    passed: bool | None

    @property
    def verdict(self) -> str:
        """``"PASS"``, ``"FAIL"`` or ``"not fitted"``."""
        return "not fitted" if self.passed is None else ("PASS" if self.passed else "FAIL")

    def to_dict(self) -> dict[str, Any]:
        return {"term": self.name, "limit": self.limit_deg, "compared": self.compared_deg,
                "by_upper_limit": self.by_upper_limit, "verdict": self.verdict}


def check_spec(model: NoiseModel, spec: NoiseSpec) -> dict[str, SpecCheck]:
    """Each term of ``spec`` against ``model``: PASS when the fitted value (or, for a term
    that is only an upper limit, its one-sided 95 % upper limit) is at or below the limit.

    Examples
    --------
    >>> import numpy as np, fogts
    >>> white = np.random.default_rng(1).normal(size=20000)   # 1 deg/h rms at 10 Hz
    >>> model = fogts.fit_noise(fogts.allan_deviation(white, fs_hz=10.0), terms="N")
    >>> round(model["N"].value, 4)   # sqrt(1/10) / 60 = 0.0053 deg/sqrt(h)
    0.0052
    >>> check_spec(model, NoiseSpec.from_mapping({"N": 0.006}))["N"].verdict
    'PASS'
    >>> check_spec(model, NoiseSpec.from_mapping({"N": 0.005}))["N"].verdict
    'FAIL'
    """
    out = {}
    for name in spec.names:
        limit = spec.limit_deg(name)
        if name not in model.names:
            out[name] = SpecCheck(name, limit, None, False, None)
            continue
        term = model[name]
        compared = model.upper_limit(name) if term.is_limit else term.value
        out[name] = SpecCheck(name, limit, float(compared), term.is_limit,
                              bool(compared <= limit))
    return out
