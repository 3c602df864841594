"""The ``fogts`` command line.  ``fogts = "fogts.cli:main"`` is the console script.

The typer app, the shared options and the error guard are in :mod:`fogts.cli._common`
(``--json`` and ``--overwrite`` in :mod:`fogts.cli._outputs`, ``--axis`` in
:mod:`fogts.cli._axes`); each command is a thin module of its own (parse options, call the
library, print).
"""

from __future__ import annotations

import importlib
import sys

import typer

from fogts.cli import _common as common
from fogts.cli._common import app

#: The commands, in the order ``fogts --help`` lists them; importing a command's module
#: registers it on the app.
COMMANDS = ("info", "allan", "curve", "batch", "report", "simulate", "davar", "filter", "compensate",
            "northfind", "select")
for _name in COMMANDS:
    importlib.import_module(f"fogts.cli.{_name}")

__all__ = ["app", "main"]


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
    """Console-script entry point.  Usage errors become one line ``error: ...`` with exit
    code 2 (:class:`fogts.cli._common._OneLineErrors`); so does any exception that escapes a
    command's guard."""
    argv = _hoist_global_flags(list(sys.argv[1:] if argv is None else argv))
    try:
        app(args=argv, prog_name="fogts")
    except Exception as exc:  # anything a command raised outside its guard: still one line
        if common._STATE["debug"]:
            raise
        from fogts.report.text import error_message

        common.err_console.print(f"error: {error_message(exc)}", markup=False, soft_wrap=True)
        raise SystemExit(common.ExitCode.ERROR) from None
