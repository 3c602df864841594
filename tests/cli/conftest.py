"""Shared fixtures of the command tests."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

FS = 100.0
N_TRUE, K_TRUE = 0.05, 10.0  # deg/sqrt(h), deg/h^1.5


@pytest.fixture(scope="module")
def gyro_npy(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """40 min of white rate noise (ARW N) plus a rate random walk (RRW K) in deg/h."""
    n = int(40 * 60 * FS)
    rng = np.random.default_rng(11)
    y = (60 * N_TRUE * math.sqrt(FS) * rng.standard_normal(n)
         + np.cumsum(K_TRUE / 60 / math.sqrt(FS) * rng.standard_normal(n)))
    path = tmp_path_factory.mktemp("allan") / "gyro.npy"
    np.save(path, y)
    return path
