"""Start-up figures: Kalman filtering, thermal compensation and north seeking."""

from __future__ import annotations

from typing import Any

import numpy as np
from matplotlib.figure import Figure

from fogts.report.plots._common import mpl_text, thin_step

__all__ = ["plot_compensation", "plot_kalman", "plot_north_seeking"]


def plot_kalman(result: Any, *, time_s: Any = None, units: str = "", max_points: int = 20000,
                width_in: float = 10.0) -> Figure:
    """Observed, Kalman-filtered and smoothed series on one axes.

    Long records are thinned to at most ``max_points`` points per line (every k-th sample).

    Parameters
    ----------
    result : fogts.startup.kalman.KalmanResult
        From :func:`fogts.startup.kalman.arma_kalman`.
    time_s : array_like, optional
        Sample times in seconds; by default the x axis counts samples.
    units : str
        Rate unit for the y label.
    max_points : int
        Largest number of points drawn per line.
    width_in : float
        Figure width in inches.

    Returns
    -------
    matplotlib.figure.Figure
    """
    obs = np.asarray(result.observed, dtype=float)
    t = np.arange(obs.size, dtype=float) if time_s is None else np.asarray(time_s, dtype=float)
    step = thin_step(obs.size, max_points)
    fig = Figure(figsize=(width_in, 4.0), layout="constrained")
    ax = fig.add_subplot()
    ax.plot(t[::step], obs[::step], lw=0.5, color="0.65", label="observed")
    ax.plot(t[::step], np.asarray(result.filtered)[::step], lw=0.8, color="C0", label="filtered")
    smoothed = np.asarray(result.smoothed, dtype=float)
    if np.isfinite(smoothed).any():
        ax.plot(t[::step], smoothed[::step], lw=0.8, color="C3", label="smoothed")
    ax.set_xlabel("time [s]" if time_s is not None else "sample")
    ax.set_ylabel(f"rate [{mpl_text(units)}]" if units else "rate")
    ax.set_title(mpl_text(f"Kalman filter, {result.model} + white noise "
                           f"(H = {result.measurement_noise:.3g}, {result.method})"))
    ax.legend(loc="upper right", fontsize="small")
    ax.grid(alpha=0.3)
    return fig


def plot_compensation(result: Any, *, max_points: int = 20000, width_in: float = 10.0) -> Figure:
    """Start-up compensation: raw rate, EMD trend and compensated rate on top, temperature
    below, and the bias stability before and after in the title.

    Parameters
    ----------
    result : fogts.startup.startup_workflow.StartupCompensation
        From :func:`fogts.startup.startup_workflow.startup_compensation`.
    max_points : int
        Largest number of points drawn per line (every k-th sample beyond it).
    width_in : float
        Figure width in inches.

    Returns
    -------
    matplotlib.figure.Figure
    """
    frame = result.to_frame()
    t = frame["time"].to_numpy()
    step = thin_step(t.size, max_points)
    units = mpl_text(result.run.units)
    fig = Figure(figsize=(width_in, 6.0), layout="constrained")
    ax1, ax2 = fig.subplots(2, 1, sharex=True, height_ratios=(2, 1))
    ax1.plot(t[::step], frame["raw"].to_numpy()[::step], lw=0.5, color="0.65", label="raw rate")
    trend = frame["trend"].to_numpy()
    if np.isfinite(trend).any():
        ax1.plot(t[::step], trend[::step], lw=1.2, color="C1", label="EMD trend")
    ax1.plot(t[::step], frame["compensated"].to_numpy()[::step], lw=0.5, color="C0", alpha=0.8,
             label="compensated")
    ax1.set_ylabel(f"rate [{units}]")
    b, a = result.before, result.after
    ax1.set_title(f"bias stability (1σ, {b.average_s:g} s average): {b.value:.3g} → "
                  f"{a.value:.3g} {mpl_text(b.unit)}")
    ax1.legend(loc="upper right", fontsize="small")
    ax1.grid(alpha=0.3)
    ax2.plot(t[::step], frame["temperature"].to_numpy()[::step], lw=1.0, color="C3")
    ax2.set_ylabel("temperature [°C]")
    ax2.set_xlabel("time [s]")
    ax2.grid(alpha=0.3)
    return fig


def plot_north_seeking(study: Any, *, width_in: float = 8.0) -> Figure:
    """Azimuth error of every north-seeking trial, raw and (when modelled) compensated.

    Parameters
    ----------
    study : fogts.startup.northfind.NorthSeekingStudy
        From :func:`fogts.startup.northfind.simulate_north_seeking`.
    width_in : float
        Figure width in inches.

    Returns
    -------
    matplotlib.figure.Figure
    """
    fig = Figure(figsize=(width_in, 4.0), layout="constrained")
    ax = fig.add_subplot()
    raw = np.asarray(study.raw_error_deg)
    ax.plot(np.arange(1, raw.size + 1), raw, "o", ms=3, color="0.5", label="raw")
    comp = study.compensated_error_deg
    if comp is not None:
        ax.plot(np.arange(1, raw.size + 1), np.asarray(comp), "o", ms=3, color="C0",
                label="compensated")
    ax.axhline(0.0, color="k", lw=0.6)
    ax.set_xlabel("trial")
    ax.set_ylabel("azimuth error [°]")
    ax.set_title(f"cold-start four-position north seeking at {study.latitude_deg:g}°")
    ax.legend(loc="upper right", fontsize="small")
    ax.grid(alpha=0.3)
    return fig
