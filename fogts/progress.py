"""Progress of long work, reported to whoever asked for it; the library itself never prints.

A caller that wants progress installs a callback for the duration of a block::

    with fogts.progress.reporting(lambda stage, done, total: print(stage, done, total)):
        fogts.allan_deviation(y, fs_hz=100.0)

and the loops that take time (one step per Allan tau, per ARMA candidate, per report
section, per dynamic-Allan tau, per batch file) report ``(stage, done, total)`` to it.  The
command line shows a rich progress bar this way (:mod:`fogts.cli.progress`).

The callback lives in a :class:`contextvars.ContextVar`, so it reaches every nested call
(a report computes Allan curves, which run estimators) without a ``progress=`` argument on
each function, and concurrent contexts (threads started with their own context, asyncio
tasks) do not see each other's.  With no callback installed a loop pays one context-variable
read per stage and a no-op call per step (measured in ``benchmarks/bench_progress.py``).
"""

from __future__ import annotations

from collections.abc import Callable, Iterator
from contextlib import contextmanager
from contextvars import ContextVar
from typing import Protocol

__all__ = ["ProgressCallback", "reporting", "ticker"]


class ProgressCallback(Protocol):
    """Receives ``(stage, done, total)``: a short description of the work, the steps done so
    far (0 when the stage starts) and the number of steps (None when unknown)."""

    def __call__(self, stage: str, done: int, total: int | None) -> None: ...


_CURRENT: ContextVar[ProgressCallback | None] = ContextVar("fogts_progress", default=None)


@contextmanager
def reporting(callback: ProgressCallback | None) -> Iterator[None]:
    """Send the progress of the work inside the block to ``callback`` (None: to nobody)."""
    token = _CURRENT.set(callback)
    try:
        yield
    finally:
        _CURRENT.reset(token)


def _ignore(done: int) -> None:
    """The step function when nobody listens."""


def ticker(stage: str, total: int | None) -> Callable[[int], None]:
    """Start a stage of ``total`` steps and return the function a loop calls with the number
    of steps done; a no-op when no callback is installed."""
    callback = _CURRENT.get()
    if callback is None:
        return _ignore
    callback(stage, 0, total)

    def step(done: int) -> None:
        callback(stage, done, total)

    return step
