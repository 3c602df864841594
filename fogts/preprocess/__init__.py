"""From a read record to an analysable series: hygiene checks (gaps, glitches, missing
values), preparation (axis, decimation, detrending, outliers, stationarity tests) and the
signal filters."""

from __future__ import annotations

from fogts.preprocess.filters import FilterResult, lowpass, moving_average
from fogts.preprocess.hygiene import (
    GAP_POLICIES,
    DataQuality,
    GapReport,
    GlitchReport,
    assess_run,
    detect_glitches,
    find_gaps,
)
from fogts.preprocess.prepare import Prepared, prepare

__all__ = [
    "GAP_POLICIES",
    "DataQuality",
    "FilterResult",
    "GapReport",
    "GlitchReport",
    "Prepared",
    "assess_run",
    "detect_glitches",
    "find_gaps",
    "lowpass",
    "moving_average",
    "prepare",
]
