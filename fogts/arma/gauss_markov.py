"""The first-order Gauss–Markov equivalent of an AR root: what a navigation filter needs.

A first-order Gauss–Markov process dx/dt = -x / T_c + w(t), with white w of two-sided
density q^2, sampled every dt is the AR(1) process x_k = phi x_{k-1} + a_k with

    phi = exp(-dt / T_c),   sigma^2 = q^2 T_c / 2,   var(a) = sigma^2 (1 - phi^2)

(the first-order Gauss–Markov process of Gelb 1974, ch. 3, and Brown & Hwang 2012,
ch. 2).  For an ARMA model the dominant real
AR root in (0, 1) gives T_c, and sigma^2 = var(a) / (1 - phi^2) is the steady-state
variance of that first-order part alone.

The root's standard error comes from the fit's covariance of (phi_1..phi_p) by the delta
method: an inverse root r solves P(r) = r^p - phi_1 r^(p-1) - ... - phi_p = 0, so
dr/dphi_i = r^(p-i) / P'(r) (implicit differentiation).  Its 95 % interval
r +- 1.96 se(r), mapped through the increasing T_c = -dt / ln r, is the interval of T_c.
A root whose interval reaches 0 is not told apart from white noise: no Gauss–Markov
state is identified.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np

from fogts.arma.whiteness import BAND_Z as _Z
from fogts.units import convert_rate

if TYPE_CHECKING:
    from fogts.arma.candidate import Candidate

__all__ = ["GaussMarkov", "gauss_markov", "root_stderr"]


@dataclass(frozen=True)
class GaussMarkov:
    """The Gauss–Markov equivalent of one AR root.

    Attributes
    ----------
    phi : float
        The real AR (inverse) root in (0, 1).
    dt_s : float
        The sample interval of the modelled series.
    tau_c_s : float
        Correlation time T_c = -dt / ln(phi).
    sigma, q : float
        Steady-state standard deviation (rate unit) and driving-noise density
        (rate unit / sqrt(s)); NaN where the model order does not separate them.
    white : float
        Standard deviation per sample of the white noise beside the process (ARMA(1,1);
        0 for AR(1); NaN otherwise).
    units : str
        The rate unit of ``sigma``, ``q`` and ``white``; :attr:`rad_s_per_unit` follows
        from it.
    model : str
        The ARMA model it was derived from.
    phi_stderr : float
        Standard error of ``phi`` (delta method, see the module docstring); NaN without the
        fit's covariance.
    tau_c_interval_s : tuple of float
        95 % interval of T_c from ``phi +- 1.96 phi_stderr``; the upper end is ``inf``
        where that interval reaches 1, the lower one 0 where it reaches 0 (NaN, NaN
        without a standard error).
    largest_complex : float
        Modulus of the largest complex AR root where it exceeds ``phi`` (an oscillation
        that outlasts this root), else 0.
    """

    phi: float
    dt_s: float
    tau_c_s: float
    sigma: float
    q: float
    white: float
    units: str
    model: str
    phi_stderr: float = math.nan
    tau_c_interval_s: tuple[float, float] = (math.nan, math.nan)
    largest_complex: float = 0.0

    @property
    def identified(self) -> bool:
        """Whether the root is told apart from 0 (white noise): ``phi - 1.96 se > 0``; True
        where there is no standard error to test it."""
        return not (self.phi - _Z * self.phi_stderr <= 0.0)

    @property
    def within_one_sample(self) -> bool:
        """Whether T_c is shorter than the sample interval (phi < 1/e): the state then
        decorrelates within one sample and acts as white noise at this rate."""
        return self.tau_c_s < self.dt_s

    @property
    def rad_s_per_unit(self) -> float:
        """One rate unit in rad/s: the factor of :attr:`sigma_si`, :attr:`q_si` and
        :attr:`white_si`, the same three in rad/s and rad/s/sqrt(s)."""
        return float(convert_rate(1.0, self.units, "rad/s"))

    @property
    def sigma_si(self) -> float:
        """``sigma`` in rad/s."""
        return self.sigma * self.rad_s_per_unit

    @property
    def q_si(self) -> float:
        """``q`` in rad/s/sqrt(s)."""
        return self.q * self.rad_s_per_unit

    @property
    def white_si(self) -> float:
        """``white`` in rad/s."""
        return self.white * self.rad_s_per_unit

    def to_dict(self) -> dict[str, Any]:
        return {"model": self.model, "phi": self.phi, "dt_s": self.dt_s,
                "tau_c_s": self.tau_c_s, "sigma": self.sigma, "q": self.q,
                "white": self.white, "units": self.units, "sigma_rad_s": self.sigma_si,
                "q_rad_s_sqrt_s": self.q_si, "white_rad_s": self.white_si,
                "phi_stderr": self.phi_stderr,
                "tau_c_interval_s": [self.tau_c_interval_s[0],
                                     None if math.isinf(self.tau_c_interval_s[1])
                                     else self.tau_c_interval_s[1]],
                "identified": self.identified, "within_one_sample": self.within_one_sample,
                "largest_complex": self.largest_complex}

    def summary(self) -> str:
        head = f"Gauss–Markov equivalent of {self.model}: "
        if not self.identified:
            return (head + f"none identified: its AR root {self.phi:.4g} (standard error "
                    f"{self.phi_stderr:.2g}) is within {_Z} standard errors of 0, so the "
                    "drift is white at this sample rate")
        text = head + f"T_c = {self.tau_c_s:.4g} s{self._interval_text()}"
        if self.within_one_sample:
            text += (f", under one sample interval ({self.dt_s:.4g} s): it decorrelates "
                     "within a sample and acts as white noise at this rate")
        if self.largest_complex > 0:
            text += (f"; an oscillating AR root pair of modulus {self.largest_complex:.4g} "
                     "outlasts it, which a first-order state does not describe")
        if not math.isfinite(self.sigma):
            return text + (" (sigma and q are not separable: an ARMA(1,1) is a Gauss–Markov "
                           "process plus white noise only with an MA coefficient between "
                           "-phi and 0, and this fit's is not)" if self.model == "ARMA(1,1)"
                           else " (sigma and q are not separable for this order)")
        text += (f", sigma = {self.sigma:.4g} {self.units} ({self.sigma_si:.4g} rad/s), "
                 f"q = {self.q:.4g} {self.units}/sqrt(s) ({self.q_si:.4g} rad/s/sqrt(s))")
        if self.white > 0:
            text += (f", plus white noise {self.white:.4g} {self.units} per sample "
                     f"({self.white_si:.4g} rad/s)")
        return text

    def _interval_text(self) -> str:
        low, high = self.tau_c_interval_s
        if not math.isfinite(low):
            return ""
        if math.isinf(high):
            return f" (95 %: over {low:.3g} s, unbounded above: the root's interval reaches 1)"
        return f" (95 %: {low:.3g} to {high:.3g} s)"


def gauss_markov(candidate: Candidate, fs_hz: float | None, units: str | None
                 ) -> GaussMarkov | None:
    """The Gauss–Markov equivalent of ``candidate``'s dominant real AR root in (0, 1);
    None when there is none, no sample rate or no unit, or the fit failed."""
    if candidate.roots is None or not fs_hz or not units or not candidate.ok:
        return None
    inverse = np.asarray(candidate.roots.ar_inverse)
    real = inverse[(np.abs(inverse.imag) < 1e-12) & (inverse.real > 0) & (inverse.real < 1)]
    if real.size == 0:
        return None
    phi = float(real.real.max())
    dt = 1.0 / fs_hz
    tau_c = -dt / math.log(phi)
    var_w, var_e = _split(candidate, phi)
    sigma = math.sqrt(var_w / (1.0 - phi * phi)) if var_w > 0 else math.nan
    q = sigma * math.sqrt(2.0 / tau_c)
    white = math.sqrt(var_e) if var_e >= 0 else math.nan
    se = root_stderr(phi, candidate.ar, _ar_covariance(candidate))
    oscillating = np.abs(inverse[np.abs(inverse.imag) >= 1e-12])
    top_complex = float(oscillating.max()) if oscillating.size else 0.0
    return GaussMarkov(phi=phi, dt_s=dt, tau_c_s=tau_c, sigma=sigma, q=q, white=white,
                       units=units, model=candidate.model, phi_stderr=se,
                       tau_c_interval_s=_tau_c_interval(phi, se, dt),
                       largest_complex=top_complex if top_complex > phi else 0.0)


def root_stderr(root: float, ar: Any, cov: Any) -> float:
    """Standard error of a simple real inverse AR root by the delta method.

    ``root`` solves P(r) = r^p - phi_1 r^(p-1) - ... - phi_p = 0 for the coefficients
    ``ar``; dr/dphi_i = r^(p-i) / P'(r), and var(r) = g' cov g with ``cov`` the
    covariance of ``ar``.  NaN without a covariance or at a repeated root (P'(r) = 0).
    """
    phi = np.asarray(ar, dtype=np.float64)
    p = phi.size
    if cov is None or p == 0:
        return math.nan
    cov = np.asarray(cov, dtype=np.float64)[:p, :p]
    powers = root ** np.arange(p - 1, -1, -1, dtype=np.float64)      # r^(p-i), i = 1..p
    slope = p * root ** (p - 1) - float(np.dot(np.arange(p - 1, 0, -1) * phi[:-1],
                                               powers[1:])) if p > 1 else 1.0
    if slope == 0.0 or not np.all(np.isfinite(cov)):
        return math.nan
    g = powers / slope
    var = float(g @ cov @ g)
    return math.sqrt(var) if var >= 0.0 else math.nan


def _ar_covariance(candidate: Candidate) -> Any:
    """The fit's covariance of (phi_1..phi_p), or the diagonal of the standard errors."""
    fit = candidate.fit
    if fit is not None and fit.coef_cov is not None:
        return fit.coef_cov
    se = [candidate.bse.get(f"ar.L{i}", math.nan) for i in range(1, candidate.p + 1)]
    return np.diag(np.square(se))


def _tau_c_interval(phi: float, se: float, dt: float) -> tuple[float, float]:
    """T_c = -dt / ln r at the ends of r's 95 % interval, clipped to (0, 1)."""
    if not math.isfinite(se):
        return math.nan, math.nan
    low, high = phi - _Z * se, phi + _Z * se
    t_low = -dt / math.log(low) if low > 0.0 else 0.0
    t_high = -dt / math.log(high) if high < 1.0 else math.inf
    return t_low, t_high


def _split(candidate: Candidate, phi: float) -> tuple[float, float]:
    """(var(w), var(e)): the Gauss–Markov driving variance per sample and the white noise
    beside it; NaN where the order does not allow the split (see the module docstring).

    A Gauss–Markov process plus white noise e is the ARMA(1,1) whose lag-0 and lag-1 MA
    autocovariances are var(w) + var(e)(1 + phi^2) = sigma2 (1 + theta^2) and
    -phi var(e) = theta sigma2, so var(e) = -theta sigma2 / phi >= 0 needs theta <= 0
    and var(w) > 0 needs (phi + theta)(1 + phi theta) > 0, i.e. theta > -phi.
    """
    s2 = candidate.sigma2
    if (candidate.p, candidate.q) == (1, 0):
        return s2, 0.0
    if (candidate.p, candidate.q) == (1, 1):
        theta = float(candidate.params.get("ma.L1", math.nan))
        if theta < 0:
            var_e = -theta * s2 / phi
            return s2 * (1.0 + theta * theta) - var_e * (1.0 + phi * phi), var_e
    return math.nan, math.nan
