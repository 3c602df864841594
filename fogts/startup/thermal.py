"""Temperature-drift model of a gyro, its compensation, and bias stability.

Seed 004 (FOG north seeking at cold start), steps 5-7, models the start-up drift of the gyro
bias as a multi-parameter linear function of the temperature T and its rate of change ΔT:

    D = a·T·ΔT + b·T² + c·T + d·ΔT² + e·ΔT + f                       (seed 004, step 6)

fitted by least squares (``statsmodels.OLS``).  The temperature rate ΔT (°C/s) is the first
derivative of a Savitzky–Golay fit (quadratic, window ``dT_smoothing_s``) of the temperature,
because temperature sensors are quantised and a raw difference is mostly noise.

Errors: the residual of a gyro drift fit is strongly autocorrelated (it is the ARMA drift of
seed 000), so plain OLS standard errors are far too small.  The default ``errors="ar"`` is
feasible generalised least squares with AR(``ar_order``) errors (``statsmodels.GLSAR``,
iterated Cochrane–Orcutt / Prais–Winsten; Greene, *Econometric Analysis*, 7th ed., §20.9),
which is least squares on the pre-whitened data.  ``"hac"`` keeps the OLS estimate with
Newey–West HAC standard errors (Newey & West 1987, *Econometrica* 55:703); ``"ols"`` is
ordinary least squares.

Standard errors of the ``"ar"`` fit are a sandwich: the estimator is the AR(``ar_order``)
GLS one, but its covariance is evaluated under a longer AR(``NOISE_AR_ORDER`` = 16) model of
the residuals (Yule–Walker), ``B Xw' L S L' Xw B`` with ``Xw = L X``, ``B = (Xw'Xw)^-1``,
``L`` the AR(``ar_order``) whitening and ``S`` the AR(16) covariance (the covariance of a
GLS estimator with a misspecified error covariance; Greene, *Econometric Analysis*, 7th ed.,
§9.2.2).  Drift noise that is AR(1) plus white noise is an
ARMA(1,1) whose AR(inf) weights decay like 0.8^k for the simulated cold start, which four
lags whiten only partly; GLSAR's own standard errors then come out 1.35x too small.
Measured over 60 simulated cold starts (:mod:`fogts.startup.simulator`, seeds 500-559;
fraction of the six coefficients' truths within 2 SE, ideal 95 %): GLSAR's own SEs 83-88 %,
the sandwich 92-93 % (|error|/SE standard deviation 1.14; longer noise models change
nothing, the rest is probably the noise of the measured temperature).  Whitening with
AR(16) itself gives 93-97 % coverage but recovers the drift curve D(T, ΔT) 1.8x worse
(median RMS error 0.070 against 0.040 of the drift's spread), so the AR(4) estimate stays.

Unidentifiable terms (for example every ΔT term when the temperature is constant) are
detected by a rank test on the normalised design matrix, reported with an
:class:`~fogts.errors.UnidentifiableTermWarning` and left out of the fit.

Bias stability follows the static test of GJB 2426A-2015 / IEEE Std 952-1997: the 1σ
standard deviation of the bias averaged over consecutive, non-overlapping windows of
``average_s`` seconds (10 s unless stated), in °/h.  The averaging time is part of every
output: a bias stability without it means nothing.
"""

from __future__ import annotations

import math
import warnings
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field, replace
from typing import Any, Literal, get_args

import numpy as np
import pandas as pd
from scipy.signal import savgol_filter

from fogts._typing import FloatArray
from fogts._validate import (
    check_choice,
    check_int,
    check_positive,
    pandas_index,
    to_float_array,
)
from fogts.errors import (
    DataError,
    InsufficientDataError,
    ModelFitError,
    UnidentifiableTermWarning,
)
from fogts.io.run import Run
from fogts.units import parse_rate_unit, to_deg_per_hour_factor

__all__ = [
    "THERMAL_TERMS",
    "BiasStability",
    "StartupCompensation",
    "ThermalModel",
    "bias_stability",
    "compensate",
    "design_matrix",
    "fit_thermal",
    "startup_compensation",
    "temperature_rate",
]

ThermalTerm = Literal["T*dT", "T2", "T", "dT2", "dT", "1"]
THERMAL_TERMS: tuple[str, ...] = get_args(ThermalTerm)
ErrorModel = Literal["ar", "hac", "ols"]
ERROR_MODELS: tuple[str, ...] = get_args(ErrorModel)
#: Default AR order of the GLSAR error model (the whitening of the estimator).
DEFAULT_AR_ORDER = 4
#: AR order of the residual model under which the standard errors are evaluated.
NOISE_AR_ORDER = 16

#: Paper letter of each term (seed 004: D = a·T·ΔT + b·T² + c·T + d·ΔT² + e·ΔT + f).
TERM_LETTERS: dict[str, str] = {"T*dT": "a", "T2": "b", "T": "c", "dT2": "d", "dT": "e", "1": "f"}
#: Order in which terms enter the rank test: a term that is a combination of terms
#: earlier in this list is unidentifiable (so a constant temperature keeps the intercept).
_RANK_ORDER = ("1", "T", "dT", "T2", "dT2", "T*dT")
#: Relative tolerance of the rank test on the column-normalised design matrix.
RANK_RTOL = 1e-9
#: Default Savitzky-Golay window for the temperature rate.
DEFAULT_DT_SMOOTHING_S = 60.0


# --------------------------------------------------------------------------- temperature rate


def temperature_rate(temperature: Any, *, fs_hz: float,
                     smoothing_s: float | None = DEFAULT_DT_SMOOTHING_S) -> FloatArray:
    """Rate of change of the temperature in °C/s.

    The first derivative of a local quadratic (Savitzky–Golay) fit over ``smoothing_s``
    seconds (an odd number of samples, at least 5, at most the record); ``None`` uses
    ``numpy.gradient`` of the raw samples.

    Examples
    --------
    >>> import numpy as np
    >>> t = np.arange(600.0)
    >>> r = temperature_rate(20 + 0.01 * t, fs_hz=1.0)
    >>> bool(np.allclose(r, 0.01))
    True
    """
    fs = check_positive("fs_hz", fs_hz)
    temp = to_float_array(temperature, "temperature", min_length=5)
    if smoothing_s is None:
        rate = np.gradient(temp) * fs
    else:
        window = round(check_positive("dT_smoothing_s", smoothing_s) * fs)
        window = max(5, window | 1)
        if window > temp.size:
            window = temp.size if temp.size % 2 else temp.size - 1
        rate = np.asarray(savgol_filter(temp, window, 2, deriv=1, delta=1.0 / fs, mode="interp"),
                          dtype=np.float64)
    # rounding residue of a constant temperature is not a rate (keeps the rank test honest)
    rate[np.abs(rate) <= 1e-12 * fs * max(1.0, float(np.max(np.abs(temp))))] = 0.0
    return rate


def design_matrix(temp: FloatArray, dtemp: FloatArray, terms: Sequence[str]) -> FloatArray:
    """Regressor columns of the seed-004 drift model, one per term, for T (°C) and ΔT (°C/s).

    Examples
    --------
    >>> design_matrix(np.array([20.0]), np.array([0.1]), ["T*dT", "T2", "1"]).tolist()
    [[2.0, 400.0, 1.0]]
    """
    cols = {"T*dT": temp * dtemp, "T2": temp * temp, "T": temp, "dT2": dtemp * dtemp,
            "dT": dtemp, "1": np.ones_like(temp)}
    return np.column_stack([cols[t] for t in terms]) if terms else np.empty((temp.size, 0))


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


# --------------------------------------------------------------------------- thermal model


@dataclass(frozen=True)
class ThermalModel:
    """A fitted temperature-drift model ``D = sum_j coef_j * term_j(T, ΔT)`` (seed 004).

    Attributes
    ----------
    terms : tuple of str
        The fitted terms, from ``"T*dT", "T2", "T", "dT2", "dT", "1"``.
    coefficients, stderr : dict
        Estimate and standard error of each fitted term, in ``units`` per term unit
        (T in °C, ΔT in °C/s).
    dropped : dict
        Requested terms left out, with the reason.
    r2, r2_adj : float
        Coefficient of determination (R² of the fit; centred when the intercept is fitted).
    residual_std : float
        Standard deviation of the fit residual, in ``units``.
    residual : ndarray or pandas.Series
        ``gyro - fitted`` (empty when the model was loaded with :meth:`from_dict`).
    units : str
        Rate unit of the gyro data the model was fitted to.
    fs_hz : float
        Sample rate of the fit data.
    dT_smoothing_s : float or None
        Savitzky–Golay window used for ΔT (None: raw gradient).
    t_ref_degC : float
        Reference temperature: :func:`compensate` removes ``D(T, ΔT) - D(t_ref, 0)``.
    temperature_range_degC : tuple of float
        Min and max temperature in the fit data (the model's domain).
    errors : str
        Error model of the fit: ``"ar"`` (GLSAR), ``"hac"`` or ``"ols"``.
    error_params : dict
        ``{"ar": [...]}`` (the fitted AR coefficients of the error) for ``"ar"``,
        ``{"maxlags": L}`` for ``"hac"``, ``{}`` for ``"ols"``.
    n : int
        Samples fitted.
    """

    terms: tuple[str, ...]
    coefficients: dict[str, float]
    stderr: dict[str, float]
    dropped: dict[str, str]
    r2: float
    r2_adj: float
    residual_std: float
    units: str
    fs_hz: float
    dT_smoothing_s: float | None
    t_ref_degC: float
    temperature_range_degC: tuple[float, float]
    errors: str
    error_params: dict[str, Any]
    n: int
    residual: Any = field(default=None, repr=False)

    # ---- evaluation
    def predict(self, temperature: Any, *, fs_hz: float | None = None,
                temperature_rate_degC_s: Any = None) -> FloatArray:
        """Drift ``D(T, ΔT)`` in ``units`` for a temperature record.

        ΔT is computed as in the fit (same smoothing) unless given.
        """
        temp = to_float_array(temperature, "temperature", min_length=1)
        if temperature_rate_degC_s is None:
            fs = self.fs_hz if fs_hz is None else check_positive("fs_hz", fs_hz)
            dtemp = temperature_rate(temp, fs_hz=fs, smoothing_s=self.dT_smoothing_s)
        else:
            dtemp = to_float_array(temperature_rate_degC_s, "temperature_rate_degC_s",
                                   min_length=1)
            if dtemp.size != temp.size:
                raise DataError(f"temperature_rate_degC_s has {dtemp.size} samples, "
                                f"temperature has {temp.size}; they must match")
        beta = np.array([self.coefficients[t] for t in self.terms])
        return design_matrix(temp, dtemp, self.terms) @ beta if self.terms else np.zeros_like(temp)

    def reference_drift(self) -> float:
        """``D(t_ref, 0)``: the steady-state drift at the reference temperature."""
        t = np.array([self.t_ref_degC])
        beta = np.array([self.coefficients[k] for k in self.terms])
        return float((design_matrix(t, np.zeros(1), self.terms) @ beta)[0]) if self.terms else 0.0

    def equation(self, digits: int = 6) -> str:
        """The model written out, e.g. ``D = 0.2·T·ΔT + 0.001·T² + ...``."""
        sym = {"T*dT": "T·ΔT", "T2": "T²", "T": "T", "dT2": "ΔT²", "dT": "ΔT", "1": ""}
        out = "D ="
        for i, t in enumerate(self.terms):
            c = self.coefficients[t]
            sign = "-" if c < 0 else ("+" if i else "")
            body = f"{abs(c):.{digits}g}" + (f"·{sym[t]}" if sym[t] else "")
            out += f" {sign} {body}" if sign else f" {body}"
        return out + f"   [{self.units}; T in °C, ΔT in °C/s]"

    # ---- serialisation
    def to_dict(self) -> dict[str, Any]:
        """JSON-safe dictionary; :meth:`from_dict` restores the model (without the residual)."""
        return {
            "model": "seed004-thermal",
            "terms": {t: {"value": float(self.coefficients[t]), "stderr": float(self.stderr[t]),
                          "letter": TERM_LETTERS[t]} for t in self.terms},
            "dropped": dict(self.dropped),
            "r2": float(self.r2),
            "r2_adj": float(self.r2_adj),
            "residual_std": float(self.residual_std),
            "units": self.units,
            "fs_hz": float(self.fs_hz),
            "dT_smoothing_s": None if self.dT_smoothing_s is None else float(self.dT_smoothing_s),
            "t_ref_degC": float(self.t_ref_degC),
            "temperature_range_degC": [float(v) for v in self.temperature_range_degC],
            "errors": self.errors,
            "error_params": dict(self.error_params),
            "n": int(self.n),
        }

    @classmethod
    def from_dict(cls, data: Mapping[str, Any]) -> ThermalModel:
        """Rebuild a model saved with :meth:`to_dict` (for example from JSON)."""
        if not isinstance(data, Mapping) or "terms" not in data or "units" not in data:
            raise DataError("a thermal model needs the keys 'terms' and 'units' (as written by "
                            f"ThermalModel.to_dict); got {sorted(data) if isinstance(data, Mapping) else type(data).__name__}")
        terms_d = data["terms"]
        if not isinstance(terms_d, Mapping):
            raise DataError(f"thermal model 'terms' must map a term to {{value, stderr}}, got "
                            f"{terms_d!r}")
        for t in terms_d:
            if t not in THERMAL_TERMS:
                raise DataError(f"unknown thermal term {t!r}; allowed: {', '.join(THERMAL_TERMS)}")
        rng = data.get("temperature_range_degC") or [math.nan, math.nan]
        smoothing = data.get("dT_smoothing_s", DEFAULT_DT_SMOOTHING_S)
        try:
            return cls(
                terms=tuple(terms_d),
                coefficients={t: float(v["value"]) for t, v in terms_d.items()},
                stderr={t: _nan_float(v.get("stderr")) for t, v in terms_d.items()},
                dropped=dict(data.get("dropped", {})),
                r2=_nan_float(data.get("r2")),
                r2_adj=_nan_float(data.get("r2_adj")),
                residual_std=_nan_float(data.get("residual_std")),
                units=parse_rate_unit(str(data["units"]), "units"),
                fs_hz=check_positive("fs_hz", data.get("fs_hz", 1.0)),
                dT_smoothing_s=None if smoothing is None else float(smoothing),
                t_ref_degC=float(data.get("t_ref_degC", 0.0)),
                temperature_range_degC=(_nan_float(rng[0]), _nan_float(rng[1])),
                errors=str(data.get("errors", "ar")),
                error_params=dict(data.get("error_params", {})),
                n=int(data.get("n", 0)),
            )
        except (KeyError, TypeError, AttributeError) as exc:
            raise DataError(f"malformed thermal model: {exc!r}") from None

    def to_frame(self) -> pd.DataFrame:
        """One row per fitted term: letter, value, stderr."""
        return pd.DataFrame({"term": list(self.terms),
                             "letter": [TERM_LETTERS[t] for t in self.terms],
                             "value": [self.coefficients[t] for t in self.terms],
                             "stderr": [self.stderr[t] for t in self.terms]}).set_index("term")

    def summary(self) -> str:
        lines = [f"Thermal drift model (seed 004), n = {self.n}, fs = {self.fs_hz:g} Hz",
                 "  " + self.equation(),
                 "  term     letter          value         stderr"]
        for t in self.terms:
            lines.append(f"  {t:<8s} {TERM_LETTERS[t]:>6s}  {self.coefficients[t]:13.6g}  "
                         f"{self.stderr[t]:13.4g}")
        for t, why in self.dropped.items():
            lines.append(f"  {t:<8s} dropped: {why}")
        lo, hi = self.temperature_range_degC
        lines.append(f"  R² = {self.r2:.4f}  residual std = {self.residual_std:.6g} {self.units}"
                     f"  (errors: {_ERROR_TEXT.get(self.errors, self.errors)})")
        lines.append(f"  fitted over T = {lo:.3g}..{hi:.3g} °C; reference T = {self.t_ref_degC:.4g} °C")
        return "\n".join(lines)


_ERROR_TEXT = {"ar": "GLS with AR errors", "hac": "OLS, HAC standard errors", "ols": "OLS"}


def _nan_float(v: Any) -> float:
    return math.nan if v is None else float(v)


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
    """Fit the seed-004 temperature-drift model by least squares.

    Parameters
    ----------
    gyro : array_like or pandas.Series
        Gyro rate (ideally the EMD trend plus the Kalman-filtered rest, seed 004 step 4).
    temperature : array_like or pandas.Series
        Temperature in °C, same length.
    fs_hz : float
        Sample rate in Hz.
    terms : sequence of str
        Subset of ``"T*dT", "T2", "T", "dT2", "dT", "1"`` (letters a..f of seed 004).
    dT_smoothing_s : float or None
        Savitzky–Golay window for ΔT in seconds (see :func:`temperature_rate`).
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
        Reference temperature for :func:`compensate` (default: mean of the last 5 % of the
        record, the warm steady state of a start-up run).
    temperature_rate_degC_s : array_like, optional
        ΔT given directly (for example computed run by run with :func:`temperature_rate`
        when several calibration runs are concatenated); default: computed from
        ``temperature``.

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
    or :func:`startup_compensation` with ``calibration``).

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
    import statsmodels.api as sm

    fs = check_positive("fs_hz", fs_hz)
    unit = parse_rate_unit(units)
    check_choice("errors", errors, ERROR_MODELS)
    order = check_int("ar_order", ar_order, minimum=1, maximum=50)
    if isinstance(terms, str):
        raise DataError(f"terms must be a sequence of term names, got the string {terms!r}")
    terms = list(terms)
    for t in terms:
        check_choice("terms", t, THERMAL_TERMS)
    if len(set(terms)) != len(terms) or not terms:
        raise DataError(f"terms must be non-empty without repeats, got {terms!r}")
    index = pandas_index(gyro)
    y = to_float_array(gyro, "gyro")
    if temperature is None:
        raise DataError("temperature is required: the thermal model needs a temperature record "
                        "(give --temperature-column on the command line)")
    temp = to_float_array(temperature, "temperature")
    if temp.size != y.size:
        raise DataError(f"temperature has {temp.size} samples but gyro has {y.size}; they must "
                        "be aligned sample by sample")
    need = max(20, 5 * len(terms))
    if y.size < need:
        raise InsufficientDataError(f"gyro needs at least {need} samples for a {len(terms)}-term "
                                    f"thermal model, got {y.size}")
    if temperature_rate_degC_s is None:
        dtemp = temperature_rate(temp, fs_hz=fs, smoothing_s=dT_smoothing_s)
    else:
        dtemp = to_float_array(temperature_rate_degC_s, "temperature_rate_degC_s")
        if dtemp.size != y.size:
            raise DataError(f"temperature_rate_degC_s has {dtemp.size} samples but gyro has "
                            f"{y.size}; they must be aligned sample by sample")
    kept, dropped = _identifiable(temp, dtemp, terms)
    if dropped:
        warnings.warn("thermal model: unidentifiable term(s) left out: "
                      + "; ".join(f"{t} ({why})" for t, why in dropped.items())
                      + (" - the temperature is constant" if np.ptp(temp) == 0 else ""),
                      UnidentifiableTermWarning, stacklevel=2)
    if not kept:
        raise InsufficientDataError(f"no identifiable thermal term among {terms!r}")
    X = design_matrix(temp, dtemp, kept)
    n = y.size
    error_params: dict[str, Any] = {}
    if errors == "ar":
        if n < 10 * (order + len(kept)):
            raise InsufficientDataError(
                f"errors='ar' with ar_order={order} needs at least {10 * (order + len(kept))} "
                f"samples, got {n}; use errors='hac' or a lower ar_order")
        glsar = sm.GLSAR(y, X, rho=order)
        res = glsar.iterative_fit(maxiter=50, rtol=1e-6)
        rho = np.atleast_1d(np.asarray(glsar.rho, dtype=float))
        noise_order = min(NOISE_AR_ORDER, max(order, n // 10 - len(kept)))
        bse_sandwich = _gls_sandwich_stderr(y - X @ np.asarray(res.params, dtype=float), X,
                                            rho, noise_order)
        error_params = {"ar": [float(v) for v in rho],
                        "iterations": int(res.iter) if hasattr(res, "iter") else None,
                        "stderr": f"sandwich under an AR({noise_order}) model of the residuals"}
    elif errors == "hac":
        lags = (check_int("hac_maxlags", hac_maxlags, minimum=0) if hac_maxlags is not None
                else max(int(4 * (n / 100) ** (2 / 9)), round(2 * n ** (1 / 3))))
        res = sm.OLS(y, X).fit(cov_type="HAC", cov_kwds={"maxlags": lags, "use_correction": True})
        error_params = {"maxlags": lags}
    else:
        res = sm.OLS(y, X).fit()
    params = np.asarray(res.params, dtype=float)
    bse = bse_sandwich if errors == "ar" else np.asarray(res.bse, dtype=float)
    resid = y - X @ params
    # centred R² of the original (not whitened) data, whatever the error model
    sst = float(np.sum((y - y.mean()) ** 2))
    r2 = 1.0 - float(np.sum(resid ** 2)) / sst if sst > 0 else math.nan
    dof = n - len(kept) - (1 if "1" not in kept else 0)
    r2_adj = 1.0 - (1.0 - r2) * (n - 1) / (n - len(kept)) if dof > 0 else math.nan
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
    bread = np.linalg.inv(xw.T @ xw)
    cov = sigma2 * bread @ (z.T @ z) @ bread
    return np.sqrt(np.diag(cov))


def _rate_on_time_base(run: Run, model: ThermalModel) -> FloatArray | None:
    """ΔT of a run whose time stamps have gaps: the temperature is interpolated onto a
    regular grid at ``run.fs_hz``, differentiated there and read back at the time stamps.
    None for a regular time base (the model then differentiates the samples directly)."""
    t = np.asarray(run.time, dtype=float)
    if t.size < 3 or run.temperature is None:
        return None
    dt = np.diff(t)
    step = 1.0 / run.fs_hz
    if np.all(np.abs(dt - step) <= 0.5 * step):
        return None
    grid = np.arange(t[0], t[-1] + 0.5 * step, step)
    temp_grid = np.interp(grid, t, np.asarray(run.temperature, dtype=float))
    rate = temperature_rate(temp_grid, fs_hz=run.fs_hz, smoothing_s=model.dT_smoothing_s)
    return np.interp(t, grid, rate)


def compensate(run: Run, model: ThermalModel, *, axis: int | str = 0,
               reference_degC: float | None = None) -> Run:
    """Remove the modelled temperature drift from a run (seed 004, step 7).

    Subtracts ``D(T, ΔT) - D(T_ref, 0)`` from the rate, where T_ref is the model's reference
    temperature (the warm steady state of the fit record) unless ``reference_degC`` is
    given.  The output therefore keeps the steady-state bias and the Earth-rate component
    that a north finder needs, and loses only the temperature-driven change.

    Parameters
    ----------
    run : Run
        A recording with a temperature column.
    model : ThermalModel
        Fitted by :func:`fit_thermal` (possibly on another run, loaded with
        :meth:`ThermalModel.from_dict`).
    axis : int or str
        Axis to compensate (the other axes are left unchanged).
    reference_degC : float, optional
        Override the reference temperature.

    Returns
    -------
    Run
        A copy of ``run`` with the compensated rate; ``source`` records the compensation.

    Raises
    ------
    DataError
        The run has no temperature.

    Examples
    --------
    >>> import numpy as np
    >>> from fogts.io.run import Run
    >>> t = np.arange(600.0)
    >>> temp = 20 + 0.02 * t
    >>> run = Run(rate=2.0 * temp, time=t, fs_hz=1.0, units="deg/h", axes=("gyro",),
    ...           temperature=temp)
    >>> m = fit_thermal(run.rate, temp, fs_hz=1.0, terms=("T", "1"))
    >>> out = compensate(run, m, reference_degC=20.0)
    >>> bool(np.allclose(out.rate, 40.0))
    True
    """
    if not isinstance(run, Run):
        raise DataError(f"run must be a fogts Run, got {type(run).__name__}")
    if not isinstance(model, ThermalModel):
        raise DataError(f"model must be a ThermalModel, got {type(model).__name__}")
    if run.temperature is None:
        raise DataError(f"run {run.source!r} has no temperature column; thermal compensation "
                        "needs one (columns are: " + ", ".join(run.columns or run.axes) + ")")
    drift = model.predict(run.temperature, fs_hz=run.fs_hz,
                          temperature_rate_degC_s=_rate_on_time_base(run, model))
    if reference_degC is not None:
        ref_model = replace(model, t_ref_degC=float(reference_degC))
        drift = drift - ref_model.reference_drift()
    else:
        drift = drift - model.reference_drift()
    factor = to_deg_per_hour_factor(model.units) / to_deg_per_hour_factor(run.units)
    drift = drift * factor
    rate = np.array(run.rate, dtype=np.float64, copy=True)
    if rate.ndim == 1:
        rate -= drift
    else:
        i = run.axes.index(axis) if isinstance(axis, str) and axis in run.axes else axis
        if isinstance(i, str):
            raise DataError(f"axis {axis!r} not found; axes are: {', '.join(run.axes)}")
        run.axis(i)  # validates the index
        rate[:, i] -= drift
    return replace(run, rate=rate, source=f"{run.source} (thermally compensated)")


# --------------------------------------------------------------------------- bias stability


@dataclass(frozen=True)
class BiasStability:
    """Bias stability: 1σ of the bias averaged over ``average_s`` (GJB 2426A / IEEE 952).

    Attributes
    ----------
    value : float
        The 1σ standard deviation of the window means, in ``unit``.
    average_s : float
        Averaging time of each window in seconds.
    n_windows : int
        Number of complete windows used.
    unit : str
        Always ``"deg/h"``.
    mean : float
        Mean of the window means (the average bias) in ``unit``.
    """

    value: float
    average_s: float
    n_windows: int
    unit: str = "deg/h"
    mean: float = math.nan

    def to_dict(self) -> dict[str, Any]:
        return {"value": self.value, "average_s": self.average_s, "n_windows": self.n_windows,
                "unit": self.unit, "mean": self.mean}

    def to_frame(self) -> pd.DataFrame:
        return pd.DataFrame([self.to_dict()])

    def summary(self) -> str:
        return (f"bias stability {self.value:.4g} {self.unit} (1σ, {self.average_s:g} s average, "
                f"{self.n_windows} windows)")

    def __str__(self) -> str:
        return self.summary()


def bias_stability(x: Any, *, fs_hz: float, average_s: float = 10.0,
                   units: str = "deg/h") -> BiasStability:
    """Bias stability of a static record (GJB 2426A-2015 §5.3 / IEEE Std 952-1997 §12.3).

    The record is cut into consecutive non-overlapping windows of ``average_s`` seconds
    (a partial last window is dropped); the result is the sample standard deviation
    (ddof = 1) of the window means, converted to °/h.

    Parameters
    ----------
    x : array_like or pandas.Series
        Rate samples in ``units``.
    fs_hz : float
        Sample rate in Hz.
    average_s : float
        Averaging time in seconds (10 s in the GJB procedure; 100 s is also common).
    units : str
        Rate unit of ``x``.

    Returns
    -------
    BiasStability

    Raises
    ------
    InsufficientDataError
        Fewer than two complete windows.

    Examples
    --------
    >>> import numpy as np
    >>> x = np.random.default_rng(0).normal(0.0, 1.0, 36000)
    >>> b = bias_stability(x, fs_hz=10.0, average_s=10.0)
    >>> b.average_s, b.n_windows, round(b.value, 1)
    (10.0, 360, 0.1)
    """
    fs = check_positive("fs_hz", fs_hz)
    avg = check_positive("average_s", average_s)
    arr = to_float_array(x, "x")
    m = round(avg * fs)
    if m < 1:
        raise DataError(f"average_s={avg:g} s is shorter than one sample at {fs:g} Hz")
    k = arr.size // m
    if k < 2:
        raise InsufficientDataError(
            f"bias stability with average_s={avg:g} s needs at least two windows "
            f"({2 * m} samples), got {arr.size}")
    means = arr[: k * m].reshape(k, m).mean(axis=1) * to_deg_per_hour_factor(parse_rate_unit(units))
    return BiasStability(value=float(np.std(means, ddof=1)), average_s=m / fs, n_windows=k,
                         unit="deg/h", mean=float(np.mean(means)))


# --------------------------------------------------------------------------- seed-004 pipeline


@dataclass(frozen=True)
class StartupCompensation:
    """The seed-004 start-up compensation pipeline and its outcome.

    Attributes
    ----------
    run : Run
        The compensated recording (raw temperature kept).
    model : ThermalModel
        The thermal model fitted (or the one given).
    gyro_split, temperature_split : TrendSplit or None
        EMD trend separations (None without EMD).
    kalman : KalmanResult or None
        Kalman filter of the gyro's EMD rest.
    arma_model : str
        Name of the ARMA model of the rest ("" without EMD).
    gyro_used, temperature_used : ndarray
        The series the thermal model was fitted to (trend + filtered rest, or raw).
    raw_rate : ndarray
        The input rate of the compensated axis.
    before, after : BiasStability
        Bias stability of the raw and of the compensated rate.
    axis : str
    notes : tuple of str
    """

    run: Run
    model: ThermalModel
    gyro_split: Any
    temperature_split: Any
    kalman: Any
    arma_model: str
    gyro_used: FloatArray = field(repr=False)
    temperature_used: FloatArray = field(repr=False)
    raw_rate: FloatArray = field(repr=False)
    before: BiasStability
    after: BiasStability
    axis: str = ""
    notes: tuple[str, ...] = ()

    @property
    def improvement(self) -> float:
        """Bias stability before / after."""
        return self.before.value / self.after.value if self.after.value > 0 else math.inf

    def to_dict(self) -> dict[str, Any]:
        emd = None
        if self.gyro_split is not None:
            emd = {"k": int(self.gyro_split.k),
                   "imf_energy": [float(v) for v in self.gyro_split.imf_energy],
                   "n_imfs": self.gyro_split.n_imfs,
                   "temperature_k": (None if self.temperature_split is None
                                     else int(self.temperature_split.k))}
        model = self.model.to_dict()
        return {
            "axis": self.axis,
            "emd": emd,
            "arma_model": self.arma_model or None,
            "kalman": None if self.kalman is None else self.kalman.to_dict(),
            "thermal": {"terms": {t: {"value": v["value"], "stderr": v["stderr"]}
                                  for t, v in model["terms"].items()},
                        "r2": model["r2"], "dropped": model["dropped"],
                        "equation": self.model.equation(), "model": model},
            "bias_stability": {"average_s": self.before.average_s, "before": self.before.value,
                               "after": self.after.value, "unit": self.before.unit,
                               "improvement": self.improvement},
            "notes": list(self.notes),
        }

    def to_frame(self) -> pd.DataFrame:
        """Columns time, raw, trend (EMD, NaN without), used (fit input), compensated,
        temperature."""
        trend = (np.asarray(self.gyro_split.trend, dtype=float) if self.gyro_split is not None
                 else np.full(self.raw_rate.size, np.nan))
        return pd.DataFrame({"time": self.run.time, "raw": self.raw_rate, "trend": trend,
                             "used": self.gyro_used,
                             "compensated": self.run.axis(self.axis or 0),
                             "temperature": self.run.temperature})

    def summary(self) -> str:
        lines = []
        if self.gyro_split is not None:
            lines.append(f"EMD: {self.gyro_split.n_imfs} IMFs, trend from IMF {self.gyro_split.k} "
                         f"(mean-energy rule); rest modelled as {self.arma_model}")
        if self.kalman is not None:
            lines.append(f"Kalman: H = {self.kalman.measurement_noise:.4g} "
                         f"({self.kalman.measurement_noise_source}), {self.kalman.method}")
        lines.append(self.model.summary())
        lines.append(f"bias stability ({self.before.average_s:g} s average, 1σ): "
                     f"before {self.before.value:.4g} {self.before.unit}, after "
                     f"{self.after.value:.4g} {self.after.unit} ({self.improvement:.2f}x)")
        lines += [f"note: {n}" for n in self.notes]
        return "\n".join(lines)


def _emd_kalman(x: FloatArray, fs: float, arma_model: str,
                measurement_noise: Any) -> tuple[Any, Any, str, FloatArray]:
    """Seed 004 steps 1-4 on one series: EMD split, ARMA of the rest, Kalman of the rest."""
    from fogts.startup.emd import separate_trend
    from fogts.startup.kalman import arma_kalman, resolve_arma_model

    split = separate_trend(x, fs_hz=fs)
    rest = np.asarray(split.rest, dtype=float)
    if split.k == 1 or float(np.ptp(rest)) == 0.0:
        return split, None, "", np.asarray(split.trend, dtype=float)
    fit = resolve_arma_model(rest, arma_model)
    kal = arma_kalman(rest, fit, measurement_noise=measurement_noise)
    name = str(getattr(fit, "name", kal.model))
    return split, kal, name, np.asarray(split.trend, dtype=float) + np.asarray(kal.filtered)


@dataclass
class _FitInput:
    gyro: FloatArray
    temp: FloatArray
    gyro_split: Any
    temp_split: Any
    kalman: Any
    arma: str
    notes: list[str]


def _prepare_fit_run(run: Run, axis: int | str, *, emd: bool, arma_model: str,
                     measurement_noise: Any) -> _FitInput:
    """Seed 004 steps 1-5 on one run: the gyro and temperature series to fit."""
    if run.temperature is None:
        raise DataError(f"run {run.source!r} has no temperature column; thermal compensation "
                        "needs one (columns are: " + ", ".join(run.columns or run.axes)
                        + "); name it with --temperature-column")
    gyro = run.axis(axis)
    temp = np.asarray(run.temperature, dtype=float)
    if not emd:
        return _FitInput(gyro, temp, None, None, None, "", [])
    notes: list[str] = []
    gsplit, kal, arma_name, gyro_used = _emd_kalman(gyro, run.fs_hz, arma_model,
                                                    measurement_noise)
    if kal is not None:
        notes.extend(kal.notes)
    tsplit = None
    temp_used = temp
    if float(np.ptp(temp)) > 0:
        try:
            tsplit, _, _, temp_used = _emd_kalman(temp, run.fs_hz, arma_model, measurement_noise)
        except (InsufficientDataError, ModelFitError) as exc:
            from fogts.startup.emd import separate_trend

            tsplit = separate_trend(temp, fs_hz=run.fs_hz)
            temp_used = np.asarray(tsplit.trend, dtype=float)
            notes.append(f"temperature rest not Kalman-filtered ({exc}); used its EMD trend")
    else:
        notes.append("the temperature is constant: no EMD of the temperature")
    return _FitInput(gyro_used, temp_used, gsplit, tsplit, kal, arma_name, notes)


def startup_compensation(
    run: Run,
    *,
    axis: int | str = 0,
    emd: bool = True,
    model: ThermalModel | None = None,
    arma_model: str = "auto",
    measurement_noise: Any = "estimate",
    terms: Sequence[str] = ("T*dT", "T2", "T", "dT2", "dT", "1"),
    dT_smoothing_s: float | None = DEFAULT_DT_SMOOTHING_S,
    errors: ErrorModel = "ar",
    average_s: float = 10.0,
    calibration: Sequence[Run] = (),
) -> StartupCompensation:
    """Seed 004's start-up drift compensation, steps 1-7, on one axis of a run.

    1. EMD of the gyro output; trend = IMFs from the first whose mean energy rises again
       (:func:`fogts.startup.emd.separate_trend`), rest = the faster IMFs;
    2. ARMA model of the rest (``arma_model``: ``"auto"`` runs the candidate selection);
    3. Kalman filter of the rest in Harvey form (:func:`fogts.startup.kalman.arma_kalman`);
    4. filtered gyro = trend + filtered rest;
    5. the same for the temperature;
    6. least-squares fit of D = a·T·ΔT + b·T² + c·T + d·ΔT² + e·ΔT + f (:func:`fit_thermal`);
    7. compensation (:func:`compensate`) and bias stability before and after.

    With ``emd=False`` steps 1-5 are skipped and the model is fitted to the raw series.
    With ``model`` given, nothing is fitted: the saved model is applied.  ``calibration``
    adds further runs (same sample rate and units; for example cold starts at other ambient
    temperatures) to the fit: one warm-up determines only the combinations of the six
    coefficients along its own (T, ΔT) path, and several ambients make the model hold
    between them.

    Raises
    ------
    DataError
        The run has no temperature, or a bad option.

    Examples
    --------
    >>> from fogts.startup.simulator import simulate_startup
    >>> sim = simulate_startup(duration_s=1800, rng=4)
    >>> res = startup_compensation(sim.run, emd=False)
    >>> res.after.value < res.before.value
    True
    """
    if not isinstance(run, Run):
        raise DataError(f"run must be a fogts Run, got {type(run).__name__}")
    if run.temperature is None:
        raise DataError(f"run {run.source!r} has no temperature column; thermal compensation "
                        "needs one (columns are: " + ", ".join(run.columns or run.axes)
                        + "); name it with --temperature-column")
    gyro = run.axis(axis)
    name = axis if isinstance(axis, str) else run.axes[int(axis)]
    temp = np.asarray(run.temperature, dtype=float)
    fs = run.fs_hz
    notes: list[str] = []
    gsplit = tsplit = kal = None
    arma_name = ""
    gyro_used, temp_used = gyro, temp
    if model is None:
        prep = _prepare_fit_run(run, axis, emd=emd, arma_model=arma_model,
                                measurement_noise=measurement_noise)
        gsplit, tsplit, kal, arma_name = prep.gyro_split, prep.temp_split, prep.kalman, prep.arma
        gyro_used, temp_used = prep.gyro, prep.temp
        notes.extend(prep.notes)
        gyros, temps, rates = [prep.gyro], [prep.temp], [
            temperature_rate(prep.temp, fs_hz=fs, smoothing_s=dT_smoothing_s)]
        for i, extra in enumerate(calibration):
            if not isinstance(extra, Run):
                raise DataError(f"calibration[{i}] must be a fogts Run, got "
                                f"{type(extra).__name__}")
            if extra.temperature is None:
                raise DataError(f"calibration run {extra.source!r} has no temperature column")
            if abs(extra.fs_hz - fs) > 1e-6 * fs:
                raise DataError(f"calibration run {extra.source!r} is sampled at "
                                f"{extra.fs_hz:g} Hz, the run at {fs:g} Hz; they must match")
            if extra.units != run.units:
                raise DataError(f"calibration run {extra.source!r} is in {extra.units}, the run "
                                f"in {run.units}; they must match")
            p2 = _prepare_fit_run(extra, axis, emd=emd, arma_model=arma_model,
                                  measurement_noise=measurement_noise)
            gyros.append(p2.gyro)
            temps.append(p2.temp)
            rates.append(temperature_rate(p2.temp, fs_hz=fs, smoothing_s=dT_smoothing_s))
        if calibration:
            notes.append(f"thermal model fitted on {1 + len(calibration)} runs "
                         "(ΔT computed run by run)")
        tail = max(1, gyro_used.size // 20)
        model = fit_thermal(np.concatenate(gyros), np.concatenate(temps), fs_hz=fs, terms=terms,
                            dT_smoothing_s=dT_smoothing_s, units=run.units, errors=errors,
                            temperature_rate_degC_s=np.concatenate(rates),
                            t_ref_degC=float(np.mean(temp_used[-tail:])))
    elif not isinstance(model, ThermalModel):
        raise DataError(f"model must be a ThermalModel or None, got {type(model).__name__}")
    comp = compensate(replace(run, temperature=temp_used), model, axis=axis)
    comp = replace(comp, temperature=run.temperature)
    comp_rate = comp.axis(axis)
    before = bias_stability(gyro, fs_hz=fs, average_s=average_s, units=run.units)
    after = bias_stability(comp_rate, fs_hz=fs, average_s=average_s, units=run.units)
    return StartupCompensation(run=comp, model=model, gyro_split=gsplit, temperature_split=tsplit,
                               kalman=kal, arma_model=arma_name, gyro_used=np.asarray(gyro_used),
                               temperature_used=np.asarray(temp_used), raw_rate=gyro,
                               before=before, after=after, axis=name, notes=tuple(notes))
