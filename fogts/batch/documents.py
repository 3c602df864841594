"""The per-run JSON document and the summary rows it carries.

The document (layout version :data:`RUN_JSON_VERSION`) holds the run's status and first
error, its ``info``, the ``allan`` and ``select`` documents of :mod:`fogts.pipeline`, one
status per axis, the warnings raised while reading it, the analysis options and its summary
rows (columns :data:`~fogts.batch.records.SUMMARY_COLUMNS`).
"""

from __future__ import annotations

from typing import Any

from fogts.batch.records import SUMMARY_COLUMNS, RunOutcome

__all__ = ["RUN_JSON_VERSION", "blank_row", "error_outcome", "run_document"]

#: Version of the per-run JSON layout (bumped on incompatible changes).
RUN_JSON_VERSION = 3


def blank_row(file: str, axis: str = "") -> dict[str, Any]:
    """A summary row of ``file`` and ``axis`` with status ``ok`` and every result empty."""
    row: dict[str, Any] = dict.fromkeys(SUMMARY_COLUMNS, None)
    row.update(file=file, axis=axis, status="ok", error="")
    return row


def run_document(file: str, status: str, error: str, info: dict[str, Any],
                 axes: list[dict[str, Any]], warn: list[str]) -> dict[str, Any]:
    """The per-run JSON of ``file``, without Allan or selection results and rows."""
    from fogts._version import __version__

    return {"version": RUN_JSON_VERSION, "fogts": __version__, "file": file, "status": status,
            "error": error, "info": info, "allan": None, "select": [], "axes": axes,
            "warnings": warn, "rows": []}


def error_outcome(file: str, message: str, *, persist: bool,
                  document: dict[str, Any] | None = None) -> RunOutcome:
    """The outcome of a run that failed as a whole: one error row with an empty axis.

    ``document`` (default: an empty error document) receives that row.
    """
    row = blank_row(file)
    row.update(status="error", error=message)
    doc = document if document is not None else run_document(file, "error", message, {}, [],
                                                             [])
    doc["rows"] = [row]
    return RunOutcome(file=file, status="error", error=message, rows=(row,), document=doc,
                      persist=persist)
