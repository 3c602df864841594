"""The first-order Gauss–Markov equivalent of an AR root: what a navigation filter needs.

A first-order Gauss–Markov process dx/dt = -x / T_c + w(t), with white w of two-sided
density q^2, sampled every dt is the AR(1) process x_k = phi x_{k-1} + a_k with

    phi = exp(-dt / T_c),   sigma^2 = q^2 T_c / 2,   var(a) = sigma^2 (1 - phi^2)

(the first-order Gauss–Markov process of Gelb 1974, ch. 3, and Brown & Hwang 2012,
ch. 2).  For an ARMA model the dominant real
AR root in (0, 1) gives T_c, and sigma^2 = var(a) / (1 - phi^2) is the steady-state
variance of that first-order part alone.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np

from fogts.units import convert_rate

if TYPE_CHECKING:
    from fogts.arma.candidate import Candidate

__all__ = ["GaussMarkov", "gauss_markov"]


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
    """

    phi: float
    dt_s: float
    tau_c_s: float
    sigma: float
    q: float
    white: float
    units: str
    model: str

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
                "q_rad_s_sqrt_s": self.q_si, "white_rad_s": self.white_si}

    def summary(self) -> str:
        text = f"Gauss–Markov equivalent of {self.model}: T_c = {self.tau_c_s:.4g} s"
        if not math.isfinite(self.sigma):
            return text + " (sigma and q are not separable for this order)"
        text += (f", sigma = {self.sigma:.4g} {self.units} ({self.sigma_si:.4g} rad/s), "
                 f"q = {self.q:.4g} {self.units}/sqrt(s) ({self.q_si:.4g} rad/s/sqrt(s))")
        if self.white > 0:
            text += (f", plus white noise {self.white:.4g} {self.units} per sample "
                     f"({self.white_si:.4g} rad/s)")
        return text


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
    return GaussMarkov(phi=phi, dt_s=dt, tau_c_s=tau_c, sigma=sigma, q=q, white=white,
                       units=units, model=candidate.model)


def _split(candidate: Candidate, phi: float) -> tuple[float, float]:
    """(var(w), var(e)): the Gauss–Markov driving variance per sample and the white noise
    beside it; NaN where the order does not allow the split (see the module docstring)."""
    s2 = candidate.sigma2
    if (candidate.p, candidate.q) == (1, 0):
        return s2, 0.0
    if (candidate.p, candidate.q) == (1, 1):
        theta = float(candidate.params.get("ma.L1", math.nan))
        if theta < 0:
            var_e = -theta * s2 / phi
            return s2 * (1.0 + theta * theta) - var_e * (1.0 + phi * phi), var_e
    return math.nan, math.nan
