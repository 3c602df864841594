"""The temperature-drift model of a gyro: its terms, the temperature rate, and the fitted model.

The start-up drift of the gyro bias is a linear function of six regressors built from the
temperature T (°C) and its rate of change ΔT (°C/s):

    D = a·T·ΔT + b·T² + c·T + d·ΔT² + e·ΔT + f

The temperature rate is the first derivative of a Savitzky–Golay fit (quadratic, window
``dT_smoothing_s``) of the temperature: temperature sensors are quantized, and a raw
difference is mostly noise.  :func:`~fogts.startup.thermal_fit.fit_thermal` estimates the
coefficients; :class:`ThermalModel` holds them and evaluates, prints and saves the model.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from typing import Any, Literal, get_args

import numpy as np
import pandas as pd
from scipy.signal import savgol_filter

from fogts._typing import FloatArray
from fogts._validate import check_positive, to_float_array
from fogts.errors import DataError
from fogts.tables import Column, Table, TableView
from fogts.units import parse_rate_unit

__all__ = ["DEFAULT_DT_SMOOTHING_S", "ERROR_MODELS", "TERM_LETTERS", "THERMAL_TERMS",
           "ThermalModel", "design_matrix", "temperature_rate"]

ThermalTerm = Literal["T*dT", "T2", "T", "dT2", "dT", "1"]
THERMAL_TERMS: tuple[str, ...] = get_args(ThermalTerm)
#: Error models of the fit: GLS with AR errors, OLS with HAC standard errors, plain OLS.
ErrorModel = Literal["ar", "hac", "ols"]
ERROR_MODELS: tuple[str, ...] = get_args(ErrorModel)
#: Letter of each term in D = a·T·ΔT + b·T² + c·T + d·ΔT² + e·ΔT + f.
TERM_LETTERS: dict[str, str] = {"T*dT": "a", "T2": "b", "T": "c", "dT2": "d", "dT": "e", "1": "f"}
#: Default Savitzky-Golay window for the temperature rate.
DEFAULT_DT_SMOOTHING_S = 60.0

_ERROR_TEXT = {"ar": "GLS with AR errors", "hac": "OLS, HAC standard errors", "ols": "OLS"}


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
    """Regressor columns of the drift model, one per term, for T (°C) and ΔT (°C/s).

    Examples
    --------
    >>> design_matrix(np.array([20.0]), np.array([0.1]), ["T*dT", "T2", "1"]).tolist()
    [[2.0, 400.0, 1.0]]
    """
    cols = {"T*dT": temp * dtemp, "T2": temp * temp, "T": temp, "dT2": dtemp * dtemp,
            "dT": dtemp, "1": np.ones_like(temp)}
    return np.column_stack([cols[t] for t in terms]) if terms else np.empty((temp.size, 0))


@dataclass(frozen=True, repr=False)
class ThermalModel(TableView):
    """A fitted temperature-drift model ``D = sum_j coef_j * term_j(T, ΔT)``.

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
        Reference temperature: :func:`~fogts.startup.compensation.compensate` removes
        ``D(T, ΔT) - D(t_ref, 0)``.
    temperature_range_degC : tuple of float
        Min and max temperature in the fit data (the model's domain).
    errors : str
        Error model of the fit: ``"ar"`` (GLSAR), ``"hac"`` or ``"ols"``.
    error_params : dict
        ``{"ar": [...]}`` (the fitted AR coefficients of the error) for ``"ar"``,
        ``{"maxlags": L}`` for ``"hac"``, ``{}`` for ``"ols"``.
    n : int
        Samples fitted.
    collinearity : dict
        Variance inflation factors and condition number of the fitted design
        (:func:`~fogts.startup.thermal_identification.collinearity`), recorded by
        :func:`~fogts.startup.startup_workflow.startup_compensation`; empty from
        :func:`~fogts.startup.thermal_fit.fit_thermal` alone (it is timed against plain OLS
        and its cross-validation folds need no diagnostics) and for older saved models.
    identification_note : str or None
        Set when the coefficients are not separately identified (only the drift curve
        along the fit run's warm-up path is;
        :func:`~fogts.startup.thermal_identification.identification_note`), or when the
        likelihood-ratio test does not find the fitted model significant
        (:func:`~fogts.startup.thermal_identification.significance_note`): the model
        should not be reused on another ambient or warm-up (another run).
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
    collinearity: dict[str, Any] = field(default_factory=dict)
    identification_note: str | None = None

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
            "model": "fogts-thermal-drift",
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
            "collinearity": _json_collinearity(self.collinearity),
            "identification_note": self.identification_note,
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
                collinearity=dict(data.get("collinearity") or {}),
                identification_note=(None if data.get("identification_note") is None
                                     else str(data["identification_note"])),
            )
        except (KeyError, TypeError, AttributeError) as exc:
            raise DataError(f"malformed thermal model: {exc!r}") from None

    def to_frame(self) -> pd.DataFrame:
        """One row per fitted term: letter, value, stderr."""
        return pd.DataFrame({"term": list(self.terms),
                             "letter": [TERM_LETTERS[t] for t in self.terms],
                             "value": [self.coefficients[t] for t in self.terms],
                             "stderr": [self.stderr[t] for t in self.terms]}).set_index("term")

    # -------------------------------------------------------------- notebook view
    def _view_table(self) -> Table:
        rows: list[tuple[Any, ...]] = [(t, TERM_LETTERS[t], self.coefficients[t],
                                        self.stderr[t]) for t in self.terms]
        rows += [(t, "dropped", why, None) for t, why in self.dropped.items()]
        return Table.build(
            f"Thermal drift model: {self.equation()}",
            (Column("term", numeric=False), Column("letter", numeric=False),
             Column("value", digits=6), Column("± stderr", digits=4)), rows,
            caption=f"R² = {self.r2:.4f}, residual std {self.residual_std:.4g} {self.units}, "
                    f"n = {self.n} at {self.fs_hz:g} Hz")

    def _view_headline(self) -> str:
        return f"{len(self.terms)} terms, R² = {self.r2:.4f}, n = {self.n}, {self.units}"

    def summary(self) -> str:
        lines = [f"Thermal drift model, n = {self.n}, fs = {self.fs_hz:g} Hz",
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
        if self.identification_note:
            lines.append(f"  {self._identification_line()}")
        return "\n".join(lines)

    def _identification_line(self) -> str:
        """The numbers behind :attr:`identification_note`, in one line (the note itself
        when it is the likelihood-ratio test's)."""
        from fogts.startup.thermal_identification import (
            NOT_SIGNIFICANT,
            T_CRITICAL,
            VIF_THRESHOLD,
            significant_terms,
        )

        if self.identification_note and self.identification_note.startswith(NOT_SIGNIFICANT):
            return self.identification_note

        diag = self.collinearity
        n_thermal = sum(t != "1" for t in self.terms)
        vif = (f"largest VIF {float(diag['max_vif']):.3g} ({diag.get('max_vif_term')}) > "
               f"{VIF_THRESHOLD:g}; " if "max_vif" in diag else "")
        return (f"coefficients not separately identified: {vif}"
                f"{len(significant_terms(self))} of {n_thermal} thermal coefficients with "
                f"|t| > {T_CRITICAL:.2f}; fitted to one warm-up path, not for reuse")


def _json_collinearity(diag: Mapping[str, Any]) -> dict[str, Any]:
    """The collinearity diagnostics with plain floats (JSON-safe)."""
    out: dict[str, Any] = {}
    for key, value in diag.items():
        if isinstance(value, Mapping):
            out[key] = {k: float(v) for k, v in value.items()}
        elif isinstance(value, (int, float, np.floating)) and not isinstance(value, bool):
            out[key] = float(value)
        else:
            out[key] = value
    return out


def _nan_float(v: Any) -> float:
    return math.nan if v is None else float(v)
