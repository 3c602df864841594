"""The progress bar of the long commands (allan, select, report, davar, batch).

The library reports its steps through :mod:`fogts.progress` and never prints; here a rich
bar on stderr receives them.  It is shown only when stderr is a terminal, not with
``--quiet``, not when the JSON goes to stdout (``--json -``), and only once the command has
run :data:`DELAY_S` seconds (the environment variable ``FOGTS_PROGRESS_DELAY`` overrides
it), so that short runs print exactly what they printed before.  The bar is transient: it
is erased when the command ends.

Commands get the ``--quiet`` option from :func:`shows_progress`, as they get the input
options from :func:`fogts.cli._common.reads_input`.
"""

from __future__ import annotations

import functools
import inspect
import os
import threading
from collections.abc import Callable
from typing import Annotated, Any, TypeVar

import typer
from rich.console import Console
from rich.progress import (
    BarColumn,
    MofNCompleteColumn,
    Progress,
    SpinnerColumn,
    TaskID,
    TextColumn,
    TimeElapsedColumn,
)

from fogts import progress
from fogts.cli import _common as common

__all__ = ["DELAY_S", "RichProgress", "bar_enabled", "shows_progress"]

#: Seconds a command runs before its bar appears.
DELAY_S = 2.0
R = TypeVar("R")
QuietOpt = Annotated[bool, typer.Option("--quiet", "-q", help="No progress bar (it is shown on a terminal for work over 2 s, never with --json -).")]
_STATE: dict[str, bool] = {"enabled": False}


def _delay_s() -> float:
    text = os.environ.get("FOGTS_PROGRESS_DELAY", "")
    try:
        return max(0.0, float(text)) if text else DELAY_S
    except ValueError:
        return DELAY_S


class RichProgress:
    """A :class:`fogts.progress.ProgressCallback` drawing one rich bar on ``console``: the
    current stage's description, its steps done out of its total (a spinner when the total
    is unknown) and the time elapsed.  Nothing is drawn before ``delay_s`` seconds."""

    def __init__(self, console: Console, delay_s: float = DELAY_S) -> None:
        self.bar = Progress(SpinnerColumn(), TextColumn("{task.description}"), BarColumn(),
                            MofNCompleteColumn(), TimeElapsedColumn(), console=console,
                            transient=True)
        self.task: TaskID | None = None
        self.lock = threading.Lock()
        self.started = self.closed = False
        self.timer = threading.Timer(delay_s, self._show)
        self.timer.daemon = True
        self.timer.start()

    def _show(self) -> None:
        with self.lock:
            if not self.closed:
                self.bar.start()
                self.started = True

    def __call__(self, stage: str, done: int, total: int | None) -> None:
        if self.task is None:
            self.task = self.bar.add_task(stage, total=total, completed=done)
        else:
            self.bar.update(self.task, description=stage, total=total, completed=done)

    def close(self) -> None:
        """Stop the timer and erase the bar."""
        self.timer.cancel()
        with self.lock:
            self.closed = True
            if self.started:
                self.bar.stop()


def bar_enabled() -> bool:
    """Whether the running command may draw a progress bar (see the module docstring)."""
    return _STATE["enabled"]


def shows_progress(*, library: bool = True) -> Callable[[Callable[..., R]], Callable[..., R]]:
    """Give a command ``--quiet`` and, when a bar is wanted, run its body with a
    :class:`RichProgress` receiving the library's steps (``library=False``: the command
    draws its own bar and asks :func:`bar_enabled`)."""

    def decorate(command: Callable[..., R]) -> Callable[..., R]:
        signature = inspect.signature(command, eval_str=True)
        params = list(signature.parameters.values())
        quiet = inspect.Parameter("quiet", inspect.Parameter.KEYWORD_ONLY, default=False,
                                  annotation=QuietOpt)

        @functools.wraps(command)
        def run_command(*args: Any, **kwargs: Any) -> R:
            wanted = not kwargs.pop("quiet") and kwargs.get("json_out") != "-" \
                and common.err_console.is_terminal
            _STATE["enabled"] = wanted
            if not (wanted and library):
                return command(*args, **kwargs)
            reporter = RichProgress(common.err_console, _delay_s())
            try:
                with progress.reporting(reporter):
                    return command(*args, **kwargs)
            finally:
                reporter.close()

        run_command.__signature__ = signature.replace(  # type: ignore[attr-defined]
            parameters=[*params, quiet])
        run_command.__annotations__ = {**command.__annotations__, "quiet": QuietOpt}
        return run_command

    return decorate
