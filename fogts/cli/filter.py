"""`fogts filter`: Kalman filter from the ARMA drift model, or a zero-phase low-pass."""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING, Annotated, Any, Literal

import typer

from fogts import choices
from fogts.cli import _common as common
from fogts.pipeline import ReadSettings

if TYPE_CHECKING:
    from fogts._typing import FloatArray
    from fogts.io.run import Run



@common.app.command("filter")
@common.reads_input()
def filter_cmd(
    file: common.FileArg,
    output: Annotated[Path, typer.Option("-o", "--output", help="Output table (.csv or .parquet): time, observed, filtered (kalman adds smoothed, predicted).")],
    method: Annotated[choices.FilterMethod, typer.Option("--method", help="kalman (ARMA drift model in Harvey state-space form), iir (zero-phase low-pass) or moving-average.")] = "kalman",
    model: Annotated[str, typer.Option("--model", help="Drift model for --method kalman: auto (run the ARMA selection), AR(1), AR(2), AR(3), ARMA(1,1), ARMA(2,1).")] = "auto",
    measurement_noise: Annotated[str, typer.Option("--measurement-noise", help="Kalman measurement-noise variance in (rate unit)^2, or 'estimate' (ML with the ARMA parameters fixed).")] = "estimate",
    cutoff: Annotated[float | None, typer.Option("--cutoff", help="--method iir: cutoff in Hz (zero-phase -3 dB point for butter), below fs/2.")] = None,
    order: Annotated[int, typer.Option("--order", help="--method iir: filter order of one pass.")] = 4,
    design: Annotated[choices.FilterDesign, typer.Option("--design", help="--method iir: the IIR design.")] = "butter",
    window: Annotated[float | None, typer.Option("--window", help="--method moving-average: window in seconds.")] = None,
    compare_allan: Annotated[bool, typer.Option("--compare-allan", help="Allan deviation and noise terms before and after filtering, side by side (with --plot: the overlay figure).")] = False,
    axis: Annotated[str, typer.Option("--axis", help="Axis to filter (name or index).")] = "0",
    json_out: common.JsonOpt = None,
    plot: Annotated[Path | None, typer.Option("--plot", help="Figure (.png, .svg, .pdf): observed/filtered/smoothed for kalman; the before/after Allan overlay with --compare-allan.")] = None,
    read: ReadSettings = common.DEFAULT_READ,
) -> None:
    """Filter a gyro record: Kalman filter with an ARMA drift model, or a
    zero-phase IIR / moving-average low-pass with a before/after Allan comparison.
    """
    with common.guard(outputs={"--output": output, "--json": json_out, "--plot": plot},
                inputs={"FILE": [file]}):
        if method == "kalman":
            noise = _parse_measurement_noise(measurement_noise)
        run, _ = common.read_input(file, read)
        pick = common.axis_index(run, axis)
        x = run.axis(pick)
        if method == "kalman":
            _kalman_filter(run, x, file, output, model, noise, json_out, plot, method)
        else:
            _lowpass_filter(run, x, file, output, method, cutoff, order, design, window,
                            compare_allan, json_out, plot)


def _parse_measurement_noise(text: str) -> Literal["estimate"] | float:
    from fogts.errors import DataError

    if text == "estimate":
        return "estimate"
    try:
        return float(text)
    except ValueError:
        raise DataError("--measurement-noise must be 'estimate' or a variance in "
                        f"(rate unit)^2; got {text!r}") from None


def _kalman_filter(run: Run, x: FloatArray, file: Path, output: Path, model: str,
                   noise: Literal["estimate"] | float,
                   json_out: str | None, plot: Path | None, method: str) -> None:
    import numpy as np
    import pandas as pd

    from fogts.io.writer import write_frame_atomic
    from fogts.startup.kalman import arma_kalman, resolve_arma_model

    fit = resolve_arma_model(x, model)
    result = arma_kalman(x, fit, measurement_noise=noise)
    frame = pd.DataFrame({"time": run.time, "observed": x,
                          "filtered": np.asarray(result.filtered),
                          "smoothed": np.asarray(result.smoothed),
                          "predicted": np.asarray(result.predicted)})
    write_frame_atomic(output, frame)
    fit_dict = fit.to_dict() if hasattr(fit, "to_dict") else {}
    common.emit_json({"input": str(file), "method": method, "units": run.units,
                "model": fit_dict, "kalman": result.to_dict(), "output": str(output)},
               json_out)
    if plot is not None:
        from fogts.report.plots import plot_kalman

        common.save_figure(plot_kalman(result, time_s=run.time, units=run.units), plot)
    equation = fit.equation() if hasattr(fit, "equation") else result.model
    common.say([f"drift model ({'selected by AIC' if model == 'auto' else 'given'}): {equation}",
          result.summary(), f"wrote {output} ({run.n} rows)"], json_out)


def _lowpass_filter(run: Run, x: FloatArray, file: Path, output: Path, method: str,
                    cutoff: float | None, order: int, design: str, window: float | None,
                    compare: bool, json_out: str | None, plot: Path | None) -> None:
    import pandas as pd

    from fogts.errors import DataError
    from fogts.io.writer import write_frame_atomic
    from fogts.preprocess.filters import lowpass, moving_average

    if method == "iir":
        if cutoff is None:
            raise DataError("--method iir needs --cutoff HZ (below the Nyquist frequency "
                            f"{run.fs_hz / 2:g} Hz)")
        result = lowpass(x, fs_hz=run.fs_hz, cutoff_hz=cutoff, order=order,
                         design=design)  # type: ignore[arg-type]
    else:
        if window is None:
            raise DataError("--method moving-average needs --window SECONDS")
        result = moving_average(x, fs_hz=run.fs_hz, window_s=window)
    if plot is not None and not compare:
        raise DataError("--plot with --method iir or moving-average draws the Allan overlay: "
                        "add --compare-allan")
    comparison = None
    if compare:
        from fogts.allan.compare import compare_allan

        comparison = compare_allan(x, result.filtered, fs_hz=run.fs_hz, units=run.units,
                                   cutoff_hz=result.cutoff_hz,
                                   labels=("raw", f"{method} filtered"))
    write_frame_atomic(output, pd.DataFrame({"time": run.time, "observed": x,
                                             "filtered": result.filtered}))
    payload: dict[str, Any] = {"input": str(file), "method": method, "units": run.units,
                               "filter": result.to_dict(), "output": str(output)}
    if comparison is not None:
        payload["compare_allan"] = comparison.to_dict()
    common.emit_json(payload, json_out)
    if plot is not None and comparison is not None:
        from fogts.report.plots import plot_allan_comparison

        common.save_figure(plot_allan_comparison(comparison), plot)
    lines = [result.summary()]
    if comparison is not None:
        lines += ["", "noise terms before and after filtering:", comparison.summary()]
    lines.append(f"wrote {output} ({run.n} rows)")
    common.say(lines, json_out)
