"""Simulated ARMA series with a known model, shared by the ARMA tests."""

from __future__ import annotations

import numpy as np
from scipy.signal import lfilter


def arma_series(ar: list[float], ma: list[float], n: int, seed: int, scale: float = 1.0,
                burn: int = 2000) -> np.ndarray:
    """x_t = sum ar_i x_{t-i} + a_t + sum ma_j a_{t-j}, a_t ~ N(0, scale^2), after ``burn``
    samples of burn-in (``scipy.signal.lfilter`` from zero initial conditions)."""
    e = np.random.default_rng(seed).standard_normal(n + burn) * scale
    x = lfilter(np.r_[1.0, ma], np.r_[1.0, -np.asarray(ar, dtype=float)], e)
    return np.ascontiguousarray(x[burn:])
