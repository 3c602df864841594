"""Simulated gyro records: IEEE-952 noise terms, ARMA series and temperature profiles."""

from __future__ import annotations

from fogts.simulate.gyro import (
    ArmaSpec,
    NoiseSpec,
    TemperatureProfile,
    simulate_arma,
    simulate_gyro,
)

__all__ = ["ArmaSpec", "NoiseSpec", "TemperatureProfile", "simulate_arma", "simulate_gyro"]
