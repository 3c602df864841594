"""The noise coefficients of a simulated gyro, :class:`NoiseSpec`, and their closed-form Allan variance.

The five IEEE-952 terms (Q, N, B, K, R) take their names, units and unit factors from the
one term table, :mod:`fogts.allan.terms`; a first-order Markov process (q_c, T_c), a
sinusoid (Omega_0, f_0) and a constant bias complete the specification.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, fields
from typing import Any

import numpy as np

from fogts._typing import FloatArray
from fogts.allan.markov import markov_avar, sinusoid_avar
from fogts.allan.terms import FLICKER_AVAR, NOISE_TERMS, TERM_DESCRIPTION, TERM_UNIT, TO_SECONDS
from fogts.errors import DataError
from fogts.units import parse_rate_unit, to_deg_per_hour_factor

__all__ = ["NoiseSpec", "markov_avar"]

#: Unit of every coefficient: the IEEE-952 terms from the term table, then the others.
SPEC_UNIT = {**TERM_UNIT, "q_c": "deg/h/sqrt(s)", "T_c": "s", "Omega_0": "deg/h",
             "f_0": "Hz", "bias": "deg/h"}
#: Plain-words name of every coefficient.
SPEC_DESCRIPTION = {**TERM_DESCRIPTION, "q_c": "Markov driving noise",
                    "T_c": "Markov correlation time", "Omega_0": "sinusoid amplitude",
                    "f_0": "sinusoid frequency", "bias": "constant bias"}
#: Other spellings accepted by :meth:`NoiseSpec.from_any` (lower case).
_ALIASES = {"markov_q": "q_c", "qc": "q_c", "markov_t": "T_c", "tc": "T_c",
            "omega0": "Omega_0", "omega_0": "Omega_0", "sine_amplitude": "Omega_0",
            "f0": "f_0", "sine_freq_hz": "f_0", "sine_frequency": "f_0"}
#: Coefficients that may be negative (signs of deterministic terms).
_SIGNED = ("R", "bias")


@dataclass(frozen=True)
class NoiseSpec:
    """Noise coefficients of a gyro, in the units :func:`fogts.allan.noise.fit_noise` reports.

    Attributes
    ----------
    Q : float
        Angle quantization noise in arcsec (= (deg/h) s).
    N : float
        Angle random walk in deg/sqrt(h).
    B : float
        Bias instability in deg/h (the Allan plateau is
        :data:`~fogts.allan.terms.B_PLATEAU` B).
    K : float
        Rate random walk in deg/h^1.5.
    R : float
        Rate ramp in deg/h^2 (may be negative: the sign of the deterministic ramp).
    q_c : float
        First-order Markov driving-noise amplitude in deg/h/sqrt(s); the process has the
        two-sided PSD (q_c T_c)^2 / (1 + (2 pi f T_c)^2) and the stationary standard
        deviation ``q_c sqrt(T_c / 2)`` (IEEE 952 Table C.1).
    T_c : float
        Markov correlation time in s (required when ``q_c > 0``).
    Omega_0 : float
        Sinusoid amplitude in deg/h.
    f_0 : float
        Sinusoid frequency in Hz (required when ``Omega_0 > 0``).
    bias : float
        Constant rate offset in deg/h (invisible to the Allan variance; e.g. Earth rate
        plus turn-on bias).

    Examples
    --------
    >>> spec = NoiseSpec(N=0.002, B=0.01, K=0.02)
    >>> spec.terms
    ('N', 'B', 'K')
    >>> round(float(spec.adev([1.0])[0]), 4)   # deg/h at tau = 1 s, dominated by 60 N
    0.1202
    """

    Q: float = 0.0
    N: float = 0.0
    B: float = 0.0
    K: float = 0.0
    R: float = 0.0
    q_c: float = 0.0
    T_c: float = 0.0
    Omega_0: float = 0.0
    f_0: float = 0.0
    bias: float = 0.0

    def __post_init__(self) -> None:
        for f in fields(self):
            value = getattr(self, f.name)
            try:
                v = float(value)
            except (TypeError, ValueError):
                raise DataError(f"noise term {f.name} must be a number, got {value!r}") from None
            if not math.isfinite(v):
                raise DataError(f"noise term {f.name} must be finite, got {value!r}")
            if v < 0 and f.name not in _SIGNED:
                raise DataError(f"noise term {f.name} ({SPEC_DESCRIPTION[f.name]}) must be "
                                f">= 0, got {value!r}")
            object.__setattr__(self, f.name, v)
        if self.q_c > 0 and self.T_c <= 0:
            raise DataError(f"a Markov term needs T_c > 0 (correlation time in s), got "
                            f"q_c={self.q_c!r}, T_c={self.T_c!r}")
        if self.Omega_0 > 0 and self.f_0 <= 0:
            raise DataError(f"a sinusoid needs f_0 > 0 (Hz), got Omega_0={self.Omega_0!r}, "
                            f"f_0={self.f_0!r}")

    # ---- construction
    @classmethod
    def from_any(cls, noise: Any) -> NoiseSpec:
        """Build a spec from a NoiseSpec, a mapping or a fitted noise model.

        Accepted: a :class:`NoiseSpec`; a mapping from term names (``Q N B K R q_c T_c
        Omega_0 f_0 bias``) to numbers, to ``{"value": ...}`` dicts (the ``noise`` block of
        ``fogts allan --json``) or to objects with a ``.value``; or any object (such as
        :class:`fogts.allan.noise.NoiseModel`) whose ``to_dict()`` gives such a mapping,
        possibly under a ``"terms"`` key, or that has the term names as attributes.
        A term whose value is None or NaN (not identified by a fit) is left out.
        """
        if isinstance(noise, NoiseSpec):
            return noise
        mapping = _term_mapping(noise)
        values: dict[str, float] = {}
        allowed = [f.name for f in fields(cls)]
        for key, raw in mapping.items():
            name = _canonical_term(str(key), allowed)
            value = _term_value(raw)
            if value is None:
                continue
            values[name] = value
            upper = _term_value(raw.get("upper_limit_95")) if isinstance(raw, Mapping) \
                else None  # None (JSON null) or NaN (Python): the term was measured
            if value > 0 and upper is not None:
                _say_not_measured(name, value, upper)
        return cls(**values)

    # ---- derived quantities
    @property
    def terms(self) -> tuple[str, ...]:
        """Names of the terms present (non-zero): a subset of Q N B K R markov sine bias."""
        out = [t for t in NOISE_TERMS if getattr(self, t) != 0.0]
        if self.q_c > 0:
            out.append("markov")
        if self.Omega_0 > 0:
            out.append("sine")
        if self.bias != 0.0:
            out.append("bias")
        return tuple(out)

    def internal(self, name: str) -> float:
        """Coefficient ``name`` (Q N B K R) converted to deg/h and seconds."""
        return float(getattr(self, name)) * TO_SECONDS[name]

    def avar(self, tau_s: Any, *, units: str = "deg/h") -> FloatArray:
        """Closed-form Allan variance at ``tau_s`` (IEEE Std 952-1997, Annex C, Table C.1).

        sigma^2 = 3Q^2/tau^2 + N'^2/tau + (2 ln2/pi) B^2 + K'^2 tau/3 + R'^2 tau^2/2
        + Markov (:func:`markov_avar`) + Omega_0^2 sin^4(pi f_0 tau)/(pi f_0 tau)^2, with the
        coefficients in deg/h and seconds (:meth:`internal`); in ``units``^2.  The flicker
        term is the IEEE asymptote (2 ln 2 / pi) B^2.
        """
        tau = np.asarray(tau_s, dtype=np.float64)
        if tau.size and (not np.all(np.isfinite(tau)) or np.any(tau <= 0)):
            raise DataError(f"tau_s must be finite and > 0, got {tau_s!r}")
        q, n_, b = self.internal("Q"), self.internal("N"), self.internal("B")
        k, r = self.internal("K"), self.internal("R")
        av = (3.0 * q * q / tau**2 + n_ * n_ / tau + FLICKER_AVAR * b * b
              + k * k * tau / 3.0 + r * r * tau**2 / 2.0)
        if self.q_c > 0:
            av = av + markov_avar(self.q_c, self.T_c, tau)
        if self.Omega_0 > 0:
            av = av + sinusoid_avar(self.Omega_0, self.f_0, tau).reshape(np.shape(av))
        scale = 1.0 / to_deg_per_hour_factor(parse_rate_unit(units))
        return np.asarray(av * scale * scale, dtype=np.float64)

    def adev(self, tau_s: Any, *, units: str = "deg/h") -> FloatArray:
        """Closed-form Allan deviation, ``sqrt(avar)``."""
        return np.sqrt(self.avar(tau_s, units=units))

    # ---- output
    def to_dict(self) -> dict[str, Any]:
        """``{name: {"value", "unit", "description"}}`` for every field (stable keys)."""
        return {f.name: {"value": getattr(self, f.name), "unit": SPEC_UNIT[f.name],
                         "description": SPEC_DESCRIPTION[f.name]} for f in fields(self)}

    def to_frame(self) -> Any:
        """One row per coefficient: term, value, unit, description."""
        import pandas as pd

        return pd.DataFrame([{"term": k, **v} for k, v in self.to_dict().items()])

    def summary(self) -> str:
        lines = ["Noise specification (IEEE Std 952-1997 units)"]
        for name, d in self.to_dict().items():
            if d["value"] != 0.0:
                lines.append(f"  {name:<8}{d['value']:>14.6g}  {d['unit']:<14}{d['description']}")
        if len(lines) == 1:
            lines.append("  (no noise terms: a noiseless record)")
        return "\n".join(lines)


def _term_mapping(noise: Any) -> Mapping[str, Any]:
    if isinstance(noise, Mapping):
        inner = noise.get("terms") if "terms" in noise else noise.get("noise")
        _say_which_axis(noise, inner)
        return inner if isinstance(inner, Mapping) else noise
    terms = getattr(noise, "terms", None)
    if isinstance(terms, Mapping):
        return terms
    to_dict = getattr(noise, "to_dict", None)
    if callable(to_dict):
        d = to_dict()
        if isinstance(d, Mapping):
            return _term_mapping(d)
    names = [f.name for f in fields(NoiseSpec)]
    found = {n: getattr(noise, n) for n in names if hasattr(noise, n)}
    if found:
        return found
    raise DataError(f"noise must be a NoiseSpec, a mapping of term names (Q, N, B, K, R, q_c, "
                    f"T_c, Omega_0, f_0, bias) to values, or a fitted NoiseModel; got "
                    f"{type(noise).__name__}")


def _say_which_axis(doc: Mapping[str, Any], inner: Any) -> None:
    """A ``fogts allan`` JSON of several axes carries the first axis' terms at its top
    level: say that those are the ones taken."""
    axes = doc.get("axes")
    if not (isinstance(inner, Mapping) and isinstance(axes, list) and len(axes) > 1):
        return
    import warnings

    from fogts.errors import DataQualityWarning

    names = [str(a.get("axis")) for a in axes if isinstance(a, Mapping)]
    warnings.warn(f"the noise terms are those of axis {names[0]!r}, the first of {len(names)} "
                  f"in the document ({', '.join(names)}); write one axis' JSON (fogts allan "
                  "--axis) to simulate another", DataQualityWarning, stacklevel=4)


#: How :meth:`NoiseSpec.from_any`'s warning about a term the fit did not measure begins,
#: followed by the term's name and " = ".
NOT_MEASURED_PREFIX = "the fit did not measure "


def _say_not_measured(name: str, value: float, upper: float) -> None:
    """A term a fit gave only as an upper limit (``upper_limit_95`` in its JSON) is taken at
    its fitted value: say so, since the data did not establish that value."""
    import warnings

    from fogts.errors import DataQualityWarning

    warnings.warn(f"{NOT_MEASURED_PREFIX}{name} = {value:.4g} (its 95 % upper limit is "
                  f"{upper:.4g}): the data only bound it, yet its fitted value is taken as the "
                  f"truth to simulate; give {name} explicitly to simulate another value",
                  DataQualityWarning, stacklevel=4)


def _canonical_term(key: str, allowed: Sequence[str]) -> str:
    if key in allowed:
        return key
    alias = _ALIASES.get(key.lower())
    if alias is not None:
        return alias
    upper = key.upper()
    if upper in NOISE_TERMS:
        return upper
    raise DataError(f"unknown noise term {key!r}; terms are: {', '.join(allowed)}")


def _term_value(raw: Any) -> float | None:
    if isinstance(raw, Mapping):
        raw = raw.get("value")
    elif hasattr(raw, "value") and not isinstance(raw, int | float | np.number):
        raw = raw.value
    if raw is None:
        return None
    try:
        v = float(raw)
    except (TypeError, ValueError):
        raise DataError(f"noise term values must be numbers, got {raw!r}") from None
    return None if math.isnan(v) else v
