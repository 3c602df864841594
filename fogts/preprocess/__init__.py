"""From a read record to an analysable series: hygiene checks (:mod:`~fogts.preprocess.gaps`,
:mod:`~fogts.preprocess.glitches`, brought together with the missing values and the unit in
:mod:`~fogts.preprocess.hygiene`), preparation (axis, decimation, detrending, outliers,
stationarity tests) and the signal filters."""

from __future__ import annotations

from fogts.preprocess.filters import FilterResult, lowpass, moving_average
from fogts.preprocess.gaps import GapReport, find_gaps
from fogts.preprocess.glitches import GlitchReport, detect_glitches
from fogts.preprocess.hygiene import GAP_POLICIES, DataQuality, assess_run
from fogts.preprocess.prepare import Prepared, prepare

__all__ = ["GAP_POLICIES", "DataQuality", "FilterResult", "GapReport", "GlitchReport", "Prepared",
           "assess_run", "detect_glitches", "find_gaps", "lowpass", "moving_average", "prepare"]
