"""The exact Gaussian likelihood of a rate record under white + random walk + Gauss-Markov
sum + drift, on block means, by the Kalman filter (used by :mod:`fogts.allan.ml`).

The model (continuous time, observed as interval averages)
    A rate gyro's output sample is the average of the rate over its sampling interval (the
    integrating sensor of IEEE Std 952-1997 Annex C; :func:`fogts.simulate.simulate_gyro`
    draws exactly this).  The rate is

    .. math:: \\Omega(t) = W(t) + r\\,t + \\sum_j x_j(t) + \\text{white}(t),

    with :math:`W` a Brownian motion of diffusion :math:`k^2 = 3 a_1` (rate random walk,
    Allan variance :math:`k^2\\tau/3 = a_1\\tau`; :math:`K = k`), ``r`` a constant ramp
    (drift, :math:`a_2 = r^2/2`), :math:`x_j` first-order Gauss-Markov processes
    :math:`dx = -x/T_j\\,dt + q_j\\,dW_j` of stationary variance :math:`s_j^2 = q_j^2T_j/2`,
    and white noise whose average over :math:`D` seconds has variance :math:`a_{-1}/D`
    (Allan variance :math:`a_{-1}/\\tau`; :math:`N^2 = a_{-1}`).  Quantisation (white
    angle noise, an MA(1) with unit root in the rate) is not in the model.

Temporal aggregation of a flow (Harvey 1989, *Forecasting, Structural Time Series Models and
the Kalman Filter*, Cambridge, on temporal aggregation and on continuous-time models of flow
variables, observed as integrals over the sampling interval)
    The mean of ``L`` consecutive samples is the average over :math:`\\Delta = L\\,\\delta t`:
    the same model observed with the interval :math:`\\Delta`, so decimation by block means
    changes only :math:`\\Delta` and the likelihood of the block means is exact.  Over one
    interval, with :math:`h = \\Delta/T`, :math:`a = e^{-h}` (the exact discretisation of
    :class:`fogts.simulate.streams.GaussMarkov`, from the Ornstein-Uhlenbeck transition):

    * :math:`x_{k+1} = a x_k + u_k`, the interval mean is
      :math:`(1-a)x_k/h + v_k/\\Delta`, :math:`\\mathrm{var}\\,u = s^2(1-a^2)`,
      :math:`\\mathrm{var}\\,v = 2s^2T^2 f(h)`, :math:`f(h) = h - 2(1-a) + (1-a^2)/2`,
      :math:`\\mathrm{cov}(u,v) = s^2T(1-a)^2`;
    * :math:`W_{k+1} = W_k + r\\Delta + u`, interval mean :math:`W_k + r\\Delta/2 + v/\\Delta`,
      :math:`\\mathrm{var}\\,u = k^2\\Delta`, :math:`\\mathrm{var}\\,v = k^2\\Delta^3/3`,
      :math:`\\mathrm{cov}(u,v) = k^2\\Delta^2/2`.

    The state :math:`\\alpha_k = (W_k, r, x_{1,k}, \\dots, x_{m,k}, Z_k)` with :math:`W_k,
    x_{j,k}` the values at the end of block ``k`` and :math:`Z_k` the block mean of the
    random parts minus :math:`W_k` (so that no observation noise is correlated with a state
    noise, as the Kalman filter of statsmodels requires) gives :math:`y_k = W_k - r\\Delta/2
    + Z_k + \\varepsilon_k`, :math:`\\mathrm{var}\\,\\varepsilon = a_{-1}/\\Delta`, and
    :math:`Z_{k+1} = \\sum_j (1-a_j)x_{j,k}/h_j + z_{k+1}`, :math:`z = v_W/\\Delta - u_W +
    \\sum_j v_j/\\Delta`; the covariance of :math:`(u_W, u_1..u_m, z)` follows from the
    lines above.  ``W`` and ``r`` start diffuse (exact diffuse initialisation, Durbin &
    Koopman 2012, *Time Series Analysis by State Space Methods*, sec. 5.2: the likelihood
    does not depend on the unknown bias and ramp); the Gauss-Markov states start
    stationary.  The filter is statsmodels' (``statsmodels.tsa.statespace``), which switches
    to the steady-state gain once the state covariance has converged (its ``tolerance``).

The within-block part (decimation ``L > 1``)
    The block means drop the :math:`\\nu = n_b(L-1)` within-block contrasts, which carry
    nearly all the information on white noise.  They enter as an approximate likelihood:
    the within-block sum of squares :math:`S_w` as the sum of squares of :math:`\\nu`
    independent normals of variance :math:`c = E[S_w]/\\nu`, with :math:`E[S_w]` exact
    under the model (white :math:`(L-1)a_{-1}/\\delta t` per block; Gauss-Markov
    :math:`L(V_{\\delta t} - V_\\Delta)` with :math:`V_D = 2s^2(h-1+e^{-h})/h^2` the
    variance of an average over ``D``; the random walk from the covariance of interval
    means of Brownian motion; the ramp left out).  Exact when white noise dominates within
    a block, and independent of the block means only then; ``decimate=1`` avoids it.
    Measured against ``decimate=1`` (tests/README.md): shifts of log N, B, K within 0.1
    standard errors at ``L = 20``, standard errors 0-10 % larger.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import numpy.typing as npt
from statsmodels.tools.numdiff import approx_hess3
from statsmodels.tsa.statespace.initialization import Initialization
from statsmodels.tsa.statespace.kalman_filter import MEMORY_CONSERVE, KalmanFilter

from fogts._typing import FloatArray

__all__ = ["BlockData", "Structure", "block_data", "conditional_limit", "log_likelihood",
           "observed_cov", "state_space"]

_SMALL_H = 1e-3
#: A flicker pole with ``T < LUMP_SHARE * Delta`` enters the block means as white
#: noise of the variance of its block mean (the correlation of adjacent blocks is then
#: below ``s^2 (T/Delta)^2``, a few per cent of that variance at most).
LUMP_SHARE = 0.1


@dataclass(frozen=True)
class Structure:
    """Which processes the model has: ``white``, ``rw`` (random walk), ``n_gm`` free
    Gauss-Markov terms, ``drift``, and ``flicker``: the poles ``(T_i, w_i)`` of a fixed
    Markov-sum flicker whose pole variances are ``w_i B^2``.  Parameters, all logs in the
    scaled units of :class:`BlockData`: ``log a_-1`` (if white), ``log k^2`` (if rw),
    ``log B^2`` (if flicker), then ``log s_j^2, log T_j`` per free term."""

    white: bool
    rw: bool
    n_gm: int
    drift: bool
    flicker: tuple[tuple[float, float], ...] = ()

    @property
    def n_params(self) -> int:
        return int(self.white) + int(self.rw) + int(bool(self.flicker)) + 2 * self.n_gm

    @property
    def gm_index(self) -> int:
        """Index in theta of the first free Gauss-Markov term's ``log s^2``."""
        return int(self.white) + int(self.rw) + int(bool(self.flicker))

    def label(self) -> str:
        parts = ((["N"] if self.white else []) + (["B"] if self.flicker else [])
                 + (["K"] if self.rw else []) + ([f"{self.n_gm} GM"] if self.n_gm else [])
                 + (["R"] if self.drift else []))
        return " + ".join(parts)


@dataclass(frozen=True)
class BlockData:
    """A record as block means ``y`` (scaled by ``scale``: the data are ``y * scale``),
    the block length ``L``, the sampling interval ``dt`` (s), the within-block sum of
    squares ``s_within`` (scaled) and the number of samples used, ``n_used``."""

    y: FloatArray
    L: int
    dt: float
    scale: float
    s_within: float
    n_used: int

    @property
    def delta(self) -> float:
        return self.L * self.dt

    @property
    def n_blocks(self) -> int:
        return int(self.y.size)


def block_data(rate: FloatArray, dt: float, L: int) -> BlockData:
    """Block means of length ``L`` of ``rate`` (the incomplete last block dropped), scaled
    by the RMS of the first differences over sqrt(2) (the white level), and the
    within-block sum of squares."""
    n_b = rate.size // L
    used = rate[: n_b * L]
    scale = float(np.sqrt(np.mean(np.diff(used) ** 2) / 2.0)) or 1.0
    x = (used / scale).reshape(n_b, L)
    means = x.mean(axis=1)
    s_w = float(np.sum((x - means[:, None]) ** 2)) if L > 1 else 0.0
    return BlockData(np.ascontiguousarray(means), L, dt, scale, s_w, n_b * L)


def _gm_moments(s2: float, t_c: float, delta: float) -> tuple[float, float, float, float]:
    """``(a, var u, var v / delta^2, cov(u, v) / delta)`` of a Gauss-Markov term over one
    interval ``delta`` (module docstring); series in ``h`` below 1e-3."""
    h = delta / t_c
    one_minus_a = -math.expm1(-h)
    if h < _SMALL_H:
        f_over_h2 = h / 3 - h**2 / 4 + 7 * h**3 / 60 - h**4 / 24
    else:
        f_over_h2 = (h - 2 * one_minus_a - math.expm1(-2 * h) / 2) / h**2
    return (1.0 - one_minus_a, s2 * -math.expm1(-2 * h), 2 * s2 * f_over_h2,
            s2 * one_minus_a**2 / h)


def _avg_var(s2: float, t_c: float, d: float) -> float:
    """Variance of the average of a Gauss-Markov process over ``d`` s."""
    h = d / t_c
    if h < _SMALL_H:
        return s2 * (1 - h / 3 + h**2 / 12 - h**3 / 60)
    return s2 * 2 * (h + math.expm1(-h)) / h**2


def _unpack(theta: FloatArray, st: Structure) -> tuple[float, float, list[tuple[float, float]]]:
    """``a_-1``, ``k^2`` and every Gauss-Markov ``(s^2, T)``: the free ones, then the
    flicker poles."""
    ex = np.exp(np.asarray(theta, dtype=np.float64))
    i = 0
    a_white = k2 = b2 = 0.0
    if st.white:
        a_white, i = float(ex[0]), 1
    if st.rw:
        k2, i = float(ex[i]), i + 1
    if st.flicker:
        b2, i = float(ex[i]), i + 1
    gms = [(float(ex[i + 2 * j]), float(ex[i + 2 * j + 1])) for j in range(st.n_gm)]
    return a_white, k2, gms + [(w * b2, t) for t, w in st.flicker]


@dataclass(frozen=True)
class Matrices:
    """State-space matrices of one parameter vector: ``T``, ``Q`` (state noise covariance,
    selection = identity), ``Z`` (design), ``H`` (observation variance), ``P1`` (the
    non-diffuse initial covariance) and ``n_diffuse`` (leading diffuse states)."""

    T: FloatArray
    Q: FloatArray
    Z: FloatArray
    H: float
    P1: FloatArray
    n_diffuse: int


def state_space(theta: FloatArray, st: Structure, delta: float,
                level_var: float | None = None) -> Matrices:
    """The matrices of the block-mean model (module docstring) for interval ``delta``.

    ``level_var`` None: ``W`` (and ``r``) diffuse; a number: ``W_0 ~ N(0, level_var)``
    known (no drift), the initial covariance then includes ``W``'s share of block 1."""
    a_white, k2, all_gms = _unpack(theta, st)
    lumped = [j >= st.n_gm and t < delta * LUMP_SHARE for j, (_, t) in enumerate(all_gms)]
    gms = [g for g, lump in zip(all_gms, lumped, strict=True) if not lump]
    a_white += delta * sum(_avg_var(s2, t, delta)
                           for (s2, t), lump in zip(all_gms, lumped, strict=True) if lump)
    nd = 1 + int(st.drift)
    k = nd + len(gms) + 1
    T, Q, Z = np.zeros((k, k)), np.zeros((k, k)), np.zeros(k)
    z_i = k - 1
    T[0, 0], Z[0], Z[z_i] = 1.0, 1.0, 1.0
    if st.drift:
        T[0, 1], T[1, 1], Z[1] = delta, 1.0, -delta / 2
    Q[0, 0], Q[0, z_i] = k2 * delta, -k2 * delta / 2
    Q[z_i, z_i] = k2 * delta / 3
    for j, (s2, t_c) in enumerate(gms):
        i = nd + j
        a, var_u, var_v, cov_uv = _gm_moments(s2, t_c, delta)
        T[i, i], T[z_i, i] = a, (1 - a) * t_c / delta
        Q[i, i], Q[i, z_i] = var_u, cov_uv
        Q[z_i, z_i] += var_v
    Q[z_i, 0] = Q[0, z_i]
    Q[z_i, nd:z_i] = Q[nd:z_i, z_i]
    P0 = np.zeros((k, k))
    for j, (s2, _) in enumerate(gms):
        P0[nd + j, nd + j] = s2
    if level_var is not None:
        P0[0, 0] = level_var
        nd = 0
    P1 = T @ P0 @ T.T + Q
    if nd:
        P1[:nd, :] = 0.0
        P1[:, :nd] = 0.0
    return Matrices(T, Q, Z, a_white / delta, P1, nd)


def _filter(m: Matrices, y: FloatArray, *, tolerance: float = 1e-19) -> KalmanFilter:
    k = m.T.shape[0]
    kf = KalmanFilter(k_endog=1, k_states=k, k_posdef=k, tolerance=tolerance)
    kf.bind(y)
    kf["design"] = m.Z[None, :]
    kf["obs_cov"] = np.array([[m.H]])
    kf["transition"] = m.T
    kf["selection"] = np.eye(k)
    kf["state_cov"] = m.Q
    init = Initialization(k)
    if m.n_diffuse:
        init.set((0, m.n_diffuse), "diffuse")
    rest = k - m.n_diffuse
    init.set((m.n_diffuse, k), "known", constant=np.zeros(rest),
             stationary_cov=m.P1[m.n_diffuse:, m.n_diffuse:])
    kf.initialize(init)
    return kf


def block_loglike(theta: FloatArray, st: Structure, data: BlockData, *,
                  level_var: float | None = None, tolerance: float = 1e-19) -> float:
    """Exact (diffuse) log-likelihood of the scaled block means by statsmodels' Kalman
    filter; ``tolerance`` 0 disables its steady-state shortcut."""
    kf = _filter(state_space(theta, st, data.delta, level_var), data.y, tolerance=tolerance)
    kf.conserve_memory = MEMORY_CONSERVE
    return float(kf.loglike())


def within_expected(theta: FloatArray, st: Structure, L: int, dt: float) -> float:
    """``E[S_w]`` per block, scaled units (module docstring)."""
    a_white, k2, gms = _unpack(theta, st)
    out = (L - 1) * a_white / dt
    out += k2 * _bm_within(L, dt)
    for s2, t_c in gms:
        out += L * (_avg_var(s2, t_c, dt) - _avg_var(s2, t_c, L * dt))
    return out


def _bm_within(L: int, dt: float) -> float:
    """``E sum_i (y_i - ybar)^2`` over one block for unit-diffusion Brownian motion
    observed as interval means ``y_i`` of width ``dt``: ``tr C - 1'C1 / L`` with
    ``C_ii = (i - 2/3) dt``, ``C_ij = (min(i, j) - 1/2) dt`` (``i, j = 1..L``)."""
    i = np.arange(1, L + 1, dtype=np.float64)
    tr = float(np.sum(i - 2.0 / 3.0))
    ones = tr + 2.0 * float(np.sum((i - 0.5) * (L - i)))
    return dt * (tr - ones / L)


def within_loglike(theta: FloatArray, st: Structure, data: BlockData) -> float:
    """The approximate likelihood of the within-block contrasts (module docstring)."""
    if data.L == 1:
        return 0.0
    nu = data.n_blocks * (data.L - 1)
    c = within_expected(theta, st, data.L, data.dt) / (data.L - 1)
    return -0.5 * (nu * math.log(2 * math.pi * c) + data.s_within / c)


def log_likelihood(theta: FloatArray, st: Structure, data: BlockData) -> float:
    """Block-mean plus within-block log-likelihood of the scaled data."""
    return block_loglike(theta, st, data) + within_loglike(theta, st, data)


def final_state(theta: FloatArray, st: Structure, data: BlockData
                ) -> tuple[FloatArray, FloatArray]:
    """The filtered state and its covariance after the last block (the ramp ``r`` is
    state 1 when ``st.drift``)."""
    kf = _filter(state_space(theta, st, data.delta), data.y)
    res = kf.filter()
    return (np.asarray(res.filtered_state[:, -1], dtype=np.float64),
            np.asarray(res.filtered_state_cov[:, :, -1], dtype=np.float64))


def conditional_limit(theta: FloatArray, i: int, st: Structure, data: BlockData, z: float
                      ) -> float:
    """The largest ``theta[i]`` with ``2 (logL(theta) - logL) <= z^2``, the other parameters
    held at ``theta`` (a likelihood-ratio bound for a variance the fit puts at zero;
    conditional, not profiled, so somewhat narrow); bisection on the log scale."""
    ll0 = log_likelihood(theta, st, data)

    def excess(v: float) -> float:
        t = np.array(theta, dtype=np.float64)
        t[i] = v
        return 2.0 * (ll0 - log_likelihood(t, st, data)) - z * z

    lo = hi = float(theta[i])
    while excess(hi) < 0 and hi < lo + 60:
        hi += 2.0
    for _ in range(30):
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if excess(mid) < 0 else (lo, mid)
    return hi


def observed_cov(theta: FloatArray, st: Structure, data: BlockData,
                 free: npt.NDArray[np.bool_]) -> FloatArray:
    """Inverse observed information, the inverse numerical Hessian of ``-log L``
    (pseudo-inverse if singular), in the log parameters of ``theta``.  A parameter at its
    lower bound (``free`` False), or one whose variance comes out non-positive (the
    likelihood is flat or curves the wrong way there: it is not identified; one at a time,
    the most negative first), is held fixed (zero rows and columns) and the others'
    covariance is the inverse of their own block of the Hessian.  Before, such a parameter left the Hessian indefinite, and the others'
    standard errors came out 0 (ADIS16405 run 4 Z: B and the Gauss-Markov term) or far too
    small (run 2 Z: K's 10x)."""
    idx, cov = np.flatnonzero(free), np.zeros((theta.size, theta.size))

    def nll(sub: FloatArray) -> float:
        t = theta.copy()
        t[idx] = sub
        return -log_likelihood(t, st, data)

    hess = approx_hess3(theta[idx], nll, epsilon=1e-4) if idx.size else np.zeros((0, 0))
    hess = 0.5 * (hess + hess.T)
    keep = np.arange(idx.size)
    while keep.size:
        sub = hess[np.ix_(keep, keep)]
        try:
            inv = np.linalg.inv(sub)
        except np.linalg.LinAlgError:
            inv = np.linalg.pinv(sub)
        if np.all(np.diag(inv) > 0):
            cov[np.ix_(idx[keep], idx[keep])] = inv
            break
        keep = np.delete(keep, int(np.argmin(np.diag(inv))))  # one at a time, worst first
    return cov
