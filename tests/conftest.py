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
