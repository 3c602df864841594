"""Parametric bootstrap of a noise fit by re-simulating the record: :func:`bootstrap_noise`.

A fitted :class:`~fogts.allan.noise_model.NoiseModel` is a complete noise model, so records
like the one it came from can be drawn from it: :func:`~fogts.simulate.gyro.simulate_gyro`
simulates each replicate (same sample rate, length and unit), the same Allan curve is
computed from it (estimator and taus of the original curve) and the same method refits it
(``wls``, ``gls``, ``ols``, ``gmwm`` on the curve; ``ml`` on the simulated series).  The
standard deviation of the refitted terms over the replicates is the bootstrap standard
error, and their ``(1 - confidence) / 2`` and ``(1 + confidence) / 2`` quantiles the
percentile interval (Efron & Tibshirani 1993, *An Introduction to the Bootstrap*, ch. 6
and 13).  For the GMWM this is the parametric bootstrap Guerrier et al. (2013, *JASA*
108(502), 1087-1102, sec. 4) propose beside the asymptotic covariance, here on whole
simulated records rather than on the wavelet variances alone (``fit_gmwm(...,
n_bootstrap=...)`` resamples those): it carries everything the fit does to a record,
its model choice (the number of Gauss-Markov terms, dropped terms) included.

What is simulated
    The five IEEE-952 terms at the fitted values (IEEE Std 952-1997, Annex C; a term at
    zero or dropped is 0).  Bias instability is the fit's own: a Markov-sum flicker of
    amplitude B for the least-squares fits and ML's flicker model; the fitted first-order
    Gauss-Markov terms (``sigma``, ``T_c``; ``q_c = sigma sqrt(2 / T_c)``, IEEE 952
    Table C.1) for GMWM and ML's Gauss-Markov model, each drawn as one more independent
    axis of the simulator and added.
"""

from __future__ import annotations

import math
import warnings
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
import pandas as pd

from fogts._typing import FloatArray, RngLike
from fogts._validate import as_rng, check_int, finite_or_none
from fogts.allan.noise_model import NoiseModel
from fogts.allan.result import AllanResult
from fogts.errors import DataError, FogtsError
from fogts.simulate.noise_spec import NoiseSpec
from fogts.tables import Column, Table, TableView

__all__ = ["NoiseBootstrap", "bootstrap_noise", "simulation_specs"]

#: Fewest replicates a standard error is computed from.
MIN_REPLICATES = 10
_FIVE = ("Q", "N", "B", "K", "R")


#: The per-term values of a :class:`NoiseBootstrap`, as its frame's columns and JSON keys.
_PER_TERM = ("estimate", "stderr", "boot_mean", "boot_stderr", "ci_low", "ci_high")


@dataclass(frozen=True, repr=False)
class NoiseBootstrap(TableView):
    """Bootstrap standard errors and percentile intervals of a noise fit's terms.

    Attributes
    ----------
    method : str
        The fit's method (the refits use it too).
    confidence : float
        Level of the percentile interval.
    terms : tuple of str
        The terms, in the order Q, N, B, K, R.
    estimate, stderr : tuple of float
        The fit's own values and standard errors (NaN where it gives none).
    replicates : ndarray
        The refitted values, one row per successful replicate, one column per term; their
        mean and standard deviation (``ddof=1``) are :attr:`boot_mean` and
        :attr:`boot_stderr` (the bootstrap standard error), their percentiles at
        ``confidence`` :attr:`ci_low` and :attr:`ci_high`.
    failures : tuple of str
        Why refits failed (each reason once).
    n_replicates, n_failed : int
        Replicates asked for, and refits that raised.
    simulated : str
        The model the replicates were drawn from, in words.
    """

    method: str
    confidence: float
    terms: tuple[str, ...]
    estimate: tuple[float, ...]
    stderr: tuple[float, ...]
    replicates: FloatArray
    failures: tuple[str, ...]
    n_replicates: int
    n_failed: int
    simulated: str

    @property
    def boot_mean(self) -> tuple[float, ...]:
        return tuple(float(v) for v in self.replicates.mean(axis=0))

    @property
    def boot_stderr(self) -> tuple[float, ...]:
        return tuple(float(v) for v in self.replicates.std(axis=0, ddof=1))

    @property
    def ci_low(self) -> tuple[float, ...]:
        return self._quantile((1.0 - self.confidence) / 2.0)

    @property
    def ci_high(self) -> tuple[float, ...]:
        return self._quantile((1.0 + self.confidence) / 2.0)

    def _quantile(self, q: float) -> tuple[float, ...]:
        return tuple(float(v) for v in np.quantile(self.replicates, q, axis=0))

    def boot_stderr_of(self, name: str) -> float:
        """The bootstrap standard error of term ``name``."""
        if name not in self.terms:
            raise DataError(f"term {name!r} is not in the bootstrap; terms are: "
                            f"{', '.join(self.terms)}")
        return self.boot_stderr[self.terms.index(name)]

    def to_frame(self) -> pd.DataFrame:
        """One row per term: estimate, stderr, boot_mean, boot_stderr, ci_low, ci_high."""
        return pd.DataFrame({c: getattr(self, c) for c in _PER_TERM},
                            index=pd.Index(self.terms, name="term"))

    def to_dict(self) -> dict[str, Any]:
        return {"method": self.method, "confidence": self.confidence,
                "n_replicates": self.n_replicates, "n_failed": self.n_failed,
                "failures": list(self.failures), "simulated": self.simulated,
                "terms": {t: {c: finite_or_none(getattr(self, c)[i]) for c in _PER_TERM}
                          for i, t in enumerate(self.terms)}}

    def table(self) -> Table:
        pct = f"{100 * self.confidence:.1f} %"
        columns = (Column("term", numeric=False), Column("estimate"),
                   Column("± stderr (fit)", digits=3), Column("± stderr (bootstrap)", digits=3),
                   Column("bootstrap mean"), Column(f"{pct} percentile interval"))
        rows = [(t, self.estimate[i], self.stderr[i], self.boot_stderr[i], self.boot_mean[i],
                 (self.ci_low[i], self.ci_high[i])) for i, t in enumerate(self.terms)]
        ok = self.n_replicates - self.n_failed
        return Table.build(
            f"Parametric bootstrap of the {self.method.upper()} fit ({ok} of "
            f"{self.n_replicates} replicates refitted)", columns, rows,
            caption=f"Replicates simulated from the fit ({self.simulated}) and refitted "
                    "the same way; the bootstrap standard error is their standard "
                    "deviation, the interval their percentiles.")

    def summary(self) -> str:
        lines = [self.table().to_text()]
        lines += [f"failed refit: {f}" for f in self.failures]
        return "\n".join(lines)

    def _view_table(self) -> Table:
        return self.table()

    def _view_headline(self) -> str:
        return (f"{self.method.upper()} bootstrap, {self.n_replicates - self.n_failed} "
                "replicates: " + ", ".join(f"{t} ± {s:.2g}" for t, s in
                                            zip(self.terms, self.boot_stderr, strict=True)))


def simulation_specs(model: NoiseModel) -> tuple[NoiseSpec, ...]:
    """The simulator's specification of a fitted model: the first spec holds the five terms
    (and the first Gauss-Markov term), each further one a further Gauss-Markov term; the
    record is the sum of their axes (module docstring)."""
    summary = model.gmwm if model.gmwm is not None else model.ml
    gms = tuple(summary.gauss_markov) if summary is not None else ()
    values = {t: (model[t].value if t in model.names else 0.0) for t in _FIVE}
    if gms:
        values["B"] = 0.0  # bias instability is the Gauss-Markov terms themselves
    markov = [{"q_c": g.sigma * math.sqrt(2.0 / g.t_c), "T_c": g.t_c} for g in gms
              if g.sigma > 0 and g.t_c > 0]
    first = NoiseSpec(**values, **(markov[0] if markov else {}))
    return (first, *(NoiseSpec(**m) for m in markov[1:]))


def bootstrap_noise(curve: AllanResult, model: NoiseModel, *, n_replicates: int = 100,
                    rng: RngLike = None) -> NoiseBootstrap:
    """Bootstrap standard errors of a noise fit by simulating records from it and refitting.

    Parameters
    ----------
    curve : AllanResult
        The Allan curve of one axis the model was fitted to (for ``ml``: the record's curve
        the model carries is enough, but the sample rate and length come from here).
    model : NoiseModel
        The fit, by ``fit_noise`` (wls, gls, ols, gmwm) or ``fit_noise_ml``.
    n_replicates : int
        Records to simulate and refit (at least 10; 100 gives the standard errors to about
        7 %).
    rng : Generator, int or None
        Random source (a fixed seed gives the same replicates).

    Returns
    -------
    NoiseBootstrap

    Raises
    ------
    DataError
        ``curve`` is not one AllanResult, ``model`` not a NoiseModel, the two disagree on
        the unit or kind, or ``n_replicates`` is below 10; fewer than 10 refits succeed.

    Examples
    --------
    >>> import warnings, fogts
    >>> curve = fogts.allan_deviation(fogts.simulate_gyro({"N": 0.01, "K": 1.0}, fs_hz=10,
    ...                                                   duration_s=1800, rng=1))
    >>> with warnings.catch_warnings():  # the fit's notes on terms the data lack
    ...     warnings.simplefilter("ignore")
    ...     model = fogts.fit_noise(curve, terms="N,K", method="gmwm")
    ...     boot = fogts.bootstrap_noise(curve, model, n_replicates=10, rng=2)
    >>> boot.terms, boot.n_failed
    (('N', 'K'), 0)
    """
    _check(curve, model)
    n_replicates = check_int("n_replicates", n_replicates, minimum=MIN_REPLICATES)
    specs = simulation_specs(model)
    seeds = as_rng(rng).spawn(n_replicates)
    values, failures = [], []
    for g in seeds:
        try:
            values.append(_refit(curve, model, specs, g))
        except (FogtsError, ValueError, np.linalg.LinAlgError) as exc:
            failures.append(f"{type(exc).__name__}: {exc}")
    ok = np.array(values, dtype=np.float64).reshape(-1, len(model.names))
    if ok.shape[0] < MIN_REPLICATES:
        raise DataError(f"only {ok.shape[0]} of {n_replicates} bootstrap refits succeeded "
                        f"(at least {MIN_REPLICATES} are needed); first failure: "
                        f"{failures[0] if failures else 'none'}")
    return NoiseBootstrap(
        method=model.method, terms=model.names,
        estimate=tuple(model[t].value for t in model.names),
        stderr=tuple(model[t].stderr for t in model.names),
        confidence=model.confidence, replicates=ok, n_replicates=n_replicates,
        n_failed=len(failures), failures=tuple(dict.fromkeys(failures)),
        simulated=_describe(specs, curve))


def _check(curve: Any, model: Any) -> None:
    if not isinstance(curve, AllanResult):
        raise DataError(f"curve must be one AllanResult (one axis), got {type(curve).__name__}")
    if not isinstance(model, NoiseModel):
        raise DataError(f"model must be a NoiseModel, got {type(model).__name__}")
    if (curve.units, curve.kind) != (model.units, model.kind):
        raise DataError(f"model and curve disagree: the model was fitted to {model.kind} in "
                        f"{model.units}, the curve is {curve.kind} in {curve.units}")


def _refit(curve: AllanResult, model: NoiseModel, specs: Sequence[NoiseSpec],
           g: np.random.Generator) -> list[float]:
    """One replicate: simulate, recompute the curve (or keep the series) and refit."""
    from fogts.allan.api import allan_deviation
    from fogts.allan.ml import fit_noise_ml
    from fogts.allan.noise import fit_noise
    from fogts.simulate.gyro import simulate_gyro

    run = simulate_gyro(list(specs), fs_hz=curve.fs_hz,
                        duration_s=curve.n_samples / curve.fs_hz, rng=g, units=curve.units)
    rate = run.rate if run.rate.ndim == 1 else run.rate.sum(axis=1)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # each replicate's own notes are not the user's
        if model.method == "ml":
            refit = fit_noise_ml(rate, curve.fs_hz, units=curve.units, axis=curve.axis,
                                 terms=model.names, confidence=model.confidence)
        else:
            again = allan_deviation(rate, fs_hz=curve.fs_hz, kind=curve.kind,  # type: ignore[arg-type]
                                    taus=[float(t) for t in curve.tau_s], units=curve.units,
                                    confidence=curve.confidence)
            narrower = model.tau_s[0] > curve.tau_s[0] or model.tau_s[-1] < curve.tau_s[-1]
            refit = fit_noise(again, terms=model.names, method=model.method,  # type: ignore[arg-type]
                              confidence=model.confidence,
                              significance=model.significance,
                              tau_range=(float(model.tau_s[0]), float(model.tau_s[-1]))
                              if narrower else None)
    return [refit[t].value for t in model.names]


def _describe(specs: Sequence[NoiseSpec], curve: AllanResult) -> str:
    first = specs[0]
    parts = [f"{t} = {getattr(first, t):.4g}" for t in _FIVE if getattr(first, t)]
    parts += [f"GM sigma = {s.q_c * math.sqrt(s.T_c / 2):.4g}, T_c = {s.T_c:.4g} s"
              for s in specs if s.q_c > 0]
    return (", ".join(parts) or "no noise") + (f"; {curve.n_samples} samples at "
                                               f"{curve.fs_hz:g} Hz")
