"""The filter and smoother runs: exact (statsmodels) and steady-state (DARE + lfilter).

Once the Riccati recursion has converged the gain is constant, and the filter is a fixed
linear system.  The steady-state run solves the discrete algebraic Riccati equation
(``scipy.linalg.solve_discrete_are``) for the steady predicted covariance P, runs
statsmodels' exact filter only over the transient, and continues with
``scipy.signal.lfilter``; the smoother uses the steady backward recursion
r_{t-1} = Z'F⁻¹v_t + L'r_t, α̂_t = a_t + P r_{t-1} (Durbin & Koopman, 2012, eq. 4.44) and
the exact time-varying recursion over the transient.  The result equals the exact filter
to the Riccati convergence tolerance :data:`RICCATI_RTOL`.

The measurement-noise variance H can be estimated by maximum likelihood with the ARMA
parameters fixed (bounded 1-D search on log(H/σ²), :func:`estimate_measurement_noise`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np
from scipy import linalg, optimize, signal

from fogts._typing import FloatArray
from fogts.startup.kalman.state_space import ArmaStateSpace, mle_model

__all__ = ["RICCATI_RTOL", "FilterRun", "estimate_measurement_noise", "exact_run",
           "riccati_transient", "steady_run", "steady_state"]

#: Relative convergence tolerance of the Riccati recursion for the steady-state switch.
RICCATI_RTOL = 1e-12
#: Search range of log10(H / sigma2) when estimating the measurement noise.
LOG_RATIO_BOUNDS = (-10.0, 4.0)


@dataclass
class FilterRun:
    """Filtered, smoothed and predicted signal, innovations and log-likelihood of one run;
    ``n0`` samples were filtered exactly."""

    filtered: FloatArray
    smoothed: FloatArray
    predicted: FloatArray
    innov: FloatArray
    loglike: float
    n0: int


# --------------------------------------------------------------------------- steady state
def steady_state(ss: ArmaStateSpace, h: float) -> tuple[FloatArray, float, FloatArray]:
    """Steady predicted covariance P (DARE), innovation variance F, filtered gain K_f."""
    h_eff = max(h, 1e-12 * ss.sigma2)  # the DARE needs a non-singular R
    q = ss.sigma2 * (ss.R @ ss.R.T)
    P = linalg.solve_discrete_are(ss.T.T, ss.Z.T, q, np.array([[h_eff]]))
    P = 0.5 * (P + P.T)
    F = float((ss.Z @ P @ ss.Z.T)[0, 0]) + h
    Kf = (P @ ss.Z.T) / F
    return P, F, Kf


def riccati_transient(ss: ArmaStateSpace, h: float, P_inf: FloatArray, limit: int) -> int | None:
    """Steps until the exact predicted covariance (stationary start) is within
    RICCATI_RTOL of the DARE solution; None if not within ``limit``."""
    from statsmodels.tsa.statespace.tools import solve_discrete_lyapunov

    P = solve_discrete_lyapunov(ss.T, ss.sigma2 * (ss.R @ ss.R.T))
    scale = float(np.max(np.abs(P_inf))) or 1.0
    q = ss.sigma2 * (ss.R @ ss.R.T)
    for t in range(limit):
        if float(np.max(np.abs(P - P_inf))) <= RICCATI_RTOL * scale:
            return t
        F = float((ss.Z @ P @ ss.Z.T)[0, 0]) + h
        if F <= 0:
            return None
        K = ss.T @ P @ ss.Z.T / F
        L = ss.T - K @ ss.Z
        P = ss.T @ P @ L.T + q
    return None


def _lti(A: FloatArray, B: FloatArray, C: FloatArray, D: FloatArray, u: FloatArray,
         x0: FloatArray | None = None) -> FloatArray:
    """Outputs (n, p) of x_{k+1} = A x_k + B u_k, y_k = C x_k + D u_k for a scalar input,
    via per-output transfer functions and ``scipy.signal.lfilter``."""
    n = u.size
    p = C.shape[0]
    out = np.empty((n, p))
    num, den = signal.ss2tf(A, B.reshape(-1, 1), C, D.reshape(-1, 1))
    for i in range(p):
        out[:, i] = signal.lfilter(num[i], den, u)
    if x0 is not None and np.any(x0 != 0):
        # zero-input response y_k = C A^k x0 = impulse response of (A, x0, C, 0) one step later
        num0, den0 = signal.ss2tf(A, x0.reshape(-1, 1), C, np.zeros((p, 1)))
        imp = np.zeros(n + 1)
        imp[0] = 1.0
        for i in range(p):
            out[:, i] += signal.lfilter(num0[i], den0, imp)[1:]
    return out


# --------------------------------------------------------------------------- runs
def exact_run(y: FloatArray, ss: ArmaStateSpace, h: float, smooth: bool) -> FilterRun:
    """statsmodels' exact filter (and smoother) over the whole record."""
    mod = mle_model(y, ss, h)
    res = mod.smooth([], return_ssm=True) if smooth else mod.filter([], return_ssm=True)
    filt = (ss.Z @ res.filtered_state)[0]
    pred = np.asarray(res.forecasts[0], dtype=float)
    sm = (ss.Z @ res.smoothed_state)[0] if smooth else np.full(y.size, np.nan)
    ll = float(np.sum(res.llf_obs))
    return FilterRun(filt, sm, pred, np.asarray(res.forecasts_error[0], float), ll, y.size)


def steady_run(y: FloatArray, ss: ArmaStateSpace, h: float, n0: int, smooth: bool) -> FilterRun:
    """Exact filter over the first ``n0`` samples, the steady gain after them."""
    P, F, Kf = steady_state(ss, h)
    Z, T = ss.Z, ss.T
    r = ss.k_states
    n = y.size
    # exact filter over the transient (statsmodels); its last predicted state seeds the rest
    filt = np.empty(n)
    pred = np.empty(n)
    innov = np.empty(n)
    ll = 0.0
    a0 = np.zeros(r)
    ex = None
    if n0 > 0:
        mod = mle_model(y[:n0], ss, h)
        ex = mod.filter([], return_ssm=True)
        filt[:n0] = (Z @ ex.filtered_state)[0]
        pred[:n0] = ex.forecasts[0]
        innov[:n0] = ex.forecasts_error[0]
        ll += float(np.sum(ex.llf_obs))
        a0 = np.asarray(ex.predicted_state[:, n0], dtype=float)
    # steady forward system: state a_t (predicted); outputs [a_{t|t} (r), Z a_t]
    IKZ = np.eye(r) - Kf @ Z
    A = T @ IKZ
    B = (T @ Kf).ravel()
    C = np.vstack([IKZ, Z])
    D = np.r_[Kf.ravel(), 0.0]
    out = _lti(A, B, C, D, y[n0:], a0)
    a_filt = out[:, :r]
    pred[n0:] = out[:, r]
    filt[n0:] = a_filt[:, 0]
    v = y[n0:] - pred[n0:]
    innov[n0:] = v
    ll += float(-0.5 * (v.size * math.log(2.0 * math.pi * F) + np.sum(v * v) / F))
    smoothed = np.full(n, np.nan)
    if smooth:
        _steady_smooth(smoothed, ss, P, F, v, pred, n0, ex)
    return FilterRun(filt, smoothed, pred, innov, ll, n0)


def _steady_smooth(smoothed: FloatArray, ss: ArmaStateSpace, P: FloatArray, F: float,
                   v: FloatArray, pred: FloatArray, n0: int, ex: Any) -> None:
    """Fill ``smoothed``: the steady backward pass after ``n0``, the exact one before it."""
    Z, T = ss.Z, ss.T
    # steady backward pass: q_t = Z'v_t/F + L'q_{t+1}, q_n = 0 (reversed-time LTI)
    K = T @ P @ Z.T / F
    L = T - K @ Z
    qs = _lti(L.T, (Z.T / F).ravel(), L.T, (Z.T / F).ravel(), v[::-1])[::-1]
    a_pred_signal = pred[n0:]
    smoothed[n0:] = a_pred_signal + (Z @ P @ qs.T)[0]
    if n0 > 0 and ex is not None:
        q = qs[0].copy()
        # q_{n0} is qs[0]; continue exactly for t = n0-1 .. 0
        q_next = q
        for t in range(n0 - 1, -1, -1):
            Pt = np.asarray(ex.predicted_state_cov[:, :, t], dtype=float)
            Ft = float(ex.forecasts_error_cov[0, 0, t])
            vt = float(ex.forecasts_error[0, t])
            Kt = T @ Pt @ Z.T / Ft
            Lt = T - Kt @ Z
            q_t = (Z.T / Ft).ravel() * vt + Lt.T @ q_next
            at = np.asarray(ex.predicted_state[:, t], dtype=float)
            smoothed[t] = float((Z @ (at + Pt @ q_t))[0])
            q_next = q_t


# --------------------------------------------------------------------------- measurement noise
def _loglike_steady(y: FloatArray, ss: ArmaStateSpace, h: float) -> float:
    """Steady-state (prediction-error) log-likelihood; used to estimate H on long records."""
    _, F, Kf = steady_state(ss, h)
    r = ss.k_states
    IKZ = np.eye(r) - Kf @ ss.Z
    pred = _lti(ss.T @ IKZ, (ss.T @ Kf).ravel(), ss.Z, np.zeros(1), y)[:, 0]
    v = y - pred
    return float(-0.5 * (y.size * math.log(2.0 * math.pi * F) + np.sum(v * v) / F))


def estimate_measurement_noise(y: FloatArray, ss: ArmaStateSpace,
                               use_steady: bool) -> tuple[float, bool]:
    """ML estimate of H with the ARMA parameters fixed, and whether it sits at the lower
    bound of the search (then H = 0 is returned)."""
    def nll(u: float) -> float:
        h = ss.sigma2 * 10.0 ** u
        if use_steady:
            return -_loglike_steady(y, ss, h)
        return -float(mle_model(y, ss, h).loglike([]))

    lo, hi = LOG_RATIO_BOUNDS
    res = optimize.minimize_scalar(nll, bounds=(lo, hi), method="bounded",
                                   options={"xatol": 1e-4})
    u = float(res.x)
    at_lower = u <= lo + 0.05 and nll(lo) <= nll(u) + 1e-9
    return (0.0 if at_lower else ss.sigma2 * 10.0 ** u), at_lower
