"""One self-contained HTML document per run: ``fogts report FILE -o report.html``.

The report is built in two steps:

1. :func:`build_report` runs the analyses on a :class:`~fogts.io.run.Run`
   (:mod:`fogts.report.analyses`) and collects, per section, figures (matplotlib figures from
   :mod:`fogts.report.plots`, embedded as SVG or PNG ``data:`` URIs), tables and text
   (:mod:`fogts.report.sections`).  Each section says in one sentence what it shows and how
   to read it.  A part that fails becomes a section with its error message (nothing fails
   silently, and one failed analysis does not cost the whole report).
2. :meth:`HtmlReport.render` fills the jinja2 template ``fogts/report/templates/report.html.j2``
   with autoescaping on, so file names, column names and comment lines from the input
   file - which are untrusted - are shown as text and never interpreted as HTML
   (:mod:`fogts.report.page`).

The document needs nothing from the network: styles are inline, figures are data URIs, it
has no script, and its Content-Security-Policy forbids loading anything else.

Examples
--------
>>> import numpy as np
>>> from fogts.io.reader import read_run
>>> rng = np.random.default_rng(0)
>>> run = read_run(rng.normal(size=3000), fs_hz=10.0)
>>> rep = build_report(run, title="bench unit 7", parts=("input", "timeseries"))
>>> [s.id for s in rep.sections]
['input', 'timeseries']
>>> html = rep.render()
>>> html.startswith("<!DOCTYPE html>") and "bench unit 7" in html
True
"""

from __future__ import annotations

import datetime as _dt
import os
from collections.abc import Sequence
from functools import partial
from pathlib import Path
from typing import TYPE_CHECKING, Any

from fogts import progress
from fogts.allan.dynamic import MIN_WINDOW_SAMPLES
from fogts.errors import DataError
from fogts.io.run import Run
from fogts.report.analyses import ReportContext, analyse_run
from fogts.report.blocks import MAX_SVG_BYTES as MAX_SVG_BYTES
from fogts.report.blocks import figure_block, fmt_num
from fogts.report.page import Block, HtmlReport, Section
from fogts.report.sections import AXIS_BUILDERS, RUN_BUILDERS, SECTION_TITLES, make_section
from fogts.report.text import duration_text

if TYPE_CHECKING:
    from fogts.allan.datasheet import NoiseSpec
    from fogts.choices import OutputUnits

__all__ = [
    "PARTS",
    "Block",
    "HtmlReport",
    "Section",
    "build_report",
    "figure_block",
    "write_report",
]

#: The report's parts, in order.  ``davar`` runs only on records long enough for it, and
#: ``thermal`` only with a temperature column.
PARTS: tuple[str, ...] = ("summary", "input", "timeseries", "allan", "arma", "prediction",
                          "davar", "thermal")

#: DAVar needs at least this many windows...
DAVAR_MIN_WINDOWS = 10
#: ... of at least this many samples each: the minimum of
#: :func:`~fogts.allan.dynamic.dynamic_allan` itself (``fogts davar --window``).
DAVAR_MIN_WINDOW_SAMPLES = MIN_WINDOW_SAMPLES


def build_report(
    run: Run,
    *,
    quality: Any = None,
    title: str | None = None,
    parts: Sequence[str] = PARTS,
    outliers: float | None = None,
    detrend: int | None = None,
    decimate: int | None = None,
    kind: str = "oadev",
    taus: str = "octave",
    criterion: str = "aic",
    davar_window_s: float | None = None,
    bias_average_s: float = 10.0,
    output_units: OutputUnits = "deg",
    spec: NoiseSpec | None = None,
    methods: Sequence[str] = ("wls",),
) -> HtmlReport:
    """Run the analyses on ``run`` and collect the report's sections.

    Parameters
    ----------
    run : Run
        The recording (from :func:`fogts.io.reader.read_run`).
    quality : DataQuality, optional
        Its hygiene (:func:`fogts.preprocess.hygiene.assess_run`); computed with the default gap
        policy (warn) when not given.  Shown in the input section.
    title : str, optional
        Document title (default: "Gyro report: <file name>").
    parts : sequence of str
        Which parts to include, from :data:`PARTS` (default: all that apply).
    outliers, detrend, decimate
        Preprocessing before the ARMA analysis (see :func:`fogts.preprocess.prepare`).
    kind, taus
        Allan estimator and tau grid.
    criterion : str
        ARMA ranking criterion.
    davar_window_s : float, optional
        DAVar window (default: a tenth of the record, at least
        :data:`DAVAR_MIN_WINDOW_SAMPLES` samples).
    bias_average_s : float
        Averaging time of the bias stability in the thermal section.
    output_units : {"deg", "si"}
        Units of the summary's noise terms (:func:`fogts.units.term_unit`).
    spec : NoiseSpec, optional
        Datasheet limits (:class:`fogts.allan.datasheet.NoiseSpec`): PASS/FAIL per term in
        the summary.
    methods : sequence of str
        Noise-fit methods (:data:`fogts.choices.FIT_METHODS`), each once; the first is the
        fit the report shows, and with more than one the Allan section adds a table of
        every method's terms side by side (:mod:`fogts.allan.noise_compare`).

    Returns
    -------
    HtmlReport

    Raises
    ------
    DataError
        An unknown part or method, a method twice, or ``run`` is not a Run.
    """
    from fogts._validate import check_choice
    from fogts.choices import OUTPUT_UNITS

    check_choice("output_units", output_units, OUTPUT_UNITS)
    wanted, bias_average_s, davar_window_s = _checked_arguments(
        run, parts, kind, taus, criterion, bias_average_s, davar_window_s)
    ctx = analyse_run(run, quality, {"outliers": outliers, "detrend": detrend,
                                   "decimate": decimate, "kind": kind, "taus": taus,
                                   "criterion": criterion, "davar_window_s": davar_window_s,
                                   "bias_average_s": bias_average_s,
                                   "output_units": output_units, "spec": spec,
                                   "methods": _checked_methods(methods)})
    sections, omitted = _collect_sections(ctx, wanted)
    return _assemble(ctx.run, title, sections, omitted,
                     ctx.quality.grid_note(ctx.run.n) if ctx.quality is not None else "")


def write_report(path: str | os.PathLike[str], report: HtmlReport) -> Path:
    """Render ``report`` and write it atomically to ``path``."""
    from fogts.io.writer import write_text_atomic

    return write_text_atomic(path, report.render())


# --------------------------------------------------------------------------- build steps


def _checked_arguments(run: Any, parts: Sequence[str], kind: str, taus: str, criterion: str,
                       bias_average_s: float, davar_window_s: float | None
                       ) -> tuple[list[str], float, float | None]:
    """Validate :func:`build_report`'s arguments: (wanted parts, bias averaging time, DAVar
    window)."""
    from fogts._validate import check_choice, check_positive

    if not isinstance(run, Run):
        raise DataError(f"run must be a fogts Run (see fogts.io.reader.read_run), got "
                        f"{type(run).__name__}")
    wanted = list(parts)
    for p in wanted:
        check_choice("parts", p, PARTS)
    check_choice("kind", kind, ("adev", "oadev", "mdev", "hdev", "ohdev", "totdev"))
    check_choice("taus", taus, ("octave", "decade", "dense", "all"))
    check_choice("criterion", criterion, ("aic", "bic", "hqic", "aicc"))
    bias_average_s = check_positive("bias_average_s", bias_average_s)
    if davar_window_s is not None:
        davar_window_s = check_positive("davar_window_s", davar_window_s)
    return wanted, bias_average_s, davar_window_s


def _checked_methods(methods: Sequence[str]) -> tuple[str, ...]:
    """``methods``: one or more of the fit methods, each once."""
    from fogts._validate import check_choice
    from fogts.choices import FIT_METHODS

    picked = (methods,) if isinstance(methods, str) else tuple(methods)
    if not picked:
        raise DataError(f"methods must name one or more of {', '.join(FIT_METHODS)}, got "
                        f"{methods!r}")
    for m in picked:
        check_choice("methods", m, FIT_METHODS)
    twice = [m for i, m in enumerate(picked) if m in picked[:i]]
    if twice:
        raise DataError(f"methods must name each method once; {twice[0]!r} is given twice "
                        f"in {methods!r}")
    return picked


def _collect_sections(ctx: ReportContext, wanted: Sequence[str]
                      ) -> tuple[list[Section], list[tuple[str, str]]]:
    """The wanted parts in :data:`PARTS` order: their sections, and the parts left out with
    the reason.  The summary is built last (it shows the verdicts of the sections that ran,
    such as the dynamic Allan deviation's) and placed first."""
    sections: list[Section] = []
    omitted: list[tuple[str, str]] = []
    parts = [part for part in PARTS if part in wanted]
    tick = progress.ticker(f"report: {len(parts)} parts", len(parts))
    for done, part in enumerate([p for p in parts if p != "summary"] + (
            ["summary"] if "summary" in parts else [])):
        tick(done)
        if part in RUN_BUILDERS:
            section = make_section(part, part, SECTION_TITLES[part],
                                   partial(RUN_BUILDERS[part], ctx))
            # the summary is PARTS' first part
            sections.insert(0 if part == "summary" else len(sections), section)
            continue
        reason = _omission(ctx, part)
        if reason is not None:
            omitted.append((SECTION_TITLES[part], reason))
        else:
            sections.extend(_axis_sections(ctx, part))
    tick(len(parts))
    return sections, omitted


def _omission(ctx: ReportContext, part: str) -> str | None:
    """Why ``part`` does not apply to the run, or None; for ``davar`` this also settles the
    window (``ctx.options["davar_window_s"]``)."""
    run = ctx.run
    if part == "davar":
        window = _davar_window(run, ctx.options["davar_window_s"])
        if window is None:
            return _davar_too_short(run, ctx.options["davar_window_s"])
        ctx.options["davar_window_s"] = window
    elif part == "thermal" and run.temperature is None:
        return ("the file has no temperature column (name it T or temperature, or pass "
                "temperature_column=)")
    return None


def _axis_sections(ctx: ReportContext, part: str) -> list[Section]:
    """One section of ``part`` per rate axis (titled with the axis when there are several)."""
    run = ctx.run
    builder = AXIS_BUILDERS[part]
    sections = []
    for i in range(run.n_axes):
        suffix = f" — axis {run.axes[i]}" if run.n_axes > 1 else ""
        sections.append(make_section(f"{part}-{i + 1}", part, SECTION_TITLES[part] + suffix,
                                 partial(builder, ctx, i)))
    return sections


def _assemble(run: Run, title: str | None, sections: list[Section],
              omitted: list[tuple[str, str]], grid_note: str = "") -> HtmlReport:
    """The report with its title, source line (``grid_note``: the missing samples a
    ``gaps="nan"`` count includes), time stamp and version."""
    from fogts._version import __version__

    name = Path(run.source).name if run.source and not run.source.startswith("<") \
        else run.source
    return HtmlReport(
        title=title if title else f"Gyro report: {name}",
        source=f"{run.source} — {run.n:,} samples at {fmt_num(run.fs_hz, 6)} Hz "
               f"({duration_text(run.duration_s)}{grid_note}), rate in {run.units}",
        generated=_dt.datetime.now(_dt.UTC).strftime("%Y-%m-%d %H:%M UTC"),
        version=__version__, sections=tuple(sections), omitted=tuple(omitted))


# --------------------------------------------------------------------------- DAVar window


def _davar_window(run: Run, window_s: float | None) -> float | None:
    """The DAVar window in seconds, or None if the record is too short for one."""
    min_window = DAVAR_MIN_WINDOW_SAMPLES / run.fs_hz
    if window_s is None:
        window_s = max(run.duration_s / DAVAR_MIN_WINDOWS, min_window)
    if window_s < min_window or run.duration_s < DAVAR_MIN_WINDOWS * window_s - 1e-9:
        return None
    return window_s


def _davar_too_short(run: Run, window_s: float | None = None) -> str:
    """Why the dynamic Allan deviation does not run: the record is too short for it, or
    the given window (``davar_window_s``) does not fit the record."""
    need = DAVAR_MIN_WINDOWS * DAVAR_MIN_WINDOW_SAMPLES
    min_window = DAVAR_MIN_WINDOW_SAMPLES / run.fs_hz
    longest = run.duration_s / DAVAR_MIN_WINDOWS
    if window_s is not None and longest >= min_window:
        return (f"the given window ({window_s:g} s) does not fit this record: a window needs "
                f"at least {DAVAR_MIN_WINDOW_SAMPLES} samples ({min_window:g} s at "
                f"{fmt_num(run.fs_hz, 6)} Hz) and the record ({run.duration_s:g} s) must "
                f"hold {DAVAR_MIN_WINDOWS} of them, so it may be {min_window:g} .. "
                f"{longest:g} s")
    return (f"the record has {run.n:,} samples; the dynamic Allan deviation needs at least "
            f"{DAVAR_MIN_WINDOWS} windows of {DAVAR_MIN_WINDOW_SAMPLES} samples ({need:,} "
            "samples)")
