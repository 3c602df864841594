"""fogts.io.run: the Run record's time base, formed on first access when it is regular by
construction (RegularTime), and the same values as the array the readers used to form."""

from __future__ import annotations

import dataclasses
import pickle
from pathlib import Path

import numpy as np
import pytest

from fogts.io.reader import read_run
from fogts.io.run import RegularTime, Run, held_time


def _arange_time(n: int, fs: float) -> np.ndarray:
    t = np.arange(n, dtype=np.float64)
    t /= fs
    return t


def _lazy_run(n: int = 5, fs: float = 3.0) -> Run:
    return Run(rate=np.arange(n, dtype=float), time=RegularTime(n, fs), fs_hz=fs,
               units="deg/h", axes=("rate",))


def test_regular_time_is_formed_on_first_access_and_kept() -> None:
    run = _lazy_run(7, 3.0)
    assert held_time(run) is None
    first = run.time
    assert np.array_equal(first, _arange_time(7, 3.0))  # bit for bit: same operations
    assert held_time(run) is first and run.time is first


def test_an_array_time_is_kept_as_given() -> None:
    t = np.array([0.0, 0.5, 1.5])
    run = Run(rate=np.ones(3), time=t, fs_hz=2.0, units="deg/h", axes=("rate",))
    assert run.time is t and held_time(run) is t


def test_run_stays_a_frozen_dataclass_with_time_a_required_field() -> None:
    run = _lazy_run()
    with pytest.raises(dataclasses.FrozenInstanceError):
        run.time = np.zeros(5)  # type: ignore[misc]
    field = {f.name: f for f in dataclasses.fields(Run)}["time"]
    assert field.default is dataclasses.MISSING
    with pytest.raises(TypeError, match="time"):
        Run(rate=np.ones(3), fs_hz=1.0, units="deg/h", axes=("rate",))  # type: ignore[call-arg]


def test_replace_and_pickle_keep_the_time_values() -> None:
    copy = pickle.loads(pickle.dumps(_lazy_run(6, 4.0)))
    assert held_time(copy) is None  # still not formed
    assert np.array_equal(copy.time, _arange_time(6, 4.0))
    changed = dataclasses.replace(_lazy_run(6, 4.0), rate=np.zeros(6))
    assert np.array_equal(changed.time, _arange_time(6, 4.0))
    assert np.array_equal(_lazy_run().to_frame()["time"], _arange_time(5, 3.0))


def test_read_run_without_time_column_defers_the_time(tmp_path: Path) -> None:
    y = np.random.default_rng(0).standard_normal(1000)
    path = tmp_path / "w.npy"
    np.save(path, y)
    run = read_run(path, fs_hz=100.0, units="deg/h")
    assert held_time(run) is None
    assert np.array_equal(run.time, _arange_time(1000, 100.0))
    angle = read_run(np.r_[0.0, np.cumsum(y)], fs_hz=100.0, input="angle")  # n + 1 angles
    assert angle.n == 1000 and np.array_equal(angle.time, _arange_time(1000, 100.0))


def test_read_run_with_interpolated_cells_times_them_as_before() -> None:
    y = np.random.default_rng(1).standard_normal(200)
    y[[0, 50, 51, 199]] = np.nan
    run = read_run(y, fs_hz=10.0, nan="interpolate")
    expected = y.copy()
    t = _arange_time(200, 10.0)
    bad = np.isnan(expected)
    expected[bad] = np.interp(t[bad], t[~bad], y[~bad])
    assert np.allclose(run.rate, expected)
    assert np.array_equal(run.time, t)
