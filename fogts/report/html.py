"""One self-contained HTML document per run: ``fogts report FILE -o report.html``.

The report is built in two steps:

1. :func:`build_report` runs the analyses on a :class:`~fogts.io.run.Run` and collects, per
   section, figures (matplotlib figures from :mod:`fogts.report.plots`, embedded as SVG or PNG
   ``data:`` URIs), tables and text.  Each section says in one sentence what it shows and how
   to read it.  A part that fails becomes a section with its error message (nothing fails
   silently, and one failed analysis does not cost the whole report).
2. :meth:`HtmlReport.render` fills the jinja2 template ``fogts/report/templates/report.html.j2``
   with autoescaping on, so file names, column names and comment lines from the input
   file - which are untrusted - are shown as text and never interpreted as HTML.

The document needs nothing from the network: styles are inline, figures are data URIs, it
has no script, and its Content-Security-Policy forbids loading anything else.

Examples
--------
>>> import numpy as np
>>> from fogts.io.reader import read_run
>>> rng = np.random.default_rng(0)
>>> run = read_run(rng.normal(size=3000), fs_hz=10.0)
>>> rep = build_report(run, title="bench unit 7", parts=("input", "timeseries"))
>>> [s.id for s in rep.sections]
['input', 'timeseries']
>>> html = rep.render()
>>> html.startswith("<!DOCTYPE html>") and "bench unit 7" in html
True
"""

from __future__ import annotations

import base64
import datetime as _dt
import io
import math
import os
import re
import warnings
from collections.abc import Callable, Iterator, Sequence
from contextlib import contextmanager
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from fogts.errors import DataError
from fogts.io.run import Run
from fogts.report.text import _duration_text, error_message, run_info, warning_texts

__all__ = [
    "PARTS",
    "Block",
    "HtmlReport",
    "Section",
    "build_report",
    "figure_block",
    "write_report",
]

#: The report's parts, in order.  ``davar`` runs only on records long enough for it, and
#: ``thermal`` only with a temperature column.
PARTS: tuple[str, ...] = ("input", "timeseries", "allan", "arma", "prediction", "davar",
                          "thermal")

#: Figures larger than this as SVG are embedded as PNG instead.
MAX_SVG_BYTES = 1_500_000
#: DAVar needs at least this many windows...
DAVAR_MIN_WINDOWS = 10
#: ... of at least this many samples each.
DAVAR_MIN_WINDOW_SAMPLES = 256


# --------------------------------------------------------------------------- content


@dataclass(frozen=True)
class Block:
    """One piece of a section: ``figure``, ``table``, ``pre``, ``list``, ``heading``,
    ``verdict`` or ``paragraph``.  Every string is plain text (escaped when rendered)."""

    kind: str
    text: str = ""
    caption: str = ""
    # figure
    id: str = ""
    mime: str = ""
    data: str = ""
    alt: str = ""
    width: int = 0
    height: int = 0
    # table
    columns: tuple[str, ...] = ()
    rows: tuple[tuple[str, ...], ...] = ()
    numeric: tuple[bool, ...] = ()
    highlight: tuple[int, ...] = ()
    # list
    items: tuple[str, ...] = ()
    # verdict
    good: bool = True

    def to_dict(self) -> dict[str, Any]:
        d: dict[str, Any] = {"kind": self.kind}
        if self.kind == "figure":
            d.update(id=self.id, mime=self.mime, bytes=len(self.data) * 3 // 4,
                     caption=self.caption)
        elif self.kind == "table":
            d.update(caption=self.caption, columns=list(self.columns),
                     rows=[list(r) for r in self.rows])
        elif self.kind == "list":
            d.update(caption=self.caption, items=list(self.items))
        else:
            d.update(text=self.text)
        return d


@dataclass(frozen=True)
class Section:
    """A titled part of the report.

    Attributes
    ----------
    id : str
        HTML anchor (built by fogts, never from input strings).
    title : str
    how_to_read : str
        One sentence: what the section shows and how to read it.
    status : str
        ``"ok"`` or ``"error"`` (then ``message`` says why).
    blocks : tuple of Block
    notes : tuple of str
        Warnings raised while computing the section.
    """

    id: str
    title: str
    how_to_read: str
    status: str = "ok"
    message: str = ""
    blocks: tuple[Block, ...] = ()
    notes: tuple[str, ...] = ()

    @property
    def figures(self) -> tuple[Block, ...]:
        return tuple(b for b in self.blocks if b.kind == "figure")

    def to_dict(self) -> dict[str, Any]:
        return {"id": self.id, "title": self.title, "how_to_read": self.how_to_read,
                "status": self.status, "message": self.message,
                "blocks": [b.to_dict() for b in self.blocks], "notes": list(self.notes)}


@dataclass(frozen=True)
class HtmlReport:
    """A report ready to render.

    Attributes
    ----------
    title, source : str
    generated : str
        UTC time stamp of the build.
    version : str
        fogts version.
    sections : tuple of Section
    omitted : tuple of (str, str)
        Parts left out and why (e.g. no temperature column).
    """

    title: str
    source: str
    generated: str
    version: str
    sections: tuple[Section, ...]
    omitted: tuple[tuple[str, str], ...] = ()

    @property
    def n_figures(self) -> int:
        return sum(len(s.figures) for s in self.sections)

    def render(self) -> str:
        """The HTML document (one string, self-contained)."""
        from jinja2 import Environment, PackageLoader, StrictUndefined

        env = Environment(loader=PackageLoader("fogts.report", "templates"), autoescape=True,
                          undefined=StrictUndefined, trim_blocks=False, lstrip_blocks=False,
                          keep_trailing_newline=True)
        template = env.get_template("report.html.j2")
        return template.render(title=self.title, source=self.source,
                               generated=self.generated, version=self.version,
                               sections=self.sections, omitted=self.omitted)

    def to_dict(self) -> dict[str, Any]:
        return {"title": self.title, "source": self.source, "generated": self.generated,
                "version": self.version, "sections": [s.to_dict() for s in self.sections],
                "omitted": [{"part": p, "reason": r} for p, r in self.omitted]}

    def to_frame(self) -> Any:
        import pandas as pd

        return pd.DataFrame([{"id": s.id, "title": s.title, "status": s.status,
                              "figures": len(s.figures), "message": s.message}
                             for s in self.sections])

    def summary(self) -> str:
        bad = [s for s in self.sections if s.status != "ok"]
        lines = [f"report {self.title!r}: {len(self.sections)} section(s), {self.n_figures} "
                 f"figure(s)"]
        lines += [f"  failed: {s.title}: {s.message}" for s in bad]
        lines += [f"  not included: {p} ({r})" for p, r in self.omitted]
        return "\n".join(lines)


# --------------------------------------------------------------------------- helpers


def figure_block(fig: Any, *, id: str, alt: str, caption: str = "",
                 max_svg_bytes: int = MAX_SVG_BYTES) -> Block:
    """Embed a matplotlib Figure as an SVG data URI (PNG if the SVG would be too large).

    The SVG carries no date and uses a fixed id salt, so the same figure gives the same
    bytes.
    """
    import matplotlib

    width_in, height_in = fig.get_size_inches()
    buf = io.BytesIO()
    with matplotlib.rc_context({"svg.hashsalt": "fogts"}):  # stable ids: same bytes
        fig.savefig(buf, format="svg", metadata={"Date": None})
    data, mime = buf.getvalue(), "image/svg+xml"
    width, height = round(width_in * 96), round(height_in * 96)
    head = re.search(rb'<svg[^>]*\swidth="([0-9.]+)pt"[^>]*\sheight="([0-9.]+)pt"', data[:2000])
    if head:  # the tight bounding box: CSS px = pt * 96 / 72
        width, height = round(float(head[1]) * 4 / 3), round(float(head[2]) * 4 / 3)
    if len(data) > max_svg_bytes:
        dpi = 110
        buf = io.BytesIO()
        fig.savefig(buf, format="png", dpi=dpi, metadata={"Software": None})
        data, mime = buf.getvalue(), "image/png"
        png_w, png_h = int.from_bytes(data[16:20], "big"), int.from_bytes(data[20:24], "big")
        width, height = round(png_w * 96 / dpi), round(png_h * 96 / dpi)
    return Block(kind="figure", id=id, mime=mime, data=base64.b64encode(data).decode("ascii"),
                 alt=alt, caption=caption, width=width, height=height)


def _num(v: Any, digits: int = 4) -> str:
    """A number for a table cell: ``digits`` significant digits, "–" for missing."""
    if v is None:
        return "–"
    if isinstance(v, bool | np.bool_):
        return "yes" if v else "no"
    if isinstance(v, int | np.integer):
        return str(int(v))
    try:
        f = float(v)
    except (TypeError, ValueError):
        return str(v)
    if not math.isfinite(f):
        return "–"
    if f == 0:
        return "0"
    if 10 ** digits <= abs(f) < 1e6:
        return f"{f:.0f}"
    if 1e-3 <= abs(f) < 1e6:
        return f"{f:.{digits}g}"
    return f"{f:.{max(digits - 1, 1)}e}"


def _pval(p: Any) -> str:
    """A p-value: 3 significant digits, "< 1e-4" below that."""
    try:
        f = float(p)
    except (TypeError, ValueError):
        return "–"
    if not math.isfinite(f):
        return "–"
    return "< 1e-4" if f < 1e-4 else f"{f:.3g}"


def _fixed(v: Any, decimals: int = 2) -> str:
    """A number with fixed decimals (information criteria, log-likelihoods)."""
    try:
        f = float(v)
    except (TypeError, ValueError):
        return "–"
    return f"{f:.{decimals}f}" if math.isfinite(f) else "–"


def _table(caption: str, columns: Sequence[str], rows: Sequence[Sequence[Any]], *,
           numeric: Sequence[bool] | None = None, highlight: Sequence[int] = ()) -> Block:
    cells = tuple(tuple(c if isinstance(c, str) else _num(c) for c in r) for r in rows)
    if numeric is None:
        numeric = [all(not isinstance(r[j], str) for r in rows) if rows else False
                   for j in range(len(columns))]
    return Block(kind="table", caption=caption, columns=tuple(columns), rows=cells,
                 numeric=tuple(numeric), highlight=tuple(highlight))


@contextmanager
def _collect_warnings(sink: list[str]) -> Iterator[None]:
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        yield
    sink.extend(t for t in warning_texts(caught) if t not in sink)


@dataclass
class _Context:
    """What the sections share: the run, options, and results computed once."""

    run: Run
    options: dict[str, Any]
    quality: Any = None  # fogts.preprocess.hygiene.DataQuality
    prepared: dict[int, Any] = field(default_factory=dict)
    allan: dict[int, Any] = field(default_factory=dict)
    noise: dict[int, Any] = field(default_factory=dict)
    selection: dict[int, Any] = field(default_factory=dict)

    def axis_label(self, i: int) -> str:
        return f"axis {self.run.axes[i]}" if self.run.n_axes > 1 else self.run.axes[i]

    def get_prepared(self, i: int) -> Any:
        if i not in self.prepared:
            from fogts.preprocess.prepare import prepare

            o = self.options
            self.prepared[i] = prepare(self.run, axis=i, outliers=o["outliers"],
                                       detrend=o["detrend"], decimate=o["decimate"])
        return self.prepared[i]

    def get_allan(self, i: int) -> Any:
        if i not in self.allan:
            from fogts.allan import allan_deviation

            self.allan[i] = allan_deviation(self.run, axis=i, kind=self.options["kind"],
                                            taus=self.options["taus"])
        return self.allan[i]

    def get_noise(self, i: int) -> Any:
        if i not in self.noise:
            from fogts.allan.noise import fit_noise

            self.noise[i] = fit_noise(self.get_allan(i))
        return self.noise[i]

    def get_selection(self, i: int) -> Any:
        if i not in self.selection:
            from fogts.arma import select_arma

            self.selection[i] = select_arma(self.get_prepared(i),
                                            criterion=self.options["criterion"])
        return self.selection[i]


# --------------------------------------------------------------------------- sections
# Each builder returns the blocks of one section (or raises: the section then shows the
# error).  ``i`` is the axis index for per-axis sections.


def _input_blocks(ctx: _Context, notes: list[str]) -> list[Block]:
    info = run_info(ctx.run)
    gaps, jitter = info["gaps"], info["jitter"]
    rows: list[tuple[str, str]] = [
        ("source", str(info["source"])),
        ("samples", f"{info['n']:,}"),
        ("sample rate", f"{_num(info['fs_hz'], 6)} Hz (from {info['fs_source']})"),
        ("duration", _duration_text(info["duration_s"])),
        ("columns", ", ".join(info["columns"])),
        ("rate axes", f"{', '.join(info['axes'])} [{info['units']}]"),
        ("rate unit from", "ASSUMED (no unit in the column names; pass --units)"
         if ctx.run.units_assumed else ctx.run.units_source),
        ("temperature", "yes" if info["temperature"] else "no temperature column"),
    ]
    if info["start_time"]:
        rows.append(("start time", str(info["start_time"])))
    if info["time_from_column"]:
        rows.append(("time base", f"{'regular' if jitter['regular'] else 'IRREGULAR'}: "
                                  f"{gaps['count']} gap(s) longer than "
                                  f"{_num(gaps['threshold_s'])} s (longest "
                                  f"{_num(gaps['max_s'])} s); jitter {_num(jitter['std_s'])} s"))
    else:
        rows.append(("time base", "none in the file: built from the sample rate"))
    blocks = [_table("What was read", ["item", "value"], rows, numeric=[False, False])]
    issues = tuple(ctx.quality.warnings()) if ctx.quality is not None else ()
    blocks.append(Block(kind="list", caption="Data quality (units, missing cells, gaps, "
                        "glitches)", items=issues or ("no issue found: units named, no "
                                                      "missing cells, no gaps, no glitches",)))
    stats = [[name, st["mean"], st["std"], st["min"], st["max"]]
             for name, st in info["stats"].items()]
    blocks.append(_table("Statistics of the raw data", ["column", "mean", "std", "min", "max"],
                         stats, numeric=[False, True, True, True, True]))
    if info["comments"]:
        shown = list(info["comments"][:20])
        if len(info["comments"]) > 20:
            shown.append(f"... {len(info['comments']) - 20} more comment line(s)")
        blocks.append(Block(kind="list", caption="Comment lines in the file",
                            items=tuple(shown)))
    steps: list[str] = []
    for i in range(ctx.run.n_axes):
        with _collect_warnings(notes):
            p = ctx.get_prepared(i)
        prefix = f"{ctx.run.axes[i]}: " if ctx.run.n_axes > 1 else ""
        steps += [prefix + s for s in p.steps] or [prefix + "none"]
    blocks.append(Block(kind="list", caption="Preprocessing before the ARMA analysis "
                        "(the Allan analysis uses the raw rate)", items=tuple(steps)))
    return blocks


def _timeseries_blocks(ctx: _Context, notes: list[str]) -> list[Block]:
    from fogts.report.plots import plot_timeseries

    fig = plot_timeseries(ctx.run)
    return [figure_block(fig, id="timeseries", alt="rate and temperature against time",
                         caption="Long records are drawn as a min-max envelope per pixel "
                                 "column, so spikes stay visible.")]


def _allan_blocks(ctx: _Context, i: int, notes: list[str]) -> list[Block]:
    from fogts.report.plots import plot_allan

    res = ctx.get_allan(i)
    with _collect_warnings(notes):
        model = ctx.get_noise(i)
    fig = plot_allan(res, model)
    pct = f"{100 * model.confidence:.1f} %"
    rows = []
    for t in model.terms:
        note = "at zero: upper limit only" if t.at_bound else ""
        if not t.identifiable:
            note = (note + "; " if note else "") + "not identifiable from this τ range"
        rows.append([t.name, _TERM_NAME.get(t.name, t.name), t.value, t.stderr,
                     f"{_num(t.ci_low)} … {_num(t.ci_high)}", t.unit, note])
    blocks = [figure_block(fig, id=f"allan-{i}", alt=f"Allan deviation of {ctx.axis_label(i)}",
                           caption=f"{res.kind} with {pct} confidence intervals; fitted total "
                                   "and each term's own line."),
              _table(f"IEEE-952 noise coefficients ({model.method.upper()} fit, {pct} "
                     "intervals)", ["term", "name", "value", "± std. error", f"{pct} interval",
                                    "unit", "note"], rows,
                     numeric=[False, False, True, True, True, False, False])]
    r = model.readoff
    blocks.append(Block(kind="paragraph", text=(
        f"Classic slope read-offs, for comparison only: N = {_num(r.N)} deg/sqrt(h) "
        f"(−1/2 line at τ = 1 s), K = {_num(r.K)} deg/h^1.5 (+1/2 line at τ = 3 s), "
        f"B = {_num(r.B)} deg/h (curve minimum / 0.664).")))
    pts = [[t, m, n, d, lo, hi, e] for t, m, n, d, lo, hi, e in
           zip(res.tau_s, res.m, res.n, res.dev, res.ci_low, res.ci_high, res.edf, strict=True)]
    blocks.append(_table(f"Allan deviation points [{res.units}]",
                         ["τ (s)", "m", "terms", "deviation", "CI low", "CI high", "edf"], pts))
    if res.dropped:
        blocks.append(Block(kind="list", caption="Taus not computed",
                            items=tuple(f"τ = {_num(d.tau_s)} s: {d.reason}"
                                        for d in res.dropped)))
    return blocks


def _arma_blocks(ctx: _Context, i: int, notes: list[str]) -> list[Block]:
    sel = ctx.get_selection(i)
    crit = sel.criterion.upper()
    rows, highlight = [], []
    for k, c in enumerate(sel.candidates):
        lb = c.diagnostics.ljung_box if c.diagnostics is not None else ()
        remarks = [f"failed: {c.reason}"] if not c.ok else []
        remarks += [f.message for f in c.flags] + list(c.warnings)
        rows.append([c.model, c.rank if c.rank is not None else "–", _fixed(c.aic),
                     _fixed(c.bic), c.sigma2, c.rho_a2, c.rho_ax3,
                     ", ".join(f"{_pval(x.pvalue)} ({x.lag})" for x in lb) or "–",
                     _yes_no(c.white) if c.ok else "–", "; ".join(remarks)])
        if sel.selected is not None and c.model == sel.selected.model:
            highlight.append(k)
    blocks: list[Block] = [
        Block(kind="paragraph", text=f"Data correlogram: {sel.correlogram.summary()}"),
        _table(f"Candidates, ranked by {crit} (the selected model is highlighted)",
               ["model", "rank", "AIC", "BIC", "σ²", "ρ_a,2", "ρ_ax,3",
                "Ljung–Box p (lag)", "white", "notes"], rows,
               numeric=[False, True, True, True, True, True, True, False, False, False],
               highlight=highlight)]
    best = sel.selected
    if best is not None:
        blocks.append(Block(kind="pre", caption=f"Selected model: {best.model}",
                            text=best.equation()))
        blocks.append(_table("Parameters of the selected model (statsmodels names)",
                             ["parameter", "estimate", "± std. error", "t"],
                             [[name, r["estimate"], r["bse"], r["t"]]
                              for name, r in best.to_frame().iterrows()],
                             numeric=[False, True, True, True]))
    blocks.append(Block(kind="verdict", good=not sel.all_white_failed, text=sel.verdict))
    return blocks


def _yes_no(v: Any) -> str:
    return "–" if v is None else ("yes" if v else "no")


def _prediction_blocks(ctx: _Context, i: int, notes: list[str]) -> list[Block]:
    sel = ctx.get_selection(i)
    best = sel.best  # raises ModelFitError (shown in the section) if every fit failed
    pred = best.predict()
    blocks: list[Block] = []
    try:
        from fogts.report.plots import plot_selection
    except ImportError:  # the ARMA diagnostics figure is not available in this version
        notes.append("the ARMA diagnostics figure (fogts.report.plots.plot_selection) is not "
                     "available in this fogts version")
    else:
        blocks.append(figure_block(plot_selection(sel), id=f"prediction-{i}",
                                   alt=f"ARMA diagnostics of {ctx.axis_label(i)}",
                                   caption="Data ACF and PACF with their bands, the residual "
                                           "ACF, the residual Q-Q plot and the one-step "
                                           "prediction against the data."))
    units = ctx.run.units
    blocks.append(_table(f"One-step-ahead prediction with {pred.model} ({pred.method})",
                         ["", "value"],
                         [[f"std of the prepared data [{units}]",
                           math.sqrt(pred.variance_observed)],
                          [f"std of the one-step residual a_t [{units}]",
                           math.sqrt(pred.variance_residual)],
                          ["share of the variance the prediction removes",
                           pred.variance_removed]],
                         numeric=[False, True]))
    d = best.diagnostics
    if d is not None:
        rows: list[list[Any]] = [
            ["ρ_a,2 (seed 000 eq. 11)", d.rho_a2.value, f"|value| ≤ {_num(d.rho_a2.band, 3)}",
             _yes_no(d.rho_a2.passed)],
            ["ρ_ax,3 (seed 000 eq. 12)", d.rho_ax3.value,
             f"|value| ≤ {_num(d.rho_ax3.band, 3)}", _yes_no(d.rho_ax3.passed)]]
        for lb in d.ljung_box:
            pt = _pval(lb.pvalue)
            rows.append([f"Ljung–Box Q at lag {lb.lag} ({lb.df} df)",
                         f"{_num(lb.q)} (p {pt if pt.startswith('<') else '= ' + pt})",
                         "p > 0.05",
                         _yes_no(lb.passed)])
        rows.append(["residual mean", d.mean, "", ""])
        blocks.append(_table(f"Residual diagnostics of {best.model} (n = {d.n})",
                             ["statistic", "value", "white if", "pass"], rows,
                             numeric=[False, True, False, False]))
        blocks.append(Block(kind="verdict", good=bool(d.white), text=(
            "The residuals are white: the model captures the drift's correlation." if d.white
            else "The residuals are not white: " + "; ".join(d.reasons))))
    return blocks


def _davar_blocks(ctx: _Context, i: int, notes: list[str]) -> list[Block]:
    from fogts.allan.dynamic import DynamicAllanResult, dynamic_allan
    from fogts.report.plots import plot_dynamic_allan

    window = float(ctx.options["davar_window_s"])
    step = max(window / 4.0, 1.0 / ctx.run.fs_hz)
    kind = ctx.options["kind"] if ctx.options["kind"] in ("oadev", "mdev", "ohdev") else "oadev"
    res = dynamic_allan(ctx.run, axis=i, window_s=window, step_s=step,
                        kind=kind)  # type: ignore[arg-type]
    assert isinstance(res, DynamicAllanResult)  # one axis was asked for
    fig = plot_dynamic_allan(res)
    ns = res.nonstationarity
    return [figure_block(fig, id=f"davar-{i}",
                         alt=f"dynamic Allan deviation of {ctx.axis_label(i)}",
                         caption=f"{res.kind}, window {_num(res.window_s)} s, step "
                                 f"{_num(res.step_s)} s, {res.shape[0]} windows."),
            Block(kind="verdict", good=bool(ns.stationary), text=ns.summary())]


_TERM_NAME = {"Q": "quantization", "N": "angle random walk", "B": "bias instability",
              "K": "rate random walk", "R": "rate ramp"}


def _thermal_blocks(ctx: _Context, i: int, notes: list[str]) -> list[Block]:
    from fogts.report.plots import plot_compensation
    from fogts.startup import TERM_LETTERS, startup_compensation

    res = startup_compensation(ctx.run, axis=i, emd=False,
                               average_s=ctx.options["bias_average_s"])
    model = res.model
    notes.extend(res.notes)  # dropped terms arrive as UnidentifiableTermWarning notes
    rows = [[t, TERM_LETTERS[t], model.coefficients[t], model.stderr[t]] for t in model.terms]
    b, a = res.before, res.after
    return [
        figure_block(plot_compensation(res), id=f"thermal-{i}",
                     alt=f"thermal compensation of {ctx.axis_label(i)}",
                     caption="Raw and compensated rate (top) and temperature (bottom)."),
        Block(kind="pre", caption="Fitted drift model (seed 004, fitted to the raw rate)",
              text=model.equation()),
        _table("Coefficients", ["term", "letter", "value", "± std. error"], rows,
               numeric=[False, False, True, True]),
        _table(f"Bias stability (1σ of {b.average_s:g} s averages, {b.unit})",
               ["", "bias stability", "windows"],
               [["before compensation", b.value, b.n_windows],
                ["after compensation", a.value, a.n_windows]],
               numeric=[False, True, True]),
        Block(kind="paragraph", text=(
            f"R² = {_num(model.r2)}; residual std {_num(model.residual_std)} {model.units}; "
            f"fitted over T = {_num(model.temperature_range_degC[0])} … "
            f"{_num(model.temperature_range_degC[1])} °C. For seed 004's full start-up "
            "pipeline (EMD trend, ARMA Kalman filter, then this fit) run "
            "'fogts compensate --emd'.")),
    ]


# --------------------------------------------------------------------------- build


_HOW = {
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
    "thermal": "The gyro drift modelled as a function of temperature T and its rate ΔT "
               "(seed 004), and the bias stability before and after removing it; a large "
               "drop in bias stability means temperature drives the drift.",
}

_TITLES = {"input": "Input and preprocessing", "timeseries": "Time series",
           "allan": "Allan deviation and noise coefficients", "arma": "ARMA model selection",
           "prediction": "One-step prediction and residual diagnostics",
           "davar": "Dynamic Allan deviation", "thermal": "Thermal model"}


def _section(sid: str, part: str, title: str, build: Callable[[list[str]], list[Block]]
             ) -> Section:
    notes: list[str] = []
    try:
        with _collect_warnings(notes):
            blocks = build(notes)
    except Exception as exc:
        return Section(id=sid, title=title, how_to_read=_HOW[part], status="error",
                       message=error_message(exc), notes=tuple(notes))
    return Section(id=sid, title=title, how_to_read=_HOW[part], blocks=tuple(blocks),
                   notes=tuple(notes))


def build_report(
    run: Run,
    *,
    quality: Any = None,
    title: str | None = None,
    parts: Sequence[str] = PARTS,
    outliers: float | None = None,
    detrend: int | None = None,
    decimate: int | None = None,
    kind: str = "oadev",
    taus: str = "octave",
    criterion: str = "aic",
    davar_window_s: float | None = None,
    bias_average_s: float = 10.0,
) -> HtmlReport:
    """Run the analyses on ``run`` and collect the report's sections.

    Parameters
    ----------
    run : Run
        The recording (from :func:`fogts.io.reader.read_run`).
    quality : DataQuality, optional
        Its hygiene (:func:`fogts.preprocess.hygiene.assess_run`); computed with the default gap
        policy (warn) when not given.  Shown in the input section.
    title : str, optional
        Document title (default: "Gyro report: <file name>").
    parts : sequence of str
        Which parts to include, from :data:`PARTS` (default: all that apply).
    outliers, detrend, decimate
        Preprocessing before the ARMA analysis (see :func:`fogts.preprocess.prepare`).
    kind, taus
        Allan estimator and tau grid.
    criterion : str
        ARMA ranking criterion.
    davar_window_s : float, optional
        DAVar window (default: a tenth of the record, at least
        :data:`DAVAR_MIN_WINDOW_SAMPLES` samples).
    bias_average_s : float
        Averaging time of the bias stability in the thermal section.

    Returns
    -------
    HtmlReport

    Raises
    ------
    DataError
        An unknown part, or ``run`` is not a Run.
    """
    from fogts._validate import check_choice, check_positive
    from fogts._version import __version__

    if not isinstance(run, Run):
        raise DataError(f"run must be a fogts Run (see fogts.io.reader.read_run), got "
                        f"{type(run).__name__}")
    wanted = list(parts)
    for p in wanted:
        check_choice("parts", p, PARTS)
    check_choice("kind", kind, ("adev", "oadev", "mdev", "hdev", "ohdev", "totdev"))
    check_choice("taus", taus, ("octave", "decade", "dense", "all"))
    check_choice("criterion", criterion, ("aic", "bic", "hqic", "aicc"))
    bias_average_s = check_positive("bias_average_s", bias_average_s)
    if davar_window_s is not None:
        davar_window_s = check_positive("davar_window_s", davar_window_s)
    if quality is None:
        from fogts.preprocess.hygiene import assess_run

        run, quality = assess_run(run)
    ctx = _Context(run=run, quality=quality, options={"outliers": outliers, "detrend": detrend,
                                     "decimate": decimate, "kind": kind, "taus": taus,
                                     "criterion": criterion, "davar_window_s": davar_window_s,
                                     "bias_average_s": bias_average_s})
    sections: list[Section] = []
    omitted: list[tuple[str, str]] = []
    axes = range(run.n_axes)

    def per_axis(part: str, builder: Callable[[_Context, int, list[str]], list[Block]]
                 ) -> None:
        for i in axes:
            suffix = f" — axis {run.axes[i]}" if run.n_axes > 1 else ""

            def build(notes: list[str], i: int = i) -> list[Block]:
                return builder(ctx, i, notes)

            sections.append(_section(f"{part}-{i + 1}", part, _TITLES[part] + suffix, build))

    for part in PARTS:
        if part not in wanted:
            continue
        if part == "input":
            sections.append(_section("input", part, _TITLES[part],
                                     lambda notes: _input_blocks(ctx, notes)))
        elif part == "timeseries":
            sections.append(_section("timeseries", part, _TITLES[part],
                                     lambda notes: _timeseries_blocks(ctx, notes)))
        elif part == "allan":
            per_axis(part, _allan_blocks)
        elif part == "arma":
            per_axis(part, _arma_blocks)
        elif part == "prediction":
            per_axis(part, _prediction_blocks)
        elif part == "davar":
            window = _davar_window(run, davar_window_s)
            if window is None:
                omitted.append((_TITLES[part], _davar_too_short(run)))
            else:
                ctx.options["davar_window_s"] = window
                per_axis(part, _davar_blocks)
        elif part == "thermal":
            if run.temperature is None:
                omitted.append((_TITLES[part], "the file has no temperature column (name it "
                                "T or temperature, or pass --temperature-column)"))
            else:
                per_axis(part, _thermal_blocks)

    name = Path(run.source).name if run.source and not run.source.startswith("<") \
        else run.source
    return HtmlReport(
        title=title if title else f"Gyro report: {name}",
        source=f"{run.source} — {run.n:,} samples at {_num(run.fs_hz, 6)} Hz "
               f"({_duration_text(run.duration_s)}), rate in {run.units}",
        generated=_dt.datetime.now(_dt.UTC).strftime("%Y-%m-%d %H:%M UTC"),
        version=__version__, sections=tuple(sections), omitted=tuple(omitted))


def write_report(path: str | os.PathLike[str], report: HtmlReport) -> Path:
    """Render ``report`` and write it atomically to ``path``."""
    from fogts.io.writer import write_text_atomic

    return write_text_atomic(path, report.render())


# --------------------------------------------------------------------------- DAVar window


def _davar_window(run: Run, window_s: float | None) -> float | None:
    """The DAVar window in seconds, or None if the record is too short for one."""
    min_window = DAVAR_MIN_WINDOW_SAMPLES / run.fs_hz
    if window_s is None:
        window_s = max(run.duration_s / DAVAR_MIN_WINDOWS, min_window)
    if window_s < min_window or run.duration_s < DAVAR_MIN_WINDOWS * window_s - 1e-9:
        return None
    return window_s


def _davar_too_short(run: Run) -> str:
    need = DAVAR_MIN_WINDOWS * DAVAR_MIN_WINDOW_SAMPLES
    return (f"the record has {run.n:,} samples; the dynamic Allan deviation needs at least "
            f"{DAVAR_MIN_WINDOWS} windows of {DAVAR_MIN_WINDOW_SAMPLES} samples ({need:,} "
            "samples)")
