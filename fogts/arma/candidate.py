"""One ARMA(p, q) candidate of a selection: its fit, residual checks and redundancy flags."""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any, Literal

import numpy as np
import pandas as pd

from fogts._typing import FloatArray
from fogts.arma.fit_result import ArmaFit, param_lines
from fogts.arma.predict import Prediction, one_step_prediction, predict_arma, prediction_summary
from fogts.arma.redundancy import RedundancyFlag
from fogts.arma.roots import Roots, unit_circle_root
from fogts.arma.whiteness import ResidualDiagnostics
from fogts.errors import ModelFitError
from fogts.io.run import RegularTime
from fogts.preprocess.demeaned import Demeaned, HeldSeries, held

__all__ = ["Candidate"]


def _fit_number(name: str, what: str) -> property:
    """A :class:`Candidate` property that reads the number ``name`` of its fit."""

    def read(self: Candidate) -> float:
        return math.nan if self.fit is None else float(getattr(self.fit, name))

    return property(read, doc=f"{what} (``fit.{name}``); NaN for a failed fit.")


@dataclass(frozen=True)
class Candidate:
    """One ARMA(p, q) candidate: its fit, residual checks and redundancy flags.

    Attributes
    ----------
    model : str
        ``"AR(1)"``, ``"ARMA(2,1)"``, ...
    p, q : int
    status : {"ok", "failed"}
    reason : str or None
        Why the fit failed.
    rank : int or None
        1 = selected; None for a failed fit.
    criterion : str
        The ranking criterion (``"aic"``, ...).
    fit : ArmaFit or None
        The fit (parameters, standard errors, likelihood, criteria, innovations, method,
        scale); None for a failed fit.  Its numbers are also properties of the candidate:
        ``params``, ``bse`` (empty for a failed fit), ``llf``, ``aic``, ``bic``, ``hqic``,
        ``aicc``, ``sigma2`` (NaN for a failed fit) and ``converged``.
    roots : Roots or None
    diagnostics : ResidualDiagnostics or None
    flags : tuple of RedundancyFlag
    warnings : tuple of str
        Convergence and numerical warnings of the fit.
    data, index, time
        The fitted series, its index and time axis (for :meth:`predict`; a regular time
        axis may be held as a :class:`~fogts.io.run.RegularTime`, formed by ``predict``, and
        a long demeaned series as a :class:`~fogts.preprocess.demeaned.Demeaned`, formed
        on first access of ``data``).
    """

    model: str
    p: int
    q: int
    status: Literal["ok", "failed"]
    reason: str | None
    rank: int | None
    criterion: str
    fit: ArmaFit | None = field(compare=False)
    roots: Roots | None
    diagnostics: ResidualDiagnostics | None
    flags: tuple[RedundancyFlag, ...]
    warnings: tuple[str, ...]
    data: FloatArray | None = field(default=None, repr=False, compare=False)
    index: pd.Index | None = field(default=None, repr=False, compare=False)
    time: FloatArray | RegularTime | None = field(default=None, repr=False, compare=False)

    @property
    def ok(self) -> bool:
        return self.status == "ok"

    @property
    def name(self) -> str:
        """Alias of ``model`` (the name ArmaFit uses)."""
        return self.model

    @property
    def params(self) -> dict[str, float]:
        """statsmodels names (``ar.L1``, ``ma.L1``, ``sigma2``), original units; {} if failed."""
        return {} if self.fit is None else self.fit.params

    @property
    def bse(self) -> dict[str, float]:
        """Standard errors of ``params``; {} for a failed fit."""
        return {} if self.fit is None else self.fit.bse

    llf = _fit_number("llf", "Log-likelihood")
    aic = _fit_number("aic", "Akaike information criterion")
    bic = _fit_number("bic", "Bayesian information criterion")
    hqic = _fit_number("hqic", "Hannan-Quinn information criterion")
    aicc = _fit_number("aicc", "Small-sample corrected AIC")
    sigma2 = _fit_number("sigma2", "Innovation variance (original units squared)")

    @property
    def converged(self) -> bool:
        return self.fit is not None and self.fit.converged

    @property
    def white(self) -> bool:
        """True when the fit succeeded and all three residual checks pass."""
        return self.diagnostics is not None and self.diagnostics.white

    @property
    def criterion_value(self) -> float:
        return float(getattr(self, self.criterion))

    @property
    def ar(self) -> FloatArray:
        return np.zeros(0) if self.fit is None else self.fit.ar

    @property
    def ma(self) -> FloatArray:
        return np.zeros(0) if self.fit is None else self.fit.ma

    @property
    def resid(self) -> FloatArray | None:
        """Innovations a_t (original units), None for a failed fit.

        Stored for the selected candidate; for the others recomputed on each access from the
        parameters and the data (bit-identical to the fit's, see :class:`ArmaFit`).
        """
        return None if self.fit is None else self.fit.resid

    @property
    def rho_a2(self) -> float:
        return self.diagnostics.rho_a2.value if self.diagnostics else math.nan

    @property
    def rho_ax3(self) -> float:
        return self.diagnostics.rho_ax3.value if self.diagnostics else math.nan

    @property
    def notes(self) -> str:
        """Short notes for the candidate table: a failed fit, an MA root on the unit circle
        (within 1/n), nearly cancelling AR/MA roots, a common AR/MA factor that cannot be
        ruled out (the reduced model and the Wald statistic), parameters that are not
        significant, no convergence."""
        if not self.ok:
            return f"fit failed: {self.reason}"
        notes = []
        if (self.roots is not None and self.fit is not None
                and unit_circle_root(self.roots.ma_inverse, self.fit.nobs) is not None):
            notes.append("MA root on the unit circle (not invertible)")
        if self.flagged("near_cancellation"):
            notes.append("AR/MA roots nearly cancel")
        for f in self.flagged("common_factor"):
            z = f.details["z"]
            notes.append(f"may reduce to {f.details['reduced']} (common-factor "
                         + (f"|z| = {abs(z):.2f} < {f.details['critical']:g})" if math.isfinite(z)
                            else "z undefined)"))
        insignificant = [f.details["param"] for f in self.flagged("insignificant")]
        if insignificant:
            notes.append(f"{', '.join(insignificant)} not significant")
        if not self.converged:
            notes.append("did not converge")
        return "; ".join(notes)

    def flagged(self, kind: str) -> tuple[RedundancyFlag, ...]:
        return tuple(f for f in self.flags if f.kind == kind)

    def equation(self, digits: int = 4) -> str:
        """The fitted model written out with its numbers and signs (statsmodels convention).

        Example: ``x_t = 0.512 x_{t-1} + a_t + 0.301 a_{t-1},  var(a_t) = 0.0012``.
        """
        if self.fit is None:
            return f"{self.model}: not fitted ({self.reason})"
        return self.fit.equation(digits)

    def predict(self, x: Any = None, *, time: Any = None) -> Prediction:
        """One-step-ahead prediction of the drift.

        Without ``x``: on the fitted series, from the fit's exact innovations (equal to
        statsmodels' ``get_prediction()``), keeping the input's index and time.  With ``x``
        (new, demeaned data of the same sensor): conditional prediction by
        :func:`fogts.arma.predict.predict_arma`.
        """
        if not self.ok or self.fit is None:
            raise ModelFitError(f"{self.model} was not fitted ({self.reason}); it cannot predict")
        if x is not None:
            return predict_arma(x, ar=self.ar, ma=self.ma, model=self.model, time=time)
        assert self.data is not None
        time = self.time.array() if isinstance(self.time, RegularTime) else self.time
        return one_step_prediction(self.data, self.fit.resid, model=self.model,
                                   index=self.index, time=time)

    def prediction_summary(self) -> dict[str, Any]:
        """``predict().to_dict()`` on the fitted series, without forming the prediction's
        series-length arrays (:func:`fogts.arma.predict.prediction_summary`)."""
        data = held(self, "data")
        if not self.ok or self.fit is None or data is None:
            raise ModelFitError(f"{self.model} was not fitted ({self.reason}); it cannot predict")
        # an unformed demeaned series: the variance of the input (the same, up to rounding)
        observed = data.raw if isinstance(data, Demeaned) else data
        return prediction_summary(observed, self.fit.resid, model=self.model)

    def to_dict(self) -> dict[str, Any]:
        """The DESIGN.md candidate record (plus ``hqic``, ``aicc``, ``reason``, ``flags`` ...)."""
        d = self.diagnostics
        fit = self.fit
        return {
            "model": self.model, "p": self.p, "q": self.q, "status": self.status,
            "reason": self.reason, "rank": self.rank,
            "aic": self.aic, "bic": self.bic, "hqic": self.hqic, "aicc": self.aicc,
            "llf": self.llf, "sigma2": self.sigma2,
            "params": dict(self.params), "bse": dict(self.bse),
            "rho_a2": d.rho_a2.value if d else None,
            "rho_ax3": d.rho_ax3.value if d else None,
            "rho_band": d.band if d else None,
            "rho_a2_pass": d.rho_a2.passed if d else None,
            "rho_ax3_pass": d.rho_ax3.passed if d else None,
            "ljung_box": [lb.to_dict() for lb in d.ljung_box] if d else [],
            "white": self.white,
            "not_white_reasons": list(d.reasons) if d else [],
            "resid_mean": d.mean if d else None,
            "resid_variance": d.variance if d else None,
            "roots": self.roots.to_dict() if self.roots else None,
            "flags": [f.to_dict() for f in self.flags],
            "warnings": list(self.warnings),
            "converged": self.converged,
            "equation": self.equation() if fit is not None else None,
            "fit": None if fit is None else {"method": fit.method, "n_iter": fit.n_iter,
                                             "standardized": fit.standardized,
                                             "scale": fit.scale},
        }

    def to_frame(self) -> pd.DataFrame:
        """Parameter table: estimate, standard error and t-value per parameter."""
        names = list(self.params)
        est = np.array([self.params[k] for k in names], dtype=float)
        se = np.array([self.bse.get(k, math.nan) for k in names], dtype=float)
        with np.errstate(divide="ignore", invalid="ignore"):
            t = est / se
        return pd.DataFrame({"estimate": est, "bse": se, "t": t},
                            index=pd.Index(names, name="param"))

    def summary(self) -> str:
        if not self.ok:
            return f"{self.model}: FAILED ({self.reason})"
        lines = [f"{self.model} (rank {self.rank}, {self.criterion} = "
                 f"{self.criterion_value:.4f}): {self.equation()}"]
        lines += param_lines(self.params, self.bse)
        if self.diagnostics is not None:
            lines.append("  " + self.diagnostics.summary())
        lines += [f"  flag: {f.message}" for f in self.flags]
        lines += [f"  warning: {w}" for w in self.warnings]
        return "\n".join(lines)


setattr(Candidate, "data", HeldSeries("data"))  # noqa: B010  (formed on first access)
