"""IEEE-952 noise terms from an Allan-variance curve, with honest uncertainties (fit_noise).

The five classical terms of IEEE Std 952-1997 Annex C (:mod:`fogts.allan.terms`; DESIGN.md
"Definitions") add in the Allan variance of a rate signal:

.. math::

    \\sigma^2(\\tau) = \\frac{R^2\\tau^2}{2} + \\frac{K^2\\tau}{3} + B^2\\frac{2\\ln 2}{\\pi}
                     + \\frac{N^2}{\\tau} + \\frac{3Q^2}{\\tau^2}
                   = \\sum_{n=-2}^{2} C_n^2\\,\\tau^n .

The model is linear in the squared coefficients :math:`a_n = C_n^2 \\ge 0`, so the fit is
non-negative least squares on :math:`\\sigma^2(\\tau)`, in four steps:

1. the curve (:mod:`fogts.allan.noise_input`): the usable points and their equivalent
   degrees of freedom (the Allan result's, else IEEE 952 C.3's :math:`N/m - 1`);
2. weighted least squares (:mod:`fogts.allan.noise_lsq`): weights from the EDF evaluated at
   the model (IRLS, NIST SP1065 sec. 5.3), a maximum-likelihood model error for curves that
   depart from the five-term model (Paule & Mandel 1982), the coefficient covariance;
3. term selection (:mod:`fogts.allan.noise_selection`): backward elimination of terms that
   are neither significant nor visible in the curve (Self & Liang 1987);
4. the result (:mod:`fogts.allan.noise_model`): values in deg/h-based units, intervals,
   identifiability, and the classic slope read-offs (:func:`fogts.allan.readoff.slope_readoff`,
   IEEE 952 Annex C; MATLAB's ``allanvar`` example) beside the fit for comparison, never as
   the answer.

Standard errors and confidence intervals
    Overlapping Allan variances at neighbouring taus are strongly correlated, so the
    standard errors come from the sandwich (``wls``) or GLS covariance with the model
    covariance of the estimates (:mod:`fogts.allan.covariance`; totdev: its EDF variances
    with the oadev correlations), or from the EDF diagonal where that covariance is not
    available; ``stderr_method`` says which (:mod:`fogts.allan.noise_lsq`).  Each
    :math:`a_n` gets the normal interval :math:`a_n \\pm z\\,se(a_n)` clipped at 0, and
    :math:`C_n` the square roots of its ends; a term at zero has an upper limit
    (:mod:`fogts.allan.noise_selection`).  The intervals of the terms measured below bias
    instability's region (Q, N) then also cover the fit with a band-limited flicker
    (:mod:`fogts.allan.noise_band`): a flat B line extrapolated to short taus where real
    bias instability has rolled off moves N by about one of its (very small) standard
    errors; B's and K's intervals are the equal-weight mixture of the flat and the
    band-limited fit's (the roll-off moves them, through their trade-off with N, by up to
    about one standard error).
"""

from __future__ import annotations

import dataclasses
import math
import re
import warnings
from collections.abc import Iterator, Sequence
from contextlib import contextmanager
from typing import Any

import numpy as np

from fogts._validate import check_choice, check_fraction, check_positive
from fogts.allan.covariance import CovarianceModel
from fogts.allan.distributions import norm_ppf
from fogts.allan.markov import split_terms
from fogts.allan.noise_band import widen_for_band_limits
from fogts.allan.noise_extra import fit_extra_terms
from fogts.allan.noise_input import FITTABLE_KINDS, FitCurve, read_fit_curve
from fogts.allan.noise_lsq import (
    FIT_METHODS,
    IRLS_MAX_ITER,
    MAX_COVARIANCE_POINTS,
    FitMethod,
    LsqProblem,
    curve_covariance_basis,
    octave_density,
)
from fogts.allan.noise_model import NoiseModel, NoiseTerm
from fogts.allan.noise_selection import (
    COVERAGE_SHARE,
    MIN_COVERED_POINTS,
    TermSelection,
    backward_elimination,
    floorless_flicker,
    identify_terms,
    term_estimates,
)
from fogts.allan.readoff import SlopeReadoff, readoff_of
from fogts.allan.terms import (
    NOISE_TERMS,
    TERM_POWER,
    TERM_UNIT,
    c_from_terms,
    parse_terms,
    terms_from_c,
)
from fogts.errors import (
    ConvergenceWarning,
    DataError,
    DataQualityWarning,
    FogtsWarning,
    InsufficientDataError,
    UnidentifiableTermWarning,
)
from fogts.units import base_unit_factor, quantity_of

__all__ = ["COVERAGE_SHARE", "FITTABLE_KINDS", "FIT_METHODS", "MAX_COVARIANCE_POINTS",
           "MIN_COVERED_POINTS", "NOISE_TERMS", "TERM_UNIT", "NoiseModel", "NoiseTerm",
           "SlopeReadoff", "c_from_terms", "fit_noise", "parse_terms", "terms_from_c"]


# Long only by its numpydoc docstring; the steps are the helpers below.
def fit_noise(
    allan_result: Any,
    *,
    terms: Sequence[str] | str = NOISE_TERMS,
    method: FitMethod = "wls",
    confidence: float = 0.683,
    significance: float | None = 0.05,
    tau_range: tuple[float | None, float | None] | None = None,
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
        Which of ``"Q", "N", "B", "K", "R"`` to fit (a comma-separated string works too),
        and optionally ``"M"`` (first-order Markov noise: correlation time ``T_c`` and
        driving noise ``q_c``) and ``"S"`` (a sinusoid: ``f_0`` and ``Omega_0``), fitted
        with their nonlinear parameter profiled and a likelihood-ratio test of whether
        adding each is significant (:mod:`fogts.allan.noise_extra`; results in
        ``NoiseModel.extra_terms``).
    method : {"wls", "gls", "ols", "gmwm", "ml"}
        ``"wls"``: weights from each point's EDF (default).  ``"gls"``: generalized least
        squares with the full covariance of the estimates (:mod:`fogts.allan.noise_lsq`;
        falls back to ``"wls"`` where that covariance is not available).  ``"ols"``:
        unweighted least squares on sigma^2 (the traditional fit; comparison only).
        ``"gmwm"``: the generalized method of wavelet moments with a composite model of
        power laws and up to three Gauss-Markov terms for B
        (:func:`fogts.allan.gmwm.fit_gmwm`, with its defaults; ``significance`` is the
        level of its J test, 0.05 if None; oadev or adev curves with ``m``,
        ``n_samples`` and ``fs_hz``; terms M and S are not available).  ``"ml"``: exact
        Gaussian maximum likelihood needs the record itself, so here it raises a
        DataError that points to :func:`fogts.allan.ml.fit_noise_ml`.
    confidence : float
        Level of the coefficient intervals, in (0, 1).
    significance : float or None
        Level, in (0, 0.5), of the one-sided tests that decide whether a term and the
        model error are supported by the data (:mod:`fogts.allan.noise_selection`):
        backward elimination drops a term whose ``z = a / se(a)`` is below
        ``z_(1 - significance)`` and that makes up a quarter of sigma^2 at fewer than two
        taus, and refits; a model error is kept only if its likelihood-ratio statistic
        exceeds ``z_(1 - significance)^2``.  ``None`` keeps every requested term and the
        unrestricted ML model error.  Not used by ``"ols"``.
    tau_range : (float or None, float or None), optional
        Fit only the points with ``tau_min <= tau <= tau_max`` seconds (None: no bound), to
        leave out a range the five terms do not describe (a sampling filter at the shortest
        taus, say); needs an :class:`~fogts.allan.result.AllanResult`.

    Returns
    -------
    NoiseModel

    Raises
    ------
    DataError
        Bad ``terms``, ``method``, ``confidence``, ``significance``; a multi-axis result;
        a kind whose tau laws differ (mdev, hdev, ...); malformed arrays; no usable EDF.
    InsufficientDataError
        Fewer usable points than terms.

    Warns
    -----
    UnidentifiableTermWarning
        A term's region (where it makes up >= 25 % of sigma^2) holds fewer than two
        data taus; or a term dominates the fitted sigma^2 only at points with fewer than
        10 EDF (it is then an upper limit, :attr:`NoiseTerm.low_edf_taus`).
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
    names, extras = split_terms(terms)
    shown = None  # with a fit range: the whole curve, which the read-offs are read from
    if tau_range is not None:
        shown, allan_result = allan_result, _within(allan_result, tau_range, len(names))
    method = check_choice("method", method, FIT_METHODS)  # type: ignore[assignment]
    confidence = check_fraction("confidence", confidence)
    significance = _check_significance(significance)
    if method == "ml":
        raise DataError("method='ml' needs the rate record, which an Allan curve does not "
                        "carry; call fogts.allan.ml.fit_noise_ml(rate, fs_hz, units=...) "
                        "on the series instead")
    if method == "gmwm":
        from fogts.allan.gmwm import fit_gmwm  # gmwm builds on this module's pieces

        gmwm = _read_off_whole(fit_gmwm(
            allan_result, terms=terms, confidence=confidence,
            significance=significance if significance is not None else 0.05), shown)
        return _floor_rule(gmwm, list(gmwm.warnings))
    curve = read_fit_curve(allan_result)
    n_params = len(names) + 2 * len(extras)  # M and S: an amplitude and a parameter each
    if curve.tau.size < n_params:
        raise InsufficientDataError(
            f"allan_result (the Allan curve) has {curve.tau.size} usable "
            f"tau{'s' if curve.tau.size != 1 else ''} "
            f"({', '.join(f'{t:.4g}' for t in curve.tau.tolist())} s), fewer than the {n_params} "
            + ("terms" if not extras else "parameters of the terms")
            + f" requested ({', '.join(names + extras)}); use more taus (taus=) or "
              "fewer terms (terms=), or a longer record")
    if extras and quantity_of(curve.units) != "rate":
        raise DataError(f"terms {', '.join(extras)} (Markov, sinusoid) are fitted to gyro "
                        f"rate curves only; this curve is in {curve.units!r} (an "
                        "accelerometer); use terms from Q, N, B, K, R")
    issued: list[str] = []
    if curve.excluded:
        _warn(issued, DataQualityWarning, _excluded_message(curve.excluded), curve.axis)
    # one-sided tests of the terms and of the model error at z_(1 - significance)
    z_crit = (float(norm_ppf(1.0 - significance))
              if significance is not None and method != "ols" else None)
    problem = _least_squares_problem(curve, names, method, z_crit)
    if problem.method != method:
        _warn(issued, FogtsWarning,
              "method='gls' needs the model covariance of the estimates, i.e. a curve with "
              f"m, n_samples and fs_hz of at most {MAX_COVARIANCE_POINTS} taus; fitted "
              "with method='wls' instead", curve.axis)
    selection = backward_elimination(problem, z_crit)
    extra_fit = None
    if extras:  # the optional Markov / sinusoid terms (fogts.allan.noise_extra)
        extra_fit = fit_extra_terms(curve, problem, selection, extras, z_crit,
                                    significance if significance is not None else 0.05,
                                    base_unit_factor(curve.units))
        problem, selection = extra_fit.problem, extra_fit.selection
    if not selection.fit.converged:
        _warn(issued, ConvergenceWarning,
              f"the noise-fit reweighting did not converge in {IRLS_MAX_ITER} iterations; "
              "the coefficients are from the last iteration", curve.axis)
    model = _noise_model(curve, names, problem, selection, confidence,
                         significance if z_crit is not None else None)
    if extra_fit is not None:
        model = dataclasses.replace(model, extra_terms=extra_fit.terms)
    identified, messages = identify_terms(model, curve.tau)
    for message in messages:
        _warn(issued, UnidentifiableTermWarning, message, curve.axis)
    return _floor_rule(_read_off_whole(dataclasses.replace(model, terms=identified), shown),
                       issued)


@contextmanager
def curve_named(name: str) -> Iterator[None]:
    """Inside the block, an error of :func:`fit_noise` that opens with its argument
    ``allan_result`` names the curve ``name`` instead: for a caller that computed the
    curve itself from a record, where no ``allan_result`` was given
    (:func:`fogts.pipeline.analyse_allan_axis`: "the Allan curve of axis 'x' of FILE")."""
    try:
        yield
    except DataError as exc:
        text, n = re.subn(r"^allan_result(?: \(the Allan curve\))?", name, str(exc))
        if not n:
            raise
        raise type(exc)(text) from exc


def _read_off_whole(model: NoiseModel, shown: Any) -> NoiseModel:
    """``model`` (fitted over part of ``shown``) with the slope read-offs of the whole curve
    ``shown``, the one the points table and the curve read-out show; those read outside the
    fitted taus say so (:attr:`~fogts.allan.readoff.SlopeReadoff.outside`).  ``shown`` None
    (no fit range): ``model`` as it is."""
    if shown is None:
        return model
    fit_taus = (float(model.tau_s[0]), float(model.tau_s[-1]))
    readoff = readoff_of(read_fit_curve(shown), model.deg_per_hour_factor, model.quantity,
                         fit_tau_s=fit_taus)
    return dataclasses.replace(model, readoff=readoff)


def _floor_rule(model: NoiseModel, issued: list[str]) -> NoiseModel:
    """``model`` with B an upper limit where its read-off found no floor
    (:func:`~fogts.allan.noise_selection.floorless_flicker`), warned of, and ``issued`` as
    its warnings."""
    terms, message = floorless_flicker(model)
    if message:
        _warn(issued, UnidentifiableTermWarning, message, model.axis, stacklevel=4)
    return dataclasses.replace(model, terms=terms, warnings=tuple(issued))


def _check_significance(significance: float | None) -> float | None:
    if significance is None:
        return None
    significance = check_fraction("significance", significance)
    if significance >= 0.5:
        raise DataError(f"significance must be in (0, 0.5) or None, got {significance!r}")
    return significance


def _excluded_message(excluded: list[float]) -> str:
    return (f"{len(excluded)} tau(s) with a non-finite or zero deviation were left out of "
            f"the noise fit: {', '.join(f'{t:.4g}' for t in excluded[:5])}"
            + (" ..." if len(excluded) > 5 else "") + " s")


def _least_squares_problem(curve: FitCurve, names: tuple[str, ...], method: str,
                           z_crit: float | None) -> LsqProblem:
    """The scaled sigma^2 problem; ``gls`` becomes ``wls`` without a model covariance.

    ``z_crit`` (None: no tests) gives the critical value ``z_crit^2`` of the boundary
    likelihood-ratio test of the model error (the 50:50 chi-bar-squared mixture; 0 keeps
    the unrestricted ML estimate)."""
    powers = np.array([TERM_POWER[n] for n in names], dtype=np.int64)
    design = curve.tau[:, None] ** powers[None, :].astype(np.float64)
    scale = float(np.median(curve.dev**2))
    basis = curve_covariance_basis(curve, powers) if method != "ols" else None
    covm = CovarianceModel(basis, powers, curve.kind) if basis is not None else None
    if method == "gls" and covm is None:
        method = "wls"
    return LsqProblem(design=design, y=curve.dev**2 / scale, scale=scale, edf=curve.edf,
                      density=octave_density(curve.tau), covm=covm, method=method,
                      crit=z_crit**2 if z_crit is not None else 0.0)


def _noise_model(curve: FitCurve, names: tuple[str, ...], problem: LsqProblem,
                 selection: TermSelection, confidence: float, significance: float | None
                 ) -> NoiseModel:
    """The fit as a NoiseModel in the curve's units (identifiability not yet assessed)."""
    fit = selection.fit
    quantity = quantity_of(curve.units)
    factor = base_unit_factor(curve.units)
    scale = math.sqrt(problem.scale) * factor  # sqrt of scaled sigma^2 -> deg/h (or m/s^2)
    terms = widen_for_band_limits(
        term_estimates(names, selection, confidence, scale, quantity), names, problem,
        selection, curve.tau, confidence, scale, quantity)
    return NoiseModel(
        terms=terms,
        confidence=confidence,
        method=problem.method, kind=curve.kind, units=curve.units, axis=curve.axis,
        deg_per_hour_factor=factor, tau_s=curve.tau, dev=curve.dev,
        fitted_dev=np.sqrt(fit.mu * problem.scale), weight=fit.w / np.max(fit.w),
        edf=curve.edf, edf_source=curve.edf_source, chi2=fit.chi2, dof=fit.dof,
        model_error=fit.model_error, stderr_method=fit.stderr_method,
        iterations=fit.iterations, converged=fit.converged,
        model_error_lr=fit.model_error_lr,
        readoff=readoff_of(curve, factor, quantity),
        excluded_tau_s=tuple(curve.excluded), significance=significance,
        _a=tuple(float(v) * problem.scale for v in selection.a[:len(names)]),
        quantity=quantity)


def _warn(issued: list[str], category: type[Warning], message: str, axis: str = "",
          stacklevel: int = 3) -> None:
    """Emit a warning (prefixed with the axis name, if any) at fit_noise's caller (from a
    function fit_noise calls: ``stacklevel=4``); record it."""
    message = f"axis {axis!r}: {message}" if axis else message
    issued.append(message)
    warnings.warn(message, category, stacklevel=stacklevel)


def _within(res: Any, tau_range: tuple[float | None, float | None], n_terms: int) -> Any:
    """``res`` restricted to ``tau_range``, with at least ``n_terms + 1`` points left."""
    from fogts.allan.result import AllanResult

    if not isinstance(res, AllanResult):
        raise DataError(f"tau_range needs an AllanResult, got {type(res).__name__}")
    lo, hi = tau_range
    for name, v in (("tau_min", lo), ("tau_max", hi)):
        if v is not None:
            check_positive(name, v)
    inside = res.within(lo, hi)
    if inside.tau_s.size < n_terms + 1:
        raise DataError(f"the fit range tau_min = {lo if lo is not None else 0:g} s .. "
                        f"tau_max = {hi if hi is not None else float('inf'):g} s holds "
                        f"{inside.tau_s.size} tau(s); {n_terms} terms need at least "
                        f"{n_terms + 1}")
    return inside
