"""Simulated gyro records: IEEE-952 noise terms, ARMA series and temperature profiles.

Modules: :mod:`~fogts.simulate.noise_spec` (the coefficients and their closed-form Allan
variance), :mod:`~fogts.simulate.streams` (one random stream per noise term),
:mod:`~fogts.simulate.temperature` (temperature profiles and thermal drift),
:mod:`~fogts.simulate.arma_series` (ARMA series) and :mod:`~fogts.simulate.gyro`
(:func:`simulate_gyro`, the record); :mod:`~fogts.simulate.bootstrap` re-simulates a
fitted noise model for bootstrap standard errors (:func:`bootstrap_noise`).  :class:`ArmaSpec` lives in :mod:`fogts.arma.spec`.
"""

from __future__ import annotations

from fogts.arma.spec import ArmaSpec
from fogts.simulate.arma_series import simulate_arma
from fogts.simulate.gyro import simulate_gyro
from fogts.simulate.noise_spec import NoiseSpec
from fogts.simulate.temperature import TemperatureProfile

__all__ = ["ArmaSpec", "NoiseSpec", "TemperatureProfile", "simulate_arma", "simulate_gyro"]
