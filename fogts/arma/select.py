"""ARMA candidate selection with residual diagnostics: :func:`select_arma`.

The drift paper models FOG drift in five steps: (1) remove the trend and the mean; (2) read
the ACF and PACF; (3) fit the admissible low-order candidates AR(1), AR(2), AR(3), ARMA(1,1)
and ARMA(2,1) and take the lowest AIC; (4) check that the residuals are white with rho_a,2
(eq. 11) and rho_ax,3 (eq. 12); (5) predict one step ahead.  :func:`select_arma` does steps
2-4 on a prepared series (step 1 is :func:`fogts.preprocess.prepare`) and step 5 is
``selection.best.predict()``.

Ranking rule
------------
Candidates whose fit succeeded and whose residuals are white (all three checks of
:mod:`fogts.arma.whiteness` pass) are ranked first, by the information criterion
(ties: fewer parameters, then the order given; but see common factors below).  The others
that fitted follow, ranked the same way.  Failed fits stay in the table with
``status="failed"``, their reason and no rank.
The selected model is rank 1.  If no candidate is white, rank 1 is still reported, a
:class:`~fogts.errors.NotWhiteWarning` is emitted and ``Selection.all_white_failed`` is True
(the CLI exits with code 1).

Within each of the two groups, a candidate whose AR and MA parts may share a root (the Wald
test of a zero resultant does not reject at 5 %, :func:`fogts.arma.redundancy.common_factor`)
ranks after those that do not: such a model is its reduced ARMA(p - 1, q - 1) with a
cancelled factor, its parameters are not identified, and parsimony prefers the identified
models (Box, Jenkins & Reinsel 1994, sec. 7.3.5).  The AIC alone does not guard against it:
under the reduced model the location of the cancelling pair is a parameter the data do not
identify, so the likelihood gain of the extra pair is a supremum over that location and
exceeds AIC's penalty more often than the chi-squared asymptotics assume (Davies 1987,
*Biometrika* 74, 33-43).  So does a candidate with an MA root on the unit circle (within 1/n,
:func:`fogts.arma.verdict.on_unit_circle`): its innovations cannot be recovered from the
data, so it cannot drive a prediction or a Kalman filter, and at short record lengths the
restricted-likelihood estimate piles up there by chance (Davis & Dunsmuir 1996).  The
verdict names a candidate ranked down either way, with its numbers.  The other redundancy flags (a near-cancelling AR/MA root pair, an insignificant
coefficient) only inform: the criterion already penalises the extra parameters.  A
simpler candidate that fails the residual checks only by a margin within sampling noise,
close in the criterion and nested in the selected model with insignificant extra
coefficients, is named in the verdict as an equally good choice but not promoted
(:mod:`fogts.arma.margins` gives the reasons).
"""

from __future__ import annotations

import dataclasses
import math
import warnings
from collections.abc import Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np
import pandas as pd

from fogts import progress
from fogts._typing import ArrayLike1D, FloatArray
from fogts._validate import check_choice, check_int
from fogts.arma.candidate import Candidate
from fogts.arma.candidate_orders import DEFAULT_FIVE, MAX_ORDER, parse_candidates
from fogts.arma.fit import ArmaFit, FitMethod, fit_arma, min_nobs, model_name, shared_statistics
from fogts.arma.identification import correlogram
from fogts.arma.redundancy import common_factor, insignificant_terms, near_cancellations
from fogts.arma.roots import arma_roots
from fogts.arma.selection import Selection
from fogts.arma.verdict import (
    CLOSE_CALL,
    QUANT_CHECK_SAMPLES,
    QUANT_MAX_LEVELS,
    SMALL_PREDICTION,
    quantization_note,
    ranks_down,
    write_verdict,
)
from fogts.arma.whiteness import diagnostics_of
from fogts.choices import CRITERIA, Criterion
from fogts.errors import (
    ConvergenceWarning,
    DataError,
    InsufficientDataError,
    ModelFitError,
    NotWhiteWarning,
)
from fogts.preprocess.demeaned import Demeaned, holds_unformed
from fogts.preprocess.demeaned import held as held_series

if TYPE_CHECKING:
    from fogts.io.run import RegularTime, Run
    from fogts.preprocess.prepare import Prepared

__all__ = ["CLOSE_CALL", "CRITERIA", "DEFAULT_FIVE", "MAX_ORDER", "MIN_SELECT_SAMPLES",
           "QUANT_CHECK_SAMPLES", "QUANT_MAX_LEVELS", "SMALL_PREDICTION", "Candidate", "Criterion",
           "Selection", "parse_candidates", "select_arma"]

#: Fewest samples :func:`select_arma` accepts (also >= 2 x the largest Ljung-Box lag and
#: each candidate's own minimum).
MIN_SELECT_SAMPLES = 50


@dataclass(frozen=True)
class _Input:
    """The series to model: ``x`` minus ``offset`` (``offset`` non-zero for a long series
    whose demeaned copy is not formed: ``x`` is then the input, ``data`` its
    :class:`~fogts.preprocess.demeaned.Demeaned` stand-in), and what describes it; ``name``
    is how its errors name it (an axis of a file, else the argument ``x``)."""

    x: FloatArray
    index: pd.Index | None
    time: FloatArray | RegularTime | None
    fs_hz: float | None
    units: str | None
    info: dict[str, Any]
    preprocessing: dict[str, Any] | None
    raw: FloatArray | None = None
    offset: float = 0.0
    data: FloatArray | Demeaned | None = None
    name: str = "x"


def _selection_input(x: ArrayLike1D | Run | Prepared, fs_hz: float | None) -> _Input:
    from fogts._validate import check_positive
    from fogts.io.run import RegularTime
    from fogts.preprocess.inputs import ensure_series
    from fogts.preprocess.prepare import Prepared, prepare

    if isinstance(x, Prepared):     # read as held (ensure_series would form a held x)
        if fs_hz is not None:
            check_positive("fs_hz", fs_hz)
        return _prepared_input(x)
    inp = ensure_series(x, "x", fs_hz=fs_hz, min_length=1,
                        pick_hint="select one: select_arma(prepare(run, axis=...))")
    if inp.run is not None:  # one axis: its mean removed, the step recorded
        return _prepared_input(prepare(inp.run, fs_hz=fs_hz))
    arr, fs = inp.values, inp.fs_hz
    mean = float(arr.mean()) if arr.size else 0.0
    steps = [f"removed the mean ({mean:.6g})"]
    info = {"source": inp.kind, "axis": inp.axes[0], "units": None,
            "n_input": int(arr.shape[0]), "n": int(arr.shape[0]), "fs_hz": fs}
    preprocessing = {"steps": steps, "demeaned": True, "mean": mean}
    if holds_unformed(arr):
        # long: neither the demeaned copy nor the time axis is formed (see _prepared_input)
        return _Input(arr, inp.index, None if fs is None else RegularTime(arr.shape[0], fs),
                      fs, None, info, preprocessing, arr, mean, Demeaned(arr, mean))
    time = None if fs is None else np.arange(arr.shape[0], dtype=np.float64) / fs
    return _Input(arr - mean, inp.index, time, fs, None, info, preprocessing, arr)


def _prepared_input(p: Prepared) -> _Input:
    """The input of a Prepared series: a long one held unformed (its input and mean), so
    that the selection makes no demeaned copy."""
    run = p.run
    info = {"source": run.source if run is not None else None, "axis": p.axis,
            "units": p.units, "n_input": p.n_input, "n": p.n, "fs_hz": p.fs_hz}
    raw = None   # the quantization check only applies to undecimated data
    if run is not None and p.axis in run.axes and p.decimate == 1:
        raw = run.axis(p.axis)
    held = p.lazy_x
    name = f"axis {p.axis!r} of {run.source}" if run is not None else "x"
    if isinstance(held, Demeaned):
        # the input and its mean: the fits and checks subtract it block by block
        return _Input(held.raw, p.index, p.lazy_time, p.fs_hz, p.units, info, p.to_dict(),
                      raw, held.mean, held, name)
    return _Input(p.x, p.index, p.lazy_time, p.fs_hz, p.units, info, p.to_dict(), raw,
                  name=name)


def _check_data(x: FloatArray, orders: Sequence[tuple[int, int]], lags: tuple[int, ...],
                name: str) -> None:
    """The series is long enough, finite and not constant; the errors name it ``name``
    (:attr:`_Input.name`: an axis of a file read by fogts, else the argument ``x``)."""
    n = x.shape[0]
    need = max([MIN_SELECT_SAMPLES, 2 * max(lags)] + [min_nobs(p, q) for p, q in orders])
    if n < need:
        raise InsufficientDataError(
            f"{name} is too short for ARMA selection: {n} samples, need at least {need} (at "
            f"least {MIN_SELECT_SAMPLES}, twice the largest Ljung-Box lag {max(lags)}, and "
            f"10 x (p + q + 1) for the largest candidate)")
    if not np.all(np.isfinite(x)):
        raise DataError(f"{name} contains non-finite values")
    if float(np.ptp(x)) == 0.0:
        raise InsufficientDataError(f"{name} is constant; there is no drift to model")


def _check_lags(lags: Any) -> tuple[int, ...]:
    if isinstance(lags, int | np.integer) and not isinstance(lags, bool):
        lags = (int(lags),)
    if not isinstance(lags, Sequence) or isinstance(lags, str) or not lags:
        raise DataError(f"lags must be a non-empty sequence of positive integers, got {lags!r}")
    return tuple(sorted({check_int("lags", v, minimum=1) for v in lags}))


def _failed(p: int, q: int, criterion: str, reason: str, msgs: Sequence[str],
            data: FloatArray | Demeaned, inp: _Input) -> Candidate:
    return Candidate(model=model_name(p, q), p=p, q=q, status="failed", reason=reason, rank=None,
                     criterion=criterion, fit=None, roots=None, diagnostics=None, flags=(),
                     warnings=tuple(msgs), data=data,  # type: ignore[arg-type]  # HeldSeries
                     index=inp.index, time=inp.time)


def _evaluate(p: int, q: int, inp: _Input, criterion: str, lags: tuple[int, ...],
              method: FitMethod) -> Candidate:
    x = inp.x
    data = x if inp.data is None else inp.data
    name = model_name(p, q)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        try:
            # the mean is estimated in the likelihood (GLS) even though x was demeaned:
            # a zero-mean fit of demeaned data favours an MA root on the unit circle (its
            # restricted likelihood is the same for x and x - offset)
            fit = _offset_mean(fit_arma(x, p, q, method=method, standardize=True, mean=True),
                               inp.offset)
        except (ModelFitError, InsufficientDataError, np.linalg.LinAlgError, ValueError,
                ArithmeticError) as exc:
            msg = str(exc).strip().splitlines()[0] if str(exc).strip() else type(exc).__name__
            return _failed(p, q, criterion, msg, [str(w.message) for w in caught], data, inp)
    msgs = list(fit.warnings)
    msgs += [f"{w.category.__name__}: {w.message}" for w in caught
             if f"{w.category.__name__}: {w.message}" not in msgs]
    values = [fit.llf, fit.sigma2, *fit.params.values()]
    if not all(math.isfinite(v) for v in values):
        return _failed(p, q, criterion, "the fit returned non-finite parameters or likelihood",
                       msgs, data, inp)
    roots = arma_roots(fit.ar, fit.ma)
    if not roots.stationary:
        return _failed(p, q, criterion, f"the fitted AR part is not stationary (largest AR "
                       f"inverse root modulus {roots.ar_radius:.4f} >= 1)", msgs, data, inp)
    if not fit.converged:
        msgs.append(f"{name}: the optimiser did not converge; its likelihood may be short of "
                    "the optimum")
    if not roots.invertible:
        msgs.append(f"the MA part is not invertible (largest MA inverse root modulus "
                    f"{roots.ma_radius:.4f} >= 1)")
    diag = diagnostics_of(fit.resid, x, p=p, q=q, lags=lags, x_offset=inp.offset)
    flags = (near_cancellations(roots) + common_factor(fit.ar, fit.ma, fit.coef_cov, nobs=fit.nobs)
             + insignificant_terms(fit.params, fit.bse))
    # memory: drop the series-length innovations now (recomputed bit for bit on access);
    # select_arma stores them again for the selected candidate only
    return Candidate(model=name, p=p, q=q, status="ok", reason=None, rank=None,
                     criterion=criterion, fit=fit._without_resid(x), roots=roots,
                     diagnostics=diag, flags=flags, warnings=tuple(msgs),
                     data=data,  # type: ignore[arg-type]  # HeldSeries forms it on access
                     index=inp.index, time=inp.time)


def _offset_mean(fit: ArmaFit, offset: float) -> ArmaFit:
    """``fit`` of x as that of x - ``offset``: its GLS mean less ``offset`` (the rest of a
    restricted-likelihood fit does not depend on a constant subtracted from the series)."""
    if not offset or fit.mean is None:
        return fit
    return dataclasses.replace(fit, params={**fit.params, "mean": fit.params["mean"] - offset})


def _rank(cands: list[Candidate], criterion: str) -> list[Candidate]:
    order = {id(c): i for i, c in enumerate(cands)}

    def key(c: Candidate) -> tuple[int, int, float, int, int]:
        return (0 if c.white else 1, 1 if ranks_down(c) else 0,
                float(getattr(c, criterion)), c.p + c.q, order[id(c)])

    ok = sorted((c for c in cands if c.ok), key=key)
    failed = [c for c in cands if not c.ok]
    ranked = [_replace(c, rank=i) for i, c in enumerate(ok, start=1)]
    return ranked + failed


def _replace(c: Candidate, **changes: Any) -> Candidate:
    # the data as held: an unformed demeaned series stays unformed
    return dataclasses.replace(c, data=held_series(c, "data"), **changes)

# over 80 lines only through its numpydoc docstring; the body is short
def select_arma(
    x: ArrayLike1D | Run | Prepared,
    *,
    candidates: Any = DEFAULT_FIVE,
    criterion: Criterion = "aic",
    lags: Sequence[int] | int = (10, 20),
    method: FitMethod = "fast",
    fs_hz: float | None = None,
) -> Selection:
    """Fit ARMA candidates, check their residuals and rank them (the drift paper's steps 2-4).

    Parameters
    ----------
    x : Prepared, Run, ndarray or Series
        The drift series.  A :class:`fogts.preprocess.prepare.Prepared` is used as is (trend and
        mean already removed, steps recorded); a one-axis :class:`fogts.io.run.Run` goes
        through :func:`~fogts.preprocess.prepare.prepare` with its defaults; an ndarray or
        Series has its mean removed here (recorded in ``preprocessing``).
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
    Residual checks: the drift paper's eqs. 11 and 12 against +-1.96/sqrt(n), Ljung-Box with
    ``model_df = p + q`` (Ljung & Box 1978), see :mod:`fogts.arma.whiteness`; redundancy flags
    in :mod:`fogts.arma.redundancy`, the ACF/PACF reading in :mod:`fogts.arma.identification`.
    Ranking: see the module docstring.

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
    inp = _selection_input(x, fs_hz)
    _check_data(inp.x, orders, lag_t, inp.name)
    corr = correlogram(inp.x)
    tick = progress.ticker(f"ARMA: {len(orders)} candidates", len(orders))
    evaluated = []
    with shared_statistics():     # the candidates share the series' scale, mean, lag sums
        for p, q in orders:
            evaluated.append(_evaluate(p, q, inp, criterion, lag_t, method))
            tick(len(evaluated))
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
    notes = tuple(n for n in (quantization_note(inp.raw, inp.units),) if n)
    verdict = " ".join((write_verdict(sel, ranked, criterion, corr), *notes))
    if sel is not None and all_white_failed:
        warnings.warn(f"no candidate leaves white residuals; {sel.model} (best by "
                      f"{criterion.upper()}) is reported anyway", NotWhiteWarning, stacklevel=2)
    return Selection(candidates=tuple(ranked), criterion=criterion, lags=lag_t,
                     n=int(inp.x.shape[0]), fs_hz=inp.fs_hz, units=inp.units, correlogram=corr,
                     selected=sel, all_white_failed=all_white_failed, verdict=verdict,
                     input=inp.info, preprocessing=inp.preprocessing, method=method,
                     notes=notes)
