"""Tests for fogts.preprocess.inputs: the one coercer of analysis input."""

from __future__ import annotations

import numpy as np
import pandas as pd
import pytest

from fogts.allan.api import allan_deviation
from fogts.allan.result import AllanResult
from fogts.arma.select import select_arma
from fogts.errors import DataError, InsufficientDataError
from fogts.io.run import Run
from fogts.preprocess.inputs import ensure_axes, ensure_series
from fogts.preprocess.prepare import prepare

FS = 10.0


def _white(n: int = 600, k: int = 1, seed: int = 0) -> np.ndarray:
    shape = (n,) if k == 1 else (n, k)
    return np.random.default_rng(seed).normal(size=shape)


def _run(rate: np.ndarray, axes: tuple[str, ...]) -> Run:
    return Run(rate=rate, time=np.arange(rate.shape[0]) / FS, fs_hz=FS, units="deg/s",
               axes=axes, columns=("time", *axes))


def test_array_is_the_rate_axis_without_a_sample_rate() -> None:
    inp = ensure_series([1, 2, 3])
    assert inp.values.dtype == np.float64 and inp.values.tolist() == [1.0, 2.0, 3.0]
    assert (inp.axes, inp.fs_hz, inp.units, inp.kind, inp.index) == (("rate",), None, None,
                                                                      "array", None)
    assert inp.wrap(inp.values, "y") is inp.values


def test_series_keeps_its_index_name_and_the_rate_of_a_time_index() -> None:
    idx = pd.timedelta_range(0, periods=600, freq="100ms")
    inp = ensure_series(pd.Series(_white(), index=idx, name="fog"), units="deg/s")
    assert inp.axes == ("fog",) and inp.kind == "Series" and inp.units == "deg/s"
    assert inp.fs_hz == pytest.approx(FS, rel=1e-12)
    wrapped = inp.wrap(inp.values * 2, "twice")
    assert isinstance(wrapped, pd.Series) and wrapped.index.equals(idx)
    assert ensure_series(pd.Series(_white()), fs_hz=5).fs_hz == 5.0  # given wins


def test_run_gives_one_axis_and_carries_rate_and_unit() -> None:
    run = _run(_white(k=3), ("x", "y", "z"))
    inp = ensure_series(run, axis="y")
    np.testing.assert_array_equal(inp.values, run.rate[:, 1])
    assert (inp.axes, inp.fs_hz, inp.units, inp.kind) == (("y",), FS, "deg/s", "Run")
    assert inp.run is run and inp.multi_axis_form
    assert ensure_series(run, axis=-1, fs_hz=20, units="rad/s").axes == ("z",)
    with pytest.raises(DataError, match=r"x is a Run with 3 axes \(x, y, z\); pass axis= "):
        ensure_series(run)


def test_prepared_is_used_as_is_or_refused() -> None:
    p = prepare(_white(), fs_hz=FS, stationarity=False)
    inp = ensure_series(p)
    assert inp.prepared is p and inp.kind == "Prepared" and inp.axes == ("rate",)
    np.testing.assert_array_equal(inp.values, p.x)
    with pytest.raises(DataError, match="data is already Prepared; pass the Run or the raw"):
        ensure_series(p, "data", accept_prepared=False)
    with pytest.raises(DataError, match="axis 'z' not found; the Prepared series is axis "
                                        "'rate'"):
        ensure_series(p, axis="z")


def test_refusals_name_the_argument_the_value_and_what_is_allowed() -> None:
    frame = pd.DataFrame({"a": _white(), "b": _white()})
    with pytest.raises(DataError, match=r"data must be one series \(an ndarray, a Series or "
                                        r"a Run\), got a DataFrame; for a DataFrame use "
                                        r"fogts.io.reader.read_run\(frame\) first"):
        ensure_series(frame, "data", accept_prepared=False)
    with pytest.raises(DataError, match=r"fs_hz is required for array input \(or pass a Run, "
                                        r"a Prepared, or a Series with a DatetimeIndex"):
        ensure_series(_white(), require_fs=True)
    with pytest.raises(DataError, match=r"fs_hz must be a finite number > 0, got -1"):
        ensure_series(_white(), fs_hz=-1)
    with pytest.raises(DataError, match=r"units"):
        ensure_series(_white(), units="furlongs")
    with pytest.raises(DataError, match=r"axis 2 not found; a 1-D series has one axis "
                                        r"\(0 or 'rate'\)"):
        ensure_series(_white(), axis=2)
    with pytest.raises(DataError, match=r"x must be a 1-D array, got shape \(600, 2\)"):
        ensure_series(_white(k=2))
    with pytest.raises(InsufficientDataError, match="x needs at least 10 samples, got 3"):
        ensure_series([1.0, 2.0, 3.0], min_length=10)


def test_axes_of_a_2d_array_a_frame_and_a_run() -> None:
    arr = _white(k=3)
    inp = ensure_axes(arr, fs_hz=FS)
    assert inp.axes == ("rate_0", "rate_1", "rate_2") and inp.multi_axis_form
    assert [name for name, _ in inp.columns()] == list(inp.axes)
    np.testing.assert_array_equal(inp.column(2), arr[:, 2])
    one = ensure_axes(arr, fs_hz=FS, axis=-1)
    assert one.axes == ("rate_2",) and one.values.ndim == 1 and one.multi_axis_form
    frame = pd.DataFrame(arr[:, :1], columns=["gyro_z"],
                         index=pd.timedelta_range(0, periods=600, freq="100ms"))
    framed = ensure_axes(frame)
    assert framed.kind == "DataFrame" and framed.multi_axis_form and framed.fs_hz == FS
    run = _run(arr, ("x", "y", "z"))
    assert ensure_axes(run).axes == ("x", "y", "z") and ensure_axes(run).units == "deg/s"
    assert not ensure_axes(_run(arr[:, 0], ("x",))).multi_axis_form


def test_axes_refusals() -> None:
    with pytest.raises(DataError, match=r"fs_hz is required for array input"):
        ensure_axes(_white())
    with pytest.raises(DataError, match=r"axis 'q' not found; axes are: rate_0, rate_1"):
        ensure_axes(_white(k=2), fs_hz=FS, axis="q")
    with pytest.raises(DataError, match=r"axis index must be in \[0, 1\], got 2"):
        ensure_axes(_white(k=2), fs_hz=FS, axis=2)
    bad = _white(k=2)
    bad[7, 1] = np.nan
    with pytest.raises(DataError, match=r"y contains a non-finite value \(nan\) at position 7"):
        ensure_axes(_run(bad, ("x", "y")))


def test_every_entry_point_reads_a_one_axis_run_alike() -> None:
    """prepare, allan_deviation and select_arma take the same axis, rate and unit from a
    one-axis Run (the rate is AR(1), so the selection has something to select)."""
    from scipy.signal import lfilter

    y = lfilter([1.0], [1.0, -0.5], _white(2000, seed=3))
    run = _run(y, ("fog",))
    p = prepare(run)
    res = allan_deviation(run, confidence=None)
    sel = select_arma(run)
    assert isinstance(res, AllanResult)
    assert p.axis == res.axis == sel.input["axis"] == "fog"
    assert p.fs_hz == res.fs_hz == sel.fs_hz == FS
    assert p.units == res.units == sel.units == "deg/s"
    for call in (prepare, select_arma):
        with pytest.raises(DataError, match=r"got a DataFrame"):
            call(pd.DataFrame({"a": y}))  # type: ignore[arg-type]


def test_missing_says_whether_nan_was_let_through() -> None:
    """``missing`` is True only when a Run's NaN passed with ``allow_nan``; every other
    input was checked finite, so the Allan analysis needs no second look for NaN."""
    y = np.random.default_rng(3).normal(size=(400, 2))
    assert not ensure_axes(_run(y, ("x", "y")), allow_nan=True).missing
    assert not ensure_axes(y, fs_hz=FS).missing
    y[10, 1] = np.nan
    gappy = _run(y, ("x", "y"))
    assert ensure_axes(gappy, allow_nan=True).missing
    assert ensure_axes(gappy, axis="y", allow_nan=True).missing
    assert not ensure_axes(gappy, axis="x", allow_nan=True).missing
    with pytest.raises(DataError, match="y"):
        ensure_axes(gappy)
