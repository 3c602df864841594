"""What the progress reports cost: ``allan_deviation`` of 10^7 samples (octave taus, one
thread) with no callback installed (what every library call and every command without a
bar pays), against the same call with the reporting stubbed out, and with the command
line's rich bar drawing (to a forced terminal in memory).

Figures (ratio = peer seconds / ours seconds; 1 = no cost):

* ``disabled`` against ``stubbed`` (``fogts.progress.ticker`` replaced by a function that
  returns a no-op without reading the context variable): the cost of the instrumentation
  when nobody listens, which must stay under 1 % (ratio >= 0.99);
* ``bar`` against ``disabled``: the cost of the drawn bar (rich refreshes it 10 times a
  second from its own thread);
* the per-call cost of a disabled ``ticker`` plus one step per tau, in nanoseconds, timed
  with ``timeit`` (the exact figure the ratio above cannot resolve).

``--quick`` uses 10^6 samples.  Run: ``python -m benchmarks.bench_progress [--quick]``.
"""

from __future__ import annotations

import timeit
from io import StringIO
from pathlib import Path
from unittest import mock

import numpy as np

from benchmarks.cli import script_main
from benchmarks.metric import Metric, accuracy_metric
from benchmarks.timing import measure, speed_from

RESULTS = Path(__file__).resolve().parent / "results" / "progress.md"


def _bare_ticker(stage: str, total: int | None) -> object:
    return _bare_step


def _bare_step(done: int) -> None:
    """A step that does nothing, without the context-variable read."""


def metrics(quick: bool = False) -> list[Metric]:
    from rich.console import Console

    from fogts import progress
    from fogts.allan import allan_deviation
    from fogts.cli.progress import RichProgress

    n = 1_000_000 if quick else 10_000_000
    y = np.random.default_rng(7).normal(size=n)

    def disabled() -> object:
        return allan_deviation(y, fs_hz=100.0, workers=1, confidence=None)

    def stubbed() -> object:
        with mock.patch.object(progress, "ticker", _bare_ticker):
            return disabled()

    def bar() -> object:
        reporter = RichProgress(Console(file=StringIO(), force_terminal=True, width=100),
                                delay_s=0.0)
        try:
            with progress.reporting(reporter):
                return disabled()
        finally:
            reporter.close()

    timing = measure({"disabled": disabled, "stubbed": stubbed, "bar": bar}, repeat=5,
                     min_total_s=3.0 if quick else 20.0)
    n_tau = int(allan_deviation(y[:100_000], fs_hz=100.0).tau_s.size)  # type: ignore[union-attr]

    def ticks() -> None:
        tick = progress.ticker("oadev", 24)
        for i in range(24):
            tick(i + 1)

    per_call_ns = min(timeit.repeat(ticks, number=10_000, repeat=5)) / 10_000 * 1e9
    size = f"{n / 1e6:.3g}M"
    details = {"samples": n, "taus": n_tau}
    return [
        speed_from(timing, f"speed.progress.disabled.n={size}",
                   f"allan_deviation ({n:,} samples) with no progress callback, vs the "
                   "reporting stubbed out", ours="disabled", peer_key="stubbed",
                   peer="stubbed reporting", details=details),
        speed_from(timing, f"speed.progress.bar.n={size}",
                   f"allan_deviation ({n:,} samples) with the rich bar drawing, vs no "
                   "callback", ours="bar", peer_key="disabled", peer="no callback",
                   details=details),
        accuracy_metric("cost.progress.disabled_ticker_24_steps_ns",
                        "a disabled ticker and 24 steps (one per tau): nanoseconds",
                        value=per_call_ns, better="lower", unit="ns", abs_tolerance=5_000.0),
    ]


def main(argv: list[str] | None = None) -> int:
    return script_main(__doc__, metrics, argv, quick_help="10^6 samples instead of 10^7",
                       default_out=RESULTS)


if __name__ == "__main__":
    raise SystemExit(main())
