"""ARMA candidate selection with residual diagnostics: the seed paper's five steps.

Seed 000 models FOG drift by time-series analysis: (1) remove the trend and the mean;
(2) read the ACF and PACF; (3) fit the admissible low-order candidates AR(1), AR(2), AR(3),
ARMA(1,1) and ARMA(2,1) and take the lowest AIC; (4) check that the residuals are white with
rho_a,2 (eq. 11) and rho_ax,3 (eq. 12); (5) predict one step ahead.  :func:`select_arma` does
steps 2-4 on a prepared series (step 1 is :func:`fogts.preprocess.prepare`) and step 5 is
``selection.best.predict()``.

Ranking rule
------------
Candidates whose fit succeeded and whose residuals are white (all three checks of
:mod:`fogts.arma.diagnostics` pass) are ranked first, by the information criterion
(ties: fewer parameters, then the order given).  The others that fitted follow, ranked the
same way.  Failed fits stay in the table with ``status="failed"``, their reason and no rank.
The selected model is rank 1.  If no candidate is white, rank 1 is still reported, a
:class:`~fogts.errors.NotWhiteWarning` is emitted and ``Selection.all_white_failed`` is True
(the CLI exits with code 1).

Redundancy (a near-cancelling AR/MA root pair, an insignificant coefficient) is flagged on
each candidate, never silently acted on: the criterion already penalises the extra
parameters, and the flags tell the reader why an over-parameterised candidate is unreliable.
"""

from __future__ import annotations

import math
import re
import warnings
from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import Any, Literal

import numpy as np
import pandas as pd

from fogts._typing import FloatArray
from fogts._validate import check_choice, check_int, check_positive, pandas_index, to_float_array
from fogts.arma.diagnostics import (
    Correlogram,
    RedundancyFlag,
    ResidualDiagnostics,
    Roots,
    arma_roots,
    correlogram,
    insignificant_terms,
    near_cancellations,
    residual_diagnostics,
)
from fogts.arma.fit import ArmaFit, FitMethod, fit_arma, min_nobs, model_name
from fogts.arma.predict import Prediction, one_step_prediction, predict_arma
from fogts.errors import (
    ConvergenceWarning,
    DataError,
    InsufficientDataError,
    ModelFitError,
    NotWhiteWarning,
)

__all__ = [
    "CRITERIA",
    "DEFAULT_FIVE",
    "MIN_SELECT_SAMPLES",
    "Candidate",
    "Criterion",
    "Selection",
    "parse_candidates",
    "select_arma",
]

Criterion = Literal["aic", "bic", "hqic", "aicc"]
CRITERIA: tuple[str, ...] = ("aic", "bic", "hqic", "aicc")
#: The seed paper's admissible candidates, as (p, q).
DEFAULT_FIVE: tuple[tuple[int, int], ...] = ((1, 0), (2, 0), (3, 0), (1, 1), (2, 1))
#: Fewest samples :func:`select_arma` accepts (also >= 2 x the largest Ljung-Box lag and
#: each candidate's own minimum).
MIN_SELECT_SAMPLES = 50
#: Largest AR or MA order a candidate may have.
MAX_ORDER = 10
#: A simpler white candidate within this many criterion units of the selected one is named in
#: the verdict (Burnham & Anderson, *Model Selection and Multimodel Inference*, 2nd ed.,
#: sec. 2.6: Delta AIC <= 2 means substantial support).
CLOSE_CALL = 2.0
#: Below this share of variance removed by the one-step prediction, the verdict says the
#: series is nearly white (the model explains almost nothing).
SMALL_PREDICTION = 0.05
#: A raw rate with at most this many distinct values (in the first QUANT_CHECK_SAMPLES) is
#: reported as quantised.
QUANT_MAX_LEVELS = 64
QUANT_CHECK_SAMPLES = 200_000

_NAME_RE = re.compile(r"^\s*(ARMA|AR|MA)\s*\(\s*(\d+)\s*(?:,\s*(\d+)\s*)?\)\s*$", re.IGNORECASE)


def _parse_one(item: Any) -> tuple[int, int]:
    if isinstance(item, str):
        m = _NAME_RE.match(item)
        if m is None:
            raise DataError(f"candidates: cannot read {item!r}; write AR(p), MA(q) or ARMA(p,q), "
                            "e.g. AR(1),ARMA(2,1)")
        kind, a, b = m.group(1).upper(), int(m.group(2)), m.group(3)
        if kind == "ARMA":
            if b is None:
                raise DataError(f"candidates: {item!r} needs two orders, e.g. ARMA(1,1)")
            p, q = a, int(b)
        elif b is not None:
            raise DataError(f"candidates: {item!r} takes one order, e.g. {kind}(1)")
        else:
            p, q = (a, 0) if kind == "AR" else (0, a)
    elif isinstance(item, Sequence) and len(item) == 2:
        p = check_int("candidates (p)", item[0], minimum=0, maximum=MAX_ORDER)
        q = check_int("candidates (q)", item[1], minimum=0, maximum=MAX_ORDER)
    else:
        raise DataError(f"candidates: each entry must be a name like 'ARMA(1,1)' or a (p, q) "
                        f"pair, got {item!r}")
    if p + q == 0:
        raise DataError(f"candidates: {item!r} has p + q = 0; white noise is not a candidate")
    if p > MAX_ORDER or q > MAX_ORDER:
        raise DataError(f"candidates: {item!r} has an order above {MAX_ORDER}")
    return p, q


def parse_candidates(spec: Any = None) -> tuple[tuple[int, int], ...]:
    """Candidate orders from names or (p, q) pairs.

    Parameters
    ----------
    spec : str, sequence or None
        ``None`` gives :data:`DEFAULT_FIVE`; a string like ``"AR(1),ARMA(1,1),MA(2)"``
        (case-insensitive, commas inside parentheses allowed); or a sequence of such names
        or of (p, q) pairs.

    Returns
    -------
    tuple of (p, q)

    Examples
    --------
    >>> parse_candidates("AR(1), ARMA(2,1)")
    ((1, 0), (2, 1))
    """
    if spec is None:
        return DEFAULT_FIVE
    if isinstance(spec, str):
        items: list[Any] = [s for s in re.split(r",(?![^()]*\))", spec) if s.strip()]
    elif isinstance(spec, Sequence):
        items = list(spec)
    else:
        raise DataError(f"candidates must be a string like 'AR(1),ARMA(1,1)' or a sequence, "
                        f"got {spec!r}")
    if not items:
        raise DataError(f"candidates must name at least one model, got {spec!r}")
    orders = [_parse_one(it) for it in items]
    seen: set[tuple[int, int]] = set()
    for o in orders:
        if o in seen:
            raise DataError(f"candidates lists {model_name(*o)} twice")
        seen.add(o)
    return tuple(orders)


# ----------------------------------------------------------------------------- results


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
    params, bse : dict
        statsmodels names (``ar.L1``, ``ma.L1``, ``sigma2``), original units.
    llf, aic, bic, hqic, aicc, sigma2 : float
        NaN for a failed fit.
    roots : Roots or None
    diagnostics : ResidualDiagnostics or None
    flags : tuple of RedundancyFlag
    warnings : tuple of str
        Convergence and numerical warnings of the fit.
    converged : bool
    fit : ArmaFit or None
        The underlying fit (residuals, method, scale).
    """

    model: str
    p: int
    q: int
    status: Literal["ok", "failed"]
    reason: str | None
    rank: int | None
    criterion: str
    params: dict[str, float]
    bse: dict[str, float]
    llf: float
    aic: float
    bic: float
    hqic: float
    aicc: float
    sigma2: float
    roots: Roots | None
    diagnostics: ResidualDiagnostics | None
    flags: tuple[RedundancyFlag, ...]
    warnings: tuple[str, ...]
    converged: bool
    fit: ArmaFit | None = field(default=None, repr=False, compare=False)
    data: FloatArray | None = field(default=None, repr=False, compare=False)
    index: pd.Index | None = field(default=None, repr=False, compare=False)
    time: FloatArray | None = field(default=None, repr=False, compare=False)

    @property
    def ok(self) -> bool:
        return self.status == "ok"

    @property
    def name(self) -> str:
        """Alias of ``model`` (the name ArmaFit uses)."""
        return self.model

    @property
    def white(self) -> bool:
        """True when the fit succeeded and all three residual checks pass."""
        return self.diagnostics is not None and self.diagnostics.white

    @property
    def criterion_value(self) -> float:
        return float(getattr(self, self.criterion))

    @property
    def ar(self) -> FloatArray:
        return np.array([self.params[f"ar.L{i}"] for i in range(1, self.p + 1)], dtype=float) \
            if self.ok else np.zeros(0)

    @property
    def ma(self) -> FloatArray:
        return np.array([self.params[f"ma.L{j}"] for j in range(1, self.q + 1)], dtype=float) \
            if self.ok else np.zeros(0)

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
        """One-step-ahead prediction (seed 000, Fig. 5).

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
        return one_step_prediction(self.data, self.fit.resid, model=self.model,
                                   index=self.index, time=self.time)

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
            "ljung_box": [{"lag": lb.lag, "q": lb.q, "pvalue": lb.pvalue, "df": lb.df,
                           "pass": lb.passed} for lb in d.ljung_box] if d else [],
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
        for k in self.params:
            lines.append(f"  {k:>8s} = {self.params[k]: .6g}  (se {self.bse.get(k, math.nan):.3g})")
        if self.diagnostics is not None:
            lines.append("  " + self.diagnostics.summary())
        lines += [f"  flag: {f.message}" for f in self.flags]
        lines += [f"  warning: {w}" for w in self.warnings]
        return "\n".join(lines)


@dataclass(frozen=True)
class Selection:
    """The ranked candidates, the data's correlogram and the selected model.

    Attributes
    ----------
    candidates : tuple of Candidate
        In ranked order (rank 1 first, failed fits last in the order given).
    criterion : str
    lags : tuple of int
        Ljung-Box lags.
    n : int
        Samples fitted.
    fs_hz : float or None
    units : str or None
    correlogram : Correlogram
        ACF/PACF of the data and the Box-Jenkins reading.
    selected : Candidate or None
        Rank 1 (None only if every fit failed).
    all_white_failed : bool
        No candidate left white residuals (the CLI exits with code 1).
    verdict : str
        One plain-language sentence.
    input : dict
        What was analysed (source, axis, n, fs_hz, units).
    preprocessing : dict or None
        ``Prepared.to_dict()``, or the steps taken here on raw input.
    method : str
        Fit method passed to :func:`fogts.arma.fit.fit_arma`.
    notes : tuple of str
        Remarks on the data (e.g. a quantised raw rate), also appended to ``verdict``.
    """

    candidates: tuple[Candidate, ...]
    criterion: str
    lags: tuple[int, ...]
    n: int
    fs_hz: float | None
    units: str | None
    correlogram: Correlogram
    selected: Candidate | None
    all_white_failed: bool
    verdict: str
    input: dict[str, Any]
    preprocessing: dict[str, Any] | None
    method: str = "fast"
    notes: tuple[str, ...] = ()

    @property
    def best(self) -> Candidate | None:
        """The selected candidate (rank 1); None only if every fit failed (see ``verdict``).

        ``selection.best.predict()`` gives the one-step prediction (seed 000, Fig. 5).
        """
        return self.selected

    def require_best(self) -> Candidate:
        """The selected candidate; raises ModelFitError (with every fit's reason) if none."""
        if self.selected is None:
            raise ModelFitError(self.verdict)
        return self.selected

    @property
    def exit_code(self) -> int:
        """0 if a white model was selected, 1 otherwise (DESIGN.md exit codes)."""
        return 1 if self.all_white_failed else 0

    def __getitem__(self, model: str) -> Candidate:
        key = model.replace(" ", "").upper()
        for c in self.candidates:
            if c.model.upper() == key:
                return c
        raise KeyError(f"no candidate {model!r}; candidates are "
                       f"{', '.join(c.model for c in self.candidates)}")

    def to_frame(self) -> pd.DataFrame:
        """One row per candidate in ranked order."""
        rows = []
        for c in self.candidates:
            row: dict[str, Any] = {"model": c.model, "rank": c.rank, "status": c.status,
                                   "p": c.p, "q": c.q, "llf": c.llf, "aic": c.aic, "bic": c.bic,
                                   "hqic": c.hqic, "aicc": c.aicc, "sigma2": c.sigma2,
                                   "rho_a2": c.rho_a2, "rho_ax3": c.rho_ax3}
            for lag in self.lags:
                lb = ([x for x in c.diagnostics.ljung_box if x.lag == lag]
                      if c.diagnostics else [])
                row[f"lb_p_{lag}"] = lb[0].pvalue if lb else math.nan
            row.update(white=c.white, flags="; ".join(f.message for f in c.flags),
                       reason=c.reason or "")
            rows.append(row)
        return pd.DataFrame(rows).set_index("model")

    def to_dict(self) -> dict[str, Any]:
        """The ``fogts select`` JSON: ``{"input", "preprocessing", "candidates", "selected"}``
        plus ``criterion``, ``lags``, ``correlogram``, ``verdict``, ``all_white_failed``."""
        sel = self.selected
        selected: dict[str, Any] | None = None
        if sel is not None:
            pred = sel.predict()
            selected = {"model": sel.model, "p": sel.p, "q": sel.q, "rank": sel.rank,
                        "criterion": self.criterion, "value": sel.criterion_value,
                        "white": sel.white, "equation": sel.equation(),
                        "params": dict(sel.params), "sigma2": sel.sigma2,
                        "prediction": pred.to_dict()}
        return {
            "input": dict(self.input),
            "preprocessing": self.preprocessing,
            "criterion": self.criterion,
            "lags": list(self.lags),
            "fit_method": self.method,
            "correlogram": self.correlogram.to_dict(),
            "candidates": [c.to_dict() for c in self.candidates],
            "selected": selected,
            "all_white_failed": self.all_white_failed,
            "verdict": self.verdict,
            "notes": list(self.notes),
        }

    def summary(self) -> str:
        crit = self.criterion.upper()
        lines = [f"ARMA selection by {crit} on {self.n} samples; {self.correlogram.summary()}",
                 f"{'rank':>4}  {'model':<10}{crit:>16}{'rho_a2':>10}{'rho_ax3':>10}"
                 + "".join(f"{'LB p(' + str(lag) + ')':>11}" for lag in self.lags)
                 + "  white"]
        for c in self.candidates:
            if not c.ok:
                lines.append(f"{'-':>4}  {c.model:<10}  failed: {c.reason}")
                continue
            assert c.diagnostics is not None
            lbs = "".join(f"{x.pvalue:>11.3g}" for x in c.diagnostics.ljung_box)
            lines.append(f"{c.rank:>4}  {c.model:<10}{c.criterion_value:>16.4f}"
                         f"{c.rho_a2:>+10.4f}{c.rho_ax3:>+10.4f}{lbs}  "
                         f"{'yes' if c.white else 'no'}")
        if self.selected is not None:
            lines.append(f"selected: {self.selected.equation()}")
        lines.append(self.verdict)
        return "\n".join(lines)


# ----------------------------------------------------------------------------- selection


@dataclass(frozen=True)
class _Input:
    x: FloatArray
    index: pd.Index | None
    time: FloatArray | None
    fs_hz: float | None
    units: str | None
    info: dict[str, Any]
    preprocessing: dict[str, Any] | None
    raw: FloatArray | None = None


def _unpack(x: Any, fs_hz: float | None) -> _Input:
    from fogts.io.run import Run
    from fogts.preprocess.prepare import Prepared

    if isinstance(x, Run):
        raise DataError("x is a Run; prepare one axis first: select_arma(prepare(run, "
                        "detrend=...))")
    if isinstance(x, Prepared):
        run = x.run
        info = {"source": run.source if run is not None else None, "axis": x.axis,
                "units": x.units, "n_input": x.n_input, "n": x.n, "fs_hz": x.fs_hz}
        raw = None   # the quantisation check only applies to undecimated data
        if run is not None and x.axis in run.axes and x.decimate == 1:
            raw = run.axis(x.axis)
        return _Input(x.x, x.index, x.time, x.fs_hz, x.units, info, x.to_dict(), raw)
    if isinstance(x, pd.DataFrame):
        raise DataError("x must be one series (Prepared, ndarray or Series), got a DataFrame")
    index = pandas_index(x)
    arr = to_float_array(x, "x", min_length=1)
    fs = None if fs_hz is None else check_positive("fs_hz", fs_hz)
    time = None if fs is None else np.arange(arr.shape[0], dtype=np.float64) / fs
    name = str(x.name) if isinstance(x, pd.Series) and x.name is not None else "x"
    mean = float(arr.mean()) if arr.size else 0.0
    steps = [f"removed the mean ({mean:.6g})"]
    info = {"source": "Series" if index is not None else "array", "axis": name, "units": None,
            "n_input": int(arr.shape[0]), "n": int(arr.shape[0]), "fs_hz": fs}
    return _Input(arr - mean, index, time, fs, None, info,
                  {"steps": steps, "demeaned": True, "mean": mean}, arr)


def _check_data(x: FloatArray, orders: Sequence[tuple[int, int]], lags: tuple[int, ...]) -> None:
    n = x.shape[0]
    need = max([MIN_SELECT_SAMPLES, 2 * max(lags)] + [min_nobs(p, q) for p, q in orders])
    if n < need:
        raise InsufficientDataError(
            f"x is too short for ARMA selection: {n} samples, need at least {need} (at least "
            f"{MIN_SELECT_SAMPLES}, twice the largest Ljung-Box lag {max(lags)}, and "
            f"10 x (p + q + 1) for the largest candidate)")
    if not np.all(np.isfinite(x)):
        raise DataError("x contains non-finite values")
    if float(np.ptp(x)) == 0.0:
        raise InsufficientDataError("x is constant; there is no drift to model")


def _check_lags(lags: Any) -> tuple[int, ...]:
    if isinstance(lags, int | np.integer) and not isinstance(lags, bool):
        lags = (int(lags),)
    if not isinstance(lags, Sequence) or isinstance(lags, str) or not lags:
        raise DataError(f"lags must be a non-empty sequence of positive integers, got {lags!r}")
    return tuple(sorted({check_int("lags", v, minimum=1) for v in lags}))


def _failed(p: int, q: int, criterion: str, reason: str, msgs: Sequence[str],
            data: FloatArray, inp: _Input) -> Candidate:
    nan = math.nan
    return Candidate(model=model_name(p, q), p=p, q=q, status="failed", reason=reason, rank=None,
                     criterion=criterion, params={}, bse={}, llf=nan, aic=nan, bic=nan,
                     hqic=nan, aicc=nan, sigma2=nan, roots=None, diagnostics=None, flags=(),
                     warnings=tuple(msgs), converged=False, fit=None, data=data,
                     index=inp.index, time=inp.time)


def _evaluate(p: int, q: int, inp: _Input, criterion: str, lags: tuple[int, ...],
              method: FitMethod) -> Candidate:
    x = inp.x
    name = model_name(p, q)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        try:
            fit = fit_arma(x, p, q, method=method, standardize=True)
        except (ModelFitError, InsufficientDataError, np.linalg.LinAlgError, ValueError,
                ArithmeticError) as exc:
            msg = str(exc).strip().splitlines()[0] if str(exc).strip() else type(exc).__name__
            return _failed(p, q, criterion, msg, [str(w.message) for w in caught], x, inp)
    msgs = list(fit.warnings)
    msgs += [f"{w.category.__name__}: {w.message}" for w in caught
             if f"{w.category.__name__}: {w.message}" not in msgs]
    values = [fit.llf, fit.sigma2, *fit.params.values()]
    if not all(math.isfinite(v) for v in values):
        return _failed(p, q, criterion, "the fit returned non-finite parameters or likelihood",
                       msgs, x, inp)
    roots = arma_roots(fit.ar, fit.ma)
    if not roots.stationary:
        return _failed(p, q, criterion, f"the fitted AR part is not stationary (largest AR "
                       f"inverse root modulus {roots.ar_radius:.4f} >= 1)", msgs, x, inp)
    if not fit.converged:
        msgs.append(f"{name}: the optimiser did not converge; its likelihood may be short of "
                    "the optimum")
    if not roots.invertible:
        msgs.append(f"the MA part is not invertible (largest MA inverse root modulus "
                    f"{roots.ma_radius:.4f} >= 1)")
    diag = residual_diagnostics(fit.resid, x, p=p, q=q, lags=lags)
    flags = near_cancellations(roots) + insignificant_terms(fit.params, fit.bse)
    # memory: drop the series-length innovations now (recomputed bit for bit on access);
    # select_arma stores them again for the selected candidate only
    return Candidate(model=name, p=p, q=q, status="ok", reason=None, rank=None,
                     criterion=criterion, params=dict(fit.params), bse=dict(fit.bse),
                     llf=fit.llf, aic=fit.aic, bic=fit.bic, hqic=fit.hqic, aicc=fit.aicc,
                     sigma2=fit.sigma2, roots=roots, diagnostics=diag, flags=flags,
                     warnings=tuple(msgs), converged=fit.converged,
                     fit=fit._without_resid(x), data=x, index=inp.index, time=inp.time)


def _rank(cands: list[Candidate], criterion: str) -> list[Candidate]:
    order = {id(c): i for i, c in enumerate(cands)}

    def key(c: Candidate) -> tuple[int, float, int, int]:
        return (0 if c.white else 1, float(getattr(c, criterion)), c.p + c.q, order[id(c)])

    ok = sorted((c for c in cands if c.ok), key=key)
    failed = [c for c in cands if not c.ok]
    ranked = [_replace(c, rank=i) for i, c in enumerate(ok, start=1)]
    return ranked + failed


def _replace(c: Candidate, **changes: Any) -> Candidate:
    import dataclasses

    return dataclasses.replace(c, **changes)


def _quantisation_note(raw: FloatArray | None, units: str | None) -> str | None:
    """A note if the raw rate takes few distinct values (a quantised gyro output)."""
    if raw is None or raw.size < 100:
        return None
    levels = np.unique(raw[:QUANT_CHECK_SAMPLES])
    if levels.size > QUANT_MAX_LEVELS:
        return None
    step = float(np.min(np.diff(levels))) if levels.size > 1 else 0.0
    unit = f" {units}" if units else ""
    return (f"The raw rate takes only {levels.size} distinct values (step {step:.4g}{unit}): "
            "it is quantised, so its residuals cannot look Gaussian; block-average it "
            "(decimate) before modelling the drift.")


def _cancellation_sentence(sel: Candidate, ranked: Sequence[Candidate], criterion: str,
                           simpler_exists: bool) -> str:
    """What nearly cancelling AR/MA roots mean here: a lower order does as well only when a
    lower-order candidate is white and close in the criterion; otherwise say why not, with
    the numbers of the best lower-order candidate."""
    if simpler_exists:
        return " Its AR and MA roots nearly cancel."
    crit = criterion.upper()
    lower = [c for c in ranked if c.ok and c.p + c.q < sel.p + sel.q]
    if not lower:
        return " Its AR and MA roots nearly cancel, but no lower-order candidate was fitted."
    best = min(lower, key=lambda c: getattr(c, criterion))
    delta = getattr(best, criterion) - getattr(sel, criterion)
    why = "and is not white" if not best.white else "though white"
    return (f" Its AR and MA roots nearly cancel, yet no lower order does as well: the best "
            f"lower-order candidate, {best.model}, is {delta:+.1f} {crit} units {why}; keep "
            f"{sel.model}.")


def _verdict(sel: Candidate | None, ranked: Sequence[Candidate], criterion: str,
             corr: Correlogram) -> str:
    crit = criterion.upper()
    if sel is None:
        reasons: dict[str, list[str]] = {}
        for c in ranked:
            reasons.setdefault(str(c.reason), []).append(c.model)
        text = "; ".join(r if len(reasons) == 1 else f"{', '.join(m)}: {r}"
                         for r, m in reasons.items())
        return f"No candidate could be fitted: {text}."
    pred = sel.predict()
    removed = 100.0 * pred.variance_removed
    if sel.white:
        text = (f"{sel.model} describes the drift: its residuals are white (rho_a2, rho_ax3 and "
                f"Ljung-Box all pass), lowest {crit} among the white candidates; one-step "
                f"prediction removes {removed:.1f} % of the variance.")
        simpler = [c for c in ranked if c.white and c.p + c.q < sel.p + sel.q
                   and getattr(c, criterion) - getattr(sel, criterion) < CLOSE_CALL]
        if sel.flagged("near_cancellation"):
            text += _cancellation_sentence(sel, ranked, criterion, bool(simpler))
        if simpler:
            alt = min(simpler, key=lambda c: (c.p + c.q, getattr(c, criterion)))
            text += (f" The simpler {alt.model} is within {CLOSE_CALL:g} {crit} units and also "
                     f"white: the data support it about as well.")
        if pred.variance_removed < SMALL_PREDICTION:
            text += (" The series is nearly white at this sample rate (white rate noise, i.e. "
                     "angle random walk, dominates): decimate to model the slower drift.")
        elif corr.acf_pattern.kind == "none" and corr.pacf_pattern.kind == "none":
            text += " The data are close to white noise to begin with."
        return text
    assert sel.diagnostics is not None
    why = "; ".join(sel.diagnostics.reasons)
    return (f"No candidate leaves white residuals: the best by {crit}, {sel.model}, still "
            f"fails ({why}). The drift needs a richer model or more preprocessing (detrend, "
            f"remove outliers, decimate); use this model with care.")


def select_arma(
    x: Any,
    *,
    candidates: Any = DEFAULT_FIVE,
    criterion: Criterion = "aic",
    lags: Sequence[int] | int = (10, 20),
    method: FitMethod = "fast",
    fs_hz: float | None = None,
) -> Selection:
    """Fit ARMA candidates, check their residuals and rank them (seed 000, steps 2-4).

    Parameters
    ----------
    x : Prepared, ndarray or Series
        The drift series.  A :class:`fogts.preprocess.prepare.Prepared` is used as is (trend and
        mean already removed, steps recorded); an ndarray or Series has its mean removed
        here (recorded in ``preprocessing``).
    candidates : str or sequence, default DEFAULT_FIVE
        AR(1), AR(2), AR(3), ARMA(1,1), ARMA(2,1) by default; see :func:`parse_candidates`.
    criterion : {"aic", "bic", "hqic", "aicc"}
        Ranking criterion (statsmodels' definitions; ``k`` counts sigma2).
    lags : int or sequence of int
        Ljung-Box lags (``model_df = p + q``).
    method : {"fast", "statsmodels"}
        Fit path of :func:`fogts.arma.fit.fit_arma` (both reach the exact-ML optimum).
    fs_hz : float, optional
        Sample rate of ndarray/Series input (gives the prediction a time column).

    Returns
    -------
    Selection

    Raises
    ------
    DataError
        Bad argument (criterion, candidates, lags) or non-finite data.
    InsufficientDataError
        Too short or constant series.

    Warns
    -----
    NotWhiteWarning
        No candidate leaves white residuals.
    ConvergenceWarning
        A candidate's optimiser did not converge.

    Notes
    -----
    Residual checks: seed 000 eqs. 11 and 12 against +-1.96/sqrt(n), Ljung-Box with
    ``model_df = p + q`` (Ljung & Box 1978); redundancy flags and the ACF/PACF reading are
    defined in :mod:`fogts.arma.diagnostics`.  Ranking: see the module docstring.

    Examples
    --------
    >>> import numpy as np
    >>> from scipy.signal import lfilter
    >>> e = np.random.default_rng(0).standard_normal(5000)
    >>> sel = select_arma(lfilter([1.0], [1.0, -0.6], e))
    >>> sel.best.model, sel.best.white
    ('AR(1)', True)
    """
    criterion = check_choice("criterion", criterion, CRITERIA)  # type: ignore[assignment]
    check_choice("method", method, ("fast", "statsmodels"))
    orders = parse_candidates(candidates)
    lag_t = _check_lags(lags)
    inp = _unpack(x, fs_hz)
    _check_data(inp.x, orders, lag_t)
    corr = correlogram(inp.x)
    evaluated = [_evaluate(p, q, inp, criterion, lag_t, method) for p, q in orders]
    for c in evaluated:
        if c.ok and not c.converged:
            warnings.warn(f"{c.model}: the optimiser did not converge; its likelihood may be "
                          "short of the optimum", ConvergenceWarning, stacklevel=2)
    ranked = _rank(evaluated, criterion)
    sel = ranked[0] if ranked and ranked[0].ok else None
    if sel is not None and sel.fit is not None:
        # the selected candidate keeps its innovations in memory (predict, plots, report),
        # recomputed once, exactly as the fit made them
        sel = ranked[0] = _replace(sel, fit=sel.fit._with_resid())
    all_white_failed = not any(c.white for c in ranked)
    notes = tuple(n for n in (_quantisation_note(inp.raw, inp.units),) if n)
    verdict = " ".join((_verdict(sel, ranked, criterion, corr), *notes))
    if sel is not None and all_white_failed:
        warnings.warn(f"no candidate leaves white residuals; {sel.model} (best by "
                      f"{criterion.upper()}) is reported anyway", NotWhiteWarning, stacklevel=2)
    return Selection(candidates=tuple(ranked), criterion=criterion, lags=lag_t,
                     n=int(inp.x.shape[0]), fs_hz=inp.fs_hz, units=inp.units, correlogram=corr,
                     selected=sel, all_white_failed=all_white_failed, verdict=verdict,
                     input=inp.info, preprocessing=inp.preprocessing, method=method,
                     notes=notes)
