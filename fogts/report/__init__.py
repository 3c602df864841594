"""Presenting results: JSON-safe dicts and messages (:mod:`~fogts.report.text`), figures
(:mod:`~fogts.report.plots`, imported on first use: matplotlib is slow to load) and the
self-contained HTML report (:mod:`~fogts.report.html`, which builds it from
:mod:`~fogts.report.analyses`, :mod:`~fogts.report.sections`, :mod:`~fogts.report.blocks`
and :mod:`~fogts.report.page`)."""

from __future__ import annotations

import importlib
from types import ModuleType

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

#: Submodules loaded on first attribute access (``fogts.report.plots``): matplotlib and
#: jinja2 stay out of ``import fogts.report``.
_LAZY = ("plots", "html")


def __getattr__(name: str) -> ModuleType:
    if name in _LAZY:
        return importlib.import_module(f"fogts.report.{name}")
    raise AttributeError(f"module 'fogts.report' has no attribute {name!r}")
