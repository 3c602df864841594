"""The default per-file analysis of a batch: read and check the file, then per axis the
Allan analysis and the ARMA selection of :mod:`fogts.pipeline`.

:func:`analyze_file` never raises for a problem with the file: a file that cannot be read
gives one error row, an axis that fails gives an error row for that axis only.
"""

from __future__ import annotations

import warnings
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any

from fogts.batch.documents import blank_row, error_outcome, run_document
from fogts.batch.records import BatchOptions, RunOutcome
from fogts.errors import DataQualityWarning
from fogts.report.text import error_message, warning_texts
from fogts.units import quantity_of

if TYPE_CHECKING:
    from fogts.arma.selection import Selection
    from fogts.io.run import Run
    from fogts.pipeline import AxisAllan, AxisSelection
    from fogts.preprocess.hygiene import DataQuality

__all__ = ["analyze_file"]


@dataclass(frozen=True)
class _AxisOutcome:
    """One axis of a run: its summary row, its status entry in the document, and the
    pipeline's results (None where the axis failed or the selection was not asked for)."""

    row: dict[str, Any]
    status: dict[str, Any]
    allan: AxisAllan | None = None
    selection: dict[str, Any] | None = None


def analyze_file(file: str, options: BatchOptions) -> RunOutcome:
    """Read one file and analyse every axis (the default batch analysis).

    Never raises for a problem with the file: it returns an outcome with ``status="error"``
    and the message.  An axis that fails gives an error row for that axis only.
    """
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        try:
            run, quality, info = _read(file, options)
        except Exception as exc:
            msg = error_message(exc)
            doc = run_document(file, "error", msg, {}, [], warning_texts(caught))
            doc["options"] = options.to_dict()
            return error_outcome(file, msg, persist=True, document=doc)
        axes = [_axis_outcome(file, run, quality, i, options) for i in range(len(run.axes))]
    return _run_outcome(file, run, quality, info, axes, warning_texts(caught), options)


def _read(file: str, options: BatchOptions) -> tuple[Run, DataQuality, dict[str, Any]]:
    """The run, its data quality (each finding also warned, named after the file) and the
    ``info`` of the per-run JSON."""
    from fogts.pipeline import load
    from fogts.report.text import run_info

    run, quality = load(file, options.read_settings)
    for line in quality.warnings():
        warnings.warn(f"{Path(file).name}: {line}", DataQualityWarning, stacklevel=1)
    return run, quality, {**run_info(run), "data_quality": quality.to_dict()}


def _axis_outcome(file: str, run: Run, quality: DataQuality, axis: int,
                  options: BatchOptions) -> _AxisOutcome:
    """Analyse one axis; an exception becomes an error row and an error status."""
    name = run.axes[axis]
    row = blank_row(file, name)
    accel = quantity_of(run.unit_of(axis)) == "accel"  # an IMU file's accelerometer axis
    row.update(n=run.n, fs_hz=run.fs_hz, input_units=run.unit_of(axis),
               units_source=run.accel_units_source if accel else run.units_source,
               n_gaps=run.sampling.n_gaps if run.sampling is not None else 0,
               n_glitches=quality.glitch_count(name))
    status: dict[str, Any] = {"axis": name, "status": "ok", "error": ""}
    try:
        fields, allan, selection = _analyze_axis(run, quality, axis, options)
        row.update(fields)
        return _AxisOutcome(row, status, allan,
                            selection.to_dict() if selection is not None else None)
    except Exception as exc:
        msg = error_message(exc)
        row.update(status="error", error=msg)
        status.update(status="error", error=msg)
        return _AxisOutcome(row, status)


def _analyze_axis(run: Run, quality: DataQuality, axis: int, options: BatchOptions
                  ) -> tuple[dict[str, Any], AxisAllan, AxisSelection | None]:
    """The pipeline's Allan analysis and ARMA selection of one axis -> (row fields, the
    two results)."""
    from fogts.pipeline import (
        AllanSettings,
        SelectSettings,
        analyse_allan_axis,
        analyse_selection,
    )
    from fogts.report.summary import axis_row

    # one thread per analysis: the parallelism is across files
    allan = analyse_allan_axis(run, axis, AllanSettings(kind=options.kind, taus=options.taus,
                                                        workers=1))
    # the terms in options.output_units with their units, spec verdicts and the fit verdict
    summary = axis_row(run.source, allan, options.output_units,  # type: ignore[arg-type]
                       options.spec)
    fields = {k: v for k, v in summary.items() if k not in ("file", "axis")}
    selection = None
    if options.select:
        selection = analyse_selection(run, quality, axis, SelectSettings(
            detrend=options.detrend, decimate=options.decimate, criterion=options.criterion,
            stationarity=False), file=run.source)
        fields.update(_selection_fields(selection.selection))
    return fields, allan, selection


def _selection_fields(sel: Selection) -> dict[str, Any]:
    """``selected``, ``aic`` and ``white`` of the selected candidate; ModelFitError (an
    error row naming every candidate's reason) if every candidate failed."""
    best = sel.require_best()
    from fogts._validate import finite_or_none

    return {"selected": best.model, "aic": finite_or_none(best.aic), "white": bool(best.white)}


def _run_outcome(file: str, run: Run, quality: DataQuality, info: dict[str, Any],
                 axes: list[_AxisOutcome], warned: list[str], options: BatchOptions
                 ) -> RunOutcome:
    """The outcome of a run that was read: its rows and its (JSON-safe) document."""
    from fogts.pipeline import AllanAnalysis
    from fogts.report.text import to_jsonable

    rows = [a.row for a in axes]
    errors = [r["error"] for r in rows if r["status"] == "error"]
    status = "error" if errors else "ok"
    error = errors[0] if errors else ""
    doc = run_document(file, status, error, info, [a.status for a in axes], warned)
    allan_axes = tuple(a.allan for a in axes if a.allan is not None)
    if allan_axes:
        doc["allan"] = AllanAnalysis(run=run, quality=quality, axes=allan_axes).to_dict()
    doc["select"] = [a.selection for a in axes if a.selection is not None]
    doc["options"] = options.to_dict()
    doc["rows"] = rows
    doc = to_jsonable(doc)
    return RunOutcome(file=file, status=status, error=error, rows=tuple(doc["rows"]),
                      document=doc)
