"""Reference series for the confidence tests: Stable32 result files and their input
rates (``../shared/data/stable32``), and simulated power-law noise of known exponent."""

from __future__ import annotations

from functools import cache

import numpy as np
import pandas as pd

from tests.conftest import shared_path


def stable32_table(*parts: str) -> np.ndarray:
    """Rows ``AF, Tau, #, Alpha, MinSigma, Sigma, MaxSigma`` of a Stable32 output file."""
    path = shared_path("stable32", *parts)
    rows = [[float(v) for v in line.split()] for line in path.read_text().splitlines()
            if line.strip() and not line.startswith("#")]
    table = np.array(rows)
    assert table.shape[1] == 7, f"unexpected Stable32 format in {path}"
    return table


@cache
def gps_rate() -> np.ndarray:
    """GPS 1PPS phase (s) at tau0 = 1 s -> fractional frequency = first difference."""
    path = shared_path("stable32", "gps", "gps_1pps_phase_data.txt.gz")
    phase = pd.read_csv(path, comment="#", header=None).iloc[:, 0].to_numpy(np.float64)
    return np.diff(phase)


@cache
def phase_dat_rate() -> np.ndarray:
    phase = np.loadtxt(shared_path("stable32", "phasedat", "PHASE.DAT"))
    return np.diff(phase)


@cache
def ocxo_rate() -> np.ndarray:
    return np.loadtxt(shared_path("stable32", "ocxo", "ocxo_frequency.txt"), comments="#") / 1e7


def kasdin(n: int, beta: float, rng: np.random.Generator) -> np.ndarray:
    """1/f**beta noise by the Kasdin & Walter (1992) fractional-integration filter:
    h_0 = 1, h_k = h_{k-1} (beta/2 + k - 1) / k, applied to white noise by FFT."""
    k = np.arange(1, n)
    h = np.concatenate(([1.0], np.cumprod((beta / 2.0 + k - 1.0) / k)))
    w = rng.standard_normal(n)
    size = 2 * n
    return np.fft.irfft(np.fft.rfft(w, size) * np.fft.rfft(h, size), size)[:n]


def power_law_noise(alpha: int, n: int, seed: int) -> np.ndarray:
    """Rate ("frequency") series with S_y(f) ~ f**alpha."""
    rng = np.random.default_rng(seed)
    if alpha == 2:
        return np.diff(rng.standard_normal(n + 1))  # white phase
    if alpha == 1:
        return np.diff(kasdin(n + 1, 1.0, rng))  # flicker phase
    if alpha == 0:
        return rng.standard_normal(n)
    if alpha == -1:
        return kasdin(n, 1.0, rng)
    return np.cumsum(rng.standard_normal(n))  # random-walk rate
