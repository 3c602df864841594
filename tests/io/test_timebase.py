"""fogts.io.timebase: ISO-8601 stamps, gaps in the time base, the sample rate."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pandas as pd
import pytest

from fogts.errors import DataError
from fogts.io.reader import read_run
from tests.io.files import write_file


def test_iso8601_time_column(tmp_path: Path) -> None:
    t = pd.date_range("2026-03-01T10:00:00", periods=20, freq="500ms")
    text = "timestamp,rate\n" + "\n".join(f"{ts.isoformat()},{i % 3}" for i, ts in enumerate(t))
    run = read_run(write_file(tmp_path, "iso.csv", text))
    assert run.fs_hz == pytest.approx(2.0)
    assert run.start_time is not None and run.start_time.startswith("2026-03-01T10:00:00")


def test_irregular_time_is_read_and_reported(tmp_path: Path) -> None:
    t = np.arange(100) / 10.0
    t[50:] += 2.0  # one 2.1 s gap after row 49
    text = "time,rate\n" + "\n".join(f"{a},{i % 4}" for i, a in enumerate(t))
    run = read_run(write_file(tmp_path, "gap.csv", text))
    assert run.n == 100  # nothing dropped
    assert run.sampling is not None
    assert run.sampling.n_gaps == 1 and run.sampling.gap_rows == (49,)
    assert run.sampling.max_gap_s == pytest.approx(2.1)
    assert not run.sampling.regular


def test_rate_from_float_stamps_is_rounded() -> None:
    df = pd.DataFrame({"time": np.arange(1000) / 10.0, "rate": np.arange(1000) % 7})
    assert read_run(df).fs_hz == 10.0  # 1/median(diff) is 10.000000000000568


def test_bad_iso_stamp(tmp_path: Path) -> None:
    text = "timestamp,rate\n2026-01-01T00:00:00,1\n2026-13-45T99:00:00,2\n2026-01-01T00:00:02,3\n"
    with pytest.raises(DataError, match="neither seconds nor ISO-8601"):
        read_run(write_file(tmp_path, "iso.csv", text))


def _step_cases() -> list[np.ndarray]:
    rng = np.random.default_rng(7)
    cases = []
    for n in (1000, 65_536, 65_537, 200_000, 200_001):
        t = np.arange(n + 1) / 100.0
        cases.append(np.diff(t))  # a fixed rate: few distinct steps
        cases.append(np.diff(np.cumsum(rng.uniform(0.009, 0.011, n + 1))))  # jitter
        cases.append(rng.exponential(size=n) + 1e-9)
        two = np.full(n, 0.01)
        two[: n // 2] = 0.02  # the middle pair straddles two values
        cases.append(two)
        cases.append(np.tile(np.r_[np.full(9, 1e-4), 0.1 - 9e-4], n // 10 + 1)[:n])  # bursts
        cases.append(np.sort(rng.exponential(size=n)))
    return cases


def test_median_step_equals_numpy_bit_for_bit() -> None:
    from fogts.io.timebase import median_step

    for dt in _step_cases():
        got, expected = np.float64(median_step(dt)), np.float64(np.median(dt))
        assert got.view(np.int64) == expected.view(np.int64), dt.size
