"""`fogts allan`: Allan deviation with confidence intervals, the IEEE-952 noise terms and the curve read-outs."""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Annotated, Any

import typer

from fogts import choices
from fogts.cli import _common as common
from fogts.cli._axes import EveryAxisOpt
from fogts.cli.progress import shows_progress
from fogts.pipeline import ReadSettings

if TYPE_CHECKING:
    from matplotlib.figure import Figure

    from fogts.allan.noise import NoiseModel
    from fogts.allan.readout import CurveReadout
    from fogts.allan.result import AllanResult
    from fogts.pipeline import AllanAnalysis, AxisAllan


def allan_tables(res: AllanResult, model: NoiseModel | None, check: dict[str, Any] | None,
                  quiet_json: str | None, units: choices.OutputUnits = "deg") -> None:
    import math

    from fogts.units import si_unit

    def g(v: float, digits: int = 5) -> str:
        return "-" if v is None or not math.isfinite(v) else f"{v:.{digits}g}"

    rate_units = si_unit(res.units) if units == "si" else None
    common.print_out(common.rich_table(res.points_table(rate_units)), quiet_json=quiet_json)
    for d in res.dropped:
        common.say([f"dropped tau = {d.tau_s:g} s (m = {d.m}): {d.reason}"], quiet_json)
    # the curve's own notes (taus rounded to whole samples, missing samples, totdev's bias
    # correction), as in its summary() and JSON; the preparation steps are printed above
    common.say([f"note: {common.option_keywords(n)}" for n in res.notes
                if not n.startswith("prepared: ")], quiet_json)
    if model is not None:
        common.print_out(common.rich_table(model.term_table(units)), quiet_json=quiet_json)
        from fogts.report.text import fit_sentences

        common.say([model.describe_readoff(units=units)], quiet_json)
        fit, *extras = fit_sentences(model)
        common.say([fit], quiet_json)
        common.say(extras, quiet_json)  # without extra terms: the blank line before the curve
    if check is not None:
        worst = check["max_rel_diff"]
        common.say([f"allantools check ({check['peer']}): largest relative difference "
              f"{g(worst, 3)} over {check['n_compared']} taus"
              + (f" (at tau = {check['tau_at_max']:g} s)" if worst is not None else "")
              + ("" if check["n_terms_equal"] else "; the numbers of terms differ")], quiet_json)


# Over 80 lines by its 24 option declarations and docstring; the analysis is fogts.pipeline's.
@common.app.command("allan")
@shows_progress()
@common.writes_outputs()
@common.reads_input()
@common.pauses_cycle_collection
def allan_cmd(
    files: Annotated[list[Path], typer.Argument(help="Input recording(s). Several files (or a multi-axis file) are overlaid on one --plot for comparing gyros.")],
    kind: common.KindOpt = "oadev",
    taus: Annotated[str, typer.Option("--taus", help="Tau grid: octave, decade, dense, all, or taus in s separated by commas.")] = "octave",
    confidence: Annotated[float, typer.Option("--confidence", help="Confidence level of the deviation and coefficient intervals.")] = 0.683,
    terms: Annotated[str, typer.Option("--terms", help="Noise terms to fit, from Q,N,B,K,R; add M (first-order Markov noise: T_c and q_c) and/or S (a sinusoid: f_0 and Omega_0), each with a likelihood-ratio test of whether adding it is significant.")] = "Q,N,B,K,R",
    method: common.MethodOpt = "wls",
    fit_tau_min: Annotated[float | None, typer.Option("--fit-tau-min", help="Fit the noise terms only from this tau (s) on, e.g. to leave out a sampling filter's effect at the shortest taus.")] = None,
    fit_tau_max: Annotated[float | None, typer.Option("--fit-tau-max", help="Fit the noise terms only up to this tau (s).")] = None,
    keep_all_terms: Annotated[bool, typer.Option("--keep-all-terms", help="Keep every --terms term in the fit even when the data do not support it (default: drop terms that are not significant at 5 % and visible at fewer than two taus).")] = False,
    axis: EveryAxisOpt = None,
    outliers: Annotated[float | None, typer.Option("--outliers", help="Replace samples beyond this many robust sigmas first (default: raw data).")] = None,
    detrend: Annotated[int | None, typer.Option("--detrend", help="Remove a polynomial trend of this order first (default: raw data).")] = None,
    decimate: Annotated[int | None, typer.Option("--decimate", help="Block-average K samples first (default: raw data).")] = None,
    csv_out: Annotated[Path | None, typer.Option("--csv", help="Write the points (and the fitted curve) to PATH (.csv, .tsv, .parquet).")] = None,
    plot: Annotated[Path | None, typer.Option("--plot", help="Log-log figure with CIs, the fit, its term lines, the fit range shaded and the residuals (data - fit)/CI half-width underneath (several inputs: an overlay): .png, .svg or .pdf.")] = None,
    check_allantools: Annotated[bool, typer.Option("--check-allantools", help="Recompute with allantools on the same data and taus; print the largest relative difference.")] = False,
    output_units: common.OutputUnitsOpt = "deg",
    spec: common.SpecOpt = None,
    export: common.ExportOpt = None,
    bias_correction: Annotated[bool, typer.Option("--bias-correction", help="--kind totdev: divide TOTVAR by its bias at flicker- and random-walk-FM taus (Howe 1999), as Stable32 does.")] = False,
    out: common.Outputs = common.NO_OUTPUTS,
    read: ReadSettings = common.DEFAULT_READ,
) -> None:
    """Allan deviation with confidence intervals, the IEEE-952 noise terms (Q, N, B, K, R)
    with standard errors, and the curve read-outs (minimum, regions, slopes).

    The output opens with a summary: one row per file and axis with N, B and K (± standard
    error, or '< x' when the data only bound the term), the fit verdict and, with --spec,
    PASS/FAIL/INCONCLUSIVE per term. The data are analysed raw unless --outliers, --detrend or --decimate
    is given. JSON for one file: {"input", "axes": [{"axis", "kind", "units", "points",
    "noise", "noise_si", "curve", ...} per axis], "summary", ...} (the top-level copy of the
    first axis is deprecated); several files give {"inputs": [one such object per file],
    "summary"}. With several methods (--method wls,gmwm,ml) the first is the fit all of
    this shows, and each axis adds "methods": every method's terms side by side.

    Exit code 1 if a term FAILs its --spec limit, 2 on bad input.
    """
    from contextlib import nullcontext

    from fogts._validate import known_sums
    from fogts.allan.kernels import phase_in_place
    from fogts.allan.markov import split_terms
    from fogts.pipeline import AllanAnalysis, AllanSettings, analyse_allan_axis
    from fogts.report.summary import SUMMARY_TERMS, summary_rows, summary_table

    export_path = export[1] if export is not None else None
    with common.guard({"tau_min": "--fit-tau-min", "tau_max": "--fit-tau-max",
                       "fit_tau_min": "--fit-tau-min", "fit_tau_max": "--fit-tau-max",
                       "method": "--method"},
                      overwrite=out.overwrite, outputs={"--json": out.json, "--csv": csv_out, "--plot": plot,
                               "--export": export_path},
                      inputs={"FILES": files, "--spec": [spec] if spec else []},
                      first=[lambda: _export_format(export, files)]):
        export_format = _export_format(export, files)
        tau_spec = common.tau_option(taus)
        five, extras = split_terms(terms)
        term_names = five + extras
        common.check_output_names(plot=plot, csv=csv_out)
        methods = method.split(",")
        settings = AllanSettings(kind=kind, taus=tau_spec, confidence=confidence,
                                 terms=term_names, method=methods[0],
                                 compare_methods=tuple(methods[1:]),
                                 significance=None if keep_all_terms else 0.05,
                                 bias_correction=bias_correction, outliers=outliers,
                                 detrend=detrend, decimate=decimate,
                                 check_allantools=check_allantools,
                                 fit_tau_min=fit_tau_min, fit_tau_max=fit_tau_max)
        limits = common.load_spec(spec)
        analyses = []
        for f in files:
            with known_sums():  # the reader's sum of the rate serves the checks after it
                run, quality = common.read_input(f, read, outliers=outliers)
                picks = range(run.n_axes) if axis is None else [common.axis_index(run, axis)]
                done = []
                for i in picks:
                    # The analysis is the last reader of a one-axis rate, unless the settings
                    # read it again: its phase may then take the rate's own memory.
                    spent = (phase_in_place(run.rate) if run.n_axes == 1
                             and not settings.reads_rate_after_curve else nullcontext())
                    with common.named_warnings(Path(run.source).name, run.axes[i]), spent:
                        done.append(analyse_allan_axis(run, i, settings))
                    common.warn(done[-1].plausibility_warning(run))
            analyses.append(AllanAnalysis(run=run, quality=quality, axes=tuple(done)))
        rows = summary_rows(analyses, output_units, limits)
        export_text = None
        if export_format is not None:  # built first: a failing export writes nothing
            from fogts.report.export import noise_export_text

            export_text = noise_export_text(analyses[0], export_format)
        payload: dict[str, Any] = (analyses[0].to_dict() if len(analyses) == 1
                                   else {"inputs": [a.to_dict() for a in analyses]})
        payload["summary"] = rows
        if limits is not None:
            payload["spec"] = limits.to_dict()
        common.emit_json(payload, out.json)
        if csv_out is not None:
            _allan_csv(analyses, csv_out)
        if plot is not None:
            common.save_figure(_allan_figure(analyses), plot)
        if export_text is not None and export_path is not None:
            from fogts.io.writer import write_text_atomic

            write_text_atomic(export_path, export_text)
        common.print_out(common.rich_table(summary_table(rows, limits)), quiet_json=out.json)
        for analysis in analyses:
            run = analysis.run
            common.say([f"{run.source}: {run.n} samples at {run.fs_hz:.6g} Hz "
                        f"({run.duration_s:.6g} s{analysis.quality.grid_note(run.n)}), "
                        f"rate in {run.units}"], out.json)
            for ax in analysis.axes:
                if ax.notes:
                    common.say([f"{ax.result.axis}: {common.option_keywords(line)}"
                                for line in ax.notes], out.json)
                allan_tables(ax.result, ax.model, ax.check, out.json, output_units)
                if ax.comparison is not None:
                    common.print_out(common.rich_table(ax.comparison.table(output_units)),
                                     quiet_json=out.json)
                curve_table(ax.result, ax.readout, out.json, output_units)
                if ax.fit_check is not None:
                    common.say([f"fit check: {ax.fit_check.verdict}"], out.json)
    if any(r[f"{t}_spec"] == "FAIL" for r in rows for t in SUMMARY_TERMS):
        raise typer.Exit(common.ExitCode.NEGATIVE)


def _export_format(export: tuple[str, Path] | None, files: list[Path]
                   ) -> choices.ExportFormat | None:
    """The --export format, checked: one of the formats, and one input file."""
    from fogts.errors import DataError

    fmt = common.export_format(export)
    if fmt is not None and len(files) > 1:
        raise DataError(f"--export describes one sensor: give one input file, not {len(files)}")
    return fmt


def _allan_csv(analyses: list[AllanAnalysis], target: Path) -> None:
    import pandas as pd

    from fogts.io.writer import write_frame_atomic

    frames = []
    many_files = len(analyses) > 1
    for a in analyses:
        for ax in a.axes:
            res, model = ax.result, ax.model
            frame = res.to_frame()
            frame["fit"] = model.curve(res.tau_s) if model is not None else float("nan")
            if len(a.axes) > 1 or many_files:
                frame.insert(0, "axis", res.axis)
            if many_files:
                frame.insert(0, "source", a.run.source)
            frames.append(frame)
    write_frame_atomic(target, pd.concat(frames, ignore_index=True))


def axes_figure(axes: Sequence[AxisAllan]) -> Figure:
    """The Allan figure of one file's axes: one curve with its fit, term lines and fit range,
    or every axis' curve and fit on one figure."""
    from fogts.allan import AllanResultSet
    from fogts.report.plots import plot_allan

    if len(axes) == 1:
        return plot_allan(axes[0].result, axes[0].model, fit_range=axes[0].fit_range)
    models = [ax.model for ax in axes]
    return plot_allan(AllanResultSet(curves=tuple(ax.result for ax in axes)),
                      models if all(m is not None for m in models) else None)


def _allan_figure(analyses: list[AllanAnalysis]) -> Figure:
    from fogts.report.plots import plot_allan_overlay

    if len(analyses) == 1:
        return axes_figure(analyses[0].axes)
    curves, fits, labels = [], [], []
    for a in analyses:
        for ax in a.axes:
            curves.append(ax.result)
            fits.append(ax.model)
            name = Path(a.run.source).name
            labels.append(name if len(a.axes) == 1 else f"{name}: {ax.result.axis}")
    return plot_allan_overlay(curves, labels, fits)


def curve_table(res: AllanResult, readout: CurveReadout, quiet_json: str | None,
                 units: choices.OutputUnits = "deg") -> None:
    """The read-outs in the unit of the points table above them (--output-units si: the
    deviations in rad/s or m/s^2, as the points)."""
    from fogts.units import si_unit

    unit = si_unit(res.units) if units == "si" else res.units
    shown = readout.in_unit(res.units, unit)
    common.print_out(common.rich_table(shown.table(unit, res.axis)), quiet_json=quiet_json)
