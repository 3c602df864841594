"""Terms beyond the five of IEEE-952's power-law model: first-order Markov (exponentially
correlated) noise ``M`` and a sinusoid ``S``.

Their Allan variances are closed forms (IEEE Std 952-1997 Annex C, "exponentially
correlated (Markov) noise" and "sinusoidal noise"; El-Sheimy, Hou & Niu, "Analysis and
modeling of inertial sensors using Allan variance", IEEE Trans. Instrum. Meas. 57(1),
140-149, 2008, sec. II), with the rate in deg/h and tau in s:

.. math::

    \\sigma^2_M(\\tau) = \\frac{(q_c T_c)^2}{\\tau}\\Big[1 - \\frac{T_c}{2\\tau}
        \\big(3 - 4e^{-\\tau/T_c} + e^{-2\\tau/T_c}\\big)\\Big],
    \\qquad
    \\sigma^2_S(\\tau) = \\Omega_0^2\\,\\frac{\\sin^4(\\pi f_0\\tau)}{(\\pi f_0\\tau)^2},

where the Markov process has correlation time :math:`T_c` (s), driving noise
:math:`q_c` (deg/h/sqrt(s); PSD :math:`(q_cT_c)^2/(1+(2\\pi fT_c)^2)`) and stationary
standard deviation :math:`\\sigma = q_c\\sqrt{T_c/2}`, and the sinusoid amplitude
:math:`\\Omega_0` (deg/h) and frequency :math:`f_0` (Hz).  For a fixed :math:`T_c` (or
:math:`f_0`) each is linear in its squared amplitude, so it enters the noise fit as one
more non-negative column (:mod:`fogts.allan.noise_extra` profiles the nonlinear
parameter).

The model covariance of the estimates (:mod:`fogts.allan.covariance`) knows power laws
only; :class:`ExtendedCovariance` represents the Markov term at each tau by the power law
it follows there (white rate noise for :math:`\\tau \\ge T_c`, a rate random walk below,
with the same Allan variance), an approximation exact in both limits.  The sinusoid is
deterministic and, like the rate ramp, has no variance of its own.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from fogts._typing import FloatArray
from fogts.allan.covariance import RANDOM_TERMS, CovarianceModel
from fogts.allan.terms import TERM_POWER
from fogts.errors import DataError

__all__ = ["EXTRA_FAMILIES", "EXTRA_POWER", "EXTRA_TERMS", "ExtendedCovariance", "ExtraFamily", "ExtraTerm",
           "flicker_poles", "markov_avar", "sinusoid_avar", "split_terms"]

#: The optional terms: M (first-order Markov) and S (sinusoid), fitted after the five.
EXTRA_TERMS: tuple[str, ...] = ("M", "S")
#: The "power" of an optional term's design column: not a power law, so the covariance
#: model gives it no variance basis of its own.
EXTRA_POWER = 100


def markov_avar(q_c: float, T_c: float, tau_s: Any) -> FloatArray:
    """Allan variance of the interval-averaged first-order Markov process (IEEE 952 Annex C;
    El-Sheimy et al. 2008).

    sigma^2(tau) = (q_c T_c)^2 / tau [1 - T_c/(2 tau) (3 - 4 e^{-tau/T_c} + e^{-2 tau/T_c})],
    evaluated with a Taylor series for tau < 0.01 T_c (where the bracket cancels).

    Examples
    --------
    >>> round(float(markov_avar(1.0, 10.0, 1e4)[0]) * 1e4, 3)   # tau >> T_c: (q_c T_c)^2/tau
    99.85
    """
    tau = np.atleast_1d(np.asarray(tau_s, dtype=np.float64))
    h = tau / T_c
    num = np.empty_like(h)
    small = h < 1e-2
    hs = h[small]
    num[small] = 2 * hs**3 / 3 - hs**4 / 2 + 7 * hs**5 / 30 - hs**6 / 12
    hl = h[~small]
    num[~small] = 2 * hl - 3 + 4 * np.exp(-hl) - np.exp(-2 * hl)
    return np.asarray((q_c * T_c) ** 2 / tau * num / (2 * h), dtype=np.float64)


def sinusoid_avar(omega_0: float, f_0: float, tau_s: Any) -> FloatArray:
    """Allan variance of a sinusoid of amplitude ``omega_0`` and frequency ``f_0`` (Hz)
    (IEEE 952 Annex C; El-Sheimy et al. 2008): ``omega_0^2 sin^4(pi f_0 tau)/(pi f_0 tau)^2``.

    Examples
    --------
    >>> round(float(sinusoid_avar(1.0, 1.0, 0.5)[0]), 4)   # 1 / (pi/2)^2
    0.4053
    """
    x = math.pi * f_0 * np.atleast_1d(np.asarray(tau_s, dtype=np.float64))
    return np.asarray(omega_0**2 * np.sin(x) ** 4 / x**2, dtype=np.float64)


@dataclass(frozen=True)
class ExtraFamily:
    """One optional term: its Allan-variance basis for a value of its nonlinear parameter,
    and where that parameter is searched.

    ``basis(tau, theta)`` is the Allan variance for a unit squared amplitude; ``grid`` the
    number of log-spaced starting values of ``theta`` between ``lo_factor / tau_min``
    style bounds (:meth:`bounds`).
    """

    name: str
    description: str
    parameter: str
    parameter_unit: str
    amplitude: str
    amplitude_unit: str
    basis: Callable[[FloatArray, float], FloatArray]
    grid: int
    per_tau: bool  # the parameter is a time (T_c) rather than a frequency (f_0)

    def bounds(self, tau: FloatArray) -> tuple[float, float]:
        """Search range of the parameter: T_c in [tau_min/2, tau_max/2] (its Allan hump, at
        about 1.9 T_c, inside the data); f_0 in [0.25/tau_max, 0.5/tau_min] (the
        sinusoid's first peak, at 0.37/f_0, inside the data or just below it)."""
        if self.per_tau:
            return float(tau[0]) / 2.0, float(tau[-1]) / 2.0
        return 0.25 / float(tau[-1]), 0.5 / float(tau[0])

    def sigma(self, amplitude: float, parameter: float) -> float:
        """Standard deviation of the process (deg/h): ``q_c sqrt(T_c/2)`` for the Markov
        term, ``Omega_0/sqrt(2)`` for the sinusoid."""
        if self.per_tau:
            return amplitude * math.sqrt(parameter / 2.0)
        return amplitude / math.sqrt(2.0)


#: The optional terms' families, by name.
EXTRA_FAMILIES: dict[str, ExtraFamily] = {
    "M": ExtraFamily("M", "first-order Markov (correlated) noise", "T_c", "s", "q_c",
                     "deg/h/sqrt(s)", lambda tau, tc: markov_avar(1.0, tc, tau), grid=40,
                     per_tau=True),
    "S": ExtraFamily("S", "sinusoid", "f_0", "Hz", "Omega_0", "deg/h",
                     lambda tau, f0: sinusoid_avar(1.0, f0, tau), grid=240, per_tau=False),
}


def split_terms(terms: Sequence[str] | str) -> tuple[tuple[str, ...], tuple[str, ...]]:
    """The five-term names (order Q, N, B, K, R) and the optional ones (order M, S).

    Examples
    --------
    >>> split_terms("N,B,K,M")
    (('N', 'B', 'K'), ('M',))
    """
    from fogts.allan.terms import parse_terms, term_items

    also = f" ({' and '.join(EXTRA_TERMS)} may be added)"
    items = term_items(terms, also)
    extras = [str(t).strip().upper() for t in items
              if isinstance(t, str) and t.strip().upper() in EXTRA_TERMS]
    if len(set(extras)) != len(extras):
        raise DataError(f"terms must not repeat a term, got {terms!r}")
    rest = [t for t in items if not (isinstance(t, str) and t.strip().upper() in EXTRA_TERMS)]
    if not rest:
        raise DataError(f"terms must name at least one of Q, N, B, K, R besides "
                        f"{', '.join(extras) or 'nothing'}, got {terms!r}")
    return parse_terms(rest, also), tuple(e for e in EXTRA_TERMS if e in extras)


@dataclass(frozen=True)
class ExtraTerm:
    """A fitted optional term (M or S) and whether adding it is significant.

    Attributes
    ----------
    name, description : str
        The family's letter and words (:class:`ExtraFamily`): ``"M"``, first-order Markov
        (correlated) noise, or ``"S"``, a sinusoid.
    amplitude, amplitude_stderr : float
        ``q_c`` (deg/h/sqrt(s)) or ``Omega_0`` (deg/h); the standard error includes the
        parameter's uncertainty (profile delta method, :mod:`fogts.allan.noise_extra`).
    amplitude_unit : str
    parameter, parameter_stderr : float
        ``T_c`` (s) or ``f_0`` (Hz); the standard error from the curvature of the profile
        likelihood (NaN at the edge of the search range or on a flat profile).
    parameter_unit : str
    sigma, sigma_stderr : float
        The process's standard deviation in deg/h (:meth:`ExtraFamily.sigma`).
    chi2_drop : float
        Likelihood-ratio statistic of adding the term: the drop of -2 log L (the Gaussian
        likelihood of the variance estimates with the model covariance).
    df : int
        2 (amplitude and parameter).
    p_value : float
        ``P(chi2_df > chi2_drop)``.
    level : float
        The test's level; ``significant`` is ``p_value < level``.
    status : str
        ``"fitted"``, or ``"at_bound"`` / ``"dropped"`` when the fit put or left it at zero.
    at_edge : bool
        The best parameter lies at the edge of the search range.
    search_range : (float, float)
        Where the parameter was searched.
    avar_coeff : float
        The squared amplitude in the curve's units (``sigma^2 = avar_coeff basis``).
    """

    name: str
    description: str
    amplitude: float
    amplitude_stderr: float
    amplitude_unit: str
    parameter: float
    parameter_stderr: float
    parameter_unit: str
    sigma: float
    sigma_stderr: float
    chi2_drop: float
    df: int
    p_value: float
    level: float
    status: str
    at_edge: bool
    search_range: tuple[float, float]
    avar_coeff: float

    @property
    def significant(self) -> bool:
        return self.status == "fitted" and self.p_value < self.level

    def avar(self, tau_s: Any) -> FloatArray:
        """The term's Allan variance at ``tau_s`` in the curve's units squared."""
        tau = np.atleast_1d(np.asarray(tau_s, dtype=np.float64))
        if self.avar_coeff <= 0:
            return np.zeros_like(tau)
        return self.avar_coeff * EXTRA_FAMILIES[self.name].basis(tau, self.parameter)

    @property
    def verdict(self) -> str:
        """``adding M: chi2 drop X on 2 df, p = ...: significant`` (or not)."""
        word = "significant" if self.significant else "not significant"
        return (f"adding {self.name} ({self.description}): chi2 drop {self.chi2_drop:.3g} on "
                f"{self.df} df, p = {self.p_value:.3g}: {word} at {100 * self.level:g} %")

    def describe(self) -> str:
        """The estimates with standard errors and units, then the verdict."""
        fam = EXTRA_FAMILIES[self.name]
        edge = (f" (at the edge of the searched {self.search_range[0]:.3g}.."
                f"{self.search_range[1]:.3g} {self.parameter_unit})" if self.at_edge else "")
        return (f"{self.name}: {fam.parameter} = {self.parameter:.4g} ± "
                f"{self.parameter_stderr:.2g} {self.parameter_unit}{edge}, {fam.amplitude} = "
                f"{self.amplitude:.4g} ± {self.amplitude_stderr:.2g} {self.amplitude_unit}, "
                f"sigma = {self.sigma:.4g} ± {self.sigma_stderr:.2g} deg/h; {self.verdict}")

    def to_dict(self) -> dict[str, Any]:
        fam = EXTRA_FAMILIES[self.name]
        return {"name": self.name, "description": self.description,
                fam.amplitude: self.amplitude, f"{fam.amplitude}_stderr": self.amplitude_stderr,
                f"{fam.amplitude}_unit": self.amplitude_unit,
                fam.parameter: self.parameter, f"{fam.parameter}_stderr": self.parameter_stderr,
                f"{fam.parameter}_unit": self.parameter_unit,
                "sigma": self.sigma, "sigma_stderr": self.sigma_stderr, "sigma_unit": "deg/h",
                "chi2_drop": self.chi2_drop, "df": self.df, "p_value": self.p_value,
                "level": self.level, "significant": self.significant, "status": self.status,
                "at_edge": self.at_edge, "search_range": list(self.search_range),
                "verdict": self.verdict}


@dataclass(frozen=True)
class ExtendedCovariance(CovarianceModel):
    """:class:`CovarianceModel` with a Markov column (module docstring): ``markov`` is its
    column index and ``T_c``; ``tau`` the curve's taus.  Other non-power-law columns (a
    sinusoid) add nothing."""

    tau: FloatArray | None = None
    markov: tuple[int, float] | None = None

    def raw(self, a: FloatArray) -> FloatArray:
        if self.markov is None or self.tau is None:
            return super().raw(a)
        coef = np.zeros((self.tau.size, len(RANDOM_TERMS)))
        for j, p in enumerate(self.powers):
            if int(p) in RANDOM_TERMS:
                coef[:, RANDOM_TERMS.index(int(p))] = a[j]
        col, tc = self.markov
        share = a[col] * markov_avar(1.0, tc, self.tau)  # the Markov Allan variance
        white = self.tau >= tc
        coef[:, RANDOM_TERMS.index(TERM_POWER["N"])] += np.where(white, share * self.tau, 0.0)
        coef[:, RANDOM_TERMS.index(TERM_POWER["K"])] += np.where(white, 0.0,
                                                                 3.0 * share / self.tau)
        cov = np.einsum("ijpq,ip,jq->ij", self.basis, coef, coef)
        return np.asarray(0.5 * (cov + cov.T), dtype=np.float64)


FLICKER_PPD = 3           # Markov poles per decade of correlation time
FLICKER_LO_DECADES = 2    # poles start at dt / 10**2
FLICKER_HI_FACTOR = 10.0  # ... and end at >= 10 x the record length


def flicker_poles(fs_hz: float, duration_s: float) -> tuple[FloatArray, FloatArray]:
    """Correlation times T_i (s) and driving amplitudes q_i (per unit B, deg/h/sqrt(s) per
    deg/h) of the Markov sum that approximates flicker noise over a record.

    Three poles per decade from ``dt/100`` (on a grid aligned with dt) to at least
    ``10 x duration``, with q_i^2 = 2 Delta B^2 / (pi T_i) and Delta = ln(10)/3, so that
    sum_i (q_i T_i)^2 / (1 + (2 pi f T_i)^2) ~ B^2 / (2 pi f), the two-sided flicker PSD of
    IEEE 952 Table C.1; the ripple of the sum keeps the Allan plateau within 0.5 % of
    :data:`~fogts.allan.terms.B_PLATEAU` B from tau = 1/fs to half the record (Keshner, "1/f noise", Proc. IEEE 70(3), 1982,
    for the superposition of Lorentzian spectra).
    """
    dt = 1.0 / fs_hz
    k_lo = -FLICKER_LO_DECADES * FLICKER_PPD
    k_hi = math.ceil(FLICKER_PPD * math.log10(FLICKER_HI_FACTOR * duration_s / dt))
    T = dt * 10.0 ** (np.arange(k_lo, k_hi + 1) / FLICKER_PPD)
    delta = math.log(10.0) / FLICKER_PPD
    q = np.sqrt(2.0 * delta / (math.pi * T))
    return T, q
