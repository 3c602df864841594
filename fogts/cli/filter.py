"""`fogts filter`: Kalman filter from the ARMA drift model, or a zero-phase low-pass."""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Annotated, Any, Literal

import typer

from fogts import choices
from fogts.cli import _common as common
from fogts.cli._arguments import measurement_noise_value
from fogts.cli._axes import AxisOpt, axis_lines, axis_path, axis_picks, with_axis_column
from fogts.pipeline import ReadSettings

if TYPE_CHECKING:
    import pandas as pd
    from matplotlib.figure import Figure

    from fogts._typing import FloatArray
    from fogts.io.run import Run



@common.app.command("filter")
@common.writes_outputs()
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
    axis: AxisOpt = None,
    plot: Annotated[Path | None, typer.Option("--plot", help="Figure (.png, .svg, .pdf): observed/filtered/smoothed for kalman; the before/after Allan overlay with --compare-allan.")] = None,
    out: common.Outputs = common.NO_OUTPUTS,
    read: ReadSettings = common.DEFAULT_READ,
) -> None:
    """Filter a gyro record: Kalman filter with an ARMA drift model, or a
    zero-phase IIR / moving-average low-pass with a before/after Allan comparison.

    With --axis all each axis is filtered in turn: the output table gains an 'axis' column,
    each figure the axis name in its file name, and the JSON is {"input", "method", "units",
    "axes": [one block per axis], "output"}.
    """
    with common.guard(_FILTER_OPTIONS, overwrite=out.overwrite, outputs={"--output": output, "--json": out.json, "--plot": plot},
                inputs={"FILE": [file]}):
        common.check_output_names(plot=plot, output=output)  # before any output is written
        _check_method_options(method, {
            "--model": model != "auto", "--measurement-noise": measurement_noise != "estimate",
            "--cutoff": cutoff is not None, "--order": order != 4,
            "--design": design != "butter", "--window": window is not None,
            "--compare-allan": compare_allan})
        noise = measurement_noise_value(measurement_noise) if method == "kalman" else None
        run, _ = common.read_input(file, read)
        picks = axis_picks(run, axis)
        many = len(picks) > 1
        done: list[_Filtered] = []
        for i in picks:
            with common.named_warnings(Path(run.source).name, run.axes[i]):
                x = run.axis(i)
                done.append(_kalman_filter(run, x, model, noise) if noise is not None else
                            _lowpass_filter(run, x, method, cutoff, order, design, window,
                                            compare_allan, plot))
        from fogts.io.writer import write_frame_atomic

        write_frame_atomic(output, with_axis_column([d.frame for d in done],
                                                    [run.axes[i] for i in picks], many=many))
        head = {"input": str(file), "method": method, "units": run.units}
        blocks = [{"axis": run.axes[i], **d.payload} for i, d in zip(picks, done, strict=True)]
        common.emit_json({**head, **blocks[0], "output": str(output)} if not many else
                         {**head, "axes": blocks, "output": str(output)}, out.json,
                         _FILTER_OPTIONS)
        if plot is not None:
            for i, d in zip(picks, done, strict=True):
                if d.figure is not None:
                    common.save_figure(d.figure(), axis_path(plot, run, i, many))
        lines = axis_lines(run, picks, axis)
        for i, d in zip(picks, done, strict=True):
            lines += ([f"{run.axes[i]}:"] if many else []) + d.lines
        lines.append(f"wrote {output} ({run.n * len(done)} rows)")
        common.say([common.option_keywords(ln, _FILTER_OPTIONS) for ln in lines], out.json)


@dataclass(frozen=True)
class _Filtered:
    """One axis filtered: the output table, its JSON block, the lines to print and the
    figure to draw with --plot (None: none applies)."""

    frame: pd.DataFrame
    payload: dict[str, Any]
    lines: list[str]
    figure: Callable[[], Figure] | None


#: The options that apply to each --method (the rest are refused, not ignored).
#: Library argument names of ``fogts filter`` and their options, for its error messages.
_FILTER_OPTIONS = {"cutoff_hz": "--cutoff", "window_s": "--window",
                   "measurement_noise": "--measurement-noise"}

_METHOD_OPTIONS: dict[str, tuple[str, ...]] = {
    "kalman": ("--model", "--measurement-noise"),
    "iir": ("--cutoff", "--order", "--design", "--compare-allan"),
    "moving-average": ("--window", "--compare-allan"),
}


def _check_method_options(method: str, given: dict[str, bool]) -> None:
    """Refuse an option of another --method (``given``: option -> set away from its
    default) instead of ignoring it silently."""
    from fogts.errors import DataError

    stray = [o for o, on in given.items() if on and o not in _METHOD_OPTIONS[method]]
    if stray:
        owners = {o: [m for m, opts in _METHOD_OPTIONS.items() if o in opts] for o in stray}
        which = "; ".join(f"{o} applies to --method {' or '.join(owners[o])}" for o in stray)
        raise DataError(f"--method {method} does not use {', '.join(stray)} ({which}); "
                        "drop it or change --method")


def _kalman_filter(run: Run, x: FloatArray, model: str,
                   noise: Literal["estimate"] | float) -> _Filtered:
    import numpy as np
    import pandas as pd

    from fogts.startup.kalman import arma_kalman, resolve_arma_model

    fit = resolve_arma_model(x, model)
    result = arma_kalman(x, fit, measurement_noise=noise)
    frame = pd.DataFrame({"time": run.time, "observed": x,
                          "filtered": np.asarray(result.filtered),
                          "smoothed": np.asarray(result.smoothed),
                          "predicted": np.asarray(result.predicted)})
    fit_dict = fit.to_dict() if hasattr(fit, "to_dict") else {}

    def figure() -> Figure:
        from fogts.report.plots import plot_kalman

        return plot_kalman(result, time_s=run.time, units=run.units)

    equation = fit.equation() if hasattr(fit, "equation") else result.model
    return _Filtered(frame, {"model": fit_dict, "kalman": result.to_dict()},
                     [f"drift model ({'selected by AIC' if model == 'auto' else 'given'}): "
                      f"{equation}  [rate in {run.units}; sigma2 and H in ({run.units})^2]",
                      result.summary()], figure)


def _lowpass_filter(run: Run, x: FloatArray, method: str, cutoff: float | None, order: int,
                    design: str, window: float | None, compare: bool, plot: Path | None
                    ) -> _Filtered:
    import pandas as pd

    from fogts.errors import DataError
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
    payload: dict[str, Any] = {"filter": result.to_dict()}
    lines = [result.summary()]
    figure = None
    if compare:
        from fogts.allan.compare import compare_allan

        comparison = compare_allan(x, result.filtered, fs_hz=run.fs_hz, units=run.units,
                                   cutoff_hz=result.cutoff_hz,
                                   labels=("raw", f"{method} filtered"))
        payload["compare_allan"] = comparison.to_dict()
        lines += ["", "noise terms before and after filtering:", comparison.summary()]

        def figure() -> Figure:
            from fogts.report.plots import plot_allan_comparison

            return plot_allan_comparison(comparison)

    return _Filtered(pd.DataFrame({"time": run.time, "observed": x,
                                   "filtered": result.filtered}), payload, lines, figure)
