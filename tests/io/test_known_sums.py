"""A reader's sum of the rate, taken while it checked the values, serves the checks after it
within fogts._validate.known_sums; arrays it did not record are still checked."""

from __future__ import annotations

import numpy as np
import pytest

from fogts import allan_deviation
from fogts._validate import finite_sum, known_sums, note_sum, sums_known
from fogts.errors import DataError
from fogts.io.reader import read_run

N = 300_001  # several read blocks, an uneven last one


@pytest.fixture()
def npy(tmp_path):  # type: ignore[no-untyped-def]
    rng = np.random.default_rng(5)
    y = rng.standard_normal(N) * 10.0 ** rng.integers(-3, 4, N) + 7.5  # sums that round
    path = tmp_path / "r.npy"
    np.save(path, y)
    return path, y


def test_reader_records_numpy_sum_within_the_context(npy) -> None:  # type: ignore[no-untyped-def]
    path, y = npy
    assert not sums_known()
    with known_sums():
        assert sums_known()
        run = read_run(path, fs_hz=100.0)
        got = finite_sum(run.rate)
        assert got == float(np.sum(y))  # bit for bit: the blocks are numpy's pairwise nodes
        assert finite_sum(run.rate.copy()) == got  # another array: summed, the same
    assert np.array_equal(run.rate, y)


def test_recorded_sum_is_used_and_forgotten() -> None:
    x = np.array([1.0, 2.0])
    with known_sums():
        note_sum(x, 10.0)
        assert finite_sum(x) == 10.0  # the recorded sum, no pass
    assert finite_sum(x) == 3.0  # outside the context: summed
    note_sum(x, 10.0)  # no context: nothing recorded
    assert finite_sum(x) == 3.0


def test_same_deviations_with_the_recorded_sum(npy) -> None:  # type: ignore[no-untyped-def]
    path, _ = npy
    plain = allan_deviation(read_run(path, fs_hz=100.0), taus="octave")
    with known_sums():
        shared = allan_deviation(read_run(path, fs_hz=100.0), taus="octave")
    assert np.array_equal(plain.dev, shared.dev)  # the same mean, the same phase
    assert np.array_equal(plain.ci_low, shared.ci_low, equal_nan=True)


@pytest.mark.parametrize("bad", [np.nan, np.inf])
def test_unrecorded_arrays_are_still_checked(npy, bad: float) -> None:  # type: ignore[no-untyped-def]
    path, y = npy
    with known_sums():
        read_run(path, fs_hz=100.0)  # a recorded array beside
        user = y.copy()
        user[N // 2] = bad
        with pytest.raises(DataError, match="non-finite|inf|nan"):
            allan_deviation(user, fs_hz=100.0)


def test_nonfinite_file_records_nothing(npy, tmp_path) -> None:  # type: ignore[no-untyped-def]
    _, y = npy
    bad = y.copy()
    bad[N - 3] = np.inf
    path = tmp_path / "bad.npy"
    np.save(path, bad)
    with known_sums(), pytest.raises(DataError, match="inf"):
        read_run(path, fs_hz=100.0)


def test_two_thread_read_same_values_and_sum(npy, monkeypatch: pytest.MonkeyPatch) -> None:  # type: ignore[no-untyped-def]
    import fogts.io.timesteps as timesteps

    path, y = npy
    monkeypatch.setattr(timesteps, "HALVES_FROM", 1 << 17)  # the halves on two threads
    with known_sums():
        run = read_run(path, fs_hz=100.0)
        assert np.array_equal(run.rate, y) and finite_sum(run.rate) == float(np.sum(y))
    bad = y.copy()
    bad[N - 2] = np.nan  # in the second half
    np.save(path, bad)
    with pytest.raises(DataError, match="nan"):
        read_run(path, fs_hz=100.0)
