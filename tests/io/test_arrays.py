"""fogts.io.arrays: Parquet, .npy/.npz, DataFrames, Series and arrays."""

from __future__ import annotations

import re
from pathlib import Path

import numpy as np
import pandas as pd
import pytest

from fogts.errors import DataError
from fogts.io.reader import read_run
from tests.io.files import write_file


def test_parquet_npy_npz(tmp_path: Path) -> None:
    x = np.random.default_rng(0).normal(size=100)
    df = pd.DataFrame({"time": np.arange(100) / 20.0, "gyro": x})
    df.to_parquet(tmp_path / "a.parquet")
    np.save(tmp_path / "a.npy", x)
    np.savez(tmp_path / "a.npz", rate=x, fs_hz=np.float64(20.0))
    for name, kwargs in [("a.parquet", {}), ("a.npy", {"fs_hz": 20.0}), ("a.npz", {})]:
        run = read_run(tmp_path / name, **kwargs)
        np.testing.assert_array_equal(run.rate, x)
        assert run.fs_hz == pytest.approx(20.0)


def test_dataframe_with_datetime_index() -> None:
    idx = pd.date_range("2026-01-01", periods=40, freq="100ms")
    df = pd.DataFrame({"rate": np.arange(40.0) % 7, "temperature": 20.0 + np.arange(40)}, index=idx)
    run = read_run(df)
    assert run.fs_hz == pytest.approx(10.0)
    assert run.start_time == "2026-01-01T00:00:00"
    assert run.time[-1] == pytest.approx(3.9)


def test_a_named_index_is_a_column(tmp_path: Path) -> None:
    """``df.set_index("time")``, in memory or saved to Parquet, keeps its time base (the
    index was dropped: "no time column found"); an unnamed index is still dropped, and a
    name that a column already has does not replace the column."""
    x = np.random.default_rng(1).normal(size=200)
    df = pd.DataFrame({"time": np.arange(200) / 20.0, "gyro": x})
    df.set_index("time").to_parquet(tmp_path / "indexed.parquet")
    for source in (df.set_index("time"), tmp_path / "indexed.parquet"):
        run = read_run(source)
        assert run.axes == ("gyro",) and run.fs_hz == pytest.approx(20.0)
        np.testing.assert_array_equal(run.rate, x)
    unnamed = df.set_index(pd.Index(np.arange(200) * 3))
    assert read_run(unnamed).fs_hz == pytest.approx(20.0)
    clash = df.set_index(pd.Index(np.arange(200) / 5.0, name="time"))
    assert read_run(clash).fs_hz == pytest.approx(20.0)


def test_series_with_timedelta_index() -> None:
    s = pd.Series(np.arange(30.0) % 5, index=pd.timedelta_range(0, periods=30, freq="20ms"),
                  name="omega")
    run = read_run(s)
    assert run.axes == ("omega",) and run.fs_hz == pytest.approx(50.0)


def test_pickled_object_array_is_refused(tmp_path: Path) -> None:
    np.save(tmp_path / "obj.npy", np.array([{"a": 1}, 2], dtype=object), allow_pickle=True)
    with pytest.raises(DataError, match="pickled object arrays are never loaded"):
        read_run(tmp_path / "obj.npy", fs_hz=1.0)


def test_npz_without_numeric_arrays(tmp_path: Path) -> None:
    np.savez(tmp_path / "s.npz", names=np.array(["a", "b"]))
    with pytest.raises(DataError, match="holds no numeric 1-D or 2-D array; keys are: names"):
        read_run(tmp_path / "s.npz", fs_hz=1.0)


def test_3d_array_refused() -> None:
    with pytest.raises(DataError, match=r"array must be 1-D \(rate\) or 2-D"):
        read_run(np.zeros((3, 3, 3)), fs_hz=1.0)


def test_bad_npy_signature(tmp_path: Path) -> None:
    with pytest.raises(DataError, match=r"not a valid .npy file \(wrong signature\)"):
        read_run(write_file(tmp_path, "x.npy", b"garbage"), fs_hz=1.0)


@pytest.mark.parametrize("shape", [(3 * (1 << 16) + 5,), ((1 << 16) + 7, 3), (5,)])
def test_npy_chunked_read_is_np_load(tmp_path: Path, shape: tuple[int, ...]) -> None:
    """The chunked, checked read of a float64 ``.npy`` (chunks of 2^16 values) gives
    ``np.load``'s values bit for bit, across chunk edges and for several axes."""
    x = np.random.default_rng(1).normal(size=shape)
    np.save(tmp_path / "x.npy", x)
    run = read_run(tmp_path / "x.npy", fs_hz=10.0)
    np.testing.assert_array_equal(run.rate, x)


@pytest.mark.parametrize(("bad", "shown"), [(np.nan, "nan"), (np.inf, "inf"),
                                            (1e200, "the value 1e+200")])
def test_npy_bad_value_in_a_later_chunk_is_named(tmp_path: Path, bad: float, shown: str
                                                 ) -> None:
    x = np.zeros((1 << 17) + 3)
    x[(1 << 16) + 9] = bad  # in the second chunk
    np.save(tmp_path / "x.npy", x)
    with pytest.raises(DataError,
                       match=re.escape(f"column 'rate' has {shown} at row {(1 << 16) + 9}")):
        read_run(tmp_path / "x.npy", fs_hz=10.0)


@pytest.mark.parametrize("arr", [np.arange(10.0).astype(">f8"), np.arange(10, dtype=np.float32),
                                 np.asfortranarray(np.arange(20.0).reshape(10, 2))])
def test_npy_other_layouts_load_as_before(tmp_path: Path, arr: np.ndarray) -> None:
    """Big-endian, float32 and Fortran-ordered arrays take ``np.load``; same values."""
    np.save(tmp_path / "x.npy", arr)
    run = read_run(tmp_path / "x.npy", fs_hz=10.0)
    np.testing.assert_array_equal(run.rate, arr.astype(np.float64))


def test_npy_that_shrinks_while_read_is_refused(tmp_path: Path,
                                                monkeypatch: pytest.MonkeyPatch) -> None:
    """A file cut short after its header was checked (e.g. still being written): a clear
    error, not a half-filled array."""
    import fogts.io.arrays as arrays

    np.save(tmp_path / "x.npy", np.zeros(1000))
    real = arrays.check_npy

    def check_then_truncate(path: Path) -> object:
        header = real(path)
        with open(path, "r+b") as fh:
            fh.truncate(header.offset + 800)
        return header

    monkeypatch.setattr(arrays, "check_npy", check_then_truncate)
    with pytest.raises(DataError, match="is truncated: it ended while its data were read"):
        read_run(tmp_path / "x.npy", fs_hz=10.0)
