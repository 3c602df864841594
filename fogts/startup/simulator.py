"""Cold-start simulation of a gyro: temperature warm-up, thermal drift and ARMA noise.

No public FOG start-up record with temperature exists, so the thermal compensation and the
north seeking of :mod:`fogts.startup` are tested and demonstrated on this physically shaped
model:

* **Temperature** rises from ``ambient_degC`` towards a steady state through two first-order
  lags in series (time constants τ₁ > τ₂: the heat source and the sensor-coil housing):

      T(t) = T_amb + A · [1 - (τ₁ e^{-t/τ₁} - τ₂ e^{-t/τ₂}) / (τ₁ - τ₂)]

  whose rate dT/dt = A (e^{-t/τ₁} - e^{-t/τ₂}) / (τ₁ - τ₂) is zero at switch-on and peaks at
  t* = τ₁τ₂ ln(τ₁/τ₂) / (τ₁ - τ₂).  A is chosen so the peak rate is ``peak_rate_degC_s``
  (0.05 °C/s by default, as in a published FOG cold start).
* **Drift** follows the thermal model D = a·T·ΔT + b·T² + c·T + d·ΔT² + e·ΔT + f with the
  given coefficients (T in °C, ΔT in °C/s, D in °/h).
* **Noise**: an ARMA(p, q) drift (statsmodels sign convention) plus white rate noise.
* **Earth rate**: a constant ``earth_rate_deg_h`` (the component the axis senses).

The temperature is quantized to ``temperature_resolution_degC`` like a real sensor.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np
import pandas as pd
from scipy.signal import lfilter

from fogts._typing import FloatArray, RngLike
from fogts._validate import as_rng, check_positive
from fogts.errors import DataError, InsufficientDataError
from fogts.io.run import Run, SamplingReport
from fogts.startup.thermal_model import THERMAL_TERMS, design_matrix

__all__ = ["DEFAULT_STARTUP_COEFFICIENTS", "StartupSimulation", "simulate_startup",
           "warmup_temperature"]

#: Default thermal-drift coefficients (°/h per term unit), chosen so that the start-up drift
#: dominates the noise for the first ~20 min, as in a published FOG cold-start record.
DEFAULT_STARTUP_COEFFICIENTS: dict[str, float] = {
    "T*dT": 0.4, "T2": 0.0015, "T": -0.12, "dT2": 120.0, "dT": 25.0, "1": 2.0}


def warmup_temperature(time_s: FloatArray, *, ambient_degC: float = 20.0,
                       peak_rate_degC_s: float = 0.05,
                       tau_s: tuple[float, float] = (400.0, 40.0)) -> tuple[FloatArray, FloatArray]:
    """Two-lag warm-up temperature and its exact rate (°C, °C/s) at ``time_s``.

    Examples
    --------
    >>> import numpy as np
    >>> T, dT = warmup_temperature(np.arange(0.0, 3600.0))
    >>> round(float(dT.max()), 4)
    0.05
    """
    tau1, tau2 = (check_positive("tau_s[0]", tau_s[0]), check_positive("tau_s[1]", tau_s[1]))
    if not tau1 > tau2:
        raise DataError(f"tau_s must be (slow, fast) with slow > fast, got {tau_s!r}")
    peak = check_positive("peak_rate_degC_s", peak_rate_degC_s)
    t_star = tau1 * tau2 * math.log(tau1 / tau2) / (tau1 - tau2)
    shape_peak = (math.exp(-t_star / tau1) - math.exp(-t_star / tau2)) / (tau1 - tau2)
    amp = peak / shape_peak
    t = np.asarray(time_s, dtype=np.float64)
    e1, e2 = np.exp(-t / tau1), np.exp(-t / tau2)
    temp = ambient_degC + amp * (1.0 - (tau1 * e1 - tau2 * e2) / (tau1 - tau2))
    rate = amp * (e1 - e2) / (tau1 - tau2)
    return temp, rate


@dataclass(frozen=True)
class StartupSimulation:
    """A simulated cold start and its ground truth.

    Attributes
    ----------
    run : Run
        Rate in °/h (axis ``"gyro"``) and the quantized temperature.
    drift : ndarray
        True thermal drift D(T, ΔT) (°/h), computed from the exact temperature and rate.
    noise : ndarray
        ARMA + white noise (°/h).
    temperature_true : ndarray
        Unquantized temperature (°C).
    temperature_rate : ndarray
        Exact dT/dt (°C/s).
    coefficients : dict
        The drift coefficients used.
    params : dict
        Every other simulation parameter (for the sidecar JSON).
    """

    run: Run
    drift: FloatArray = field(repr=False)
    noise: FloatArray = field(repr=False)
    temperature_true: FloatArray = field(repr=False)
    temperature_rate: FloatArray = field(repr=False)
    coefficients: dict[str, float]
    params: dict[str, Any]

    def to_frame(self) -> pd.DataFrame:
        return pd.DataFrame({"time": self.run.time, "rate": self.run.rate,
                             "temperature": self.run.temperature, "drift": self.drift,
                             "noise": self.noise, "temperature_rate": self.temperature_rate})

    def to_dict(self) -> dict[str, Any]:
        return {"coefficients": dict(self.coefficients), **self.params}

    def summary(self) -> str:
        t = self.run.temperature
        assert t is not None
        return (f"simulated cold start: {self.run.n} samples at {self.run.fs_hz:g} Hz, "
                f"T {t[0]:.2f} -> {t[-1]:.2f} °C, peak dT/dt {self.temperature_rate.max():.4f} °C/s,"
                f" drift {self.drift.min():.3g}..{self.drift.max():.3g} °/h")


# Long by its signature and docstring (14 options); noise and sampling are helpers below.
def simulate_startup(
    *,
    duration_s: float = 3600.0,
    fs_hz: float = 1.0,
    ambient_degC: float = 20.0,
    peak_rate_degC_s: float = 0.05,
    tau_s: tuple[float, float] = (400.0, 40.0),
    coefficients: Mapping[str, float] | None = None,
    ar: Sequence[float] = (0.9,),
    ma: Sequence[float] = (),
    arma_sigma_deg_h: float = 0.05,
    white_sigma_deg_h: float = 0.3,
    earth_rate_deg_h: float = 0.0,
    temperature_resolution_degC: float = 0.01,
    start_s: float = 0.0,
    rng: RngLike = None,
) -> StartupSimulation:
    """Simulate a gyro cold start (see the module docstring for the model).

    Parameters
    ----------
    duration_s, fs_hz : float
        Length and sample rate.
    ambient_degC, peak_rate_degC_s, tau_s :
        Warm-up shape (see :func:`warmup_temperature`).
    coefficients : mapping, optional
        Thermal-drift coefficients by term (``"T*dT", "T2", "T", "dT2", "dT", "1"``); missing
        terms are 0.  Default :data:`DEFAULT_STARTUP_COEFFICIENTS`.
    ar, ma : sequence of float
        ARMA drift coefficients (statsmodels sign: x_t = Σφ x_{t-i} + a_t + Σθ a_{t-j}).
    arma_sigma_deg_h : float
        Standard deviation of the ARMA innovation a_t.
    white_sigma_deg_h : float
        Standard deviation of the white rate noise per sample.
    earth_rate_deg_h : float
        Constant Earth-rate component sensed by the axis.
    temperature_resolution_degC : float
        Quantization step of the temperature sensor (0 = none).
    start_s : float
        Time since switch-on of the first sample (to simulate a later segment).
    rng : Generator, int or None
        Random source.

    Returns
    -------
    StartupSimulation

    Examples
    --------
    >>> sim = simulate_startup(duration_s=600, rng=4)
    >>> sim.run.n, sim.run.units
    (600, 'deg/h')
    """
    fs = check_positive("fs_hz", fs_hz)
    dur = check_positive("duration_s", duration_s)
    n = round(dur * fs)
    if n < 10:
        raise InsufficientDataError(f"duration_s * fs_hz gives {n} samples; at least 10 needed")
    coefs = _checked_coefficients(coefficients)
    ar_a = np.asarray(ar, dtype=float)
    ma_a = np.asarray(ma, dtype=float)
    if ar_a.size and np.any(np.abs(np.roots(np.r_[1.0, -ar_a])) >= 1.0):
        raise DataError(f"ar={list(ar)} is not stationary (a root of 1 - Σφ z^i lies inside "
                        "the unit circle)")
    gen = as_rng(rng)
    check_positive("arma_sigma_deg_h", arma_sigma_deg_h, allow_zero=True)
    check_positive("white_sigma_deg_h", white_sigma_deg_h, allow_zero=True)
    res = check_positive("temperature_resolution_degC", temperature_resolution_degC,
                         allow_zero=True)
    time = np.arange(n, dtype=np.float64) / fs
    temp, dtemp = warmup_temperature(time + check_positive("start_s", start_s, allow_zero=True),
                                     ambient_degC=ambient_degC,
                                     peak_rate_degC_s=peak_rate_degC_s, tau_s=tau_s)
    names = list(coefs)
    drift = design_matrix(temp, dtemp, names) @ np.array([float(coefs[k]) for k in names])
    noise = (_arma_noise(gen, n, ar_a, ma_a, arma_sigma_deg_h)
             + gen.standard_normal(n) * white_sigma_deg_h)
    rate = drift + noise + float(earth_rate_deg_h)
    temp_q = np.round(temp / res) * res if res > 0 else temp.copy()
    run = Run(rate=rate, time=time, fs_hz=fs, units="deg/h", axes=("gyro",),
              temperature=temp_q, columns=("time", "gyro", "temperature"),
              source="<simulate_startup>", sampling=_regular_sampling(fs))
    params = {"duration_s": dur, "fs_hz": fs, "ambient_degC": float(ambient_degC),
              "peak_rate_degC_s": float(peak_rate_degC_s), "tau_s": [float(v) for v in tau_s],
              "ar": ar_a.tolist(), "ma": ma_a.tolist(),
              "arma_sigma_deg_h": float(arma_sigma_deg_h),
              "white_sigma_deg_h": float(white_sigma_deg_h),
              "earth_rate_deg_h": float(earth_rate_deg_h),
              "temperature_resolution_degC": res, "start_s": float(start_s)}
    return StartupSimulation(run=run, drift=drift, noise=noise, temperature_true=temp,
                             temperature_rate=dtemp, coefficients=coefs, params=params)


def _checked_coefficients(coefficients: Mapping[str, float] | None) -> dict[str, float]:
    """The drift coefficients (default :data:`DEFAULT_STARTUP_COEFFICIENTS`), known terms only."""
    coefs = dict(DEFAULT_STARTUP_COEFFICIENTS if coefficients is None else coefficients)
    for k in coefs:
        if k not in THERMAL_TERMS:
            raise DataError(f"unknown thermal term {k!r} in coefficients; allowed: "
                            f"{', '.join(THERMAL_TERMS)}")
    return coefs


def _arma_noise(gen: np.random.Generator, n: int, ar: FloatArray, ma: FloatArray,
                sigma: float) -> FloatArray:
    """``n`` samples of the ARMA drift, after a burn-in so that it starts in its stationary
    distribution."""
    burn = 10 * max(1, math.ceil(-1.0 / math.log(max(np.max(np.abs(np.roots(
        np.r_[1.0, -ar]))), 1e-3)))) if ar.size else 0
    a = gen.standard_normal(n + burn) * sigma
    return np.asarray(lfilter(np.r_[1.0, ma], np.r_[1.0, -ar], a)[burn:], dtype=np.float64)


def _regular_sampling(fs: float) -> SamplingReport:
    """The sampling report of a gap-free record at ``fs`` Hz."""
    return SamplingReport(median_dt_s=1.0 / fs, n_gaps=0, max_gap_s=1.0 / fs, gap_rows=(),
                          jitter_s=0.0, jitter_rel=0.0, regular=True, from_time_column=False,
                          mean_dt_s=1.0 / fs, fs_source="given")
