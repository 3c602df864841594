"""A simulated static gyro record from IEEE-952 noise coefficients: :func:`simulate_gyro`.

The coefficients (:class:`fogts.simulate.noise_spec.NoiseSpec`, in the units
:mod:`fogts.allan.noise` reports, DESIGN.md "Definitions") become a rate record whose Allan
variance follows the closed forms of IEEE Std 952-1997, Annex C, Table C.1.  With the rate
``y`` in deg/h and tau in s, and every sample being the *average* rate over its sample
interval (which is what an integrating gyro's output is, and what the phase-based Allan
estimators assume):

==========================  ===================================  ==========================
term (unit)                 synthesis                            sigma^2(tau)
==========================  ===================================  ==========================
Q, quantization             white angle noise, differenced       3 Q^2 / tau^2
(arcsec = (deg/h) s)
N, angle random walk        white rate noise                     N'^2 / tau
(deg/sqrt(h))
B, bias instability         flicker: sum of Markov processes     (2 ln 2 / pi) B^2
(deg/h)                     (default) or Kasdin-Walter
K, rate random walk         continuous random walk, interval     K'^2 tau / 3
(deg/h^1.5)                 averages (exact)
R, rate ramp (deg/h^2)      deterministic ramp                   R'^2 tau^2 / 2
Markov (q_c, T_c)           exact discretisation of the          (q_c T_c)^2/tau [1 - T_c/(2 tau)
                            interval-averaged Gauss-Markov        (3 - 4 e^{-tau/T_c} + e^{-2tau/T_c})]
sinusoid (Omega_0, f_0)     exact interval averages              Omega_0^2 sin^4(pi f_0 tau)/(pi f_0 tau)^2
==========================  ===================================  ==========================

where N' = 60 N (deg/h sqrt(s)), K' = K / 60 (deg/h / sqrt(s)) and R' = R / 3600 (deg/h/s)
are the coefficients in deg/h and seconds (:data:`fogts.allan.terms.TO_SECONDS`).  The
term streams are in :mod:`fogts.simulate.streams`: every synthesis except Kasdin-Walter
flicker is exact in discrete time and runs in chunks, so memory beyond the output array is
bounded by the chunk size.
"""

from __future__ import annotations

from collections.abc import Iterable, Mapping, Sequence
from dataclasses import fields
from typing import Any

import numpy as np

from fogts._typing import FloatArray, RngLike
from fogts._validate import as_rng, check_choice, check_int, check_positive
from fogts.arma.spec import ArmaSpec
from fogts.errors import DataError
from fogts.io.run import Run, SamplingReport
from fogts.simulate.noise_spec import SPEC_UNIT, NoiseSpec
from fogts.simulate.streams import DEFAULT_CHUNK, FLICKER_METHODS, FlickerMethod, axis_streams
from fogts.simulate.temperature import temperature_series, thermal_drift_of
from fogts.units import parse_duration, parse_rate_unit, to_deg_per_hour_factor

__all__ = ["simulate_gyro"]


def simulate_gyro(
    noise: Any,
    *,
    fs_hz: float,
    duration_s: float | str,
    rng: RngLike = None,
    units: str = "deg/h",
    n_axes: int | None = None,
    arma: Any = None,
    temperature: Any = None,
    thermal_coefficients: Mapping[str, float] | None = None,
    flicker: FlickerMethod = "markov",
    chunk_size: int = DEFAULT_CHUNK,
) -> Run:
    """Simulate a static gyro record from IEEE-952 noise coefficients.

    Parameters
    ----------
    noise : NoiseSpec, mapping, NoiseModel, or a sequence of these (one per axis)
        Coefficients in the units ``fit_noise`` reports (see :class:`NoiseSpec`).
    fs_hz : float
        Sample rate in Hz.
    duration_s : float or str
        Record length in seconds, or a duration string (``"3h"``, ``"90min"``).
    rng : Generator, int or None
        Random source (fixed seed -> byte-identical output); every axis and every term
        draws from its own stream, so toggling one term leaves the others unchanged.
    units : str
        Unit of the output rate (deg/h, deg/s, rad/s, arcsec/s); coefficients stay in
        deg/h-based units.
    n_axes : int, optional
        Number of independent axes with the same coefficients (default 1, or the length
        of a sequence ``noise``).  Axes are named ``rate`` (one axis) or ``rate_x``,
        ``rate_y``, ``rate_z`` (``rate_1``... beyond three).
    arma : optional
        An ARMA model (anything :meth:`ArmaSpec.from_any` accepts, e.g. ``Selection.best``)
        whose output, in deg/h at ``fs_hz``, is added to every axis.
    temperature : TemperatureProfile, str, array_like or callable, optional
        Temperature in degC: a profile (or its string form, e.g. ``"warmup:20,30,20min"``),
        an array of one value per sample, or ``f(time_s) -> array``.  It is stored on the
        Run; with ``thermal_coefficients`` it also drives a drift.
    thermal_coefficients : mapping, optional
        Coefficients of D = a T dT + b T^2 + c T + d dT^2 + e dT + f (keys
        :data:`fogts.startup.thermal_model.THERMAL_TERMS`, deg/h per unit of the regressor); see
        :func:`fogts.simulate.temperature.thermal_drift`.
    flicker : {"markov", "kasdin"}
        Flicker (B): a sum of Markov processes (exact, chunked) or Kasdin-Walter fractional
        integration (whole record in memory); see :mod:`fogts.simulate.streams`.
    chunk_size : int
        Samples generated at a time (changes the output only by rounding: the random draws
        are the same).

    Returns
    -------
    Run
        ``rate`` of shape (n,) or (n, n_axes), ``time = arange(n) / fs_hz``, and
        ``temperature`` if one was given.  ``comments`` records the coefficients.

    Examples
    --------
    >>> run = simulate_gyro({"N": 0.01, "B": 0.02}, fs_hz=10, duration_s="10min", rng=1)
    >>> run.n, run.axes, run.units
    (6000, ('rate',), 'deg/h')
    """
    fs, duration, n = _record_length(fs_hz, duration_s)
    unit = parse_rate_unit(units)
    flicker = check_choice("flicker", flicker, FLICKER_METHODS)  # type: ignore[assignment]
    chunk = check_int("chunk_size", chunk_size, minimum=1)
    specs = _axis_specs(noise, n_axes, fs)
    arma_spec = ArmaSpec.from_any(arma) if arma is not None else None
    time = np.arange(n, dtype=np.float64) / fs
    temp = temperature_series(temperature, time, duration)
    drift = thermal_drift_of(thermal_coefficients, temp, fs_hz=fs)
    axis_rngs = as_rng(rng).spawn(len(specs))
    rate = np.empty((n, len(specs)) if len(specs) > 1 else n, dtype=np.float64)
    scale = 1.0 / to_deg_per_hour_factor(unit)
    for j, (spec, g) in enumerate(zip(specs, axis_rngs, strict=True)):
        _fill_axis(rate if len(specs) == 1 else rate[:, j], spec, arma_spec, time, drift,
                   fs=fs, duration=duration, flicker=flicker, chunk=chunk, scale=scale, rng=g)
    return _as_run(rate, time, temp, specs, arma_spec, fs=fs, flicker=flicker, unit=unit)


def _record_length(fs_hz: float, duration_s: float | str) -> tuple[float, float, int]:
    """Sample rate, duration in s and number of samples (at least 2)."""
    fs = check_positive("fs_hz", fs_hz)
    duration = parse_duration(duration_s, "duration_s")
    n = round(duration * fs)
    if n < 2:
        raise DataError(f"duration_s * fs_hz must give at least 2 samples, got {n} "
                        f"(duration {duration:g} s at {fs:g} Hz)")
    return fs, duration, n


def _axis_specs(noise: Any, n_axes: int | None, fs: float) -> tuple[NoiseSpec, ...]:
    """One NoiseSpec per axis; every sinusoid below the Nyquist frequency."""
    specs = _specs(noise, n_axes)
    for spec in specs:
        if spec.Omega_0 > 0 and spec.f_0 >= fs / 2:
            raise DataError(f"sinusoid frequency f_0={spec.f_0:g} Hz must be below the Nyquist "
                            f"frequency {fs / 2:g} Hz")
    return specs


def _specs(noise: Any, n_axes: int | None) -> tuple[NoiseSpec, ...]:
    if isinstance(noise, Sequence) and not isinstance(noise, str | bytes):
        if len(noise) == 0:
            raise DataError("noise must hold at least one axis specification, got []")
        specs = tuple(NoiseSpec.from_any(s) for s in noise)
        if n_axes is not None and check_int("n_axes", n_axes, minimum=1) != len(specs):
            raise DataError(f"n_axes={n_axes} does not match the {len(specs)} noise "
                            "specifications given")
        return specs
    k = 1 if n_axes is None else check_int("n_axes", n_axes, minimum=1, maximum=64)
    return (NoiseSpec.from_any(noise),) * k


def _fill_axis(col: FloatArray, spec: NoiseSpec, arma: ArmaSpec | None, time: FloatArray,
               drift: FloatArray | None, *, fs: float, duration: float, flicker: str,
               chunk: int, scale: float, rng: np.random.Generator) -> None:
    """Write one axis into ``col``, chunk by chunk: bias + ramp + term streams + drift."""
    n = time.size
    streams = axis_streams(spec, arma, fs=fs, n=n, duration=duration, flicker=flicker, rng=rng)
    for i0 in range(0, n, chunk):
        i1 = min(n, i0 + chunk)
        acc = np.full(i1 - i0, spec.bias)
        if spec.R != 0.0:
            acc += spec.internal("R") * (time[i0:i1] + 0.5 / fs)
        for stream in streams:
            acc += stream.next(i0, i1 - i0)
        if drift is not None:
            acc += drift[i0:i1]
        col[i0:i1] = acc * scale if scale != 1.0 else acc


def _axis_names(k: int) -> tuple[str, ...]:
    """``rate`` for one axis, ``rate_x``.. for up to three, ``rate_1``.. beyond."""
    if k == 1:
        return ("rate",)
    if k <= 3:
        return tuple(f"rate_{c}" for c in ("x", "y", "z")[:k])
    return tuple(f"rate_{i + 1}" for i in range(k))


def _as_run(rate: FloatArray, time: FloatArray, temp: FloatArray | None,
            specs: tuple[NoiseSpec, ...], arma: ArmaSpec | None, *, fs: float, flicker: str,
            unit: str) -> Run:
    """The simulated record as a regularly sampled Run, its coefficients in ``comments``."""
    axes = _axis_names(len(specs))
    columns = ("time", *axes) + (("temperature",) if temp is not None else ())
    comments = _describe(specs, arma, fs=fs, n=time.size, flicker=flicker, units=unit)
    sampling = SamplingReport(1.0 / fs, 0, 1.0 / fs, (), 0.0, 0.0, True, False, 1.0 / fs,
                              "given")
    return Run(rate=rate, time=time, fs_hz=fs, units=unit, axes=axes, temperature=temp,
               columns=columns, source="<simulate_gyro>", sampling=sampling,
               comments=comments)


def _describe(specs: Iterable[NoiseSpec], arma: ArmaSpec | None, *, fs: float, n: int,
              flicker: str, units: str) -> tuple[str, ...]:
    lines = [f"simulated by fogts.simulate_gyro: {n} samples at {fs:g} Hz, rate in {units}, "
             f"flicker={flicker}"]
    for i, spec in enumerate(specs):
        terms = ", ".join(f"{f.name}={getattr(spec, f.name):g} {SPEC_UNIT[f.name]}"
                          for f in fields(spec) if getattr(spec, f.name) != 0.0) or "no noise"
        lines.append(f"axis {i}: {terms}")
    if arma is not None:
        lines.append(f"arma: ar={list(arma.ar)}, ma={list(arma.ma)}, sigma2={arma.sigma2:g}")
    return tuple(lines)
