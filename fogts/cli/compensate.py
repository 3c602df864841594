"""`fogts compensate`: start-up temperature-drift model and compensation."""

from __future__ import annotations

from pathlib import Path
from typing import Annotated

import typer

from fogts.cli import _common as common
from fogts.pipeline import ReadSettings


@common.app.command("compensate")
@common.reads_input(gaps=False)
def compensate_cmd(
    file: common.FileArg,
    output: Annotated[Path | None, typer.Option("-o", "--output", help="Output table (.csv or .parquet): time, raw, trend, used, compensated, temperature.")] = None,
    emd: Annotated[bool, typer.Option("--emd/--no-emd", help="Separate the trend by EMD and Kalman-filter the rest before fitting.")] = True,
    save_model: Annotated[Path | None, typer.Option("--save-model", help="Save the fitted thermal model as JSON.")] = None,
    model: Annotated[Path | None, typer.Option("--model", help="Apply a saved thermal model (JSON) instead of fitting one.")] = None,
    calibration: Annotated[list[Path] | None, typer.Option("--calibration", help="Further calibration run(s) fitted together with FILE (repeat the option), e.g. cold starts at other ambient temperatures.")] = None,
    arma_model: Annotated[str, typer.Option("--arma-model", help="ARMA model of the EMD rest: auto, AR(1), AR(2), AR(3), ARMA(1,1), ARMA(2,1).")] = "auto",
    average: Annotated[float, typer.Option("--average", help="Averaging time of the bias stability in seconds (GJB/IEEE: 10 s).")] = 10.0,
    dt_smoothing: Annotated[float, typer.Option("--dt-smoothing", help="Window in seconds of the temperature-rate (dT/dt) estimate.")] = 60.0,
    axis: Annotated[str, typer.Option("--axis", help="Axis to compensate (name or index).")] = "0",
    json_out: common.JsonOpt = None,
    plot: Annotated[Path | None, typer.Option("--plot", help="Raw rate, trend, compensated rate and temperature: .png, .svg or .pdf.")] = None,
    read: ReadSettings = common.DEFAULT_READ,
) -> None:
    """Fit the start-up temperature-drift model D = aT·dT + bT² + cT + d·dT² + e·dT + f and
    compensate; prints the model and the bias stability before and after."""
    from fogts.startup.startup_workflow import startup_compensation

    with common.guard(outputs={"--output": output, "--save-model": save_model, "--json": json_out,
                         "--plot": plot},
                inputs={"FILE": [file], "--model": [model] if model else [],
                        "--calibration": calibration or []}):
        run, quality = common.read_input(file, read)
        pick = common.axis_index(run, axis)
        given = common.load_thermal_model(model) if model is not None else None
        extra = [common.read_input(c, read)[0]
                 for c in (calibration or [])]
        if extra and given is not None:
            from fogts.errors import DataError

            raise DataError("--calibration fits a model; it cannot be combined with --model")
        result = startup_compensation(run, axis=pick, emd=emd, model=given,
                                      arma_model=arma_model, dT_smoothing_s=dt_smoothing,
                                      average_s=average, calibration=extra)
        if output is not None:
            from fogts.io.writer import write_frame_atomic

            write_frame_atomic(output, result.to_frame())
        if save_model is not None:
            from fogts.io.writer import write_text_atomic
            from fogts.report.text import json_dumps

            write_text_atomic(save_model, json_dumps(result.model.to_dict()) + "\n")
        payload = {"input": str(file), **result.to_dict(), "data_quality": quality.to_dict()}
        if given is not None:
            payload["thermal"]["source"] = str(model)
        common.emit_json(payload, json_out)
        if plot is not None:
            from fogts.report.plots import plot_compensation

            common.save_figure(plot_compensation(result), plot)
        lines = [result.summary()]
        if output is not None:
            lines.append(f"wrote {output} ({run.n} rows)")
        if save_model is not None:
            lines.append(f"saved the thermal model to {save_model}")
        common.say(lines, json_out)
