"""Least-squares fit of the temperature-drift model, with standard errors that allow for
autocorrelated residuals.

The model D = a·T·ΔT + b·T² + c·T + d·ΔT² + e·ΔT + f (:mod:`~fogts.startup.thermal_model`)
is linear in its coefficients.  The residual of a gyro drift fit is the ARMA drift of the gyro,
strongly autocorrelated, so plain OLS standard errors are far too small.  Error models:

* ``"ar"`` (default): feasible generalised least squares with AR(``ar_order``) errors
  (``statsmodels.GLSAR``, iterated Cochrane–Orcutt / Prais–Winsten; Greene, *Econometric
  Analysis*, 7th ed., §20.9), i.e. least squares on the pre-whitened data;
* ``"hac"``: the OLS estimate with Newey–West HAC standard errors (Newey & West 1987,
  *Econometrica* 55:703);
* ``"ols"``: ordinary least squares.

Standard errors of the ``"ar"`` fit are a sandwich: the estimator is the AR(``ar_order``) GLS
one, its covariance is evaluated under a longer AR(``NOISE_AR_ORDER`` = 16) Yule–Walker model
of the residuals (the covariance of a GLS estimator with a misspecified error covariance;
Greene, *Econometric Analysis*, 7th ed., §9.2.2):

    Cov(β) = B Xw' L Σ L' Xw B,     Xw = L X,  B = (Xw'Xw)^-1,

with ``L`` the AR(``ar_order``) whitening and ``Σ`` the AR(16) covariance.  Drift noise that
is AR(1) plus white noise is an ARMA(1,1) whose AR(∞) weights decay slowly, so a short
whitening filter removes its correlation only in part; whitening the estimate itself with
AR(16) recovers the drift curve D(T, ΔT) less well, so the estimate keeps the short filter.

Unidentifiable terms (for example every ΔT term when the temperature is constant) are
detected by a greedy rank test on the column-normalised design matrix, reported with an
:class:`~fogts.errors.UnidentifiableTermWarning` and left out of the fit.  Terms that pass it
may still be nearly collinear: :func:`~fogts.startup.thermal_identification.collinearity`
measures that (the start-up workflow records it with the model).
"""

from __future__ import annotations

import math
import warnings
from collections.abc import Sequence
from typing import Any

import numpy as np
import pandas as pd

from fogts._typing import FloatArray
from fogts._validate import check_choice, check_int, check_positive, pandas_index, to_float_array
from fogts.errors import DataError, InsufficientDataError, UnidentifiableTermWarning
from fogts.startup.thermal_model import (
    DEFAULT_DT_SMOOTHING_S,
    ERROR_MODELS,
    THERMAL_TERMS,
    ErrorModel,
    ThermalModel,
    design_matrix,
    temperature_rate,
)
from fogts.units import parse_rate_unit

__all__ = ["DEFAULT_AR_ORDER", "NOISE_AR_ORDER", "RANK_RTOL", "fit_thermal"]

#: Default AR order of the GLSAR error model (the whitening of the estimator).
DEFAULT_AR_ORDER = 4
#: AR order of the residual model under which the standard errors are evaluated.
NOISE_AR_ORDER = 16
#: Order in which terms enter the rank test: a term that is a combination of terms
#: earlier in this list is unidentifiable (so a constant temperature keeps the intercept).
_RANK_ORDER = ("1", "T", "dT", "T2", "dT2", "T*dT")
#: Relative tolerance of the rank test on the column-normalised design matrix.
RANK_RTOL = 1e-9


# Long only by its signature and docstring (11 options); the body calls the named steps below.
def fit_thermal(
    gyro: Any,
    temperature: Any,
    *,
    fs_hz: float,
    terms: Sequence[str] = ("T*dT", "T2", "T", "dT2", "dT", "1"),
    dT_smoothing_s: float | None = DEFAULT_DT_SMOOTHING_S,
    units: str = "deg/h",
    errors: ErrorModel = "ar",
    ar_order: int = DEFAULT_AR_ORDER,
    hac_maxlags: int | None = None,
    t_ref_degC: float | None = None,
    temperature_rate_degC_s: Any = None,
) -> ThermalModel:
    """Fit the temperature-drift model by least squares.

    Parameters
    ----------
    gyro : array_like or pandas.Series
        Gyro rate (ideally the EMD trend plus the Kalman-filtered rest, see
        :func:`~fogts.startup.startup_workflow.startup_compensation`).
    temperature : array_like or pandas.Series
        Temperature in °C, same length.
    fs_hz : float
        Sample rate in Hz.
    terms : sequence of str
        Subset of ``"T*dT", "T2", "T", "dT2", "dT", "1"`` (letters a..f of the model).
    dT_smoothing_s : float or None
        Savitzky–Golay window for ΔT in seconds (see
        :func:`~fogts.startup.thermal_model.temperature_rate`).
    units : str
        Rate unit of ``gyro``.
    errors : {"ar", "hac", "ols"}
        Error model (see the module docstring): GLS with AR(``ar_order``) errors (default),
        OLS with Newey–West HAC standard errors, or plain OLS.
    ar_order : int
        AR order of the error model for ``errors="ar"`` (default 4).
    hac_maxlags : int, optional
        HAC (Bartlett kernel) lags for ``errors="hac"``; default: see Notes.
    t_ref_degC : float, optional
        Reference temperature for :func:`~fogts.startup.compensation.compensate` (default:
        mean of the last 5 % of the record, the warm steady state of a start-up run).
    temperature_rate_degC_s : array_like, optional
        ΔT given directly (for example computed run by run with
        :func:`~fogts.startup.thermal_model.temperature_rate` when several calibration runs
        are concatenated); default: computed from ``temperature``.

    Returns
    -------
    ThermalModel

    Raises
    ------
    DataError
        Unknown or repeated term, mismatched lengths, bad option.
    InsufficientDataError
        Fewer than ``max(20, 5 * len(terms))`` samples, or no identifiable term.

    Warns
    -----
    UnidentifiableTermWarning
        When a requested term is collinear with others (it is left out and recorded).

    Notes
    -----
    The default HAC lag is ``max(floor(4 (n/100)^(2/9)), round(2 n^(1/3)))``: the
    Newey–West rule of thumb raised to ``2 n^(1/3)`` because gyro drift residuals are
    correlated over many samples.  A coarse temperature resolution (compared with the change
    over ``dT_smoothing_s``) makes ΔT noisy and biases the ΔT terms (errors in variables).
    A single first-order warm-up T = T_end - A e^{-t/τ} has ΔT = (T_end - T)/τ, exactly
    collinear with T and 1: the model is then not identifiable from that record (use a
    record with a richer temperature history, or several runs via ``temperature_rate_degC_s``
    or :func:`~fogts.startup.startup_workflow.startup_compensation` with ``calibration``).

    Examples
    --------
    >>> import numpy as np
    >>> t = np.arange(3600.0)
    >>> temp = 20 + 25 * (1 - np.exp(-t / 900)) + 2 * np.sin(2 * np.pi * t / 1800)
    >>> dT = np.gradient(temp)
    >>> gyro = 0.5 * temp + 20 * dT + 1.0 + np.random.default_rng(0).normal(0, 0.1, t.size)
    >>> m = fit_thermal(gyro, temp, fs_hz=1.0, terms=("T", "dT", "1"))
    >>> round(m.coefficients["T"], 1), round(m.coefficients["dT"], 0)
    (0.5, 20.0)
    """
    fs = check_positive("fs_hz", fs_hz)
    unit = parse_rate_unit(units)
    check_choice("errors", errors, ERROR_MODELS)
    order = check_int("ar_order", ar_order, minimum=1, maximum=50)
    term_list = _checked_terms(terms)
    index = pandas_index(gyro)
    y, temp, dtemp = _aligned_series(gyro, temperature, temperature_rate_degC_s, fs=fs,
                                     smoothing_s=dT_smoothing_s, n_terms=len(term_list))
    kept, dropped = _identifiable_terms(temp, dtemp, term_list)
    X = design_matrix(temp, dtemp, kept)
    n = y.size
    if errors == "ar":
        params, bse, error_params = _fit_gls_ar(y, X, order)
    elif errors == "hac":
        params, bse, error_params = _fit_ols_hac(y, X, hac_maxlags)
    else:
        params, bse, error_params = _fit_ols(y, X)
    _warn_missing_stderr(kept, bse, temp)
    resid = y - X @ params
    r2, r2_adj = _r_squared(y, resid, kept)
    tail = max(1, n // 20)
    tref = float(np.mean(temp[-tail:])) if t_ref_degC is None else float(t_ref_degC)
    resid_out: Any = pd.Series(resid, index=index, name="residual") if index is not None else resid
    return ThermalModel(
        terms=tuple(kept),
        coefficients=dict(zip(kept, map(float, params), strict=True)),
        stderr=dict(zip(kept, map(float, bse), strict=True)),
        dropped=dropped, r2=r2, r2_adj=r2_adj,
        residual_std=float(np.std(resid, ddof=len(kept))),
        units=unit, fs_hz=fs, dT_smoothing_s=dT_smoothing_s, t_ref_degC=tref,
        temperature_range_degC=(float(temp.min()), float(temp.max())),
        errors=errors, error_params=error_params, n=n, residual=resid_out)


# --------------------------------------------------------------------------- input checks


def _checked_terms(terms: Sequence[str]) -> list[str]:
    """The requested terms as a list: known names, no repeats, at least one."""
    if isinstance(terms, str):
        raise DataError(f"terms must be a sequence of term names, got the string {terms!r}")
    out = list(terms)
    for t in out:
        check_choice("terms", t, THERMAL_TERMS)
    if len(set(out)) != len(out) or not out:
        raise DataError(f"terms must be non-empty without repeats, got {out!r}")
    return out


def _aligned_series(gyro: Any, temperature: Any, temperature_rate_degC_s: Any, *, fs: float,
                    smoothing_s: float | None, n_terms: int
                    ) -> tuple[FloatArray, FloatArray, FloatArray]:
    """Gyro, temperature and temperature rate as float arrays of one length, long enough for
    ``n_terms`` terms; the rate is computed unless given."""
    y = to_float_array(gyro, "gyro")
    if temperature is None:
        raise DataError("temperature is required: the thermal model needs a temperature record; "
                        "pass temperature= (deg C, aligned sample by sample with gyro)")
    temp = to_float_array(temperature, "temperature")
    if temp.size != y.size:
        raise DataError(f"temperature has {temp.size} samples but gyro has {y.size}; they must "
                        "be aligned sample by sample")
    need = max(20, 5 * n_terms)
    if y.size < need:
        raise InsufficientDataError(f"gyro needs at least {need} samples for a {n_terms}-term "
                                    f"thermal model, got {y.size}")
    if temperature_rate_degC_s is None:
        dtemp = temperature_rate(temp, fs_hz=fs, smoothing_s=smoothing_s)
    else:
        dtemp = to_float_array(temperature_rate_degC_s, "temperature_rate_degC_s")
        if dtemp.size != y.size:
            raise DataError(f"temperature_rate_degC_s has {dtemp.size} samples but gyro has "
                            f"{y.size}; they must be aligned sample by sample")
    return y, temp, dtemp


# --------------------------------------------------------------------------- rank test


def _identifiable(temp: FloatArray, dtemp: FloatArray, terms: Sequence[str]
                  ) -> tuple[list[str], dict[str, str]]:
    """Greedy rank test in :data:`_RANK_ORDER`: keep a term only if it adds rank."""
    kept: list[str] = []
    dropped: dict[str, str] = {}
    ordered = [t for t in _RANK_ORDER if t in terms]
    for term in ordered:
        col = design_matrix(temp, dtemp, [term])[:, 0]
        norm = float(np.linalg.norm(col))
        if norm == 0.0 or not math.isfinite(norm):
            dropped[term] = "its column is identically zero"
            continue
        trial = design_matrix(temp, dtemp, [*kept, term])
        trial = trial / np.linalg.norm(trial, axis=0)
        sv = np.linalg.svd(trial, compute_uv=False)
        if sv[-1] <= RANK_RTOL * sv[0]:
            dropped[term] = (f"collinear with {', '.join(kept) or 'nothing'} (smallest "
                             f"singular value ratio {sv[-1] / sv[0]:.2e})")
            continue
        kept.append(term)
    # report kept terms in the caller's order
    return [t for t in terms if t in kept], dropped


def _identifiable_terms(temp: FloatArray, dtemp: FloatArray, terms: Sequence[str]
                        ) -> tuple[list[str], dict[str, str]]:
    """The rank test of :func:`_identifiable`, with a warning (attributed to the caller of
    :func:`fit_thermal`) for the terms left out, and an error when none is left."""
    kept, dropped = _identifiable(temp, dtemp, terms)
    if dropped:
        warnings.warn("thermal model: unidentifiable term(s) left out: "
                      + "; ".join(f"{t} ({why})" for t, why in dropped.items())
                      + (" - the temperature is constant" if np.ptp(temp) == 0 else ""),
                      UnidentifiableTermWarning, stacklevel=3)
    if not kept:
        raise InsufficientDataError(f"no identifiable thermal term among {list(terms)!r}")
    return kept, dropped


def _warn_missing_stderr(kept: Sequence[str], bse: FloatArray, temp: FloatArray) -> None:
    """Warn, naming them, about the kept terms that got no standard error (NaN: their
    columns nearly collinear over the record), attributed to the caller of fit_thermal."""
    missing = [t for t, se in zip(kept, bse, strict=True) if not np.isfinite(se)]
    if missing:
        warnings.warn(f"thermal model: no standard error for {', '.join(missing)}: their "
                      "columns are nearly collinear over the recorded temperature (span "
                      f"{float(np.ptp(temp)):.3g} °C), so the data do not determine their "
                      "values", UnidentifiableTermWarning, stacklevel=3)


# --------------------------------------------------------------------------- error models


def _fit_gls_ar(y: FloatArray, X: FloatArray, order: int
                ) -> tuple[FloatArray, FloatArray, dict[str, Any]]:
    """GLSAR estimate with AR(``order``) errors and its sandwich standard errors."""
    import statsmodels.api as sm

    n, k = X.shape
    if n < 10 * (order + k):
        raise InsufficientDataError(
            f"errors='ar' with ar_order={order} needs at least {10 * (order + k)} "
            f"samples, got {n}; use errors='hac' or a lower ar_order")
    glsar = sm.GLSAR(y, X, rho=order)
    res = glsar.iterative_fit(maxiter=50, rtol=1e-6)
    rho = np.atleast_1d(np.asarray(glsar.rho, dtype=float))
    noise_order = min(NOISE_AR_ORDER, max(order, n // 10 - k))
    params = np.asarray(res.params, dtype=float)
    bse = _gls_sandwich_stderr(y - X @ params, X, rho, noise_order)
    error_params = {"ar": [float(v) for v in rho],
                    "iterations": int(res.iter) if hasattr(res, "iter") else None,
                    "stderr": f"sandwich under an AR({noise_order}) model of the residuals"}
    return params, bse, error_params


def _fit_ols_hac(y: FloatArray, X: FloatArray, hac_maxlags: int | None
                 ) -> tuple[FloatArray, FloatArray, dict[str, Any]]:
    """OLS estimate with Newey–West HAC standard errors (default lags: see fit_thermal)."""
    import statsmodels.api as sm

    n = y.size
    lags = (check_int("hac_maxlags", hac_maxlags, minimum=0) if hac_maxlags is not None
            else max(int(4 * (n / 100) ** (2 / 9)), round(2 * n ** (1 / 3))))
    res = sm.OLS(y, X).fit(cov_type="HAC", cov_kwds={"maxlags": lags, "use_correction": True})
    return (np.asarray(res.params, dtype=float), np.asarray(res.bse, dtype=float),
            {"maxlags": lags})


def _fit_ols(y: FloatArray, X: FloatArray) -> tuple[FloatArray, FloatArray, dict[str, Any]]:
    """Ordinary least squares with its own standard errors."""
    import statsmodels.api as sm

    res = sm.OLS(y, X).fit()
    return np.asarray(res.params, dtype=float), np.asarray(res.bse, dtype=float), {}


def _gls_sandwich_stderr(resid: FloatArray, X: FloatArray, rho: FloatArray,
                         noise_order: int) -> FloatArray:
    """Standard errors of the AR(``len(rho)``)-whitened GLS estimate under an AR(q) noise.

    With ``L`` the whitening (rows ``t >= p``: ``e_t - sum_j rho_j e_{t-j}``) and
    ``Xw = L X``, the estimate is ``(Xw'Xw)^-1 Xw' L y``, so its covariance is
    ``B Xw' L Sigma L' Xw B`` with ``B = (Xw'Xw)^-1``.  ``Sigma = s^2 A^-1 A^-T`` is the
    AR(q) covariance of the residuals (``A`` the lower-triangular AR(q) filter, Yule–Walker
    estimates), so ``Xw' L Sigma L' Xw = s^2 Z'Z`` with ``Z = A^-T L' Xw``: ``L'`` and
    ``A^-T`` are the time-reversed filters, applied with :func:`scipy.signal.lfilter`.
    """
    from scipy.linalg import solve_toeplitz
    from scipy.signal import lfilter
    from statsmodels.tsa.stattools import acovf

    n, p = X.shape[0], rho.size
    xw = X[p:].copy()
    for j in range(p):
        xw -= rho[j] * X[p - 1 - j : n - 1 - j]
    v = np.zeros_like(X)
    v[p:] = xw
    g = v.copy()  # L' v: g_s = v_s - sum_j rho_j v_{s+j}
    for j in range(p):
        g[: n - 1 - j] -= rho[j] * v[1 + j :]
    acov = acovf(resid, nlag=noise_order, fft=True)  # biased (1/n): Yule-Walker "mle"
    try:
        phi = solve_toeplitz(acov[:noise_order], acov[1:])
    except np.linalg.LinAlgError:  # (numerically) exact fit: no noise to model
        phi = np.zeros(noise_order)
    sigma2 = float(acov[0] - phi @ acov[1:])
    z = lfilter([1.0], np.concatenate([[1.0], -phi]), g[::-1], axis=0)[::-1]
    return np.sqrt(sigma2 * _sandwich_diagonal(xw, z))


def _sandwich_diagonal(xw: FloatArray, z: FloatArray) -> FloatArray:
    """``diag(B Z'Z B)`` with ``B = (Xw'Xw)^-1``, as column sums of squares of ``M = Z B``.

    The columns are scaled to unit norm and ``B`` taken from the QR factor of the scaled
    ``Xw`` by two triangular solves (Golub & Van Loan, *Matrix Computations*, 4th ed.,
    sec. 5.3: least squares by QR), never by inverting ``Xw'Xw``: the terms in T², T and 1
    over a record whose temperature spans 0.5 °C near 36 °C make ``Xw'Xw`` so ill-conditioned
    that its explicit inverse gave negative variances (NaN standard errors) on one CPU's
    kernel and finite ones on another.  A sum of squares is never negative."""
    from scipy.linalg import solve_triangular

    scale = np.linalg.norm(xw, axis=0)
    scale[scale == 0.0] = 1.0
    r = np.linalg.qr(xw / scale, mode="r")
    w_t = solve_triangular(r, (z / scale).T, trans="T")   # (Z S^-1 R^-1)'
    m_t = solve_triangular(r, w_t)                         # (Z S^-1 R^-1 R^-T)'
    return np.asarray(np.sum(m_t**2, axis=1) / scale**2, dtype=np.float64)


def _r_squared(y: FloatArray, resid: FloatArray, kept: Sequence[str]) -> tuple[float, float]:
    """Centred R² and adjusted R² of the original (not whitened) data, whatever the error
    model."""
    n = y.size
    sst = float(np.sum((y - y.mean()) ** 2))
    r2 = 1.0 - float(np.sum(resid ** 2)) / sst if sst > 0 else math.nan
    dof = n - len(kept) - (1 if "1" not in kept else 0)
    r2_adj = 1.0 - (1.0 - r2) * (n - 1) / (n - len(kept)) if dof > 0 else math.nan
    return r2, r2_adj
