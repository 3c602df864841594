"""Temperature of a simulated record and the drift it drives.

:class:`TemperatureProfile` gives a smooth temperature history; :func:`thermal_drift`
turns a temperature series into the drift of the temperature model of
:mod:`fogts.startup.thermal_model`.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any, Literal

import numpy as np

from fogts._typing import FloatArray
from fogts._validate import check_choice, check_positive
from fogts.errors import DataError
from fogts.startup.thermal_model import THERMAL_TERMS, design_matrix, temperature_rate
from fogts.units import parse_duration

__all__ = ["TemperatureProfile", "temperature_series", "thermal_drift", "thermal_drift_of"]


@dataclass(frozen=True)
class TemperatureProfile:
    """A smooth temperature history in degC.

    Kinds:

    * ``constant``: T = ``start_c``;
    * ``warmup``: first-order approach to a steady state (a powered-up FOG heating its
      enclosure), T = end - (end - start) exp(-t / tau); the rate of change peaks at t = 0
      with (end - start) / tau degC/s;
    * ``ramp``: linear from ``start_c`` to ``end_c`` over the record.

    Examples
    --------
    >>> p = TemperatureProfile.parse("warmup:20,30,20min")
    >>> round(float(p.evaluate(np.array([0.0, 1200.0]), duration_s=3600)[1]), 3)
    26.321
    """

    kind: Literal["constant", "warmup", "ramp"]
    start_c: float
    end_c: float = float("nan")
    time_constant_s: float = float("nan")

    def __post_init__(self) -> None:
        check_choice("temperature profile kind", self.kind, ("constant", "warmup", "ramp"))
        for name in ("start_c",) + (("end_c",) if self.kind != "constant" else ()):
            v = float(getattr(self, name))
            if not math.isfinite(v) or not -273.15 < v < 1000:
                raise DataError(f"temperature {name} must be a temperature in degC, got "
                                f"{getattr(self, name)!r}")
        if self.kind == "warmup":
            check_positive("temperature time constant", self.time_constant_s)

    @classmethod
    def parse(cls, text: str) -> TemperatureProfile:
        """``"constant:25"``, ``"warmup:START,END,TAU"`` (TAU a duration such as ``20min``)
        or ``"ramp:START,END"``."""
        kind, _, rest = str(text).partition(":")
        kind = kind.strip().lower()
        args = [a.strip() for a in rest.split(",") if a.strip()]
        usage = ("temperature profile must be 'constant:T', 'warmup:START,END,TAU' or "
                 f"'ramp:START,END' (degC; TAU like 20min); got {text!r}")
        expected = {"constant": 1, "const": 1, "warmup": 3, "ramp": 2}
        if kind not in expected or len(args) != expected[kind]:
            raise DataError(usage)
        try:
            nums = [float(a) for a in args[:2]]
        except ValueError:
            raise DataError(usage) from None
        if kind in ("constant", "const"):
            return cls("constant", nums[0])
        if kind == "ramp":
            return cls("ramp", nums[0], nums[1])
        return cls("warmup", nums[0], nums[1],
                   parse_duration(args[2], "temperature time constant"))

    def evaluate(self, time_s: FloatArray, *, duration_s: float) -> FloatArray:
        t = np.asarray(time_s, dtype=np.float64)
        if self.kind == "constant":
            return np.full(t.shape, self.start_c)
        if self.kind == "ramp":
            return self.start_c + (self.end_c - self.start_c) * t / duration_s
        return self.end_c - (self.end_c - self.start_c) * np.exp(-t / self.time_constant_s)

    def to_dict(self) -> dict[str, Any]:
        return {"kind": self.kind, "start_c": self.start_c, "end_c": self.end_c,
                "time_constant_s": self.time_constant_s}


def temperature_series(temperature: Any, time: FloatArray,
                       duration: float) -> FloatArray | None:
    """The temperature at every sample time, or None without a temperature.

    ``temperature`` is a :class:`TemperatureProfile`, its string form, an array of one
    value per sample, or a callable ``f(time_s) -> array``.
    """
    if temperature is None:
        return None
    if isinstance(temperature, str):
        temperature = TemperatureProfile.parse(temperature)
    if isinstance(temperature, TemperatureProfile):
        return temperature.evaluate(time, duration_s=duration)
    values = temperature(time) if callable(temperature) else temperature
    arr = np.asarray(values, dtype=np.float64)
    if arr.shape != time.shape:
        raise DataError(f"temperature must have one value per sample ({time.size}), got shape "
                        f"{arr.shape}")
    if not np.all(np.isfinite(arr)):
        raise DataError("temperature contains non-finite values")
    return np.ascontiguousarray(arr)


def thermal_drift(temperature: Any, coefficients: Mapping[str, float], *,
                  fs_hz: float) -> FloatArray:
    """Temperature-driven drift D = a T dT + b T^2 + c T + d dT^2 + e dT + f.

    The regressors are those of :func:`fogts.startup.thermal_model.design_matrix`; dT is the temperature
    rate of change in degC/s from ``numpy.gradient`` of the noiseless profile
    (:func:`fogts.startup.thermal_model.temperature_rate` with ``smoothing_s=None``).

    Parameters
    ----------
    temperature : array_like
        Temperature in degC, one value per sample (at least 5).
    coefficients : mapping
        Any of ``"T*dT"`` (a), ``"T2"`` (b), ``"T"`` (c), ``"dT2"`` (d), ``"dT"`` (e) and
        ``"1"`` (f), in deg/h per unit of the regressor.
    fs_hz : float
        Sample rate.

    Returns
    -------
    ndarray of float64
        Drift in deg/h.

    Examples
    --------
    >>> d = thermal_drift(np.linspace(20, 21, 11), {"T": 0.1, "dT": 10.0}, fs_hz=1.0)
    >>> round(float(d[0]), 6)   # 0.1 * 20 + 10 * 0.1
    3.0
    """
    unknown = set(coefficients) - set(THERMAL_TERMS)
    if unknown:
        raise DataError(f"thermal coefficient names must be among {', '.join(THERMAL_TERMS)}; "
                        f"got {sorted(unknown)}")
    names = list(coefficients)
    values = np.array([float(coefficients[k]) for k in names], dtype=np.float64)
    if not np.all(np.isfinite(values)):
        bad = names[int(np.argmax(~np.isfinite(values)))]
        raise DataError(f"thermal coefficient {bad!r} must be finite, got "
                        f"{coefficients[bad]!r}")
    dtemp = temperature_rate(temperature, fs_hz=fs_hz, smoothing_s=None)
    temp = np.asarray(temperature, dtype=np.float64)
    return np.asarray(design_matrix(temp, dtemp, names) @ values, dtype=np.float64)


def thermal_drift_of(thermal_coefficients: Any, temperature: FloatArray | None, *,
                     fs_hz: float) -> FloatArray | None:
    """The drift of ``thermal_coefficients`` over ``temperature`` (None without coefficients).

    Raises
    ------
    DataError
        The coefficients are not a mapping, or there is no temperature to drive them.
    """
    if thermal_coefficients is None:
        return None
    if not isinstance(thermal_coefficients, Mapping):
        raise DataError(f"thermal_coefficients must be a mapping such as {{'T': 0.01}}, "
                        f"got {thermal_coefficients!r}")
    if temperature is None:
        raise DataError("thermal_coefficients need a temperature profile (temperature=...)")
    return thermal_drift(temperature, thermal_coefficients, fs_hz=fs_hz)
