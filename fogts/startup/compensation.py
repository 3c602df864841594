"""Removal of the modelled temperature drift from a run, and the bias stability that measures
what it gained.

:func:`compensate` subtracts ``D(T, ΔT) - D(T_ref, 0)`` of a
:class:`~fogts.startup.thermal_model.ThermalModel` from one axis of a run, so that the output
keeps the steady-state bias and the Earth-rate component and loses only the
temperature-driven change.

Bias stability follows the static test of GJB 2426A-2015 / IEEE Std 952-1997: the 1σ
standard deviation of the bias averaged over consecutive, non-overlapping windows of
``average_s`` seconds (10 s unless stated), in °/h.  The averaging time is part of every
output: a bias stability without it means nothing.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace
from typing import Any

import numpy as np
import pandas as pd

from fogts._typing import ArrayLike1D, FloatArray
from fogts._validate import check_positive, to_float_array
from fogts.errors import DataError, InsufficientDataError
from fogts.io.run import Run
from fogts.startup.thermal_model import ThermalModel, temperature_rate
from fogts.units import parse_rate_unit, to_deg_per_hour_factor

__all__ = ["BiasStability", "bias_stability", "compensate"]


def require_temperature(run: Run, *, hint: str = "") -> None:
    """Raise :class:`~fogts.errors.DataError` naming the run's columns when it has no
    temperature; ``hint`` is appended to the message."""
    if run.temperature is None:
        raise DataError(f"run {run.source!r} has no temperature column; thermal compensation "
                        "needs one (columns are: " + ", ".join(run.columns or run.axes) + ")"
                        + hint)


def check_calibration_run(i: int, extra: Any, run: Run) -> None:
    """A calibration run must be a Run with a temperature, at the run's rate and units."""
    fs = run.fs_hz
    if not isinstance(extra, Run):
        raise DataError(f"calibration[{i}] must be a fogts Run, got "
                        f"{type(extra).__name__}")
    if extra.temperature is None:
        raise DataError(f"calibration run {extra.source!r} has no temperature column")
    if abs(extra.fs_hz - fs) > 1e-6 * fs:
        raise DataError(f"calibration run {extra.source!r} is sampled at "
                        f"{extra.fs_hz:g} Hz, the run at {fs:g} Hz; they must match")
    if extra.units != run.units:
        raise DataError(f"calibration run {extra.source!r} is in {extra.units}, the run "
                        f"in {run.units}; they must match")


def _rate_on_time_base(run: Run, model: ThermalModel) -> FloatArray | None:
    """ΔT of a run whose time stamps have gaps: the temperature is interpolated onto a
    regular grid at ``run.fs_hz``, differentiated there and read back at the time stamps.
    None for a regular time base (the model then differentiates the samples directly)."""
    t = np.asarray(run.time, dtype=float)
    if t.size < 3 or run.temperature is None:
        return None
    dt = np.diff(t)
    step = 1.0 / run.fs_hz
    if np.all(np.abs(dt - step) <= 0.5 * step):
        return None
    grid = np.arange(t[0], t[-1] + 0.5 * step, step)
    temp_grid = np.interp(grid, t, np.asarray(run.temperature, dtype=float))
    rate = temperature_rate(temp_grid, fs_hz=run.fs_hz, smoothing_s=model.dT_smoothing_s)
    return np.interp(t, grid, rate)


def compensate(run: Run, model: ThermalModel, *, axis: int | str = 0,
               reference_degC: float | None = None) -> Run:
    """Remove the modelled temperature drift from a run.

    Subtracts ``D(T, ΔT) - D(T_ref, 0)`` from the rate, where T_ref is the model's reference
    temperature (the warm steady state of the fit record) unless ``reference_degC`` is
    given.  The output therefore keeps the steady-state bias and the Earth-rate component
    that a north finder needs, and loses only the temperature-driven change.

    Parameters
    ----------
    run : Run
        A recording with a temperature column.
    model : ThermalModel
        Fitted by :func:`~fogts.startup.thermal_fit.fit_thermal` (possibly on another run,
        loaded with :meth:`ThermalModel.from_dict`).
    axis : int or str
        Axis to compensate (the other axes are left unchanged).
    reference_degC : float, optional
        Override the reference temperature.

    Returns
    -------
    Run
        A copy of ``run`` with the compensated rate; ``source`` records the compensation.

    Raises
    ------
    DataError
        The run has no temperature.

    Examples
    --------
    >>> import numpy as np
    >>> from fogts.io.run import Run
    >>> from fogts.startup.thermal_fit import fit_thermal
    >>> t = np.arange(600.0)
    >>> temp = 20 + 0.02 * t
    >>> run = Run(rate=2.0 * temp, time=t, fs_hz=1.0, units="deg/h", axes=("gyro",),
    ...           temperature=temp)
    >>> m = fit_thermal(run.rate, temp, fs_hz=1.0, terms=("T", "1"))
    >>> out = compensate(run, m, reference_degC=20.0)
    >>> bool(np.allclose(out.rate, 40.0))
    True
    """
    if not isinstance(run, Run):
        raise DataError(f"run must be a fogts Run, got {type(run).__name__}")
    if not isinstance(model, ThermalModel):
        raise DataError(f"model must be a ThermalModel, got {type(model).__name__}")
    require_temperature(run)
    drift = model.predict(run.temperature, fs_hz=run.fs_hz,
                          temperature_rate_degC_s=_rate_on_time_base(run, model))
    if reference_degC is not None:
        ref_model = replace(model, t_ref_degC=float(reference_degC))
        drift = drift - ref_model.reference_drift()
    else:
        drift = drift - model.reference_drift()
    factor = to_deg_per_hour_factor(model.units) / to_deg_per_hour_factor(run.units)
    drift = drift * factor
    rate = np.array(run.rate, dtype=np.float64, copy=True)
    if rate.ndim == 1:
        rate -= drift
    else:
        i = run.axes.index(axis) if isinstance(axis, str) and axis in run.axes else axis
        if isinstance(i, str):
            raise DataError(f"axis {axis!r} not found; axes are: {', '.join(run.axes)}")
        run.axis(i)  # validates the index
        rate[:, i] -= drift
    return replace(run, rate=rate, source=f"{run.source} (thermally compensated)", angle=None)


# --------------------------------------------------------------------------- bias stability


@dataclass(frozen=True)
class BiasStability:
    """Bias stability: 1σ of the bias averaged over ``average_s`` (GJB 2426A / IEEE 952).

    Attributes
    ----------
    value : float
        The 1σ standard deviation of the window means, in ``unit``.
    average_s : float
        Averaging time of each window in seconds.
    n_windows : int
        Number of complete windows used.
    unit : str
        Always ``"deg/h"``.
    mean : float
        Mean of the window means (the average bias) in ``unit``.
    """

    value: float
    average_s: float
    n_windows: int
    unit: str = "deg/h"
    mean: float = math.nan

    def to_dict(self) -> dict[str, Any]:
        return {"value": self.value, "average_s": self.average_s, "n_windows": self.n_windows,
                "unit": self.unit, "mean": self.mean}

    def to_frame(self) -> pd.DataFrame:
        return pd.DataFrame([self.to_dict()])

    def summary(self) -> str:
        return (f"bias stability {self.value:.4g} {self.unit} (1σ, {self.average_s:g} s average, "
                f"{self.n_windows} windows)")

    def __str__(self) -> str:
        return self.summary()


def bias_stability(x: ArrayLike1D, *, fs_hz: float, average_s: float = 10.0,
                   units: str = "deg/h") -> BiasStability:
    """Bias stability of a static record (GJB 2426A-2015 §5.3 / IEEE Std 952-1997 §12.3).

    The record is cut into consecutive non-overlapping windows of ``average_s`` seconds
    (a partial last window is dropped); the result is the sample standard deviation
    (ddof = 1) of the window means, converted to °/h.

    Parameters
    ----------
    x : array_like or pandas.Series
        Rate samples in ``units``.
    fs_hz : float
        Sample rate in Hz.
    average_s : float
        Averaging time in seconds (10 s in the GJB procedure; 100 s is also common).
    units : str
        Rate unit of ``x``.

    Returns
    -------
    BiasStability

    Raises
    ------
    InsufficientDataError
        Fewer than two complete windows.

    Examples
    --------
    >>> import numpy as np
    >>> x = np.random.default_rng(0).normal(0.0, 1.0, 36000)
    >>> b = bias_stability(x, fs_hz=10.0, average_s=10.0)
    >>> b.average_s, b.n_windows, round(b.value, 1)
    (10.0, 360, 0.1)
    """
    fs = check_positive("fs_hz", fs_hz)
    avg = check_positive("average_s", average_s)
    arr = to_float_array(x, "x")
    m = round(avg * fs)
    if m < 1:
        raise DataError(f"average_s={avg:g} s is shorter than one sample at {fs:g} Hz")
    k = arr.size // m
    if k < 2:
        raise InsufficientDataError(
            f"bias stability with average_s={avg:g} s needs at least two windows "
            f"({2 * m} samples), got {arr.size}")
    means = arr[: k * m].reshape(k, m).mean(axis=1) * to_deg_per_hour_factor(parse_rate_unit(units))
    return BiasStability(value=float(np.std(means, ddof=1)), average_s=m / fs, n_windows=k,
                         unit="deg/h", mean=float(np.mean(means)))
