"""`fogts davar`: the dynamic Allan deviation."""

from __future__ import annotations

from pathlib import Path
from typing import Annotated

import typer

from fogts import choices
from fogts.cli import _common as common
from fogts.cli._axes import EveryAxisOpt
from fogts.cli.progress import shows_progress
from fogts.pipeline import ReadSettings


@common.app.command("davar")
@shows_progress()
@common.writes_outputs()
@common.reads_input()
def davar_cmd(
    file: common.FileArg,
    window: Annotated[str, typer.Option("--window", help="Window length: 200s, 5min, ....")] = "200s",
    step: Annotated[str, typer.Option("--step", help="Step between windows: 20s, 1min, ...")] = "20s",
    kind: Annotated[choices.Kind, typer.Option("--kind", help="Estimator per window (oadev, mdev and ohdev are the fast ones).")] = "oadev",
    taus: Annotated[str, typer.Option("--taus", help="Tau grid within the window: octave, decade, dense, all, or taus in s separated by commas.")] = "octave",
    axis: EveryAxisOpt = None,
    confidence: Annotated[float, typer.Option("--confidence", help="Confidence level of each window's interval.")] = 0.683,
    min_change: Annotated[float, typer.Option("--min-change", help="Smallest relative change of the deviation called non-stationary (0.1 = 10 %); a significant smaller change is reported as stationary within it.")] = 0.10,
    plot: Annotated[Path | None, typer.Option("--plot", help="Heat map of log deviation over (time, tau): .png, .svg or .pdf.")] = None,
    out: common.Outputs = common.NO_OUTPUTS,
    read: ReadSettings = common.DEFAULT_READ,
) -> None:
    """Dynamic Allan deviation (DAVAR, Galleani & Tavella 2009): the deviation in a
    window sliding along the record, and a non-stationarity score."""
    from fogts.allan.dynamic import dynamic_allan
    from fogts.units import parse_duration

    with common.guard({"min_change": "--min-change", "window_s": "--window", "step_s": "--step"}, overwrite=out.overwrite, outputs={"--json": out.json, "--plot": plot},
                      inputs={"FILE": [file]}):
        common.check_output_names(plot=plot)  # before any output is written
        window_s = parse_duration(window, "--window")
        step_s = parse_duration(step, "--step")
        tau_spec = common.tau_option(taus)
        run, quality = common.read_input(file, read)
        pick = None if axis is None else common.axis_index(run, axis)
        result = dynamic_allan(run, window_s=window_s, step_s=step_s, kind=kind,  # type: ignore[arg-type]
                               min_change=min_change, glitches=quality,
                               taus=tau_spec, confidence=confidence, axis=pick)
        payload = {"input": str(file), **result.to_dict(), "data_quality": quality.to_dict()}
        common.emit_json(payload, out.json)
        if plot is not None:
            from fogts.report.plots import plot_dynamic_allan

            common.save_figure(plot_dynamic_allan(result), plot)
        target = common.err_console if out.json == "-" else common.console
        target.print(result.summary(), markup=False, soft_wrap=True)
