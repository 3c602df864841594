"""An independent gyro simulator whose bias instability is a sum of Gauss–Markov processes.

Real FOG and MEMS bias instability is not the ideal flat 1/f of the IEEE-952 B term: it is
well described by a few first-order Gauss–Markov (GM) processes with spread correlation
times, whose Allan deviation has a flat-ish plateau with ripples and rolls off at both ends.
This module simulates such records *without* :func:`fogts.simulate.simulate_gyro`, so that
the noise fit is checked against a generator it was not built with:

    y_k = w_k + sum_j g_{j,k} + r_k          (rate in deg/h, sample k at fs_hz)

* ``w``: white rate noise, sd ``60 N sqrt(fs)`` (N in deg/sqrt(h));
* ``g_j``: stationary AR(1) ``g_{j,k} = phi_j g_{j,k-1} + sqrt(1 - phi_j^2) s e_k``,
  ``phi_j = exp(-1/(fs T_j))``, the exact samples of a GM process with correlation time
  ``T_j`` and steady-state sd ``s`` (the same for every j: equal power per log-spaced
  correlation time is the classical sum-of-Lorentzians approximation of a 1/f spectrum,
  e.g. Keshner, Proc. IEEE 70(3), 1982);
* ``r``: rate random walk with increments of sd ``(K/60) / sqrt(fs)`` (K in deg/h^1.5).

Truth
    The expected overlapping Allan variance of this sample sequence is known exactly
    (:func:`expected_avar`): ``sigma_w^2 / m`` for the white part, ``q^2 (2 m^2 + 1) /
    (6 m)`` for a discrete random walk with increment variance ``q^2``, and for each
    AR(1) ``(V_m - C_m) / m^2`` with ``V_m`` the variance of a block sum of ``m`` samples
    and ``C_m`` the covariance of adjacent block sums (geometric sums of ``s^2 phi^h``).
    N and K are the simulator's own white and random-walk parameters.  B has no value in
    the simulator; its truth is *defined* as the flicker-equivalent level of the GM sum:
    the ``B`` for which ``(2 ln 2 / pi) B^2`` matches the GM sum's exact Allan variance
    best (least squares in log sigma^2) over the octave taus of its plateau,
    ``2 T_min <= tau <= T_max / 2``.  The GM amplitude ``s`` is scaled so that this
    equals the grade's B.  :func:`curve_departure` reports how far the exact curve then
    lies from the five-term curve ``N^2/tau + (2 ln 2/pi) B^2 + K^2 tau/3``: that
    departure (a few per cent, the GM sum's ripple and roll-off) is the model misfit the
    fit's intervals must account for.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy.signal import lfilter

#: Correlation times of the GM processes (s): five, log-spaced from 1 s to 3000 s.
DEFAULT_TIMES_S: tuple[float, ...] = tuple(float(t) for t in np.geomspace(1.0, 3000.0, 5))
#: Flicker Allan variance per B^2 (IEEE 952 Annex C).
FLICKER = 2.0 * math.log(2.0) / math.pi


@dataclass(frozen=True)
class GaussMarkovGyro:
    """White rate noise N, a GM sum with flicker-equivalent level B, rate random walk K.

    Units: N deg/sqrt(h), B deg/h, K deg/h^1.5; the rate is simulated in deg/h.
    """

    N: float
    B: float
    K: float
    times_s: tuple[float, ...] = DEFAULT_TIMES_S

    def gm_sd(self, fs_hz: float) -> float:
        """Steady-state sd of each GM process (deg/h) that makes the plateau level B."""
        unit = _gm_avar(self._plateau_taus(), fs_hz, self.times_s, 1.0)
        b_unit = math.sqrt(math.exp(float(np.mean(np.log(unit)))) / FLICKER)
        return self.B / b_unit

    def _plateau_taus(self) -> np.ndarray:
        lo, hi = 2.0 * min(self.times_s), 0.5 * max(self.times_s)
        return 2.0 ** np.arange(math.ceil(math.log2(lo)), math.floor(math.log2(hi)) + 1)

    def simulate(self, *, fs_hz: float, duration_s: float, seed: int) -> np.ndarray:
        """One record of ``round(duration_s * fs_hz)`` rate samples (deg/h)."""
        n = round(duration_s * fs_hz)
        rng = np.random.default_rng(seed)
        y = 60.0 * self.N * math.sqrt(fs_hz) * rng.standard_normal(n)
        s = self.gm_sd(fs_hz)
        for t in self.times_s:
            phi = math.exp(-1.0 / (fs_hz * t))
            drive = math.sqrt(-math.expm1(-2.0 / (fs_hz * t))) * s * rng.standard_normal(n)
            start = s * float(rng.standard_normal())  # the stationary initial state
            g, _ = lfilter([1.0], [1.0, -phi], drive, zi=[phi * start])
            y += g
        y += np.cumsum((self.K / 60.0) / math.sqrt(fs_hz) * rng.standard_normal(n))
        return y

    def expected_avar(self, tau_s: np.ndarray, fs_hz: float) -> np.ndarray:
        """Exact expected (overlapping) Allan variance of the simulated samples, (deg/h)^2."""
        m = np.rint(np.asarray(tau_s, dtype=np.float64) * fs_hz)
        white = (60.0 * self.N) ** 2 * fs_hz / m
        q2 = (self.K / 60.0) ** 2 / fs_hz
        walk = q2 * (2.0 * m**2 + 1.0) / (6.0 * m)
        return white + walk + _gm_avar(m / fs_hz, fs_hz, self.times_s, self.gm_sd(fs_hz))

    def five_term_avar(self, tau_s: np.ndarray) -> np.ndarray:
        """The ideal curve N^2/tau + (2 ln 2/pi) B^2 + K^2 tau/3 with this truth."""
        tau = np.asarray(tau_s, dtype=np.float64)
        return (60.0 * self.N) ** 2 / tau + FLICKER * self.B**2 + (self.K / 60.0) ** 2 * tau / 3


def _gm_avar(tau_s: np.ndarray, fs_hz: float, times_s: tuple[float, ...],
             sd: float) -> np.ndarray:
    """Exact Allan variance of a sum of sampled AR(1) processes (module docstring)."""
    m = np.rint(np.asarray(tau_s, dtype=np.float64) * fs_hz)
    out = np.zeros(m.shape)
    for t in times_s:
        one_minus = -math.expm1(-1.0 / (fs_hz * t))       # 1 - phi, without cancellation
        phi = 1.0 - one_minus
        one_minus_pm = -np.expm1(-m / (fs_hz * t))          # 1 - phi^m
        block_var = m * (1.0 + phi) / one_minus - 2.0 * phi * one_minus_pm / one_minus**2
        adjacent = phi * one_minus_pm**2 / one_minus**2
        out += sd**2 * (block_var - adjacent) / m**2
    return out


def curve_departure(gyro: GaussMarkovGyro, tau_s: np.ndarray, fs_hz: float) -> np.ndarray:
    """Exact Allan deviation of the simulator over the ideal five-term one, per tau."""
    return np.sqrt(gyro.expected_avar(tau_s, fs_hz) / gyro.five_term_avar(tau_s))
