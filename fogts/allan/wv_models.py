"""Theoretical Haar wavelet variance (WV) of the processes of a GMWM composite model.

The Haar wavelet variance and the Allan variance
    At the dyadic scales :math:`\\tau_j = 2^{j-1}\\Delta t` the Haar MODWT wavelet
    coefficient is half the difference of two adjacent averages of length :math:`m =
    2^{j-1}`, so its variance is half the Allan variance at :math:`\\tau = m\\Delta t`,

    .. math:: \\nu^2(\\tau) = \\sigma_A^2(\\tau) / 2,

    and the unbiased MODWT estimator of :math:`\\nu^2` (the :math:`N - 2m + 1` coefficients
    free of the boundary) is exactly half the overlapping Allan variance (Percival &
    Guttorp, "Long-memory processes, the Allan variance and wavelets", in *Wavelets in
    Geophysics*, Academic Press, 1994, pp. 325-344; Percival & Walden, *Wavelet Methods for
    Time Series Analysis*, Cambridge, 2000, sec. 8.6).  Every closed form below is
    therefore IEEE 952's Allan variance of the term halved; a scale is given here by its
    averaging time ``tau`` (s), Guerrier et al.'s :math:`\\tau_j = 2^j` is ``2 m``.

The processes (rate in the curve's unit, tau in s, :math:`\\Delta t = 1/f_s`)
    The four power laws of :mod:`fogts.allan.terms` (IEEE Std 952-1997 Annex C; DESIGN.md),
    with ``a_n = C_n^2`` the coefficient of :math:`\\tau^n` in :math:`\\sigma_A^2`:
    quantisation :math:`\\nu^2 = 3a_{-2}/(2\\tau^2)` (white angle noise; Guerrier et al.'s
    :math:`6Q^2/\\tau_j^2` with :math:`Q^2 = a_{-2}/\\Delta t^2`), white rate noise
    :math:`a_{-1}/(2\\tau)` (their :math:`\\sigma^2/\\tau_j` with :math:`\\sigma^2 =
    a_{-1}/\\Delta t`), rate random walk :math:`a_1\\tau/6` (the continuous, interval-
    averaged walk of IEEE 952; their sampled walk adds :math:`\\gamma^2/(6\\tau_j)`, a
    white-like term below the resolution of the fits here) and drift :math:`a_2\\tau^2/4`
    (their :math:`\\omega^2\\tau_j^2/16`).

    The first-order Gauss-Markov process sampled at :math:`\\Delta t` is the AR(1)
    :math:`x_k = \\phi x_{k-1} + e_k`, :math:`\\phi = e^{-\\Delta t/T_c}`, with stationary
    variance :math:`s^2`.  From the variance of a block sum of ``m`` samples,
    :math:`V_m = s^2[m(1+\\phi)/(1-\\phi) - 2\\phi(1-\\phi^m)/(1-\\phi)^2]`, and the
    covariance of adjacent block sums, :math:`C_m = s^2\\phi(1-\\phi^m)^2/(1-\\phi)^2`,
    :math:`\\sigma_A^2 = (V_m - C_m)/m^2`, i.e.

    .. math::

        \\nu^2(\\tau) = s^2\\,\\frac{m(1-\\phi^2) - 3\\phi + 4\\phi^{m+1} - \\phi^{2m+1}}
                                  {2m^2(1-\\phi)^2},

    the AR(1) WV of Guerrier, Skaloud, Stebler & Victoria-Feser (2013), "Wavelet-variance-
    based estimation for composite stochastic processes", *J. Am. Stat. Assoc.* 108(503),
    1021-1030, with their innovation variance :math:`\\sigma^2 = s^2(1-\\phi^2)`.  For
    :math:`\\delta = \\Delta t/T_c < 10^{-3}` the expression cancels; there the expansion in
    :math:`\\delta` at fixed :math:`h = m\\delta = \\tau/T_c` is used,

    .. math::

        \\frac{\\nu^2}{s^2} = \\frac{g(h)}{2h^2} + \\delta^2\\frac{4h - g(h)}{24h^2}
                            + O(\\delta^4), \\qquad g(h) = 2h - 3 + 4e^{-h} - e^{-2h},

    whose first term is half the Allan variance of the interval-averaged continuous
    Gauss-Markov process (IEEE 952 Annex C; :func:`fogts.allan.markov.markov_avar`, which
    also supplies the series of ``g`` at small ``h``).
"""

from __future__ import annotations

import math

import numpy as np

from fogts._typing import FloatArray
from fogts.allan.markov import markov_avar

__all__ = ["GM_PEAK", "ar1_wv", "power_law_wv", "wv_from_avar"]

#: Largest value of a Gauss-Markov WV per unit variance, nu^2 / s^2 (at tau ~ 1.89 T_c).
GM_PEAK = 0.1906
_SERIES_DELTA = 1e-3


def wv_from_avar(avar: FloatArray) -> FloatArray:
    """The Haar wavelet variance from the Allan variance, ``nu^2 = sigma_A^2 / 2``
    (module docstring; Percival & Guttorp 1994).

    Examples
    --------
    >>> wv_from_avar(np.array([2.0, 0.5])).tolist()
    [1.0, 0.25]
    """
    return np.asarray(avar, dtype=np.float64) / 2.0


def power_law_wv(a: float, power: int, tau: FloatArray) -> FloatArray:
    """Haar WV ``a tau^n / 2`` of one IEEE-952 power-law term (``a = C_n^2``; module
    docstring for each ``n``).

    Examples
    --------
    >>> power_law_wv(4.0, -1, np.array([1.0, 2.0])).tolist()   # white: a / (2 tau)
    [2.0, 1.0]
    """
    return np.asarray(0.5 * a * np.asarray(tau, dtype=np.float64) ** float(power),
                      dtype=np.float64)


def ar1_wv(s2: float, t_c: float, tau: FloatArray, dt: float) -> FloatArray:
    """Haar WV of a Gauss-Markov process of variance ``s2`` and correlation time ``t_c``
    (s) sampled every ``dt`` s, at averaging times ``tau`` (multiples of ``dt``); exact
    closed form or its small-``dt/t_c`` expansion (module docstring).

    Examples
    --------
    >>> round(float(ar1_wv(1.0, 1e-9, np.array([1.0]), 1.0)[0]), 6)   # white: s2 / (2 m)
    0.5
    >>> round(float(ar1_wv(2.0, 10.0, np.array([1e4]), 1.0)[0]) * 1e4, 2)  # ~ s2 T_c / tau
    19.99
    """
    tau = np.asarray(tau, dtype=np.float64)
    delta = dt / t_c
    if delta < _SERIES_DELTA:
        h = tau / t_c
        g_over_h2 = 2.0 * markov_avar(1.0, 1.0, h)  # markov_avar(1, 1, h) = g(h) / (2h^2)
        out = 0.5 * g_over_h2 + delta**2 * (4.0 / h - g_over_h2) / 24.0
        return np.asarray(s2 * out, dtype=np.float64)
    m = np.rint(tau / dt)
    one_minus = -math.expm1(-delta)                      # 1 - phi
    phi = 1.0 - one_minus
    e_m = -np.expm1(-m * delta)                          # 1 - phi^m
    num = m * (-math.expm1(-2.0 * delta)) - phi * e_m * (2.0 + e_m)
    return np.asarray(s2 * num / (2.0 * m**2 * one_minus**2), dtype=np.float64)
