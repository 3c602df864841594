"""The one-page summary of Allan analyses: one row per file and axis with N, B and K (with
their standard errors, or their upper limits), the fit verdict and, given a datasheet
specification, PASS/FAIL per term.

The same rows feed the table ``fogts allan`` prints first, the table at the top of the HTML
report, the ``summary`` of the ``fogts allan`` JSON and the columns of the ``fogts batch``
summary (:func:`term_fields`).
"""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Any

from fogts._validate import finite_or_none
from fogts.allan.datasheet import SPEC_TERMS
from fogts.choices import OutputUnits
from fogts.tables import Column, Table
from fogts.units import quantity_of, term_unit

if TYPE_CHECKING:
    from fogts.allan.datasheet import NoiseSpec
    from fogts.allan.noise_model import NoiseModel
    from fogts.pipeline import AllanAnalysis, AxisAllan

__all__ = ["SUMMARY_TERMS", "axis_row", "summary_rows", "summary_table",
           "term_fields"]

#: The terms of the summary: those a datasheet specification may limit.
SUMMARY_TERMS: tuple[str, ...] = SPEC_TERMS
#: The fit cell of a GMWM fit whose J test rejects the model (:func:`axis_row`).
J_REJECTS = "J rejects"


def term_fields(model: NoiseModel | None, units: OutputUnits = "deg",
                spec: NoiseSpec | None = None, quantity: str | None = None) -> dict[str, Any]:
    """For each of :data:`SUMMARY_TERMS`: ``T`` (the value), ``T_stderr``, ``T_upper`` (the
    one-sided 95 % upper limit of a term that is only a limit, else None), ``T_unit`` (in
    ``units``, for the model's quantity: an accelerometer's N is in m/s/sqrt(h), not
    deg/sqrt(h)) and ``T_spec`` (``"PASS"``, ``"FAIL"``, ``"INCONCLUSIVE"``, ``"not fitted"``; None without a
    limit for the term).  Values are None where the term was not fitted.  ``quantity``
    (``"rate"`` or ``"accel"``): the axis' quantity, for the units when there is no model
    (default: the model's, else ``"rate"``)."""
    from fogts.allan.datasheet import check_spec

    checks = check_spec(model, spec) if model is not None and spec is not None else {}
    if quantity is None:
        quantity = model.quantity if model is not None else "rate"
    out: dict[str, Any] = {}
    for name in SUMMARY_TERMS:
        shown = model.in_units(name, units) if model is not None and name in model.names \
            else None
        out[name] = finite_or_none(shown["value"]) if shown else None
        out[f"{name}_stderr"] = finite_or_none(shown["stderr"]) if shown else None
        out[f"{name}_upper"] = finite_or_none(shown["upper_limit_95"]) if shown else None
        out[f"{name}_unit"] = term_unit(name, units, quantity)
        verdict = checks[name].verdict if name in checks else None
        out[f"{name}_spec"] = "not fitted" if spec is not None and name in spec.names \
            and verdict is None else verdict
    return out


def axis_row(file: str, axis: AxisAllan, units: OutputUnits = "deg",
             spec: NoiseSpec | None = None) -> dict[str, Any]:
    """The summary row of one axis: ``file``, ``axis``, :func:`term_fields` and ``fit``
    (``"ok"``, ``"misses"`` when the model misses the curve, None when not checked; for a
    GMWM fit whose J test rejects the model, its own verdict on the fit, ``"J rejects"``,
    or ``"misses, J rejects"``)."""
    check = axis.fit_check
    quantity = quantity_of(axis.result.units)
    fit = None if check is None else ("ok" if check.ok else "misses")
    gmwm = axis.model.gmwm if axis.model is not None else None
    if gmwm is not None and not gmwm.consistent:
        fit = J_REJECTS if fit in (None, "ok") else f"{fit}, {J_REJECTS}"
    return {"file": file, "axis": axis.result.axis,
            **term_fields(axis.model, units, spec, quantity), "fit": fit}


def summary_rows(analyses: Sequence[AllanAnalysis], units: OutputUnits = "deg",
                 spec: NoiseSpec | None = None) -> list[dict[str, Any]]:
    """One :func:`axis_row` per file and axis, files named by their base name."""
    return [axis_row(Path(a.run.source).name, ax, units, spec)
            for a in analyses for ax in a.axes]


def summary_table(rows: Sequence[dict[str, Any]], spec: NoiseSpec | None = None) -> Table:
    """The summary as a :class:`~fogts.tables.Table`: a term measured as ``value ± stderr``,
    a term that is only a limit as ``< upper limit``; with ``spec`` a PASS/FAIL column per
    term it limits (FAIL cells and misfits are marked failed)."""
    spec_terms = [t for t in SUMMARY_TERMS if spec is not None and t in spec.names]
    units_of = {t: {r[f"{t}_unit"] for r in rows} for t in SUMMARY_TERMS}
    columns = [Column("file", numeric=False), Column("axis", numeric=False)]
    columns += [Column(t if len(units_of[t]) != 1 else f"{t} ({next(iter(units_of[t]))})")
                for t in SUMMARY_TERMS]
    columns.append(Column("fit", numeric=False))
    columns += [Column(f"{t} spec", numeric=False) for t in spec_terms]
    table_rows, failed = [], []
    fit_col = 2 + len(SUMMARY_TERMS)
    for i, r in enumerate(rows):
        cells = [r["file"], r["axis"]]
        cells += [_term_cell(r, t, with_unit=len(units_of[t]) != 1) for t in SUMMARY_TERMS]
        cells.append(r["fit"] or "not checked")
        cells += [r[f"{t}_spec"] for t in spec_terms]
        failed += [(i, j) for j, v in enumerate(cells) if v == "FAIL" or (
            j == fit_col and r["fit"] not in (None, "ok"))]
        table_rows.append(cells)
    accel = any(r["N_unit"] in (term_unit("N", u, "accel") for u in ("deg", "si"))
                for r in rows)
    j_test = any(J_REJECTS in (r["fit"] or "") for r in rows)
    return Table.build("Summary: noise terms per file and axis", columns, table_rows,
                       caption=_caption(spec, accel, j_test), failed=failed)


def _term_cell(row: dict[str, Any], name: str, *, with_unit: bool) -> str:
    value, se, upper = row[name], row[f"{name}_stderr"], row[f"{name}_upper"]
    unit = f" {row[f'{name}_unit']}" if with_unit else ""
    if upper is not None:
        return f"< {_short(upper, 3)}{unit}"
    if value is None:
        return "–"
    return (f"{_short(value, 4)} ± {_short(se, 2)}" if se is not None
            else _short(value, 4)) + unit


def _short(v: float, digits: int) -> str:
    """``v`` with ``digits`` significant digits, in exponent form below 0.01 (SI values)."""
    return f"{v:.{digits - 1}e}" if v != 0 and abs(v) < 0.01 else f"{v:.{digits}g}"


def _caption(spec: NoiseSpec | None, accel: bool = False, j_test: bool = False) -> str:
    names = ("N angle random walk, B bias instability, K rate random walk" + (
        " (accelerometer axes: N velocity random walk, B bias instability, K acceleration "
        "random walk)" if accel else ""))
    text = (f"{names}: value ± standard "
            "error; '< x': the data do not measure the term and x is its one-sided 95 % "
            "upper limit. fit: 'ok' when the fitted model lies within the points' intervals, "
            "'misses' when it does not (see each axis' fit check)." + (
                f" '{J_REJECTS}': a GMWM fit whose J test rejects the model at its level (the "
                "fit's own verdict, whether or not the model lies within the intervals; see "
                "each axis' GMWM J test)." if j_test else ""))
    if spec is None:
        return text
    limits = ", ".join(f"{n} ≤ {spec.limit(n):g} {term_unit(n, spec.units)}"
                       for n in spec.names)
    return (text + f" spec ({spec.source}: {limits}): PASS when the term's one-sided 95 % "
            "upper bound is at or below the limit, FAIL when its 95 % lower bound is above "
            "it, INCONCLUSIVE when the limit lies within its uncertainty (ISO 14253-1); a "
            "term given only as an upper limit passes only if that upper limit is below the "
            "spec.")

