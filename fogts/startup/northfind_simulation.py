"""Simulated four-position north seeking during a gyro's cold start.

A simulated warm-up (:func:`~fogts.startup.simulator.simulate_startup`) is measured at the
positions 0°, 90°, 180°, 270° in turn, each for ``position_s`` (60 s at 1 Hz by default),
with the Earth-rate component of each position added (convention of
:mod:`~fogts.startup.northfind`).  The thermal drift changes between positions, which is the
start-up error the thermal compensation removes: :func:`simulate_north_seeking` repeats the
experiment and finds north with and without
:func:`~fogts.startup.compensation.compensate`; :func:`simulated_calibration` fits the
thermal model on simulated calibration cold starts, as a temperature chamber would.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any

import numpy as np
import pandas as pd

from fogts._typing import FloatArray, RngLike
from fogts._validate import as_rng, check_int, check_positive
from fogts.errors import DataError, InsufficientDataError
from fogts.io.run import Run
from fogts.startup.compensation import compensate
from fogts.startup.northfind import (
    MIN_POSITION_SAMPLES,
    POSITIONS_DEG,
    angle_error_deg,
    check_latitude,
    four_position,
)
from fogts.startup.simulator import simulate_startup
from fogts.startup.startup_workflow import startup_compensation
from fogts.startup.thermal_model import ThermalModel
from fogts.units import earth_rate_component

__all__ = ["NorthSeekingStudy", "StartupPositions", "simulate_north_seeking",
           "simulate_startup_positions", "simulated_calibration"]


def _samples_per_position(position_s: float, fs: float) -> int:
    """Samples measured at each position; at least :data:`MIN_POSITION_SAMPLES`."""
    m = round(position_s * fs)
    if m < MIN_POSITION_SAMPLES:
        raise InsufficientDataError(f"position_s * fs_hz gives {m} samples per position; at "
                                    f"least {MIN_POSITION_SAMPLES} needed")
    return m


@dataclass(frozen=True)
class StartupPositions:
    """A four-position north-seeking record taken while a simulated gyro warms up.

    What :func:`simulate_startup_positions` returns; :meth:`rates_by_position` gives each
    position's samples to :func:`~fogts.startup.northfind.four_position`.

    Attributes
    ----------
    run : Run
        The whole record in °/h, turns included: the cold-start rate
        (:func:`fogts.startup.simulator.simulate_startup`) plus, at each position, the
        Earth-rate component Ω cos L cos(ψ + k·90°).  Turn samples carry no Earth rate (they
        are not used).  Compensate this run (continuous temperature), then cut it.
    slices : dict
        Samples of ``run`` measured at each position (0, 90, 180, 270).
    latitude_deg, azimuth_deg : float
        Latitude and true azimuth ψ of the input axis at position 0 (module convention).
    earth_rate_h_deg_h : float
        Ω cos L in °/h.
    position_s, turn_s, start_delay_s : float
        Seconds measured per position, spent turning between positions, and waited after
        the start of the record before position 0.
    simulation : StartupSimulation
        The underlying cold start (drift, noise and temperature truth, without Earth rate).
    """

    run: Run
    slices: dict[int, slice]
    latitude_deg: float
    azimuth_deg: float
    earth_rate_h_deg_h: float
    position_s: float
    turn_s: float
    start_delay_s: float
    simulation: Any = field(repr=False)

    def rates_by_position(self) -> dict[int, FloatArray]:
        """Rate samples at each position, for :func:`four_position`."""
        return {p: self.run.rate[sl] for p, sl in self.slices.items()}

    @property
    def position_time_s(self) -> dict[int, float]:
        """Centre time of each position (s from the start of the record)."""
        return {p: (sl.start + 0.5 * (sl.stop - sl.start)) / self.run.fs_hz
                for p, sl in self.slices.items()}

    def to_frame(self) -> pd.DataFrame:
        """The measured samples as ``time, position_deg, rate, temperature`` (turns left out),
        the table ``fogts northfind`` reads."""
        temp = self.run.temperature
        parts = [pd.DataFrame({"time": self.run.time[sl], "position_deg": p,
                               "rate": self.run.rate[sl],
                               "temperature": np.nan if temp is None else temp[sl]})
                 for p, sl in self.slices.items()]
        return pd.concat(parts, ignore_index=True)

    def to_dict(self) -> dict[str, Any]:
        return {"latitude_deg": self.latitude_deg, "azimuth_deg": self.azimuth_deg,
                "position_s": self.position_s, "turn_s": self.turn_s,
                "start_delay_s": self.start_delay_s,
                "earth_rate_h_deg_h": self.earth_rate_h_deg_h, **self.simulation.to_dict()}

    def summary(self) -> str:
        measured = sum(sl.stop - sl.start for sl in self.slices.values())
        return (f"{self.simulation.summary()}\nfour positions (0, 90, 180, 270°) of "
                f"{self.position_s:g} s with {self.turn_s:g} s turns at latitude "
                f"{self.latitude_deg:g}° (Ω cos L = {self.earth_rate_h_deg_h:.4f} °/h); true "
                f"azimuth {self.azimuth_deg:g}°; {measured:,} of the {self.run.n:,} samples "
                "measured at the positions (turns and the wait before them left out)")


def simulate_startup_positions(
    *,
    latitude_deg: float,
    azimuth_deg: float,
    rng: RngLike = None,
    position_s: float = 60.0,
    turn_s: float = 10.0,
    start_delay_s: float = 0.0,
    fs_hz: float = 1.0,
    **startup: Any,
) -> StartupPositions:
    """Simulate four-position north seeking during a cold start.

    The gyro is switched on, waits ``start_delay_s``, then measures 0°, 90°, 180°, 270° in
    turn for ``position_s`` each, with ``turn_s`` between positions, while it warms up
    (:func:`fogts.startup.simulator.simulate_startup`, which ``**startup`` is passed to).  At
    position k the rate gains Ω cos L cos(ψ + k·90°) (module convention).

    Parameters
    ----------
    latitude_deg : float
        |L| <= 89°.
    azimuth_deg : float
        True ψ in degrees.
    rng : Generator, int or None
    position_s, turn_s, start_delay_s, fs_hz : float
    **startup
        ``ambient_degC``, ``coefficients``, ``ar``, ``white_sigma_deg_h``, ... of
        :func:`~fogts.startup.simulator.simulate_startup`.

    Returns
    -------
    StartupPositions

    Examples
    --------
    >>> rec = simulate_startup_positions(latitude_deg=32.05, azimuth_deg=37.5, rng=4005)
    >>> rec.to_frame().shape
    (240, 4)
    >>> res = four_position(rec.rates_by_position(), latitude_deg=32.05)
    >>> abs(float(angle_error_deg(res.azimuth_deg, 37.5))) < 3
    True
    """
    lat = check_latitude(latitude_deg)
    psi = float(azimuth_deg)
    if not math.isfinite(psi):
        raise DataError(f"azimuth_deg must be a finite number of degrees, got {azimuth_deg!r}")
    fs = check_positive("fs_hz", fs_hz)
    pos_s = check_positive("position_s", position_s)
    trans = check_positive("turn_s", turn_s, allow_zero=True)
    delay = check_positive("start_delay_s", start_delay_s, allow_zero=True)
    m = _samples_per_position(pos_s, fs)
    gap = round(trans * fs)
    sim = simulate_startup(duration_s=delay + 4 * pos_s + 3 * trans, fs_hz=fs, rng=rng,
                           **startup)
    run = sim.run
    omega_h = earth_rate_component(lat, unit="deg/h", axis="north")
    start = round(delay * fs)
    earth = np.zeros(run.n)
    slices: dict[int, slice] = {}
    for k, p in enumerate(POSITIONS_DEG):
        sl = slice(start + k * (m + gap), start + k * (m + gap) + m)
        slices[p] = sl
        earth[sl] = omega_h * math.cos(math.radians(psi + p))
    run_e = Run(rate=run.rate + earth, time=run.time, fs_hz=fs, units=run.units,
                axes=run.axes, temperature=run.temperature, source=run.source)
    return StartupPositions(run=run_e, slices=slices, latitude_deg=lat, azimuth_deg=psi,
                            earth_rate_h_deg_h=omega_h, position_s=m / fs, turn_s=gap / fs,
                            start_delay_s=start / fs, simulation=sim)


@dataclass(frozen=True)
class NorthSeekingStudy:
    """Repeated cold-start north finding, raw and thermally compensated.

    Attributes
    ----------
    truth_deg : ndarray
        True azimuth of each trial.
    raw_deg, compensated_deg : ndarray
        Azimuths found without and with the thermal compensation.
    latitude_deg : float
    position_s : float
        Seconds measured at each position.
    fs_hz : float
    params : dict
        Simulation settings.
    """

    truth_deg: FloatArray
    raw_deg: FloatArray
    compensated_deg: FloatArray | None
    latitude_deg: float
    position_s: float
    fs_hz: float
    params: dict[str, Any]

    @staticmethod
    def _stats(err: FloatArray) -> dict[str, float]:
        return {"mean_deg": float(np.mean(err)), "std_deg": float(np.std(err, ddof=1)),
                "rms_deg": float(np.sqrt(np.mean(err ** 2))),
                "max_abs_deg": float(np.max(np.abs(err)))}

    @property
    def raw_error_deg(self) -> FloatArray:
        return angle_error_deg(self.raw_deg, self.truth_deg)

    @property
    def compensated_error_deg(self) -> FloatArray | None:
        if self.compensated_deg is None:
            return None
        return angle_error_deg(self.compensated_deg, self.truth_deg)

    @property
    def improvement(self) -> float:
        """RMS error raw / RMS error compensated."""
        comp = self.compensated_error_deg
        if comp is None:
            return math.nan
        return self._stats(self.raw_error_deg)["rms_deg"] / self._stats(comp)["rms_deg"]

    def to_dict(self) -> dict[str, Any]:
        comp = self.compensated_error_deg
        return {"n_trials": int(self.truth_deg.size), "latitude_deg": self.latitude_deg,
                "position_s": self.position_s, "fs_hz": self.fs_hz,
                "raw": self._stats(self.raw_error_deg),
                "compensated": None if comp is None else self._stats(comp),
                "improvement_rms": self.improvement, "params": self.params}

    def to_frame(self) -> pd.DataFrame:
        data: dict[str, Any] = {"truth_deg": self.truth_deg, "raw_deg": self.raw_deg,
                                "raw_error_deg": self.raw_error_deg}
        if self.compensated_deg is not None:
            data["compensated_deg"] = self.compensated_deg
            data["compensated_error_deg"] = self.compensated_error_deg
        return pd.DataFrame(data)

    def summary(self) -> str:
        d = self.to_dict()
        lines = [f"Cold-start north seeking, {d['n_trials']} trials at latitude "
                 f"{self.latitude_deg:g}°, {self.position_s:g} s per position at {self.fs_hz:g} Hz",
                 "  case           mean [°]   std [°]   RMS [°]   max |err| [°]"]
        for name in ("raw", "compensated"):
            s = d[name]
            if s is not None:
                lines.append(f"  {name:<12s} {s['mean_deg']:9.4f} {s['std_deg']:9.4f} "
                             f"{s['rms_deg']:9.4f} {s['max_abs_deg']:12.4f}")
        if d["compensated"] is not None:
            lines.append(f"  RMS error reduced {self.improvement:.2f}x by the thermal compensation")
        return "\n".join(lines)


def simulate_north_seeking(
    n_trials: int = 50,
    *,
    latitude_deg: float = 32.05,
    model: Any = None,
    position_s: float = 60.0,
    fs_hz: float = 1.0,
    transition_s: float = 10.0,
    start_delay_s: float = 0.0,
    ambient_degC: tuple[float, float] = (15.0, 25.0),
    rng: RngLike = None,
    **startup: Any,
) -> NorthSeekingStudy:
    """Repeat four-position north seeking from a cold start, with and without compensation.

    Each trial: switch on at an ambient temperature drawn uniformly from ``ambient_degC``,
    wait ``start_delay_s``, then measure 0°, 90°, 180°, 270° in turn for ``position_s`` each
    (``transition_s`` to turn between them) while the gyro warms up
    (:func:`fogts.startup.simulator.simulate_startup`); the true azimuth is uniform in
    [0, 360).  The thermal drift changes between positions, which is the start-up error the
    thermal compensation removes.  With a ``model`` the recorded rates are also compensated
    (:func:`~fogts.startup.compensation.compensate`) before north finding.

    Parameters
    ----------
    n_trials : int
    latitude_deg : float
    model : ThermalModel, optional
        Thermal model fitted on a separate calibration run.
    position_s, fs_hz, transition_s, start_delay_s : float
    ambient_degC : (low, high)
    rng : Generator, int or None
    **startup
        Passed to :func:`~fogts.startup.simulator.simulate_startup` (coefficients, ar, noise).

    Returns
    -------
    NorthSeekingStudy

    Examples
    --------
    >>> st = simulate_north_seeking(3, rng=4)
    >>> st.truth_deg.size
    3
    """
    n = check_int("n_trials", n_trials, minimum=2)
    lat = check_latitude(latitude_deg)
    fs = check_positive("fs_hz", fs_hz)
    pos_s = check_positive("position_s", position_s)
    trans = check_positive("transition_s", transition_s, allow_zero=True)
    delay = check_positive("start_delay_s", start_delay_s, allow_zero=True)
    if model is not None and not isinstance(model, ThermalModel):
        raise DataError(f"model must be a ThermalModel or None, got {type(model).__name__}")
    lo, hi = (float(ambient_degC[0]), float(ambient_degC[1]))
    if not hi >= lo:
        raise DataError(f"ambient_degC must be (low, high) with high >= low, got {ambient_degC!r}")
    gen = as_rng(rng)
    m = _samples_per_position(pos_s, fs)
    truth = gen.uniform(0.0, 360.0, n)
    raw = np.empty(n)
    comp = np.empty(n) if model is not None else None
    for i in range(n):
        rec = simulate_startup_positions(
            latitude_deg=lat, azimuth_deg=float(truth[i]), position_s=pos_s, turn_s=trans,
            start_delay_s=delay, fs_hz=fs, ambient_degC=float(gen.uniform(lo, hi)), rng=gen,
            **startup)
        times = rec.position_time_s
        raw[i] = four_position(rec.rates_by_position(), latitude_deg=lat, fs_hz=fs,
                               position_time_s=times).azimuth_deg
        if comp is not None and model is not None:
            cr = compensate(rec.run, model)
            comp[i] = four_position({p: cr.rate[sl] for p, sl in rec.slices.items()},
                                    latitude_deg=lat, fs_hz=fs,
                                    position_time_s=times).azimuth_deg
    params = {"transition_s": trans, "start_delay_s": delay, "ambient_degC": [lo, hi],
              **{k: v for k, v in startup.items() if isinstance(v, int | float | str)}}
    return NorthSeekingStudy(truth_deg=truth, raw_deg=raw, compensated_deg=comp,
                             latitude_deg=lat, position_s=m / fs, fs_hz=fs, params=params)


def simulated_calibration(ambient_degC: tuple[float, ...] = (15.0, 20.0, 25.0), *,
                          duration_s: float = 3600.0, fs_hz: float = 1.0, emd: bool = False,
                          rng: RngLike = None, **startup: Any) -> Any:
    """Thermal model from simulated calibration cold starts, one per ambient temperature.

    Mirrors a temperature-chamber calibration: each run is a full warm-up
    (:func:`fogts.startup.simulator.simulate_startup`), and the model is fitted to all of
    them together (:func:`~fogts.startup.startup_workflow.startup_compensation` with ``calibration``).

    Examples
    --------
    >>> m = simulated_calibration(rng=4)
    >>> sorted(m.terms)
    ['1', 'T', 'T*dT', 'T2', 'dT', 'dT2']
    """
    if len(ambient_degC) < 1:
        raise DataError("ambient_degC needs at least one calibration temperature")
    gen = as_rng(rng)
    runs = [simulate_startup(duration_s=duration_s, fs_hz=fs_hz, ambient_degC=float(a), rng=gen,
                             **startup).run for a in ambient_degC]
    return startup_compensation(runs[0], emd=emd, calibration=runs[1:]).model
