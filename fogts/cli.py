"""The ``fogts`` command line (typer).  The only module that prints.

Every command follows the same pattern:

* input options shared by every command (``--rate-column``, ``--time-column``,
  ``--temperature-column``, ``--fs``, ``--units``) come from the ``*Opt`` aliases below and
  are turned into a :class:`fogts.run.Run` by :func:`_read`;
* the body runs inside :func:`_guard`, which maps any exception to one line
  ``error: ...`` on stderr and exit code 2 (no traceback unless ``--debug``);
* JSON goes through :func:`_emit_json` (``-`` means stdout; files are written atomically).

Exit codes (DESIGN.md): 0 success, 1 negative verdict, 2 bad usage/input/internal error.
"""

from __future__ import annotations

import re
import sys
import warnings
from collections.abc import Iterable, Iterator, Mapping
from contextlib import contextmanager
from pathlib import Path
from typing import Annotated, Any

import typer
from rich.console import Console

try:  # typer >= 0.16 vendors click as typer._click
    from typer._click import exceptions as _click_exc
except ImportError:  # pragma: no cover - older typer uses click itself
    from click import exceptions as _click_exc  # type: ignore[no-redef]
from rich.table import Table

from fogts import __version__

app = typer.Typer(
    name="fogts",
    help="Fibre-optic-gyro drift analysis: Allan variance, IEEE-952 noise terms, ARMA models.",
    no_args_is_help=True,
    add_completion=False,
    pretty_exceptions_enable=False,
)
# Outside a terminal (pipes, CI logs, CliRunner) rich would wrap tables at 80 columns.
_WIDTH = None if sys.stdout.isatty() else 120
console = Console(highlight=False, width=_WIDTH)
err_console = Console(stderr=True, highlight=False, width=_WIDTH)

_STATE: dict[str, bool] = {"debug": False}

# ---------------------------------------------------------------- shared input options
FileArg = Annotated[Path, typer.Argument(help="Input recording (CSV/TSV/text, .gz, Parquet, .npy/.npz).")]
RateColOpt = Annotated[str | None, typer.Option("--rate-column", help="Rate column(s), comma-separated; default: auto-detect.")]
TimeColOpt = Annotated[str | None, typer.Option("--time-column", help="Time column; default: auto-detect.")]
TempColOpt = Annotated[str | None, typer.Option("--temperature-column", help="Temperature column; default: auto-detect.")]
FsOpt = Annotated[float | None, typer.Option("--fs", help="Sample rate in Hz (overrides the time column).")]
UnitsOpt = Annotated[str | None, typer.Option("--units", help="Rate unit of the input: deg/h, deg/s, rad/s, arcsec/s (default: from a unit in the column name such as gyro_x_deg_s, else deg/h).")]
JsonOpt = Annotated[str | None, typer.Option("--json", help="Write JSON to PATH, or '-' for stdout.")]
NanOpt = Annotated[str, typer.Option("--nan", help="Empty, NaN or inf cells: error (name the first one), drop (the rows become gaps) or interpolate (linearly in time).")]
GapsOpt = Annotated[str, typer.Option("--gaps", help="Gaps in the time base: warn (analyse as if regular, and say so), error, split (analyse the longest regular segment) or ignore (no warning; still in the JSON).")]


class ExitCode:
    OK = 0
    NEGATIVE = 1
    ERROR = 2


def _version_callback(value: bool) -> None:
    if value:
        console.print(f"fogts {__version__}")
        raise typer.Exit(0)


@app.callback()
def _main_options(
    version: Annotated[bool, typer.Option("--version", callback=_version_callback,
                                          is_eager=True, help="Print the version and exit.")] = False,
    debug: Annotated[bool, typer.Option("--debug", help="Show tracebacks on errors.")] = False,
) -> None:
    """fogts: turn a static gyro recording into a validated noise model."""
    _STATE["debug"] = debug


@contextmanager
def _guard(options: Mapping[str, str] | None = None, *,
           outputs: Mapping[str, Path | str | None] | None = None,
           inputs: Mapping[str, Iterable[Path]] | None = None) -> Iterator[None]:
    """Run a command body: warnings become ``warning: ...`` lines on stderr (each once),
    and any exception becomes one line ``error: ...`` on stderr with exit code 2.

    ``options`` maps library argument names (``latitude_deg``) to the command's option
    names (``--latitude``), so that an error raised by the library names what the user
    typed.  ``outputs`` (option -> path) and ``inputs`` (argument -> paths) are checked by
    :func:`fogts.paths.check_outputs` before the body runs: no output replaces an input."""
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("default")
        try:
            if outputs:
                from fogts.paths import check_outputs

                check_outputs(outputs, inputs or {})
            yield
        except (typer.Exit, typer.Abort):
            raise
        except Exception as exc:
            if _STATE["debug"]:
                raise
            from fogts.report import error_message

            message = _option_names(error_message(exc), options or {})
            err_console.print(f"error: {message}", markup=False, soft_wrap=True)
            raise typer.Exit(ExitCode.ERROR) from None
        finally:
            from fogts.report import warning_texts

            for text in warning_texts(caught):
                err_console.print(f"warning: {text}", markup=False, soft_wrap=True)


def _option_names(message: str, options: Mapping[str, str]) -> str:
    """Replace whole-word library argument names in ``message`` by option names."""
    for name, option in options.items():
        message = re.sub(rf"(?<![\w-]){re.escape(name)}(?!\w)", option, message)
    return message


#: Library argument names of ``fogts simulate`` (both modes) and their options.
_SIMULATE_OPTIONS = {
    "fs_hz": "--fs", "duration_s": "--duration", "latitude_deg": "--latitude",
    "azimuth_deg": "--azimuth", "position_s": "--position-time", "turn_s": "--turn-time",
    "start_delay_s": "--start-after", "start_s": "--start-after",
    "ambient_degC": "--ambient-c", "peak_rate_degC_s": "--peak-heating-c-s",
    "tau_s": "--time-constants", "white_sigma_deg_h": "--white-deg-h",
    "temperature_resolution_degC": "--temperature-resolution-c",
}
#: ... and of ``fogts northfind``.
_NORTHFIND_OPTIONS = {"latitude_deg": "--latitude", "transition_s": "--transition",
                      "bias_sigma_deg_h": "--bias-sigma", "n_trials": "--simulate"}


def _read(path: Path, rate_column: str | None, time_column: str | None,
          temperature_column: str | None, fs: float | None, units: str | None, *,
          nan: str = "error", gaps: str = "warn", glitches: bool = True) -> tuple[Any, Any]:
    """Read one input and check its hygiene (:func:`fogts.hygiene.assess_run`): assumed
    units, missing cells, gaps and glitches are printed at once as ``warning:`` lines
    naming the file, before any analysis output.  Returns the Run (restricted to the
    longest regular segment with ``--gaps split``) and its DataQuality."""
    from fogts.hygiene import assess_run
    from fogts.io import read_run

    rate_cols: str | list[str] | None = None
    if rate_column:
        parts = [c.strip() for c in rate_column.split(",") if c.strip()]
        rate_cols = parts if len(parts) > 1 else parts[0]
    run = read_run(path, rate_column=rate_cols, time_column=time_column,
                   temperature_column=temperature_column, fs_hz=fs, units=units, nan=nan)
    run, quality = assess_run(run, gaps=gaps, glitches=glitches)  # type: ignore[arg-type]
    for line in quality.warnings():
        err_console.print(f"warning: {Path(run.source).name}: {line}", markup=False,
                          soft_wrap=True)
    return run, quality


def _emit_json(payload: dict[str, Any], target: str | None) -> None:
    """Write ``payload`` as JSON to ``target`` ('-' = stdout); files are written atomically."""
    if target is None:
        return
    from fogts.io import write_text_atomic
    from fogts.report import json_dumps

    text = json_dumps(payload)
    if target == "-":
        sys.stdout.write(text + "\n")
    else:
        write_text_atomic(Path(target), text + "\n")


def _table(title: str, columns: list[str], rows: list[list[Any]]) -> Table:
    table = Table(title=title, title_justify="left")
    for c in columns:
        table.add_column(c, justify="left" if c in ("term", "model", "name", "column", "read-out") else "right")
    for r in rows:
        table.add_row(*[str(v) for v in r])
    return table


def _print(*objects: Any, quiet_json: str | None = None) -> None:
    """Print to the terminal unless JSON goes to stdout (keep stdout parseable)."""
    target = err_console if quiet_json == "-" else console
    target.print(*objects)


# ---------------------------------------------------------------- commands
# (each command lives in its own section below; keep them independent)


# ---- info -------------------------------------------------------------------------------
def _info_payload(run: Any) -> dict[str, Any]:
    from fogts.report import run_info

    return run_info(run)


@app.command("info")
def info_cmd(
    file: FileArg,
    rate_column: RateColOpt = None,
    time_column: TimeColOpt = None,
    temperature_column: TempColOpt = None,
    fs: FsOpt = None,
    units: UnitsOpt = None,
    nan: NanOpt = "error",
    json_out: JsonOpt = None,
) -> None:
    """Show what was read: columns, sample rate, duration, gaps, jitter, glitches and
    statistics."""
    with _guard(outputs={"--json": json_out}, inputs={"FILE": [file]}):
        run, quality = _read(file, rate_column, time_column, temperature_column, fs, units,
                             nan=nan, gaps="ignore")
        payload = {**_info_payload(run), "data_quality": quality.to_dict()}
        _emit_json(payload, json_out)
        if json_out != "-":
            from fogts.report import info_text

            console.print(info_text(payload), markup=False, soft_wrap=True)


# ---- allan ------------------------------------------------------------------------------
_TAU_GRIDS = ("octave", "decade", "dense", "all")


def _tau_option(text: str, option: str = "--taus") -> Any:
    """``octave``, ``decade``, ``dense``, ``all``, or taus in seconds separated by commas."""
    from fogts.errors import DataError

    if text in _TAU_GRIDS:
        return text
    try:
        values = [float(t) for t in text.split(",") if t.strip()]
    except ValueError:
        values = []
    if not values:
        raise DataError(f"{option} must be {', '.join(_TAU_GRIDS)} or taus in seconds "
                        f"separated by commas; got {text!r}")
    return values


_FIGURE_SUFFIXES = (".png", ".svg", ".pdf")
_TABLE_SUFFIXES = (".csv", ".csv.gz", ".tsv", ".txt", ".parquet", ".pq")


def _check_output_names(**outputs: Path | None) -> None:
    """Reject output names the writers would refuse, before any analysis runs.

    ``plot`` must be a figure (.png, .svg, .pdf); every other keyword names a table option
    (``csv=...`` is ``--csv``) written by :func:`fogts.io.write_frame_atomic`.
    """
    from fogts.errors import DataError

    for option, path in outputs.items():
        if path is None:
            continue
        name = path.name.lower()
        if option == "plot" and not name.endswith(_FIGURE_SUFFIXES):
            raise DataError(f"--plot must end in .png, .svg or .pdf; got {path.name!r}")
        if option != "plot" and not name.endswith(_TABLE_SUFFIXES):
            raise DataError(f"--{option} must end in .csv, .csv.gz, .tsv, .txt or .parquet; "
                            f"got {path.name!r}")


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
    from fogts.preprocess import prepare

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
    if axis is None:
        return list(range(run.n_axes))
    if axis.lstrip("-").isdigit():
        run.axis(int(axis))  # validates the index
        return [int(axis) % run.n_axes]
    run.axis(axis)  # validates the name
    return [run.axes.index(axis)]


def _allan_csv(analyses: list[_AllanAnalysis], target: Path) -> None:
    import pandas as pd

    from fogts.io import write_frame_atomic

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
    from fogts.plots import plot_allan, plot_allan_overlay

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


# ---- batch ------------------------------------------------------------------------------
@app.command("batch")
def batch_cmd(
    patterns: Annotated[list[str], typer.Argument(help="Input files or glob patterns (quote them to let fogts expand '**').")],
    output: Annotated[Path, typer.Option("--output", "-o", help="Summary table (.csv or .parquet): one row per run and axis.")],
    json_dir: Annotated[Path | None, typer.Option("--json-dir", help="Folder for the per-run JSON (default: <summary name>_runs beside the summary).")] = None,
    workers: Annotated[int | None, typer.Option("--workers", help="Local worker processes (default: the number of CPUs).")] = None,
    scheduler: Annotated[str | None, typer.Option("--scheduler", help="Dask scheduler address (tcp://host:8786): run on that cluster instead of locally (needs the fogts\\[dask] extra).")] = None,
    resume: Annotated[bool, typer.Option("--resume", help="Skip runs whose per-run JSON already exists (delete a failed run's JSON to retry it).")] = False,
    rate_column: RateColOpt = None,
    time_column: TimeColOpt = None,
    temperature_column: TempColOpt = None,
    fs: FsOpt = None,
    units: UnitsOpt = None,
    kind: Annotated[str, typer.Option("--kind", help="Allan estimator: adev, oadev, mdev, hdev, ohdev, totdev.")] = "oadev",
    taus: Annotated[str, typer.Option("--taus", help="Tau grid: octave, decade, dense, all.")] = "octave",
    detrend: Annotated[int | None, typer.Option("--detrend", help="Polynomial order removed before the ARMA selection.")] = None,
    decimate: Annotated[int | None, typer.Option("--decimate", help="Block-average K samples before the ARMA selection.")] = None,
    criterion: Annotated[str, typer.Option("--criterion", help="ARMA ranking criterion: aic, bic, hqic, aicc.")] = "aic",
    no_select: Annotated[bool, typer.Option("--no-select", help="Skip the ARMA selection (info and Allan only).")] = False,
    nan: NanOpt = "error",
    gaps: GapsOpt = "warn",
) -> None:
    """Run info, allan and select on many files; write one summary row per run and axis.

    A bad file gives a row with status=error and the message; the batch goes on.

    Exit code 0 if every run is ok, 1 if any failed.
    """
    from rich.progress import (
        BarColumn,
        MofNCompleteColumn,
        Progress,
        SpinnerColumn,
        TextColumn,
        TimeElapsedColumn,
        TimeRemainingColumn,
    )

    from fogts.batch import BatchOptions, BatchProgress, run_batch

    with _guard({"summary_path": "--output", "patterns": "PATTERNS"}):
        options = BatchOptions(rate_column=rate_column, time_column=time_column,
                               temperature_column=temperature_column, fs_hz=fs, units=units,
                               kind=kind, taus=taus, detrend=detrend, decimate=decimate,
                               criterion=criterion, select=not no_select, nan=nan, gaps=gaps)
        bar = Progress(SpinnerColumn(), TextColumn("{task.description}"), BarColumn(),
                       MofNCompleteColumn(),
                       TextColumn("failed {task.fields[failed]}, remaining "
                                  "{task.fields[remaining]}"),
                       TimeElapsedColumn(), TextColumn("ETA"), TimeRemainingColumn(),
                       console=err_console, transient=False)
        task_id: list[Any] = []

        def on_progress(p: BatchProgress) -> None:
            if not task_id:
                task_id.append(bar.add_task("runs", total=p.total, completed=p.done,
                                            failed=p.failed, remaining=p.remaining))
            else:
                bar.update(task_id[0], completed=p.done, failed=p.failed,
                           remaining=p.remaining)

        with bar:
            result = run_batch(patterns, summary_path=output, json_dir=json_dir,
                               workers=workers, scheduler=scheduler, resume=resume,
                               options=options, progress=on_progress)
        console.print(result.summary(), markup=False, soft_wrap=True)
        for line in _batch_quality_lines(result.rows):
            err_console.print(f"warning: {line}", markup=False, soft_wrap=True)
        errors = [r for r in result.rows if r["status"] == "error"]
        if errors:
            from rich.text import Text

            failed = Table(title="failed runs", title_justify="left")
            for c in ("file", "axis", "error"):
                failed.add_column(c)
            for r in errors:  # Text(): file names and messages are not rich markup
                failed.add_row(Text(r["file"]), Text(r["axis"] or ""), Text(r["error"]))
            console.print(failed)
    if result.interrupted:
        err_console.print("error: interrupted; rerun with --resume to finish", markup=False)
        raise typer.Exit(ExitCode.ERROR)
    raise typer.Exit(ExitCode.NEGATIVE if errors else ExitCode.OK)


def _batch_quality_lines(rows: Iterable[Mapping[str, Any]]) -> list[str]:
    """One line per data-quality finding across the batch, naming the files (details in
    each run's JSON ``info.data_quality``)."""
    checks = (("units_source", lambda v: v == "assumed", "rate unit assumed (deg/h)"),
              ("n_gaps", lambda v: bool(v), "gaps in the time base"),
              ("n_glitches", lambda v: bool(v), "glitches"))
    lines = []
    for key, flagged, label in checks:
        files = sorted({Path(str(r["file"])).name for r in rows if flagged(r.get(key))})
        if files:
            lines.append(f"{label} in {len(files)} file(s): {', '.join(files)} (see the per-run "
                         "JSON, info.data_quality)")
    return lines


# ---- report -----------------------------------------------------------------------------
@app.command("report")
def report_cmd(
    file: FileArg,
    output: Annotated[Path, typer.Option("--output", "-o", help="HTML file to write (self-contained: figures embedded, no network needed).")],
    rate_column: RateColOpt = None,
    time_column: TimeColOpt = None,
    temperature_column: TempColOpt = None,
    fs: FsOpt = None,
    units: UnitsOpt = None,
    title: Annotated[str | None, typer.Option("--title", help="Document title (default: 'Gyro report: <file name>').")] = None,
    outliers: Annotated[float | None, typer.Option("--outliers", help="Replace samples beyond this many robust sigmas before the ARMA analysis.")] = None,
    detrend: Annotated[int | None, typer.Option("--detrend", help="Polynomial order removed before the ARMA analysis.")] = None,
    decimate: Annotated[int | None, typer.Option("--decimate", help="Block-average K samples before the ARMA analysis.")] = None,
    kind: Annotated[str, typer.Option("--kind", help="Allan estimator: adev, oadev, mdev, hdev, ohdev, totdev.")] = "oadev",
    taus: Annotated[str, typer.Option("--taus", help="Tau grid: octave, decade, dense, all.")] = "octave",
    criterion: Annotated[str, typer.Option("--criterion", help="ARMA ranking criterion: aic, bic, hqic, aicc.")] = "aic",
    davar_window: Annotated[float | None, typer.Option("--davar-window", help="Dynamic Allan window in seconds (default: a tenth of the record).")] = None,
    nan: NanOpt = "error",
    gaps: GapsOpt = "warn",
) -> None:
    """Write one self-contained HTML report of a recording.

    Sections: input, time series, Allan deviation and noise terms, ARMA selection, prediction, dynamic Allan deviation and the thermal model (the last two when they apply).

    Exit code 1 if a section could not be computed (the report is still written and says why).
    """
    from fogts.report_html import build_report, write_report

    with _guard(outputs={"--output": output}, inputs={"FILE": [file]}):
        run, quality = _read(file, rate_column, time_column, temperature_column, fs, units,
                             nan=nan, gaps=gaps)
        rep = build_report(run, quality=quality, title=title, outliers=outliers, detrend=detrend,
                           decimate=decimate, kind=kind, taus=taus, criterion=criterion,
                           davar_window_s=davar_window)
        write_report(output, rep)
        failed = [s for s in rep.sections if s.status != "ok"]
        for s in failed:
            err_console.print(f"warning: {s.title}: {s.message}", markup=False, soft_wrap=True)
        console.print(f"wrote {output} ({len(rep.sections)} sections, {rep.n_figures} "
                      f"figures)", markup=False, soft_wrap=True)
        for part, why in rep.omitted:
            console.print(f"not included: {part}: {why}", markup=False, soft_wrap=True)
    raise typer.Exit(ExitCode.NEGATIVE if failed else ExitCode.OK)


# ---- simulate ---------------------------------------------------------------------------
_SIM_SUFFIXES = (".csv", ".csv.gz", ".tsv", ".txt", ".parquet", ".pq")


def _pair(text: str | None, option: str, names: str) -> tuple[float, float] | None:
    """Parse ``"a,b"`` into two floats (for --markov and --sine)."""
    import math

    from fogts.errors import DataError

    if text is None:
        return None
    parts = [p.strip() for p in text.split(",")]
    try:
        a, b = (float(p) for p in parts) if len(parts) == 2 else (math.nan, math.nan)
    except ValueError:
        a = b = math.nan
    if not (math.isfinite(a) and math.isfinite(b)):
        raise DataError(f"{option} must be two numbers '{names}', got {text!r}")
    return a, b


def _coefficients(text: str | None, option: str) -> dict[str, float] | None:
    """Parse ``"T=0.02,dT=30,1=0.5"`` into a dict."""
    from fogts.errors import DataError

    if text is None:
        return None
    out: dict[str, float] = {}
    for part in text.split(","):
        key, sep, value = part.partition("=")
        try:
            out[key.strip()] = float(value)
        except ValueError:
            sep = ""
        if not sep:
            raise DataError(f"{option} must look like 'T=0.02,dT=30,1=0.5', got {text!r}")
    return out


@app.command("simulate")
def simulate_cmd(
    output: Annotated[Path, typer.Option("--output", "-o", help="Output file: .csv, .csv.gz, .tsv, .txt or .parquet. The true parameters go to OUTPUT.json beside it.")],
    fs: Annotated[float | None, typer.Option("--fs", help="Sample rate in Hz (default 100; 1 with --startup, as in seed 004).")] = None,
    duration: Annotated[str | None, typer.Option("--duration", help="Record length: 3h, 90min, 600s, 1d, 1h30min or seconds (default 1h).")] = None,
    q_term: Annotated[float, typer.Option("--Q", help="Angle quantisation Q in arcsec.")] = 0.0,
    n_term: Annotated[float, typer.Option("--N", help="Angle random walk N in deg/sqrt(h).")] = 0.0,
    b_term: Annotated[float, typer.Option("--B", help="Bias instability B in deg/h (Allan plateau 0.664 B).")] = 0.0,
    k_term: Annotated[float, typer.Option("--K", help="Rate random walk K in deg/h^1.5.")] = 0.0,
    r_term: Annotated[float, typer.Option("--R", help="Rate ramp R in deg/h^2.")] = 0.0,
    markov: Annotated[str | None, typer.Option("--markov", help="First-order Markov term 'q_c,T_c': q_c in deg/h/sqrt(s), T_c in s.")] = None,
    sine: Annotated[str | None, typer.Option("--sine", help="Sinusoid 'amplitude,frequency': deg/h and Hz.")] = None,
    bias: Annotated[float, typer.Option("--bias", help="Constant rate offset in deg/h.")] = 0.0,
    arma: Annotated[str | None, typer.Option("--arma", help="ARMA drift added to the rate, e.g. 'ar=0.9,-0.2;ma=0.3;sigma2=1e-4' (statsmodels signs; deg/h).")] = None,
    noise_json: Annotated[Path | None, typer.Option("--from-json", help="Take the noise terms from a JSON file: 'fogts allan --json' output, a NoiseModel dict or a simulate sidecar; --Q/--N/... override single terms.")] = None,
    axes: Annotated[int, typer.Option("--axes", help="Number of independent axes (rate_x, rate_y, rate_z).")] = 1,
    temperature_profile: Annotated[str | None, typer.Option("--temperature-profile", help="Temperature column: 'constant:T', 'warmup:START,END,TAU' (degC; TAU like 20min) or 'ramp:START,END'.")] = None,
    thermal: Annotated[str | None, typer.Option("--thermal", help="Temperature-driven drift D = a T dT + b T^2 + c T + d dT^2 + e dT + f, as 'T*dT=a,T2=b,T=c,dT2=d,dT=e,1=f' (deg/h; dT in degC/s); needs --temperature-profile or --startup (default there: T*dT=0.4,T2=0.0015,T=-0.12,dT2=120,dT=25,1=2).")] = None,
    flicker: Annotated[str, typer.Option("--flicker", help="Flicker (B) synthesis: markov (sum of Markov processes, chunked) or kasdin (Kasdin-Walter, in memory).")] = "markov",
    seed: Annotated[int | None, typer.Option("--seed", help="Random seed (default: a fresh one, recorded in the sidecar JSON).")] = None,
    units: Annotated[str, typer.Option("--units", help="Unit of the output rate: deg/h, deg/s, rad/s, arcsec/s (coefficients stay in deg/h-based units).")] = "deg/h",
    decimals: Annotated[int | None, typer.Option("--decimals", help="Round the rate and temperature to this many decimals (smaller files).")] = None,
    startup: Annotated[bool, typer.Option("--startup", help="Simulate a seed-004 cold start instead: warm-up temperature, thermal drift (--thermal), ARMA drift (--arma, default 'ar=0.9;sigma2=0.0025') and white noise; writes time,rate,temperature.", rich_help_panel="Cold start (--startup, seed 004)")] = False,
    ambient_c: Annotated[float | None, typer.Option("--ambient-c", help="Ambient (switch-on) temperature in degC (default 20).", rich_help_panel="Cold start (--startup, seed 004)")] = None,
    peak_heating_c_s: Annotated[float | None, typer.Option("--peak-heating-c-s", help="Peak warm-up rate dT/dt in degC/s (default 0.05, as in seed 004).", rich_help_panel="Cold start (--startup, seed 004)")] = None,
    time_constants: Annotated[str | None, typer.Option("--time-constants", help="Slow and fast warm-up lags 'SLOW,FAST' (default '400s,40s').", rich_help_panel="Cold start (--startup, seed 004)")] = None,
    white_deg_h: Annotated[float | None, typer.Option("--white-deg-h", help="1-sigma white rate noise per sample in deg/h (default 0.3; = 60 N sqrt(fs) with N in deg/sqrt(h)).", rich_help_panel="Cold start (--startup, seed 004)")] = None,
    temperature_resolution_c: Annotated[float | None, typer.Option("--temperature-resolution-c", help="Temperature sensor resolution in degC, 0 = exact (default 0.01).", rich_help_panel="Cold start (--startup, seed 004)")] = None,
    start_after: Annotated[str | None, typer.Option("--start-after", help="Time from switch-on to the first sample, e.g. 10min (default 0).", rich_help_panel="Cold start (--startup, seed 004)")] = None,
    positions: Annotated[bool, typer.Option("--positions", help="Four-position north seeking during the cold start: writes time,position_deg,rate,temperature for 'fogts northfind'; needs --latitude and --azimuth.", rich_help_panel="Cold start (--startup, seed 004)")] = False,
    latitude: Annotated[float | None, typer.Option("--latitude", help="Latitude in degrees (|L| <= 89) for --positions.", rich_help_panel="Cold start (--startup, seed 004)")] = None,
    azimuth: Annotated[float | None, typer.Option("--azimuth", help="True azimuth of the input axis at position 0 in degrees, clockwise from north, for --positions.", rich_help_panel="Cold start (--startup, seed 004)")] = None,
    position_time: Annotated[str | None, typer.Option("--position-time", help="Time measured at each position (default 60s).", rich_help_panel="Cold start (--startup, seed 004)")] = None,
    turn_time: Annotated[str | None, typer.Option("--turn-time", help="Time spent turning between positions, left out of the file (default 10s).", rich_help_panel="Cold start (--startup, seed 004)")] = None,
) -> None:
    """Simulate a static gyro record from IEEE-952 noise coefficients (seed 000 Table 1),
    or with --startup a seed-004 cold start (optionally a four-position north seeking).

    Writes time, rate (rate_x, rate_y, rate_z with --axes 3) and temperature (with a
    profile), and a sidecar JSON OUTPUT.json with the true parameters and the closed-form
    Allan deviation (with --startup: the true thermal coefficients and warm-up parameters).
    """
    import dataclasses

    import numpy as np

    from fogts import __version__ as version
    from fogts.errors import DataError
    from fogts.io import write_frame_atomic, write_text_atomic
    from fogts.report import json_dumps
    from fogts.simulate import (
        ArmaSpec,
        NoiseSpec,
        TemperatureProfile,
        simulate_gyro,
    )
    from fogts.units import parse_duration

    sidecar_path = output.with_name(output.name + ".json")
    with _guard(_SIMULATE_OPTIONS, outputs={"--output": output,
                                            "--output's sidecar": sidecar_path},
                inputs={"--from-json": [noise_json] if noise_json else []}):
        if not output.name.lower().endswith(_SIM_SUFFIXES):
            raise DataError(f"--output must end in {', '.join(_SIM_SUFFIXES)}; got "
                             f"{output.name!r}")
        cold = {"--ambient-c": ambient_c, "--peak-heating-c-s": peak_heating_c_s,
                "--time-constants": time_constants, "--white-deg-h": white_deg_h,
                "--temperature-resolution-c": temperature_resolution_c,
                "--start-after": start_after, "--positions": positions or None,
                "--latitude": latitude, "--azimuth": azimuth,
                "--position-time": position_time, "--turn-time": turn_time}
        if startup:
            noise_opts = {"--Q": q_term, "--N": n_term, "--B": b_term, "--K": k_term,
                          "--R": r_term, "--markov": markov, "--sine": sine,
                          "--from-json": noise_json, "--axes": None if axes == 1 else axes,
                          "--temperature-profile": temperature_profile,
                          "--flicker": None if flicker == "markov" else flicker}
            _simulate_startup(output, fs=fs, duration=duration, seed=seed, units=units,
                              decimals=decimals, bias=bias, arma=arma, thermal=thermal,
                              cold=cold, noise_opts=noise_opts)
            return
        for name, value in cold.items():
            if value is not None:
                raise DataError(f"{name} needs --startup (it describes a cold start)")
        fs = 100.0 if fs is None else fs
        duration_s = parse_duration("1h" if duration is None else duration, "--duration")
        values: dict[str, float] = {}
        if noise_json is not None:
            from fogts.io import read_json

            loaded = read_json(noise_json, "--from-json file")
            values.update(dataclasses.asdict(NoiseSpec.from_any(loaded)))
        given = {"Q": q_term, "N": n_term, "B": b_term, "K": k_term, "R": r_term, "bias": bias}
        values.update({k: v for k, v in given.items() if v != 0.0 or k not in values})
        pm = _pair(markov, "--markov", "q_c,T_c")
        if pm is not None:
            values["q_c"], values["T_c"] = pm
        ps = _pair(sine, "--sine", "amplitude,frequency")
        if ps is not None:
            values["Omega_0"], values["f_0"] = ps
        spec = NoiseSpec(**values)
        arma_spec = ArmaSpec.parse(arma) if arma is not None else None
        profile = TemperatureProfile.parse(temperature_profile) \
            if temperature_profile is not None else None
        coefs = _coefficients(thermal, "--thermal")
        if decimals is not None and not 0 <= decimals <= 15:
            raise DataError(f"--decimals must be in 0..15, got {decimals}")
        if seed is None:
            seed = int(np.random.SeedSequence().generate_state(1, np.uint64)[0] >> np.uint64(1))
        run = simulate_gyro(spec, fs_hz=fs, duration_s=duration_s, rng=seed, units=units,
                            n_axes=axes, arma=arma_spec, temperature=profile,
                            thermal_coefficients=coefs,
                            flicker=flicker)  # type: ignore[arg-type]
        frame = run.to_frame()
        frame["time"] = np.round(frame["time"].to_numpy(), 9)
        if decimals is not None:
            for col in frame.columns[1:]:
                frame[col] = np.round(frame[col].to_numpy(), decimals)
        m = 2 ** np.arange(int(np.log2(max(run.n // 4, 1))) + 1)
        sidecar = {
            "generator": f"fogts {version} simulate", "output": output.name, "seed": seed,
            "fs_hz": run.fs_hz, "duration_s": run.duration_s, "n": run.n, "units": run.units,
            "columns": list(frame.columns), "axes": list(run.axes), "flicker": flicker,
            "decimals": decimals, "noise": spec.to_dict(),
            "arma": arma_spec.to_dict() if arma_spec is not None else None,
            "temperature_profile": profile.to_dict() if profile is not None else None,
            "thermal_coefficients": coefs,
            "closed_form": {"kind": "oadev", "units": run.units, "tau": (m / run.fs_hz).tolist(),
                            "dev": spec.adev(m / run.fs_hz, units=run.units).tolist(),
                            "note": "IEEE 952 Table C.1 closed form of the noise terms "
                                    "(without ARMA and thermal drift)"},
        }
        write_frame_atomic(output, frame)
        side = output.with_name(output.name + ".json")
        write_text_atomic(side, json_dumps(sidecar) + "\n")
        console.print(f"wrote {output}: {run.n:,} samples x {run.n_axes} axis(es) at "
                      f"{run.fs_hz:g} Hz ({run.duration_s:g} s), rate in {run.units}, seed "
                      f"{seed}; true parameters in {side}", markup=False, soft_wrap=True)
        console.print(spec.summary(), markup=False, soft_wrap=True)


def _duration_or_zero(text: str | None, option: str, default: float) -> float:
    """A duration option that may also be 0 (``"0"``, ``"0s"``)."""
    from fogts.units import parse_duration

    if text is None:
        return default
    if text.strip().rstrip("s").strip() in ("0", "0.0"):
        return 0.0
    return parse_duration(text, option)


def _simulate_startup(output: Path, *, fs: float | None, duration: str | None,
                      seed: int | None, units: str, decimals: int | None, bias: float,
                      arma: str | None, thermal: str | None, cold: dict[str, Any],
                      noise_opts: dict[str, Any]) -> None:
    """``fogts simulate --startup``: a seed-004 cold start (or four-position record) to a file
    that ``fogts compensate``, ``filter`` and ``northfind`` read directly."""
    import math

    import numpy as np

    from fogts import __version__ as version
    from fogts._validate import check_positive
    from fogts.errors import DataError
    from fogts.io import write_frame_atomic, write_text_atomic
    from fogts.northfind import simulate_startup_positions
    from fogts.report import json_dumps
    from fogts.simulate import ArmaSpec
    from fogts.simulate_startup import DEFAULT_STARTUP_COEFFICIENTS, simulate_startup
    from fogts.units import convert_rate, parse_duration, parse_rate_unit

    for name, value in noise_opts.items():
        if value not in (None, 0.0):
            raise DataError(f"{name} does not apply with --startup (the cold start's noise is "
                            "set by --arma and --white-deg-h)")
    if decimals is not None and not 0 <= decimals <= 15:
        raise DataError(f"--decimals must be in 0..15, got {decimals}")
    unit = parse_rate_unit(units, "--units")
    kwargs: dict[str, Any] = {"ambient_degC": 20.0 if cold["--ambient-c"] is None
                              else cold["--ambient-c"], "earth_rate_deg_h": bias}
    for name, key, zero in (("--peak-heating-c-s", "peak_rate_degC_s", False),
                            ("--white-deg-h", "white_sigma_deg_h", True),
                            ("--temperature-resolution-c", "temperature_resolution_degC", True)):
        if cold[name] is not None:
            kwargs[key] = check_positive(name, cold[name], allow_zero=zero)
    if cold["--time-constants"] is not None:
        parts = cold["--time-constants"].split(",")
        taus = tuple(parse_duration(p, "--time-constants") for p in parts)
        if len(taus) != 2 or not taus[0] > taus[1]:
            raise DataError("--time-constants must be two durations 'SLOW,FAST' with SLOW > "
                            f"FAST, such as '400s,40s'; got {cold['--time-constants']!r}")
        kwargs["tau_s"] = taus
    kwargs["start_s"] = _duration_or_zero(cold["--start-after"], "--start-after", 0.0)
    if arma is not None:
        spec = ArmaSpec.parse(arma)
        kwargs.update(ar=spec.ar, ma=spec.ma, arma_sigma_deg_h=math.sqrt(spec.sigma2),
                      earth_rate_deg_h=bias + spec.const)
    kwargs["coefficients"] = _coefficients(thermal, "--thermal") or DEFAULT_STARTUP_COEFFICIENTS
    fs_hz = 1.0 if fs is None else fs
    if seed is None:
        seed = int(np.random.SeedSequence().generate_state(1, np.uint64)[0] >> np.uint64(1))
    if cold["--positions"]:
        if duration is not None:
            raise DataError("--duration does not apply with --positions: the record lasts 4 x "
                            "--position-time + 3 x --turn-time (+ --start-after before it)")
        for name in ("--latitude", "--azimuth"):
            if cold[name] is None:
                raise DataError(f"--positions needs {name} (degrees)")
        rec = simulate_startup_positions(
            latitude_deg=cold["--latitude"], azimuth_deg=cold["--azimuth"],
            position_s=parse_duration(cold["--position-time"] or "60s", "--position-time"),
            turn_s=_duration_or_zero(cold["--turn-time"], "--turn-time", 10.0),
            fs_hz=fs_hz, rng=seed, **kwargs)
        frame, run, truth, summary = (rec.to_frame(), rec.run, rec.to_dict(), rec.summary())
    else:
        for name in ("--latitude", "--azimuth", "--position-time", "--turn-time"):
            if cold[name] is not None:
                raise DataError(f"{name} needs --positions (a four-position north-seeking "
                                "record)")
        sim = simulate_startup(duration_s=parse_duration(duration or "1h", "--duration"),
                               fs_hz=fs_hz, rng=seed, **kwargs)
        run, truth, summary = sim.run, sim.to_dict(), sim.summary()
        frame = run.to_frame().rename(columns={"gyro": "rate"})
    frame["time"] = np.round(frame["time"].to_numpy(), 9)
    frame["rate"] = convert_rate(frame["rate"].to_numpy(), "deg/h", unit)
    if decimals is not None:
        frame["rate"] = np.round(frame["rate"].to_numpy(), decimals)
    # a quantised temperature is written at its resolution (20.01, not 20.010000000000002)
    res = truth["temperature_resolution_degC"]
    digits = [d for d in range(16) if round(res, d) == res][:1] if res > 0 else []
    if digits or decimals is not None:
        nd = min(digits + ([] if decimals is None else [decimals]))
        frame["temperature"] = np.round(frame["temperature"].to_numpy(), nd)
    sidecar = {"generator": f"fogts {version} simulate --startup", "output": output.name,
               "seed": seed, "mode": "startup-positions" if cold["--positions"] else "startup",
               "n": len(frame), "units": unit, "columns": list(frame.columns),
               "decimals": decimals, **truth,
               "note": "drift D = a T dT + b T^2 + c T + d dT^2 + e dT + f in deg/h (T in degC, "
                       "dT in degC/s), coefficients keyed by term; rate = drift + ARMA + white "
                       "noise + earth_rate_deg_h (+ the Earth rate at each position)"}
    write_frame_atomic(output, frame)
    side = output.with_name(output.name + ".json")
    write_text_atomic(side, json_dumps(sidecar) + "\n")
    console.print(f"wrote {output}: {len(frame):,} samples at {run.fs_hz:g} Hz, rate in {unit}, "
                  f"seed {seed}; true parameters in {side}", markup=False, soft_wrap=True)
    console.print(summary, markup=False, soft_wrap=True)


# ---- davar ------------------------------------------------------------------------------
def _save_figure(fig: Any, path: str | Path) -> None:
    """Save a Figure atomically; the format follows the suffix (.png, .svg, .pdf)."""
    from fogts.errors import DataError
    from fogts.io import atomic_path

    target = Path(path)
    fmt = target.suffix.lstrip(".").lower()
    if fmt not in ("png", "svg", "pdf"):
        raise DataError(f"--plot must end in .png, .svg or .pdf; got {target.name!r}")
    with atomic_path(target) as tmp:
        fig.savefig(tmp, format=fmt, dpi=150)


@app.command("davar")
def davar_cmd(
    file: FileArg,
    window: Annotated[str, typer.Option("--window", help="Window length: 200s, 5min, ... (the seed paper uses 201 s).")] = "200s",
    step: Annotated[str, typer.Option("--step", help="Step between windows: 20s, 1min, ...")] = "20s",
    kind: Annotated[str, typer.Option("--kind", help="Estimator per window: oadev, mdev, ohdev (fast), adev, hdev, totdev.")] = "oadev",
    taus: Annotated[str, typer.Option("--taus", help="Tau grid within the window: octave, decade, dense, all, or taus in s separated by commas.")] = "octave",
    axis: Annotated[str | None, typer.Option("--axis", help="Analyse one axis (name or index) (default: every axis).")] = None,
    confidence: Annotated[float, typer.Option("--confidence", help="Confidence level of each window's interval.")] = 0.683,
    rate_column: RateColOpt = None,
    time_column: TimeColOpt = None,
    temperature_column: TempColOpt = None,
    fs: FsOpt = None,
    units: UnitsOpt = None,
    json_out: JsonOpt = None,
    plot: Annotated[Path | None, typer.Option("--plot", help="Heat map of log deviation over (time, tau): .png, .svg or .pdf.")] = None,
    nan: NanOpt = "error",
    gaps: GapsOpt = "warn",
) -> None:
    """Dynamic Allan deviation (DAVAR, Galleani & Tavella 2009): the deviation in a
    window sliding along the record, and a non-stationarity score."""
    from fogts.allan.dynamic import dynamic_allan
    from fogts.units import parse_duration

    with _guard(outputs={"--json": json_out, "--plot": plot}, inputs={"FILE": [file]}):
        window_s = parse_duration(window, "--window")
        step_s = parse_duration(step, "--step")
        tau_spec = _tau_option(taus)
        pick: int | str | None = int(axis) if axis is not None and axis.isdigit() else axis
        run, quality = _read(file, rate_column, time_column, temperature_column, fs, units,
                             nan=nan, gaps=gaps)
        result = dynamic_allan(run, window_s=window_s, step_s=step_s, kind=kind,  # type: ignore[arg-type]
                               taus=tau_spec, confidence=confidence, axis=pick)
        payload = {"input": str(file), **result.to_dict(), "data_quality": quality.to_dict()}
        _emit_json(payload, json_out)
        if plot is not None:
            from fogts.plots import plot_dynamic_allan

            _save_figure(plot_dynamic_allan(result), plot)
        target = err_console if json_out == "-" else console
        target.print(result.summary(), markup=False, soft_wrap=True)


# ---- filter (issue 6: Kalman; issue 8 adds --method iir|moving-average) -----------------
FILTER_METHODS = ("kalman", "iir", "moving-average")


def _say(lines: list[str], json_out: str | None) -> None:
    """Print text lines unwrapped (to stderr when the JSON goes to stdout)."""
    target = err_console if json_out == "-" else console
    target.print("\n".join(lines), markup=False, soft_wrap=True)


@app.command("filter")
def filter_cmd(
    file: FileArg,
    output: Annotated[Path, typer.Option("-o", "--output", help="Output table (.csv or .parquet): time, observed, filtered (kalman adds smoothed, predicted).")],
    method: Annotated[str, typer.Option("--method", help="kalman (ARMA drift model in Harvey state-space form), iir (zero-phase low-pass) or moving-average.")] = "kalman",
    model: Annotated[str, typer.Option("--model", help="Drift model for --method kalman: auto (run the ARMA selection), AR(1), AR(2), AR(3), ARMA(1,1), ARMA(2,1).")] = "auto",
    measurement_noise: Annotated[str, typer.Option("--measurement-noise", help="Kalman measurement-noise variance in (rate unit)^2, or 'estimate' (ML with the ARMA parameters fixed).")] = "estimate",
    cutoff: Annotated[float | None, typer.Option("--cutoff", help="--method iir: cutoff in Hz (zero-phase -3 dB point for butter), below fs/2.")] = None,
    order: Annotated[int, typer.Option("--order", help="--method iir: filter order of one pass.")] = 4,
    design: Annotated[str, typer.Option("--design", help="--method iir: butter, cheby1 or ellip.")] = "butter",
    window: Annotated[float | None, typer.Option("--window", help="--method moving-average: window in seconds.")] = None,
    compare_allan: Annotated[bool, typer.Option("--compare-allan", help="Allan deviation and noise terms before and after filtering, side by side (with --plot: the overlay figure).")] = False,
    axis: Annotated[str, typer.Option("--axis", help="Axis to filter (name or index).")] = "0",
    rate_column: RateColOpt = None,
    time_column: TimeColOpt = None,
    temperature_column: TempColOpt = None,
    fs: FsOpt = None,
    units: UnitsOpt = None,
    json_out: JsonOpt = None,
    plot: Annotated[Path | None, typer.Option("--plot", help="Figure (.png, .svg, .pdf): observed/filtered/smoothed for kalman; the before/after Allan overlay with --compare-allan.")] = None,
    nan: NanOpt = "error",
    gaps: GapsOpt = "warn",
) -> None:
    """Filter a gyro record: Kalman filter with an ARMA drift model (seed 004), or a
    zero-phase IIR / moving-average low-pass with a before/after Allan comparison (seed 001).
    """
    from fogts._validate import check_choice

    with _guard(outputs={"--output": output, "--json": json_out, "--plot": plot},
                inputs={"FILE": [file]}):
        check_choice("--method", method, FILTER_METHODS)
        if method == "kalman":
            noise = _parse_measurement_noise(measurement_noise)
        run, _ = _read(file, rate_column, time_column, temperature_column, fs, units, nan=nan,
                       gaps=gaps)
        pick: int | str = int(axis) if axis.lstrip("-").isdigit() else axis
        x = run.axis(pick)
        if method == "kalman":
            _kalman_filter(run, x, file, output, model, noise, json_out, plot, method)
        else:
            _lowpass_filter(run, x, file, output, method, cutoff, order, design, window,
                            compare_allan, json_out, plot)


def _parse_measurement_noise(text: str) -> Any:
    from fogts.errors import DataError

    if text == "estimate":
        return text
    try:
        return float(text)
    except ValueError:
        raise DataError("--measurement-noise must be 'estimate' or a variance in "
                        f"(rate unit)^2; got {text!r}") from None


def _kalman_filter(run: Any, x: Any, file: Path, output: Path, model: str, noise: Any,
                   json_out: str | None, plot: Path | None, method: str) -> None:
    import numpy as np
    import pandas as pd

    from fogts.io import write_frame_atomic
    from fogts.kalman import arma_kalman, resolve_arma_model

    fit = resolve_arma_model(x, model)
    result = arma_kalman(x, fit, measurement_noise=noise)
    frame = pd.DataFrame({"time": run.time, "observed": x,
                          "filtered": np.asarray(result.filtered),
                          "smoothed": np.asarray(result.smoothed),
                          "predicted": np.asarray(result.predicted)})
    write_frame_atomic(output, frame)
    fit_dict = fit.to_dict() if hasattr(fit, "to_dict") else {}
    _emit_json({"input": str(file), "method": method, "units": run.units,
                "model": fit_dict, "kalman": result.to_dict(), "output": str(output)},
               json_out)
    if plot is not None:
        from fogts.plots import plot_kalman

        _save_figure(plot_kalman(result, time_s=run.time, units=run.units), plot)
    equation = fit.equation() if hasattr(fit, "equation") else result.model
    _say([f"drift model ({'selected by AIC' if model == 'auto' else 'given'}): {equation}",
          result.summary(), f"wrote {output} ({run.n} rows)"], json_out)


def _lowpass_filter(run: Any, x: Any, file: Path, output: Path, method: str,
                    cutoff: float | None, order: int, design: str, window: float | None,
                    compare: bool, json_out: str | None, plot: Path | None) -> None:
    import pandas as pd

    from fogts.errors import DataError
    from fogts.filters import lowpass, moving_average
    from fogts.io import write_frame_atomic

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
    _emit_json(payload, json_out)
    if plot is not None and comparison is not None:
        from fogts.plots import plot_allan_comparison

        _save_figure(plot_allan_comparison(comparison), plot)
    lines = [result.summary()]
    if comparison is not None:
        lines += ["", "noise terms before and after filtering:", comparison.summary()]
    lines.append(f"wrote {output} ({run.n} rows)")
    _say(lines, json_out)


# ---- compensate (issue 6: seed-004 start-up drift compensation) ---------------------------
def _load_thermal_model(path: Path) -> Any:
    from fogts.io import read_json
    from fogts.thermal import ThermalModel

    data = read_json(path, "thermal model")
    if isinstance(data, dict) and "thermal" in data and "terms" not in data:
        data = data["thermal"].get("model", data["thermal"])  # a `compensate --json` file
    return ThermalModel.from_dict(data)


@app.command("compensate")
def compensate_cmd(
    file: FileArg,
    output: Annotated[Path | None, typer.Option("-o", "--output", help="Output table (.csv or .parquet): time, raw, trend, used, compensated, temperature.")] = None,
    emd: Annotated[bool, typer.Option("--emd/--no-emd", help="Separate the trend by EMD and Kalman-filter the rest before fitting (seed 004).")] = True,
    save_model: Annotated[Path | None, typer.Option("--save-model", help="Save the fitted thermal model as JSON.")] = None,
    model: Annotated[Path | None, typer.Option("--model", help="Apply a saved thermal model (JSON) instead of fitting one.")] = None,
    calibration: Annotated[list[Path] | None, typer.Option("--calibration", help="Further calibration run(s) fitted together with FILE (repeat the option), e.g. cold starts at other ambient temperatures.")] = None,
    arma_model: Annotated[str, typer.Option("--arma-model", help="ARMA model of the EMD rest: auto, AR(1), AR(2), AR(3), ARMA(1,1), ARMA(2,1).")] = "auto",
    average: Annotated[float, typer.Option("--average", help="Averaging time of the bias stability in seconds (GJB/IEEE: 10 s).")] = 10.0,
    dt_smoothing: Annotated[float, typer.Option("--dt-smoothing", help="Window in seconds of the temperature-rate (dT/dt) estimate.")] = 60.0,
    axis: Annotated[str, typer.Option("--axis", help="Axis to compensate (name or index).")] = "0",
    rate_column: RateColOpt = None,
    time_column: TimeColOpt = None,
    temperature_column: TempColOpt = None,
    fs: FsOpt = None,
    units: UnitsOpt = None,
    json_out: JsonOpt = None,
    plot: Annotated[Path | None, typer.Option("--plot", help="Raw rate, trend, compensated rate and temperature: .png, .svg or .pdf.")] = None,
    nan: NanOpt = "error",
) -> None:
    """Fit the seed-004 temperature-drift model D = aT·dT + bT² + cT + d·dT² + e·dT + f and
    compensate; prints the model and the bias stability before and after."""
    from fogts.thermal import startup_compensation

    with _guard(outputs={"--output": output, "--save-model": save_model, "--json": json_out,
                         "--plot": plot},
                inputs={"FILE": [file], "--model": [model] if model else [],
                        "--calibration": calibration or []}):
        run, quality = _read(file, rate_column, time_column, temperature_column, fs, units,
                             nan=nan)
        pick: int | str = int(axis) if axis.lstrip("-").isdigit() else axis
        given = _load_thermal_model(model) if model is not None else None
        extra = [_read(c, rate_column, time_column, temperature_column, fs, units, nan=nan)[0]
                 for c in (calibration or [])]
        if extra and given is not None:
            from fogts.errors import DataError

            raise DataError("--calibration fits a model; it cannot be combined with --model")
        result = startup_compensation(run, axis=pick, emd=emd, model=given,
                                      arma_model=arma_model, dT_smoothing_s=dt_smoothing,
                                      average_s=average, calibration=extra)
        if output is not None:
            from fogts.io import write_frame_atomic

            write_frame_atomic(output, result.to_frame())
        if save_model is not None:
            from fogts.io import write_text_atomic
            from fogts.report import json_dumps

            write_text_atomic(save_model, json_dumps(result.model.to_dict()) + "\n")
        payload = {"input": str(file), **result.to_dict(), "data_quality": quality.to_dict()}
        if given is not None:
            payload["thermal"]["source"] = str(model)
        _emit_json(payload, json_out)
        if plot is not None:
            from fogts.plots import plot_compensation

            _save_figure(plot_compensation(result), plot)
        lines = [result.summary()]
        if output is not None:
            lines.append(f"wrote {output} ({run.n} rows)")
        if save_model is not None:
            lines.append(f"saved the thermal model to {save_model}")
        _say(lines, json_out)


# ---- northfind (issue 6: four-position north seeking) -------------------------------------
def _position_rates(files: list[Path], *, position_column: str, rate_column: str | None,
                    time_column: str | None, temperature_column: str | None, fs: float | None,
                    units: str | None, thermal: Any) -> tuple[dict[int, Any], dict[int, float] | None, float, str]:
    import numpy as np

    from fogts.errors import DataError
    from fogts.northfind import POSITIONS_DEG, positions_from_frame
    from fogts.thermal import compensate

    if len(files) == 1:
        run, _ = _read(files[0], f"{rate_column or 'rate'},{position_column}", time_column,
                       temperature_column, fs, units, gaps="ignore", glitches=False)
        if thermal is not None:
            run = compensate(run, thermal, axis=0)
        import pandas as pd

        frame = pd.DataFrame({"position_deg": run.rate[:, 1], "rate": run.rate[:, 0],
                              "time": run.time})
        rates = positions_from_frame(frame)
        keys = np.round(frame["position_deg"].to_numpy()) % 360
        times = {p: float(frame["time"].to_numpy()[keys == p].mean()) for p in POSITIONS_DEG}
        return rates, times, run.fs_hz, run.units
    if len(files) != 4:
        raise DataError(f"give one file with a {position_column!r} column, or four files (0, 90, "
                        f"180, 270 degrees in that order); got {len(files)} files")
    rates = {}
    fs_hz, unit = 0.0, "deg/h"
    for p, path in zip(POSITIONS_DEG, files, strict=True):
        run, _ = _read(path, rate_column, time_column, temperature_column, fs, units,
                       gaps="ignore", glitches=False)
        if thermal is not None:
            run = compensate(run, thermal, axis=0)
        rates[p] = run.axis(0)
        fs_hz, unit = run.fs_hz, run.units
    return rates, None, fs_hz, unit


@app.command("northfind")
def northfind_cmd(
    files: Annotated[list[Path] | None, typer.Argument(help="One CSV with position_deg and rate columns, or four files for 0/90/180/270 degrees (omit with --simulate).")] = None,
    latitude: Annotated[float, typer.Option("--latitude", help="Latitude in degrees (|L| <= 89).")] = ...,  # type: ignore[assignment]
    thermal_model: Annotated[Path | None, typer.Option("--thermal-model", help="Compensate the rates with a saved thermal model (JSON from 'fogts compensate --save-model').")] = None,
    position_column: Annotated[str, typer.Option("--position-column", help="Column holding the position in degrees (0/90/180/270).")] = "position_deg",
    transition: Annotated[float, typer.Option("--transition", help="Seconds spent turning between positions (four-file input).")] = 0.0,
    bias_sigma: Annotated[float, typer.Option("--bias-sigma", help="1-sigma position-to-position bias variation in deg/h for the error budget.")] = 0.0,
    simulate: Annotated[int | None, typer.Option("--simulate", help="Simulation mode: repeat cold-start north seeking N times, with and without thermal compensation.")] = None,
    seed: Annotated[int, typer.Option("--seed", help="Random seed of the simulation mode.")] = 4,
    rate_column: RateColOpt = None,
    time_column: TimeColOpt = None,
    temperature_column: TempColOpt = None,
    fs: FsOpt = None,
    units: UnitsOpt = None,
    json_out: JsonOpt = None,
    plot: Annotated[Path | None, typer.Option("--plot", help="Simulation mode: azimuth error per trial (.png, .svg, .pdf).")] = None,
) -> None:
    """Four-position north seeking (seed 004): azimuth of the input axis at position 0,
    clockwise from true north, with its error budget; or, with --simulate N, the cold-start
    error with and without thermal compensation."""
    from fogts.errors import DataError
    from fogts.northfind import four_position, simulate_north_seeking

    with _guard(_NORTHFIND_OPTIONS, outputs={"--json": json_out, "--plot": plot},
                inputs={"FILES": files or [],
                        "--thermal-model": [thermal_model] if thermal_model else []}):
        thermal = _load_thermal_model(thermal_model) if thermal_model is not None else None
        if simulate is not None:
            if files:
                raise DataError("--simulate takes no input files")
            notes = []
            if thermal is None:
                from fogts.northfind import simulated_calibration

                thermal = simulated_calibration((15.0, 20.0, 25.0), rng=seed + 1_000_003)
                notes.append("thermal model fitted on three separate simulated calibration cold "
                             "starts (ambient 15, 20, 25 degC)")
            study = simulate_north_seeking(simulate, latitude_deg=latitude, model=thermal,
                                           rng=seed)
            payload = {"mode": "simulate", "seed": seed, **study.to_dict(), "notes": notes}
            _emit_json(payload, json_out)
            if plot is not None:
                from fogts.plots import plot_north_seeking

                _save_figure(plot_north_seeking(study), plot)
            _say([study.summary(), *notes], json_out)
            return
        if not files:
            raise DataError("give one positions file or four files, or --simulate N")
        rates, times, fs_hz, unit = _position_rates(
            files, position_column=position_column, rate_column=rate_column,
            time_column=time_column, temperature_column=temperature_column, fs=fs, units=units,
            thermal=thermal)
        result = four_position(rates, latitude_deg=latitude, fs_hz=fs_hz, units=unit,
                               position_time_s=times, transition_s=transition,
                               bias_sigma_deg_h=bias_sigma)
        payload = {"input": [str(f) for f in files],
                   "thermal_model": None if thermal_model is None else str(thermal_model),
                   **result.to_dict()}
        _emit_json(payload, json_out)
        if plot is not None:
            raise DataError("--plot is available in --simulate mode only")
        _say([result.summary()], json_out)


# ---- select -----------------------------------------------------------------------------
def _fmt(v: Any, spec: str = ".4g") -> str:
    import math

    return "–" if v is None or (isinstance(v, float) and not math.isfinite(v)) else \
        format(v, spec)


def _select_notes(c: Any) -> str:
    """Short notes for one candidate row: why not white, redundancy, convergence."""
    if not c.ok:
        return f"fit failed: {c.reason}"
    notes = []
    if c.flagged("near_cancellation"):
        notes.append("AR/MA roots nearly cancel")
    insig = [f.details["param"] for f in c.flagged("insignificant")]
    if insig:
        notes.append(f"{', '.join(insig)} not significant")
    if not c.converged:
        notes.append("did not converge")
    return "; ".join(notes)


def _select_table(sel: Any) -> Table:
    from rich.text import Text

    crit = sel.criterion.upper()
    best = sel.selected.criterion_value if sel.selected is not None else float("nan")
    band = 1.96 / sel.n ** 0.5
    title = f"ARMA candidates ranked by {crit}, white residuals first"
    if sel.selected is not None:
        title += f" ({crit} of #1: {best:.2f})"
    table = Table(title=title, title_justify="left", box=None, pad_edge=False, padding=(0, 1),
                  header_style="bold underline")
    for name in ("#", "model", f"Δ{crit}", "σ_a²", "ρ_a,2", "ρ_ax,3",
                 *[f"LB p({lag})" for lag in sel.lags], "white"):
        table.add_column(name, justify="left" if name == "model" else "right", no_wrap=True)
    for c in sel.candidates:
        if not c.ok:
            table.add_row("–", c.model, *["–"] * (4 + len(sel.lags)), Text("failed", "red"))
            continue
        d = c.diagnostics

        def chk(value: float, ok: bool | None) -> Text:
            return Text(_fmt(value, "+.4f"), "" if ok in (True, None) else "red")

        lbs = [Text(_fmt(x.pvalue, ".3g"), "" if x.passed in (True, None) else "red")
               for x in d.ljung_box]
        table.add_row(str(c.rank), Text(c.model, "bold" if c is sel.selected else ""),
                      _fmt(c.criterion_value - best, "+.2f"), _fmt(c.sigma2, ".3g"),
                      chk(d.rho_a2.value, d.rho_a2.passed), chk(d.rho_ax3.value, d.rho_ax3.passed),
                      *lbs, Text("yes", "green") if c.white else Text("no", "red"))
    table.caption = (f"white: |ρ_a,2|, |ρ_ax,3| ≤ 1.96/√n = {band:.3g} (seed eqs. 11, 12) and "
                     f"Ljung–Box p ≥ 0.05 at each lag (model_df = p+q); red: check fails")
    table.caption_justify = "left"
    return table


def _select_params(c: Any, units: str | None) -> list[str]:
    lines = []
    for k, v in c.params.items():
        se = c.bse.get(k)
        t = v / se if se else float("nan")
        unit = f" ({units})²" if k == "sigma2" and units else ""
        sig = "" if k == "sigma2" else f"  t = {t:+.1f}"
        lines.append(f"  {k:<7} = {v: .6g} ± {_fmt(se, '.2g')}{unit}{sig}")
    return lines


@app.command("select")
def select_cmd(
    file: FileArg,
    rate_column: RateColOpt = None,
    time_column: TimeColOpt = None,
    temperature_column: TempColOpt = None,
    fs: FsOpt = None,
    units: UnitsOpt = None,
    axis: Annotated[str | None, typer.Option("--axis", help="Axis to model, by name or index (default: the first).")] = None,
    outliers: Annotated[float | None, typer.Option("--outliers", help="Replace samples beyond this many robust sigmas first.")] = None,
    detrend: Annotated[int | None, typer.Option("--detrend", help="Remove a polynomial trend of this order; 0 removes the mean only (default: remove the mean).")] = None,
    decimate: Annotated[int | None, typer.Option("--decimate", help="Block-average K samples first (e.g. 100 Hz -> 1 Hz with K=100).")] = None,
    candidates: Annotated[str | None, typer.Option("--candidates", help="Models to compare, e.g. 'AR(1),AR(2),ARMA(1,1)' (default: AR(1),AR(2),AR(3),ARMA(1,1),ARMA(2,1)).")] = None,
    criterion: Annotated[str, typer.Option("--criterion", help="Ranking criterion: aic, bic, hqic, aicc.")] = "aic",
    json_out: JsonOpt = None,
    plot: Annotated[Path | None, typer.Option("--plot", help="Diagnostics figure (data ACF/PACF, residual ACF, Q-Q, prediction): .png, .svg or .pdf.")] = None,
    predict: Annotated[Path | None, typer.Option("--predict", help="Write the one-step prediction as CSV (time, observed, predicted, residual); .csv, .csv.gz, .tsv or .parquet.")] = None,
    nan: NanOpt = "error",
    gaps: GapsOpt = "warn",
) -> None:
    """Select the ARMA model of the drift (seed 000): fit AR(1), AR(2), AR(3), ARMA(1,1) and ARMA(2,1), check that their residuals are white, rank them and predict one step ahead.

    Exit code 0 if the selected model leaves white residuals, 1 if no candidate does (the best one is still reported), 2 on bad input.
    """
    from rich.text import Text

    from fogts.arma.select import parse_candidates, select_arma
    from fogts.errors import DataError
    from fogts.preprocess import prepare

    with _guard(outputs={"--json": json_out, "--plot": plot, "--predict": predict},
                inputs={"FILE": [file]}):
        if criterion not in ("aic", "bic", "hqic", "aicc"):
            raise DataError(f"--criterion must be one of aic, bic, hqic, aicc; got {criterion!r}")
        orders = parse_candidates(candidates)
        _check_output_names(plot=plot, predict=predict)
        run, quality = _read(file, rate_column, time_column, temperature_column, fs, units,
                             nan=nan, gaps=gaps)
        pick: int | str = 0 if axis is None else (int(axis) if axis.isdigit() else axis)
        if isinstance(pick, str) and pick not in run.axes:
            raise DataError(f"--axis {pick!r} not found; axes are: {', '.join(run.axes)}")
        if isinstance(pick, int) and not 0 <= pick < run.n_axes:
            raise DataError(f"--axis must be 0..{run.n_axes - 1}, got {pick}")
        prepared = prepare(run, axis=pick, outliers=outliers, detrend=detrend,
                           decimate=decimate)
        sel = select_arma(prepared, candidates=orders, criterion=criterion)  # type: ignore[arg-type]
        payload = sel.to_dict()
        payload["input"] = {**payload["input"], "file": str(file),
                            "units_source": run.units_source}
        payload["data_quality"] = quality.to_dict()
        _emit_json(payload, json_out)
        if plot is not None:
            from fogts.plots import plot_selection

            _save_figure(plot_selection(sel), plot)
        pred = None
        if predict is not None and sel.selected is not None:
            from fogts.io import write_frame_atomic

            pred = sel.selected.predict()
            frame = pred.to_frame().reset_index(drop=True)
            if "time" not in frame:
                frame.insert(0, "time", prepared.time)
            write_frame_atomic(predict, frame[["time", "observed", "predicted", "residual"]])

        out = err_console if json_out == "-" else console

        def say(text: str = "", style: str = "") -> None:
            out.print(Text(text, style), soft_wrap=True)

        dur = run.duration_s
        dur_text = f"{dur / 3600:.3g} h" if dur >= 3600 else (
            f"{dur / 60:.3g} min" if dur >= 60 else f"{dur:.3g} s")
        say(f"read      {file}: {run.n:,} samples of {prepared.axis!r} at {run.fs_hz:g} Hz "
            f"({dur_text}), rate in {run.units}")
        if run.n_axes > 1:
            say(f"{'':<10}axes in the file: {', '.join(run.axes)} (choose with --axis)")
        for i, step in enumerate(prepared.steps):
            say(f"{'prepared' if i == 0 else '':<10}{step}")
        say(f"{'modelled':<10}{sel.n:,} samples at {prepared.fs_hz:g} Hz")
        corr = sel.correlogram
        say(f"{'ACF/PACF':<10}ACF {corr.acf_pattern.describe()}, PACF "
            f"{corr.pacf_pattern.describe()} -> {corr.suggestion}")
        out.print(_select_table(sel))
        for c in sel.candidates:
            note = _select_notes(c)
            if note and c is not sel.selected:
                say(f"{'note':<10}{c.model}: {note}")
        best = sel.selected
        if best is not None:
            how = (f"lowest {sel.criterion.upper()} among the white candidates" if best.white
                   else f"lowest {sel.criterion.upper()}; residuals NOT white")
            say(f"selected  {best.model} ({how}), drift in {prepared.units}:", "bold")
            say(f"  {best.equation()}", "bold")
            for line in _select_params(best, prepared.units):
                say(line)
            for f in best.flags:
                say(f"  note: {f.message}")
            bp = best.predict()
            say(f"  one-step prediction: std {bp.variance_observed ** 0.5:.4g} -> "
                f"{bp.variance_residual ** 0.5:.4g} {prepared.units} "
                f"({100 * bp.variance_removed:.1f} % of the variance removed)")
        say(f"verdict   {sel.verdict}", "green" if sel.exit_code == 0 else "red")
        if json_out not in (None, "-"):
            say(f"wrote     {json_out}")
        if plot is not None:
            say(f"wrote     {plot}")
        if pred is not None:
            say(f"wrote     {predict}")
        elif predict is not None:
            say(f"not written {predict}: no candidate could be fitted")
    raise typer.Exit(sel.exit_code)


_GLOBAL_FLAGS = ("--debug", "--version")


def _hoist_global_flags(argv: list[str]) -> list[str]:
    """Move ``--debug`` and ``--version`` given after the command name to the front, so that
    ``fogts info X --debug`` works like ``fogts --debug info X``.

    A token is moved only where it is a flag, not the value of an option that takes one
    (``--title --debug`` keeps its title); tokens after ``--`` are left alone."""
    group = typer.main.get_command(app)
    names = getattr(group, "commands", {})
    command = next((names[t] for t in argv if t in names), None)
    if command is None:
        return argv
    takes_value = {opt for p in command.params if not getattr(p, "is_flag", True)
                   for opt in p.opts}
    front: list[str] = []
    rest: list[str] = []
    start = argv.index(command.name) if command.name in argv else 0
    skip_next = False
    for i, token in enumerate(argv):
        if i <= start or skip_next or "--" in argv[:i]:
            rest.append(token)
            skip_next = False
            continue
        if token in _GLOBAL_FLAGS:
            front.append(token)
            continue
        skip_next = token in takes_value
        rest.append(token)
    return front + rest


def main(argv: list[str] | None = None) -> None:
    """Console-script entry point: usage errors become one line ``error: ...``, exit 2."""
    argv = _hoist_global_flags(list(sys.argv[1:] if argv is None else argv))
    try:
        rv = app(args=argv, prog_name="fogts", standalone_mode=False)
    except _click_exc.NoArgsIsHelpError as exc:
        console.print(exc.format_message(), markup=False, soft_wrap=True)
        raise SystemExit(ExitCode.OK) from None
    except _click_exc.ClickException as exc:
        ctx = getattr(exc, "ctx", None)
        name = ctx.command.name if ctx is not None and ctx.command is not None else None
        hint = f" (see 'fogts {name} --help')" if name and name != "fogts" else \
            " (see 'fogts --help')"
        err_console.print(f"error: {exc.format_message()}{hint}", markup=False, soft_wrap=True)
        raise SystemExit(ExitCode.ERROR) from None
    except typer.Exit as exc:
        raise SystemExit(exc.exit_code) from None
    except typer.Abort:
        err_console.print("error: aborted", markup=False)
        raise SystemExit(ExitCode.ERROR) from None
    raise SystemExit(rv if isinstance(rv, int) else 0)
