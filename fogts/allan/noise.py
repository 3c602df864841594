"""IEEE-952 noise terms from an Allan-variance curve, with honest uncertainties.

The five classical terms of IEEE Std 952-1997 Annex C (seed 000; DESIGN.md "Definitions")
add in the Allan variance of a rate signal:

.. math::

    \\sigma^2(\\tau) = \\frac{R^2\\tau^2}{2} + \\frac{K^2\\tau}{3} + B^2\\frac{2\\ln 2}{\\pi}
                     + \\frac{N^2}{\\tau} + \\frac{3Q^2}{\\tau^2}
                   = \\sum_{n=-2}^{2} C_n^2\\,\\tau^n .

The model is linear in the squared coefficients :math:`a_n = C_n^2 \\ge 0`, so
:func:`fit_noise` solves non-negative least-squares problems (``scipy.optimize.nnls``) on
:math:`\\sigma^2(\\tau)`.

Weights (``method="wls"``, the default)
    An Allan-variance estimate with ``edf`` equivalent degrees of freedom is distributed as
    :math:`\\sigma^2\\chi^2_{edf}/edf`, so :math:`\\mathrm{Var}[\\hat\\sigma^2] = 2\\sigma^4/edf`
    (NIST SP1065 sec. 5.3; IEEE 952 C.3 gives the same through
    :math:`1/\\sqrt{2(N/m-1)}`).  Each point is weighted by the inverse of that variance,
    evaluated at the *model* value rather than at the noisy observation (a weight computed
    from the observation favours points that happen to fall low and biases the fit
    downwards).  Because the weight depends on the fit, the fit is iterated (IRLS) from
    observation-based weights until the model changes by less than ``1e-7`` relative; the
    fixed point is the maximum-likelihood estimate for independent scaled-chi-square
    observations (a Gamma GLM with identity link; McCullagh & Nelder, *Generalized Linear
    Models*, 2nd ed., 1989, ch. 8), restricted to :math:`a_n \\ge 0`.  So long-tau points,
    with few terms and few degrees of freedom, count for less.  The EDF comes from the
    Allan result (Greenhall's algorithm); where it is missing it falls back to IEEE 952's
    :math:`N/m - 1`, recorded in ``edf_source``.

    Estimates at taus closer than an octave share most of their data.  So that a ``dense``
    or ``all`` grid does not count the same information many times (an ``all`` grid puts
    nearly all its points at long tau), each weight is multiplied by the width in octaves
    (at most 1) of the tau interval the point represents, i.e. half the log2-distance to
    its neighbours.  On octave or sparser grids this factor is 1.

Model error
    A real gyro is not exactly the five-term model (its bandwidth limit bends the first
    points, Gauss-Markov bumps, ...), and the short-tau points have EDFs in the millions:
    without care, a 3 % misfit there would dictate every coefficient.  Every point is
    therefore given a relative model-error variance on top of its sampling variance,
    :math:`\\mathrm{Var}[\\hat\\sigma^2_i] = \\mu_i^2 (2/edf_i + \\epsilon^2)`, and
    :math:`\\epsilon` is estimated by maximum likelihood, profiled over the coefficients:
    the estimates are Gamma distributed with mean :math:`\\mu_i` and shape
    :math:`1/(2/edf_i + \\epsilon^2)` (Gaussian with covariance :math:`V + \\epsilon^2
    \\mathrm{diag}(\\mu^2)` for ``gls``).  This is the random-effects idea of Paule & Mandel
    (*J. Res. NBS* 87(5), 1982) with a likelihood instead of their moment equation, which
    the heavy right tail of low-EDF long-tau points would trip.  ``model_error`` is
    :math:`\\epsilon` (0 when the curve is consistent with its sampling noise).
    :math:`\\epsilon^2 = 0` lies on the boundary of the parameter space, so the
    unrestricted ML estimate is positive for some curves that follow the model exactly
    (3 to 7 of the 30 white + random-walk curves below), and each such value caps the
    weight of the short-tau points (EDF in the millions) that pin N.  :math:`\\epsilon` is therefore kept only if the
    likelihood-ratio statistic :math:`2(\\ell(\\hat\\epsilon) - \\ell(0))` exceeds the
    critical value of its null distribution, the 50:50 mixture of :math:`\\chi^2_0` and
    :math:`\\chi^2_1` (Self & Liang, *J. Am. Stat. Assoc.* 82(398), 1987, case 1), i.e.
    :math:`z_{1-\\alpha}^2` at level ``significance`` :math:`\\alpha` (2.71 at 5 %).

Term selection (``significance``, default 0.05)
    A term absent from the data is still estimated, and the non-negative fit keeps it
    whenever the noise pushes it up.  Q and N are nearly collinear over the first taus
    (as are K and R over the last), so a spurious Q takes part of N: on white + random-walk
    noise (100 Hz, 3 h, 30 seeds) the five-term fit's median N error was 0.071 %, worse
    than the slope read-off's 0.056 %, against 0.046 % with the spurious terms removed.
    fogts therefore runs a backward elimination: among the terms that are neither
    significant (Wald statistic :math:`z_j = a_j / se(a_j)` below :math:`z_{1-\\alpha}`,
    standard error from the covariance above, which accounts for the correlation between
    taus) nor visible in the curve (fewer than :data:`MIN_COVERED_POINTS` taus where the
    term makes up :data:`COVERAGE_SHARE` of the fitted :math:`\\sigma^2`, see
    "Identifiability"), it drops the one with the smallest :math:`z_j`, refits (model
    error included) and repeats; terms the NNLS put at zero stay at zero.  A term that
    shapes the curve over several taus is kept even when its z is small: dropping a real
    but weakly determined B or K would hand its share to its neighbours and bias them
    (on ``data/example_fog_10hz_3h.csv``, K = 0.034 with z = 1.2, truth 0.05).  For a
    parameter on the boundary :math:`a_j = 0`, :math:`\\max(z_j, 0)^2` has the 50:50
    :math:`\\chi^2_0 / \\chi^2_1` null distribution of the likelihood-ratio statistic
    (Self & Liang 1987; Chernoff, *Ann. Math. Stat.* 25, 1954), so the one-sided
    :math:`z > z_{1-\\alpha}` is its level-:math:`\\alpha` test; the Wald form is used because
    the Gamma likelihood treats correlated taus as independent and its ratio would be
    miscalibrated.  A dropped term keeps value 0, ``status="dropped"`` and the ``z_score``
    it was dropped with; its interval is the upper limit described below.
    ``significance=None`` keeps every requested term (and the unrestricted model error).
    ``method="ols"`` (the traditional fit) is never pruned.

Standard errors and confidence intervals
    Overlapping Allan variances at octave-spaced taus are strongly correlated (about 0.5
    between neighbours for white rate noise and 0.9 for a rate random walk), so the
    inverse weighted normal matrix alone would understate the errors.  For ``oadev`` and
    ``adev`` curves fogts computes the covariance of the estimates implied by the fitted
    model itself: each term is a power-law phase process with a generalized covariance
    (Q: white phase, :math:`K(u) = s^2\\delta(u)`; N: :math:`-N^2|u|/2`; B:
    :math:`(a_0/4\\ln 2)\\,u^2\\ln|u|`; K: :math:`a_1|u|^3/4`), the covariance of two
    second differences is a 9-term sum of :math:`K`, and for Gaussian data
    :math:`\\mathrm{Cov}[d_i^2, d_j^2] = 2\\,\\mathrm{Cov}[d_i, d_j]^2`, summed over all
    pairs of overlapping terms (exactly for short lags, by Gauss-Legendre quadrature with
    an Euler-Maclaurin end correction for long ones).  It reproduces SP1065's white-FM
    EDF, the exact white-PM EDF, and Monte-Carlo variances and correlations of white and
    random-walk FM (tests; flicker FM was checked the same way with 800 records, to the
    8 % Monte-Carlo error).

    ``adev`` (non-overlapping) terms start at multiples of :math:`m`, so the pairs of
    terms of :math:`\\tau_i` and :math:`\\tau_j` sit on the lattice of lags
    :math:`h = l m_j - k m_i`, multiples of :math:`\\gcd(m_i, m_j)`.  For each term l of
    the longer tau the sum over k runs through one residue class of that lattice; on
    octave grids (:math:`m_i` divides :math:`m_j`) there is one class and the sum is exact
    like oadev's, otherwise up to four classes are summed one by one and more are averaged
    over the phase (0.6 % or less on the standard errors of a 100-tau dense grid);
    coincident phase points (Q) are always counted exactly.  It equals
    :math:`2\\,\\mathrm{tr}(A_i S A_j S)` computed from the phase covariance matrix S of
    white PM, white FM and random-walk FM to round-off when every class is summed, and
    to 3 % (correlation scale) with the phase average on a tiny 60-sample grid (tests);
    over 500 simulated
    records of 4096 samples its relative variances are within 0.90..1.10 of the
    Monte-Carlo ones and its correlations within 0.09 for white, flicker and random-walk
    FM (the Monte-Carlo error).

    ``totdev`` extends the record by reflection at both ends, which the generalized
    covariances above do not capture in closed form.  Its covariance is taken as the
    correlation matrix of the oadev model covariance at the same taus, scaled by totdev's
    own variances :math:`2\\mu_i^2/edf_i` (SP1065's totdev EDF, the one its weights and
    intervals use).  Over 500 simulated records of 4096 samples the neighbour
    correlations of totdev agree with oadev's to 0.06 (white, flicker and random-walk FM),
    and its variances with the EDF's within 0.90..1.17 from m = 4 on; at m = 1 and 2 the
    SP1065 EDF understates the variance of white-FM totdev 2.1x and 1.35x (at m = 1 totdev
    is oadev).

    The coefficient covariance is then the sandwich
    :math:`H^{-1}A^TWVWAH^{-1}`, :math:`H = A^TWA`, with :math:`V` that covariance plus the
    model error.  The rate ramp R is treated as deterministic (no variance of its own).
    For a curve without ``m``, ``n_samples`` and ``fs_hz``, or grids of more than
    :data:`MAX_COVARIANCE_POINTS` taus, ``V`` is the EDF diagonal and the errors ignore the
    correlation.  ``stderr_method`` says which covariance was used.  Measured coverage of
    the nominal 68.3 % intervals of N and K (white + random-walk FM, 100 Hz, 3 h, octave
    taus, 40 seeds; binomial error 0.07): oadev 0.80 / 0.63, adev 0.80 / 0.65 (0.63 /
    0.53 with the EDF diagonal), totdev 0.73 / 0.68 (0.58 / 0.43).

    ``method="gls"`` goes one step further and *fits* with the full covariance (IRLS:
    :math:`V` recomputed from the current fit, whitened by its Cholesky factor, NNLS),
    which makes better use of correlated points; see ``benchmarks/bench_noise_fit.py``.

    Each :math:`a_n` gets the normal interval :math:`a_n \\pm z\\,se(a_n)` clipped at 0,
    and :math:`C_n` the square roots of its ends (so intervals are asymmetric); the
    standard error of :math:`C_n` is the delta-method :math:`se(a_n)/(2C_n)`.  A term
    fitted to exactly zero (``at_bound``) has no standard error (NaN): its interval is
    :math:`[0, \\sqrt{z\\,se}]`, with ``se`` from the active set plus that term, i.e. an
    upper limit (the same for a term dropped by the term selection).

Unit conversion (DESIGN.md; seed paper)
    With rate in deg/h and tau in s: ``N = C_-1/60`` deg/sqrt(h), ``B = C_0/0.664`` deg/h,
    ``K = 60 sqrt(3) C_1`` deg/h^1.5, ``R = 3600 sqrt(2) C_2`` deg/h^2 and
    ``Q = C_-2/sqrt(3)`` (deg/h)*s = arcsec.  Other input units are converted with
    :func:`fogts.units.to_deg_per_hour_factor`.  The exact bias-instability factor of the
    model is :math:`\\sqrt{2\\ln 2/\\pi} = 0.66428`; the reported ``B`` uses the rounded
    0.664 of IEEE 952 and the seed paper (0.04 % apart), while the fitted curves are
    computed from the ``C_n`` and are exact.

Identifiability
    A term's *region* is where it makes up at least a quarter
    (:data:`COVERAGE_SHARE`) of the fitted :math:`\\sigma^2`.  The term is *identifiable*
    when the data have at least :data:`MIN_COVERED_POINTS` taus in its region, or one tau
    and an interval that excludes zero.  Otherwise its region is not covered by the data
    (it lies outside the measured taus, or the other terms swamp it everywhere), its value
    is at best an upper limit, and :class:`~fogts.errors.UnidentifiableTermWarning` is
    emitted and recorded.

The classic slope read-offs (IEEE 952 Annex C; MATLAB's ``allanvar`` example) are reported
beside the fit for comparison, never as the answer: N from the -1/2 line at tau = 1 s, K
from the +1/2 line at tau = 3 s, B from the minimum of the curve divided by 0.664.
"""

from __future__ import annotations

import math
import warnings
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field
from typing import Any, Literal, get_args

import numpy as np
import numpy.typing as npt
import pandas as pd
from scipy.optimize import minimize_scalar, nnls
from scipy.special import gammaln
from scipy.stats import norm

from fogts._typing import FloatArray, IntArray
from fogts._validate import check_choice, check_fraction
from fogts.allan.covariance import CovarianceModel, covariance_basis
from fogts.allan.readout import read_curve
from fogts.allan.terms import (
    B_PLATEAU,
    C_UNIT,
    NOISE_TERMS,
    TERM_DESCRIPTION,
    TERM_FACTOR,
    TERM_POWER,
    TERM_UNIT,
)
from fogts.errors import (
    ConvergenceWarning,
    DataError,
    DataQualityWarning,
    FogtsWarning,
    InsufficientDataError,
    UnidentifiableTermWarning,
)
from fogts.units import parse_rate_unit, to_deg_per_hour_factor

__all__ = [
    "FIT_METHODS",
    "NOISE_TERMS",
    "TERM_UNIT",
    "NoiseModel",
    "NoiseTerm",
    "SlopeReadoff",
    "c_from_terms",
    "fit_noise",
    "parse_terms",
    "terms_from_c",
]

FitMethod = Literal["wls", "gls", "ols"]
FIT_METHODS: tuple[str, ...] = get_args(FitMethod)
#: Allan-variance kinds whose expected value follows the IEEE-952 tau laws.  (The modified
#: and Hadamard variances have other constants, so their curves cannot be fitted here.)
FITTABLE_KINDS: tuple[str, ...] = ("adev", "oadev", "totdev")

#: A term's region: where it makes up at least this share of the fitted sigma^2.
COVERAGE_SHARE = 0.25
#: A term must have this many data taus in its region to count as identified.
MIN_COVERED_POINTS = 2
#: Largest grid for which the full model covariance of the estimates is computed.
MAX_COVARIANCE_POINTS = 200
_IRLS_MAX_ITER = 60
_IRLS_TOL = 1e-7


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
        False when fewer than :data:`MIN_COVERED_POINTS` data taus lie in the term's
        region (one suffices if its interval excludes 0).
    n_covered : int
        Number of data taus in the term's region (where it makes up at least
        :data:`COVERAGE_SHARE` of the fitted sigma^2).
    region_tau_s : tuple of float
        Tau range (s) of the term's region (share of sigma^2 >= COVERAGE_SHARE),
        searched over 1000x beyond the data on each side; ``(nan, nan)`` if nowhere.
    status : str
        ``"fitted"`` (non-zero in the final fit), ``"at_bound"`` (the non-negative fit put
        it at zero) or ``"dropped"`` (it was positive but neither significant at the
        model's ``significance`` nor visible at two taus, so backward elimination removed
        it and refitted); the last two
        have value 0 and ``at_bound`` True.
    z_score : float
        Wald statistic ``a / se(a)`` of ``a = C_n^2``: in the final fit for a fitted term,
        when it was dropped for a dropped one, 0 at the bound.
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
    n_covered: int
    region_tau_s: tuple[float, float]
    status: str = "fitted"
    z_score: float = math.nan

    @property
    def slope(self) -> float:
        """Log-log slope of this term's Allan-deviation line (-1, -1/2, 0, 1/2, 1)."""
        return self.power / 2.0

    def to_dict(self) -> dict[str, Any]:
        return {"value": self.value, "stderr": self.stderr, "ci_low": self.ci_low,
                "ci_high": self.ci_high, "unit": self.unit, "c_coeff": self.c_coeff,
                "c_stderr": self.c_stderr, "c_unit": self.c_unit,
                "identifiable": self.identifiable, "at_bound": self.at_bound,
                "slope": self.slope, "n_covered": self.n_covered,
                "region_tau": list(self.region_tau_s), "status": self.status,
                "z": self.z_score}


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
        ``"wls"`` (EDF-weighted IRLS, the default), ``"gls"`` (full model covariance) or
        ``"ols"`` (unweighted, the traditional fit; for comparison).
    kind, units, axis : str
        From the Allan result; ``units`` is the rate unit of the curve.
    deg_per_hour_factor : float
        Multiply the curve's deviations by this to get deg/h.
    tau_s, dev, fitted_dev, weight : ndarray
        The points used in the fit, the fitted deviation there and each point's final
        diagonal weight relative to the largest (all 1 for ``ols``; for ``gls`` the
        inverse of the diagonal of the covariance).
    edf : ndarray
        Degrees of freedom used per point.
    edf_source : str
        ``"result"`` (from the Allan result), ``"ieee952"`` (N/m - 1) or ``"mixed"``.
    chi2, dof : float
        Pearson chi-square of the final fit and its (effective) degrees of freedom: the
        sum of the grid-density factors minus the number of non-zero terms.
    model_error : float
        Relative standard deviation on sigma^2 added to every point because the model
        misfits the curve beyond its sampling noise (maximum likelihood; 0 when the fit
        is consistent with the EDF; NaN for ``ols``).
    stderr_method : str
        How the standard errors were obtained: the sandwich or GLS with the model
        covariance of the adev or oadev estimates, or with totdev's EDF variances and the
        oadev correlations; the EDF diagonal (correlation ignored); or the OLS residual
        variance.
    iterations : int
    converged : bool
    readoff : SlopeReadoff
    excluded_tau_s : tuple of float
        Taus dropped before the fit (non-finite or non-positive deviation).
    significance : float or None
        Level of the term-selection and model-error tests (None: every requested term was
        kept and the model error is the unrestricted ML estimate; always None for ols).
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
    stderr_method: str
    iterations: int
    converged: bool
    readoff: SlopeReadoff
    excluded_tau_s: tuple[float, ...] = ()
    warnings: tuple[str, ...] = ()
    significance: float | None = None
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
    def dropped(self) -> tuple[str, ...]:
        """Terms removed by the backward elimination (status ``"dropped"``)."""
        return tuple(t.name for t in self.terms if t.status == "dropped")

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
        >>> np.round(model.curve([1.0, 3.0]), 4).tolist()   # sqrt(0.25/tau + 1e-4 tau/3)
        [0.5, 0.2888]
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
        """One row per term: value, stderr, CI, unit, C_n, identifiability, status, z."""
        rows = [{"term": t.name, "value": t.value, "stderr": t.stderr, "ci_low": t.ci_low,
                 "ci_high": t.ci_high, "unit": t.unit, "c_coeff": t.c_coeff,
                 "c_stderr": t.c_stderr, "slope": t.slope, "at_bound": t.at_bound,
                 "identifiable": t.identifiable, "status": t.status, "z": t.z_score}
                for t in self.terms]
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
                    "edf_source": self.edf_source, "stderr_method": self.stderr_method,
                    "deg_per_hour_factor": self.deg_per_hour_factor,
                    "significance": self.significance, "dropped": list(self.dropped)},
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
            note = ("at zero (upper limit)" if t.status == "at_bound" else
                    f"dropped, z = {t.z_score:.2f} (upper limit)" if t.status == "dropped"
                    else "")
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
        if self.significance is not None:
            lines.append(f"term selection: one-sided tests at {100 * self.significance:g} % "
                         f"(drop if z < {norm.ppf(1 - self.significance):.3f}); dropped: "
                         + (", ".join(self.dropped) or "none"))
        lines += [f"warning: {w}" for w in self.warnings]
        return "\n".join(lines)


# --------------------------------------------------------------------------- fit


def fit_noise(
    allan_result: Any,
    *,
    terms: Sequence[str] | str = NOISE_TERMS,
    method: FitMethod = "wls",
    confidence: float = 0.683,
    significance: float | None = 0.05,
) -> NoiseModel:
    """Fit the IEEE-952 noise terms to an Allan-deviation curve.

    Non-negative, EDF-weighted, iteratively reweighted least squares on sigma^2(tau), with
    a model-error term when the curve departs from the five-term model, and standard
    errors from the model covariance of the estimates (see the module docstring).

    Parameters
    ----------
    allan_result : AllanResult
        One curve (``kind`` adev, oadev or totdev) with ``tau_s``, ``dev``, ``units`` and,
        ideally, ``edf``, ``m``, ``n_samples`` and ``fs_hz``.  Pick one curve of a
        multi-axis result set first.
    terms : sequence of str or str
        Which of ``"Q", "N", "B", "K", "R"`` to fit (a comma-separated string works too).
    method : {"wls", "gls", "ols"}
        ``"wls"``: weights from each point's EDF (default).  ``"gls"``: generalized least
        squares with the full covariance of the estimates (module docstring; falls back to
        ``"wls"`` where that covariance is not available).  ``"ols"``: unweighted least squares on
        sigma^2 (the traditional fit; comparison only).
    confidence : float
        Level of the coefficient intervals, in (0, 1).
    significance : float or None
        Level, in (0, 0.5), of the one-sided tests that decide whether a term and the
        model error are supported by the data (module docstring, "Term selection"):
        backward elimination drops a term whose ``z = a / se(a)`` is below
        ``z_(1 - significance)`` and that makes up a quarter of sigma^2 at fewer than two
        taus, and refits; a model error is kept only if its
        likelihood-ratio statistic exceeds ``z_(1 - significance)^2``.  ``None`` keeps
        every requested term and the unrestricted ML model error.  Not used by ``"ols"``.

    Returns
    -------
    NoiseModel

    Raises
    ------
    DataError
        Bad ``terms``, ``method``, ``confidence``, ``significance``; a multi-axis result;
        a kind whose tau
        laws differ (mdev, hdev, ...); malformed arrays; no usable EDF.
    InsufficientDataError
        Fewer usable points than terms.

    Warns
    -----
    UnidentifiableTermWarning
        A term's region (where it makes up >= 25 % of sigma^2) holds fewer than two
        data taus.
    ConvergenceWarning
        The reweighting did not settle.
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
    >>> round(model["N"].c_coeff, 6), round(float(model["K"].c_coeff) * 3**0.5, 6)
    (0.5, 0.01)
    >>> round(model["N"].value, 6)    # N = C_-1 / 60 in deg/sqrt(h)
    0.008333
    """
    names = parse_terms(terms)
    method = check_choice("method", method, FIT_METHODS)  # type: ignore[assignment]
    confidence = check_fraction("confidence", confidence)
    if significance is not None:
        significance = check_fraction("significance", significance)
        if significance >= 0.5:
            raise DataError(f"significance must be in (0, 0.5) or None, got {significance!r}")
    curve = _unpack(allan_result)
    tau, dev = curve.tau, curve.dev
    if tau.size < len(names):
        raise InsufficientDataError(
            f"allan_result has {tau.size} usable taus, fewer than the {len(names)} terms "
            f"requested ({', '.join(names)}); use more taus or fewer terms")
    issued: list[str] = []
    if curve.excluded:
        _warn(issued, DataQualityWarning,
              f"{len(curve.excluded)} tau(s) with a non-finite or zero deviation were left "
              f"out of the noise fit: {', '.join(f'{t:.4g}' for t in curve.excluded[:5])}"
              + (" ..." if len(curve.excluded) > 5 else "") + " s", curve.axis)

    powers = np.array([TERM_POWER[n] for n in names], dtype=np.int64)
    design = tau[:, None] ** powers[None, :].astype(np.float64)
    scale_y = float(np.median(dev**2))
    y = dev**2 / scale_y
    basis = _covariance_basis(curve, powers) if method != "ols" else None
    covm = CovarianceModel(basis, powers, curve.kind) if basis is not None else None
    if method == "gls" and covm is None:
        method = "wls"  # type: ignore[assignment]
        _warn(issued, FogtsWarning,
              "method='gls' needs the model covariance of the estimates, i.e. a curve with "
              f"m, n_samples and fs_hz of at most {MAX_COVARIANCE_POINTS} taus; fitted "
              "with method='wls' instead", curve.axis)
    testing = significance is not None and method != "ols"
    z_crit = float(norm.ppf(1.0 - significance)) if testing and significance else math.inf
    # chi-bar-squared 50:50 critical value of the boundary likelihood-ratio test: z^2
    crit = z_crit**2 if testing else 0.0
    density = _octave_density(tau)

    def run(free: npt.NDArray[np.bool_]) -> _Fit:
        if method == "ols":
            return _fit_ols(design, y)
        wls = _fit_wls(design, y, curve.edf, density, covm, free, crit)
        if method == "gls":
            assert covm is not None
            return _fit_gls(design, y, curve.edf, covm, wls, free, crit)
        return wls

    free = np.ones(len(names), dtype=bool)
    fit = run(free)
    a = _round_off_zero(design, fit)
    dropped_z: dict[int, float] = {}
    while testing:  # backward elimination (module docstring, "Term selection")
        free &= a > 0  # terms the NNLS put at zero stay there
        z_act = _z_scores(fit, a)
        covered = np.count_nonzero(design * a[None, :] >= COVERAGE_SHARE * fit.mu[:, None],
                                   axis=0)
        weak = [(z, j) for j, z in z_act.items()
                if z < z_crit and covered[j] < MIN_COVERED_POINTS]
        if not weak or np.count_nonzero(free) <= 1:
            break
        z_min, j_min = min(weak)
        dropped_z[j_min] = z_min
        free[j_min] = False
        fit = run(free)
        a = _round_off_zero(design, fit)
    if not fit.converged:
        _warn(issued, ConvergenceWarning,
              f"the noise-fit reweighting did not converge in {_IRLS_MAX_ITER} iterations; "
              "the coefficients are from the last iteration", curve.axis)
    active = a > 0
    z_final = _z_scores(fit, a)
    z = float(norm.ppf(0.5 + confidence / 2))
    factor = to_deg_per_hour_factor(curve.units)
    s = math.sqrt(scale_y) * factor  # sqrt of scaled sigma^2 -> deg/h
    idx_active = np.flatnonzero(active)
    var_active = np.diag(fit.cov(idx_active)) if idx_active.size else np.zeros(0)
    fit_terms: list[NoiseTerm] = []
    for j, name in enumerate(names):
        if active[j]:
            se_a = math.sqrt(max(float(var_active[int(np.searchsorted(idx_active, j))]), 0.0))
            c = math.sqrt(a[j])
            c_se = se_a / (2 * c)
            lo_a, hi_a = max(0.0, a[j] - z * se_a), a[j] + z * se_a
            status, z_score = "fitted", z_final[j]
        else:
            idx = np.append(np.flatnonzero(active), j)
            se_bound = math.sqrt(max(float(fit.cov(idx)[-1, -1]), 0.0))
            c, c_se = 0.0, math.nan
            lo_a, hi_a = 0.0, z * se_bound
            status = "dropped" if j in dropped_z else "at_bound"
            z_score = dropped_z.get(j, 0.0)
        tf = TERM_FACTOR[name]
        fit_terms.append(NoiseTerm(
            name=name, value=tf * c * s, stderr=tf * c_se * s,
            ci_low=tf * math.sqrt(lo_a) * s, ci_high=tf * math.sqrt(hi_a) * s,
            unit=TERM_UNIT[name], c_coeff=c * s, c_stderr=c_se * s, c_unit=C_UNIT[name],
            power=TERM_POWER[name], at_bound=not bool(active[j]), identifiable=True,
            n_covered=0, region_tau_s=(math.nan, math.nan), status=status, z_score=z_score))

    model = NoiseModel(
        terms=tuple(fit_terms), confidence=confidence, method=method, kind=curve.kind,
        units=curve.units, axis=curve.axis, deg_per_hour_factor=factor, tau_s=tau, dev=dev,
        fitted_dev=np.sqrt(fit.mu * scale_y), weight=fit.w / np.max(fit.w), edf=curve.edf,
        edf_source=curve.edf_source, chi2=fit.chi2, dof=fit.dof,
        model_error=fit.model_error, stderr_method=fit.stderr_method,
        iterations=fit.iterations, converged=fit.converged,
        readoff=_slope_readoff(tau, dev, factor, curve.edf), excluded_tau_s=tuple(curve.excluded),
        significance=significance if testing else None,
        _a=tuple(float(v) * scale_y for v in a))
    fit_terms = _identifiability(model, tau, issued)
    return NoiseModel(**{**_fields(model), "terms": tuple(fit_terms),
                         "warnings": tuple(issued)})


def parse_terms(terms: Sequence[str] | str) -> tuple[str, ...]:
    """Validate a term selection; returns the names in the order Q, N, B, K, R.

    Examples
    --------
    >>> parse_terms("k, n")
    ('N', 'K')
    """
    if isinstance(terms, str):
        items: list[Any] = [t.strip() for t in terms.split(",") if t.strip()]
    else:
        try:
            items = list(terms)
        except TypeError:
            raise DataError(f"terms must be a sequence of Q, N, B, K, R, got {terms!r}") from None
    if not items:
        raise DataError(f"terms must name at least one of Q, N, B, K, R, got {terms!r}")
    for t in items:
        if not isinstance(t, str) or t.strip().upper() not in TERM_POWER:
            raise DataError(f"terms must be drawn from Q, N, B, K, R; got {t!r}")
    upper = [t.strip().upper() for t in items]
    if len(set(upper)) != len(upper):
        raise DataError(f"terms must not repeat a term, got {terms!r}")
    return tuple(n for n in NOISE_TERMS if n in upper)


# --------------------------------------------------------------------------- input


@dataclass(frozen=True)
class _Curve:
    tau: FloatArray
    dev: FloatArray
    edf: FloatArray
    edf_source: str
    units: str
    kind: str
    axis: str
    excluded: list[float]
    m: IntArray | None
    n_samples: int | None
    fs_hz: float | None


def _fields(model: NoiseModel) -> dict[str, Any]:
    return {k: getattr(model, k) for k in model.__dataclass_fields__}


def _warn(issued: list[str], category: type[Warning], message: str, axis: str = "") -> None:
    """Emit a warning (prefixed with the axis name, if any) and record it."""
    message = f"axis {axis!r}: {message}" if axis else message
    issued.append(message)
    warnings.warn(message, category, stacklevel=3)


def _unpack(res: Any) -> _Curve:
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
    given = _attr_array(res, "edf", n)
    m_all = _attr_array(res, "m", n)
    n_samples = getattr(res, "n_samples", None)
    edf = given.copy()
    missing_edf = ~(np.isfinite(edf) & (edf > 0))
    if np.any(missing_edf) and n_samples is not None:
        # IEEE Std 952-1997 C.3: %error of sigma = 1/sqrt(2(N/m - 1)), i.e. edf = N/m - 1
        edf[missing_edf] = np.maximum(float(n_samples) / m_all[missing_edf] - 1.0, 1.0)
    ok = np.isfinite(dev) & (dev > 0)
    excluded = [float(t) for t in tau[~ok]]
    usable = np.isfinite(edf) & (edf > 0)
    if not np.all(usable[ok]):
        bad = float(tau[ok & ~usable][0])
        raise DataError(f"allan_result has no usable edf at tau = {bad:.6g} s (and no "
                        "n_samples and m to fall back on IEEE 952's N/m - 1)")
    from_result = np.isfinite(given[ok]) & (given[ok] > 0)
    source = ("result" if np.all(from_result) else "ieee952" if not np.any(from_result)
              else "mixed")
    fs = getattr(res, "fs_hz", None)
    m_ok = m_all[ok]
    have_m = bool(np.all(np.isfinite(m_ok)) and np.all(m_ok >= 1))
    return _Curve(tau=tau[ok], dev=dev[ok], edf=edf[ok], edf_source=source, units=units,
                  kind=kind, axis=str(getattr(res, "axis", "")), excluded=excluded,
                  m=m_ok.astype(np.int64) if have_m else None,
                  n_samples=int(n_samples) if n_samples is not None else None,
                  fs_hz=float(fs) if fs is not None and float(fs) > 0 else None)


def _attr_array(res: Any, name: str, n: int) -> FloatArray:
    value = getattr(res, name, None)
    if value is None:
        return np.full(n, np.nan)
    arr = np.asarray(value, dtype=np.float64)
    if arr.shape != (n,):
        raise DataError(f"allan_result.{name} must have the shape of tau_s ({n},), got "
                        f"{arr.shape}")
    return arr


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


# --------------------------------------------------------------------------- covariance


def _covariance_basis(curve: _Curve, powers: IntArray) -> FloatArray | None:
    """The model-covariance basis of the curve's estimates (:mod:`fogts.allan.covariance`),
    or None without ``m``, ``n_samples`` and ``fs_hz`` or with more than
    :data:`MAX_COVARIANCE_POINTS` taus."""
    if (curve.m is None or curve.n_samples is None or curve.fs_hz is None
            or curve.tau.size > MAX_COVARIANCE_POINTS):
        return None
    return covariance_basis(curve.kind, curve.m, curve.n_samples, curve.fs_hz, powers)


# --------------------------------------------------------------------------- fits


@dataclass(frozen=True)
class _Fit:
    a: FloatArray             # squared coefficients (scaled units)
    mu: FloatArray            # model sigma^2 at the data taus
    w: FloatArray             # final diagonal weights
    cov: Callable[[IntArray], FloatArray]  # covariance of a[idx] with idx free, rest fixed
    chi2: float
    dof: float
    model_error: float
    stderr_method: str
    iterations: int
    converged: bool


def _wnnls(design: FloatArray, y: FloatArray, w: FloatArray) -> FloatArray:
    """Weighted NNLS with column scaling (the basis spans many decades)."""
    sw = np.sqrt(w)
    return _nnls_scaled(design * sw[:, None], y * sw)


def _nnls_scaled(a: FloatArray, b: FloatArray) -> FloatArray:
    col = np.linalg.norm(a, axis=0)
    col[col == 0] = 1.0
    sol, _ = nnls(a / col, b, maxiter=50 * a.shape[1])
    return np.asarray(sol / col, dtype=np.float64)


def _forward_substitution(lower: npt.NDArray[np.floating[Any]], rhs: FloatArray) -> FloatArray:
    """Solve ``lower @ x = rhs`` row by row.

    For these small systems (at most MAX_COVARIANCE_POINTS rows) this is ~100x faster than
    LAPACK's threaded triangular solve on a busy machine, and exact to round-off.
    """
    x = np.empty_like(rhs)
    for i in range(lower.shape[0]):
        x[i] = (rhs[i] - lower[i, :i] @ x[:i]) / lower[i, i]
    return x


def _scaled_inverse(normal: FloatArray) -> FloatArray:
    d = np.sqrt(np.abs(np.diag(normal)))
    d[d == 0] = 1.0
    return np.asarray(np.linalg.pinv(normal / np.outer(d, d), rcond=1e-13) / np.outer(d, d),
                      dtype=np.float64)


def _irls(step: Callable[[FloatArray, FloatArray], tuple[FloatArray, FloatArray]],
          mu0: FloatArray, a0: FloatArray) -> tuple[FloatArray, FloatArray, int, bool]:
    """Iterate ``(a, mu) -> step`` until mu changes by < 1e-7 relative (damped late)."""
    mu, a = mu0, a0
    for it in range(1, _IRLS_MAX_ITER + 1):
        a, new = step(mu, a)
        if it > _IRLS_MAX_ITER // 3:  # damp a slow oscillation between active sets
            new = np.sqrt(new * mu)
        change = float(np.max(np.abs(new - mu) / mu))
        mu = new
        if change < _IRLS_TOL:
            return a, mu, it, True
    return a, mu, _IRLS_MAX_ITER, False


def _ml_eps2(nll: Callable[[float], float], crit: float) -> float:
    """The model-error variance eps2 >= 0 that minimises ``nll`` (profile likelihood).

    eps2 = 0 is kept unless the likelihood-ratio statistic ``2 (nll(0) - nll(eps2))``
    exceeds ``crit`` (the chi-bar-squared critical value of the boundary test; 0 accepts
    any improvement, i.e. the unrestricted ML estimate).
    """
    base = nll(0.0)
    best = minimize_scalar(lambda t: nll(math.exp(t)), bounds=(math.log(1e-8), math.log(10.0)),
                           method="bounded", options={"xatol": 1e-3})
    return math.exp(float(best.x)) if 2.0 * (base - float(best.fun)) > crit else 0.0


def _nnls_free(a: FloatArray, b: FloatArray, free: npt.NDArray[np.bool_]) -> FloatArray:
    """NNLS on the ``free`` columns only; the other coefficients are fixed at 0."""
    out = np.zeros(a.shape[1])
    out[free] = _nnls_scaled(a[:, free], b)
    return out


def _fit_wls(design: FloatArray, y: FloatArray, edf: FloatArray, density: FloatArray,
             covm: CovarianceModel | None, free: npt.NDArray[np.bool_], crit: float) -> _Fit:
    """EDF-weighted IRLS + ML model error; sandwich errors (module docstring).

    Only the ``free`` terms are fitted (the others stay at 0); ``crit`` is the critical
    value of the likelihood-ratio test of the model error (:func:`_ml_eps2`).
    """
    floor = 1e-12 * float(np.max(y))
    state: dict[str, Any] = {"mu": y.copy(), "a": np.zeros(design.shape[1]), "iters": 0}

    def solve(eps2: float) -> tuple[FloatArray, FloatArray, FloatArray, int, bool]:
        rel = 2.0 / edf + eps2

        def step(mu: FloatArray, a: FloatArray) -> tuple[FloatArray, FloatArray]:
            sw = np.sqrt(density / (rel * mu**2))
            a_new = _nnls_free(design * sw[:, None], y * sw, free)
            return a_new, np.maximum(design @ a_new, floor)

        a, mu, it, ok = _irls(step, state["mu"], state["a"])
        state.update(mu=mu, a=a, iters=state["iters"] + it)
        return a, mu, density / (rel * mu**2), it, ok

    def nll(eps2: float) -> float:
        # Gamma likelihood of sigma^2-hat with mean mu and shape k = 1 / (2/edf + eps2)
        _, mu, _, _, _ = solve(eps2)
        k = 1.0 / (2.0 / edf + eps2)
        ll = k * np.log(k) - k * np.log(mu) + (k - 1) * np.log(y) - k * y / mu - gammaln(k)
        return -float(np.sum(density * ll))

    eps2 = _ml_eps2(nll, crit)
    a, mu, w, _, ok = solve(eps2)
    chi2 = float(np.sum(w * (y - mu) ** 2))
    dof = float(np.sum(density)) - np.count_nonzero(a > 0)
    if covm is not None:
        v = covm(a, mu, edf) + np.diag(eps2 * mu**2)
        how = f"sandwich with {covm.label}"
    else:
        v = np.diag(mu**2 * (2.0 / edf + eps2))
        how = "EDF diagonal (correlation between taus ignored)"

    def cov(idx: IntArray) -> FloatArray:
        x = design[:, idx] * w[:, None]
        h_inv = _scaled_inverse(design[:, idx].T @ x)
        return h_inv @ (x.T @ v @ x) @ h_inv

    return _Fit(a, mu, w, cov, chi2, dof, math.sqrt(eps2), how, int(state["iters"]), ok)


def _fit_gls(design: FloatArray, y: FloatArray, edf: FloatArray, covm: CovarianceModel,
             start: _Fit, free: npt.NDArray[np.bool_], crit: float) -> _Fit:
    """GLS with the model covariance recomputed from the fit (IRLS) + ML model error."""
    floor = 1e-12 * float(np.max(y))
    state: dict[str, Any] = {"iters": 0}

    def cov_of(a: FloatArray, mu: FloatArray, eps2: float) -> FloatArray:
        return covm(a, mu, edf) + np.diag((eps2 + 1e-10) * mu**2)

    def solve(eps2: float) -> tuple[FloatArray, FloatArray, FloatArray, int, bool]:
        def step(mu: FloatArray, a: FloatArray) -> tuple[FloatArray, FloatArray]:
            chol = np.linalg.cholesky(cov_of(a, mu, eps2))
            white = _forward_substitution(chol, np.column_stack([design, y]))
            a_new = _nnls_free(white[:, :-1], white[:, -1], free)
            return a_new, np.maximum(design @ a_new, floor)

        a, mu, it, ok = _irls(step, start.mu, start.a)
        state["iters"] += it
        return a, mu, cov_of(a, mu, eps2), it, ok

    def nll(eps2: float) -> float:
        # Gaussian approximation: r' V^-1 r + log det V
        _, mu, v, _, _ = solve(eps2)
        r = y - mu
        chol = np.linalg.cholesky(v)
        z = _forward_substitution(chol, r[:, None])[:, 0]
        return 0.5 * float(z @ z) + float(np.sum(np.log(np.diag(chol))))

    eps2 = _ml_eps2(nll, crit)
    a, mu, v, _, ok = solve(eps2)
    r = y - mu
    v_inv = np.linalg.inv(v)

    def cov(idx: IntArray) -> FloatArray:
        x = design[:, idx]
        return _scaled_inverse(x.T @ v_inv @ x)

    return _Fit(a, mu, 1.0 / np.diag(v), cov, float(r @ v_inv @ r),
                float(y.size - np.count_nonzero(a > 0)), math.sqrt(eps2),
                f"GLS with {covm.label}",
                start.iterations + int(state["iters"]), ok)


def _fit_ols(design: FloatArray, y: FloatArray) -> _Fit:
    """Unweighted NNLS on sigma^2 (the traditional fit); covariance s^2 (A^T A)^-1."""
    w = np.ones_like(y)
    a = _wnnls(design, y, w)
    mu = design @ a
    rss = float(np.sum((y - mu) ** 2))
    dof = float(y.size - np.count_nonzero(a > 0))
    s2 = rss / dof if dof > 0 else math.nan

    def cov(idx: IntArray) -> FloatArray:
        x = design[:, idx]
        return s2 * _scaled_inverse(x.T @ x)

    return _Fit(a, mu, w, cov, rss, dof, math.nan, "OLS residual variance", 1, True)


def _round_off_zero(design: FloatArray, fit: _Fit) -> FloatArray:
    """The fitted ``a`` with NNLS round-off (< 1e-9 of the curve at every tau) set to 0."""
    share = np.max(design / fit.mu[:, None], axis=0) * fit.a
    return np.where(share < 1e-9, 0.0, fit.a)


def _z_scores(fit: _Fit, a: FloatArray) -> dict[int, float]:
    """Wald statistic ``a_j / se(a_j)`` of every non-zero term (covariance of the fit)."""
    idx = np.flatnonzero(a > 0)
    if not idx.size:
        return {}
    var = np.diag(fit.cov(idx))
    return {int(j): (float(a[j] / math.sqrt(v)) if v > 0 else math.inf)
            for j, v in zip(idx, var, strict=True)}


# --------------------------------------------------------------------------- read-offs


def _slope_readoff(tau: FloatArray, dev: FloatArray, factor: float,
                   edf: FloatArray | None = None) -> SlopeReadoff:
    """IEEE 952 Annex C / MATLAB ``allanvar`` example: lines through the point whose local
    log-log slope is closest to -1/2 (+1/2), read at tau = 1 s (3 s); B = minimum / 0.664.

    The minimum is :func:`fogts.allan.readout.read_curve`'s: the lowest point among those
    with at least ``MIN_EDF_FOR_MINIMUM`` degrees of freedom, so that a last point with two
    terms that happens to fall low is not read as the flicker floor."""
    logt, logd = np.log10(tau), np.log10(dev)
    slopes = np.diff(logd) / np.diff(logt) if tau.size >= 2 else np.array([math.nan])

    def line(target: float, at: float) -> tuple[float, float, float]:
        if not np.any(np.isfinite(slopes)):
            return math.nan, math.nan, math.nan
        i = int(np.nanargmin(np.abs(slopes - target)))
        b = logd[i] - target * logt[i]
        return float(10 ** (target * math.log10(at) + b)), float(tau[i]), float(slopes[i])

    n_dev, tau_n, slope_n = line(-0.5, 1.0)
    k_dev, tau_k, slope_k = line(0.5, 3.0)
    if tau.size >= 2:
        floor = read_curve(tau, dev, edf=edf)
        b_dev, tau_b = floor.dev_min, floor.tau_min_s
    else:
        b_dev, tau_b = float(dev[0]), float(tau[0])
    return SlopeReadoff(
        N=n_dev * factor / 60.0, K=k_dev * factor * 60.0, B=b_dev * factor / B_PLATEAU,
        tau_N_s=tau_n, tau_K_s=tau_k, tau_B_s=tau_b, slope_N=slope_n, slope_K=slope_k,
        points=(("N", 1.0, n_dev), ("K", 3.0, k_dev), ("B", tau_b, b_dev)))


def _identifiability(model: NoiseModel, tau: FloatArray, issued: list[str]
                     ) -> list[NoiseTerm]:
    """Where each term makes up >= COVERAGE_SHARE of the fitted sigma^2 (module docstring)."""
    share = np.vstack(list(model.lines(tau).values())) ** 2 / model.curve(tau) ** 2
    wide = np.logspace(math.log10(tau[0]) - 3, math.log10(tau[-1]) + 3, 601)
    wide_share = np.vstack(list(model.lines(wide).values())) ** 2 / model.curve(wide) ** 2
    pct = f"{100 * COVERAGE_SHARE:g} %"
    out: list[NoiseTerm] = []
    for j, term in enumerate(model.terms):
        n_cov = int(np.count_nonzero(share[j] >= COVERAGE_SHARE))
        where = wide_share[j] >= COVERAGE_SHARE
        region = ((float(wide[where][0]), float(wide[where][-1])) if np.any(where)
                  else (math.nan, math.nan))
        ok = n_cov >= MIN_COVERED_POINTS or (n_cov == 1 and term.ci_low > 0)
        if not ok:
            if term.status == "dropped":
                why = (f"it was dropped as not significant, z = {term.z_score:.2f} at "
                       f"level {model.significance:g}")
            elif term.at_bound:
                why = "it was fitted to zero"
            elif not np.any(where):
                why = f"it never reaches {pct} of the fitted curve"
            else:
                why = f"it would reach {pct} only at tau {region[0]:.3g}..{region[1]:.3g} s"
            _warn(issued, UnidentifiableTermWarning,
                  f"noise term {term.name} ({TERM_DESCRIPTION[term.name]}, slope "
                  f"{term.slope:+g}) is not identifiable from taus {tau[0]:.4g}..{tau[-1]:.4g}"
                  f" s: it makes up at least {pct} of the fitted sigma^2 at {n_cov} of "
                  f"{tau.size} taus ({why}); treat its value as an upper limit", model.axis)
        out.append(NoiseTerm(**{**{k: getattr(term, k) for k in term.__dataclass_fields__},
                                "identifiable": ok, "n_covered": n_cov,
                                "region_tau_s": region}))
    return out


def _tau_array(tau_s: Any) -> FloatArray:
    tau = np.atleast_1d(np.asarray(tau_s, dtype=np.float64))
    if tau.ndim != 1 or not np.all(np.isfinite(tau) & (tau > 0)):
        raise DataError(f"tau_s must be finite and > 0, got {tau_s!r}")
    return tau
