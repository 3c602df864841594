"""Dynamic Allan deviation (DAVar) against looping ``allantools.oadev`` over the same windows.

The record is 3 h of 100 Hz white rate noise plus a rate random walk (1.08 million samples),
the window 200 s and the step 20 s, as in the simulation issue; ``--quick`` uses 30 minutes.
The peer is what a user does without fogts: ``allantools.oadev(y[s:s+W], rate=fs,
data_type="freq", taus=...)`` for every window start, on the taus fogts used.  fogts also
computes each window's EDF, confidence interval and the non-stationarity score, which the
loop does not.

Figures: the speed ratio (loop seconds / fogts seconds) and the largest relative difference
between the two dev grids (accuracy; must stay at rounding level).

Run: ``python benchmarks/bench_davar.py [--quick]``.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

import numpy as np

try:
    from benchmarks._runner import (
        Metric,
        accuracy_metric,
        paired_times,
        render_markdown,
        speed_metric,
    )
except ImportError:  # run as a script: python benchmarks/bench_davar.py
    sys.path.insert(0, str(Path(__file__).resolve().parents[1]))
    from benchmarks._runner import (
        Metric,
        accuracy_metric,
        paired_times,
        render_markdown,
        speed_metric,
    )

FS_HZ = 100.0
WINDOW_S, STEP_S = 200.0, 20.0


def _record(duration_s: float, seed: int = 3) -> np.ndarray:
    rng = np.random.default_rng(seed)
    n = int(duration_s * FS_HZ)
    return rng.normal(0.0, 0.2, n) + np.cumsum(rng.normal(0.0, 2e-4, n)) + 5.0


def metrics(quick: bool) -> list[Metric]:
    """Measure and return the figures (the runner's entry point)."""
    import allantools

    from fogts.allan.dynamic import dynamic_allan

    duration = 1800.0 if quick else 3 * 3600.0
    y = _record(duration)

    def ours():  # type: ignore[no-untyped-def]
        return dynamic_allan(y, fs_hz=FS_HZ, window_s=WINDOW_S, step_s=STEP_S, kind="oadev")

    res = ours()
    starts = np.rint(res.start_s * FS_HZ).astype(np.int64)
    win = int(res.window_n)
    taus = np.asarray(res.tau_s, dtype=np.float64)

    def loop() -> np.ndarray:
        out = np.empty((starts.size, taus.size))
        for k, s in enumerate(starts):
            out[k] = allantools.oadev(y[s:s + win], rate=FS_HZ, data_type="freq",
                                      taus=taus)[1]
        return out

    ref = loop()
    rel = float(np.max(np.abs(np.asarray(res.dev) / ref - 1.0)))
    t_ours, t_loop = paired_times(ours, loop, repeat=3 if quick else 2)
    hours = duration / 3600.0
    tag = f"{hours:g}h"
    title = (f"DAVar, {hours:g} h at 100 Hz, window {WINDOW_S:g} s, step {STEP_S:g} s "
             f"({starts.size} windows, {taus.size} taus)")
    return [
        speed_metric(f"speed.davar.{tag}", title, fogts_s=t_ours, peer_s=t_loop,
                     peer="allantools loop", details={"windows": int(starts.size),
                                                      "taus": int(taus.size)}),
        accuracy_metric(f"accuracy.davar_vs_allantools.{tag}", f"DAVar, {hours:g} h: largest "
                        "relative difference to the allantools loop", value=rel,
                        better="lower", abs_tolerance=1e-9),
    ]


def main(argv: list[str] | None = None) -> int:
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--quick", action="store_true", help="30 minutes instead of 3 hours")
    args = p.parse_args(argv)
    print(render_markdown({"metrics": metrics(args.quick), "quick": args.quick}))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
