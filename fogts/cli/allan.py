"""`fogts allan`: Allan deviation with confidence intervals, the IEEE-952 noise terms and the curve read-outs."""

from __future__ import annotations

import warnings
from pathlib import Path
from typing import Annotated, Any

import typer

from fogts.cli._common import (
    FsOpt,
    GapsOpt,
    JsonOpt,
    NanOpt,
    RateColOpt,
    TempColOpt,
    TimeColOpt,
    UnitsOpt,
    _axis_index,
    _check_output_names,
    _emit_json,
    _guard,
    _print,
    _read,
    _save_figure,
    _say,
    _table,
    _tau_option,
    app,
    err_console,
)


def _allantools_check(y: Any, res: Any) -> dict[str, Any]:
    """Run allantools on the same data and taus; the largest relative difference."""
    import allantools
    import numpy as np

    funcs = {"adev": allantools.adev, "oadev": allantools.oadev, "mdev": allantools.mdev,
             "hdev": allantools.hdev, "ohdev": allantools.ohdev, "totdev": allantools.totdev}
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        taus, dev, _, n = funcs[res.kind](np.asarray(y, dtype=np.float64), rate=res.fs_hz,
                                          data_type="freq", taus=np.asarray(res.tau_s))
    m_peer = np.rint(np.asarray(taus) * res.fs_hz).astype(np.int64)
    common, mine, theirs = np.intersect1d(res.m, m_peer, return_indices=True)
    peer = np.asarray(dev, dtype=np.float64)[theirs]
    label = f"allantools {allantools.__version__} {res.kind}(data_type='freq')"
    if res.bias_corrected:  # allantools' totdev is uncorrected: apply fogts' bias to it
        from fogts.allan.confidence import totdev_bias

        peer = peer / np.sqrt(totdev_bias(res.alpha[mine], res.m[mine], res.n_samples + 1))
        label += " / sqrt(fogts' totdev_bias)"
    rel = np.abs(res.dev[mine] - peer) / np.abs(peer)
    worst = int(np.argmax(rel)) if rel.size else -1
    return {"peer": label,
            "n_compared": int(common.size),
            "max_rel_diff": float(rel[worst]) if rel.size else None,
            "tau_at_max": float(res.tau_s[mine][worst]) if rel.size else None,
            "n_terms_equal": bool(np.array_equal(res.n[mine], np.asarray(n)[theirs]))}


def _allan_axis_payload(res: Any, model: Any, prepared: Any, check: Any) -> dict[str, Any]:
    import numpy as np

    points = res.to_dict()["points"]
    fit = model.curve(res.tau_s) if model is not None else np.full(len(points), np.nan)
    for p, f in zip(points, fit, strict=True):
        p["fit"] = float(f)
    out: dict[str, Any] = {
        "axis": res.axis, "kind": res.kind, "units": res.units,
        "confidence": res.confidence, "bias_corrected": res.bias_corrected, "points": points,
        "noise": model.noise_dict() if model is not None else {},
        "noise_fit": ({k: v for k, v in model.to_dict().items() if k != "terms"}
                      if model is not None else
                      {"skipped": f"IEEE-952 terms are fitted to adev, oadev or totdev curves "
                                  f"only, not {res.kind}"}),
        "dropped": [d.to_dict() for d in res.dropped], "notes": list(res.notes),
        "preprocessing": prepared.to_dict() if prepared is not None else None,
    }
    if check is not None:
        out["allantools_check"] = check
    return out


def _allan_tables(res: Any, model: Any, check: Any, quiet_json: str | None) -> None:
    import math

    def g(v: float, digits: int = 5) -> str:
        return "-" if v is None or not math.isfinite(v) else f"{v:.{digits}g}"

    from rich.markup import escape

    pct = f"{100 * res.confidence:.1f} % CI" if math.isfinite(res.confidence) else "no CI"
    rows = [[g(t, 6), int(m), int(n), g(d), g(lo), g(hi), g(e, 4)]
            for t, m, n, d, lo, hi, e in zip(res.tau_s, res.m, res.n, res.dev, res.ci_low,
                                             res.ci_high, res.edf, strict=True)]
    corrected = ", bias-corrected (Howe 1999)" if res.bias_corrected else ""
    _print(_table(escape(f"{res.kind} of {res.axis} ({res.units}), {pct}{corrected}"),
                  ["tau (s)", "m", "n", "dev", "ci_low", "ci_high", "edf"], rows),
           quiet_json=quiet_json)
    for d in res.dropped:
        _say([f"dropped tau = {d.tau_s:g} s (m = {d.m}): {d.reason}"], quiet_json)
    if model is not None:
        trows = []
        for t in model.terms:
            note = "upper limit only" if t.at_bound or not t.identifiable else ""
            trows.append([t.name, f"{t.value:.4g}", g(t.stderr, 3),
                          f"{t.ci_low:.4g} .. {t.ci_high:.4g}", t.unit, note])
        pct = f"{100 * model.confidence:.1f} %"
        _print(_table(escape(f"IEEE-952 noise terms of {res.axis} ({model.method.upper()} "
                             f"fit)"),
                      ["term", "value", "± stderr", f"{pct} interval", "unit", "note"],
                      trows), quiet_json=quiet_json)
        _say(["seed-paper coefficients C_n (rate in deg/h, tau in s): "
              + ", ".join(f"C{t.power:+d} = {t.c_coeff:.4g}" for t in model.terms)], quiet_json)
        r = model.readoff
        _say([f"slope read-offs (comparison only, not the fit): N = {r.N:.4g} deg/sqrt(h) "
              f"(-1/2 line at tau = 1 s), K = {r.K:.4g} deg/h^1.5 (+1/2 line at tau = 3 s), "
              f"B = {r.B:.4g} deg/h (minimum / 0.664)"], quiet_json)
        _say([f"fit: chi2 = {model.chi2:.4g} on {model.dof:.4g} dof, model error "
              f"{model.model_error:.3g}; standard errors: {model.stderr_method}"], quiet_json)
    if check is not None:
        worst = check["max_rel_diff"]
        _say([f"allantools check ({check['peer']}): largest relative difference "
              f"{g(worst, 3)} over {check['n_compared']} taus"
              + (f" (at tau = {check['tau_at_max']:g} s)" if worst is not None else "")
              + ("" if check["n_terms_equal"] else "; the numbers of terms differ")], quiet_json)


@app.command("allan")
def allan_cmd(
    files: Annotated[list[Path], typer.Argument(help="Input recording(s). Several files (or a multi-axis file) are overlaid on one --plot for comparing gyros.")],
    rate_column: RateColOpt = None,
    time_column: TimeColOpt = None,
    temperature_column: TempColOpt = None,
    fs: FsOpt = None,
    units: UnitsOpt = None,
    kind: Annotated[str, typer.Option("--kind", help="Estimator: oadev, adev, mdev, hdev, ohdev, totdev (noise terms are fitted to adev, oadev and totdev).")] = "oadev",
    taus: Annotated[str, typer.Option("--taus", help="Tau grid: octave, decade, dense, all, or taus in s separated by commas.")] = "octave",
    confidence: Annotated[float, typer.Option("--confidence", help="Confidence level of the deviation and coefficient intervals.")] = 0.683,
    terms: Annotated[str, typer.Option("--terms", help="Noise terms to fit, from Q,N,B,K,R.")] = "Q,N,B,K,R",
    method: Annotated[str, typer.Option("--method", help="Noise fit: wls (EDF weights), gls (full covariance), ols (unweighted, comparison only).")] = "wls",
    keep_all_terms: Annotated[bool, typer.Option("--keep-all-terms", help="Keep every --terms term in the fit even when the data do not support it (default: drop terms that are not significant at 5 % and visible at fewer than two taus).")] = False,
    axis: Annotated[str | None, typer.Option("--axis", help="Analyse one axis (name or index) (default: every axis).")] = None,
    outliers: Annotated[float | None, typer.Option("--outliers", help="Replace samples beyond this many robust sigmas first (default: raw data).")] = None,
    detrend: Annotated[int | None, typer.Option("--detrend", help="Remove a polynomial trend of this order first (default: raw data).")] = None,
    decimate: Annotated[int | None, typer.Option("--decimate", help="Block-average K samples first (default: raw data).")] = None,
    json_out: JsonOpt = None,
    csv_out: Annotated[Path | None, typer.Option("--csv", help="Write the points (and the fitted curve) to PATH (.csv, .tsv, .parquet).")] = None,
    plot: Annotated[Path | None, typer.Option("--plot", help="Log-log figure with CIs, the fit and its term lines (several inputs: an overlay): .png, .svg or .pdf.")] = None,
    check_allantools: Annotated[bool, typer.Option("--check-allantools", help="Recompute with allantools on the same data and taus; print the largest relative difference.")] = False,
    bias_correction: Annotated[bool, typer.Option("--bias-correction", help="--kind totdev: divide TOTVAR by its bias at flicker- and random-walk-FM taus (Howe 1999), as Stable32 does.")] = False,
    nan: NanOpt = "error",
    gaps: GapsOpt = "warn",
) -> None:
    """Allan deviation with confidence intervals, the IEEE-952 noise terms (Q, N, B, K, R)
    with standard errors, and the curve read-outs (minimum, regions, slopes).

    The data are analysed raw unless --outliers, --detrend or --decimate is given. JSON for
    one file: {"input", "kind", "units", "points", "noise", "curve", ...}; a multi-axis file
    adds "axes" (one such block per axis; the top level repeats the first axis). Several
    files give {"inputs": [one such object per file]}.
    """
    from fogts.allan.noise import parse_terms

    with _guard(outputs={"--json": json_out, "--csv": csv_out, "--plot": plot},
                inputs={"FILES": files}):
        tau_spec = _tau_option(taus)
        term_names = parse_terms(terms)
        _check_output_names(plot=plot, csv=csv_out)
        analyses = [_allan_file(f, rate_column, time_column, temperature_column, fs, units,
                                kind=kind, taus=tau_spec, confidence=confidence,
                                terms=term_names, method=method,
                                keep_all_terms=keep_all_terms, axis=axis, outliers=outliers,
                                detrend=detrend, decimate=decimate,
                                check_allantools=check_allantools,
                                bias_correction=bias_correction, nan=nan, gaps=gaps)
                    for f in files]
        payload = (analyses[0].payload if len(analyses) == 1
                   else {"inputs": [a.payload for a in analyses]})
        _emit_json(payload, json_out)
        if csv_out is not None:
            _allan_csv(analyses, csv_out)
        if plot is not None:
            _save_figure(_allan_figure(analyses), plot)
        for a in analyses:
            run = a.run
            _say([f"{run.source}: {run.n} samples at {run.fs_hz:.6g} Hz "
                  f"({run.duration_s:.6g} s), rate in {run.units}"], json_out)
            for res, model, readout, check, lines in zip(a.results, a.models, a.readouts,
                                                         a.checks, a.lines, strict=True):
                if lines:
                    _say([f"{res.axis}: {line}" for line in lines], json_out)
                _allan_tables(res, model, check, json_out)
                _curve_table(res, readout, json_out)


class _AllanAnalysis:
    """Everything `fogts allan` computed for one input file."""

    def __init__(self, run: Any, quality: Any) -> None:
        self.run = run
        self.quality = quality
        self.results: list[Any] = []
        self.models: list[Any] = []
        self.readouts: list[Any] = []
        self.checks: list[Any] = []
        self.blocks: list[dict[str, Any]] = []
        self.lines: list[list[str]] = []  # preprocessing and data notes, one list per axis

    @property
    def payload(self) -> dict[str, Any]:
        run, first = self.run, self.blocks[0]
        out: dict[str, Any] = {
            "input": {"source": run.source, "n": run.n, "fs_hz": run.fs_hz,
                      "duration_s": run.duration_s, "units": run.units,
                      "units_source": run.units_source,
                      "axis": first["axis"], "axes": [b["axis"] for b in self.blocks],
                      "columns": list(run.columns)},
            **first,
            "data_quality": self.quality.to_dict(),
        }
        if len(self.blocks) > 1:
            out["axes"] = self.blocks
        return out


def _allan_file(file: Path, rate_column: str | None, time_column: str | None,
                temperature_column: str | None, fs: float | None, units: str | None, *,
                kind: str, taus: Any, confidence: float, terms: tuple[str, ...], method: str,
                keep_all_terms: bool, axis: str | None, outliers: float | None, detrend: int | None,
                decimate: int | None, check_allantools: bool,
                bias_correction: bool = False, nan: str = "error",
                gaps: str = "warn") -> _AllanAnalysis:
    from fogts.allan import AllanResult, allan_deviation
    from fogts.allan.noise import FITTABLE_KINDS, fit_noise
    from fogts.errors import FogtsWarning
    from fogts.preprocess.prepare import prepare

    run, quality = _read(file, rate_column, time_column, temperature_column, fs, units,
                         nan=nan, gaps=gaps)
    analysis = _AllanAnalysis(run, quality)
    for i in _axis_picks(run, axis):
        prepared = None
        source: Any = run
        y = run.axis(i)
        if outliers is not None or detrend is not None or decimate is not None:
            prepared = prepare(run, axis=i, outliers=outliers, detrend=detrend,
                               decimate=decimate, stationarity=False)
            source, y = prepared, prepared.x
        res = allan_deviation(source, kind=kind, taus=taus,  # type: ignore[arg-type]
                              confidence=confidence, axis=None if prepared else i,
                              bias_correction=bias_correction)
        assert isinstance(res, AllanResult)
        model = (fit_noise(res, terms=terms, method=method,  # type: ignore[arg-type]
                           confidence=confidence,
                           significance=None if keep_all_terms else 0.05)
                 if res.kind in FITTABLE_KINDS else None)
        if model is None:
            warnings.warn(f"noise terms are fitted to adev, oadev or totdev curves only; "
                          f"not fitted to {res.kind}", FogtsWarning, stacklevel=1)
        readout = res.readout(model)
        check = _allantools_check(y, res) if check_allantools else None
        block = _allan_axis_payload(res, model, prepared, check)
        block["curve"] = readout.to_dict()
        lines = list(prepared.steps) if prepared is not None else []
        if prepared is not None and prepared.outliers is not None:
            unscreened = (prepare(run, axis=i, outliers=None, detrend=detrend,
                                  decimate=decimate, stationarity=False)
                          if detrend is not None or decimate is not None else run)
            effect = _outlier_effect(prepared, model, unscreened, i, lambda r: fit_noise(
                r, terms=terms, method=method, confidence=confidence,  # type: ignore[arg-type]
                significance=None if keep_all_terms else 0.05), kind=kind, taus=taus,
                confidence=confidence, bias_correction=bias_correction)
            block["outliers_effect"] = effect
            lines.append(effect["text"])
        if model is not None:
            plausibility = _plausibility(model, run.units)
            block["plausibility"] = plausibility.to_dict()
            if plausibility.verdict == "implausible" or (run.units_assumed
                                                          and plausibility.ambiguous):
                err_console.print(f"warning: {Path(run.source).name}: {res.axis}: "
                                  f"{plausibility.message}", markup=False, soft_wrap=True)
        analysis.lines.append(lines)
        analysis.results.append(res)
        analysis.models.append(model)
        analysis.readouts.append(readout)
        analysis.checks.append(check)
        analysis.blocks.append(block)
    return analysis


def _plausibility(model: Any, units: str) -> Any:
    """N and B against the range real gyros span (:mod:`fogts.allan.plausibility`)."""
    from fogts.allan.plausibility import check_plausibility

    def value(name: str) -> float | None:
        return model[name].value if name in model.names else None

    return check_plausibility(value("N"), value("B"), units=units)


def _outlier_effect(prepared: Any, model: Any, unscreened: Any, axis: int, fit: Any, *,
                    kind: str, taus: Any, confidence: float,
                    bias_correction: bool) -> dict[str, Any]:
    """How many samples ``--outliers`` replaced and what that did to N (the same analysis
    on the data without the replacement)."""
    from fogts.allan import allan_deviation

    report = prepared.outliers
    share = report.count / max(prepared.n_input, 1)
    out: dict[str, Any] = {"replaced": report.count, "share": share,
                           "sigma_factor": report.sigma_factor}
    text = (f"--outliers {report.sigma_factor:g}: replaced {report.count:,} of "
            f"{prepared.n_input:,} samples ({100 * share:.3g} %)")
    if model is None or "N" not in model.names:
        out["text"] = text
        return out
    raw = allan_deviation(unscreened, kind=kind, taus=taus,  # type: ignore[arg-type]
                          confidence=confidence,
                          axis=None if unscreened is not prepared and hasattr(unscreened, "x")
                          else axis, bias_correction=bias_correction)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # the unscreened fit's own warnings are not news
        raw_model = fit(raw)
    n_clean = model["N"].value
    n_raw = raw_model["N"].value if "N" in raw_model.names else float("nan")
    change = n_clean / n_raw - 1.0 if n_raw > 0 else float("nan")
    out.update({"N": n_clean, "N_unscreened": n_raw, "N_change": change})
    out["text"] = (f"{text}; N = {n_clean:.4g} {model['N'].unit} against {n_raw:.4g} without "
                   f"the replacement ({100 * change:+.1f} %)")
    return out


def _axis_picks(run: Any, axis: str | None) -> list[int]:
    return list(range(run.n_axes)) if axis is None else [_axis_index(run, axis)]


def _allan_csv(analyses: list[_AllanAnalysis], target: Path) -> None:
    import pandas as pd

    from fogts.io.writer import write_frame_atomic

    frames = []
    many_files = len(analyses) > 1
    for a in analyses:
        for res, model in zip(a.results, a.models, strict=True):
            frame = res.to_frame()
            frame["fit"] = model.curve(res.tau_s) if model is not None else float("nan")
            if len(a.results) > 1 or many_files:
                frame.insert(0, "axis", res.axis)
            if many_files:
                frame.insert(0, "source", a.run.source)
            frames.append(frame)
    write_frame_atomic(target, pd.concat(frames, ignore_index=True))


def _allan_figure(analyses: list[_AllanAnalysis]) -> Any:
    from fogts.allan import AllanResultSet
    from fogts.report.plots import plot_allan, plot_allan_overlay

    if len(analyses) == 1:
        a = analyses[0]
        if len(a.results) == 1:
            return plot_allan(a.results[0], a.models[0])
        complete = all(m is not None for m in a.models)
        return plot_allan(AllanResultSet(curves=tuple(a.results)),
                          a.models if complete else None)
    curves, models, labels = [], [], []
    for a in analyses:
        for res, model in zip(a.results, a.models, strict=True):
            curves.append(res)
            models.append(model)
            name = Path(a.run.source).name
            labels.append(name if len(a.results) == 1 else f"{name}: {res.axis}")
    return plot_allan_overlay(curves, labels, models)


def _curve_table(res: Any, readout: Any, quiet_json: str | None) -> None:
    from rich.markup import escape

    lo, hi = readout.dev_min_ci
    rows: list[list[Any]] = [["minimum", f"{readout.tau_min_s:.4g} s",
                              f"{readout.dev_min:.4g} [{lo:.4g}, {hi:.4g}] {res.units}"]]
    for name, label in (("B", "falling (B)"), ("C", "floor (C)"), ("D", "rising (D)")):
        span = readout.regions[name]
        if span is not None:
            rows.append([label, f"{span[0]:.4g} .. {span[1]:.4g} s", ""])
    for d in readout.dominant:
        rows.append([f"{d.term} dominates", f"{d.tau_from_s:.4g} .. {d.tau_to_s:.4g} s",
                     f"slope {d.slope:+g}"])
    _print(_table(escape(f"curve of {res.axis}"), ["read-out", "tau", "value"], rows),
           quiet_json=quiet_json)
