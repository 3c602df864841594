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

Accelerometers obey the same Allan-variance model with the specific force (m/s^2) in place
of the rate (IEEE Std 1293-2018, the accelerometer counterpart of IEEE 952).
:data:`ACCEL_TERMS` is the same table with the accelerometer's names and engineering units
(:data:`fogts.units.ACCEL_TERM_UNIT`): ``C_n`` in m/s^2-and-seconds units, N = 60 C_-1 in
m/s/sqrt(h) (velocity random walk), B = C_0 / 0.664 / 9.80665e-6 in ug, K = 60^3 sqrt(3) C_1
in m/s/h^1.5 (acceleration random walk), R = 60^4 sqrt(2) C_2 in m/s/h^2, Q = C_-2/sqrt(3)
in m/s.  :func:`term_rows` picks the table of a quantity (``"rate"`` or ``"accel"``).
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import Any, Literal, get_args

import numpy as np

from fogts.errors import DataError
from fogts.units import ACCEL_TERM_UNIT, STANDARD_GRAVITY_MPS2, TERM_DEG_UNIT

__all__ = ["ACCEL_TERMS", "B_PLATEAU", "C_UNIT", "FLICKER_AVAR", "FLICKER_PLATEAU",
           "HVAR_FLICKER_RATIO", "MVAR_FLICKER_RATIO", "NOISE_TERMS", "TERMS", "TERM_DESCRIPTION",
           "TERM_FACTOR", "TERM_POWER", "TERM_SLOPE", "TERM_UNIT", "TO_SECONDS", "NoiseTermInfo",
           "TermName", "c_from_terms", "flicker_plateau", "from_seconds", "parse_terms",
           "term_items", "term_rows", "terms_from_c"]

TermName = Literal["Q", "N", "B", "K", "R"]
NOISE_TERMS: tuple[str, ...] = get_args(TermName)

#: Flicker floor of the Allan deviation per unit of B (IEEE 952 Annex C, rounded).
B_PLATEAU = 0.664
#: Flicker constant of the Allan variance, sigma^2 = FLICKER_AVAR B^2 (IEEE 952 Table C.1);
#: B_PLATEAU rounds its square root.
FLICKER_AVAR = 2.0 * math.log(2.0) / math.pi
#: Flicker-FM modified Allan variance over the Allan variance for many samples per tau
#: (NIST SP1065 sec. 5.2, modified Allan variance: its ratio R(n) to the Allan variance
#: tends to about 0.67 for flicker FM).  From the
#: transfer functions (SP1065 sec. 5.2), for S_y(f) = h_-1/f: AVAR = 2 h_-1 int sin^4 x/x^3
#: dx = 2 ln2 h_-1 and, for n -> inf, MVAR = 2 h_-1 int sin^6 x/x^5 dx
#: = (27/8 ln3 - 4 ln2) h_-1 = 0.9353 h_-1; the ratio is 0.6746.
MVAR_FLICKER_RATIO = (27.0 / 8.0 * math.log(3.0) - 4.0 * math.log(2.0)) / (2.0 * math.log(2.0))
#: Flicker-FM Hadamard variance over the Allan variance (SP1065 sec. 5.2, Hadamard variance; Riley,
#: "Handbook of Frequency Stability Analysis", Hadamard transfer function
#: 8/3 sin^6(x)/x^2): HVAR = 8/3 h_-1 int sin^6 x/x^3 dx = (4 ln2 - 3/2 ln3) h_-1
#: = 1.1247 h_-1; the ratio is 0.8113.
HVAR_FLICKER_RATIO = (4.0 * math.log(2.0) - 1.5 * math.log(3.0)) / (2.0 * math.log(2.0))
#: Flicker-FM (bias-instability) plateau of each estimator's deviation per unit of B:
#: ``floor = FLICKER_PLATEAU[kind] * B``.  adev, oadev and totdev share the Allan variance's
#: expectation (:data:`B_PLATEAU`; plain totdev is biased low by sqrt(1 - tau/(3 ln2 T)) for
#: flicker FM, Howe 1999, i.e. under 2.5 % at tau <= T/10); mdev and hdev/ohdev scale it by
#: the square roots of :data:`MVAR_FLICKER_RATIO` (its large-m limit: at m = 1 MVAR is
#: AVAR) and :data:`HVAR_FLICKER_RATIO`.  Checked by simulation in the tests.
FLICKER_PLATEAU: dict[str, float] = {
    "adev": B_PLATEAU, "oadev": B_PLATEAU, "totdev": B_PLATEAU,
    "mdev": B_PLATEAU * math.sqrt(MVAR_FLICKER_RATIO),
    "hdev": B_PLATEAU * math.sqrt(HVAR_FLICKER_RATIO),
    "ohdev": B_PLATEAU * math.sqrt(HVAR_FLICKER_RATIO),
}


def flicker_plateau(kind: str) -> float:
    """The flicker-FM plateau factor of estimator ``kind`` (:data:`FLICKER_PLATEAU`), NaN
    for a kind without an established constant.

    Examples
    --------
    >>> flicker_plateau("oadev"), round(flicker_plateau("mdev"), 4), flicker_plateau("x")
    (0.664, 0.5454, nan)
    """
    return FLICKER_PLATEAU.get(kind, math.nan)


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
    value_scale : float
        Further factor of the value after the hours conversion (1 but for an
        accelerometer's B: m/s^2 -> ug is 1 / 9.80665e-6).
    """

    name: str
    description: str
    power: int
    unit: str
    c_unit: str
    hour_power: int
    allan_root: float
    readoff_tau_s: float = math.nan
    value_scale: float = 1.0

    @property
    def slope(self) -> float:
        """Log-log slope of the term's Allan-deviation line (``power / 2``)."""
        return self.power / 2.0

    @property
    def seconds_factor(self) -> float:
        """Multiplies the value to give the coefficient in deg/h-and-seconds units."""
        hours = (_SQRT_S_PER_H ** -self.hour_power if self.hour_power <= 0
                 else 1.0 / _SQRT_S_PER_H ** self.hour_power)
        return hours if self.value_scale == 1.0 else hours / self.value_scale

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

#: The accelerometer's five terms (module docstring): the rows of :data:`TERMS` with the
#: specific force in m/s^2 as the rate, so the hours conversion differs (the coefficient is
#: in m/s^2 and seconds, the engineering unit per hour) and B is reported in ug.
ACCEL_TERMS: dict[str, NoiseTermInfo] = {t.name: t for t in (
    NoiseTermInfo("Q", "velocity quantization", -2, ACCEL_TERM_UNIT["Q"], "m/s^2*s", 0,
                  math.sqrt(3.0)),
    NoiseTermInfo("N", "velocity random walk", -1, ACCEL_TERM_UNIT["N"], "m/s^2*sqrt(s)", 1,
                  1.0, readoff_tau_s=1.0),
    NoiseTermInfo("B", "bias instability", 0, ACCEL_TERM_UNIT["B"], "m/s^2", 0, B_PLATEAU,
                  value_scale=1e6 / STANDARD_GRAVITY_MPS2),
    NoiseTermInfo("K", "acceleration random walk", 1, ACCEL_TERM_UNIT["K"], "m/s^2/sqrt(s)",
                  3, 1.0 / math.sqrt(3.0), readoff_tau_s=3.0),
    NoiseTermInfo("R", "acceleration ramp", 2, ACCEL_TERM_UNIT["R"], "m/s^2/s", 4,
                  1.0 / math.sqrt(2.0)),
)}


def term_rows(quantity: str = "rate") -> dict[str, NoiseTermInfo]:
    """The term table of a ``quantity``: :data:`TERMS` (``"rate"``, a gyro) or
    :data:`ACCEL_TERMS` (``"accel"``, an accelerometer).

    Examples
    --------
    >>> term_rows("accel")["N"].description, round(term_rows("accel")["N"].factor, 6)
    ('velocity random walk', 60.0)
    """
    if quantity == "rate":
        return TERMS
    if quantity == "accel":
        return ACCEL_TERMS
    raise DataError(f"quantity must be one of rate, accel; got {quantity!r}")


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


def from_seconds(name: str, coefficient: float, quantity: str = "rate") -> float:
    """A term's value from its coefficient in rate-and-seconds units (deg/h and s for a
    gyro, m/s^2 and s for an accelerometer).

    Examples
    --------
    >>> from_seconds("N", 0.6), from_seconds("K", 0.01)
    (0.01, 0.6)
    >>> from_seconds("N", 0.001, "accel")     # 1e-3 m/s/sqrt(s) = 0.06 m/s/sqrt(h)
    0.06
    """
    row = term_rows(quantity)[name]
    p = row.hour_power
    value = coefficient * _SQRT_S_PER_H ** p if p >= 0 else coefficient / _SQRT_S_PER_H ** -p
    return value if row.value_scale == 1.0 else value * row.value_scale


# --------------------------------------------------------------------------- conversions


def terms_from_c(c: Mapping[str | int, float], quantity: str = "rate") -> dict[str, float]:
    """Convert coefficients ``C_n`` (rate in deg/h, tau in s) to IEEE-952 terms.

    Parameters
    ----------
    c : mapping
        ``C_n`` keyed by the power ``n`` (-2..2) or by the term name (``"Q"`` .. ``"R"``).
    quantity : {"rate", "accel"}
        ``"accel"``: ``C_n`` in m/s^2 and seconds, terms in :data:`ACCEL_TERMS`' units.

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
    rows = term_rows(quantity)
    out = {name: rows[name].factor * v
           for name, v in _checked(c, lambda key: f"C coefficient {key!r}").items()}
    return {n: out[n] for n in NOISE_TERMS if n in out}


def c_from_terms(terms: Mapping[str, float], quantity: str = "rate") -> dict[int, float]:
    """Inverse of :func:`terms_from_c`: IEEE-952 terms to ``C_n`` keyed by the power n.

    Examples
    --------
    >>> round(c_from_terms({"N": 0.01})[-1], 6)
    0.6
    >>> round(c_from_terms({"B": 1.0}, "accel")[0] / 0.664, 11)   # 1 ug in m/s^2
    9.80665e-06
    """
    rows = term_rows(quantity)
    out = {TERM_POWER[name]: v / rows[name].factor
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


def term_items(terms: Sequence[str] | str, also: str = "") -> list[Any]:
    """The items of a term selection: a comma-separated string or a sequence (``also`` ends
    the error message, e.g. the optional terms a caller accepts besides)."""
    if isinstance(terms, str):
        return [t.strip() for t in terms.split(",") if t.strip()]
    try:
        return list(terms)
    except TypeError:
        raise DataError(f"terms must be a sequence of Q, N, B, K, R, got {terms!r}"
                        f"{also}") from None


def parse_terms(terms: Sequence[str] | str, also: str = "") -> tuple[str, ...]:
    """Validate a term selection; returns the names in the order Q, N, B, K, R (``also``
    ends the error messages).

    Examples
    --------
    >>> parse_terms("k, n")
    ('N', 'K')
    """
    items = term_items(terms, also)
    if not items:
        raise DataError(f"terms must name at least one of Q, N, B, K, R, got {terms!r}{also}")
    for t in items:
        if not isinstance(t, str) or t.strip().upper() not in TERM_POWER:
            raise DataError(f"terms must be drawn from Q, N, B, K, R; got {t!r}{also}")
    upper = [t.strip().upper() for t in items]
    if len(set(upper)) != len(upper):
        raise DataError(f"terms must not repeat a term, got {terms!r}")
    return tuple(n for n in NOISE_TERMS if n in upper)
