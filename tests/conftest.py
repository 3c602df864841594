"""Shared test helpers.

Reference data live in ``../shared/data`` (beside the repository, never inside it).  Tests
that need them call :func:`shared_path`, which skips the test with a clear reason when the
folder is absent (a user's fresh clone); CI always has it.
"""

from __future__ import annotations

import os

# On a loaded 2-core machine multithreaded OpenBLAS makes small BLAS calls up to 1000x
# slower (measured: a 36k-element dot product 21 ms instead of 26 us); tests use one thread.
os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

from pathlib import Path

import matplotlib
import numpy as np
import pytest

matplotlib.use("Agg")

_REPO = Path(__file__).resolve().parents[1]
SHARED_DATA = Path(os.environ.get("FOGTS_SHARED_DATA", _REPO.parent / "shared" / "data"))


def shared_path(*parts: str) -> Path:
    """Path to a file under ``../shared/data``; skip the test if it is not there."""
    path = SHARED_DATA.joinpath(*parts)
    if not path.exists():
        pytest.skip(f"reference data not available: {path} (the ../shared/data folder is "
                    "absent; CI provides it)")
    return path


@pytest.fixture
def shared() -> type:
    """Fixture form: ``shared.path("stable32", "...")``."""

    class _Shared:
        path = staticmethod(shared_path)
        root = SHARED_DATA

    return _Shared


# ---- Stable32 reference files (used by the Allan estimator and API tests)


def stable32(path: Path) -> dict[str, np.ndarray]:
    """Columns of a Stable32 result file: ``AF Tau # Alpha MinSigma Sigma MaxSigma``."""
    a = np.loadtxt(path, comments="#", ndmin=2)
    return {"m": a[:, 0].astype(np.int64), "tau": a[:, 1], "n": a[:, 2].astype(np.int64),
            "alpha": a[:, 3].astype(np.int64), "lo": a[:, 4], "dev": a[:, 5], "hi": a[:, 6]}


def stable32_rounded_input(freq: np.ndarray) -> np.ndarray:
    """The frequency Stable32 effectively analysed for the OCXO octave files.

    Those files were made from ``ocxo_frequency.001``, whose header says Average = 1.0:
    Stable32 was given ``f / 1e7`` itself, not the fractional frequency, and integrated it
    to phase without removing the mean.  The phase then grows to 2e4 while its second
    differences are ~1e-10, so every stored phase point carries a rounding error of about
    eps x 2e4 = 4e-12, and the overlapping statistics computed from it are off by ~5e-4
    (OADEV(1 s) = 7.6143e-11 in oadev_octave.txt against 7.6106e-11 in adev_octave.txt and
    in stable32_oadev_alltau.txt, which fogts matches to 6e-7; at m = 1 they are the same
    statistic).  Integrating the same way here and differencing the rounded phase back
    (exact by Sterbenz's lemma) hands fogts the rate that phase implies.
    """
    phase = np.concatenate([[0.0], np.cumsum(freq)])
    return np.diff(phase)


def error_output(stderr: str) -> str:
    """``stderr`` without the ``warning:`` lines a command prints about its input (assumed
    units, gaps, glitches) as soon as it has read it: what is left of a failed command
    must be its one ``error:`` line."""
    return "\n".join(ln for ln in stderr.strip().splitlines()
                     if not ln.startswith("warning: ")).strip()
