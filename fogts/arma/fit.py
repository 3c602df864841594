"""Fit one ARMA(p, q) model by exact Gaussian maximum likelihood: :func:`fit_arma`.

Two methods maximise the same exact likelihood, the state-space likelihood statsmodels'
``ARIMA(order=(p,0,q), trend="n")`` evaluates: ``"statsmodels"`` runs statsmodels itself;
``"fast"`` evaluates the likelihood without the Kalman filter's per-sample overhead
(:mod:`fogts.arma.likelihood`), maximises it by Newton's method (:mod:`fogts.arma.optimiser`)
from Hannan-Rissanen start values (:mod:`fogts.arma.start_values`) and takes the standard
errors from the observed information (:mod:`fogts.arma.standard_errors`).  The result is an
:class:`~fogts.arma.fit_result.ArmaFit` in the units of the series.

No mean is fitted (``trend="n"``) unless ``mean=True``: then the mean is profiled out of the
likelihood by GLS (``trend="c"``) and the restricted likelihood maximised, which
:func:`~fogts.arma.select.select_arma` uses; at a unit AR root, where the mean is not
identifiable, the fit without a mean of the demeaned series is used instead.
"""

from __future__ import annotations

import math
import warnings as _warnings
from collections.abc import Iterator
from contextlib import contextmanager
from contextvars import ContextVar
from dataclasses import dataclass
from typing import Any, Literal

import numpy as np

from fogts._typing import ArrayLike1D, FloatArray
from fogts._validate import check_choice, check_int, to_float_array
from fogts.arma.ar_exact import fit_exact_ar
from fogts.arma.blockwise import BLOCKWISE_MIN_N, lagged_products, scale_and_offsets
from fogts.arma.fit_result import ArmaFit, criteria, fitted_series, model_name, param_names
from fogts.arma.likelihood import Evaluation, ExactLikelihood
from fogts.arma.optimiser import PRESAMPLE, NewtonResult, maximise
from fogts.arma.region import UNIT_ROOT_GAP, spectral_radius, unit_root_gap
from fogts.arma.standard_errors import standard_errors
from fogts.arma.start_values import START_SAMPLES, hannan_rissanen, normal_equations
from fogts.errors import ConvergenceWarning, DataError, InsufficientDataError, ModelFitError

__all__ = ["ArmaFit", "FitMethod", "fit_arma", "min_nobs", "model_name", "param_names"]

FitMethod = Literal["fast", "statsmodels"]
_METHODS = ("fast", "statsmodels")
_FD_HESSIAN_MAX_N = 50_000  # up to this n: exact polish and bse from finite-difference Hessians

#: What the fit of one path returns, in the units of the (scaled) series it was given:
#: params, bse, llf, innovations, converged, messages, Newton iterations, and the covariance
#: of the AR and MA coefficients.
_PathResult = tuple[dict[str, float], dict[str, float], float, FloatArray, bool, list[str],
                    int | None, FloatArray]


def min_nobs(p: int, q: int) -> int:
    """Smallest series length accepted for an ARMA(p, q) fit: ``max(20, 10 * (p + q + 1))``."""
    return max(20, 10 * (p + q + 1))


def _prepare(x: Any, p: int, q: int) -> FloatArray:
    arr = to_float_array(x, "x", min_length=1)
    need = min_nobs(p, q)
    if arr.shape[0] < need:
        raise InsufficientDataError(
            f"x is too short for {model_name(p, q)}: need at least {need} samples "
            f"(max(20, 10*(p+q+1))), got {arr.shape[0]}")
    if float(np.ptp(arr)) == 0.0:
        raise InsufficientDataError(
            f"x is constant (every sample equals {arr[0]!r}); an ARMA model needs variation")
    return arr


def _fit_statsmodels(xs: FloatArray, p: int, q: int, mean: bool) -> _PathResult:
    """statsmodels' own ``ARIMA(order=(p,0,q), trend="n" or "c").fit()`` on the (scaled)
    series.  With ``trend="c"`` the mean is its ``const`` (returned as ``"mean"``), and the
    log-likelihood returned is the restricted one at statsmodels' coefficients (statsmodels
    has no restricted likelihood), so both methods rank candidates by the same criterion."""
    from statsmodels.tools.sm_exceptions import ConvergenceWarning as SmConvergenceWarning
    from statsmodels.tsa.arima.model import ARIMA

    msgs: list[str] = []
    with _warnings.catch_warnings(record=True) as caught:
        _warnings.simplefilter("always")
        try:
            res = ARIMA(xs, order=(p, 0, q), trend="c" if mean else "n").fit(cov_type="approx")
        except (ValueError, np.linalg.LinAlgError) as exc:
            raise ModelFitError(f"statsmodels fit failed: {exc}") from exc
    converged = True
    for w in caught:
        if issubclass(w.category, SmConvergenceWarning):
            converged = False
        msgs.append(f"{w.category.__name__}: {w.message}")
    if not math.isfinite(float(res.llf)):
        raise ModelFitError(f"statsmodels returned a non-finite log-likelihood ({res.llf})")
    mle = getattr(res, "mle_retvals", None) or {}
    if mle.get("converged") is False:
        converged = False
    names = (["mean"] if mean else []) + param_names(p, q)
    params = dict(zip(names, map(float, np.asarray(res.params)), strict=True))
    bse = dict(zip(names, map(float, np.asarray(res.bse)), strict=True))
    n_iter = mle.get("iterations")
    k0 = 1 if mean else 0        # statsmodels orders const, ar, ma, sigma2
    cov = np.asarray(res.cov_params(), dtype=float)[k0:k0 + p + q, k0:k0 + p + q]
    llf = float(res.llf)
    if mean:
        model = ExactLikelihood(xs, p, q, mean=True)
        ev = model.evaluate(np.array([params[f"ar.L{i}"] for i in range(1, p + 1)]),
                            np.array([params[f"ma.L{j}"] for j in range(1, q + 1)]))
        llf = _restricted_llf(model.nu, ev.S, ev.D)
    return (params, bse, llf, np.asarray(res.resid, dtype=float), converged, msgs,
            None if n_iter is None else int(n_iter), cov)


def _restricted_llf(nu: int, S: float, D: float) -> float:
    """The log-likelihood at sigma2 = S / nu (exact for nu = n, restricted for nu = n - 1)."""
    return -0.5 * nu * (math.log(2 * math.pi) + 1.0 + math.log(S / nu)) - 0.5 * D


def _check_not_explosive(xs: FloatArray) -> None:
    """Raise ModelFitError if a least-squares AR(3) fit has a root clearly outside the unit circle.

    Under a unit root the least-squares root estimate is within a few 1/n of 1 (Dickey & Fuller
    1979 asymptotics: n(rho_hat - 1) rarely exceeds 2); an explosive x_t = c x_{t-1} + e_t with
    |c| > 1 gives |c| itself.  The threshold is 1 + 10/n.
    """
    _check_ar_roots(normal_equations(xs, [(xs, i) for i in range(1, 4)], 3), xs.shape[0])


@dataclass(frozen=True)
class _LongStatistics:
    """What the fits of a long series share: its scale, offsets and lagged products."""

    scale: float
    offset: float
    offset2: float
    products: FloatArray


# keyed by the array's id; the array is held beside its statistics, so that id cannot be
# reused by another array while the context lasts
_SHARED: ContextVar[dict[tuple[int, bool, bool], tuple[FloatArray, _LongStatistics]] | None] = \
    ContextVar("fogts_arma_shared_statistics", default=None)


@contextmanager
def shared_statistics() -> Iterator[None]:
    """Within this context the fits of one long series (the same array object, unchanged
    meanwhile) share the statistics :func:`fit_arma` takes of it before fitting (its scale,
    mean and lagged products: four block-wise passes over it per fit otherwise)."""
    token = _SHARED.set({})
    try:
        yield
    finally:
        _SHARED.reset(token)


def _long_statistics(arr: FloatArray, standardize: bool, mean: bool
                     ) -> tuple[float, float, float, FloatArray]:
    """Scale, offsets (:func:`~fogts.arma.blockwise.scale_and_offsets`) and the explosive
    check's lagged products of a long series, shared within :func:`shared_statistics`."""
    shared = _SHARED.get()
    key = (id(arr), standardize, mean)
    held = shared.get(key) if shared is not None else None
    if held is not None and held[0] is arr:
        got = held[1]
    else:
        scale, offset, offset2 = scale_and_offsets(arr, standardize, mean)
        got = _LongStatistics(scale, offset, offset2,
                              _check_not_explosive_blockwise(arr, scale, offset))
        if shared is not None:
            shared[key] = (arr, got)
    return got.scale, got.offset, got.offset2, got.products


def _check_not_explosive_blockwise(x: FloatArray, scale: float, offset: float) -> FloatArray:
    """:func:`_check_not_explosive` of ``x / scale - offset``, formed block by block; returns
    the lagged products of :func:`~fogts.arma.blockwise.lagged_products` (k = 3) it used."""
    M = lagged_products(x, scale, offset, 3)
    try:
        coef = np.linalg.solve(M[1:, 1:], M[1:, 0])
    except np.linalg.LinAlgError:
        coef = np.linalg.lstsq(M[1:, 1:], M[1:, 0], rcond=None)[0]
    _check_ar_roots(np.asarray(coef), x.shape[0])
    return M


def _check_ar_roots(coef: FloatArray, n: int) -> None:
    """Raise ModelFitError if the AR(3) coefficients ``coef`` have a root of modulus
    > 1 + 10/n."""
    k = coef.size
    rho = spectral_radius(coef)
    if rho > 1.0 + 10.0 / n:
        raise ModelFitError(
            f"x looks explosive: a least-squares AR({k}) fit has a root of modulus {rho:.4g} "
            f"(> 1 + 10/n = {1 + 10 / n:.4g}); an ARMA model needs a stationary series - "
            "difference or detrend it first")


def _fit_demeaned(model: ExactLikelihood, head: FloatArray, offset: float,
                  exact: bool) -> tuple[ExactLikelihood, NewtonResult, int]:
    """The exact ML fit without a mean of the model's series minus its sample mean
    ``offset`` (model, result, iterations); ``head``: the series' first samples.

    Used where the restricted likelihood is maximised at a unit AR root (see
    :func:`_unit_root_note`): the mean of a unit-root process is not identifiable, and the
    zero-mean likelihood of the demeaned series has its maximum inside the stationarity
    region (the sample mean's removal costs a unit root about log(n)/2).
    """
    p, q = model.p, model.q
    y = head - offset
    demeaned = ExactLikelihood(model.x, p, q, scale=model.scale,
                               offsets=(*model.offsets, offset), work=model.work)
    res, n_iter = maximise(y, demeaned, *hannan_rissanen(y, p, q), polish=exact)
    return demeaned, res, n_iter


def _unit_root_note(stopped: Evaluation) -> str:
    """What a fit whose restricted likelihood runs to a unit AR root did.

    As an inverse AR root tends to 1 the restricted likelihood tends to that of the
    differenced series under ARMA(p - 1, q) (plus log(n)/2, the Jacobian of differences
    against orthonormal contrasts): the contrasts of a series with a unit root are its
    differences, and its mean is not identifiable (Harville 1974; Francke & de Vos 2007,
    *J. Econometrics* 137, 708-728).  The optimum is then on the boundary of the stationary
    region, which a stationary ARMA(p, q) cannot represent.
    """
    root = 1.0 - unit_root_gap(stopped.phi)
    return (f"the restricted likelihood rises towards a unit AR root (its maximisation reached "
            f"inverse root {root:.6f}, within {UNIT_ROOT_GAP:g} of 1), where the mean is not "
            "identifiable: the coefficients are the exact ML ones of the demeaned series "
            "without a mean, and llf is the restricted likelihood at them")


def _fit_fast(x: FloatArray, head: FloatArray, scale: float, offsets: tuple[float, float],
              p: int, q: int, mean: bool) -> _PathResult:
    """Exact ML by Newton's method on the fast exact likelihood, from Hannan-Rissanen starts.

    The likelihood sees ``x / scale - offsets[0]`` (``offsets[0]``: with ``mean``; the
    demeaned fallback also subtracts ``offsets[1]``, that series' own sample mean) block by
    block; ``head``: its first samples (start values, presample).  Up to
    ``_FD_HESSIAN_MAX_N`` samples the optimum is polished with, and the standard errors
    come from, the finite-difference Hessians of the exact gradient; above, from the
    analytic Hessian of the last Newton step.  The innovations returned are the models'
    shared workspace (no other series-length array is made).
    """
    n = x.shape[0]
    exact = n <= _FD_HESSIAN_MAX_N
    model = ExactLikelihood(x, p, q, mean=mean, scale=scale,
                            offsets=(offsets[0],) if mean else ())
    res, n_iter = maximise(head, model, *hannan_rissanen(head, p, q), polish=exact)
    se_model, se_res = model, res
    if mean and unit_root_gap(res.ev.phi) < UNIT_ROOT_GAP:
        se_model, se_res, n_alt = _fit_demeaned(model, head, offsets[1], exact)
        n_iter += n_alt
        res = NewtonResult(ev=se_res.ev, converged=se_res.converged, n_iter=n_iter,
                           msgs=[*se_res.msgs, _unit_root_note(res.ev)])
    se, cov, note = standard_errors(se_model, se_res, exact=exact)
    ev = res.ev if se_model is model else model.evaluate(se_res.ev.phi, se_res.ev.theta)
    return path_result(model, ev, se, cov, note, res.converged, res.msgs, n_iter)


def path_result(model: ExactLikelihood, ev: Evaluation, se: FloatArray, cov: FloatArray,
                note: str | None, converged: bool, msgs: list[str],
                n_iter: int | None) -> _PathResult:
    """A fast path's result at the evaluation ``ev`` of ``model`` (the restricted
    likelihood's model with a mean), standard errors ``se`` of (phi, theta, sigma2) and
    their covariance ``cov``; ``note`` (if any) joins the messages."""
    p, q, mean = model.p, model.q, model.mean
    msgs = [*msgs, note] if note is not None else msgs
    sigma2 = ev.S / model.nu      # nu = n, or n - 1 for the restricted likelihood
    llf = _restricted_llf(model.nu, ev.S, ev.D)
    names = param_names(p, q)
    values = np.r_[ev.phi, ev.theta, sigma2]
    params = dict(zip(names, map(float, values), strict=True))
    bse = dict(zip(names, map(float, se), strict=True))
    if mean:
        # the GLS variance sigma2 (1' R^-1 1)^-1, R = Cov(x)/sigma2, and 1' R^-1 1 = s11
        params = {"mean": ev.mu, **params}
        bse = {"mean": math.sqrt(sigma2 / ev.s11), **bse}
    return params, bse, llf, model.innovations(ev), converged, msgs, n_iter, cov[:p + q, :p + q]


def _boundary_notes(params: dict[str, float], p: int, q: int) -> list[str]:
    """Notes for inverse AR/MA roots within 1e-3 of the unit circle (fit near the boundary)."""
    notes = []
    phi = np.array([params[f"ar.L{i}"] for i in range(1, p + 1)])
    theta = np.array([params[f"ma.L{j}"] for j in range(1, q + 1)])
    rho_ar, rho_ma = spectral_radius(phi), spectral_radius(-theta)
    if rho_ar >= 0.999:
        notes.append(f"an inverse AR root has modulus {rho_ar:.6f} (>= 0.999): the fitted model "
                     "is nearly non-stationary (close to a unit root)")
    if rho_ma >= 0.999:
        notes.append(f"an inverse MA root has modulus {rho_ma:.6f} (>= 0.999): the fitted model "
                     "is nearly non-invertible; the likelihood maximum may lie on the boundary")
    return notes


# over 80 lines only through its numpydoc docstring; the body is short
def fit_arma(x: ArrayLike1D, p: int, q: int, *, method: FitMethod = "fast",
             standardize: bool = True, mean: bool = False) -> ArmaFit:
    """Fit ARMA(p, q) by exact Gaussian maximum likelihood, without a mean or with one.

    Parameters
    ----------
    x : array_like or pandas.Series
        The series, 1-D (demeaned and detrended for ``mean=False``).
    p, q : int
        AR and MA orders, ``p, q >= 0`` and ``p + q >= 1``.
    method : {"fast", "statsmodels"}
        ``"statsmodels"`` runs ``ARIMA(order=(p,0,q), trend="n").fit(cov_type="approx")``;
        ``"fast"`` (default) maximises the same exact likelihood with Newton steps on an
        lfilter-based evaluation and reaches the statsmodels optimum (parameters within
        1e-4, AIC at most 0.05 worse, often better where statsmodels stops in a worse local
        optimum), much faster on long series.
    standardize : bool
        Divide the series by its standard deviation before fitting and report everything in
        the original units (``scale`` and ``standardized`` record it).  Recommended:
        statsmodels' optimiser stops early on series with a tiny variance (gyro rates in
        deg/s), hundreds of AIC units short, without a warning.
    mean : bool
        Remove the mean by GLS and maximise the restricted (marginal) likelihood of the
        n - 1 contrasts free of it (REML): ``params["mean"]`` is the GLS mean, ``llf`` the
        restricted log-likelihood (the same for x and x - mean(x)) and the criteria count
        p + q + 1 parameters.  Use it on a series whose sample mean was subtracted: a
        zero-mean fit of demeaned data, and also the likelihood with the mean as a
        parameter (statsmodels' ``trend="c"``), reward an MA root on the unit circle by
        about log(n)/2 of likelihood; the restricted likelihood does not.  Where the
        restricted likelihood rises to a unit AR root (an inverse root within 1e-4 of 1, as
        on white noise + random walk), the mean is not identifiable: the coefficients are
        then those of the exact ML fit of the demeaned series without a mean, ``llf`` the
        restricted likelihood at them, and ``warnings`` says so.  With
        ``method="statsmodels"`` the coefficients are statsmodels' ``trend="c"`` ML ones.

    Returns
    -------
    ArmaFit
        Parameters, standard errors (observed information), log-likelihood and criteria in
        the original units, and the innovations ``resid``.

    Raises
    ------
    DataError
        Bad orders or method, non-finite or non-1-D data.
    InsufficientDataError
        The series is shorter than :func:`min_nobs` or constant.
    ModelFitError
        The series looks explosive (a least-squares AR(3) root > 1 + 10/n), or the likelihood
        could not be evaluated or maximised.  The message starts with the model name.

    Warns
    -----
    ConvergenceWarning
        The optimiser stopped before converging (also recorded in ``warnings``).

    Notes
    -----
    Exact Gaussian likelihood of an ARMA process: Brockwell & Davis, *Time Series: Theory and
    Methods* (2nd ed., 1991), eqs. 8.7.4-8.7.5; the start-up block uses Ansley (1979),
    *Biometrika* 66, 59-65; the Fisher information is B&D eq. 8.8.3; start values are
    Hannan & Rissanen (1982), *Biometrika* 69, 81-94.  AIC, BIC, HQIC and AICc count sigma2
    as a parameter (k = p + q + 1), as statsmodels, gretl and R do.  The mean by GLS:
    Brockwell & Davis, *Introduction to Time Series and Forecasting* (2nd ed., 2002),
    sec. 6.6; the restricted likelihood: Harville (1974), *Biometrika* 61, 383-385; it
    removes most of the pile-up of MA roots on the unit circle that estimating the mean
    causes (Tunnicliffe Wilson 1989, *J. R. Statist. Soc. B* 51, 15-27; Shephard 1993,
    *J. Amer. Statist. Assoc.* 88, 590-595; Davis & Dunsmuir 1996, *Econometric Theory*
    12, 1-29).

    Examples
    --------
    >>> import numpy as np
    >>> from scipy.signal import lfilter
    >>> e = np.random.default_rng(0).standard_normal(2000)
    >>> x = lfilter([1.0], [1.0, -0.6], e)
    >>> fit = fit_arma(x, 1, 0)
    >>> round(fit.params["ar.L1"], 1)
    0.6
    """
    p = check_int("p", p, minimum=0)
    q = check_int("q", q, minimum=0)
    if p + q == 0:
        raise DataError("p + q must be >= 1 (white noise needs no fit), got p=0, q=0")
    check_choice("method", method, _METHODS)
    arr = _prepare(x, p, q)
    n = arr.shape[0]
    name = model_name(p, q)
    blockwise = method == "fast" and n > BLOCKWISE_MIN_N
    if blockwise:
        # no standardised copy: its statistics block by block (rounding-level differences)
        scale, offset, offset2, products = _long_statistics(arr, standardize, mean)
        head = arr[:max(START_SAMPLES, PRESAMPLE)] / scale - offset
        xs = None
    else:
        scale = float(np.std(arr)) if standardize else 1.0
        products = None
        xs, offset = fitted_series(arr, scale, standardize, mean)
        _check_not_explosive(xs)
    try:
        if method == "fast":
            if xs is not None:
                # the likelihood forms the series block by block: only its head is kept
                head = xs[:max(START_SAMPLES, PRESAMPLE)].copy()
                offset2 = float(np.mean(xs))
                del xs
            with np.errstate(over="raise", invalid="raise", divide="raise", under="ignore"):
                # long pure AR series: from the sufficient statistics (one pass), unless
                # the general path must decide (a unit root, see fit_exact_ar)
                ar = None if q or not blockwise else fit_exact_ar(
                    arr, head, scale, (offset, offset2), p, mean, products)
                if ar is None:
                    out = _fit_fast(arr, head, scale if standardize else 1.0,
                                    (offset, offset2), p, q, mean)
                else:
                    model, ev, se, cov, note, n_ar = ar
                    out = path_result(model, ev, se, cov, note, True, [], n_ar)
        else:
            assert xs is not None
            out = _fit_statsmodels(xs, p, q, mean)
    except ModelFitError as exc:
        raise ModelFitError(f"{name}: {exc}") from exc
    except (np.linalg.LinAlgError, FloatingPointError, ValueError) as exc:
        raise ModelFitError(f"{name}: exact ML fit failed ({type(exc).__name__}: {exc})") from exc
    params_s, bse_s, llf_s, resid_s, converged, msgs, n_iter, coef_cov = out
    if mean:
        params_s["mean"] += offset
    msgs = list(msgs) + _boundary_notes(params_s, p, q)
    if not converged:
        _warnings.warn(f"{name}: the likelihood maximisation did not converge: "
                       + "; ".join(msgs), ConvergenceWarning, stacklevel=2)
    return _to_original(p, q, params_s, bse_s, llf_s, resid_s, converged, msgs, n_iter,
                        scale, standardize, method, n, coef_cov)


def _to_original(p: int, q: int, params_s: dict[str, float], bse_s: dict[str, float],
                 llf_s: float, resid_s: FloatArray, converged: bool, msgs: list[str],
                 n_iter: int | None, scale: float, standardized: bool, method: str,
                 n: int, coef_cov: FloatArray) -> ArmaFit:
    s2 = scale * scale
    if method == "fast":
        resid_s *= scale          # the fit's own workspace: scaled in place, no copy
        resid = resid_s
    else:
        resid = resid_s * scale
    params = dict(params_s)
    params["sigma2"] = params_s["sigma2"] * s2
    bse = dict(bse_s)
    bse["sigma2"] = bse_s["sigma2"] * s2
    if "mean" in params:
        params["mean"] = params_s["mean"] * scale
        bse["mean"] = bse_s["mean"] * scale
    # the restricted likelihood is the density of n - 1 contrasts; the mean is not one of
    # its parameters
    llf = llf_s - (n - 1 if "mean" in params else n) * math.log(scale)
    k = p + q + 1
    aic, bic, hqic, aicc = criteria(llf, k, n)
    return ArmaFit(p=p, q=q, name=model_name(p, q), params=params, bse=bse, llf=llf, aic=aic,
                   bic=bic, hqic=hqic, aicc=aicc, nobs=n, sigma2=params["sigma2"],
                   resid=resid, converged=converged, warnings=tuple(msgs),
                   scale=scale, standardized=standardized, method=method, n_iter=n_iter,
                   coef_cov=coef_cov)
