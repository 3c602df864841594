"""The IEEE-952 noise terms: the one table of names, powers, slopes, units and factors.

The Allan variance of a rate gyro with the five terms is (IEEE Std 952-1997, Annex C;
DESIGN.md "Definitions")

    sigma^2(tau) = 3 Q^2 / tau^2 + N^2 / tau + (2 ln 2 / pi) B^2 + K^2 tau / 3 + R^2 tau^2 / 2
                 = sum_n C_n^2 tau^n,   n = -2 .. 2,

with every coefficient in rate-and-seconds units.  ``C_n`` is the square root of the
coefficient of ``tau^n`` (rate in deg/h, tau in s); each term is
``value = C_n / (seconds_factor * allan_root)``, i.e. N = C_-1/60, B = C_0/0.664,
K = 60 sqrt(3) C_1, R = 3600 sqrt(2) C_2 and Q = C_-2/sqrt(3) (DESIGN.md).  B uses IEEE 952's
rounded plateau factor 0.664 (:data:`B_PLATEAU`) rather than sqrt(2 ln 2/pi) = 0.66428
(:data:`FLICKER_AVAR` is 2 ln 2/pi; 0.04 % apart); fitted curves are computed from the ``C_n``
and are exact.

The slope read-offs (IEEE 952 Annex C) read a term's own Allan-deviation line at the tau
where it equals the coefficient in deg/h-and-seconds units (:attr:`NoiseTermInfo.readoff_tau_s`:
1 s for N, 3 s for K) and convert it with :func:`from_seconds`; B is the plateau divided by
:data:`B_PLATEAU`.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import Any, Literal, get_args

import numpy as np

from fogts.errors import DataError
from fogts.units import TERM_DEG_UNIT

__all__ = ["B_PLATEAU", "C_UNIT", "FLICKER_AVAR", "NOISE_TERMS", "TERMS", "TERM_DESCRIPTION",
           "TERM_FACTOR", "TERM_POWER", "TERM_SLOPE", "TERM_UNIT", "TO_SECONDS", "NoiseTermInfo",
           "TermName", "c_from_terms", "from_seconds", "parse_terms", "terms_from_c"]

TermName = Literal["Q", "N", "B", "K", "R"]
NOISE_TERMS: tuple[str, ...] = get_args(TermName)

#: Flicker floor of the Allan deviation per unit of B (IEEE 952 Annex C, rounded).
B_PLATEAU = 0.664
#: Flicker constant of the Allan variance, sigma^2 = FLICKER_AVAR B^2 (IEEE 952 Table C.1);
#: B_PLATEAU rounds its square root.
FLICKER_AVAR = 2.0 * math.log(2.0) / math.pi
#: sqrt(seconds per hour): deg/sqrt(h) = 60 deg/h sqrt(s).
_SQRT_S_PER_H = 60.0


@dataclass(frozen=True)
class NoiseTermInfo:
    """One IEEE-952 term.

    A row of :data:`TERMS`; the per-term tables (:data:`TERM_UNIT`, :data:`TERM_FACTOR`, ...)
    are read from the rows.

    Attributes
    ----------
    name : str
        ``"Q"``, ``"N"``, ``"B"``, ``"K"`` or ``"R"``.
    description : str
        ``"quantization"``, ``"angle random walk"``, ...
    power : int
        Power of tau of its Allan-variance basis function.
    unit : str
        Engineering unit of the value (deg/h based).
    c_unit : str
        Unit of ``C_n`` (rate in deg/h, tau in s).
    hour_power : int
        value = (coefficient in deg/h-and-seconds units) x 60^hour_power: -1 for N
        (deg/sqrt(h) -> deg/h sqrt(s) is x 60), 1 for K, 2 for R, 0 for Q and B.
    allan_root : float
        Square root of the term's constant in sigma^2(tau): sqrt(3), 1, 0.664, 1/sqrt(3),
        1/sqrt(2).
    readoff_tau_s : float
        Tau (s) at which the term's own Allan-deviation line equals its coefficient in
        deg/h-and-seconds units (the IEEE 952 slope read-off); NaN for terms not read off
        that way.
    """

    name: str
    description: str
    power: int
    unit: str
    c_unit: str
    hour_power: int
    allan_root: float
    readoff_tau_s: float = math.nan

    @property
    def slope(self) -> float:
        """Log-log slope of the term's Allan-deviation line (``power / 2``)."""
        return self.power / 2.0

    @property
    def seconds_factor(self) -> float:
        """Multiplies the value to give the coefficient in deg/h-and-seconds units."""
        if self.hour_power <= 0:
            return _SQRT_S_PER_H ** -self.hour_power
        return 1.0 / _SQRT_S_PER_H ** self.hour_power

    @property
    def factor(self) -> float:
        """``value = factor * C_n``."""
        return 1.0 / (self.seconds_factor * self.allan_root)


#: The five terms in the order Q, N, B, K, R.
TERMS: dict[str, NoiseTermInfo] = {t.name: t for t in (
    NoiseTermInfo("Q", "quantization", -2, TERM_DEG_UNIT["Q"], "deg/h*s", 0, math.sqrt(3.0)),
    NoiseTermInfo("N", "angle random walk", -1, TERM_DEG_UNIT["N"], "deg/h*sqrt(s)", -1, 1.0,
                  readoff_tau_s=1.0),
    NoiseTermInfo("B", "bias instability", 0, TERM_DEG_UNIT["B"], "deg/h", 0, B_PLATEAU),
    NoiseTermInfo("K", "rate random walk", 1, TERM_DEG_UNIT["K"], "deg/h/sqrt(s)", 1,
                  1.0 / math.sqrt(3.0), readoff_tau_s=3.0),
    NoiseTermInfo("R", "rate ramp", 2, TERM_DEG_UNIT["R"], "deg/h/s", 2, 1.0 / math.sqrt(2.0)),
)}

#: Power of tau of each term's basis function in sigma^2(tau) = sum a_n tau^n.
TERM_POWER: dict[str, int] = {n: t.power for n, t in TERMS.items()}
#: Log-log slope of each term's Allan-deviation line (-1, -1/2, 0, 1/2, 1).
TERM_SLOPE: dict[str, float] = {n: t.slope for n, t in TERMS.items()}
#: term value (deg/h-based units) = factor * C_n (rate in deg/h, tau in s).
TERM_FACTOR: dict[str, float] = {n: t.factor for n, t in TERMS.items()}
#: Engineering unit of each term's value.
TERM_UNIT: dict[str, str] = {n: t.unit for n, t in TERMS.items()}
#: Unit of each ``C_n``.
C_UNIT: dict[str, str] = {n: t.c_unit for n, t in TERMS.items()}
#: Plain-words name of each term.
TERM_DESCRIPTION: dict[str, str] = {n: t.description for n, t in TERMS.items()}
#: Value -> deg/h-and-seconds coefficient, per term.
TO_SECONDS: dict[str, float] = {n: t.seconds_factor for n, t in TERMS.items()}


def from_seconds(name: str, coefficient: float) -> float:
    """A term's value from its coefficient in deg/h-and-seconds units.

    Examples
    --------
    >>> from_seconds("N", 0.6), from_seconds("K", 0.01)
    (0.01, 0.6)
    """
    p = TERMS[name].hour_power
    return coefficient * _SQRT_S_PER_H ** p if p >= 0 else coefficient / _SQRT_S_PER_H ** -p


# --------------------------------------------------------------------------- conversions


def terms_from_c(c: Mapping[str | int, float]) -> dict[str, float]:
    """Convert coefficients ``C_n`` (rate in deg/h, tau in s) to IEEE-952 terms.

    Parameters
    ----------
    c : mapping
        ``C_n`` keyed by the power ``n`` (-2..2) or by the term name (``"Q"`` .. ``"R"``).

    Returns
    -------
    dict
        Term name to value in the units of :data:`TERM_UNIT` (DESIGN.md "Definitions").

    Examples
    --------
    >>> t = terms_from_c({-2: 1.1754e-5, -1: 1.0228e-2, 0: 3.835e-3, 1: 1.196e-3, 2: 1.827e-4})
    >>> f"{t['B']:.3e} {t['K']:.4f} {t['Q']:.3e}"
    '5.776e-03 0.1243 6.786e-06'
    """
    out = {name: TERM_FACTOR[name] * v
           for name, v in _checked(c, lambda key: f"C coefficient {key!r}").items()}
    return {n: out[n] for n in NOISE_TERMS if n in out}


def c_from_terms(terms: Mapping[str, float]) -> dict[int, float]:
    """Inverse of :func:`terms_from_c`: IEEE-952 terms to ``C_n`` keyed by the power n.

    Examples
    --------
    >>> round(c_from_terms({"N": 0.01})[-1], 6)
    0.6
    """
    out = {TERM_POWER[name]: v / TERM_FACTOR[name]
           for name, v in _checked(terms, lambda key: f"term {key!r}").items()}
    return dict(sorted(out.items()))


def _checked(values: Mapping[Any, Any], label: Any) -> dict[str, float]:
    """Term name to value, every value a finite number >= 0 (``label(key)`` names it)."""
    out: dict[str, float] = {}
    for key, value in values.items():
        name = _term_key(key)
        v = float(value)
        if not math.isfinite(v) or v < 0:
            raise DataError(f"{label(key)} must be a finite number >= 0, got {value!r}")
        out[name] = v
    return out


def _term_key(key: str | int) -> str:
    if isinstance(key, str) and key in TERM_POWER:
        return key
    if isinstance(key, int | np.integer) and not isinstance(key, bool):
        for name, power in TERM_POWER.items():
            if power == int(key):
                return name
    raise DataError(f"coefficient key must be a term name (Q, N, B, K, R) or a power "
                    f"(-2, -1, 0, 1, 2), got {key!r}")


def parse_terms(terms: Sequence[str] | str) -> tuple[str, ...]:
    """Validate a term selection; returns the names in the order Q, N, B, K, R.

    Examples
    --------
    >>> parse_terms("k, n")
    ('N', 'K')
    """
    if isinstance(terms, str):
        items: list[Any] = [t.strip() for t in terms.split(",") if t.strip()]
    else:
        try:
            items = list(terms)
        except TypeError:
            raise DataError(f"terms must be a sequence of Q, N, B, K, R, got {terms!r}") from None
    if not items:
        raise DataError(f"terms must name at least one of Q, N, B, K, R, got {terms!r}")
    for t in items:
        if not isinstance(t, str) or t.strip().upper() not in TERM_POWER:
            raise DataError(f"terms must be drawn from Q, N, B, K, R; got {t!r}")
    upper = [t.strip().upper() for t in items]
    if len(set(upper)) != len(upper):
        raise DataError(f"terms must not repeat a term, got {terms!r}")
    return tuple(n for n in NOISE_TERMS if n in upper)
