"""IEEE-952 noise terms from an Allan-variance curve, with uncertainties.

The five classical terms of IEEE Std 952-1997 Annex C (seed 000; DESIGN.md "Definitions")
add in the Allan variance of a rate signal:

.. math::

    \\sigma^2(\\tau) = \\frac{R^2\\tau^2}{2} + \\frac{K^2\\tau}{3} + B^2\\frac{2\\ln 2}{\\pi}
                     + \\frac{N^2}{\\tau} + \\frac{3Q^2}{\\tau^2}
                   = \\sum_{n=-2}^{2} C_n^2\\,\\tau^n .

The model is linear in the squared coefficients :math:`a_n = C_n^2 \\ge 0`, so
:func:`fit_noise` solves a non-negative least-squares problem (``scipy.optimize.nnls``) on
:math:`\\sigma^2(\\tau)`.

Weights (``method="wls"``, the default)
    An Allan-variance estimate with ``edf`` equivalent degrees of freedom is distributed as
    :math:`\\sigma^2\\chi^2_{edf}/edf`, so :math:`\\mathrm{Var}[\\hat\\sigma^2] = 2\\sigma^4/edf`
    (NIST SP1065 sec. 5.3; IEEE 952 C.3 gives the same through
    :math:`1/\\sqrt{2(N/m-1)}`).  Each point is weighted by the inverse of that variance,
    evaluated at the *model* value rather than the noisy observation (a weight computed from
    the observation favours points that happen to fall low, and biases the fit
    downwards).  Because the weight depends on the fit, the fit is iterated (IRLS) from
    observation-based weights until the model changes by less than ``1e-7`` relative; the
    fixed point is the quasi-likelihood estimate of a Gamma GLM with identity link
    (McCullagh & Nelder, *Generalized Linear Models*, 1989, ch. 8), restricted to
    :math:`a_n \\ge 0`.  So long-tau points, with few terms and few degrees of freedom, count
    for less.  The EDF comes from the Allan result (Greenhall's algorithm); where it is
    missing it falls back to IEEE 952's :math:`N/m - 1`, recorded in ``edf_source``.

Density of the tau grid
    Estimates at neighbouring taus are strongly correlated when the taus are closer than an
    octave (the same data enter both).  Treating them as independent would let a ``dense``
    or ``all`` grid count the same information many times, mostly at long tau where an
    ``all`` grid puts nearly all its points.  Each point's weight is therefore multiplied by
    the width (in octaves, at most 1) of the tau interval it represents, i.e. half the
    log2-distance to its neighbours.  On octave or sparser grids this factor is 1.

Standard errors and confidence intervals
    The covariance of the active (non-zero) coefficients is the inverse of the weighted
    normal matrix :math:`(A^T W A)^{-1}`, multiplied by the dispersion
    :math:`\\max(1, \\chi^2_{Pearson}/dof)` so that a model that does not fit the curve does
    not report over-confident errors.  The correlation between overlapping estimates at
    octave-spaced taus is ignored, as usual; the errors are approximate.  Each ``a_n``
    gets the normal interval :math:`a_n \\pm z\\,se(a_n)` clipped at 0, and ``C_n`` the square
    roots of its ends; the standard error of ``C_n`` is the delta-method value
    :math:`se(a_n)/(2C_n)`.  A term estimated at the zero bound has no standard error
    (``stderr`` is NaN, ``at_bound`` is True): its interval is ``[0, sqrt(z se)]`` where
    ``se`` comes from the normal matrix of the active set plus that term, i.e. an upper limit.

Unit conversion (DESIGN.md; seed paper)
    With rate in deg/h and tau in s: ``N = C_-1/60`` deg/sqrt(h), ``B = C_0/0.664`` deg/h,
    ``K = 60 sqrt(3) C_1`` deg/h^1.5, ``R = 3600 sqrt(2) C_2`` deg/h^2 and
    ``Q = C_-2/sqrt(3)`` (deg/h)*s = arcsec.  Other input units are converted with
    :func:`fogts.units.to_deg_per_hour_factor`.  Note that the exact bias-instability factor
    of the model is :math:`\\sqrt{2\\ln 2/\\pi} = 0.66428`; the reported ``B`` uses the
    rounded 0.664 of IEEE 952 and the seed paper (0.04 % apart), while the fitted curves are
    computed from the ``C_n`` and are exact.

Identifiability
    A term is *identifiable* when its own line is the largest contribution to the fitted
    curve at at least two of the data's taus.  Otherwise its tau region is not covered by
    the data (it would dominate only outside the measured range, or nowhere), its value
    is at best an upper limit, and :class:`~fogts.errors.UnidentifiableTermWarning` is
    emitted and recorded.

The classic slope read-offs (IEEE 952 Annex C; MATLAB's ``allanvar`` example) are reported
beside the fit for comparison, never as the answer: N from the -1/2 line at tau = 1 s, K
from the +1/2 line at tau = 3 s, B from the minimum of the curve divided by 0.664.
"""

from __future__ import annotations

import math
import warnings
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from typing import Any, Literal, Protocol, get_args

import numpy as np
import pandas as pd
from scipy.optimize import brentq, nnls
from scipy.stats import norm

from fogts._typing import FloatArray
from fogts._validate import check_choice, check_fraction
from fogts.allan.readout import TERM_SLOPES, read_curve
from fogts.errors import (
    ConvergenceWarning,
    DataError,
    DataQualityWarning,
    InsufficientDataError,
    UnidentifiableTermWarning,
)
from fogts.units import parse_rate_unit, to_deg_per_hour_factor

__all__ = [
    "NOISE_TERMS",
    "NoiseModel",
    "NoiseTerm",
    "SlopeReadoff",
    "c_from_terms",
    "fit_noise",
    "terms_from_c",
]

TermName = Literal["Q", "N", "B", "K", "R"]
FitMethod = Literal["wls", "ols"]
NOISE_TERMS: tuple[str, ...] = get_args(TermName)
FIT_METHODS: tuple[str, ...] = get_args(FitMethod)
#: Allan-variance kinds whose expected value follows the IEEE-952 tau laws.  (The modified
#: and Hadamard variances have other constants, so their curves cannot be fitted here.)
FITTABLE_KINDS: tuple[str, ...] = ("adev", "oadev", "totdev")

#: Power of tau of each term's basis function in sigma^2(tau) = sum a_n tau^n.
TERM_POWER: dict[str, int] = {"Q": -2, "N": -1, "B": 0, "K": 1, "R": 2}
#: term value (deg/h-based units) = factor * C_n (rate in deg/h, tau in s); DESIGN.md.
TERM_FACTOR: dict[str, float] = {
    "Q": 1.0 / math.sqrt(3.0),
    "N": 1.0 / 60.0,
    "B": 1.0 / 0.664,
    "K": 60.0 * math.sqrt(3.0),
    "R": 3600.0 * math.sqrt(2.0),
}
TERM_UNIT: dict[str, str] = {"Q": "arcsec", "N": "deg/sqrt(h)", "B": "deg/h",
                             "K": "deg/h^1.5", "R": "deg/h^2"}
C_UNIT: dict[str, str] = {"Q": "deg/h*s", "N": "deg/h*sqrt(s)", "B": "deg/h",
                          "K": "deg/h/sqrt(s)", "R": "deg/h/s"}
TERM_DESCRIPTION: dict[str, str] = {"Q": "quantization", "N": "angle random walk",
                                    "B": "bias instability", "K": "rate random walk",
                                    "R": "rate ramp"}

#: A term must dominate the fitted curve at this many data taus to count as identified.
MIN_DOMINANT_POINTS = 2
_IRLS_MAX_ITER = 50
_IRLS_TOL = 1e-7


class AllanLike(Protocol):
    """What :func:`fit_noise` reads from an :class:`~fogts.allan.result.AllanResult`."""

    kind: str
    units: str
    axis: str
    tau_s: FloatArray
    dev: FloatArray


# --------------------------------------------------------------------------- conversions


def terms_from_c(c: Mapping[str | int, float]) -> dict[str, float]:
    """Convert seed-paper coefficients ``C_n`` (rate in deg/h, tau in s) to IEEE-952 terms.

    Parameters
    ----------
    c : mapping
        ``C_n`` keyed by the power ``n`` (-2..2) or by the term name (``"Q"`` .. ``"R"``).

    Returns
    -------
    dict
        Term name to value in the units of :data:`TERM_UNIT` (DESIGN.md "Definitions").

    Examples
    --------
    >>> t = terms_from_c({-2: 1.1754e-5, -1: 1.0228e-2, 0: 3.835e-3, 1: 1.196e-3, 2: 1.827e-4})
    >>> f"{t['B']:.3e} {t['K']:.4f} {t['Q']:.3e}"
    '5.776e-03 0.1243 6.786e-06'
    """
    out: dict[str, float] = {}
    for key, value in c.items():
        name = _term_key(key)
        v = float(value)
        if not math.isfinite(v) or v < 0:
            raise DataError(f"C coefficient {key!r} must be a finite number >= 0, got {value!r}")
        out[name] = TERM_FACTOR[name] * v
    return {n: out[n] for n in NOISE_TERMS if n in out}


def c_from_terms(terms: Mapping[str, float]) -> dict[int, float]:
    """Inverse of :func:`terms_from_c`: IEEE-952 terms to ``C_n`` keyed by the power n.

    Examples
    --------
    >>> round(c_from_terms({"N": 0.01})[-1], 6)
    0.6
    """
    out: dict[int, float] = {}
    for key, value in terms.items():
        name = _term_key(key)
        v = float(value)
        if not math.isfinite(v) or v < 0:
            raise DataError(f"term {key!r} must be a finite number >= 0, got {value!r}")
        out[TERM_POWER[name]] = v / TERM_FACTOR[name]
    return dict(sorted(out.items()))


def _term_key(key: str | int) -> str:
    if isinstance(key, str) and key in TERM_POWER:
        return key
    if isinstance(key, int | np.integer) and not isinstance(key, bool):
        for name, power in TERM_POWER.items():
            if power == int(key):
                return name
    raise DataError(f"coefficient key must be a term name (Q, N, B, K, R) or a power "
                    f"(-2, -1, 0, 1, 2), got {key!r}")


# --------------------------------------------------------------------------- results


@dataclass(frozen=True)
class NoiseTerm:
    """One fitted IEEE-952 term.

    Attributes
    ----------
    name : str
        ``"Q"``, ``"N"``, ``"B"``, ``"K"`` or ``"R"``.
    value, stderr, ci_low, ci_high : float
        The coefficient in ``unit`` (deg/h based, DESIGN.md), its standard error and its
        confidence interval at the model's ``confidence``.  ``stderr`` is NaN at the zero
        bound (see ``at_bound``).
    unit : str
    c_coeff, c_stderr : float
        The seed paper's ``C_n`` (rate in deg/h, tau in s) and its standard error.
    c_unit : str
    power : int
        ``n`` in ``C_n^2 tau^n``; the slope of the term's Allan-deviation line is ``n/2``.
    at_bound : bool
        True when the fit put the term at zero (the interval is then an upper limit).
    identifiable : bool
        False when the term dominates the fitted curve at fewer than
        :data:`MIN_DOMINANT_POINTS` data taus.
    n_dominant : int
        Number of data taus where this term is the largest contribution.
    region_tau_s : tuple of float
        Tau range (s) where the term is the largest contribution to the fitted curve,
        searched over 1000x beyond the data on each side; ``(nan, nan)`` if nowhere.
    """

    name: str
    value: float
    stderr: float
    ci_low: float
    ci_high: float
    unit: str
    c_coeff: float
    c_stderr: float
    c_unit: str
    power: int
    at_bound: bool
    identifiable: bool
    n_dominant: int
    region_tau_s: tuple[float, float]

    @property
    def slope(self) -> float:
        """Log-log slope of this term's Allan-deviation line (-1, -1/2, 0, 1/2, 1)."""
        return self.power / 2.0

    def to_dict(self) -> dict[str, Any]:
        return {"value": self.value, "stderr": self.stderr, "ci_low": self.ci_low,
                "ci_high": self.ci_high, "unit": self.unit, "c_coeff": self.c_coeff,
                "c_stderr": self.c_stderr, "c_unit": self.c_unit,
                "identifiable": self.identifiable, "at_bound": self.at_bound,
                "slope": self.slope, "n_dominant": self.n_dominant,
                "region_tau": list(self.region_tau_s)}


@dataclass(frozen=True)
class SlopeReadoff:
    """The classic graphical read-offs (comparison only; NOT the fitted answer).

    IEEE Std 952-1997 Annex C and MATLAB's ``allanvar`` example: a line of the term's slope
    is drawn through the curve point whose local log-log slope is closest to it; N is that
    -1/2 line at tau = 1 s (divided by 60 for deg/sqrt(h)), K the +1/2 line at tau = 3 s
    (times 60 for deg/h^1.5); B is the minimum deviation / 0.664.

    Attributes
    ----------
    N, K, B : float
        In deg/sqrt(h), deg/h^1.5 and deg/h.
    tau_N_s, tau_K_s, tau_B_s : float
        The curve point each value was read from.
    slope_N, slope_K : float
        The local slope found there (how well the curve shows the -1/2 or +1/2 line).
    """

    N: float
    K: float
    B: float
    tau_N_s: float
    tau_K_s: float
    tau_B_s: float
    slope_N: float
    slope_K: float
    # the read-off points in the curve's own units, for plotting: (tau_s, dev)
    points: tuple[tuple[str, float, float], ...] = ()

    def to_dict(self) -> dict[str, Any]:
        return {"method": "slope read-off (IEEE 952 Annex C / MATLAB allanvar example); "
                          "comparison only, not the fit",
                "N": {"value": self.N, "unit": TERM_UNIT["N"], "tau": self.tau_N_s,
                      "local_slope": self.slope_N, "read_at_tau": 1.0},
                "K": {"value": self.K, "unit": TERM_UNIT["K"], "tau": self.tau_K_s,
                      "local_slope": self.slope_K, "read_at_tau": 3.0},
                "B": {"value": self.B, "unit": TERM_UNIT["B"], "tau": self.tau_B_s}}


@dataclass(frozen=True)
class NoiseModel:
    """IEEE-952 noise terms fitted to one Allan-variance curve.

    Attributes
    ----------
    terms : tuple of NoiseTerm
        The fitted terms, in the order Q, N, B, K, R (only those requested).
    confidence : float
        Level of every term's interval.
    method : str
        ``"wls"`` (EDF-weighted IRLS, the default) or ``"ols"`` (unweighted, the
        traditional fit; for comparison).
    kind, units, axis : str
        From the Allan result; ``units`` is the rate unit of the curve.
    deg_per_hour_factor : float
        Multiply the curve's deviations by this to get deg/h.
    tau_s, dev, fitted_dev, weight : ndarray
        The points used in the fit, the fitted deviation there and each point's final
        weight relative to the largest (``weight`` is all 1 for ``ols``).
    edf : ndarray
        Degrees of freedom used per point.
    edf_source : str
        ``"result"`` (from the Allan result), ``"ieee952"`` (N/m - 1) or ``"mixed"``.
    chi2, dof : float
        Pearson chi-square of the final fit and its (effective) degrees of freedom: the
        sum of the grid-density factors minus the number of non-zero terms.
    model_error : float
        Relative standard deviation on sigma^2 added to every point because the model
        misfits the curve beyond its sampling noise (Paule-Mandel; 0 when the fit is
        consistent with the EDF; NaN for ``ols``).
    iterations : int
    converged : bool
    readoff : SlopeReadoff
    excluded_tau_s : tuple of float
        Taus dropped before the fit (non-finite or non-positive deviation).
    warnings : tuple of str
        Every warning emitted by the fit.
    """

    terms: tuple[NoiseTerm, ...]
    confidence: float
    method: str
    kind: str
    units: str
    axis: str
    deg_per_hour_factor: float
    tau_s: FloatArray
    dev: FloatArray
    fitted_dev: FloatArray
    weight: FloatArray
    edf: FloatArray
    edf_source: str
    chi2: float
    dof: float
    model_error: float
    iterations: int
    converged: bool
    readoff: SlopeReadoff
    excluded_tau_s: tuple[float, ...] = ()
    warnings: tuple[str, ...] = ()
    _a: tuple[float, ...] = field(default=(), repr=False)

    # -------------------------------------------------------------- access
    def __getitem__(self, name: str) -> NoiseTerm:
        for t in self.terms:
            if t.name == name:
                return t
        raise KeyError(f"term {name!r} was not fitted; fitted terms are: "
                       f"{', '.join(self.names)}")

    @property
    def names(self) -> tuple[str, ...]:
        return tuple(t.name for t in self.terms)

    @property
    def values(self) -> dict[str, float]:
        """Term name to value (deg/h-based units)."""
        return {t.name: t.value for t in self.terms}

    # -------------------------------------------------------------- curves
    def term_line(self, name: str, tau_s: Any) -> FloatArray:
        """One term's own Allan-deviation line ``C_n tau^(n/2)`` in the curve's units."""
        term = self[name]
        tau = _tau_array(tau_s)
        a = self._a[self.names.index(term.name)]
        return np.sqrt(a * tau ** float(term.power))

    def lines(self, tau_s: Any) -> dict[str, FloatArray]:
        """Every fitted term's own line at ``tau_s`` (curve units)."""
        return {n: self.term_line(n, tau_s) for n in self.names}

    def curve(self, tau_s: Any) -> FloatArray:
        """The fitted total Allan deviation at ``tau_s`` (curve units).

        Examples
        --------
        >>> import numpy as np, warnings
        >>> from types import SimpleNamespace
        >>> tau = 2.0 ** np.arange(-5, 12)
        >>> res = SimpleNamespace(kind="oadev", units="deg/h", axis="x", tau_s=tau,
        ...                       dev=np.sqrt(0.25 / tau + 1e-4 * tau / 3), edf=100 + 0 * tau)
        >>> with warnings.catch_warnings():
        ...     warnings.simplefilter("ignore")
        ...     model = fit_noise(res, terms="N,K")
        >>> np.round(model.curve([1.0, 3.0]), 4)
        array([0.5001, 0.2893])
        """
        tau = _tau_array(tau_s)
        total = np.zeros_like(tau)
        for name, a in zip(self.names, self._a, strict=True):
            total += a * tau ** float(TERM_POWER[name])
        return np.sqrt(total)

    # -------------------------------------------------------------- exports
    def noise_dict(self) -> dict[str, dict[str, Any]]:
        """Term name to ``{value, stderr, ci_low, ci_high, unit, ...}`` (the JSON ``noise``)."""
        return {t.name: t.to_dict() for t in self.terms}

    def to_frame(self) -> pd.DataFrame:
        """One row per term: value, stderr, CI, unit, C_n, identifiability."""
        rows = [{"term": t.name, "value": t.value, "stderr": t.stderr, "ci_low": t.ci_low,
                 "ci_high": t.ci_high, "unit": t.unit, "c_coeff": t.c_coeff,
                 "c_stderr": t.c_stderr, "slope": t.slope, "at_bound": t.at_bound,
                 "identifiable": t.identifiable} for t in self.terms]
        return pd.DataFrame(rows).set_index("term")

    def to_dict(self) -> dict[str, Any]:
        return {
            "method": self.method,
            "confidence": self.confidence,
            "kind": self.kind,
            "units": self.units,
            "axis": self.axis,
            "terms": self.noise_dict(),
            "readoff": self.readoff.to_dict(),
            "fit": {"n_points": int(self.tau_s.size),
                    "tau_range": [float(self.tau_s[0]), float(self.tau_s[-1])],
                    "chi2": self.chi2, "dof": self.dof, "model_error": self.model_error,
                    "iterations": self.iterations, "converged": self.converged,
                    "edf_source": self.edf_source,
                    "deg_per_hour_factor": self.deg_per_hour_factor},
            "excluded_tau": list(self.excluded_tau_s),
            "warnings": list(self.warnings),
        }

    def summary(self) -> str:
        pct = 100 * self.confidence
        lines = [f"IEEE-952 noise terms ({self.method.upper()} fit of {self.kind} on "
                 f"{self.tau_s.size} taus {self.tau_s[0]:.4g}..{self.tau_s[-1]:.4g} s, "
                 f"axis {self.axis!r}, input in {self.units})",
                 f"{'term':<5}{'value':>12}  {'± stderr':>11}  {f'{pct:.1f} % CI':>25}  "
                 f"{'unit':<12}{'C_n':>11}  note"]
        for t in self.terms:
            se = "-" if not math.isfinite(t.stderr) else f"{t.stderr:.3e}"
            note = "at zero (upper limit)" if t.at_bound else ""
            if not t.identifiable:
                note = (note + "; " if note else "") + "not identifiable"
            lines.append(f"{t.name:<5}{t.value:>12.4e}  {se:>11}  "
                         f"[{t.ci_low:.3e}, {t.ci_high:.3e}]  {t.unit:<12}"
                         f"{t.c_coeff:>11.4e}  {note}")
        r = self.readoff
        lines.append(f"slope read-offs (comparison only): N = {r.N:.4e} {TERM_UNIT['N']}, "
                     f"K = {r.K:.4e} {TERM_UNIT['K']}, B = {r.B:.4e} {TERM_UNIT['B']}")
        lines.append(f"chi2 = {self.chi2:.4g} on {self.dof:.4g} dof; model error "
                     f"{self.model_error:.3g} (relative, on sigma^2); "
                     f"{self.iterations} iteration(s)"
                     + ("" if self.converged else " (NOT converged)")
                     + f"; edf from {self.edf_source}")
        lines += [f"warning: {w}" for w in self.warnings]
        return "\n".join(lines)


# --------------------------------------------------------------------------- fit


def fit_noise(
    allan_result: Any,
    *,
    terms: Sequence[str] | str = NOISE_TERMS,
    method: FitMethod = "wls",
    confidence: float = 0.683,
) -> NoiseModel:
    """Fit the IEEE-952 noise terms to an Allan-deviation curve.

    Non-negative, EDF-weighted, iteratively reweighted least squares on sigma^2(tau)
    (see the module docstring for the weights, the standard errors and the treatment of
    terms at zero).

    Parameters
    ----------
    allan_result : AllanResult
        One curve (``kind`` adev, oadev or totdev) with ``tau_s``, ``dev``, ``units`` and,
        ideally, ``edf`` (else ``n_samples`` and ``m`` for the IEEE 952 fallback).  Pick one
        curve of a multi-axis result set first.
    terms : sequence of str or str
        Which of ``"Q", "N", "B", "K", "R"`` to fit (a comma-separated string works too).
    method : {"wls", "ols"}
        ``"wls"``: weights from each point's EDF (default).  ``"ols"``: unweighted least
        squares on sigma^2 (the traditional fit; comparison only).
    confidence : float
        Level of the coefficient intervals, in (0, 1).

    Returns
    -------
    NoiseModel

    Raises
    ------
    DataError
        Bad ``terms``, ``method``, ``confidence``, a multi-axis result, a kind whose tau
        laws differ (mdev, hdev, ...), or malformed arrays.
    InsufficientDataError
        Fewer usable points than terms.

    Warns
    -----
    UnidentifiableTermWarning
        A term dominates the fitted curve at fewer than two taus.
    ConvergenceWarning
        The reweighting did not settle in 50 iterations.
    DataQualityWarning
        Points with a non-finite or zero deviation were left out.

    Examples
    --------
    >>> import numpy as np, warnings
    >>> from types import SimpleNamespace
    >>> tau = 2.0 ** np.arange(-5, 12)
    >>> dev = np.sqrt(0.5**2 / tau + 0.01**2 * tau / 3)       # N=0.5, K=0.01 (deg/h, s)
    >>> res = SimpleNamespace(kind="oadev", units="deg/h", axis="x", tau_s=tau, dev=dev,
    ...                       edf=np.full(tau.size, 100.0))
    >>> with warnings.catch_warnings():
    ...     warnings.simplefilter("ignore")
    ...     model = fit_noise(res, terms=("N", "K"))
    >>> round(model["N"].c_coeff, 6), round(model["K"].c_coeff * np.sqrt(3), 6)
    (0.5, 0.01)
    """
    names = _check_terms(terms)
    method = check_choice("method", method, FIT_METHODS)  # type: ignore[assignment]
    confidence = check_fraction("confidence", confidence)
    tau, dev, edf, edf_source, units, kind, axis, excluded = _unpack(allan_result)
    if tau.size < len(names):
        raise InsufficientDataError(
            f"allan_result has {tau.size} usable taus, fewer than the {len(names)} terms "
            f"requested ({', '.join(names)}); use more taus or fewer terms")
    issued: list[str] = []
    if excluded:
        _warn(issued, DataQualityWarning,
              f"{len(excluded)} tau(s) with a non-finite or zero deviation were left out of "
              f"the noise fit: {', '.join(f'{t:.4g}' for t in excluded[:5])}"
              + (" ..." if len(excluded) > 5 else "") + " s")

    powers = np.array([TERM_POWER[n] for n in names], dtype=np.float64)
    design = tau[:, None] ** powers[None, :]
    scale_y = float(np.median(dev**2))
    y = dev**2 / scale_y
    fit = (_fit_wls(design, y, edf, _octave_density(tau)) if method == "wls"
           else _fit_ols(design, y))
    if not fit.converged:
        _warn(issued, ConvergenceWarning,
              f"the noise-fit reweighting did not converge in {_IRLS_MAX_ITER} iterations; "
              "the coefficients are from the last iteration")
    a, mu, w = fit.a, fit.mu, fit.w
    active = a > 0
    cov = _covariance(design, w, active, fit.scale)
    z = float(norm.ppf(0.5 + confidence / 2))

    factor = to_deg_per_hour_factor(units)
    a_units = a * scale_y  # squared coefficients in the curve's units
    fit_terms: list[NoiseTerm] = []
    for j, name in enumerate(names):
        if active[j]:
            se_a = math.sqrt(max(cov[j, j], 0.0))
            c = math.sqrt(a[j])
            c_se = se_a / (2 * c)
            lo_a, hi_a = max(0.0, a[j] - z * se_a), a[j] + z * se_a
        else:
            se_bound = _bound_stderr(design, w, active, j, fit.scale)
            c, c_se = 0.0, math.nan
            lo_a, hi_a = 0.0, z * se_bound
        s = math.sqrt(scale_y) * factor  # curve units -> deg/h
        tf = TERM_FACTOR[name]
        fit_terms.append(NoiseTerm(
            name=name, value=tf * c * s, stderr=tf * c_se * s,
            ci_low=tf * math.sqrt(lo_a) * s, ci_high=tf * math.sqrt(hi_a) * s,
            unit=TERM_UNIT[name], c_coeff=c * s, c_stderr=c_se * s, c_unit=C_UNIT[name],
            power=TERM_POWER[name], at_bound=not bool(active[j]), identifiable=True,
            n_dominant=0, region_tau_s=(math.nan, math.nan)))

    fitted_dev = np.sqrt(mu * scale_y)
    readoff = _slope_readoff(tau, dev, factor)
    model = NoiseModel(
        terms=tuple(fit_terms), confidence=confidence, method=method, kind=kind,
        units=units, axis=axis, deg_per_hour_factor=factor, tau_s=tau, dev=dev,
        fitted_dev=fitted_dev, weight=w / np.max(w), edf=edf, edf_source=edf_source,
        chi2=fit.chi2, dof=fit.dof, model_error=fit.model_error, iterations=fit.iterations,
        converged=fit.converged, readoff=readoff, excluded_tau_s=tuple(excluded),
        _a=tuple(float(v) for v in a_units))
    fit_terms = _identifiability(model, tau, issued)
    return NoiseModel(**{**_fields(model), "terms": tuple(fit_terms),
                         "warnings": tuple(issued)})


# --------------------------------------------------------------------------- helpers


def _fields(model: NoiseModel) -> dict[str, Any]:
    return {k: getattr(model, k) for k in model.__dataclass_fields__}


def _warn(issued: list[str], category: type[Warning], message: str) -> None:
    issued.append(message)
    warnings.warn(message, category, stacklevel=3)


def _check_terms(terms: Sequence[str] | str) -> tuple[str, ...]:
    if isinstance(terms, str):
        items = [t.strip() for t in terms.split(",") if t.strip()]
    else:
        try:
            items = list(terms)
        except TypeError:
            raise DataError(f"terms must be a sequence of Q, N, B, K, R, got {terms!r}") from None
    if not items:
        raise DataError(f"terms must name at least one of Q, N, B, K, R, got {terms!r}")
    for t in items:
        if not isinstance(t, str) or t.upper() not in TERM_POWER:
            raise DataError(f"terms must be drawn from Q, N, B, K, R; got {t!r}")
    upper = [t.upper() for t in items]
    if len(set(upper)) != len(upper):
        raise DataError(f"terms must not repeat a term, got {terms!r}")
    return tuple(n for n in NOISE_TERMS if n in upper)


def _unpack(res: Any) -> tuple[FloatArray, FloatArray, FloatArray, str, str, str, str,
                                list[float]]:
    if hasattr(res, "curves") and not hasattr(res, "dev"):
        axes = ", ".join(map(str, getattr(res, "axes", ())))
        raise DataError(f"allan_result is a multi-axis result set (axes: {axes}); fit one "
                        "curve at a time, e.g. [fit_noise(c) for c in result.curves]")
    missing = [a for a in ("tau_s", "dev", "units", "kind") if not hasattr(res, a)]
    if missing:
        raise DataError(f"allan_result must be an AllanResult (with tau_s, dev, units, "
                        f"kind); {type(res).__name__} lacks {', '.join(missing)}")
    kind = str(res.kind)
    if kind not in FITTABLE_KINDS:
        raise DataError(f"allan_result.kind must be one of {', '.join(FITTABLE_KINDS)} (the "
                        f"IEEE-952 tau laws hold for the Allan variance), got {kind!r}")
    units = parse_rate_unit(str(res.units), "allan_result.units")
    tau = np.asarray(res.tau_s, dtype=np.float64)
    dev = np.asarray(res.dev, dtype=np.float64)
    if tau.ndim != 1 or tau.shape != dev.shape:
        raise DataError(f"allan_result.tau_s and .dev must be 1-D of equal length, got "
                        f"shapes {tau.shape} and {dev.shape}")
    if not np.all(np.isfinite(tau) & (tau > 0)):
        raise DataError("allan_result.tau_s must be finite and > 0")
    if np.any(np.diff(tau) <= 0):
        raise DataError("allan_result.tau_s must be strictly increasing")
    n = tau.size
    edf = _edf(res, n)
    ok = np.isfinite(dev) & (dev > 0)
    excluded = [float(t) for t in tau[~ok]]
    edf = edf[ok]
    has_result_edf = np.isfinite(_attr_array(res, "edf", n))[ok]
    if np.all(has_result_edf):
        source = "result"
    elif not np.any(has_result_edf):
        source = "ieee952"
    else:
        source = "mixed"
    if not np.all(np.isfinite(edf) & (edf > 0)):
        bad = float(tau[ok][~(np.isfinite(edf) & (edf > 0))][0])
        raise DataError(f"allan_result has no usable edf at tau = {bad:.6g} s (and no "
                        "n_samples and m to fall back on IEEE 952's N/m - 1)")
    return (tau[ok], dev[ok], edf, source, units, kind, str(getattr(res, "axis", "")),
            excluded)


def _attr_array(res: Any, name: str, n: int) -> FloatArray:
    value = getattr(res, name, None)
    if value is None:
        return np.full(n, np.nan)
    arr = np.asarray(value, dtype=np.float64)
    if arr.shape != (n,):
        raise DataError(f"allan_result.{name} must have the shape of tau_s ({n},), got "
                        f"{arr.shape}")
    return arr


def _edf(res: Any, n: int) -> FloatArray:
    """EDF per point: the result's, else IEEE 952 C.3's N/m - 1 (at least 1)."""
    edf = _attr_array(res, "edf", n).copy()
    missing = ~(np.isfinite(edf) & (edf > 0))
    if np.any(missing):
        n_samples = getattr(res, "n_samples", None)
        m = _attr_array(res, "m", n)
        if n_samples is not None:
            fallback = np.maximum(float(n_samples) / m - 1.0, 1.0)
            edf[missing] = fallback[missing]
    return edf


def _octave_density(tau: FloatArray) -> FloatArray:
    """Width in octaves (<= 1) of the tau interval each point represents."""
    if tau.size == 1:
        return np.ones(1)
    lg = np.log2(tau)
    gaps = np.diff(lg)
    width = np.empty_like(lg)
    width[0], width[-1] = gaps[0], gaps[-1]
    width[1:-1] = 0.5 * (gaps[:-1] + gaps[1:])
    return np.minimum(width, 1.0)


def _wnnls(design: FloatArray, y: FloatArray, w: FloatArray) -> FloatArray:
    """Weighted NNLS with column scaling (the basis spans many decades)."""
    sw = np.sqrt(w)
    aw = design * sw[:, None]
    col = np.linalg.norm(aw, axis=0)
    col[col == 0] = 1.0
    sol, _ = nnls(aw / col, y * sw, maxiter=50 * design.shape[1])
    return np.asarray(sol / col, dtype=np.float64)


@dataclass(frozen=True)
class _Fit:
    a: FloatArray            # squared coefficients (scaled units)
    mu: FloatArray           # model sigma^2 at the data taus
    w: FloatArray            # final weights (inverse variances)
    scale: float             # factor on (A^T W A)^-1 giving the covariance
    chi2: float
    dof: float
    model_error: float       # Paule-Mandel relative model error on sigma^2 (wls)
    iterations: int
    converged: bool


def _irls(design: FloatArray, y: FloatArray, edf: FloatArray, density: FloatArray,
          eps2: float, mu0: FloatArray) -> tuple[FloatArray, FloatArray, FloatArray, int, bool]:
    """IRLS with Var[y_i] = mu_i^2 (2/edf_i + eps2) / density_i, mu from the model."""
    floor = 1e-12 * float(np.max(y))
    rel = 2.0 / edf + eps2
    mu = mu0.copy()
    a = np.zeros(design.shape[1])
    for it in range(1, _IRLS_MAX_ITER + 1):
        w = density / (rel * mu**2)
        a = _wnnls(design, y, w)
        new = np.maximum(design @ a, floor)
        if it > _IRLS_MAX_ITER // 3:  # damp a slow oscillation between active sets
            new = np.sqrt(new * mu)
        change = float(np.max(np.abs(new - mu) / mu))
        mu = new
        if change < _IRLS_TOL:
            return a, mu, density / (rel * mu**2), it, True
    return a, mu, density / (rel * mu**2), _IRLS_MAX_ITER, False


def _fit_wls(design: FloatArray, y: FloatArray, edf: FloatArray, density: FloatArray) -> _Fit:
    """EDF-weighted IRLS, with a Paule-Mandel relative model error when the model misfits.

    If the Pearson chi-square of the EDF-only fit exceeds its degrees of freedom, the
    five-term model does not describe the curve to within the sampling noise (a real gyro
    also has bandwidth limits, Gauss-Markov bumps, ...); the points with enormous EDF at
    short tau would then dictate the fit.  A relative model-error variance ``eps2`` is added
    to every point (Var = mu^2 (2/edf + eps2)) and chosen so that chi2 = dof: the
    Paule-Mandel estimator (Paule & Mandel, J. Res. NBS 87(5), 1982, 377-385).
    """
    dof = float(np.sum(density))
    a, mu, w, iters, ok = _irls(design, y, edf, density, 0.0, y)

    def chi2_of(mu_: FloatArray, w_: FloatArray) -> float:
        return float(np.sum(w_ * (y - mu_) ** 2))

    n_act = int(np.count_nonzero(a > 0))
    dof_eff = dof - n_act
    chi2 = chi2_of(mu, w)
    if dof_eff <= 0 or chi2 <= dof_eff:
        return _Fit(a, mu, w, 1.0, chi2, dof_eff, 0.0, iters, ok)
    state = {"mu": mu, "iters": iters, "ok": ok}

    def excess(log_eps2: float) -> float:
        a_, mu_, w_, it_, ok_ = _irls(design, y, edf, density, math.exp(log_eps2), state["mu"])
        state.update(mu=mu_, iters=int(state["iters"]) + it_, ok=bool(state["ok"]) and ok_)
        return chi2_of(mu_, w_) - (dof - np.count_nonzero(a_ > 0))

    lo, hi = math.log(1e-12), math.log(1e-2)
    while excess(hi) > 0 and hi < math.log(1e4):
        lo, hi = hi, hi + math.log(100.0)
    log_eps2 = brentq(excess, lo, hi, xtol=1e-6) if excess(lo) > 0 else lo
    eps2 = math.exp(log_eps2)
    a, mu, w, it, ok = _irls(design, y, edf, density, eps2, state["mu"])
    n_act = int(np.count_nonzero(a > 0))
    return _Fit(a, mu, w, 1.0, chi2_of(mu, w), dof - n_act, math.sqrt(eps2),
                int(state["iters"]) + it, bool(state["ok"]) and ok)


def _fit_ols(design: FloatArray, y: FloatArray) -> _Fit:
    """Unweighted NNLS on sigma^2 (the traditional fit); covariance s^2 (A^T A)^-1."""
    w = np.ones_like(y)
    a = _wnnls(design, y, w)
    mu = design @ a
    rss = float(np.sum((y - mu) ** 2))
    dof = float(y.size - np.count_nonzero(a > 0))
    scale = rss / dof if dof > 0 else math.nan
    return _Fit(a, mu, w, scale, rss, dof, math.nan, 1, True)


def _covariance(design: FloatArray, w: FloatArray, active: np.ndarray,
                scale: float) -> FloatArray:
    k = design.shape[1]
    cov = np.full((k, k), np.nan)
    idx = np.flatnonzero(active)
    if idx.size == 0:
        return cov
    sub = _inverse_normal(design[:, idx], w) * scale
    cov[np.ix_(idx, idx)] = sub
    return cov


def _inverse_normal(a: FloatArray, w: FloatArray) -> FloatArray:
    col = np.linalg.norm(a * np.sqrt(w)[:, None], axis=0)
    col[col == 0] = 1.0
    scaled = a / col
    normal = scaled.T @ (scaled * w[:, None])
    inv = np.linalg.pinv(normal, rcond=1e-13)
    return np.asarray(inv / np.outer(col, col), dtype=np.float64)


def _bound_stderr(design: FloatArray, w: FloatArray, active: np.ndarray, j: int,
                  scale: float) -> float:
    """Standard error of a zero-bound coefficient, freed beside the active set."""
    idx = np.append(np.flatnonzero(active), j)
    inv = _inverse_normal(design[:, idx], w) * scale
    return math.sqrt(max(float(inv[-1, -1]), 0.0))


def _slope_readoff(tau: FloatArray, dev: FloatArray, factor: float) -> SlopeReadoff:
    logt, logd = np.log10(tau), np.log10(dev)
    if tau.size >= 2:
        slopes = np.diff(logd) / np.diff(logt)
    else:
        slopes = np.array([math.nan])

    def line(target: float, at: float) -> tuple[float, float, float]:
        if not np.any(np.isfinite(slopes)):
            return math.nan, math.nan, math.nan
        i = int(np.nanargmin(np.abs(slopes - target)))
        b = logd[i] - target * logt[i]
        return float(10 ** (target * math.log10(at) + b)), float(tau[i]), float(slopes[i])

    n_dev, tau_n, slope_n = line(-0.5, 1.0)
    k_dev, tau_k, slope_k = line(0.5, 3.0)
    floor = read_curve(tau, dev) if tau.size >= 2 else None
    b_dev = floor.dev_min if floor is not None else float(dev[0])
    tau_b = floor.tau_min_s if floor is not None else float(tau[0])
    return SlopeReadoff(
        N=n_dev * factor / 60.0, K=k_dev * factor * 60.0, B=b_dev * factor / 0.664,
        tau_N_s=tau_n, tau_K_s=tau_k, tau_B_s=tau_b, slope_N=slope_n, slope_K=slope_k,
        points=(("N", 1.0, n_dev), ("K", 3.0, k_dev), ("B", tau_b, b_dev)))


def _identifiability(model: NoiseModel, tau: FloatArray, issued: list[str]
                     ) -> list[NoiseTerm]:
    lines = model.lines(tau)
    stack = np.vstack([lines[n] for n in model.names])
    winner = np.argmax(stack, axis=0)
    wide = np.logspace(math.log10(tau[0]) - 3, math.log10(tau[-1]) + 3, 601)
    wide_lines = model.lines(wide)
    wide_stack = np.vstack([wide_lines[n] for n in model.names])
    wide_winner = np.argmax(wide_stack, axis=0)
    out: list[NoiseTerm] = []
    for j, term in enumerate(model.terms):
        n_dom = int(np.count_nonzero((winner == j) & (stack[j] > 0)))
        where = (wide_winner == j) & (wide_stack[j] > 0)
        region = ((float(wide[where][0]), float(wide[where][-1])) if np.any(where)
                  else (math.nan, math.nan))
        ok = n_dom >= MIN_DOMINANT_POINTS
        if not ok:
            if term.at_bound:
                why = "it was fitted to zero"
            elif not np.any(where):
                why = "no other term leaves it room anywhere"
            else:
                why = (f"it would dominate only at tau {region[0]:.3g}..{region[1]:.3g} s")
            _warn(issued, UnidentifiableTermWarning,
                  f"noise term {term.name} ({TERM_DESCRIPTION[term.name]}, slope "
                  f"{term.slope:+g}) is not identifiable from taus {tau[0]:.4g}..{tau[-1]:.4g}"
                  f" s: it dominates the fitted curve at {n_dom} of {tau.size} taus ({why}); "
                  "treat its value as an upper limit")
        out.append(NoiseTerm(**{**{k: getattr(term, k) for k in term.__dataclass_fields__},
                                "identifiable": ok, "n_dominant": n_dom,
                                "region_tau_s": region}))
    return out


def _tau_array(tau_s: Any) -> FloatArray:
    tau = np.atleast_1d(np.asarray(tau_s, dtype=np.float64))
    if tau.ndim != 1 or not np.all(np.isfinite(tau) & (tau > 0)):
        raise DataError(f"tau_s must be finite and > 0, got {tau_s!r}")
    return tau

