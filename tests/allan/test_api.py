"""``allan_deviation`` and its result records: inputs, multi-axis, confidence wiring, output."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pandas as pd
import pytest

from fogts.allan import AllanResult, AllanResultSet, allan_deviation
from fogts.allan.confidence import confidence_table
from fogts.allan.estimators import ESTIMATORS
from fogts.allan.taus import KINDS, DroppedTau, tau_grid
from fogts.errors import DataError, InsufficientDataError
from fogts.io.reader import read_run
from fogts.io.run import Run
from fogts.preprocess.prepare import prepare
from fogts.report.text import json_dumps

FS = 10.0


@pytest.fixture(scope="module")
def rate() -> np.ndarray:
    rng = np.random.default_rng(42)
    return 0.05 * rng.normal(size=6000) + 1e-4 * np.cumsum(rng.normal(size=6000)) + 15.0


@pytest.fixture(scope="module")
def three_axes() -> np.ndarray:
    rng = np.random.default_rng(43)
    return rng.normal(size=(4000, 3)) * np.array([0.1, 0.2, 0.3])


def _run(rate: np.ndarray, axes: tuple[str, ...], units: str = "deg/s") -> Run:
    return Run(rate=rate, time=np.arange(rate.shape[0]) / FS, fs_hz=FS, units=units,
               axes=axes)


# ------------------------------------------------------------------------- results


def test_array_input_gives_one_curve_equal_to_the_kernel(rate: np.ndarray) -> None:
    res = allan_deviation(rate, fs_hz=FS)
    assert isinstance(res, AllanResult)
    grid = tau_grid("octave", fs_hz=FS, n_samples=rate.size, kind="oadev")
    ref = ESTIMATORS["oadev"](rate, fs_hz=FS, m=grid.m)
    np.testing.assert_array_equal(res.m, grid.m)
    np.testing.assert_array_equal(res.tau_s, grid.tau_s)
    np.testing.assert_array_equal(res.n, ref.n)
    np.testing.assert_array_equal(res.dev, ref.dev)
    np.testing.assert_allclose(res.avar, ref.dev**2)
    assert (res.kind, res.units, res.axis, res.fs_hz, res.n_samples) == (
        "oadev", "deg/h", "rate", FS, rate.size)
    assert len(res) == grid.m.size and res.dropped == ()


@pytest.mark.parametrize("kind", KINDS)
def test_every_kind_and_grid_through_the_api(rate: np.ndarray, kind: str) -> None:
    for spec in ("octave", "decade", "dense"):
        res = allan_deviation(rate, fs_hz=FS, kind=kind, taus=spec, per_decade=4,
                              confidence=None)
        assert isinstance(res, AllanResult) and res.kind == kind
        grid = tau_grid(spec, fs_hz=FS, n_samples=rate.size, kind=kind, per_decade=4)
        np.testing.assert_array_equal(res.dev, ESTIMATORS[kind](rate, fs_hz=FS, m=grid.m).dev)


def test_confidence_table_is_wired_in(rate: np.ndarray) -> None:
    res = allan_deviation(rate, fs_hz=FS, taus="decade", confidence=0.9)
    assert isinstance(res, AllanResult)
    table = confidence_table(rate, fs_hz=FS, kind="oadev", m=res.m, dev=res.dev,
                             confidence=0.9)
    np.testing.assert_array_equal(res.ci_low, table.ci_low)
    np.testing.assert_array_equal(res.ci_high, table.ci_high)
    np.testing.assert_array_equal(res.edf, table.edf)
    np.testing.assert_array_equal(res.alpha, table.alpha)
    assert res.alpha_method == tuple(table.alpha_method)
    assert res.confidence == 0.9 and res.has_ci
    # Every point with an interval reports the alpha behind its EDF.
    assert [p["alpha"] for p in res.to_dict()["points"]] == res.alpha.tolist()
    ok = np.isfinite(res.ci_low)
    assert ok.sum() >= res.dev.size - 2
    assert np.all(res.ci_low[ok] < res.dev[ok]) and np.all(res.dev[ok] < res.ci_high[ok])


def test_confidence_none_skips_intervals(rate: np.ndarray) -> None:
    res = allan_deviation(rate, fs_hz=FS, confidence=None)
    assert isinstance(res, AllanResult)
    assert not res.has_ci and np.isnan(res.confidence)
    assert np.isnan(res.edf).all() and np.isnan(res.ci_low).all()
    assert set(res.alpha_method) == {"none"}
    d = res.to_dict()
    assert d["confidence"] is None
    assert all(p["alpha"] is None and p["edf"] is None for p in d["points"])
    assert res.to_frame()["alpha"].isna().all()


def test_series_with_datetime_index_supplies_fs_and_name(rate: np.ndarray) -> None:
    idx = pd.date_range("2024-01-01", periods=rate.size, freq="100ms")
    res = allan_deviation(pd.Series(rate, index=idx, name="fog_z"), confidence=None)
    assert isinstance(res, AllanResult)
    assert res.axis == "fog_z" and res.fs_hz == pytest.approx(FS, rel=1e-9)
    ref = allan_deviation(rate, fs_hz=FS, confidence=None)
    assert isinstance(ref, AllanResult)
    np.testing.assert_allclose(res.dev, ref.dev, rtol=1e-12)
    np.testing.assert_allclose(res.tau_s, ref.tau_s, rtol=1e-9)


def test_plain_series_needs_fs(rate: np.ndarray) -> None:
    res = allan_deviation(pd.Series(rate), fs_hz=FS, units="deg/s", confidence=None)
    assert isinstance(res, AllanResult) and res.units == "deg/s" and res.axis == "rate"
    with pytest.raises(DataError, match=r"no sample rate given; pass fs_hz="):
        allan_deviation(pd.Series(rate))


def test_dataframe_gives_one_curve_per_column(three_axes: np.ndarray) -> None:
    frame = pd.DataFrame(three_axes, columns=["gx", "gy", "gz"],
                         index=pd.timedelta_range(0, periods=4000, freq="100ms"))
    res = allan_deviation(frame, confidence=None)
    assert isinstance(res, AllanResultSet)
    assert res.axes == ("gx", "gy", "gz") and len(res) == 3
    for i, name in enumerate(res.axes):
        single = allan_deviation(three_axes[:, i], fs_hz=FS, confidence=None)
        assert isinstance(single, AllanResult)
        np.testing.assert_allclose(res[name].dev, single.dev, rtol=1e-12)
    one = allan_deviation(frame, axis="gy", confidence=None)
    assert isinstance(one, AllanResult) and one.axis == "gy"


def test_dataframe_time_and_temperature_columns_are_recognised(rate: np.ndarray) -> None:
    frame = pd.DataFrame({"time": np.arange(rate.size) / FS, "gyro_z": rate,
                          "temperature": np.linspace(20, 30, rate.size)})
    res = allan_deviation(frame, confidence=None)
    assert isinstance(res, AllanResultSet) and res.axes == ("gyro_z",)
    assert res[0].fs_hz == pytest.approx(FS)
    ref = allan_deviation(rate, fs_hz=FS, confidence=None)
    assert isinstance(ref, AllanResult)
    np.testing.assert_allclose(res[0].dev, ref.dev, rtol=1e-12)


def test_dataframe_with_time_column_and_unnamed_axes_raises() -> None:
    frame = pd.DataFrame({"time": np.arange(100) / FS, "a": np.arange(100) % 7,
                          "b": np.arange(100) % 5})
    with pytest.raises(DataError, match=r"column 'time' cannot be both a rate and a "
                                        r"time/temperature column"):
        allan_deviation(frame)


def test_multi_axis_run_and_axis_selection(three_axes: np.ndarray) -> None:
    run = _run(three_axes, ("x", "y", "z"))
    res = allan_deviation(run, taus="decade", confidence=None)
    assert isinstance(res, AllanResultSet)
    assert res.axes == ("x", "y", "z") and res.kind == "oadev" and res.units == "deg/s"
    assert [c.axis for c in res] == ["x", "y", "z"]
    assert res["y"] is res[1] and res[-1].axis == "z"
    # Each axis' white noise level (0.1, 0.2, 0.3) is its deviation at tau0.
    np.testing.assert_allclose([c.dev[0] for c in res], [0.1, 0.2, 0.3], rtol=0.05)
    by_name = allan_deviation(run, axis="z", taus="decade", confidence=None)
    by_index = allan_deviation(run, axis=2, taus="decade", confidence=None)
    assert isinstance(by_name, AllanResult) and isinstance(by_index, AllanResult)
    assert by_name.axis == by_index.axis == "z"
    np.testing.assert_array_equal(by_name.dev, res["z"].dev)


def test_single_axis_run_gives_one_curve(rate: np.ndarray) -> None:
    res = allan_deviation(_run(rate, ("fog",), units="rad/s"), confidence=None)
    assert isinstance(res, AllanResult) and res.axis == "fog" and res.units == "rad/s"


def test_fs_override_on_a_run(rate: np.ndarray) -> None:
    res = allan_deviation(_run(rate, ("fog",)), fs_hz=1.0, confidence=None)
    assert isinstance(res, AllanResult) and res.fs_hz == 1.0 and res.tau_s[0] == 1.0


def test_two_dimensional_array(three_axes: np.ndarray) -> None:
    res = allan_deviation(three_axes, fs_hz=FS, confidence=None)
    assert isinstance(res, AllanResultSet) and res.axes == ("rate_0", "rate_1", "rate_2")
    one = allan_deviation(three_axes, fs_hz=FS, axis=1, confidence=None)
    named = allan_deviation(three_axes, fs_hz=FS, axis="rate_1", confidence=None)
    last = allan_deviation(three_axes, fs_hz=FS, axis=-1, confidence=None)
    assert isinstance(one, AllanResult) and isinstance(named, AllanResult)
    assert isinstance(last, AllanResult) and last.axis == "rate_2"
    np.testing.assert_array_equal(one.dev, named.dev)
    np.testing.assert_array_equal(one.dev, res[1].dev)


def test_prepared_input_carries_fs_units_and_steps(rate: np.ndarray) -> None:
    prep = prepare(_run(rate, ("fog",)), decimate=2, stationarity=False)
    res = allan_deviation(prep, confidence=None)
    assert isinstance(res, AllanResult)
    assert res.fs_hz == FS / 2 and res.units == "deg/s" and res.n_samples == rate.size // 2
    assert res.axis == "fog"
    assert any(n.startswith("prepared: decimated by block averaging") for n in res.notes)
    np.testing.assert_allclose(res.dev, ESTIMATORS["oadev"](prep.x, fs_hz=FS / 2,
                                                            m=res.m).dev)


def test_dropped_taus_and_rounding_notes_reach_the_result(rate: np.ndarray) -> None:
    res = allan_deviation(rate, fs_hz=FS, taus=[0.01, 0.1, 1.04, 1e6], confidence=None)
    assert isinstance(res, AllanResult)
    assert res.m.tolist() == [1, 10]
    assert [d.tau_s for d in res.dropped] == [0.01, 1e6]
    assert all(isinstance(d, DroppedTau) for d in res.dropped)
    assert any("rounded to the nearest whole number" in n for n in res.notes)
    d = res.to_dict()
    assert [x["m"] for x in d["dropped"]] == [0, 10_000_000]
    text = res.summary()
    assert "dropped 2 tau(s):" in text and "below half a sample period" in text


@pytest.mark.parametrize("c", [-4.0, 1e-3])
def test_scaling_and_offset_invariance_through_the_api(rate: np.ndarray, c: float) -> None:
    base = allan_deviation(rate, fs_hz=FS, taus="decade")
    scaled = allan_deviation(c * rate + 123.0, fs_hz=FS, taus="decade")
    assert isinstance(base, AllanResult) and isinstance(scaled, AllanResult)
    np.testing.assert_allclose(scaled.dev, abs(c) * base.dev, rtol=1e-9)
    np.testing.assert_array_equal(scaled.alpha, base.alpha)
    ok = np.isfinite(base.ci_low)
    np.testing.assert_allclose(scaled.ci_low[ok], abs(c) * base.ci_low[ok], rtol=1e-9)


# ------------------------------------------------------------------------- output


def test_to_frame_and_to_dict_layout(rate: np.ndarray) -> None:
    res = allan_deviation(rate, fs_hz=FS, taus="decade")
    assert isinstance(res, AllanResult)
    frame = res.to_frame()
    assert list(frame.columns) == ["tau", "m", "n", "dev", "ci_low", "ci_high", "edf", "alpha"]
    assert len(frame) == len(res)
    np.testing.assert_array_equal(frame["dev"].to_numpy(), res.dev)
    d = res.to_dict()
    assert list(d) == ["kind", "units", "axis", "fs_hz", "n_samples", "confidence",
                       "bias_corrected", "points", "dropped", "notes"]
    assert list(d["points"][0]) == ["tau", "m", "n", "dev", "ci_low", "ci_high", "edf",
                                    "alpha", "alpha_method"]
    assert d["points"][1]["m"] == 2 and d["points"][1]["tau"] == 0.2
    text = json_dumps(d)
    assert json.loads(text)["points"][0]["dev"] == pytest.approx(res.dev[0])
    again = allan_deviation(rate, fs_hz=FS, taus="decade")
    assert isinstance(again, AllanResult)
    assert json_dumps(again.to_dict()) == text        # deterministic, byte for byte


def test_result_set_frame_dict_summary(three_axes: np.ndarray) -> None:
    res = allan_deviation(three_axes, fs_hz=FS, taus="decade", confidence=None)
    assert isinstance(res, AllanResultSet)
    frame = res.to_frame()
    assert list(frame.columns)[:2] == ["axis", "tau"]
    assert frame["axis"].tolist().count("rate_2") == len(res[2])
    d = res.to_dict()
    assert d["axes"] == ["rate_0", "rate_1", "rate_2"] and len(d["curves"]) == 3
    assert d["curves"][1]["axis"] == "rate_1"
    json.loads(json_dumps(d))
    assert res.summary().count("overlapping Allan deviation (oadev)") == 3


def test_summary_text(rate: np.ndarray) -> None:
    res = allan_deviation(rate, fs_hz=FS, kind="mdev", taus="decade")
    assert isinstance(res, AllanResult)
    text = res.summary()
    assert text.startswith("modified Allan deviation (mdev) of axis 'rate': 6000 samples at "
                           "10 Hz")
    assert "confidence intervals at 68.3 %" in text
    assert len(text.splitlines()) >= 3 + len(res)


def test_results_are_frozen_and_read_only(rate: np.ndarray) -> None:
    res = allan_deviation(rate, fs_hz=FS, confidence=None)
    assert isinstance(res, AllanResult)
    with pytest.raises(AttributeError, match="cannot assign"):
        res.kind = "adev"  # type: ignore[misc]
    with pytest.raises(ValueError, match="read-only"):
        res.dev[0] = 0.0
    rs = AllanResultSet(curves=(res,))
    with pytest.raises(AttributeError, match="cannot assign"):
        rs.curves = ()  # type: ignore[misc]


# ------------------------------------------------------------------------- bad input


def test_bad_arguments_raise(rate: np.ndarray) -> None:
    with pytest.raises(DataError, match=r"kind must be one of adev, oadev, mdev, hdev, ohdev, "
                                        r"totdev; got 'tdev'"):
        allan_deviation(rate, fs_hz=FS, kind="tdev")  # type: ignore[arg-type]
    with pytest.raises(DataError, match=r"confidence must be in \(0, 1\), got 1.5"):
        allan_deviation(rate, fs_hz=FS, confidence=1.5)
    with pytest.raises(DataError, match=r"units must be a rate unit \(deg/h, deg/s, rad/s, "
                                        r"arcsec/s\) or a specific-force unit \(m/s\^2, g, "
                                        r"mg, ug\), got 'furlong/s'"):
        allan_deviation(rate, fs_hz=FS, units="furlong/s")
    with pytest.raises(DataError, match=r"fs_hz must be a finite number > 0, got -1"):
        allan_deviation(rate, fs_hz=-1)
    with pytest.raises(DataError, match=r"taus must be one of octave, decade, dense, all; got "
                                        r"'hourly'"):
        allan_deviation(rate, fs_hz=FS, taus="hourly")


def test_array_without_fs_raises(rate: np.ndarray) -> None:
    with pytest.raises(DataError, match=r"fs_hz is required for array input"):
        allan_deviation(rate)


def test_bad_data_raises() -> None:
    with pytest.raises(DataError, match=r"x contains a non-finite value"):
        allan_deviation(np.array([1.0, np.inf, 2.0, 3.0]), fs_hz=1.0)
    with pytest.raises(DataError, match=r"x must be a 1-D or 2-D array, got shape \(2, 2, 2\)"):
        allan_deviation(np.ones((2, 2, 2)), fs_hz=1.0)
    with pytest.raises(InsufficientDataError, match=r"hdev needs more samples: 3 rate"):
        allan_deviation(np.array([1.0, 2.0, 4.0]), fs_hz=1.0, kind="hdev")
    with pytest.raises(InsufficientDataError, match=r"none of the requested taus can be "
                                                    r"computed"):
        allan_deviation(np.arange(20.0) % 3, fs_hz=1.0, taus=[100.0])


def test_bad_axis_raises(rate: np.ndarray, three_axes: np.ndarray) -> None:
    with pytest.raises(DataError, match=r"axis 'w' not found; axes are: x, y, z"):
        allan_deviation(_run(three_axes, ("x", "y", "z")), axis="w")
    with pytest.raises(DataError, match=r"axis index must be in \[0, 2\], got 3"):
        allan_deviation(_run(three_axes, ("x", "y", "z")), axis=3)
    with pytest.raises(DataError, match=r"axis index must be in \[0, 2\], got 5"):
        allan_deviation(three_axes, fs_hz=FS, axis=5)
    with pytest.raises(DataError, match=r"axis 'gyro' not found; axes are: rate_0, rate_1, "
                                        r"rate_2"):
        allan_deviation(three_axes, fs_hz=FS, axis="gyro")
    with pytest.raises(DataError, match=r"axis 1 not found; a 1-D series has one axis \(0 or 'rate'\)"):
        allan_deviation(rate, fs_hz=FS, axis=1)
    prep = prepare(rate, fs_hz=FS, stationarity=False)
    with pytest.raises(DataError, match=r"axis 'y' not found; the Prepared series is axis "
                                        r"'rate'"):
        allan_deviation(prep, axis="y")


def test_result_set_indexing_errors(three_axes: np.ndarray) -> None:
    res = allan_deviation(three_axes, fs_hz=FS, confidence=None)
    assert isinstance(res, AllanResultSet)
    with pytest.raises(DataError, match=r"axis 'q' not found; axes are: rate_0, rate_1, rate_2"):
        res["q"]
    with pytest.raises(DataError, match=r"axis index must be in \[0, 2\], got -4"):
        res[-4]
    with pytest.raises(DataError, match=r"index AllanResultSet by axis name or position, "
                                        r"got 1.0"):
        res[1.0]  # type: ignore[index]
    with pytest.raises(DataError, match=r"AllanResultSet needs at least one curve"):
        AllanResultSet(curves=())
    with pytest.raises(DataError, match=r"AllanResultSet axis names must be unique, got "
                                        r"\['rate_0', 'rate_0'\]"):
        AllanResultSet(curves=(res[0], res[0]))


def test_result_consistency_checks() -> None:
    base = dict(kind="oadev", units="deg/h", axis="x", fs_hz=1.0, n_samples=10,
                confidence=0.683, tau_s=[1.0, 2.0], m=[1, 2], n=[9, 7], dev=[1.0, 0.5],
                ci_low=[0.9, 0.4], ci_high=[1.1, 0.6], edf=[9.0, 5.0], alpha=[0, 0])
    ok = AllanResult(**base, alpha_method=("acf", "acf"))  # type: ignore[arg-type]
    assert ok.to_dict()["points"][1]["alpha"] == 0
    with pytest.raises(DataError, match=r"AllanResult.edf has 1 values; dev has 2"):
        AllanResult(**{**base, "edf": [1.0]})  # type: ignore[arg-type]
    with pytest.raises(DataError, match=r"AllanResult.alpha_method has 1 values; dev has 2"):
        AllanResult(**base, alpha_method=("acf",))  # type: ignore[arg-type]


# --------------------------------------------------------------------------- totdev bias


def test_totdev_bias_correction_reproduces_stable32_ocxo_octave_file() -> None:
    """End to end: fogts' own noise identification plus the bias correction gives the
    Stable32 OCXO TOTDEV octave file (f / 1e7 with Stable32's phase rounding, see
    tests/allan/test_estimators.py) wherever fogts and Stable32 identify the same noise."""
    from tests.conftest import shared_path, stable32, stable32_rounded_input

    freq = np.loadtxt(shared_path("stable32", "ocxo", "ocxo_frequency.txt"), comments="#") / 1e7
    ref = stable32(shared_path("stable32", "ocxo", "totdev_octave.txt"))
    y = stable32_rounded_input(freq)
    res = allan_deviation(y, fs_hz=1.0, kind="totdev", taus=ref["tau"], bias_correction=True)
    plain = allan_deviation(y, fs_hz=1.0, kind="totdev", taus=ref["tau"])
    assert isinstance(res, AllanResult) and isinstance(plain, AllanResult)
    assert res.bias_corrected and not plain.bias_corrected
    assert any("Howe 1999" in note for note in res.notes)
    same = res.alpha == ref["alpha"]
    # measured: 11 of 14 alphas agree; at m = 2048..8192 (8 to 2 terms) fogts' B1 ratio
    # says random-walk FM where Stable32 says white FM, and the correction follows it
    assert np.count_nonzero(same) >= 11
    np.testing.assert_allclose(res.dev[same], ref["dev"][same], rtol=1e-4, atol=0)
    np.testing.assert_allclose(res.ci_low[same], ref["lo"][same], rtol=1e-3, atol=0)
    np.testing.assert_allclose(res.ci_high[same], ref["hi"][same], rtol=1e-3, atol=0)
    assert np.max(np.abs(plain.dev / ref["dev"] - 1)) > 1e-2
    np.testing.assert_allclose(res.dev / res.ci_low, plain.dev / plain.ci_low, rtol=1e-12)


def test_totdev_bias_matches_monte_carlo_on_a_rate_random_walk() -> None:
    """Howe's bias E[TOTVAR]/AVAR = 1 - 0.75 tau/T for random-walk FM, checked with fogts'
    kernels: 400 records of 2048 samples (seed 5); the overlapping Allan variance of the
    same records is the unbiased reference.  Tolerance: 3 Monte-Carlo standard errors."""
    from fogts.allan.bias import totdev_bias
    from fogts.allan.estimators import oadev, totdev

    rng = np.random.default_rng(5)
    m = np.array([128, 256, 512])
    walks = [np.cumsum(rng.standard_normal(2048)) for _ in range(400)]
    tot = np.array([totdev(y, fs_hz=1.0, m=m).dev ** 2 for y in walks])
    ovar = np.array([oadev(y, fs_hz=1.0, m=m).dev ** 2 for y in walks])
    ratio = tot.mean(axis=0) / ovar.mean(axis=0)
    expected = totdev_bias(-2, m, 2049)          # 0.953, 0.906, 0.813
    se = tot.std(axis=0) / np.sqrt(len(tot)) / ovar.mean(axis=0)
    assert np.all(np.abs(ratio - expected) < 3 * se), (ratio, expected, se)
    assert ratio[-1] < 0.9                           # the bias is real at tau = T/4


def test_bias_correction_argument_errors(rate: np.ndarray) -> None:
    with pytest.raises(DataError, match="bias_correction applies to kind='totdev' only.*'oadev'"):
        allan_deviation(rate, fs_hz=FS, bias_correction=True)
    with pytest.raises(DataError, match="bias_correction needs the per-tau noise identification"):
        allan_deviation(rate, fs_hz=FS, kind="totdev", confidence=None, bias_correction=True)
    with pytest.raises(DataError, match="bias_correction must be True or False, got 'yes'"):
        allan_deviation(rate, fs_hz=FS, kind="totdev", bias_correction="yes")  # type: ignore[arg-type]


def test_read_and_allan_deviation_memory_on_a_long_record(tmp_path: Path) -> None:
    """n = 2e6 read from a .npy (16 MB), then the default oadev with intervals: the arrays
    that must exist are the rate (1x), the phase of n + 1 points (1x) and the phase
    decimated by m = 8 ... 64 that the noise identification keeps (n/8 + ... + n/64,
    0.23x), plus cache-sized chunk buffers: about 2.3x, bound 2.5x.  (A time array formed
    by the reader for the regular time base would add 1x: 3.3x.)"""
    import gc
    import tracemalloc
    import warnings

    y = np.random.default_rng(3).standard_normal(2_000_000)
    path = tmp_path / "w.npy"
    np.save(path, y)
    size = y.nbytes
    del y
    allan_deviation(np.random.default_rng(4).standard_normal(5000), fs_hz=100.0)  # imports
    gc.collect()
    tracemalloc.start()
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            run = read_run(path, fs_hz=100.0, units="deg/h")
            kept = tracemalloc.get_traced_memory()[0]
            res = allan_deviation(run, axis=0)
        peak = tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()
    assert isinstance(res, AllanResult) and res.n_samples == 2_000_000
    assert kept < 1.05 * size, kept / size   # the rate only: no time array
    assert peak < 2.5 * size, peak / size
