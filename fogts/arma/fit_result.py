"""One fitted ARMA(p, q) model in the units of its series: :class:`ArmaFit`.

Sign convention (statsmodels):
x_t = phi_1 x_{t-1} + ... + phi_p x_{t-p} + a_t + theta_1 a_{t-1} + ... + theta_q a_{t-q}.
Parameter names are statsmodels' (``ar.L1``.., ``ma.L1``.., ``sigma2``, and ``mean`` when the mean
was estimated); the information criteria count sigma2 (and the mean) as parameters
(k = p + q + 1, or p + q + 2), as statsmodels, gretl and R do.
"""

from __future__ import annotations

import copy
import math
from dataclasses import dataclass, field
from typing import Any

import numpy as np
import pandas as pd

from fogts._typing import FloatArray
from fogts.arma.blockwise import BLOCKWISE_MIN_N, mean_of
from fogts.arma.likelihood import ExactLikelihood
from fogts.tables import Column, Table, TableView

__all__ = ["ArmaFit", "coefficient_text", "criteria", "fitted_series", "model_name", "param_lines",
           "param_names"]


def model_name(p: int, q: int) -> str:
    """Conventional name of an ARMA(p, q) model: ``"AR(p)"``, ``"MA(q)"`` or ``"ARMA(p,q)"``."""
    if q == 0:
        return f"AR({p})"
    if p == 0:
        return f"MA({q})"
    return f"ARMA({p},{q})"


def param_names(p: int, q: int) -> list[str]:
    """statsmodels' parameter names of ARIMA(p, 0, q) with ``trend="n"``."""
    return ([f"ar.L{i}" for i in range(1, p + 1)] + [f"ma.L{j}" for j in range(1, q + 1)]
            + ["sigma2"])


def param_lines(params: dict[str, float], bse: dict[str, float]) -> list[str]:
    """One summary line per parameter: its estimate and standard error."""
    return [f"  {k:>8s} = {v: .6g}  (se {bse.get(k, math.nan):.3g})" for k, v in params.items()]


@dataclass(frozen=True, repr=False)
class ArmaFit(TableView):
    """One fitted ARMA(p, q) candidate, in the units of the input series.

    The fit is done on ``x / scale`` (when ``standardized``) and transformed back:
    AR and MA coefficients are scale-free, ``sigma2`` is multiplied by ``scale**2`` and the
    log-likelihood of the original series is ``llf_std - nobs * log(scale)``.

    ``resid`` (the innovations a_t, as long as the series) is normally stored.  A ``"fast"``
    fit may instead hold only a reference to the series it was fitted on (``select_arma``
    does this for every candidate but the selected one, to keep one series-length array per
    selection): ``resid`` is then recomputed on each access from the parameters and that
    series by the same exact-innovations code the fit used, so it is bit-identical to the
    stored array.  Keep a reference (``a = fit.resid``) when using it repeatedly.
    """

    p: int
    q: int
    name: str
    params: dict[str, float]
    bse: dict[str, float]
    resid: FloatArray = field(repr=False)
    llf: float
    aic: float
    bic: float
    hqic: float
    aicc: float
    nobs: int
    sigma2: float
    converged: bool
    warnings: tuple[str, ...]
    scale: float
    standardized: bool
    method: str
    n_iter: int | None
    #: Covariance of the AR and MA coefficients (phi_1..phi_p, theta_1..theta_q; scale-free):
    #: that block of the inverse observed information (NaN where it is singular); None if
    #: not computed.  :func:`fogts.arma.redundancy.common_factor` tests a shared root with it.
    coef_cov: FloatArray | None = field(default=None, repr=False, compare=False)

    @property
    def ar(self) -> FloatArray:
        """AR coefficients phi_1..phi_p (statsmodels sign)."""
        return np.array([self.params[f"ar.L{i}"] for i in range(1, self.p + 1)], dtype=float)

    @property
    def ma(self) -> FloatArray:
        """MA coefficients theta_1..theta_q (statsmodels sign: + theta_1 a_{t-1})."""
        return np.array([self.params[f"ma.L{j}"] for j in range(1, self.q + 1)], dtype=float)

    @property
    def mean(self) -> float | None:
        """The mean estimated in the likelihood (``fit_arma(..., mean=True)``), else None."""
        return self.params.get("mean")

    @property
    def k_params(self) -> int:
        """Number of estimated parameters, sigma2 (and the mean) included (as statsmodels
        counts them)."""
        return self.p + self.q + 1 + ("mean" in self.params)

    def equation(self, digits: int = 6) -> str:
        """The fitted model written out, e.g. ``x_t = 0.5 x_{t-1} + a_t - 0.3 a_{t-1}``; with
        an estimated mean m, in y_t = x_t - m."""
        v = "x" if self.mean is None else "y"
        terms = []
        for i, c in enumerate(self.ar, start=1):
            terms.append((c, f"{v}_{{t-{i}}}"))
        out = f"{v}_t = "
        first = True
        for c, sym in terms:
            out += (f"{coefficient_text(c, digits)} {sym}" if first
                    else f" {'-' if c < 0 else '+'} {coefficient_text(abs(c), digits)} {sym}")
            first = False
        out += "a_t" if first else " + a_t"
        for j, c in enumerate(self.ma, start=1):
            out += f" {'-' if c < 0 else '+'} {coefficient_text(abs(c), digits)} a_{{t-{j}}}"
        if self.mean is not None:
            out += f",  y_t = x_t {'-' if self.mean >= 0 else '+'} {abs(self.mean):.{digits}g}"
        return out + f",  var(a_t) = {self.sigma2:.{digits}g}"

    def to_dict(self) -> dict[str, Any]:
        """JSON-safe dictionary with stable keys (the residual series is not included)."""
        return {
            "model": self.name,
            "p": self.p,
            "q": self.q,
            "params": {k: float(v) for k, v in self.params.items()},
            "bse": {k: float(v) for k, v in self.bse.items()},
            "llf": float(self.llf),
            "aic": float(self.aic),
            "bic": float(self.bic),
            "hqic": float(self.hqic),
            "aicc": float(self.aicc),
            "nobs": int(self.nobs),
            "sigma2": float(self.sigma2),
            "converged": bool(self.converged),
            "warnings": list(self.warnings),
            "scale": float(self.scale),
            "standardized": bool(self.standardized),
            "method": self.method,
            "n_iter": None if self.n_iter is None else int(self.n_iter),
        }

    def to_frame(self) -> pd.DataFrame:
        """Parameter table: one row per parameter with its estimate and standard error."""
        names = list(self.params)
        return pd.DataFrame({"param": names,
                             "estimate": [self.params[k] for k in names],
                             "bse": [self.bse.get(k, math.nan) for k in names]}).set_index("param")

    # -------------------------------------------------------------- notebook view
    def _view_table(self) -> Table:
        """The parameters with their standard errors, the criteria in the caption."""
        rows = [(k, v, self.bse.get(k)) for k, v in self.params.items()]
        return Table.build(
            f"{self.name}: {self.equation()}",
            (Column("parameter", numeric=False), Column("value", digits=6),
             Column("± stderr", digits=3)), rows,
            caption=f"n = {self.nobs}; llf = {self.llf:.6g}, AIC = {self.aic:.6g}, "
                    f"BIC = {self.bic:.6g}" + ("" if self.converged else "; NOT converged"))

    def _view_headline(self) -> str:
        return f"{self.name}, n = {self.nobs}, AIC = {self.aic:.6g}"

    def summary(self) -> str:
        """Human-readable summary: the equation, the parameter table and the criteria."""
        lines = [f"{self.name} fitted by exact Gaussian ML ({self.method}), n = {self.nobs}"]
        if self.standardized:
            lines.append(f"  fitted on x / {self.scale:.6g}; reported in the original units")
        lines.append("  " + self.equation())
        lines += param_lines(self.params, self.bse)
        lines.append(f"  llf = {self.llf:.6f}  aic = {self.aic:.4f}  bic = {self.bic:.4f}  "
                     f"hqic = {self.hqic:.4f}  aicc = {self.aicc:.4f}")
        if not self.converged:
            lines.append("  NOT CONVERGED")
        lines.extend(f"  warning: {w}" for w in self.warnings)
        return "\n".join(lines)

    def _without_resid(self, x: FloatArray) -> ArmaFit:
        """A copy that does not store ``resid`` but recomputes it from ``x`` on access.

        ``x`` must be the float64 series this fit was fitted on (in the original units).  Only
        ``"fast"`` fits can recompute their innovations bit for bit (a ``"statsmodels"`` fit
        comes from statsmodels' Kalman filter): any other fit is returned unchanged, and so
        is the fit when ``x`` is not a float64 array of its length.
        """
        if (self.method != "fast" or not isinstance(x, np.ndarray) or x.dtype != np.float64
                or x.shape != (self.nobs,)):
            return self
        out = copy.copy(self)
        object.__setattr__(out, "resid", None)
        object.__setattr__(out, _RESID_SOURCE, x)
        return out

    def _with_resid(self) -> ArmaFit:
        """A copy that stores ``resid`` (computed once if this fit recomputes it)."""
        if self.__dict__.get(_RESID_STORE) is not None:
            return self
        out = copy.copy(self)
        object.__setattr__(out, "resid", self.resid)
        out.__dict__.pop(_RESID_SOURCE, None)
        return out


_RESID_STORE = "_resid"           # instance-dict key of the stored innovations
_RESID_SOURCE = "_resid_source"   # instance-dict key of the series to recompute them from


class _Innovations:
    """Data descriptor behind ``ArmaFit.resid``: the stored array, or a recomputation.

    Installed on the class after ``@dataclass`` has made ``resid`` an ordinary field (its
    ``__init__``, ``repr=False``, ``fields()`` and ``replace()`` are unchanged: the generated
    ``__init__`` stores through ``__set__``).  See :class:`ArmaFit` for when it recomputes.
    """

    def __get__(self, obj: ArmaFit | None, objtype: type | None = None) -> Any:
        if obj is None:
            return self
        stored = obj.__dict__.get(_RESID_STORE)
        if stored is not None:
            return stored
        x = obj.__dict__.get(_RESID_SOURCE)
        if x is None:
            raise AttributeError("this ArmaFit holds neither its innovations nor the series "
                                 "to recompute them from")
        return _exact_innovations(x, obj)

    def __set__(self, obj: ArmaFit, value: FloatArray | None) -> None:
        obj.__dict__[_RESID_STORE] = value


setattr(ArmaFit, "resid", _Innovations())  # noqa: B010  (mypy keeps the plain field type)


def fitted_series(x: FloatArray, scale: float, standardized: bool,
                  mean: bool) -> tuple[FloatArray, float]:
    """The series the likelihood sees: ``x / scale`` (if ``standardized``) and, with a mean,
    minus its sample mean (the restricted likelihood does not depend on a constant
    subtracted first; removing it keeps the GLS correction small), and that sample mean."""
    xs = x / scale if standardized else x
    if not mean:
        return xs, 0.0
    offset = float(np.mean(xs))
    if xs is x:
        return x - offset, offset
    xs -= offset          # in place on the scaled copy: no second series-length array
    return xs, offset


def _exact_innovations(x: FloatArray, fit: ArmaFit) -> FloatArray:
    """The innovations of a ``"fast"`` fit, recomputed exactly as ``fit_arma`` made them.

    Same standardisation (``x / scale``, minus the same sample mean), formed block by block
    as the fit formed it, same exact likelihood evaluation (:meth:`ExactLikelihood.evaluate`
    at the fitted coefficients, which are stored as the very float64 values the optimiser
    ended on) and the same back-scaling in place, so the result is bit-identical to the
    array the fit returned, and the only series-length array made.
    """
    mean = fit.mean is not None
    offsets: tuple[float, ...] = ()
    if mean:
        scale = fit.scale if fit.standardized else 1.0
        offsets = (mean_of(x, scale, 0.0) if x.shape[0] > BLOCKWISE_MIN_N
                   else float(np.mean(x / fit.scale if fit.standardized else x)),)
    model = ExactLikelihood(x, fit.p, fit.q, mean=mean,
                            scale=fit.scale if fit.standardized else 1.0, offsets=offsets)
    with np.errstate(over="raise", invalid="raise", divide="raise", under="ignore"):
        e = model.innovations(model.evaluate(fit.ar, fit.ma))
    e *= fit.scale
    return e


def criteria(llf: float, k: int, n: int) -> tuple[float, float, float, float]:
    """AIC, BIC, HQIC and AICc as statsmodels defines them (k counts sigma2)."""
    aic = -2.0 * llf + 2.0 * k
    bic = -2.0 * llf + k * math.log(n)
    hqic = -2.0 * llf + 2.0 * k * math.log(math.log(n))
    aicc = aic + 2.0 * k * (k + 1) / (n - k - 1) if n - k - 1 > 0 else math.inf
    return aic, bic, hqic, aicc


def coefficient_text(c: float, digits: int) -> str:
    """``c`` to ``digits`` significant digits, with more where that would print a
    coefficient near a unit root as exactly 1 (0.99996 as "0.99996", not "1")."""
    text = f"{c:.{digits}g}"
    while abs(float(text)) == 1.0 and abs(c) != 1.0 and digits < 17:
        digits += 1
        text = f"{c:.{digits}g}"
    return text
