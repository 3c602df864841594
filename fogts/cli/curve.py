"""`fogts curve`: fit the IEEE-952 noise terms to a published Allan-deviation curve (a
datasheet curve digitised to CSV, SMAC-Group/avar's ``*_av.csv``, Stable32 output)."""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path
from typing import Annotated, Any

import typer

from fogts import choices
from fogts.cli import _common as common

OptionalKindOpt = Annotated[choices.Kind | None, typer.Option("--kind", help="The estimator the curve was computed with (default: from the file, else oadev; noise terms are fitted to adev, oadev and totdev).")]


@common.app.command("curve")
@common.writes_outputs()
def curve_cmd(
    file: Annotated[Path, typer.Argument(help="Allan curve: CSV/TSV/whitespace text with a tau column and a deviation (adev, oadev, dev, sigma, ...) or variance (avar, ...) column; SMAC-Group/avar *_av.csv; Stable32 text output.")],
    units: Annotated[str | None, typer.Option("--units", help="Unit of the deviation: deg/h, deg/s, rad/s, arcsec/s (or an accelerometer unit). Default: from the column name (adev_deg_h), else deg/h with a warning.")] = None,
    fs: Annotated[float | None, typer.Option("--fs", help="Sample rate (Hz) of the record the curve came from. Default: the file (SMAC header, Stable32 AF, an m column), else 1 / the shortest tau (said in a note).")] = None,
    n_samples: Annotated[int | None, typer.Option("--n-samples", help="Number of rate samples of that record (gives each point's EDF when the file has no edf or errors column).")] = None,
    kind: OptionalKindOpt = None,
    channel: Annotated[str | None, typer.Option("--channel", help="With a channel column: one channel, or 'all' (default: every channel of the --units quantity).")] = None,
    method: common.MethodOpt = "wls",
    terms: Annotated[str, typer.Option("--terms", help="Noise terms to fit, from Q,N,B,K,R (M, S as for fogts allan).")] = "Q,N,B,K,R",
    fit_tau_min: Annotated[float | None, typer.Option("--fit-tau-min", help="Fit only from this tau (s) on.")] = None,
    fit_tau_max: Annotated[float | None, typer.Option("--fit-tau-max", help="Fit only up to this tau (s).")] = None,
    keep_all_terms: Annotated[bool, typer.Option("--keep-all-terms", help="Keep every --terms term even when the data do not support it.")] = False,
    output_units: common.OutputUnitsOpt = "deg",
    plot: Annotated[Path | None, typer.Option("--plot", help="Log-log figure of the curve with the fit and its term lines: .png, .svg or .pdf.")] = None,
    export: common.ExportOpt = None,
    out: common.Outputs = common.NO_OUTPUTS,
) -> None:
    """Fit the IEEE-952 noise terms (Q, N, B, K, R) to a published Allan-deviation curve,
    with standard errors, and read the curve (minimum, regions, slopes).

    The output says where the unit, the sample rate, the record length and the weights
    (each point's EDF) came from: the options, the file, or inferred (in a note). JSON:
    {"input": {source, format, channels, kind, units, fs_hz, fs_source, n_samples,
    n_samples_source, weights, ...}, "axes": [one block per channel, as an axis of fogts
    allan --json]}, and for one channel that block's keys ("kind", "units", "points",
    "noise", "noise_si", "curve", ...) at the top level too. Methods: wls, gls, ols, and
    gmwm when the record length is known; ml needs the recording (fogts allan). --export
    writes N and K for a filter as fogts allan does; Kalibr's update_rate is the curve's
    sample rate, and a comment says so when it was inferred from the shortest tau.

    Exit code 2 on bad input.
    """
    from fogts.allan.curve_input import check_curve_methods, read_curves
    from fogts.allan.markov import split_terms
    from fogts.cli.allan import axes_figure
    from fogts.pipeline import AllanSettings, analyse_curve

    export_path = export[1] if export is not None else None
    with common.guard({"tau_min": "--fit-tau-min", "tau_max": "--fit-tau-max",
                       "fs_hz": "--fs", "n_samples": "--n-samples"},
                      overwrite=out.overwrite, outputs={"--json": out.json, "--plot": plot, "--export": export_path},
                      inputs={"FILE": [file]}, first=[lambda: common.export_format(export)]):
        export_format = common.export_format(export)
        common.check_output_names(plot=plot)
        methods = method.split(",")
        five, extras = split_terms(terms)
        read = read_curves(file, units=units, fs_hz=fs, n_samples=n_samples, kind=kind,
                           channel=channel)
        check_curve_methods(methods, read.provenance)
        settings = AllanSettings(kind=read.provenance.kind, terms=five + extras,
                                 method=methods[0], compare_methods=tuple(methods[1:]),
                                 significance=None if keep_all_terms else 0.05,
                                 fit_tau_min=fit_tau_min, fit_tau_max=fit_tau_max)
        name = file.name
        axes = []
        for curve in read.curves:
            with common.named_warnings(name, curve.axis):
                axes.append(analyse_curve(curve, settings))
            common.warn(axes[-1].plausibility_warning(read.provenance))
        export_text = None
        if export_format is not None:  # built first: a failing export writes nothing
            from fogts.report.export import ExportSource, noise_export_text

            export_text = noise_export_text(ExportSource.of_curve(read.provenance, tuple(axes)),
                                            export_format)
        blocks = [ax.to_dict() for ax in axes]
        payload: dict[str, Any] = {"input": read.provenance.to_dict(), "axes": blocks}
        if len(blocks) == 1:
            payload = {**blocks[0], **payload}
        common.emit_json(payload, out.json)
        if plot is not None:
            common.save_figure(axes_figure(axes), plot)
        if export_text is not None and export_path is not None:
            from fogts.io.writer import write_text_atomic

            write_text_atomic(export_path, export_text)
        _print(read.provenance.describe(), axes, out.json, output_units)


def _print(read_lines: list[str], axes: list[Any], json_out: str | None,
           output_units: choices.OutputUnits) -> None:
    """What was read, then per channel the points, the terms, the fit and the read-outs (as
    ``fogts allan`` prints them); the curves' shared notes once, under the first."""
    from fogts.cli.allan import allan_tables, curve_table

    common.say(read_lines, json_out)
    for i, ax in enumerate(axes):
        result = ax.result if i == 0 else replace(ax.result, notes=())
        allan_tables(result, ax.model, None, json_out, output_units)
        if ax.comparison is not None:
            common.print_out(common.rich_table(ax.comparison.table(output_units)),
                             quiet_json=json_out)
        curve_table(result, ax.readout, json_out, output_units)
        if ax.fit_check is not None:
            common.say([f"fit check: {ax.fit_check.verdict}"], json_out)
