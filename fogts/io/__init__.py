"""Reading recordings and writing outputs safely.

The :class:`Run` record (:mod:`fogts.io.run`); the readers (:mod:`fogts.io.reader`, which
dispatches to the format families :mod:`fogts.io.text` and :mod:`fogts.io.arrays`, then gives
the columns their roles, :mod:`fogts.io.columns`, applies the missing-cell policy,
:mod:`fogts.io.missing`, and builds the time base, :mod:`fogts.io.timebase`); the input
limits (:mod:`fogts.io.limits`: regular files only, size and line caps); the output rules
(:mod:`fogts.io.paths`: no output replaces an input) and atomic writes
(:mod:`fogts.io.writer`).
"""

from __future__ import annotations

from fogts.io.paths import check_outputs
from fogts.io.reader import read_json, read_run
from fogts.io.run import MissingReport, Run, SamplingReport
from fogts.io.writer import atomic_path, write_frame_atomic, write_text_atomic

__all__ = ["MissingReport", "Run", "SamplingReport", "atomic_path", "check_outputs", "read_json",
           "read_run", "write_frame_atomic", "write_text_atomic"]
