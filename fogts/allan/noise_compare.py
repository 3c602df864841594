"""Noise fits of one axis by several methods, side by side: :func:`side_by_side` ->
:class:`MethodComparison` (``fogts allan --method wls,gmwm,ml``).

The methods estimate the same IEEE-952 terms (IEEE Std 952-1997, Annex C) from different
statistics: ``wls``, ``gls`` and ``ols`` fit the Allan curve (:func:`fogts.allan.noise.fit_noise`),
``gmwm`` its Haar wavelet variances, i.e. half the overlapping Allan variances (Guerrier et
al. 2013, *JASA* 108(502), 1087-1102; Percival & Guttorp 1994; :mod:`fogts.allan.gmwm`),
and ``ml`` the record itself by its exact Gaussian likelihood (Harvey 1989;
:mod:`fogts.allan.ml`).  B of GMWM and ML is the flicker equivalent of their Gauss-Markov
components.  Each term keeps its own fit's standard error and upper-limit rule
(:attr:`fogts.allan.noise_model.NoiseTerm.is_limit`).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import pandas as pd

from fogts._validate import finite_or_none
from fogts.allan.noise_model import NoiseModel
from fogts.choices import OutputUnits
from fogts.errors import DataError
from fogts.tables import Column, Table, TableView

__all__ = ["MethodComparison", "model_label", "side_by_side"]

_ORDER = ("Q", "N", "B", "K", "R")
_FIELDS = ("value", "stderr", "ci_low", "ci_high", "upper_limit_95")


def model_label(model: NoiseModel) -> str:
    """The fitted model in a few words: the GMWM or ML composite model (``"N + K + 2 GM"``),
    else the terms the least-squares fit kept (``"N + B"``)."""
    if model.ml is not None:
        return model.ml.model
    if model.gmwm is not None:
        return model.gmwm.model
    kept = [t.name for t in model.terms if t.status == "fitted" and t.value > 0]
    return " + ".join(kept) or "no term"


@dataclass(frozen=True, repr=False)
class MethodComparison(TableView):
    """Noise fits of one axis by several methods; the first is the primary fit (the one a
    report's other tables show).

    Attributes
    ----------
    models : tuple of NoiseModel
        One fit per method, the primary first; their methods are distinct.

    Examples
    --------
    >>> import warnings
    >>> from fogts.allan import allan_deviation
    >>> from fogts.allan.noise import fit_noise
    >>> from fogts.simulate.gyro import simulate_gyro
    >>> run = simulate_gyro({"N": 0.01, "K": 1.0}, fs_hz=10, duration_s=3600, rng=1)
    >>> curve = allan_deviation(run, taus="octave")
    >>> with warnings.catch_warnings():
    ...     warnings.simplefilter("ignore")
    ...     both = side_by_side([fit_noise(curve), fit_noise(curve, method="gmwm")])
    >>> both.methods, both.terms
    (('wls', 'gmwm'), ('Q', 'N', 'B', 'K', 'R'))
    """

    models: tuple[NoiseModel, ...]

    @property
    def methods(self) -> tuple[str, ...]:
        return tuple(m.method for m in self.models)

    @property
    def primary(self) -> NoiseModel:
        return self.models[0]

    @property
    def terms(self) -> tuple[str, ...]:
        """Every term some method fitted, in the order Q, N, B, K, R."""
        names = {n for m in self.models for n in m.names}
        return tuple(n for n in _ORDER if n in names)

    def estimate(self, method: str, name: str, units: OutputUnits = "deg"
                 ) -> dict[str, Any] | None:
        """Term ``name`` of ``method``'s fit: value, stderr, interval, 95 % upper limit
        (None for a measured term), ``measured`` and ``status``; None when the method does
        not model the term."""
        model = self.models[self.methods.index(method)]
        if name not in model.names:
            return None
        shown = model.in_units(name, units)
        term = model[name]
        out: dict[str, Any] = {k: finite_or_none(shown[k]) for k in _FIELDS}
        return {**out, "measured": not term.is_limit, "status": term.status}

    def to_dict(self, units: OutputUnits = "deg") -> dict[str, Any]:
        """The JSON ``methods`` block: ``primary``, ``order`` (the methods), ``models``
        (each method's fitted model in words) and ``terms``: per term its ``unit`` and per
        method :meth:`estimate` (null where the method does not model the term)."""
        described = {n: self._unit(n, units) for n in self.terms}
        return {"primary": self.methods[0], "order": list(self.methods),
                "models": {m.method: model_label(m) for m in self.models},
                "terms": {n: {"unit": described[n],
                              **{m: self.estimate(m, n, units) for m in self.methods}}
                          for n in self.terms}}

    def to_frame(self, units: OutputUnits = "deg") -> pd.DataFrame:
        """One row per term; columns (method, field) with field value, stderr, ci_low,
        ci_high, upper_limit_95 (NaN where a method does not model the term)."""
        data = {}
        for m in self.methods:
            for f in _FIELDS:
                cells = [self.estimate(m, n, units) for n in self.terms]
                data[(m, f)] = [float("nan") if c is None or c[f] is None else c[f]
                                for c in cells]
        frame = pd.DataFrame(data, index=pd.Index(self.terms, name="term"))
        frame.columns = pd.MultiIndex.from_tuples(list(data), names=["method", "field"])
        return frame

    def table(self, units: OutputUnits = "deg") -> Table:
        """The side-by-side table: per term its value ± standard error by each method (or
        ``< x``, the 95 % upper limit of a term the method does not measure), and a last
        row with each method's model."""
        columns = [Column("term", numeric=False), Column("unit", numeric=False)]
        columns += [Column(_header(model, primary=i == 0))
                    for i, model in enumerate(self.models)]
        rows = [[n, self._unit(n, units)] + [self._cell(m, n, units) for m in self.methods]
                for n in self.terms]
        rows.append(["model", ""] + [model_label(m) for m in self.models])
        axis = self.primary.axis
        return Table.build(
            f"Noise terms of {axis} by method, side by side", columns, rows,
            caption="value ± standard error; '< x': the method does not measure the term "
                    "and x is its one-sided 95 % upper limit; 'not modelled': the method "
                    "has no such term. WLS, GLS and OLS fit the Allan curve, GMWM its "
                    "wavelet variances (Haar WV = Allan variance / 2), ML the record itself; "
                    "GMWM's and ML's B is the flicker equivalent of their Gauss-Markov "
                    "terms. The other tables show the primary fit; a method whose model "
                    "its own test rejects is marked, and its values and standard errors "
                    "hold only under that rejected model.")

    def summary(self) -> str:
        return self.table().to_text()

    def _cell(self, method: str, name: str, units: OutputUnits) -> str:
        est = self.estimate(method, name, units)
        if est is None:
            return "not modelled"
        if not est["measured"]:
            upper = est["upper_limit_95"]
            return "–" if upper is None else f"< {upper:.3g}"
        se = est["stderr"]
        return f"{est['value']:.4g}" + ("" if se is None else f" ± {se:.2g}")

    def _unit(self, name: str, units: OutputUnits) -> str:
        model = next(m for m in self.models if name in m.names)
        return str(model.in_units(name, units)["unit"])

    def _view_table(self) -> Table:
        return self.table()

    def _view_headline(self) -> str:
        return f"{self.primary.axis!r} by {', '.join(m.upper() for m in self.methods)}"


def _header(model: NoiseModel, *, primary: bool) -> str:
    """A method's column title: the method, whether it is the primary fit, and a GMWM
    model that its J test rejects."""
    title = model.method.upper() + (" (primary)" if primary else "")
    if model.gmwm is not None and not model.gmwm.consistent:
        title += f" (model rejected: J test p = {model.gmwm.p_value:.2g})"
    return title


def side_by_side(models: Sequence[NoiseModel]) -> MethodComparison:
    """Put noise fits of one axis by different methods side by side.

    Parameters
    ----------
    models : sequence of NoiseModel
        At least one fit; the first is the primary one.  Their methods must be distinct
        and their axis and quantity the same.

    Returns
    -------
    MethodComparison

    Raises
    ------
    DataError
        No model, a method twice, or fits of different axes or quantities.
    """
    models = tuple(models)
    if not models or not all(isinstance(m, NoiseModel) for m in models):
        raise DataError(f"models must be one or more NoiseModel, got {models!r}")
    methods = [m.method for m in models]
    twice = sorted({m for m in methods if methods.count(m) > 1})
    if twice:
        raise DataError(f"models must have distinct methods; {', '.join(twice)} appears "
                        f"more than once in {', '.join(methods)}")
    axes = sorted({(m.axis, m.quantity) for m in models})
    if len(axes) > 1:
        raise DataError(f"models must be fits of one axis; got {axes}")
    return MethodComparison(models=models)
