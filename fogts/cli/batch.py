"""`fogts batch`: info, allan and select on many files, on a process pool or a Dask cluster."""

from __future__ import annotations

from collections.abc import Iterable, Mapping
from pathlib import Path
from typing import TYPE_CHECKING, Annotated, Any

import typer

from fogts import choices
from fogts.cli import _common as common
from fogts.cli._arguments import option_keywords
from fogts.cli.progress import bar_enabled, shows_progress
from fogts.pipeline import ReadSettings

if TYPE_CHECKING:
    from rich.progress import Progress

    from fogts.tables import Table as FogtsTable


@common.app.command("batch")
@shows_progress(library=False)
@common.writes_outputs(json=False)
@common.reads_input()
def batch_cmd(
    patterns: Annotated[list[str], typer.Argument(help="Input files or glob patterns (quote them to let fogts expand '**').")],
    output: Annotated[Path, typer.Option("--output", "-o", help="Summary table (.csv or .parquet): one row per run and axis.")],
    json_dir: Annotated[Path | None, typer.Option("--json-dir", help="Folder for the per-run JSON (default: `SUMMARY_runs` beside the summary).")] = None,
    workers: Annotated[int | None, typer.Option("--workers", help="Local worker processes (default: the number of CPUs).")] = None,
    scheduler: Annotated[str | None, typer.Option("--scheduler", help="Dask scheduler address (tcp://host:8786): run on that cluster instead of locally (needs the fogts\\[dask] extra).")] = None,
    resume: Annotated[bool, typer.Option("--resume", help="Skip runs whose per-run JSON already exists (delete a failed run's JSON to retry it).")] = False,
    kind: common.KindOpt = "oadev",
    taus: Annotated[str, typer.Option("--taus", help="Tau grid: octave, decade, dense, all.")] = "octave",
    detrend: Annotated[int | None, typer.Option("--detrend", help="Polynomial order removed before the ARMA selection.")] = None,
    decimate: Annotated[int | None, typer.Option("--decimate", help="Block-average K samples before the ARMA selection.")] = None,
    criterion: common.CriterionOpt = "aic",
    no_select: Annotated[bool, typer.Option("--no-select", help="Skip the ARMA selection (info and Allan only).")] = False,
    output_units: Annotated[choices.OutputUnits, typer.Option("--output-units", help="Units of the noise terms in the summary: deg (deg/sqrt(h), deg/h, deg/h^1.5) or si (rad/s/sqrt(Hz), rad/s, rad/s^2/sqrt(Hz)); the columns N_unit, B_unit, K_unit name them.")] = "deg",
    spec: common.SpecOpt = None,
    out: common.Outputs = common.NO_OUTPUTS,
    read: ReadSettings = common.DEFAULT_READ,
) -> None:
    """Run info, allan and select on many files; write one summary row per run and axis.

    A bad file gives a row with status=error and the message; the batch goes on. The summary
    has, per term, its value, standard error, 95 % upper limit (a term the data only bound),
    unit and, with --spec, PASS/FAIL/INCONCLUSIVE (columns N, N_stderr, N_upper, N_unit, N_spec, ...), and
    the fit verdict (fit); input_units is the rate unit of the input.

    Exit code 0 if every run is ok, 1 if any failed.
    """
    from fogts.batch import BatchOptions, BatchProgress, run_batch

    with common.guard({"summary_path": "--output", "patterns": "PATTERNS",
                       "output_units": "--output-units"}):
        limits = common.load_spec(spec)
        options = BatchOptions(rate_column=read.rate_column, time_column=read.time_column,
                               temperature_column=read.temperature_column, fs_hz=read.fs_hz,
                               units=read.units, kind=kind, taus=taus, detrend=detrend,
                               decimate=decimate, criterion=criterion, select=not no_select,
                               nan=read.nan, gaps=read.gaps, output_units=output_units,
                               spec=limits)
        bar = _runs_bar()
        task_id: list[Any] = []

        def on_progress(p: BatchProgress) -> None:
            if not task_id:
                task_id.append(bar.add_task("runs", total=p.total, completed=p.done,
                                            failed=p.failed, remaining=p.remaining))
            else:
                bar.update(task_id[0], completed=p.done, failed=p.failed,
                           remaining=p.remaining)

        with bar:
            result = run_batch(patterns, summary_path=output, json_dir=json_dir,
                               workers=workers, scheduler=scheduler, resume=resume,
                               overwrite=out.overwrite,
                               options=options, progress=on_progress)
        common.console.print(result.summary(), markup=False, soft_wrap=True)
        for line in _batch_quality_lines(result.rows):
            common.warn(line)
        errors = [r for r in result.rows if r["status"] == "error"]
        if errors:
            common.print_out(common.rich_table(_failed_runs_table(errors)))
    if result.interrupted:
        common.err_console.print("error: interrupted; rerun with --resume to finish", markup=False)
        raise typer.Exit(common.ExitCode.ERROR)
    raise typer.Exit(common.ExitCode.NEGATIVE if errors else common.ExitCode.OK)


def _runs_bar() -> Progress:
    """The batch's progress bar on stderr: runs done of all, failed, remaining, ETA."""
    from rich.progress import (
        BarColumn,
        MofNCompleteColumn,
        Progress,
        SpinnerColumn,
        TextColumn,
        TimeElapsedColumn,
        TimeRemainingColumn,
    )

    return Progress(SpinnerColumn(), TextColumn("{task.description}"), BarColumn(),
                    MofNCompleteColumn(),
                    TextColumn("failed {task.fields[failed]}, remaining "
                               "{task.fields[remaining]}"),
                    TimeElapsedColumn(), TextColumn("ETA"), TimeRemainingColumn(),
                    console=common.err_console, transient=False, disable=not bar_enabled())


def _failed_runs_table(errors: Iterable[Mapping[str, Any]]) -> FogtsTable:
    """The runs that failed: file and axis (kept whole) and the error message (wrapped)."""
    from fogts.tables import Column
    from fogts.tables import Table as FogtsTable

    return FogtsTable.build("failed runs", (Column("file", numeric=False),
                                            Column("axis", numeric=False),
                                            Column("error", numeric=False, wrap=True)),
                            [(r["file"], r["axis"] or "", option_keywords(str(r["error"])))
                             for r in errors])  # the options to pass, not the keywords


def _batch_quality_lines(rows: Iterable[Mapping[str, Any]]) -> list[str]:
    """One line per data-quality finding across the batch, naming the files (details in
    each run's JSON ``info.data_quality``)."""
    checks = (("units_source", lambda v: v == "assumed", "rate unit assumed (deg/h)"),
              ("n_gaps", lambda v: bool(v), "gaps in the time base"),
              ("n_glitches", lambda v: bool(v), "glitches"))
    lines = []
    for key, flagged, label in checks:
        files = sorted({Path(str(r["file"])).name for r in rows if flagged(r.get(key))})
        if files:
            lines.append(f"{label} in {len(files)} file(s): {', '.join(files)} (see the per-run "
                         "JSON, info.data_quality)")
    return lines
