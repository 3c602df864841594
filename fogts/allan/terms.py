"""The IEEE-952 noise terms: the one table of powers, unit factors, units and names.

The Allan variance of a rate gyro with the five terms is (IEEE Std 952-1997, Annex C;
DESIGN.md "Definitions")

    sigma^2(tau) = 3 Q^2 / tau^2 + N^2 / tau + (2 ln 2 / pi) B^2 + K^2 tau / 3 + R^2 tau^2 / 2

with every coefficient in rate-and-seconds units.  Writing ``C_n`` for the square root of
the fitted coefficient of ``tau^n`` (rate in deg/h, tau in s; the seed paper's notation),
each term is ``value = C_n / (seconds_factor * allan_root)``, which gives DESIGN.md's
N = C_-1/60, B = C_0/0.664, K = 60 sqrt(3) C_1, R = 3600 sqrt(2) C_2 and Q = C_-2/sqrt(3).
B uses IEEE 952's rounded 0.664 rather than sqrt(2 ln 2/pi) = 0.66428 (0.04 % apart).

Used by the fit (:mod:`fogts.allan.noise`), the simulator (:mod:`fogts.simulate.gyro`) and
the curve read-outs (:mod:`fogts.allan.readout`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Literal, get_args

__all__ = [
    "B_PLATEAU",
    "C_UNIT",
    "NOISE_TERMS",
    "TERMS",
    "TERM_DESCRIPTION",
    "TERM_FACTOR",
    "TERM_POWER",
    "TERM_UNIT",
    "TO_SECONDS",
    "NoiseTermInfo",
    "TermName",
]

TermName = Literal["Q", "N", "B", "K", "R"]
NOISE_TERMS: tuple[str, ...] = get_args(TermName)

#: Flicker floor of the Allan deviation per unit of B (IEEE 952 Annex C, rounded).
B_PLATEAU = 0.664


@dataclass(frozen=True)
class NoiseTermInfo:
    """One IEEE-952 term.

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
    seconds_factor : float
        Multiplies the value to give the coefficient in deg/h-and-seconds units
        (deg/sqrt(h) -> deg/h sqrt(s): x 60; deg/h^1.5 -> deg/h/sqrt(s): / 60; ...).
    allan_root : float
        Square root of the term's constant in sigma^2(tau): sqrt(3), 1, 0.664, 1/sqrt(3),
        1/sqrt(2).
    """

    name: str
    description: str
    power: int
    unit: str
    c_unit: str
    seconds_factor: float
    allan_root: float

    @property
    def factor(self) -> float:
        """``value = factor * C_n``."""
        return 1.0 / (self.seconds_factor * self.allan_root)


#: The five terms in the order Q, N, B, K, R.
TERMS: dict[str, NoiseTermInfo] = {t.name: t for t in (
    NoiseTermInfo("Q", "quantization", -2, "arcsec", "deg/h*s", 1.0, math.sqrt(3.0)),
    NoiseTermInfo("N", "angle random walk", -1, "deg/sqrt(h)", "deg/h*sqrt(s)", 60.0, 1.0),
    NoiseTermInfo("B", "bias instability", 0, "deg/h", "deg/h", 1.0, B_PLATEAU),
    NoiseTermInfo("K", "rate random walk", 1, "deg/h^1.5", "deg/h/sqrt(s)", 1.0 / 60.0,
                  1.0 / math.sqrt(3.0)),
    NoiseTermInfo("R", "rate ramp", 2, "deg/h^2", "deg/h/s", 1.0 / 3600.0,
                  1.0 / math.sqrt(2.0)),
)}

#: Power of tau of each term's basis function in sigma^2(tau) = sum a_n tau^n.
TERM_POWER: dict[str, int] = {n: t.power for n, t in TERMS.items()}
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
