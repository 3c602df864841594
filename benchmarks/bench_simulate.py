"""``simulate_gyro`` speed and memory: a 10^8-sample record in chunks, and a peer in the same run.

Figures:

* **10^8 samples, every term** (Q, N, B, K, R, Markov, sinusoid, ARMA; 100 Hz, 11.6 days):
  wall time and peak traced memory (``tracemalloc``, numpy allocations included) as a
  multiple of the output (the rate array plus the time array of the Run).  The synthesis
  runs in chunks of 2^20 samples, so the peak should stay close to 1x the output.
* **speed against allantools** on 2^22 samples (2^18 with ``--quick``): N + B + K with
  fogts (flicker as a sum of Markov processes, and as Kasdin-Walter) against
  ``allantools.noise_kasdin.Noise`` generating the same three power laws (white FM,
  flicker FM, random-walk FM; b = -2, -3, -4 on phase) and differencing the phase to rate,
  which is how one builds such a record with allantools.  Ratio = allantools seconds /
  fogts seconds; also the peak memory of each as a multiple of its output.

Run: ``python -m benchmarks.bench_simulate [--quick]``; the table goes to
``benchmarks/results/simulate.md``.  ``--quick`` uses 2x10^6 samples for the chunked run.
"""

from __future__ import annotations

import gc
import time
import tracemalloc
from collections.abc import Callable
from pathlib import Path
from typing import Any

import numpy as np

from benchmarks.cli import script_main
from benchmarks.metric import Metric, accuracy_metric
from benchmarks.timing import measure, speed_from

FS_HZ = 100.0
ALL_TERMS = {"Q": 0.05, "N": 0.01, "B": 0.1, "K": 0.5, "R": 0.2, "q_c": 0.05, "T_c": 30.0,
             "Omega_0": 0.02, "f_0": 0.01}
NBK = {"N": 0.01, "B": 0.1, "K": 0.5}
RESULTS = Path(__file__).resolve().parent / "results" / "simulate.md"


def traced(fn: Callable[[], Any]) -> tuple[float, int]:
    """Wall time and peak traced bytes of one call (the result is dropped)."""
    gc.collect()
    tracemalloc.start()
    t0 = time.perf_counter()
    out = fn()
    dt = time.perf_counter() - t0
    _, peak = tracemalloc.get_traced_memory()
    tracemalloc.stop()
    del out
    gc.collect()
    return dt, peak


def allantools_nbk(n: int, seed: int = 1) -> np.ndarray:
    """The peer: white + flicker + random-walk FM with allantools' Kasdin generator."""
    from allantools.noise_kasdin import Noise

    np.random.seed(seed)  # noqa: NPY002 - allantools draws from the global generator
    rate = np.zeros(n)
    for b, qd in ((-2, 1.0), (-3, 1e-3), (-4, 1e-6)):
        gen = Noise(nr=2 * n, qd=qd, b=b)  # phase, 2n points: the FFT convolution needs them
        gen.generateNoise()
        rate += np.diff(gen.time_series[:n + 1]) * FS_HZ
    return rate


def metrics(quick: bool = False) -> list[Metric]:
    from fogts.simulate.gyro import simulate_gyro

    big = 2 * 10**6 if quick else 10**8
    arma = {"ar": [0.5], "sigma2": 1e-4}

    def chunked() -> object:
        return simulate_gyro(ALL_TERMS, fs_hz=FS_HZ, duration_s=big / FS_HZ, rng=1, arma=arma)

    t_big, peak_big = traced(chunked)
    out_bytes = 2 * 8 * big  # rate + time
    n = 2**18 if quick else 2**22

    def markov() -> object:
        return simulate_gyro(NBK, fs_hz=FS_HZ, duration_s=n / FS_HZ, rng=1)

    def kasdin() -> object:
        return simulate_gyro(NBK, fs_hz=FS_HZ, duration_s=n / FS_HZ, rng=1, flicker="kasdin")

    timing = measure({"markov": markov, "kasdin": kasdin, "peer": lambda: allantools_nbk(n)},
                     repeat=3 if quick else 2)
    _, peak_markov = traced(markov)
    _, peak_kasdin = traced(kasdin)
    _, peak_peer = traced(lambda: allantools_nbk(n))
    size = f"{big:.0e}".replace("+0", "")
    return [
        accuracy_metric(f"memory.simulate_gyro.all_terms.n={size}",
                        f"simulate_gyro, {big:,} samples, every term ({t_big:.1f} s, "
                        f"{big / t_big / 1e6:.2f} M samples/s): peak memory / output",
                        value=peak_big / out_bytes, better="lower", unit="x output",
                        details={"seconds": t_big, "peak_bytes": peak_big,
                                 "output_bytes": out_bytes}),
        speed_from(timing, f"speed.simulate_gyro.nbk_markov.n={n}",
                     f"simulate_gyro N+B+K, {n:,} samples, flicker as Markov sum (peak "
                     f"{peak_markov / (16 * n):.2f}x output), vs allantools Kasdin (peak "
                     f"{peak_peer / (8 * n):.1f}x output)", ours="markov",
                     peer="allantools noise_kasdin"),
        speed_from(timing, f"speed.simulate_gyro.nbk_kasdin.n={n}",
                     f"simulate_gyro N+B+K, {n:,} samples, Kasdin-Walter flicker (peak "
                     f"{peak_kasdin / (16 * n):.2f}x output), vs allantools Kasdin",
                     ours="kasdin", peer="allantools noise_kasdin"),
    ]


def main(argv: list[str] | None = None) -> int:
    return script_main(__doc__, metrics, argv, quick_help="2x10^6 samples instead of 10^8", default_out=RESULTS)


if __name__ == "__main__":
    raise SystemExit(main())
