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

import sys
import warnings
from collections.abc import Iterator
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
from fogts.errors import FogtsError

app = typer.Typer(
    name="fogts",
    help="Fibre-optic-gyro drift analysis: Allan variance, IEEE-952 noise terms, ARMA models.",
    no_args_is_help=True,
    add_completion=False,
    pretty_exceptions_enable=False,
)
console = Console(highlight=False)
err_console = Console(stderr=True, highlight=False)

_STATE: dict[str, bool] = {"debug": False}

# ---------------------------------------------------------------- shared input options
FileArg = Annotated[Path, typer.Argument(help="Input recording (CSV/TSV/text, .gz, Parquet, .npy/.npz).")]
RateColOpt = Annotated[str | None, typer.Option("--rate-column", help="Rate column(s), comma-separated; default: auto-detect.")]
TimeColOpt = Annotated[str | None, typer.Option("--time-column", help="Time column; default: auto-detect.")]
TempColOpt = Annotated[str | None, typer.Option("--temperature-column", help="Temperature column; default: auto-detect.")]
FsOpt = Annotated[float | None, typer.Option("--fs", help="Sample rate in Hz (overrides the time column).")]
UnitsOpt = Annotated[str | None, typer.Option("--units", help="Rate unit of the input: deg/h, deg/s, rad/s, arcsec/s [default: from a unit in the column name such as gyro_x_deg_s, else deg/h].")]
JsonOpt = Annotated[str | None, typer.Option("--json", help="Write JSON to PATH, or '-' for stdout.")]


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
def _guard() -> Iterator[None]:
    """Run a command body: warnings become ``warning: ...`` lines on stderr (each once),
    and any exception becomes one line ``error: ...`` on stderr with exit code 2."""
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("default")
        try:
            yield
        except (typer.Exit, typer.Abort):
            raise
        except Exception as exc:
            if _STATE["debug"]:
                raise
            msg = str(exc).strip().splitlines()[0] if str(exc).strip() else type(exc).__name__
            if not isinstance(exc, FogtsError | ValueError | OSError):
                msg = f"internal error ({type(exc).__name__}): {msg}"
            err_console.print(f"error: {msg}", markup=False, soft_wrap=True)
            raise typer.Exit(ExitCode.ERROR) from None
        finally:
            _report_warnings(caught)


def _report_warnings(caught: list[warnings.WarningMessage]) -> None:
    seen: set[str] = set()
    for w in caught:
        text = str(w.message).strip().splitlines()[0] if str(w.message).strip() else ""
        if text and text not in seen:
            seen.add(text)
            err_console.print(f"warning: {text}", markup=False, soft_wrap=True)


def _read(path: Path, rate_column: str | None, time_column: str | None,
          temperature_column: str | None, fs: float | None, units: str | None) -> Any:
    from fogts.io import read_run

    rate_cols: str | list[str] | None = None
    if rate_column:
        parts = [c.strip() for c in rate_column.split(",") if c.strip()]
        rate_cols = parts if len(parts) > 1 else parts[0]
    return read_run(path, rate_column=rate_cols, time_column=time_column,
                    temperature_column=temperature_column, fs_hz=fs, units=units)


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
        table.add_column(c, justify="right" if c not in ("term", "model", "name", "column") else "left")
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
    json_out: JsonOpt = None,
) -> None:
    """Show what was read: columns, sample rate, duration, gaps, jitter and statistics."""
    with _guard():
        run = _read(file, rate_column, time_column, temperature_column, fs, units)
        payload = _info_payload(run)
        _emit_json(payload, json_out)
        if json_out != "-":
            from fogts.report import info_text

            console.print(info_text(payload), markup=False, soft_wrap=True)


def main(argv: list[str] | None = None) -> None:
    """Console-script entry point: usage errors become one line ``error: ...``, exit 2."""
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
