"""Kalman filtering and smoothing of a gyro series with an ARMA drift model.

The ARMA(p, q) drift (statsmodels sign convention, DESIGN.md)

    x_t = φ₁x_{t-1} + … + φ_p x_{t-p} + a_t + θ₁a_{t-1} + … + θ_q a_{t-q},   a_t ~ N(0, σ²)

observed with white measurement noise, y_t = x_t + ε_t, ε_t ~ N(0, H), is written in
Harvey's state-space form (Harvey, *Forecasting, Structural Time Series Models and the Kalman
Filter*, 1989, §3.4; Durbin & Koopman, *Time Series Analysis by State Space Methods*, 2nd ed.,
2012, §3.4), with r = max(p, q + 1):

    α_{t+1} = T α_t + R a_{t+1},  y_t = Z α_t + ε_t,
    T = [φ | I_{r-1}; 0],  R = (1, θ₁, …, θ_{r-1})',  Z = (1, 0, …, 0).

Outputs are the *filtered* signal Z a_{t|t} = E[x_t | y_1..y_t], the *smoothed* signal
E[x_t | y_1..y_n] and the one-step *predictions* Z a_t = E[y_t | y_1..y_{t-1}].

Modules: :mod:`~fogts.startup.kalman.state_space` (the Harvey matrices),
:mod:`~fogts.startup.kalman.runs` (the exact and the steady-state filter and smoother),
:mod:`~fogts.startup.kalman.result` (:class:`KalmanResult`) and
:mod:`~fogts.startup.kalman.api` (:func:`arma_kalman`, :func:`resolve_arma_model`).
"""

from __future__ import annotations

from fogts.startup.kalman.api import KALMAN_METHODS, MODEL_CHOICES, arma_kalman, resolve_arma_model
from fogts.startup.kalman.result import KalmanResult
from fogts.startup.kalman.state_space import ArmaStateSpace, arma_state_space

__all__ = ["KALMAN_METHODS", "MODEL_CHOICES", "ArmaStateSpace", "KalmanResult", "arma_kalman",
           "arma_state_space", "resolve_arma_model"]
