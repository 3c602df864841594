"""The output options every command shares, ``--json`` and ``--overwrite``, declared once.

A command takes them as one :class:`Outputs` argument ``out`` (the way it takes the input
options as one ``read``): :func:`writes_outputs` puts the two options in the command's
signature for typer and hands the command their values.  The command's own outputs
(``--plot``, ``--output``, ...) stay in its signature, each with the help that says what it
writes.
"""

from __future__ import annotations

import functools
import inspect
from collections.abc import Callable
from dataclasses import dataclass
from typing import Annotated, Any, TypeVar

import typer

R = TypeVar("R")

JsonOpt = Annotated[str | None, typer.Option("--json", help="Write JSON to PATH, or '-' for stdout.")]
OverwriteOpt = Annotated[bool, typer.Option("--overwrite", help="Replace output files that already exist (a figure or an HTML report is replaced anyway; any other existing file is refused without it, so that a mistyped name never turns another recording into an output).")]


@dataclass(frozen=True)
class Outputs:
    """The shared output options of one command call.

    Attributes
    ----------
    json : str or None
        ``--json``: the path to write the JSON to, ``"-"`` for stdout, None for none.
    overwrite : bool
        ``--overwrite``: whether an existing data file may be replaced
        (:func:`fogts.io.paths.check_outputs`).
    """

    json: str | None = None
    overwrite: bool = False


#: The default of a command's ``out`` parameter (the options' defaults).
NO_OUTPUTS = Outputs()


def writes_outputs(*, json: bool = True) -> Callable[[Callable[..., R]], Callable[..., R]]:
    """Give a command ``--overwrite`` and, with ``json``, ``--json``, and pass them to it as
    one :class:`Outputs` argument ``out``.

    The command declares the parameter ``out: Outputs = NO_OUTPUTS``; typer sees the two
    options through the wrapper's ``__signature__``, in place of ``out``.
    """
    options: list[tuple[str, Any, Any]] = [("json_out", None, JsonOpt)] if json else []
    options.append(("overwrite", False, OverwriteOpt))

    def decorate(command: Callable[..., R]) -> Callable[..., R]:
        signature = inspect.signature(command, eval_str=True)
        params = list(signature.parameters.values())
        at = [p.name for p in params].index("out")
        added = [inspect.Parameter(name, params[at].kind, default=default, annotation=annotation)
                 for name, default, annotation in options]
        shared = params[:at] + added + params[at + 1:]

        @functools.wraps(command)
        def run_command(*args: Any, **kwargs: Any) -> R:
            out = Outputs(json=kwargs.pop("json_out", None), overwrite=kwargs.pop("overwrite"))
            return command(*args, out=out, **kwargs)

        run_command.__signature__ = signature.replace(  # type: ignore[attr-defined]
            parameters=shared)
        run_command.__annotations__ = {p.name: p.annotation for p in shared}
        return run_command

    return decorate
