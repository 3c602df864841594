"""The one-pass statistics of a long time base (fogts.io.timesteps) against the numpy
formulas, and read_run's time base through them against the array path."""

from __future__ import annotations

import operator
import warnings

import numpy as np
import pandas as pd
import pytest

from fogts.errors import DataError
from fogts.io.reader import read_run
from fogts.io.timebase import Steps, sample_rate, sampling_report, step_stats
from fogts.io.timesteps import LEAF, pairwise_fold, step_deviation, summarise_steps

N = 3 * LEAF + 12_345  # several blocks and an uneven last one


def _stamps(kind: str, rng: np.random.Generator) -> np.ndarray:
    k = np.arange(N, dtype=np.float64)
    if kind == "regular":  # steps equal but for float rounding
        return k / 100.0
    if kind == "epoch":  # absolute stamps: the shift by t[0] matters
        return 1.7e9 + k / 100.0
    if kind == "jittered":
        return k / 100.0 + rng.normal(0.0, 2e-5, N)
    if kind == "irregular":  # no typical step: the counted median candidate misses
        return np.cumsum(rng.uniform(0.005, 0.015, N))
    if kind == "gapped":
        t = k / 100.0
        t[N // 3:] += 2.5
        t[2 * N // 3:] += 0.7
        return t
    if kind == "burst":  # stamps in clumps: the mean step gives the rate
        return np.floor(k / 10.0) * 0.1 + (k % 10) * 1.3e-4
    raise AssertionError(kind)


KINDS = ["regular", "epoch", "jittered", "irregular", "gapped", "burst"]


@pytest.mark.parametrize("size", [1, 7, 128, 129, LEAF, LEAF + 1, 2 * LEAF + 9, 1_000_003])
def test_pairwise_fold_is_numpy_sum(size: int) -> None:
    # the blocks are nodes of numpy's pairwise summation: the sum is numpy's, bit for bit
    rng = np.random.default_rng(size)
    x = rng.standard_normal(size) * 10.0 ** rng.integers(-6, 6, size)  # sums that round
    got = pairwise_fold(0, size, lambda s, e: float(np.sum(x[s:e])), operator.add)
    assert got == float(np.sum(x))


@pytest.mark.parametrize("kind", KINDS)
def test_summary_equals_numpy(kind: str) -> None:
    raw = _stamps(kind, np.random.default_rng(7))
    time, summary = summarise_steps(raw, float(raw[0]))
    expected_time = raw - raw[0]
    dt = np.diff(expected_time)
    assert np.array_equal(time, expected_time)
    assert summary.count == dt.size
    assert summary.smallest == dt.min() and summary.longest == dt.max()
    assert summary.total == float(np.sum(dt)) and summary.mean == float(np.mean(dt))
    assert summary.below == np.count_nonzero(dt < summary.guess)
    assert summary.at_or_below == np.count_nonzero(dt <= summary.guess)
    median = summary.median()
    if median is not None:  # found by counting: numpy's median
        assert median == float(np.median(dt))
    # stamps at a fixed rate take few distinct steps, and the candidate is the median;
    # continuous steps leave the median to the array path
    assert (median is not None) == (kind in ("regular", "epoch", "gapped"))
    # the jitter pass: numpy.std of the steps, to 1e-12 relative (bit for bit in fact)
    assert step_deviation(time, summary.mean) == pytest.approx(float(np.std(dt)), rel=1e-12,
                                                               abs=0.0)
    assert step_deviation(time, summary.mean) == float(np.std(dt))


def test_summary_without_shift_and_nan() -> None:
    raw = np.arange(N, dtype=np.float64) / 10.0
    time, summary = summarise_steps(raw, None)
    assert time is raw and summary.mean == float(np.mean(np.diff(raw)))
    raw = raw.copy()
    raw[LEAF + 5] = np.nan
    _, summary = summarise_steps(raw, None)
    assert np.isnan(summary.smallest) and np.isnan(summary.longest)  # as numpy's min/max


@pytest.mark.parametrize("kind", KINDS)
@pytest.mark.parametrize("given", [None, 100.0])
def test_steps_equal_the_array_path(kind: str, given: float | None) -> None:
    raw = _stamps(kind, np.random.default_rng(11))
    time, summary = summarise_steps(raw, float(raw[0]))
    dt = np.diff(raw - raw[0])
    fast = Steps(time=time, summary=summary)
    with warnings.catch_warnings(record=True) as seen:
        warnings.simplefilter("always")
        got = fast.sample_rate(given, None, "x")
        want = sample_rate(dt, given, None, "x", steps=step_stats(dt))
    assert got == want
    assert len(seen) == (2 if kind == "burst" and given is None else 0)
    report, expected = fast.report(got[0], got[1]), sampling_report(dt, got[0], got[1])
    assert report == expected  # every field, bit for bit
    assert Steps(dt).report(got[0], got[1]) == expected


@pytest.mark.parametrize("kind", ["regular", "jittered", "gapped"])
def test_read_run_time_base_unchanged(kind: str, tmp_path) -> None:  # type: ignore[no-untyped-def]
    rng = np.random.default_rng(3)
    t = _stamps(kind, rng) + 12.5
    frame = pd.DataFrame({"time": t, "rate": rng.standard_normal(N)})
    path = tmp_path / "r.parquet"
    frame.to_parquet(path)
    run = read_run(path)
    time = t - t[0]
    dt = np.diff(time)
    fs, source = sample_rate(dt, None, None, "x", steps=step_stats(dt))
    assert np.array_equal(run.time, time) and run.fs_hz == fs
    assert run.sampling == sampling_report(dt, fs, source)


def test_decreasing_time_found_by_the_pass() -> None:
    t = np.arange(N, dtype=np.float64) / 100.0
    t[2 * LEAF + 3] = t[2 * LEAF + 1]
    frame = pd.DataFrame({"time": t, "rate": np.random.default_rng(0).standard_normal(N)})
    with pytest.raises(DataError, match=f"time column 'time' is decreasing at row {2 * LEAF + 3}"):
        read_run(frame)


@pytest.mark.parametrize("bad", [np.nan, np.inf, -np.inf, 1e200])
@pytest.mark.parametrize("at", [0, LEAF + 17, N - 1])
def test_bad_time_cell_named_as_before(bad: float, at: int) -> None:
    # the one-pass path checks the time column by its ends and its order; a bad cell
    # anywhere still gets the general path's message
    t = np.arange(N, dtype=np.float64) / 100.0
    t[at] = bad
    frame = pd.DataFrame({"time": t, "rate": np.random.default_rng(0).standard_normal(N)})
    with pytest.raises(DataError, match="column 'time'") as got:
        read_run(frame)
    if bad != 1e200 or at in (0, N - 1):
        assert f"row {at}" in str(got.value)


@pytest.mark.parametrize("kind", ["regular", "jittered", "gapped"])
def test_two_threads_give_the_same_bits(kind: str, monkeypatch: pytest.MonkeyPatch) -> None:
    # the halves of the top node on two threads: the same nodes, the same result
    import fogts.io.timesteps as timesteps

    raw = _stamps(kind, np.random.default_rng(13))
    one = summarise_steps(raw, float(raw[0]))
    monkeypatch.setattr(timesteps, "HALVES_FROM", 2 * LEAF)
    two = summarise_steps(raw, float(raw[0]))
    assert np.array_equal(one[0], two[0]) and one[1] == two[1]
    dt = np.diff(raw - raw[0])
    assert step_deviation(two[0], two[1].mean) == float(np.std(dt))
    assert two[1].total == float(np.sum(dt))
