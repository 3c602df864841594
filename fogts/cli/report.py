"""`fogts report`: one self-contained HTML report of a recording."""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING, Annotated

import typer

from fogts.cli import _common as common
from fogts.cli.progress import shows_progress
from fogts.pipeline import ReadSettings

if TYPE_CHECKING:
    from fogts.report.page import HtmlReport


@common.app.command("report")
@shows_progress()
@common.writes_outputs(json=False)
@common.reads_input()
def report_cmd(
    file: common.FileArg,
    output: Annotated[Path, typer.Option("--output", "-o", help="HTML file to write (self-contained: figures embedded, no network needed).")],
    title: Annotated[str | None, typer.Option("--title", help="Document title (default: `Gyro report: FILE`).")] = None,
    outliers: Annotated[float | None, typer.Option("--outliers", help="Replace samples beyond this many robust sigmas before the ARMA analysis.")] = None,
    detrend: Annotated[int | None, typer.Option("--detrend", help="Polynomial order removed before the ARMA analysis.")] = None,
    decimate: Annotated[int | None, typer.Option("--decimate", help="Block-average K samples before the ARMA analysis.")] = None,
    kind: common.KindOpt = "oadev",
    taus: Annotated[str, typer.Option("--taus", help="Tau grid: octave, decade, dense, all.")] = "octave",
    criterion: common.CriterionOpt = "aic",
    davar_window: Annotated[float | None, typer.Option("--davar-window", help="Dynamic Allan window in seconds (default: a tenth of the record).")] = None,
    output_units: common.OutputUnitsOpt = "deg",
    spec: common.SpecOpt = None,
    method: common.MethodOpt = "wls",
    out: common.Outputs = common.NO_OUTPUTS,
    read: ReadSettings = common.DEFAULT_READ,
) -> None:
    """Write one self-contained HTML report of a recording.

    Sections: the summary (N, B, K per axis, the fit verdict, PASS/FAIL with --spec), input, time series, Allan deviation and noise terms, ARMA selection, prediction, dynamic Allan deviation and the thermal model (the last two when they apply).

    Exit code 1 if a section could not be computed (the report is still written and says why).
    """
    from fogts.report.html import build_report, write_report

    with common.guard({"davar_window_s": "--davar-window"}, overwrite=out.overwrite, outputs={"--output": output},
                      inputs={"FILE": [file], "--spec": [spec] if spec else []}):
        if not output.name.lower().endswith((".html", ".htm")):
            from fogts.errors import DataError

            raise DataError(f"--output must end in .html or .htm (the report is one HTML "
                            f"page); got {output.name!r}")
        limits = common.load_spec(spec)
        run, quality = common.read_input(file, read)
        rep = build_report(run, quality=quality, title=title, outliers=outliers, detrend=detrend,
                           decimate=decimate, kind=kind, taus=taus, criterion=criterion,
                           davar_window_s=davar_window, output_units=output_units,
                           spec=limits, methods=method.split(","))
        rep = _options_named(rep)
        write_report(output, rep)
        failed = [s for s in rep.sections if s.status != "ok"]
        for s in failed:
            common.warn(f"{s.title}: {s.message}")
        common.console.print(f"wrote {output} ({len(rep.sections)} sections, {rep.n_figures} "
                      f"figures)", markup=False, soft_wrap=True)
        for part, why in rep.omitted:
            common.console.print(f"not included: {part}: {why}", markup=False, soft_wrap=True)
    raise typer.Exit(common.ExitCode.NEGATIVE if failed else common.ExitCode.OK)


def _options_named(rep: HtmlReport) -> HtmlReport:
    """The report with the options the user typed where its messages suggest a library
    keyword (``pass units=`` becomes ``pass --units``): the data-quality findings, the
    sections' notes and errors, the reasons a part was left out.  The tables and the
    file's comment lines, whose text comes from the input, stay as they are."""
    from dataclasses import replace

    from fogts.report.sections import QUALITY_CAPTION

    named = common.option_keywords
    sections = tuple(replace(
        s, message=named(s.message), notes=tuple(named(n) for n in s.notes),
        blocks=tuple(replace(b, items=tuple(named(i) for i in b.items))
                     if b.kind == "list" and b.caption == QUALITY_CAPTION else b
                     for b in s.blocks)) for s in rep.sections)
    return replace(rep, sections=sections, omitted=tuple((part, named(why))
                                                         for part, why in rep.omitted))
