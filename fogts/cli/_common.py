"""The ``fogts`` command line: the typer app, the options every command shares, the error
guard and the input/output helpers.  Each command lives in its own module of this package
(``fogts.cli.allan``, ``fogts.cli.select``, ...); this is the only package that prints.

* input options shared by every command (``--rate-column``, ``--time-column``,
  ``--temperature-column``, ``--fs``, ``--units``, ``--nan``) come from the ``*Opt``
  aliases below and are turned into a :class:`fogts.io.run.Run` by :func:`_read`;
* the body runs inside :func:`_guard`, which checks the output names against the inputs
  and maps any exception to one line ``error: ...`` on stderr and exit code 2 (no
  traceback unless ``--debug``);
* JSON goes through :func:`_emit_json` (``-`` means stdout; files are written atomically).

Exit codes (DESIGN.md): 0 success, 1 negative verdict, 2 bad usage/input/internal error.
"""

from __future__ import annotations

import dataclasses
import functools
import gc
import inspect
import re
import sys
import warnings
from collections.abc import Callable, Iterable, Iterator, Mapping, Sequence
from contextlib import contextmanager
from pathlib import Path
from typing import TYPE_CHECKING, Annotated, Any, TypeVar

import typer
from rich.console import Console
from typer.core import TyperGroup

from fogts import choices
from fogts._version import __version__
from fogts.cli._arguments import cli_payload, option_keywords, option_names, stray_arguments
from fogts.cli._outputs import NO_OUTPUTS as NO_OUTPUTS
from fogts.cli._outputs import Outputs as Outputs
from fogts.cli._outputs import writes_outputs as writes_outputs
from fogts.cli._rich_table import rich_table as rich_table  # the commands' common.rich_table
from fogts.pipeline import ReadSettings

try:  # typer >= 0.16 vendors click as typer._click
    from typer._click import exceptions as _click_exc
except ImportError:  # pragma: no cover - older typer uses click itself
    from click import exceptions as _click_exc  # type: ignore[no-redef]


class _OneLineErrors(TyperGroup):
    """The ``fogts`` group: a usage error (a bad choice, a missing argument) is one line
    ``error: ...`` on stderr with exit code 2, as every other error, whether the app runs
    as the console script or under a test runner."""

    def main(self, args: Sequence[str] | None = None, prog_name: str | None = None,
             complete_var: str | None = None, standalone_mode: bool = True,
             windows_expand_args: bool = True, **extra: Any) -> Any:
        try:
            rv = super().main(args, prog_name, complete_var, standalone_mode=False,
                              windows_expand_args=windows_expand_args, **extra)
        except _click_exc.NoArgsIsHelpError as exc:
            console.print(exc.format_message(), markup=False, soft_wrap=True)
            rv = ExitCode.OK
        except _click_exc.ClickException as exc:
            ctx = getattr(exc, "ctx", None)
            path = ctx.command_path if ctx is not None else ""
            hint = f" (see '{path} --help')" if path.startswith("fogts ") else \
                " (see 'fogts --help')"
            # typer's choice check prefixes its reason with "Value error, ": drop it
            message = exc.format_message().replace(": Value error, ", ": ")
            if isinstance(exc, _click_exc.MissingParameter) and ctx is not None:
                message = stray_arguments(ctx, sys.argv[1:] if args is None else args, message)
            err_console.print(f"error: {message}{hint}", markup=False, soft_wrap=True)
            rv = ExitCode.ERROR
        except typer.Abort:
            err_console.print("error: aborted", markup=False)
            rv = ExitCode.ERROR
        if not standalone_mode:
            return rv
        sys.exit(rv if isinstance(rv, int) else ExitCode.OK)


R = TypeVar("R")

app = typer.Typer(
    name="fogts",
    cls=_OneLineErrors,
    help="Fibre-optic-gyro drift analysis: Allan variance, IEEE-952 noise terms, ARMA models.",
    no_args_is_help=True,
    add_completion=False,
    pretty_exceptions_enable=False,
    # paragraphs reflow to the terminal and [..] stays literal (rich markup would eat a
    # JSON shape such as {"axes": [...]} and break lines where the docstring does)
    rich_markup_mode="markdown",
)
# Outside a terminal (pipes, CI logs, CliRunner) rich would wrap tables at 80 columns.
_WIDTH = None if sys.stdout.isatty() else 120
console = Console(highlight=False, width=_WIDTH)
err_console = Console(stderr=True, highlight=False, width=_WIDTH)

_STATE: dict[str, bool] = {"debug": False}

# ---------------------------------------------------------------- shared input options
FileArg = Annotated[Path, typer.Argument(help="Input recording (CSV/TSV/text, .gz, Parquet, .npy/.npz).")]
RateColOpt = Annotated[str | None, typer.Option("--rate-column", rich_help_panel="Input", help="Rate column(s), comma-separated; default: auto-detect.")]
TimeColOpt = Annotated[str | None, typer.Option("--time-column", rich_help_panel="Input", help="Time column; default: auto-detect.")]
TempColOpt = Annotated[str | None, typer.Option("--temperature-column", rich_help_panel="Input", help="Temperature column; default: auto-detect.")]
FsOpt = Annotated[float | None, typer.Option("--fs", rich_help_panel="Input", help="Sample rate in Hz (overrides the time column).")]
UnitsOpt = Annotated[str | None, typer.Option("--units", rich_help_panel="Input", help="Rate unit of the input: deg/h, deg/s, rad/s, arcsec/s (default: from a unit in the column name such as gyro_x_deg_s, else deg/h).")]
TopicOpt = Annotated[str | None, typer.Option("--topic", rich_help_panel="Input", help="ROS bags: the sensor_msgs/Imu topic (needed when the bag has several).")]
InputOpt = Annotated[choices.InputKind | None, typer.Option("--input", rich_help_panel="Input", help="What the rate columns hold: rate, increment (angle per sample, e.g. dtheta) or angle (integrated angle); angle and increments feed the Allan estimators as phase, without differencing. Default: from the names (dtheta, delta_angle, angle_deg, theta), else rate.")]
AccelUnitsOpt = Annotated[str | None, typer.Option("--accel-units", rich_help_panel="Input", help="Unit of the accelerometer columns (acc*, ax.., linear_acceleration_*): m/s^2, g, mg, ug (default: from the names such as acc_x_mps2, else from the gravity magnitude, else m/s^2).")]
ExportOpt = Annotated[tuple[str, Path] | None, typer.Option("--export", metavar="FORMAT PATH", help="Write the filter-ready noise parameters (N and K in SI; a term not measured as its 95 % upper limit, marked): kalibr (imu.yaml), imu_utils (OpenCV YAML) or json.")]
SpecOpt = Annotated[Path | None, typer.Option("--spec", help="Datasheet limits (YAML: 'units: deg' or 'si', then any of N, B, K, e.g. 'N: 0.15'): PASS when a term's one-sided 95 % upper bound is within the limit, FAIL when its 95 % lower bound is above it, else INCONCLUSIVE (a term the data only bound never FAILs).")]
OutputUnitsOpt = Annotated[choices.OutputUnits, typer.Option("--output-units", help="Units of the printed tables: deg (IEEE 952: deg/sqrt(h), deg/h, deg/h^1.5; the deviations in the input unit) or si (rad/s/sqrt(Hz), rad/s, rad/s^2/sqrt(Hz); deviations in rad/s). Accelerometer axes: m/s/sqrt(h), ug, m/s/h^1.5, or in si m/s^2/sqrt(Hz), m/s^2, m/s^3/sqrt(Hz). The JSON has both (noise, noise_si).")]


# ---------------------------------------------------------------- choices
# The library's own Literal types (fogts.choices): typer validates them and lists their
# values in --help, and the library's checks quote the same tuples.

NanOpt = Annotated[choices.NanPolicy, typer.Option("--nan", rich_help_panel="Input", help="Empty, NaN or inf cells: error (name the first one), drop (the rows become gaps) or interpolate (linearly in time).")]
GapsOpt = Annotated[choices.GapPolicy, typer.Option("--gaps", rich_help_panel="Input", help="Gaps in the time base: warn (analyse as if regular, and say so), error, split (analyse the longest regular segment), nan (the whole record on its regular grid, missing samples as NaN, gap-robust overlapping ADEV after Sesia & Tavella 2008; --kind oadev only) or ignore (no warning; still in the JSON).")]
#: The shared input options: (parameter, annotation, default), in --help order.
_INPUT_OPTIONS: list[tuple[str, Any, Any]] = [
    ("rate_column", RateColOpt, None), ("time_column", TimeColOpt, None),
    ("temperature_column", TempColOpt, None), ("fs", FsOpt, None), ("units", UnitsOpt, None),
    ("topic", TopicOpt, None), ("input", InputOpt, None), ("accel_units", AccelUnitsOpt, None),
    ("nan", NanOpt, "error"), ("gaps", GapsOpt, "warn"),
]
def fit_methods(text: str) -> str:
    """Check ``--method``: one noise-fit method or several separated by commas, each once
    (a typer callback: a bad value is a usage error naming the option)."""
    names = [m.strip() for m in text.split(",")]
    allowed = ", ".join(repr(m) for m in choices.FIT_METHODS)
    if not any(names):
        raise typer.BadParameter(f"{text!r} names no method; give one or more of {allowed}, "
                                 "separated by commas")
    for m in names:
        if m not in choices.FIT_METHODS:
            raise typer.BadParameter(f"{m!r} is not one of {allowed}" + (
                f" (in {text!r}; several methods are separated by commas)" if m != text
                else "."))
    twice = [m for i, m in enumerate(names) if m in names[:i]]
    if twice:
        raise typer.BadParameter(f"{twice[0]!r} is given twice in {text!r}; give each "
                                 "method once")
    return ",".join(names)


MethodOpt = Annotated[str, typer.Option("--method", callback=fit_methods, metavar="|".join(choices.FIT_METHODS) + "[,...]", help="Noise fit: wls (EDF weights), gls (full covariance), ols (unweighted, comparison only), gmwm (generalized method of wavelet moments, B as up to three Gauss-Markov terms), ml (exact Gaussian maximum likelihood of the record by the Kalman filter: N, B, K, R; Q is not modelled). Several, separated by commas (e.g. wls,gmwm,ml): the first is the fit every other output shows; all are shown side by side (a table, and 'methods' in the JSON).")]

KindOpt = Annotated[choices.Kind, typer.Option("--kind", help="Allan estimator (noise terms are fitted to adev, oadev and totdev).")]
CriterionOpt = Annotated[choices.Criterion, typer.Option("--criterion", help="ARMA ranking criterion.")]

if TYPE_CHECKING:
    from matplotlib.figure import Figure

    from fogts.allan.datasheet import NoiseSpec
    from fogts.io.run import Run
    from fogts.preprocess.hygiene import DataQuality
    from fogts.startup.thermal_model import ThermalModel



class ExitCode:
    """Exit codes (DESIGN.md): success, a negative verdict, bad usage/input/internal error."""

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
def guard(options: Mapping[str, str] | None = None, *,
           outputs: Mapping[str, Path | str | None] | None = None,
           inputs: Mapping[str, Iterable[Path]] | None = None,
           overwrite: bool = False, first: Iterable[Callable[[], object]] = ()) -> Iterator[None]:
    """Run a command body: warnings become ``warning: ...`` lines on stderr (each once),
    and any exception becomes one line ``error: ...`` on stderr with exit code 2.

    ``options`` maps library argument names (``latitude_deg``) to the command's option
    names (``--latitude``), so that an error raised by the library names what the user
    typed (:func:`fogts.cli._arguments.option_names`, which also maps the keywords every
    command shares, ``fs_hz=`` to ``--fs``).  ``outputs`` (option -> path) and ``inputs`` (argument -> paths) are checked by
    :func:`fogts.io.paths.check_outputs` before the body runs: no output replaces an input,
    nor, without ``overwrite`` (``--overwrite``), an existing data file; after the checks
    in ``first`` (an option's value, so that ``--export foo k.yaml`` is told the format)."""
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("default")
        try:
            for check in first:
                check()
            if outputs:
                from fogts.io.paths import check_outputs

                check_outputs(outputs, inputs or {}, overwrite=overwrite)
            yield
        except (typer.Exit, typer.Abort):
            raise
        except Exception as exc:
            if _STATE["debug"]:
                raise
            from fogts.report.text import error_message

            message = option_names(error_message(exc), options or {})
            err_console.print(f"error: {message}", markup=False, soft_wrap=True)
            raise typer.Exit(ExitCode.ERROR) from None
        finally:
            from fogts.report.text import warning_texts

            for text in warning_texts(caught):
                warn(text)


def warn(text: str | None) -> None:
    """Print ``warning: TEXT`` on stderr (nothing for None); a library keyword the text
    suggests (``pass units=``) is named as the option (``pass --units``:
    :func:`fogts.cli._arguments.option_keywords`)."""
    if text is not None:
        err_console.print(f"warning: {option_keywords(text)}", markup=False, soft_wrap=True)


@contextmanager
def named_warnings(file: str, axis: str | None = None) -> Iterator[None]:
    """Print the warnings raised inside the block at once as ``warning: FILE: AXIS: ...``
    lines on stderr.  Each file and axis is collected on its own (Python's warnings
    registry would otherwise show a message only the first time), so the same finding on
    two files or two axes is printed for each; within the block, each text once."""
    from fogts.report.text import warning_texts

    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        try:
            yield
        finally:
            for text in warning_texts(caught):
                warn(_attributed(text, file, axis))


def _attributed(text: str, file: str, axis: str | None) -> str:
    """``text`` prefixed with the file and the axis (the ``FILE: `` or ``axis 'X': `` prefix
    the library gave is replaced)."""
    if text.startswith(f"{file}: "):
        text = text[len(file) + 2:]
    if axis is not None:  # the analysis' own axis label (an array analysed alone is 'rate')
        text = re.sub(r"^axis '[^']*': ", "", text)
        text = text[len(axis) + 2:] if text.startswith(f"{axis}: ") else text
    return f"{file}: {axis}: {text}" if axis is not None else f"{file}: {text}"


def pauses_cycle_collection(command: Callable[..., R]) -> Callable[..., R]:
    """Run ``command`` with Python's cyclic garbage collector off (restored after).

    For a short command that imports most of its modules when it runs (numpy's, pandas'
    and scipy's: many objects, next to no cyclic garbage): each full collection the growing
    heap triggers scans every object imported so far (the cost is measured in
    ``benchmarks/README.md``).  Reference counting still frees everything else as usual.
    """
    @functools.wraps(command)
    def run_command(*args: Any, **kwargs: Any) -> R:
        enabled = gc.isenabled()
        gc.disable()
        try:
            return command(*args, **kwargs)
        finally:
            if enabled:
                gc.enable()

    return run_command


#: The placeholder default of a command's ``read`` parameter (replaced by :func:`reads_input`).
DEFAULT_READ = ReadSettings()


def reads_input(*, nan: bool = True, gaps: bool = True
                ) -> Callable[[Callable[..., R]], Callable[..., R]]:
    """Give a command the shared input options and pass them to it as one
    :class:`~fogts.pipeline.ReadSettings` argument ``read``.

    The options (``--rate-column``, ``--time-column``, ``--temperature-column``, ``--fs``,
    ``--units`` and, where asked, ``--nan`` and ``--gaps``) are declared once here and
    listed under "Input" in each command's ``--help``.  The command declares a last
    parameter ``read: ReadSettings = DEFAULT_READ`` instead; typer sees the options through the
    wrapper's ``__signature__``.
    """
    names = [name for name, _, _ in _INPUT_OPTIONS
             if (name != "nan" or nan) and (name != "gaps" or gaps)]

    def decorate(command: Callable[..., R]) -> Callable[..., R]:
        signature = inspect.signature(command, eval_str=True)
        kept = [p for p in signature.parameters.values() if p.name != "read"]
        added = [inspect.Parameter(name, inspect.Parameter.KEYWORD_ONLY, default=default,
                                   annotation=annotation)
                 for name, annotation, default in _INPUT_OPTIONS if name in names]

        @functools.wraps(command)
        def run_command(*args: Any, **kwargs: Any) -> R:
            given = {name: kwargs.pop(name) for name in names}
            read = ReadSettings(
                rate_column=given["rate_column"], time_column=given["time_column"],
                temperature_column=given["temperature_column"], fs_hz=given["fs"],
                units=given["units"], topic=given["topic"], input=given["input"],
                accel_units=given["accel_units"], nan=str(given.get("nan", "error")),
                gaps=str(given.get("gaps", "warn")))
            return command(*args, read=read, **kwargs)

        run_command.__signature__ = signature.replace(  # type: ignore[attr-defined]
            parameters=kept + added)
        run_command.__annotations__ = {p.name: p.annotation for p in kept + added}
        return run_command

    return decorate


def read_input(path: Path, read: ReadSettings, *, glitches: bool = True,
               outliers: float | None = None) -> tuple[Run, DataQuality]:
    """Read one input and check its hygiene (:func:`fogts.pipeline.load`): assumed units,
    missing cells, gaps and glitches are printed at once as ``warning:`` lines naming the
    file, before any analysis output.  Returns the Run (restricted to the longest regular
    segment with ``--gaps split``) and its DataQuality.  ``outliers``: the command's
    ``--outliers K`` (the glitch lines then say the samples are replaced, not kept)."""
    from fogts import progress
    from fogts.pipeline import load
    progress.ticker(f"reading {path.name}", None)
    with warnings.catch_warnings(record=True) as read_warnings:
        warnings.simplefilter("always")
        run, quality = load(path, dataclasses.replace(read, glitches=glitches))
    if outliers is not None:
        quality = dataclasses.replace(quality, outliers=outliers)
    lines = quality.warnings()
    for line in lines:
        warn(f"{Path(run.source).name}: {line}")
    for w in read_warnings:  # the read's own, less those the quality lines just said
        if not any(str(w.message).endswith(f": {line}") for line in lines):
            warnings.warn_explicit(w.message, w.category, w.filename, w.lineno)
    return run, quality


def emit_json(payload: dict[str, Any], target: str | None,
              options: Mapping[str, str] | None = None) -> None:
    """Write ``payload`` as JSON to ``target`` ('-' = stdout); files are written atomically.
    The warnings and notes in it name the options, not the library's keywords
    (:func:`fogts.cli._arguments.cli_payload`; ``options``: the command's own)."""
    if target is None:
        return
    from fogts.io.writer import write_text_atomic
    from fogts.report.text import json_dumps

    text = json_dumps(cli_payload(payload, options))
    if target == "-":
        sys.stdout.write(text + "\n")
    else:
        write_text_atomic(Path(target), text + "\n")


def print_out(*objects: Any, quiet_json: str | None = None) -> None:
    """Print to the terminal unless JSON goes to stdout (keep stdout parseable); uncropped,
    so that a table wider than the terminal (:func:`rich_table`: its numbers are never
    split) runs long instead of being cut at the terminal's width."""
    target = err_console if quiet_json == "-" else console
    target.print(*objects, crop=False)



_TAU_GRIDS = ("octave", "decade", "dense", "all")


def tau_option(text: str, option: str = "--taus") -> str | list[float]:
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


def export_format(export: tuple[str, Path] | None) -> choices.ExportFormat | None:
    """The ``--export`` format, checked against :data:`fogts.choices.EXPORT_FORMATS`."""
    from fogts.errors import DataError

    if export is None:
        return None
    fmt = export[0]
    if fmt not in choices.EXPORT_FORMATS:
        raise DataError(f"--export FORMAT must be one of {', '.join(choices.EXPORT_FORMATS)}; "
                        f"got {fmt!r}")
    return fmt  # type: ignore[return-value]


def check_output_names(**outputs: Path | None) -> None:
    """Reject output names the writers would refuse, before any analysis runs.

    ``plot`` must be a figure (.png, .svg, .pdf); every other keyword names a table option
    (``csv=...`` is ``--csv``) written by :func:`fogts.io.reader.write_frame_atomic`.
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



def save_figure(fig: Figure, path: str | Path) -> None:
    """Save a Figure atomically; the format follows the suffix (.png, .svg, .pdf)."""
    from fogts.errors import DataError
    from fogts.io.writer import atomic_path

    target = Path(path)
    fmt = target.suffix.lstrip(".").lower()
    if fmt not in ("png", "svg", "pdf"):
        raise DataError(f"--plot must end in .png, .svg or .pdf; got {target.name!r}")
    with atomic_path(target) as tmp:
        fig.savefig(tmp, format=fmt, dpi=150)



def say(lines: list[str], json_out: str | None) -> None:
    """Print text lines unwrapped (to stderr when the JSON goes to stdout)."""
    target = err_console if json_out == "-" else console
    target.print("\n".join(lines), markup=False, soft_wrap=True)



def load_thermal_model(path: Path) -> ThermalModel:
    from fogts.io.reader import read_json
    from fogts.startup.thermal_model import ThermalModel

    data = read_json(path, "thermal model")
    if isinstance(data, dict) and "thermal" in data and "terms" not in data:
        data = data["thermal"].get("model", data["thermal"])  # a `compensate --json` file
    return ThermalModel.from_dict(data)


def load_spec(path: Path | None) -> NoiseSpec | None:
    """``--spec SPEC.yaml``: the datasheet limits (:class:`fogts.allan.datasheet.NoiseSpec`);
    its warning (no ``units:``, degree units assumed) is printed at once, before any
    analysis output, as an input's assumed rate unit is."""
    if path is None:
        return None
    from fogts.allan.datasheet import NoiseSpec
    from fogts.io.reader import read_yaml

    with named_warnings(path.name):
        return NoiseSpec.from_mapping(read_yaml(path, "--spec file"), source=path.name)


def axis_index(run: Run, axis: str) -> int:
    """``--axis`` as a position in ``run.axes``: an axis name, or an index (negative ones
    count from the end, as in Python).  One parser for every command."""
    from fogts.errors import DataError

    text = axis.strip()
    if re.fullmatch(r"[+-]?\d+", text):
        i = int(text)
        if not -run.n_axes <= i < run.n_axes:
            raise DataError(f"--axis must be an axis name or an index in {-run.n_axes}.."
                            f"{run.n_axes - 1}, got {i}; axes are: {', '.join(run.axes)}")
        return i % run.n_axes
    if text not in run.axes:
        raise DataError(f"--axis {text!r} not found; axes are: {', '.join(run.axes)}")
    return int(run.axes.index(text))

