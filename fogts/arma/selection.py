"""The result of an ARMA selection: ranked candidates, the data's correlogram, the verdict."""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import pandas as pd

from fogts.arma.candidate import Candidate
from fogts.arma.gauss_markov import GaussMarkov, gauss_markov
from fogts.arma.identification import Correlogram
from fogts.arma.margins import EquivalentSimpler, equivalent_simpler
from fogts.arma.whiteness import BAND_Z, LB_ALPHA
from fogts.errors import ModelFitError
from fogts.tables import Column, Table, TableView

__all__ = ["Selection"]


@dataclass(frozen=True, repr=False)
class Selection(TableView):
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
        Remarks on the data (e.g. a quantized raw rate), also appended to ``verdict``.
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

        ``selection.best.predict()`` gives the one-step prediction.
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

    @property
    def equivalent_simpler(self) -> EquivalentSimpler | None:
        """A simpler candidate that fails the residual checks only marginally, is close in
        the criterion and whose omitted coefficients are not significant in the selected
        model: the data cannot decide between the two (:mod:`fogts.arma.margins`); None
        if there is none."""
        return equivalent_simpler(self.selected, self.candidates, self.criterion)

    def gauss_markov(self) -> GaussMarkov | None:
        """The Gauss–Markov equivalent (correlation time, sigma, driving noise) of the selected
        model's dominant real AR root, in the input unit and in SI; None without one."""
        if self.selected is None:
            return None
        return gauss_markov(self.selected, self.fs_hz, self.units)

    def to_dict(self) -> dict[str, Any]:
        """The ``fogts select`` JSON: ``{"input", "preprocessing", "candidates", "selected"}``
        plus ``criterion``, ``lags``, ``correlogram``, ``verdict``, ``all_white_failed``."""
        sel = self.selected
        selected: dict[str, Any] | None = None
        if sel is not None:
            selected = {"model": sel.model, "p": sel.p, "q": sel.q, "rank": sel.rank,
                        "criterion": self.criterion, "value": sel.criterion_value,
                        "white": sel.white, "equation": sel.equation(),
                        "params": dict(sel.params), "sigma2": sel.sigma2,
                        "prediction": sel.prediction_summary()}
            gm = self.gauss_markov()
            selected["gauss_markov"] = gm.to_dict() if gm is not None else None
            eq = self.equivalent_simpler
            selected["equivalent_simpler"] = eq.to_dict() if eq is not None else None
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

    def candidate_table(self) -> Table:
        """The candidates ranked, with the residual checks (failed checks marked) and
        notes; the selected model's row is emphasised."""
        crit = self.criterion.upper()
        best = self.selected.criterion_value if self.selected is not None else math.nan
        columns = (Column("#"), Column("model", numeric=False), Column(crit, digits=2, fixed=True),
                   Column(f"Δ{crit}", digits=2, fixed=True, signed=True),
                   Column("σ_a²", digits=3), Column("ρ_a,2", fixed=True, signed=True),
                   Column("ρ_ax,3", fixed=True, signed=True),
                   *[Column(f"LB p({lag})", digits=3, pvalue=True) for lag in self.lags],
                   Column("white", numeric=False), Column("notes", numeric=False, wrap=True))
        rows: list[tuple[Any, ...]] = []
        failed: list[tuple[int, int]] = []
        eq = self.equivalent_simpler
        for i, c in enumerate(self.candidates):
            d = c.diagnostics
            if not c.ok or d is None:
                rows.append((None, c.model, *[None] * (5 + len(self.lags)), "failed",
                             f"fit failed: {c.reason}"))
                failed.append((i, len(columns) - 2))
                continue
            checks = [d.rho_a2.passed, d.rho_ax3.passed, *(x.passed for x in d.ljung_box)]
            failed += [(i, 5 + k) for k, ok in enumerate(checks) if ok is False]
            if not c.white:
                failed.append((i, len(columns) - 2))
            notes = c.notes
            if eq is not None and c.model == eq.model and self.selected is not None:
                notes = "; ".join(filter(None, (f"marginally not white: as good as "
                                                f"{self.selected.model}", notes)))
            rows.append((c.rank, c.model, c.criterion_value, c.criterion_value - best,
                         c.sigma2, d.rho_a2.value, d.rho_ax3.value,
                         *(x.pvalue for x in d.ljung_box), c.white, notes))
        band = BAND_Z / math.sqrt(self.n)
        return Table.build(
            f"ARMA candidates ranked by {crit}, white residuals first", columns, rows,
            caption=f"white: |ρ_a,2|, |ρ_ax,3| ≤ {BAND_Z}/√n = {band:.3g} and Ljung–Box "
                    f"p ≥ {LB_ALPHA} "
                    f"at each lag (model_df = p+q); marked cells fail their check",
            failed=failed,
            highlight=[i for i, c in enumerate(self.candidates) if c is self.selected])

    # -------------------------------------------------------------- notebook view
    def _view_table(self) -> Table:
        return self.candidate_table()

    def _view_headline(self) -> str:
        best = self.selected
        if best is None:
            return f"no candidate fitted, n = {self.n}"
        return (f"selected {best.model} by {self.criterion.upper()}, n = {self.n}, residuals "
                f"{'white' if best.white else 'NOT white'}")

    def summary(self) -> str:
        lines = [f"ARMA selection by {self.criterion.upper()} on {self.n} samples; "
                 f"{self.correlogram.summary()}", self.candidate_table().to_text()]
        if self.selected is not None:
            lines.append(f"selected: {self.selected.equation()}")
        lines.append(self.verdict)
        return "\n".join(lines)

