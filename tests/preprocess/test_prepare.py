"""Tests for fogts.preprocess.prepare."""

from __future__ import annotations

import numpy as np
import pandas as pd
import pytest

from fogts.errors import DataError, InsufficientDataError
from fogts.io.reader import read_run
from fogts.io.run import RegularTime, Run, held_time
from fogts.preprocess.prepare import MAD_TO_SIGMA, prepare
from tests.conftest import shared_path


def _white(n: int = 5000, seed: int = 0) -> np.ndarray:
    return np.random.default_rng(seed).normal(size=n)


def test_mad_constant() -> None:
    from scipy.stats import norm

    assert pytest.approx(1.0 / norm.ppf(0.75), rel=1e-12) == MAD_TO_SIGMA


def test_detrend_removes_known_polynomial() -> None:
    t = np.arange(4000) / 10.0
    x = 3.0 + 0.02 * t - 1e-4 * t**2 + _white(4000)
    p = prepare(x, fs_hz=10.0, detrend=2, stationarity=False)
    # coefficients in powers of seconds, lowest first; tolerance from the noise (sd 1)
    c0, c1, c2 = p.trend_coefficients
    assert c0 == pytest.approx(3.0, abs=0.1)
    assert c1 == pytest.approx(0.02, abs=2e-3)
    assert c2 == pytest.approx(-1e-4, abs=1e-5)
    assert abs(p.x.mean()) < 1e-10
    assert p.steps == ("removed a polynomial trend of order 2",)


def test_outliers_replaced_and_recorded() -> None:
    x = _white()
    x[[100, 2500]] = [40.0, -35.0]
    p = prepare(x, fs_hz=100.0, outliers=6, stationarity=False)
    assert p.outliers is not None
    assert p.outliers.indices.tolist() == [100, 2500]
    assert p.outliers.values.tolist() == [40.0, -35.0]
    assert p.n == x.size  # replaced, not dropped
    assert abs(p.x[100]) < 5 and abs(p.x[2500]) < 5


def test_real_glitch_in_adis_run4_is_found() -> None:
    # ../shared/data/README.md: run 4 has a real glitch near t = 4046 s (on axis X the
    # samples at 4046.05 s and 4046.07 s read +11.45 and -17.0 deg/s; median 0.4 deg/s)
    run = read_run(shared_path("imu", "adis_16405_imu4_gyro.npz"))
    p = prepare(run, axis=0, outliers=20, stationarity=False)
    assert p.outliers is not None
    times = p.outliers.indices / run.fs_hz
    assert p.outliers.count >= 2
    assert np.all(np.abs(times - 4046.1) < 0.2)  # nothing flagged elsewhere in 2.8 h
    assert {11.45, -17.0} <= {round(v, 2) for v in p.outliers.values}


def test_decimate_block_average_and_tail() -> None:
    x = np.arange(103, dtype=float) % 5
    p = prepare(x, fs_hz=10.0, decimate=10, demean=False, stationarity=False)
    assert p.n == 10 and p.dropped_tail == 3 and p.fs_hz == 1.0
    np.testing.assert_allclose(p.x, x[:100].reshape(10, 10).mean(axis=1))
    assert "dropped 3 tail samples" in p.steps[0]


def test_series_index_kept_and_fs_from_datetime_index() -> None:
    idx = pd.date_range("2026-01-01", periods=600, freq="100ms")
    s = pd.Series(_white(600), index=idx, name="fog")
    p = prepare(s, decimate=2, stationarity=False)
    assert p.fs_hz == pytest.approx(5.0)
    assert p.axis == "fog"
    assert p.index is not None and p.index[1] == idx[2]
    assert p.series().index.equals(p.index)


def test_stationarity_verdicts() -> None:
    white = prepare(_white(3000), fs_hz=1.0)
    assert white.stationarity is not None and white.stationarity.verdict == "stationary"
    walk = prepare(np.cumsum(_white(3000, 1)), fs_hz=1.0)
    assert walk.stationarity is not None and walk.stationarity.verdict == "non-stationary"



def test_stationarity_summary_shows_table_bounds_as_bounds() -> None:
    # KPSS's table spans 0.01-0.1: statsmodels returns the end it passed and says so (the
    # note); the summary shows the bound, not a value.  MacKinnon's ADF p-value is 0 for a
    # statistic beyond its range: shown as p<0.0001.
    white = prepare(_white(3000), fs_hz=1.0).stationarity
    walk = prepare(np.cumsum(_white(3000, 1)), fs_hz=1.0).stationarity
    assert white is not None and walk is not None
    assert any("greater than the p-value returned" in n for n in white.notes)
    assert white.kpss_pvalue == pytest.approx(0.1, abs=1e-12)
    assert "KPSS p>0.1;" in white.summary() and "KPSS p=" not in white.summary()
    assert any("smaller than the p-value returned" in n for n in walk.notes)
    assert "KPSS p<0.01;" in walk.summary()
    assert white.adf_pvalue < 1e-4 and "(ADF p<0.0001," in white.summary()
    assert f"(ADF p={walk.adf_pvalue:.3g}," in walk.summary()


def test_stationarity_summary_of_interpolated_kpss_pvalue() -> None:
    # a KPSS statistic inside the table: the interpolated value, with '='
    from fogts.preprocess.prepare import StationarityReport

    rep = StationarityReport(-5.0, 0.02, 1, 0.3, 0.0417, 3, 100, 1, "stationary")
    assert rep.summary() == ("level: stationary (ADF p=0.02, KPSS p=0.0417; tests the mean, "
                             "not the noise level)")

def test_units_of_array_input() -> None:
    assert prepare(_white(100), fs_hz=1.0, units="deg/s", stationarity=False).units == "deg/s"
    assert prepare(_white(100), fs_hz=1.0, stationarity=False).units == "deg/h"
    with pytest.raises(DataError, match=r"units must be a rate unit \(deg/h, .*got .rpm."):
        prepare(_white(100), fs_hz=1.0, units="rpm")


def test_run_input_keeps_units_and_axis() -> None:
    run = read_run(np.column_stack([_white(100), _white(100, 2)]), fs_hz=50.0, units="deg/s")
    p = prepare(run, axis=1, stationarity=False)
    assert p.units == "deg/s" and p.axis == "rate_1" and p.fs_hz == 50.0
    d = p.to_dict()
    assert d["n"] == 100 and d["steps"][0].startswith("removed the mean")


@pytest.mark.parametrize(("kwargs", "exc", "match"), [
    ({"detrend": -1}, DataError, "detrend must be >= 0, got -1"),
    ({"detrend": 11}, DataError, "detrend must be <= 10, got 11"),
    # audit2: it said ">= 2" while 1 (no decimation) is accepted, as batch says ">= 1"
    ({"decimate": 0}, DataError, "decimate must be >= 1, got 0"),
    ({"decimate": 2.5}, DataError, "decimate must be an integer, got 2.5"),
    ({"decimate": 1000}, InsufficientDataError, "decimate=1000 leaves 5 samples"),
    ({"outliers": -3}, DataError, "outliers must be a finite number > 0, got -3"),
    ({"fs_hz": 0}, DataError, "fs_hz must be a finite number > 0, got 0"),
])
def test_bad_arguments(kwargs: dict[str, object], exc: type[Exception], match: str) -> None:
    kw: dict[str, object] = {"fs_hz": 10.0, **kwargs}
    with pytest.raises(exc, match=match):
        prepare(_white(5000), **kw)  # type: ignore[arg-type]


def test_bad_data() -> None:
    with pytest.raises(InsufficientDataError, match="is constant"):
        prepare(np.ones(100), fs_hz=1.0)
    with pytest.raises(InsufficientDataError, match="needs at least 10 samples, got 3"):
        prepare(np.arange(3.0), fs_hz=1.0)
    with pytest.raises(DataError, match="fs_hz is required for array input"):
        prepare(_white(100))
    with pytest.raises(DataError, match=r"non-finite value \(nan\) at position 100"):
        prepare(np.r_[_white(100), np.nan], fs_hz=1.0)
    with pytest.raises(DataError, match="for a DataFrame use fogts.io.reader.read_run"):
        prepare(pd.DataFrame({"a": _white(100)}), fs_hz=1.0)
    with pytest.raises(DataError, match="marks every sample as an outlier"):
        prepare(np.r_[np.zeros(50), np.ones(50)], fs_hz=1.0, outliers=1e-9)
    with pytest.raises(DataError, match="axis index must be in"):
        prepare(read_run(_white(100), fs_hz=1.0), axis=3)


def test_a_regular_time_base_is_not_formed_to_decimate() -> None:
    """A Run read without time stamps (RegularTime): block averaging takes every k-th time
    (the same values as from the array) and leaves the run's time unformed."""
    y = np.random.default_rng(7).standard_normal(10_007)
    t = np.arange(y.size, dtype=np.float64) / 50.0

    def run_with(time: object) -> Run:
        return Run(rate=y, time=time, fs_hz=50.0, units="deg/h", axes=("rate",))  # type: ignore[arg-type]

    lazy = run_with(RegularTime(y.size, 50.0))
    got = prepare(lazy, decimate=10, stationarity=False)
    ref = prepare(run_with(t), decimate=10, stationarity=False)
    assert held_time(lazy) is None
    assert np.array_equal(got.time, ref.time) and np.array_equal(got.x, ref.x)
    full = prepare(run_with(RegularTime(y.size, 50.0)), stationarity=False)
    assert np.array_equal(full.time, t)


def test_a_regular_time_base_is_formed_only_on_access() -> None:
    """Without decimation a regular time base stays a RegularTime (a 1e8-sample record's
    array would be 800 MB) until ``time`` is read; selection and its summary never read it,
    ``predict()`` forms the same values."""
    from fogts.arma.select import select_arma

    y = np.random.default_rng(8).standard_normal(3000)
    run = Run(rate=y, time=RegularTime(y.size, 20.0), fs_hz=20.0, units="deg/h",
              axes=("rate",))
    prep = prepare(run, stationarity=False)
    assert isinstance(prep.lazy_time, RegularTime)
    sel = select_arma(prep, candidates="AR(1)")
    assert sel.best is not None
    sel.best.prediction_summary()
    assert isinstance(prep.lazy_time, RegularTime)
    t = np.arange(y.size, dtype=np.float64) / 20.0
    assert np.array_equal(sel.best.predict().time, t)
    assert np.array_equal(prep.time, t) and prep.lazy_time is prep.time
