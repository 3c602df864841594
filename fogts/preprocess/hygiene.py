"""Data hygiene of one recording: units, missing cells, gaps and glitches, said up front.

Every command runs :func:`assess_run` right after reading, so that what could make an
answer wrong is printed before the answer, and recorded in the JSON:

* the rate unit was assumed (no unit in the column names, no ``units=``);
* empty/NaN cells were dropped or interpolated (:class:`fogts.io.run.MissingReport`);
* the time base has gaps (:class:`~fogts.preprocess.gaps.GapReport`), handled by the gap
  policy: ``warn`` (analyse as if regular and say so), ``error``, ``split`` (the longest
  regular segment), ``nan`` (the whole record on the regular grid, NaN where samples are
  missing, for the gap-robust ADEV :func:`fogts.allan.gradev.gradev`) or ``ignore`` (no
  warning; still recorded);
* glitches: samples far outside the noise that arrive by a jump
  (:func:`~fogts.preprocess.glitches.detect_glitches`);
* a position column (``position_deg``, as a north-seeking record has): the record is not
  static, it turns between positions (:func:`position_column`).

Nothing here changes the data except ``gaps="split"`` and ``gaps="nan"``, which are
recorded.
"""

from __future__ import annotations

import re
from dataclasses import dataclass
from typing import Any

import pandas as pd

from fogts._validate import check_choice
from fogts.choices import GAP_POLICIES, GapPolicy
from fogts.errors import DataError
from fogts.io.run import MissingReport, Run, held_time
from fogts.io.timebase import burst_logging_text
from fogts.preprocess.gaps import Gap, GapReport, fill_gaps_nan, find_gaps, segment_run
from fogts.preprocess.glitches import GLITCH_SIGMAS, Glitch, GlitchReport, detect_glitches
from fogts.units import quantity_of

__all__ = ["GAP_POLICIES", "GLITCH_SIGMAS", "POSITION_NAMES", "DataQuality", "Gap", "GapReport",
           "Glitch", "GlitchReport", "assess_run", "detect_glitches", "find_gaps",
           "position_column"]



@dataclass(frozen=True)
class DataQuality:
    """What :func:`assess_run` found, and what it did (only ``gaps="split"`` changes the
    data: the longest regular segment is analysed).

    Attributes
    ----------
    source, units, units_source : str
    missing : MissingReport or None
    gap_policy : str
    gaps : GapReport
    segment : tuple of (int, int) or None
        Rows analysed under ``gaps="split"`` (None otherwise).
    n_input : int
        Samples read (before any split).
    glitches : tuple of GlitchReport
        One per axis (empty when glitch detection was off).
    outliers : float or None
        The ``outliers`` (K) of the analysis that follows (samples beyond K robust sigmas
        replaced): the glitch lines then say so; None: the glitches stay in the analysis.
    position_column : str or None
        A column of turn-table positions beside the rate (:func:`position_column`): the
        record turns between positions and is not the static record an Allan or ARMA
        analysis assumes.
    """

    source: str
    units: str
    units_source: str
    axes: tuple[str, ...]
    missing: MissingReport | None
    gap_policy: str
    gaps: GapReport
    segment: tuple[int, int] | None
    n_input: int
    fs_hz: float
    glitches: tuple[GlitchReport, ...] = ()
    outliers: float | None = None
    position_column: str | None = None

    def glitch_count(self, axis: str) -> int:
        """Glitch events found on ``axis`` (0 when detection was off)."""
        return next((g.n_events for g in self.glitches if g.axis == axis), 0)

    def grid_note(self, n: int) -> str:
        """What a count of ``n`` samples includes: ``"; 60,000 of them missing (NaN) in the
        time stamps' gaps"`` when ``gaps="nan"`` put the record on its regular grid (``n``
        grid points for the ``n_input`` samples read), else ``""``."""
        missing = n - self.n_input if self.gap_policy == "nan" else 0
        return (f"; {missing:,} of them missing (NaN) in the time stamps' gaps"
                if missing > 0 else "")

    def warnings(self) -> list[str]:
        """The lines a command prints (after ``warning: <file>:``) before its output."""
        out: list[str] = []
        if self.units_source == "assumed":
            cols = ", ".join(repr(a) for a in self.axes)
            out.append(f"no unit in the rate column(s) {cols}; assuming {self.units}; pass "
                       "units= (deg/h, deg/s, rad/s, arcsec/s)")
        if self.position_column is not None:
            out.append(f"column {self.position_column!r} holds turn-table positions: the "
                       "record is not static (it turns between positions), so its Allan "
                       "curve and noise terms (K above all) measure the steps between the "
                       "positions' rates; for north-finding use fogts northfind, or analyse "
                       "one position's rows")
        if self.missing is not None:
            out.append(self.missing.summary())
        out += self._gap_lines()
        fate = GLITCHES_KEPT if self.outliers is None else glitches_replaced(self.outliers)
        out += [f"axis {g.axis!r}: {g.summary()}; {fate}" for g in self.glitches
                if g.n_events]
        return out

    def _gap_lines(self) -> list[str]:
        g = self.gaps
        if self.gap_policy == "ignore" or g.n_gaps == 0:
            return [] if self.gap_policy == "ignore" or g.jitter_rel < 0.01 or g.burst_logged \
                else [f"time steps jitter by {100 * g.jitter_rel:.3g} % of the nominal step; "
                      "analysed as if regular"]
        if self.gap_policy == "nan":
            return [f"{g.summary()}; gaps='nan': the whole record on the regular grid, "
                    "missing samples as NaN, gap-robust overlapping ADEV (Sesia & Tavella "
                    "2008)"]
        if self.segment is not None:
            a, b = self.segment
            return [f"{g.summary()}; gaps='split': analysing the longest regular segment, "
                    f"rows {a}..{b - 1} ({b - a:,} of {self.n_input:,} samples, "
                    f"{(b - a) / self.fs_hz:.6g} s) of {len(g.segments)}"]
        if g.burst_logged:  # word for word the read's warning (the CLI prints it once)
            return [burst_logging_text(self.fs_hz)]
        return [f"{g.summary()}; analysed as if the samples were regular (gaps='split' "
                "analyses the longest regular segment, gaps='error' refuses the file)"]

    def to_dict(self) -> dict[str, Any]:
        return {"units": self.units, "units_source": self.units_source,
                "missing": self.missing.to_dict() if self.missing is not None else None,
                "gap_policy": self.gap_policy, "gaps": self.gaps.to_dict(),
                "segment": ({"start_row": self.segment[0], "stop_row": self.segment[1],
                             "n": self.segment[1] - self.segment[0]}
                            if self.segment is not None else None),
                "glitches": [g.to_dict() for g in self.glitches],
                "warnings": self.warnings()}

    def to_frame(self) -> pd.DataFrame:
        """One row per warning (column ``text``): empty when nothing was found."""
        return pd.DataFrame({"text": self.warnings()}, dtype=object)

    def summary(self) -> str:
        lines = self.warnings()
        return "\n".join(lines) if lines else "no data-quality issue found"


#: What the glitch warning says of the glitches when the analysis keeps them.
GLITCHES_KEPT = "kept in the analysis (outliers=K replaces samples beyond K robust sigmas)"


def glitches_replaced(outliers: float) -> str:
    """What the glitch warning says instead of :data:`GLITCHES_KEPT` when the command
    replaces outliers beyond ``outliers`` robust sigmas before its analysis.

    Examples
    --------
    >>> glitches_replaced(7.0)
    'outliers=7: samples beyond 7 robust sigmas are replaced before the analysis (counted below)'
    """
    return (f"outliers={outliers:g}: samples beyond {outliers:g} robust sigmas are replaced "
            "before the analysis (counted below)")


#: Column names of turn-table positions (``position_deg``, the default of ``fogts
#: northfind --position-column`` and of ``fogts simulate northfind``'s files).
POSITION_NAMES = re.compile(r"position(_?deg(rees)?)?", re.IGNORECASE)


def position_column(run: Run) -> str | None:
    """The first column of ``run`` named as turn-table positions (:data:`POSITION_NAMES`)
    that is not one of its rate axes (one read as an axis was asked for), else None.

    Examples
    --------
    >>> import numpy as np
    >>> from fogts.io.run import Run
    >>> run = Run(rate=np.zeros(4), time=np.arange(4.0), fs_hz=1.0, units="deg/h",
    ...           axes=("rate",), columns=("time", "position_deg", "rate"))
    >>> position_column(run)
    'position_deg'
    """
    return next((c for c in run.columns
                 if POSITION_NAMES.fullmatch(c) and c not in run.axes), None)


def assess_run(run: Run, *, gaps: GapPolicy = "warn", glitches: bool = True,
               glitch_threshold: float = GLITCH_SIGMAS) -> tuple[Run, DataQuality]:
    """Check one recording before analysis: units, missing cells, gaps, glitches.

    Parameters
    ----------
    run : Run
    gaps : {"warn", "error", "split", "ignore"}
        ``warn``: analyse as if regular, and say so; ``error``: raise if there are gaps;
        ``split``: return the longest regular segment; ``ignore``: no warning (the gaps
        are still in the report).
    glitches : bool
        Run :func:`detect_glitches` on every axis.
    glitch_threshold : float
        In robust sigmas.

    Returns
    -------
    (Run, DataQuality)
        The run to analyse (a segment under ``split``) and what was found.

    Raises
    ------
    DataError
        ``gaps="error"`` and the time base has gaps.

    Examples
    --------
    >>> import numpy as np
    >>> from fogts.io.reader import read_run
    >>> run, q = assess_run(read_run(np.random.default_rng(0).standard_normal(1000),
    ...                              fs_hz=10.0))
    >>> q.warnings()
    ["no unit in the rate column(s) 'rate'; assuming deg/h; pass units= (deg/h, deg/s, rad/s, arcsec/s)"]
    """
    check_choice("gaps", gaps, GAP_POLICIES)
    report = find_gaps(run.time, fs_hz=run.fs_hz, sampling=run.sampling) \
        if run.sampling is not None and run.sampling.n_gaps else \
        GapReport(0, 0.0, 1.0 / run.fs_hz, (), ((0, run.n),),
                  run.sampling.jitter_rel if run.sampling is not None else 0.0,
                  run.sampling is not None and run.sampling.fs_source == "mean step")
    if gaps == "error" and report.n_gaps:
        raise DataError(f"{run.source}: {report.summary()}; gaps='error' "
                        "refuses it: pass "
                        + ("gaps='warn'" if report.burst_logged else "gaps='split' to analyse "
                           "the longest regular segment or gaps='warn'"))
    segment = report.longest_segment() if gaps == "split" and report.n_gaps else None
    if segment is not None and report.burst_logged:
        raise DataError(f"{run.source}: gaps='split' needs regular stretches "
                        "between gaps, and these time stamps are logged in bursts: the longest "
                        f"stretch is {segment[1] - segment[0]:,} of {run.n:,} samples; use "
                        "gaps='warn' (the record at its mean rate)")
    n_input = run.n
    if segment is not None:
        run = segment_run(run, *segment)
    found = tuple(detect_glitches(run.axis(i), time_s=held_time(run), fs_hz=run.fs_hz,
                                  threshold=glitch_threshold,
                                  axis=name, units=run.unit_of(i))
                  for i, name in enumerate(run.axes)) if glitches else ()
    if gaps == "nan" and report.n_gaps:
        run = fill_gaps_nan(run)
    # the unit warning names the rate axes only: accelerometer axes have their own unit
    rate_axes = tuple(a for i, a in enumerate(run.axes) if quantity_of(run.unit_of(i)) == "rate")
    quality = DataQuality(run.source, run.units, run.units_source, rate_axes, run.missing,
                          gaps, report, segment, n_input, run.fs_hz, found,
                          position_column=position_column(run))
    return run, quality
