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


def test_a_given_rate_that_contradicts_the_file_is_reported(tmp_path: Path) -> None:
    """--fs 10 on a 100 Hz record (time column or an .npz fs_hz key) warns with both
    numbers and is still used; a given rate that matches either step rate (a burst-logged
    file's mean step, say) or the file's rate is silent."""
    import warnings

    from fogts.errors import DataQualityWarning
    from fogts.io.timebase import GIVEN_RATE_TOLERANCE

    rate = np.random.default_rng(2).normal(size=400)
    frame = pd.DataFrame({"time": np.arange(400) / 100.0, "rate_deg_h": rate})
    with pytest.warns(DataQualityWarning, match=r"fs_hz = 10 Hz \(given\) disagrees with the "
                      r"time stamps \(median step 0\.01 s: 100 Hz; mean step 0\.01 s: 100 Hz\)"
                      r" by more than 10 %; the given rate is used for every tau"):
        run = read_run(frame, fs_hz=10.0)
    assert run.fs_hz == 10.0
    npz = tmp_path / "r.npz"
    np.savez(npz, gyro_deg_s=rate, fs_hz=100.0)
    with pytest.warns(DataQualityWarning, match="disagrees with the file's own sample rate "
                      "100 Hz by more than 10 %"):
        assert read_run(npz, fs_hz=10.0).fs_hz == 10.0
    within = 100.0 * (1 + GIVEN_RATE_TOLERANCE) * 0.99  # inside the tolerance: silent
    with warnings.catch_warnings():
        warnings.simplefilter("error", DataQualityWarning)
        assert read_run(frame, fs_hz=within).fs_hz == within
        assert read_run(npz, fs_hz=100.0).fs_hz == 100.0
        assert read_run(rate, fs_hz=3.0).fs_hz == 3.0  # nothing to contradict
