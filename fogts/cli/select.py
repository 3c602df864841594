"""`fogts select`: the ARMA model of the drift, its residual checks and prediction."""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING, Annotated, Any

import typer

from fogts.cli import _common as common
from fogts.cli._axes import AxisOpt, axis_lines, axis_path, axis_picks, with_axis_column
from fogts.cli.progress import shows_progress
from fogts.pipeline import ReadSettings

if TYPE_CHECKING:
    from fogts.arma.select import Candidate
    from fogts.pipeline import AxisSelection



def _fmt(v: Any, spec: str = ".4g") -> str:
    import math

    return "–" if v is None or (isinstance(v, float) and not math.isfinite(v)) else \
        format(v, spec)


def _select_params(c: Candidate, units: str | None) -> list[str]:
    from fogts.arma.fit_result import coefficient_text

    lines = []
    for k, v in c.params.items():
        se = c.bse.get(k)
        t = v / se if se else float("nan")
        unit = f" ({units})²" if k == "sigma2" and units else ""
        sig = "" if k == "sigma2" else f"  t = {t:+.1f}"
        value = (f"{v: .6g}" if k in ("mean", "sigma2")
                 else ("" if v < 0 else " ") + coefficient_text(v, 6))
        lines.append(f"  {k:<7} = {value} ± {_fmt(se, '.2g')}{unit}{sig}")
    return lines


@common.app.command("select")
@shows_progress()
@common.writes_outputs()
@common.reads_input()
def select_cmd(
    file: common.FileArg,
    axis: AxisOpt = None,
    outliers: Annotated[float | None, typer.Option("--outliers", help="Replace samples beyond this many robust sigmas first.")] = None,
    detrend: Annotated[int | None, typer.Option("--detrend", help="Remove a polynomial trend of this order; 0 removes the mean only (default: remove the mean).")] = None,
    decimate: Annotated[int | None, typer.Option("--decimate", help="Block-average K samples first (e.g. 100 Hz -> 1 Hz with K=100).")] = None,
    candidates: Annotated[str | None, typer.Option("--candidates", help="Models to compare, e.g. 'AR(1),AR(2),ARMA(1,1)' (default: AR(1),AR(2),AR(3),ARMA(1,1),ARMA(2,1)).")] = None,
    criterion: common.CriterionOpt = "aic",
    plot: Annotated[Path | None, typer.Option("--plot", help="Diagnostics figure (data ACF/PACF, residual ACF, Q-Q, prediction): .png, .svg or .pdf.")] = None,
    predict: Annotated[Path | None, typer.Option("--predict", help="Write the one-step prediction as CSV (time, observed, predicted, residual; observed and predicted in the input's units, the removed mean or trend added back); .csv, .csv.gz, .tsv or .parquet.")] = None,
    out: common.Outputs = common.NO_OUTPUTS,
    read: ReadSettings = common.DEFAULT_READ,
) -> None:
    """Select the ARMA model of the drift: fit AR(1), AR(2), AR(3), ARMA(1,1) and ARMA(2,1), check that their residuals are white, rank them and predict one step ahead.

    With --axis all each axis is modelled in turn; the JSON is then {"axes": [one such
    document per axis]}.

    Exit code 0 if the selected model leaves white residuals, 1 if no candidate does (the best one is still reported; with --axis all: for any axis), 2 on bad input.
    """
    from fogts.arma.select import parse_candidates
    from fogts.pipeline import SelectSettings, analyse_selection

    with common.guard(overwrite=out.overwrite, outputs={"--json": out.json, "--plot": plot, "--predict": predict},
                inputs={"FILE": [file]}):
        orders = parse_candidates(candidates)
        common.check_output_names(plot=plot, predict=predict)
        run, quality = common.read_input(file, read, outliers=outliers)
        picks = axis_picks(run, axis)
        settings = SelectSettings(outliers=outliers, detrend=detrend, decimate=decimate,
                                  candidates=orders, criterion=criterion)
        analyses = []
        for i in picks:
            with common.named_warnings(Path(run.source).name, run.axes[i]):
                analyses.append(analyse_selection(run, quality, i, settings, file=str(file)))
        many = len(analyses) > 1
        common.emit_json(analyses[0].to_dict() if not many
                         else {"axes": [a.to_dict() for a in analyses]}, out.json)
        written = [path for path in (out.json,) if path not in (None, "-")]
        if plot is not None:
            from fogts.report.plots import plot_selection

            for i, a in zip(picks, analyses, strict=True):
                written.append(str(axis_path(plot, run, i, many)))
                common.save_figure(plot_selection(a.selection), written[-1])
        fitted = _write_prediction(analyses, predict) if predict is not None else False
        if run.n_axes > 1:
            common.say(axis_lines(run, picks, axis), out.json)
        for a in analyses:
            _print_selection(a, out.json)
        common.say([f"wrote     {path}" for path in written]
             + ([f"wrote     {predict}"] if fitted else [])
             + ([f"not written {predict}: no candidate could be fitted"]
                if predict is not None and not fitted else []), out.json)
    raise typer.Exit(max(a.selection.exit_code for a in analyses))


def _write_prediction(analyses: list[AxisSelection], target: Path) -> bool:
    """Write the selected models' one-step predictions (time, observed, predicted,
    residual; with several axes an ``axis`` column first); False when no candidate could be
    fitted on any axis.

    ``observed`` and ``predicted`` are on the input's scale: the mean or trend that the
    preparation removed (:meth:`~fogts.preprocess.prepare.Prepared.removed_level`) is added
    back, so that ``observed`` is the rate as read (block means after ``--decimate``,
    outliers replaced after ``--outliers``), as ``fogts filter -o`` writes it."""
    from fogts.io.writer import write_frame_atomic

    frames, names = [], []
    for analysis in analyses:
        best = analysis.selection.selected
        if best is None:
            continue
        frame = best.predict().to_frame().reset_index(drop=True)
        level = analysis.prepared.removed_level()
        frame["observed"] += level
        frame["predicted"] += level
        if "time" not in frame:
            frame.insert(0, "time", analysis.prepared.time)
        frames.append(frame[["time", "observed", "predicted", "residual"]])
        names.append(analysis.prepared.axis)
    if not frames:
        return False
    write_frame_atomic(target, with_axis_column(frames, names, many=len(analyses) > 1))
    return True


def _print_selection(analysis: AxisSelection, json_out: str | None) -> None:
    """What was read and prepared, the candidate table, the selected model and the verdict
    (to stderr when the JSON goes to stdout)."""
    from rich.text import Text

    from fogts.report.text import duration_text

    out = common.err_console if json_out == "-" else common.console
    run, prepared, sel = analysis.run, analysis.prepared, analysis.selection

    def say(text: str = "", style: str = "") -> None:
        out.print(Text(text, style), soft_wrap=True)

    say(f"read      {analysis.file}: {run.n:,} samples of {prepared.axis!r} at "
        f"{run.fs_hz:g} Hz, {duration_text(run.duration_s)}, rate in {run.units}")
    for i, step in enumerate(prepared.steps):
        say(f"{'prepared' if i == 0 else '':<10}{step}")
    say(f"{'modelled':<10}{sel.n:,} samples at {prepared.fs_hz:g} Hz")
    corr = sel.correlogram
    say(f"{'ACF/PACF':<10}ACF {corr.acf_pattern.describe()}, PACF "
        f"{corr.pacf_pattern.describe()} -> {corr.suggestion}")
    common.print_out(common.rich_table(sel.candidate_table()), quiet_json=json_out)
    best = sel.selected
    if best is not None:
        how = (f"lowest {sel.criterion.upper()} among the white candidates" if best.white
               else f"lowest {sel.criterion.upper()}; residuals NOT white")
        say(f"selected  {best.model} ({how}), drift in {prepared.units}:", "bold")
        say(f"  {best.equation()}", "bold")
        for line in _select_params(best, prepared.units):
            say(line)
        gm = sel.gauss_markov()
        if gm is not None:
            say(f"  {gm.summary()}")
        for f in best.flags:
            say(f"  note: {f.message}")
        bp = best.prediction_summary()   # no series-length arrays (predict() makes two)
        say(f"  one-step prediction: std {bp['variance_observed'] ** 0.5:.4g} -> "
            f"{bp['variance_residual'] ** 0.5:.4g} {prepared.units} "
            f"({100 * bp['variance_removed']:.1f} % of the variance removed)")
    say(f"verdict   {sel.verdict}", "green" if sel.exit_code == 0 else "red")
