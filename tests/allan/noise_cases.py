"""Curves with a known truth for the noise-fit tests.

Truth comes from closed-form Allan variances of the five terms (IEEE Std 952-1997
Annex C), simulated white + random-walk rate noise with fixed seeds, and published Allan
curves of real FOGs (SMAC-Group/avar: LN-200, iMAR FSAS, KVH 1750).
"""

from __future__ import annotations

import math
import re
import warnings

import numpy as np
import pandas as pd

from fogts.allan import AllanResult
from fogts.allan.noise import NoiseModel, fit_noise
from fogts.allan.noise_input import FitCurve
from fogts.errors import UnidentifiableTermWarning
from tests.conftest import shared_path

#: Truth of the simulated white + rate-random-walk records: deg/sqrt(h), deg/h^1.5 (the
#: -1/2 and +1/2 lines cross at 31 s).
N_TRUE, K_TRUE = 0.05, 10.0


def avar(tau: np.ndarray, *, Q: float = 0.0, N: float = 0.0, B: float = 0.0, K: float = 0.0,
         R: float = 0.0) -> np.ndarray:
    """DESIGN.md sigma^2(tau), rate in deg/h: terms in arcsec, deg/sqrt(h), deg/h,
    deg/h^1.5, deg/h^2 converted to deg/h-and-seconds (Q as is; N*60; B; K/60; R/3600)."""
    n, k, r = 60.0 * N, K / 60.0, R / 3600.0
    return (r**2 * tau**2 / 2 + k**2 * tau / 3 + B**2 * 2 * math.log(2) / math.pi + n**2 / tau
            + 3 * Q**2 / tau**2)


def make_result(tau: np.ndarray, dev: np.ndarray, *, edf: np.ndarray | float = 1000.0,
                units: str = "deg/h", kind: str = "oadev", fs_hz: float = 100.0,
                n_samples: int | None = None, ci: tuple[np.ndarray, np.ndarray] | None = None,
                confidence: float = 0.683) -> AllanResult:
    """An AllanResult with the given curve (m = tau fs, n_samples 4 m_max + 10 by default)."""
    m = np.rint(tau * fs_hz).astype(np.int64)
    n_samples = n_samples if n_samples is not None else int(4 * m.max() + 10)
    nan = np.full(tau.size, np.nan)
    lo, hi = ci if ci is not None else (nan, nan)
    return AllanResult(kind=kind, units=units, axis="x", fs_hz=fs_hz, n_samples=n_samples,
                       confidence=confidence, tau_s=tau, m=m, n=n_samples - 2 * m + 1,
                       dev=dev, ci_low=lo, ci_high=hi, edf=np.broadcast_to(edf, tau.shape),
                       alpha=np.zeros(tau.size, dtype=np.int64))


def nk_result() -> AllanResult:
    """N = 0.02 deg/sqrt(h) and K = 0.5 deg/h^1.5, exactly, on 16 octave taus from 1/16 s."""
    tau = 2.0 ** np.arange(-4, 12)
    return make_result(tau, np.sqrt(avar(tau, N=0.02, K=0.5)))


def quiet_fit(res: object, **kw: object) -> NoiseModel:
    """:func:`fit_noise` with UnidentifiableTermWarning silenced."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", UnidentifiableTermWarning)
        return fit_noise(res, **kw)  # type: ignore[arg-type]


def white_plus_rw(seed: int, *, n_deg_rt_h: float, k_deg_h15: float, fs_hz: float,
                  n: int) -> np.ndarray:
    """White rate noise (ARW N) plus a random walk in rate (RRW K), rate in deg/h.

    Two-sided white PSD N'^2 with N' = 60 N (deg/h sqrt(s)) -> sample std N' sqrt(fs);
    rate random walk with increments K' / sqrt(fs) per sample, K' = K / 60 (deg/h/sqrt(s)).
    """
    rng = np.random.default_rng(seed)
    white = 60.0 * n_deg_rt_h * math.sqrt(fs_hz) * rng.standard_normal(n)
    walk = np.cumsum(k_deg_h15 / 60.0 / math.sqrt(fs_hz) * rng.standard_normal(n))
    return white + walk


def smac_result(sensor: str, units: str, channel: str = "Gyro. X") -> AllanResult:
    """A published SMAC-Group/avar curve as an AllanResult.

    Its ``errors`` column is IEEE 952's 1/sqrt(2 (N/m - 1)), so edf = 1 / (2 errors^2); its
    bounds are adev (1 -/+ 2 errors), about a 95 % interval.
    """
    path = shared_path("allan_curves", "smac_avar", f"{sensor}_av.csv")
    head = path.read_text().splitlines()[0]
    fs = float(re.search(r"freq_hz=\[([0-9.]+)\]", head).group(1))  # type: ignore[union-attr]
    n = int(re.search(r"n=\[([0-9]+)\]", head).group(1))  # type: ignore[union-attr]
    df = pd.read_csv(path, comment="#")
    df = df[df["channel"] == channel]
    tau = df["tau_s"].to_numpy()
    return make_result(tau, df["adev"].to_numpy(),
                       edf=1.0 / (2.0 * df["errors"].to_numpy() ** 2), units=units, fs_hz=fs,
                       n_samples=n, ci=(df["adev_lci"].to_numpy(), df["adev_uci"].to_numpy()),
                       confidence=0.954)


def unit_curve(m: np.ndarray, *, kind: str, n_samples: int) -> FitCurve:
    """A FitCurve at averaging factors ``m`` (fs = 1 Hz) for the covariance basis alone."""
    return FitCurve(tau=m.astype(float), dev=np.ones(m.size), edf=np.ones(m.size),
                    edf_source="", units="deg/h", kind=kind, axis="", excluded=[], m=m,
                    n_samples=n_samples, fs_hz=1.0)
