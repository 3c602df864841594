"""`fogts compensate`: start-up temperature-drift model and compensation."""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING, Annotated, Any, Literal

import typer

from fogts import choices
from fogts.cli import _common as common
from fogts.cli._arguments import measurement_noise_value
from fogts.cli._axes import AxisOpt, axis_lines, axis_path, axis_picks, with_axis_column
from fogts.pipeline import ReadSettings

if TYPE_CHECKING:
    from fogts.io.run import Run
    from fogts.startup.startup_workflow import StartupCompensation


def _save_models(save_model: Path | None, run: Run, picks: list[int],
                 results: list[StartupCompensation], many: bool) -> list[Path]:
    """Write each axis' thermal model as JSON (``--save-model``); the paths written.

    A fitted model the likelihood-ratio test does not find significant is saved with its
    note, and a ``warning:`` line says so (the collinearity note warned at the fit)."""
    if save_model is None:
        return []
    from fogts.io.writer import write_text_atomic
    from fogts.report.text import json_dumps

    saved = []
    for i, r in zip(picks, results, strict=True):
        saved.append(axis_path(save_model, run, i, many))
        write_text_atomic(saved[-1], json_dumps(r.model.to_dict()) + "\n")
        if r.significance is not None and not r.significance.significant \
                and r.model.identification_note:
            common.warn(f"{Path(run.source).name}: {run.axes[i]}: --save-model {saved[-1]} "
                        f"is saved with its note: {r.model.identification_note}")
    return saved


def _saved_line(path: Path, result: StartupCompensation) -> str:
    """``saved the thermal model to PATH``, with the model's note in brief."""
    from fogts.startup.thermal_identification import note_in_brief

    brief = note_in_brief(result.model)
    return f"saved the thermal model to {path}" + (f" (with its note: {brief})" if brief else "")


def _check_model_paths(save_model: Path | None, run: Run, picks: list[int], file: Path, *,
                       overwrite: bool) -> None:
    """With several axes, ``--save-model`` writes one file per axis: each is an output
    (:func:`fogts.io.paths.check_outputs`), checked before any analysis."""
    if save_model is None or len(picks) < 2:
        return
    from fogts.io.paths import check_outputs

    check_outputs({f"--save-model ({run.axes[i]})": axis_path(save_model, run, i, True)
                   for i in picks}, {"FILE": [file]}, overwrite=overwrite)


def _kalman_noise(text: str, *, emd: bool, model: Path | None) -> Literal["estimate"] | float:
    """``--measurement-noise``, refused where no Kalman filter runs (``--no-emd``, ``--model``)."""
    from fogts.errors import DataError

    noise = measurement_noise_value(text)
    if noise != "estimate" and (not emd or model is not None):
        skipped = "--no-emd skips" if not emd else "--model skips (nothing is fitted)"
        raise DataError(f"--measurement-noise sets the Kalman filter of the EMD rest, which "
                        f"{skipped}: give one or the other")
    return noise


#: compensate's own library keywords and their options (errors and notes name the options).
_COMPENSATE_OPTIONS = {"average_s": "--average", "dT_smoothing_s": "--dt-smoothing",
                       "arma_model": "--arma-model", "measurement_noise": "--measurement-noise"}


@common.app.command("compensate")
@common.writes_outputs()
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
    measurement_noise: Annotated[str, typer.Option("--measurement-noise", help="--emd: Kalman measurement-noise variance of the gyro rate's EMD rest in (rate unit)^2, or 'estimate' (ML with the ARMA parameters fixed; the temperature's is always estimated).")] = "estimate",
    dt_smoothing: Annotated[float, typer.Option("--dt-smoothing", help="Window in seconds of the temperature-rate (dT/dt) estimate.")] = 60.0,
    apply: Annotated[choices.ApplyRule, typer.Option("--apply", help="Subtract the fitted model only when the likelihood-ratio test finds a significant temperature dependence (significant), or in any case (always). A --model is always applied.")] = "significant",
    axis: AxisOpt = None,
    plot: Annotated[Path | None, typer.Option("--plot", help="Raw rate, trend, compensated rate and temperature: .png, .svg or .pdf.")] = None,
    out: common.Outputs = common.NO_OUTPUTS,
    read: ReadSettings = common.DEFAULT_READ,
) -> None:
    """Fit the start-up temperature-drift model D = aT·dT + bT² + cT + d·dT² + e·dT + f and
    compensate; prints the model and the bias stability before and after.

    With --axis all each axis gets its own model; the JSON is then {"input", "axes": [one
    compensation per axis]}."""
    from fogts.startup.startup_workflow import startup_compensation

    with common.guard(_COMPENSATE_OPTIONS,
                      overwrite=out.overwrite, outputs={"--output": output, "--save-model": save_model, "--json": out.json,
                         "--plot": plot},
                inputs={"FILE": [file], "--model": [model] if model else [],
                        "--calibration": calibration or []}):
        common.check_output_names(plot=plot, output=output)  # before any output is written
        noise = _kalman_noise(measurement_noise, emd=emd, model=model)
        run, quality = common.read_input(file, read)
        picks = axis_picks(run, axis)
        many = len(picks) > 1
        _check_model_paths(save_model, run, picks, file, overwrite=out.overwrite)
        given = common.load_thermal_model(model) if model is not None else None
        extra = [common.read_input(c, read)[0]
                 for c in (calibration or [])]
        from fogts.errors import DataError

        if extra and given is not None:
            raise DataError("--calibration fits a model; it cannot be combined with --model")
        if many and given is not None:
            raise DataError("--model holds the thermal model of one axis: give --axis NAME "
                            "or INDEX, not --axis all")
        results = []
        for i in picks:
            with common.named_warnings(Path(run.source).name, run.axes[i]):
                results.append(startup_compensation(
                    run, axis=i, emd=emd, model=given, arma_model=arma_model,
                    measurement_noise=noise, dT_smoothing_s=dt_smoothing, average_s=average,
                    calibration=extra, apply=apply))
        if output is not None:
            from fogts.io.writer import write_frame_atomic

            write_frame_atomic(output, with_axis_column([r.to_frame() for r in results],
                                                        [r.axis for r in results], many=many))
        saved = _save_models(save_model, run, picks, results, many)
        blocks = [r.to_dict() for r in results]
        if given is not None:
            blocks[0]["thermal"]["source"] = str(model)
        payload: dict[str, Any] = ({"input": str(file), **blocks[0]} if not many
                                   else {"input": str(file), "axes": blocks})
        payload["data_quality"] = quality.to_dict()
        common.emit_json(payload, out.json, _COMPENSATE_OPTIONS)
        if plot is not None:
            from fogts.report.plots import plot_compensation

            for i, r in zip(picks, results, strict=True):
                common.save_figure(plot_compensation(r), axis_path(plot, run, i, many))
        lines = axis_lines(run, picks, axis)
        for r in results:
            lines += ([f"{r.axis}:"] if many else []) + [r.summary()]
        if output is not None:
            lines.append(f"wrote {output} ({run.n * len(results)} rows)")
        lines += [_saved_line(path, r) for path, r in zip(saved, results, strict=False)]
        common.say([common.option_keywords(ln, _COMPENSATE_OPTIONS) for ln in lines], out.json)
