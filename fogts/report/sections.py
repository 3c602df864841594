"""The HTML report's sections: each builder renders results of
:class:`fogts.report.analyses.ReportContext` as blocks (figures, tables, text).

A builder returns the blocks of one section or raises; :func:`make_section` turns the exception
into a section that shows its message, so one failed analysis does not cost the whole
report.  ``i`` is the axis index of per-axis sections.
"""

from __future__ import annotations

import math
import warnings
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from typing import Any

from fogts.errors import DataError
from fogts.report.analyses import ReportContext
from fogts.report.blocks import figure_block, fmt_num, fmt_pval, html_table, table_block, yes_no
from fogts.report.page import Block, Section
from fogts.report.text import (
    axes_rows,
    duration_line,
    error_message,
    fit_sentences,
    gaps_phrase,
    run_info,
    time_base_verdict,
    warning_texts,
)

__all__ = ["AXIS_BUILDERS", "RUN_BUILDERS", "SECTION_TITLES", "make_section"]

#: One sentence per part: what it shows and how to read it.
_HOW = {
    "summary": "The noise terms of every axis on one line each, in the report's units: N "
               "(angle random walk), B (bias instability) and K (rate random walk) with their "
               "standard errors, or '< x' where the data only bound a term; the fit verdict "
               "says whether the five-term model describes the curve (each axis' Allan "
               "section has the details and the warnings); when the dynamic Allan deviation "
               "ran, a line per axis says whether the noise level stayed constant (the terms "
               "are averages over the record, and average over any change).",
    "input": "What fogts read from the file and what it did to the data before modelling; "
             "check the sample rate, the gaps and the units first, since every other number "
             "depends on them.",
    "timeseries": "The raw rate against time (and the temperature below it, if recorded); "
                  "look for steps, spikes, warm-up drift and gaps that would bias the "
                  "noise analysis.",
    "allan": "The Allan deviation against averaging time τ on log-log axes, with the fitted "
             "IEEE-952 terms; each term dominates where the curve has its slope (−1/2 angle "
             "random walk, 0 bias instability, +1/2 rate random walk), and the table gives "
             "each coefficient with its uncertainty.",
    "arma": "The candidate ARMA models of the drift ranked by the information criterion; "
            "the selected model is the best-ranked one whose residuals pass the whiteness "
            "checks, and its equation is written out with the signs as used.",
    "prediction": "The selected model's one-step-ahead prediction against the data, and its "
                  "residuals; white residuals (statistics inside their ±1.96/√n bands, "
                  "Ljung–Box p-values above 0.05) mean the model has captured the drift.",
    "davar": "The dynamic Allan deviation: the Allan deviation of a window sliding along the "
             "record, as colour over time and τ; horizontal bands mean a stationary gyro, "
             "while colour changing along time shows the noise changing during the run.",
    "thermal": "The gyro drift modelled as a function of temperature T and its rate ΔT, "
               "the test of that model against a random-walk drift with no temperature "
               "dependence (read it first), and the bias stability before and after "
               "removing it, claimed as an improvement only when the model is significant.",
}

SECTION_TITLES = {"summary": "Summary", "input": "Input and preprocessing", "timeseries": "Time series",
           "allan": "Allan deviation and noise coefficients", "arma": "ARMA model selection",
           "prediction": "One-step prediction and residual diagnostics",
           "davar": "Dynamic Allan deviation", "thermal": "Thermal model"}

_TERM_NAME = {"Q": "quantization", "N": "angle random walk", "B": "bias instability",
              "K": "rate random walk", "R": "rate ramp"}


@contextmanager
def _collect_warnings(sink: list[str]) -> Iterator[None]:
    """Record the warnings raised inside the block; append the new ones' texts to ``sink``."""
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        yield
    sink.extend(t for t in warning_texts(caught) if t not in sink)


def make_section(sid: str, part: str, title: str, build: Callable[[list[str]], list[Block]]
             ) -> Section:
    """Run ``build`` (collecting its warnings as notes) into a section, or an error section
    with the exception's message."""
    notes: list[str] = []
    try:
        with _collect_warnings(notes):
            blocks = build(notes)
    except Exception as exc:
        return Section(id=sid, title=title, how_to_read=_HOW[part], status="error",
                       message=error_message(exc), notes=tuple(notes))
    return Section(id=sid, title=title, how_to_read=_HOW[part], blocks=tuple(blocks),
                   notes=tuple(notes))


def _axis_label(ctx: ReportContext, i: int) -> str:
    return f"axis {ctx.run.axes[i]}" if ctx.run.n_axes > 1 else ctx.run.axes[i]


# --------------------------------------------------------------------------- whole run


def _input_rows(ctx: ReportContext, info: dict[str, Any]) -> list[tuple[str, str]]:
    """The "What was read" table: source, sampling, columns, units, time base."""
    jitter = info["jitter"]
    rows: list[tuple[str, str]] = [
        ("source", str(info["source"])),
        ("samples", f"{info['n']:,}"),
        ("sample rate", f"{fmt_num(info['fs_hz'], 6)} Hz (from {info['fs_source']})"),
        ("duration", duration_line(info)),
        ("columns", ", ".join(info["columns"])),
        *axes_rows(info, ctx.run.accel_units_source),
        ("rate unit from", "ASSUMED (no unit in the column names; see Data quality)"
         if ctx.run.units_assumed else ctx.run.units_source),
        ("temperature", "yes" if info["temperature"] else "no temperature column"),
    ]
    if info["start_time"]:
        rows.append(("start time", str(info["start_time"])))
    if info["time_from_column"]:
        rows.append(("time base", f"{time_base_verdict(info)}: {gaps_phrase(info, fmt_num)}; "
                                  f"jitter {fmt_num(jitter['std_s'])} s"))
    else:
        rows.append(("time base", "none in the file: built from the sample rate"))
    return rows


#: The caption of the input section's list of data-quality findings
#: (:meth:`fogts.preprocess.hygiene.DataQuality.warnings`).
QUALITY_CAPTION = "Data quality (units, missing cells, gaps, glitches)"


def _input_blocks(ctx: ReportContext, notes: list[str]) -> list[Block]:
    info = run_info(ctx.run)
    blocks = [html_table("What was read", ["item", "value"], _input_rows(ctx, info),
                     numeric=[False, False])]
    issues = tuple(ctx.quality.warnings()) if ctx.quality is not None else ()
    blocks.append(Block(kind="list", caption=QUALITY_CAPTION, items=issues or ("no issue found: units named, no "
                                                      "missing cells, no gaps, no glitches",)))
    stats = [[name, st["mean"], st["std"], st["min"], st["max"]]
             for name, st in info["stats"].items()]
    blocks.append(html_table("Statistics of the raw data", ["column", "mean", "std", "min", "max"],
                         stats, numeric=[False, True, True, True, True]))
    if info["comments"]:
        shown = list(info["comments"][:20])
        if len(info["comments"]) > 20:
            shown.append(f"... {len(info['comments']) - 20} more comment line(s)")
        blocks.append(Block(kind="list", caption="Comment lines in the file",
                            items=tuple(shown)))
    steps: list[str] = []
    for i in range(ctx.run.n_axes):
        axis_notes: list[str] = []
        with _collect_warnings(axis_notes):
            p = ctx.get_prepared(i)
        prefix = _axis_prefix(ctx, i)
        notes.extend(n for n in (prefix + t for t in axis_notes) if n not in notes)
        steps += [prefix + s for s in p.steps] or [prefix + "none"]
    blocks.append(Block(kind="list", caption="Preprocessing before the ARMA analysis "
                        "(the Allan analysis uses the raw rate)", items=tuple(steps)))
    return blocks


def _timeseries_blocks(ctx: ReportContext, notes: list[str]) -> list[Block]:
    from fogts.report.plots import plot_timeseries

    fig = plot_timeseries(ctx.run)
    return [figure_block(fig, id="timeseries", alt="rate and temperature against time",
                         caption="Long records are drawn as a min-max envelope per pixel "
                                 "column, so spikes stay visible.")]


def _summary_blocks(ctx: ReportContext, notes: list[str]) -> list[Block]:
    """The one-page summary (:mod:`fogts.report.summary`) of every axis; with a spec, a
    verdict naming the terms that fail it."""
    from pathlib import Path

    from fogts.report.summary import axis_row, summary_table

    units, spec = ctx.options.get("output_units", "deg"), ctx.options.get("spec")
    name = Path(ctx.run.source).name
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # each axis' warnings are notes of its Allan section
        rows = [axis_row(name, ctx._allan_axis(i), units, spec) for i in range(ctx.run.n_axes)]
    table = summary_table(rows, spec)
    blocks = [table_block(table), Block(kind="paragraph", text=table.caption)]
    if spec is not None:
        blocks.append(_spec_verdict(rows, spec))
    return blocks + _noise_level_blocks(ctx)


def _noise_level_blocks(ctx: ReportContext) -> list[Block]:
    """The dynamic Allan deviation's verdict on each axis' noise level, for the axes whose
    DAVAR section ran (the summary is built after it): the noise terms above are fitted to
    the whole record, and average over a change in the noise."""
    return [Block(kind="verdict", good=bool(ns.stationary),
                  text=_axis_prefix(ctx, i) + ns.noise_level())
            for i in range(ctx.run.n_axes) if i in ctx.dynamic
            for ns in (ctx.dynamic[i].nonstationarity,)]


def _axis_prefix(ctx: ReportContext, i: int) -> str:
    """"Y: " before a line about axis ``i`` of a run with several axes, else nothing."""
    return f"{ctx.run.axes[i]}: " if ctx.run.n_axes > 1 else ""


# --------------------------------------------------------------------------- per axis


def _allan_blocks(ctx: ReportContext, i: int, notes: list[str]) -> list[Block]:
    from fogts.report.plots import plot_allan

    with _collect_warnings(notes):
        res = ctx.get_allan(i)
        model = ctx.get_noise(i)
    if model is None:
        raise DataError(f"the IEEE-952 terms are fitted to adev, oadev or totdev curves only, "
                        f"not {res.kind}")
    fig = plot_allan(res, model, fit_range=ctx.get_fit_range(i))
    pct = f"{100 * model.confidence:.1f} %"
    terms = model.term_table()
    blocks = [figure_block(fig, id=f"allan-{i}", alt=f"Allan deviation of {_axis_label(ctx, i)}",
                           caption=f"{res.kind} with {pct} confidence intervals; fitted total "
                                   "and each term's own line; the fit range shaded. Below: "
                                   "each point's residual (data − fit) in half-widths of its "
                                   "interval; beyond ±3 the fit misses the point."),
              table_block(terms), Block(kind="paragraph", text=terms.caption),
              *_comparison_blocks(ctx.get_comparison(i)),
              *_fit_check_blocks(ctx.get_fit_check(i)),
              Block(kind="paragraph", text=model.describe_readoff(fmt_num)),
              *(Block(kind="paragraph", text=line) for line in fit_sentences(model)),
              *_readout_blocks(ctx, i),
              table_block(res.points_table())]
    if res.dropped:
        blocks.append(Block(kind="list", caption="Taus not computed",
                            items=tuple(f"τ = {fmt_num(d.tau_s)} s: {d.reason}"
                                        for d in res.dropped)))
    return blocks


def _readout_blocks(ctx: ReportContext, i: int) -> list[Block]:
    """The curve read-outs (minimum, regions, dominant terms) as ``fogts allan`` prints them
    (:meth:`fogts.allan.readout.CurveReadout.table`), in the points' unit."""
    res, readout = ctx.get_allan(i), ctx.get_readout(i)
    table = readout.table(res.units, res.axis)
    return [table_block(table), Block(kind="paragraph", text=table.caption)]


def _comparison_blocks(comparison: Any) -> list[Block]:
    """Every method's terms side by side, when more than one method ran."""
    if comparison is None:
        return []
    table = comparison.table()
    return [table_block(table), Block(kind="paragraph", text=table.caption)]


def _fit_check_blocks(check: Any) -> list[Block]:
    if check is None:
        return []
    text = check.verdict
    return [Block(kind="verdict", good=check.ok, text=f"Fit check: {text}.")]


def _estimate_cell(name: str, value: Any) -> Any:
    """An AR or MA coefficient as the equation prints it: never "1" for one near a unit
    root (0.99995 stays 0.99995; :func:`fogts.arma.fit_result.coefficient_text`)."""
    from fogts.arma.fit_result import coefficient_text

    if name.startswith(("ar.", "ma.")) and isinstance(value, float) and math.isfinite(value):
        return coefficient_text(value, 4)
    return value


def _arma_blocks(ctx: ReportContext, i: int, notes: list[str]) -> list[Block]:
    sel = ctx.get_selection(i)
    candidates = sel.candidate_table()
    blocks: list[Block] = [
        Block(kind="paragraph", text=f"Data correlogram: {sel.correlogram.summary()}"),
        table_block(candidates), Block(kind="paragraph", text=candidates.caption)]
    best = sel.selected
    if best is not None:
        blocks.append(Block(kind="pre", caption=f"Selected model: {best.model}",
                            text=best.equation()))
        blocks.append(html_table("Parameters of the selected model (statsmodels names)",
                             ["parameter", "estimate", "± std. error", "t"],
                             [[name, _estimate_cell(str(name), r["estimate"]), r["bse"], r["t"]]
                              for name, r in best.to_frame().iterrows()],
                             numeric=[False, True, True, True]))
        gm = sel.gauss_markov()
        if gm is not None:
            blocks.append(Block(kind="paragraph", text=gm.summary() + "."))
    blocks.append(Block(kind="verdict", good=not sel.all_white_failed, text=sel.verdict))
    return blocks


def _residual_blocks(best: Any) -> list[Block]:
    """The selected model's residual statistics against their bands, and the verdict."""
    from fogts.arma.whiteness import LB_ALPHA

    d = best.diagnostics
    if d is None:
        return []
    rows: list[list[Any]] = [
        ["ρ_a,2 = Σ a_t a_{t−2} / Σ a_t² (residuals at lag 2)", d.rho_a2.value, f"|value| ≤ {fmt_num(d.rho_a2.band, 3)}",
         yes_no(d.rho_a2.passed)],
        ["ρ_ax,3: residuals against the data 3 steps back", d.rho_ax3.value,
         f"|value| ≤ {fmt_num(d.rho_ax3.band, 3)}", yes_no(d.rho_ax3.passed)]]
    for lb in d.ljung_box:
        pt = fmt_pval(lb.pvalue)
        rows.append([f"Ljung–Box Q at lag {lb.lag} ({lb.df} df)",
                     f"{fmt_num(lb.q)} (p {pt if pt.startswith('<') else '= ' + pt})",
                     f"p ≥ {LB_ALPHA:g}",
                     yes_no(lb.passed)])
    rows.append(["residual mean", d.mean, "", ""])
    return [html_table(f"Residual diagnostics of {best.model} (n = {d.n})",
                   ["statistic", "value", "white if", "pass"], rows,
                   numeric=[False, True, False, False]),
            Block(kind="verdict", good=bool(d.white), text=(
                "The residuals are white: the model captures the drift's correlation." if d.white
                else "The residuals are not white: " + "; ".join(d.reasons)))]


def _prediction_blocks(ctx: ReportContext, i: int, notes: list[str]) -> list[Block]:
    from fogts.report.plots import plot_selection

    sel = ctx.get_selection(i)
    best = sel.require_best()  # ModelFitError (shown in the section) if every fit failed
    pred = best.predict()
    units = ctx.run.units
    return [
        figure_block(plot_selection(sel), id=f"prediction-{i}",
                     alt=f"ARMA diagnostics of {_axis_label(ctx, i)}",
                     caption="Data ACF and PACF with their bands, the residual ACF, the "
                             "residual Q-Q plot and the one-step prediction against the data."),
        html_table(f"One-step-ahead prediction with {pred.model} ({pred.method})", ["", "value"],
               [[f"std of the prepared data [{units}]", math.sqrt(pred.variance_observed)],
                [f"std of the one-step residual a_t [{units}]",
                 math.sqrt(pred.variance_residual)],
                ["share of the variance the prediction removes", pred.variance_removed]],
               numeric=[False, True]),
        *_residual_blocks(best),
    ]


def _spec_verdict(rows: list[dict[str, Any]], spec: Any) -> Block:
    """The spec line: every term within its limit, or which terms FAIL and which the data
    cannot decide (:func:`fogts.allan.datasheet.check_spec`)."""
    from fogts.report.summary import SUMMARY_TERMS

    def terms(verdict: str) -> list[str]:
        return [f"{r['axis']}: {t}" for r in rows for t in SUMMARY_TERMS
                if r[f"{t}_spec"] == verdict]

    failing, open_ = terms("FAIL"), terms("INCONCLUSIVE")
    parts = ([f"FAIL for {', '.join(failing)}"] if failing else []) + (
        [f"INCONCLUSIVE for {', '.join(open_)} (the limit lies within the estimate's "
         "uncertainty)"] if open_ else [])
    return Block(kind="verdict", good=not parts, text=f"Spec {spec.source}: " + (
        "every term within its limit." if not parts else "; ".join(parts) + "."))


def _davar_blocks(ctx: ReportContext, i: int, notes: list[str]) -> list[Block]:
    from fogts.report.plots import plot_dynamic_allan

    res = ctx.get_dynamic_allan(i)
    fig = plot_dynamic_allan(res)
    ns = res.nonstationarity
    return [figure_block(fig, id=f"davar-{i}",
                         alt=f"dynamic Allan deviation of {_axis_label(ctx, i)}",
                         caption=f"{res.kind}, window {fmt_num(res.window_s)} s, step "
                                 f"{fmt_num(res.step_s)} s, {res.shape[0]} windows."),
            Block(kind="verdict", good=bool(ns.stationary), text=ns.summary())]


def _thermal_blocks(ctx: ReportContext, i: int, notes: list[str]) -> list[Block]:
    from fogts.report.plots import plot_compensation
    from fogts.startup.thermal_model import TERM_LETTERS

    res = ctx.get_compensation(i)
    model = res.model
    notes.extend(res.notes)  # dropped terms arrive as UnidentifiableTermWarning notes
    rows = [[t, TERM_LETTERS[t], model.coefficients[t], model.stderr[t]] for t in model.terms]
    b, a = res.before, res.after
    verdict = [] if res.significance is None else [
        Block(kind="verdict", good=res.significance.significant,
              text=res.significance.verdict[0].upper() + res.significance.verdict[1:] + ".")]
    # a fitted model's note of no significance repeats the verdict above it
    if model.identification_note and (res.significance is None or res.significance.significant):
        note = model.identification_note
        verdict.append(Block(kind="verdict", good=False, text=note[0].upper() + note[1:] + "."))
    if not res.applied:
        after_label = f"after (nothing compensated: {res.not_applied_reason()})"
    elif res.claims_improvement:
        after_label = "after compensation"
    else:
        after_label = f"after compensation (not claimed as an improvement: {res.no_claim_reason()})"
    return [
        *verdict,
        figure_block(plot_compensation(res), id=f"thermal-{i}",
                     alt=f"thermal compensation of {_axis_label(ctx, i)}",
                     caption="Raw and compensated rate (top) and temperature (bottom)."),
        Block(kind="pre", caption=("Fitted drift model (fitted to the raw rate)" if res.applied
                                   else "Fitted drift model, not applied: "
                                   f"{res.not_applied_reason()}"),
              text=model.equation()),
        html_table("Coefficients", ["term", "letter", "value", "± std. error"], rows,
               numeric=[False, False, True, True]),
        html_table(f"Bias stability (1σ of {b.average_s:g} s averages, {b.unit})",
               ["", "bias stability", "windows"],
               [["before compensation", b.value, b.n_windows],
                [after_label, a.value, a.n_windows]],
               numeric=[False, True, True]),
        *_out_of_sample_blocks(res),
        Block(kind="paragraph", text=(
            f"R² = {fmt_num(model.r2)}; residual std {fmt_num(model.residual_std)} {model.units}; "
            f"fitted over T = {fmt_num(model.temperature_range_degC[0])} … "
            f"{fmt_num(model.temperature_range_degC[1])} °C. For the full start-up pipeline "
            "(EMD trend, ARMA Kalman filter, then this fit) run 'fogts compensate --emd'.")),
    ]


def _out_of_sample_blocks(res: Any) -> list[Block]:
    """The cross-validated gain: a table of the folds and the summary sentence."""
    cv = res.out_of_sample
    if cv is None:
        return []
    rows = [[f.label + ("" if f.scored else " (not scored: extrapolates)"), f.before, f.after,
             f.ratio] for f in cv.folds]
    return [html_table(f"Bias stability out of sample ({cv.scheme}, {cv.average_s:g} s averages, "
                   "deg/h)", ["held out", "before", "after", "before / after"], rows,
                   numeric=[False, True, True, True]),
            Block(kind="paragraph", text=cv.summary()[0].upper() + cv.summary()[1:] + ".")]


#: Builders of the sections that show the whole run, by part.
RUN_BUILDERS: dict[str, Callable[[ReportContext, list[str]], list[Block]]] = {
    "summary": _summary_blocks, "input": _input_blocks, "timeseries": _timeseries_blocks}
#: Builders of the sections drawn once per rate axis, by part.
AXIS_BUILDERS: dict[str, Callable[[ReportContext, int, list[str]], list[Block]]] = {
    "allan": _allan_blocks, "arma": _arma_blocks, "prediction": _prediction_blocks,
    "davar": _davar_blocks, "thermal": _thermal_blocks}
