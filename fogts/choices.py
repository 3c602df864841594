"""The named choices of fogts' options, defined once.

Each choice is a ``Literal`` type (what the library's signatures and mypy use, and what
typer validates and lists in ``--help``) and the tuple of its values (what the library's
run-time checks quote in their errors).  The domain modules re-export the ones they own,
for example :data:`fogts.allan.taus.KINDS`.  This module imports nothing from fogts, so
the CLI reads its choices without importing numpy or pandas.
"""

from __future__ import annotations

from typing import Literal, get_args

__all__ = [
           "APPLY_RULES",
           "CRITERIA",
           "EXPORT_FORMATS",
           "FILTER_DESIGNS",
           "FILTER_METHODS",
           "FIT_METHODS",
           "FLICKER_METHODS",
           "GAP_POLICIES",
           "INPUT_KINDS",
           "KINDS",
           "NAN_POLICIES",
           "OUTPUT_UNITS",
           "ApplyRule",
           "Criterion",
           "ExportFormat",
           "FilterDesign",
           "FilterMethod",
           "FitMethod",
           "FlickerMethod",
           "GapPolicy",
           "InputKind",
           "Kind",
           "NanPolicy",
           "OutputUnits",
]

#: Allan-family estimators.
Kind = Literal["adev", "oadev", "mdev", "hdev", "ohdev", "totdev"]
KINDS: tuple[str, ...] = get_args(Kind)

#: Fits of the IEEE-952 terms to an Allan curve: EDF-weighted, full covariance, unweighted,
#: generalized method of wavelet moments.
FitMethod = Literal["wls", "gls", "ols", "gmwm", "ml"]
FIT_METHODS: tuple[str, ...] = get_args(FitMethod)

#: Criteria that rank ARMA candidates.
Criterion = Literal["aic", "bic", "hqic", "aicc"]
CRITERIA: tuple[str, ...] = get_args(Criterion)

#: When a fitted thermal model is subtracted: only when the likelihood-ratio test finds it
#: significant, or in any case.
ApplyRule = Literal["significant", "always"]
APPLY_RULES: tuple[str, ...] = get_args(ApplyRule)

#: What the reader does with empty, NaN or inf cells.
NanPolicy = Literal["error", "drop", "interpolate"]
NAN_POLICIES: tuple[str, ...] = get_args(NanPolicy)

#: What the analysis does with gaps in the time base.
GapPolicy = Literal["warn", "error", "split", "ignore", "nan"]
GAP_POLICIES: tuple[str, ...] = get_args(GapPolicy)

#: What the sensor columns hold: rate, angle increments per sample, or integrated angle.
InputKind = Literal["rate", "increment", "angle"]
INPUT_KINDS: tuple[str, ...] = get_args(InputKind)

#: Filters of ``fogts filter``.
FilterMethod = Literal["kalman", "iir", "moving-average"]
FILTER_METHODS: tuple[str, ...] = get_args(FilterMethod)

#: IIR low-pass designs.
FilterDesign = Literal["butter", "cheby1", "ellip"]
FILTER_DESIGNS: tuple[str, ...] = get_args(FilterDesign)

#: Flicker (bias-instability) synthesis: a sum of Markov processes, or Kasdin-Walter.
FlickerMethod = Literal["markov", "kasdin"]
FLICKER_METHODS: tuple[str, ...] = get_args(FlickerMethod)

#: Units of the reported noise terms: IEEE-952's degree units, or SI (rad, s, Hz).
OutputUnits = Literal["deg", "si"]
OUTPUT_UNITS: tuple[str, ...] = get_args(OutputUnits)

#: Filter-ready exports of the noise terms (``fogts allan --export``).
ExportFormat = Literal["kalibr", "imu_utils", "json"]
EXPORT_FORMATS: tuple[str, ...] = get_args(ExportFormat)
