"""The result of a noise fit: :class:`NoiseModel`, the fitted terms (:class:`NoiseTerm`,
:mod:`fogts.allan.noise_term`) with the fit's curve, statistics and read-offs.

Produced by :func:`fogts.allan.noise.fit_noise`; the term table (names, powers, units) is
:mod:`fogts.allan.terms`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any

import numpy as np
import pandas as pd

from fogts._typing import FloatArray
from fogts.allan.distributions import norm_ppf
from fogts.allan.gmwm_result import GmwmSummary
from fogts.allan.markov import ExtraTerm
from fogts.allan.ml_result import MlSummary
from fogts.allan.noise_lsq import chi2_sentence, model_error_p_value
from fogts.allan.noise_term import Z_MEASURED, NoiseTerm
from fogts.allan.readoff import FitBound, SlopeReadoff
from fogts.allan.readout import MIN_EDF_FOR_MINIMUM
from fogts.allan.terms import TERM_POWER, term_rows
from fogts.choices import OutputUnits
from fogts.errors import DataError
from fogts.tables import Column, Table, TableView
from fogts.units import term_in_units, term_unit

__all__ = ["NoiseModel", "NoiseTerm"]


@dataclass(frozen=True, repr=False)
class NoiseModel(TableView):
    """IEEE-952 noise terms fitted to one Allan-variance curve.

    Attributes
    ----------
    terms : tuple of NoiseTerm
        The fitted terms, in the order Q, N, B, K, R (only those requested).
    confidence : float
        Level of every term's interval.
    method : str
        ``"wls"`` (EDF-weighted IRLS, the default), ``"gls"`` (full model covariance),
        ``"ols"`` (unweighted, the traditional fit; for comparison) or ``"gmwm"`` (the
        generalized method of wavelet moments, :mod:`fogts.allan.gmwm`; B is then the
        flicker equivalent of a Gauss-Markov sum, and :meth:`curve` the five-term curve
        with that B, while ``fitted_dev`` is the GMWM model itself) or ``"ml"`` (exact
        Gaussian maximum likelihood of the record, :mod:`fogts.allan.ml`; ``chi2``,
        ``dof`` and ``model_error`` are NaN).
    kind, units, axis : str
        From the Allan result; ``units`` is the rate unit of the curve.
    deg_per_hour_factor : float
        Multiply the curve's deviations by this to get deg/h (m/s^2 for an accelerometer:
        the unit the terms are computed from).
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
    model_error_lr : float
        The likelihood-ratio statistic of the model-error test that kept or dropped
        ``model_error`` (the 50:50 chi-bar-squared boundary test, :mod:`fogts.allan.noise_lsq`;
        its p-value is :attr:`model_error_p`); NaN when no such test was made (``ols``,
        ``gmwm``, ``ml``, or a model read back).
    stderr_method : str
        How the standard errors were obtained: the sandwich or GLS with the model
        covariance of the adev or oadev estimates, or with totdev's EDF variances and the
        oadev correlations; the EDF diagonal (correlation ignored); or the OLS residual
        variance.
    iterations : int
    converged : bool
    readoff : SlopeReadoff
    significance : float or None
        Level of the term-selection and model-error tests (None: every requested term was
        kept and the model error is the unrestricted ML estimate; always None for ols).
    excluded_tau_s : tuple of float
        Taus dropped before the fit (non-finite or non-positive deviation).
    warnings : tuple of str
        Every warning emitted by the fit.
    extra_terms : tuple of ExtraTerm
        The optional first-order Markov (``M``) and sinusoid (``S``) terms, when asked
        for (:mod:`fogts.allan.markov`); :meth:`curve` includes them.
    quantity : str
        ``"rate"`` (a gyro; terms in IEEE 952's degree units) or ``"accel"`` (an
        accelerometer; terms in :data:`fogts.units.ACCEL_TERM_UNIT`), from ``units``.
    gmwm : GmwmSummary or None
        For ``method="gmwm"``: the composite model, its Gauss-Markov components and the J
        test (:mod:`fogts.allan.gmwm_result`); None otherwise.
    ml : MlSummary or None
        For ``method="ml"`` (:func:`fogts.allan.ml.fit_noise_ml`): the state-space model,
        its Gauss-Markov components, the log-likelihood and the decimation
        (:mod:`fogts.allan.ml_result`); None otherwise.
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
    significance: float | None = None
    excluded_tau_s: tuple[float, ...] = ()
    warnings: tuple[str, ...] = ()
    _a: tuple[float, ...] = field(default=(), repr=False)
    extra_terms: tuple[ExtraTerm, ...] = ()
    quantity: str = "rate"
    gmwm: GmwmSummary | None = None
    ml: MlSummary | None = None
    model_error_lr: float = math.nan

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
    def model_error_p(self) -> float:
        """The p-value of :attr:`model_error_lr` (:func:`model_error_p_value`)."""
        return model_error_p_value(self.model_error_lr)

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
        >>> from fogts.allan.noise import fit_noise
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
        for extra in self.extra_terms:
            total += extra.avar(tau)
        return np.sqrt(total)

    # -------------------------------------------------------------- exports
    def in_units(self, name: str, units: OutputUnits = "deg") -> dict[str, Any]:
        """Term ``name``'s value, stderr, interval and 95 % upper limit in ``units``:
        ``"deg"`` (IEEE 952's degree units; an accelerometer's engineering units) or ``"si"``
        (:data:`fogts.units.TERM_SI_FACTOR`, :data:`fogts.units.ACCEL_TERM_SI_FACTOR`)."""
        t = self[name]
        scale = term_in_units(name, 1.0, units, self.quantity)
        return {"value": t.value * scale, "stderr": t.stderr * scale,
                "ci_low": t.ci_low * scale, "ci_high": t.ci_high * scale,
                "unit": t.unit if units == "deg" else term_unit(name, units, self.quantity),
                "upper_limit_95": self.upper_limit(name) * scale}

    def noise_dict(self, units: OutputUnits = "deg") -> dict[str, dict[str, Any]]:
        """Term name to ``{value, stderr, ci_low, ci_high, unit, ..., upper_limit_95}`` in
        ``units`` (the JSON ``noise``; ``upper_limit_95`` is :meth:`upper_limit`, null for a
        fitted term; ``c_coeff`` stays in deg/h-and-seconds units)."""
        return {t.name: {**t.to_dict(), **self.in_units(t.name, units)} for t in self.terms}

    def to_frame(self, units: OutputUnits = "deg") -> pd.DataFrame:
        """One row per term: value, stderr, CI and unit in ``units`` (``"deg"`` or ``"si"``),
        C_n, identifiability, status, z."""
        rows = [{"term": t.name, **{k: v for k, v in self.in_units(t.name, units).items()
                                    if k != "upper_limit_95"},
                 "c_coeff": t.c_coeff, "c_stderr": t.c_stderr, "slope": t.slope,
                 "at_bound": t.at_bound, "identifiable": t.identifiable, "status": t.status,
                 "z": t.z_score}
                for t in self.terms]
        return pd.DataFrame(rows).set_index("term")

    def to_dict(self, units: OutputUnits = "deg") -> dict[str, Any]:
        """The JSON ``noise`` block; ``units="si"`` gives the terms in SI (``output_units``)."""
        return {
            "method": self.method, "confidence": self.confidence, "kind": self.kind,
            "units": self.units, "axis": self.axis, "output_units": units,
            **({"quantity": self.quantity} if self.quantity != "rate" else {}),
            "terms": self.noise_dict(units),
            "readoff": self.readoff.to_dict(self.readoff_bounds()),
            "fit": {"n_points": int(self.tau_s.size),
                    "tau_range": [float(self.tau_s[0]), float(self.tau_s[-1])],
                    "chi2": self.chi2, "dof": self.dof, "model_error": self.model_error,
                    "iterations": self.iterations, "converged": self.converged,
                    "edf_source": self.edf_source, "stderr_method": self.stderr_method,
                    "deg_per_hour_factor": self.deg_per_hour_factor,
                    "significance": self.significance, "dropped": list(self.dropped)},
            "excluded_tau": list(self.excluded_tau_s),
            "warnings": list(self.warnings),
            **({"extra_terms": {e.name: e.to_dict() for e in self.extra_terms}}
               if self.extra_terms else {}),
            **({"gmwm": self.gmwm.to_dict()} if self.gmwm is not None else {}),
            **({"ml": self.ml.to_dict()} if self.ml is not None else {}),
        }

    def upper_limit(self, name: str, level: float = 0.95) -> float:
        """The one-sided ``level`` upper limit of a term that is only a limit
        (:attr:`NoiseTerm.is_limit`).  At zero: the interval ``[0, ci_high]`` rescaled from
        the model's two-sided ``confidence`` (its end is ``sqrt(z se)`` of the squared
        coefficient ``a``, so it scales with ``sqrt(z)``); fitted with a small z:
        ``sqrt(a + z se(a))`` in the term's units.  NaN for a measured term."""
        term = self[name]
        if not term.is_limit:
            return math.nan
        z_level = float(norm_ppf(level))
        if not term.at_bound:  # a weak fitted term: the one-sided bound of C_n^2 = a
            return math.sqrt(term.value**2 + 2.0 * z_level * term.value * term.stderr)
        z_conf = float(norm_ppf(0.5 + self.confidence / 2))
        return term.ci_high * math.sqrt(z_level / z_conf)

    def readoff_bounds(self) -> dict[str, FitBound]:
        """The fit's range of each term (degree units) that the slope read-offs are checked
        against (:func:`fogts.allan.readoff.fit_check`): the 95 % upper limit of a term the
        fit reports only as a limit, else its interval at ``confidence``."""
        pct = f"{100 * self.confidence:.1f} % interval"
        return {t.name: (FitBound(0.0, self.upper_limit(t.name), "95 % upper limit", True)
                         if t.is_limit else FitBound(t.ci_low, t.ci_high, pct, False))
                for t in self.terms}

    def describe_readoff(self, number: Any = None, units: OutputUnits = "deg") -> str:
        """The slope read-offs' sentence, each checked against the fit
        (:meth:`SlopeReadoff.describe` with :meth:`readoff_bounds`): the one wording of the
        terminal, the summary and the HTML report; ``number`` formats the values (default
        4 significant digits)."""
        fmt = number if number is not None else (lambda v: f"{v:.4g}")
        return self.readoff.describe(fmt, units, fit=self.readoff_bounds())

    def _table_note(self, term: NoiseTerm, units: OutputUnits = "deg") -> str:
        if not term.is_limit:
            return term.note
        limit = self.in_units(term.name, units)["upper_limit_95"]
        reason = term.limit_reason
        note = f"< {limit:.3g} (95 % upper limit; {reason})"
        return note + ("; not identifiable" if not term.identifiable
                       and "not identifiable" not in reason else "")

    def term_table(self, units: OutputUnits = "deg") -> Table:
        """The terms with their standard errors, intervals, units (``"deg"`` or ``"si"``),
        C_n and notes: the one definition the summary, the terminal and the HTML report
        show."""
        pct = f"{100 * self.confidence:.1f} %"
        columns = (Column("term", numeric=False), Column("name", numeric=False),
                   Column("value"), Column("± stderr", digits=3),
                   Column(f"{pct} interval"), Column("unit", numeric=False),
                   Column("C_n"), Column("note", numeric=False, wrap=True))
        shown = {t.name: self.in_units(t.name, units) for t in self.terms}
        described = term_rows(self.quantity)
        rows = [(t.name, described[t.name].description, shown[t.name]["value"],
                 shown[t.name]["stderr"], (shown[t.name]["ci_low"], shown[t.name]["ci_high"]),
                 shown[t.name]["unit"], t.c_coeff, self._table_note(t, units))
                for t in self.terms]
        fitted = (f"the record ({self.ml.n_used} samples)" if self.ml is not None
                  else f"{self.kind} on {self.tau_s.size} taus {self.tau_s[0]:.4g}.."
                       f"{self.tau_s[-1]:.4g} s")
        return Table.build(
            f"IEEE-952 noise terms of {self.axis} ({self.method.upper()} fit of {fitted}, "
            f"input in {self.units})", columns, rows,
            caption="C_n: square root of the coefficient of tau^n in sigma^2(tau) = sum C_n^2 tau^n ("
                    + ("specific force in m/s^2" if self.quantity == "accel" else "rate in deg/h")
                    + ", tau in s). The interval is formed on C_n^2 (so it is asymmetric) "
                    "and, in a least-squares fit, also covers a band-limited bias instability: "
                    "it can be wider than value ± k·stderr (k the normal quantile). Upper "
                    "limit: a term at zero, dropped, or fitted with z(C²) < "
                    f"{Z_MEASURED:g}, where z(C²) = C_n²/se(C_n²) ≈ value/(2·stderr), is not "
                    "measured (the rule is on C_n², at about 95 %); the note gives its "
                    "one-sided 95 % bound." + self._limit_in_interval(pct)
                    + " Not identifiable: the term makes up a sizeable share of the "
                    "fitted sigma^2 at too few taus of this grid to be measured.")

    def _limit_in_interval(self, pct: str) -> str:
        """Why a term whose interval excludes 0 is still only a limit (the rule asks for
        z(C²) >= 2, or it dominates only at low-EDF points); "" if none is."""
        weak = [t.name for t in self.terms if not t.at_bound and t.ci_low > 0
                and not t.z_score >= Z_MEASURED]
        low = [t.name for t in self.terms if t.low_edf_taus and t.z_score >= Z_MEASURED]
        floorless = [t.name for t in self.terms if t.no_floor and t.z_score >= Z_MEASURED
                     and not t.low_edf_taus]
        verb = "excludes" if len(weak) == 1 else "exclude"
        weaker = (f", a stricter test than a {pct} interval" if self.confidence < 0.95
                  else "")
        return ((f" {', '.join(weak)}: the {pct} interval {verb} 0, yet only a limit: the "
                 f"rule asks for z(C²) ≥ {Z_MEASURED:g}{weaker}." if weak else "")
                + (f" {', '.join(low)}: only a limit whatever its z, because it dominates the "
                   f"fitted sigma^2 only at points with EDF < {MIN_EDF_FOR_MINIMUM:g}, whose "
                   "deviations are too uncertain to measure it." if low else "")
                + (" B: only a limit whatever its z, because the curve has no floor where "
                   "its trusted points end (B is read on the flat bottom)." if floorless
                   else ""))

    # -------------------------------------------------------------- notebook view
    def _view_table(self) -> Table:
        return self.term_table()

    def _view_headline(self) -> str:
        """The fitted terms as ``N = value ± se`` or ``K < limit``, in degree units."""
        parts = [f"{t.name} < {self.upper_limit(t.name):.3g}" if t.is_limit
                 else f"{t.name} = {t.value:.4g} ± {t.stderr:.2g}" for t in self.terms]
        return f"{self.axis!r} {self.method.upper()}: " + ", ".join(parts)

    def summary(self) -> str:
        """The term table, the read-offs and the method's own account of the fit: the
        chi-square, model error and term selection of the least-squares fits, the J test
        of the GMWM, the likelihood and decimation of ML."""
        lines = [self.term_table().to_text()]
        lines.append(self.describe_readoff(lambda v: f"{v:.4e}"))
        if self.gmwm is None and self.ml is None:
            sentence = chi2_sentence(self.chi2, self.dof, self.model_error,
                                     self.model_error_lr, self.significance)
            lines.append(f"{sentence}; "
                         f"{self.iterations} iteration(s)"
                         + ("" if self.converged else " (NOT converged)")
                         + f"; edf from {self.edf_source}")
        if self.significance is not None and self.gmwm is None and self.ml is None:
            lines.append(f"term selection: one-sided tests at {100 * self.significance:g} % "
                         f"(drop if z < {norm_ppf(1 - self.significance):.3f}); dropped: "
                         + (", ".join(self.dropped) or "none"))
        lines += [e.describe() for e in self.extra_terms]
        if self.gmwm is not None:
            lines.append(self.gmwm.describe())
        if self.ml is not None:
            lines.append(self.ml.describe())
        lines += [f"warning: {w}" for w in self.warnings]
        return "\n".join(lines)



def _tau_array(tau_s: Any) -> FloatArray:
    tau = np.atleast_1d(np.asarray(tau_s, dtype=np.float64))
    if tau.ndim != 1 or not np.all(np.isfinite(tau) & (tau > 0)):
        raise DataError(f"tau_s must be finite and > 0, got {tau_s!r}")
    return tau
