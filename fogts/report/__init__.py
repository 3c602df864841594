"""Presenting results: JSON-safe dicts and messages (:mod:`~fogts.report.text`), figures
(:mod:`~fogts.report.plots`, imported on first use: matplotlib is slow to load) and the
self-contained HTML report (:mod:`~fogts.report.html`, which builds it from
:mod:`~fogts.report.analyses`, :mod:`~fogts.report.sections`, :mod:`~fogts.report.blocks`
and :mod:`~fogts.report.page`)."""

from __future__ import annotations

from fogts.report.text import (
    error_message,
    info_text,
    json_dumps,
    run_info,
    to_jsonable,
    warning_texts,
)

__all__ = ["error_message", "info_text", "json_dumps", "run_info", "to_jsonable",
           "warning_texts"]
