"""Reading recordings and writing outputs safely.

The :class:`Run` record (:mod:`fogts.io.run`), the readers (:mod:`fogts.io.reader`), the
input limits (:mod:`fogts.io.limits`: regular files only, size and line caps) and the
output rules (:mod:`fogts.io.paths`: no output replaces an input; atomic writes).
"""

from __future__ import annotations

from fogts.io.paths import check_outputs
from fogts.io.reader import (
    atomic_path,
    read_json,
    read_run,
    write_frame_atomic,
    write_text_atomic,
)
from fogts.io.run import MissingReport, Run, SamplingReport

__all__ = [
    "MissingReport",
    "Run",
    "SamplingReport",
    "atomic_path",
    "check_outputs",
    "read_json",
    "read_run",
    "write_frame_atomic",
    "write_text_atomic",
]
