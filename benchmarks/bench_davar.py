"""Dynamic Allan deviation speed against a loop of allantools.oadev over the same windows.

The record is 3 h at 100 Hz (1.08 million samples) of white + flicker + random-walk rate
noise (``fogts.simulate_gyro``); the windows are 200 s long every 20 s (531 windows), and
the taus are the octave grid of one window (m = 1 .. 8192).  Figures (ratio = allantools
seconds / fogts seconds, > 1 means fogts is faster):

* ``dynamic_allan(..., method="cumsum")`` (the default for oadev: one running sum per tau
  over the whole record, sampled at the window edges; includes the noise identification,
  EDF, intervals and the non-stationarity score) against ``allantools.oadev`` called on
  each window with the same taus;
* ``method="kernel"`` (fogts' own oadev kernel on each window) against the same loop;
* the largest relative difference between fogts' and allantools' deviations (must be
  <= 1e-9).

``--quick`` uses 20 min at 100 Hz.  Run: ``python -m benchmarks.bench_davar [--quick]``;
the table goes to ``benchmarks/results/davar.md``.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from benchmarks.cli import script_main
from benchmarks.metric import Metric, accuracy_metric
from benchmarks.timing import measure, speed_from

FS_HZ = 100.0
WINDOW_S = 200.0
STEP_S = 20.0
RESULTS = Path(__file__).resolve().parent / "results" / "davar.md"


def allantools_loop(y: np.ndarray, taus: np.ndarray) -> np.ndarray:
    """The peer: allantools.oadev on every window, same taus."""
    import allantools

    win, step = round(WINDOW_S * FS_HZ), round(STEP_S * FS_HZ)
    starts = range(0, y.size - win + 1, step)
    return np.array([allantools.oadev(y[s:s + win], rate=FS_HZ, data_type="freq",
                                      taus=taus)[1] for s in starts])


def metrics(quick: bool = False) -> list[Metric]:
    from fogts.allan.dynamic import dynamic_allan
    from fogts.simulate.gyro import simulate_gyro

    duration = "20min" if quick else "3h"
    y = simulate_gyro({"N": 0.01, "B": 0.1, "K": 0.5}, fs_hz=FS_HZ, duration_s=duration,
                      rng=1).rate
    res = dynamic_allan(y, fs_hz=FS_HZ, window_s=WINDOW_S, step_s=STEP_S)
    taus = res.tau_s  # type: ignore[union-attr]
    peer = allantools_loop(y, taus)
    diff = float(np.max(np.abs(res.dev / peer - 1)))  # type: ignore[union-attr]
    assert diff <= 1e-9, diff

    def fast() -> object:
        return dynamic_allan(y, fs_hz=FS_HZ, window_s=WINDOW_S, step_s=STEP_S)

    def kernel() -> object:
        return dynamic_allan(y, fs_hz=FS_HZ, window_s=WINDOW_S, step_s=STEP_S,
                             method="kernel")

    timing = measure({"cumsum": fast, "kernel": kernel, "peer": lambda: allantools_loop(y, taus)},
                     repeat=3, min_total_s=2.0 if quick else 5.0)
    n_win, n_tau = res.shape  # type: ignore[union-attr]
    size = f"{y.size / 1e6:.3g}M"
    details = {"samples": y.size, "windows": n_win, "taus": n_tau, "window_s": WINDOW_S,
               "step_s": STEP_S}
    return [
        speed_from(timing, f"speed.davar.cumsum.n={size}",
                   f"dynamic_allan ({y.size:,} samples, {n_win} windows x {n_tau} taus), "
                   "vs allantools.oadev per window", ours="cumsum", peer="allantools loop",
                   details=details),
        speed_from(timing, f"speed.davar.kernel.n={size}",
                   "dynamic_allan method='kernel' (fogts oadev per window), vs allantools "
                   "loop", ours="kernel", peer="allantools loop", details=details),
        accuracy_metric(f"accuracy.davar.max_rel_diff.n={size}",
                        "dynamic_allan vs allantools per window: largest relative difference",
                        value=diff, better="lower", abs_tolerance=1e-9),
    ]


def main(argv: list[str] | None = None) -> int:
    return script_main(__doc__, metrics, argv, quick_help="20 min instead of 3 h", default_out=RESULTS)


if __name__ == "__main__":
    raise SystemExit(main())
