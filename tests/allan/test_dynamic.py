"""Tests of the dynamic Allan deviation (fogts.allan.dynamic) and its plot.

References: each window's deviation must equal allantools' oadev of that window's samples
(an independent implementation); the O(n)-per-tau running-sum path must equal the
per-window estimator kernels to 1e-9; simulated records with known truth (stationary
white noise, and white noise whose level doubles half-way) with fixed seeds.
"""

from __future__ import annotations

import json

import allantools
import numpy as np
import pandas as pd
import pytest
from matplotlib.figure import Figure

from fogts.allan.dynamic import (
    DynamicAllanResult,
    DynamicAllanResultSet,
    dynamic_allan,
)
from fogts.errors import DataError, InsufficientDataError
from fogts.report.plots import plot_dynamic_allan
from fogts.report.text import json_dumps
from fogts.simulate.gyro import simulate_gyro

FS = 10.0


def _white(n: int, seed: int, *, sd: float = 1.0) -> np.ndarray:
    return np.random.default_rng(seed).normal(scale=sd, size=n)


def _step(n: int = 36_000, seed: int = 3) -> np.ndarray:
    y = _white(n, seed)
    y[n // 2:] *= 2.0  # the white-noise level doubles at half time (1800 s at 10 Hz)
    return y


@pytest.mark.parametrize("kind", ["oadev", "mdev", "ohdev"])
def test_cumsum_path_equals_per_window_kernels(kind: str) -> None:
    y = _white(20_000, 1) + 12.3  # a large bias must not cost precision
    fast = dynamic_allan(y, fs_hz=FS, window_s=201, step_s=37.3, kind=kind, method="cumsum")
    slow = dynamic_allan(y, fs_hz=FS, window_s=201, step_s=37.3, kind=kind, method="kernel")
    assert isinstance(fast, DynamicAllanResult) and isinstance(slow, DynamicAllanResult)
    assert fast.method == "cumsum" and slow.method == "kernel"
    np.testing.assert_array_equal(fast.m, slow.m)
    np.testing.assert_allclose(fast.dev, slow.dev, rtol=1e-9)


def test_windows_equal_allantools_on_each_window() -> None:
    y = _white(12_000, 2)
    res = dynamic_allan(y, fs_hz=FS, window_s=201, step_s=100, taus="decade")
    assert isinstance(res, DynamicAllanResult)
    assert res.window_n == 2010 and res.step_n == 1000 and res.window_s == 201.0
    for i in (0, 4, res.shape[0] - 1):
        s = round(float(res.start_s[i]) * FS)
        taus, dev, _, ns = allantools.oadev(y[s:s + 2010], rate=FS, data_type="freq",
                                            taus=res.tau_s)
        np.testing.assert_allclose(taus, res.tau_s)
        np.testing.assert_allclose(res.dev[i], dev, rtol=1e-9)
        np.testing.assert_array_equal(res.n, ns)
    # window centres in seconds from the start
    np.testing.assert_allclose(res.times_s[:3], [100.5, 200.5, 300.5])


@pytest.mark.parametrize("kind", ["adev", "hdev", "totdev"])
def test_kernel_path_serves_every_kind(kind: str) -> None:
    y = _white(6000, 4)
    res = dynamic_allan(y, fs_hz=FS, window_s=100, step_s=50, kind=kind)
    assert isinstance(res, DynamicAllanResult) and res.method == "kernel"
    fn = {"adev": allantools.adev, "hdev": allantools.hdev, "totdev": allantools.totdev}[kind]
    _, dev, _, _ = fn(y[500:1500], rate=FS, data_type="freq", taus=res.tau_s)
    np.testing.assert_allclose(res.dev[1], dev, rtol=1e-9)


def test_stationary_white_noise_is_flat_within_cis() -> None:
    res = dynamic_allan(_white(36_000, 5), fs_hz=FS, window_s=200, step_s=20)
    assert isinstance(res, DynamicAllanResult)
    stat = res.nonstationarity
    assert stat.stationary and stat.change_time_s is None and stat.change_ratio is None
    assert 0.3 < stat.score < 2.0 and stat.pvalue > 0.01
    # white noise: alpha = 0 at every tau, and dev = 1/sqrt(tau*fs) (unit-variance samples)
    assert set(res.alpha.tolist()) == {0}
    covered = (res.ci_low <= res.reference_dev) & (res.reference_dev <= res.ci_high)
    # 68.3 % intervals of overlapping windows: between 50 % and 85 % cover the pooled value
    assert np.all((covered.mean(axis=0) > 0.5) & (covered.mean(axis=0) < 0.85))
    # pooled over ~n/window independent windows: 4 sigma of a chi-squared deviation
    tol = 4 / np.sqrt(2 * res.edf * stat.n_independent)
    assert np.all(np.abs(res.reference_dev * np.sqrt(res.tau_s * FS) - 1) < tol)
    assert res.outside.mean() < 0.01  # Bonferroni-level flags are rare


def test_a_step_longer_than_the_window_counts_only_the_windows_computed() -> None:
    # 3600 s at 10 Hz, windows of 30 s every 100 s: 36 windows, not the 120 the record
    # would hold side by side; the score test and the flags count the 36 (audit2: davar
    # --window 0.05 printed "500 windows ... 200000 independent windows")
    res = dynamic_allan(_white(36_000, 11), fs_hz=FS, window_s=30, step_s=100)
    assert res.dev.shape[0] == 36
    assert res.nonstationarity.n_independent == 36
    assert "36 independent windows" in res.nonstationarity.summary()
    overlapping = dynamic_allan(_white(36_000, 11), fs_hz=FS, window_s=100, step_s=25)
    assert overlapping.nonstationarity.n_independent == 36  # n // window, as before


def test_level_doubling_half_way_is_found_at_the_right_time() -> None:
    res = dynamic_allan(_step(), fs_hz=FS, window_s=200, step_s=20)
    assert isinstance(res, DynamicAllanResult)
    stat = res.nonstationarity
    assert not stat.stationary and stat.pvalue < 1e-6 and stat.score > 50
    assert stat.change_time_s is not None and abs(stat.change_time_s - 1800.0) <= res.step_s
    assert stat.change_ratio == pytest.approx(2.0, rel=0.05)
    # the surface: short-tau deviation ~1/sqrt(10) before, twice that after
    before = res.times_s + res.window_s / 2 < 1800
    after = res.times_s - res.window_s / 2 > 1800
    np.testing.assert_allclose(np.median(res.dev[before, 0]), 1 / np.sqrt(1.0), rtol=0.05)
    np.testing.assert_allclose(np.median(res.dev[after, 0]), 2 / np.sqrt(1.0), rtol=0.05)
    # every window entirely on one side of the step is flagged at the shortest tau
    assert np.all(res.outside[before | after, 0])
    assert len(stat.flagged_windows) >= int((before | after).sum())
    assert "NOT stationary" in res.summary() and "most likely change at t = 1" in stat.summary()


def test_series_run_and_multi_axis_inputs() -> None:
    y = _white(6000, 6)
    index = pd.timedelta_range(0, periods=6000, freq="100ms")
    from_series = dynamic_allan(pd.Series(y, index=index), window_s=100, step_s=50)
    from_array = dynamic_allan(y, fs_hz=FS, window_s=100, step_s=50)
    assert isinstance(from_series, DynamicAllanResult)
    assert isinstance(from_array, DynamicAllanResult)
    np.testing.assert_allclose(from_series.dev, from_array.dev)
    run = simulate_gyro({"N": 0.01}, fs_hz=FS, duration_s=600, rng=1, n_axes=3)
    res = dynamic_allan(run, window_s=100, step_s=50)
    assert isinstance(res, DynamicAllanResultSet) and res.axes == ("rate_x", "rate_y", "rate_z")
    assert res["rate_y"] is res[1] and len(res) == 3 and len(list(res)) == 3
    frame = res.to_frame()
    assert list(frame.columns[:2]) == ["axis", "time"] and len(frame) == 3 * np.prod(
        res[0].shape)
    assert set(res.to_dict()) == {"kind", "window_s", "step_s", "axes", "curves"}
    one = dynamic_allan(run, window_s=100, step_s=50, axis="rate_z")
    assert isinstance(one, DynamicAllanResult) and one.axis == "rate_z"
    assert "rate_x" in res.summary()
    assert run.units == res[0].units == "deg/h"


def test_result_exports_and_json_contract() -> None:
    res = dynamic_allan(_step(12_000), fs_hz=FS, window_s=200, step_s=100)
    assert isinstance(res, DynamicAllanResult)
    d = res.to_dict()
    assert {"kind", "window_s", "step_s", "taus", "times", "dev", "nonstationarity"} <= set(d)
    nw, nt = res.shape
    assert len(d["times"]) == nw and len(d["dev"]) == nw and len(d["dev"][0]) == nt
    assert d["dev"][3][2] == res.dev[3, 2]
    assert {"score", "pvalue", "stationary", "change_time", "flagged_windows"} <= set(
        d["nonstationarity"])
    text = json_dumps(d)
    assert json.loads(text)["taus"] == res.tau_s.tolist()
    assert json_dumps(dynamic_allan(_step(12_000), fs_hz=FS, window_s=200,
                                    step_s=100).to_dict()) == text  # deterministic
    frame = res.to_frame()
    assert list(frame.columns) == ["time", "tau", "m", "dev", "ci_low", "ci_high", "outside"]
    assert len(frame) == nw * nt and frame["dev"].iloc[nt + 1] == res.dev[1, 1]
    np.testing.assert_allclose(res.avar, res.dev**2)


def test_dropped_taus_are_reported() -> None:
    res = dynamic_allan(_white(6000, 7), fs_hz=FS, window_s=100, step_s=50,
                        taus=[0.1, 1.0, 90.0])
    assert isinstance(res, DynamicAllanResult)
    assert res.tau_s.tolist() == [0.1, 1.0] and [d.tau_s for d in res.dropped] == [90.0]
    assert "dropped 1 tau" in res.summary()


@pytest.mark.parametrize("kwargs, exc, match", [
    ({"kind": "theo1"}, DataError, "kind must be one of"),
    ({"method": "fast"}, DataError, "method must be one of auto, cumsum, kernel"),
    ({"kind": "adev", "method": "cumsum"}, DataError, "method='cumsum' serves kinds"),
    ({"window_s": -5}, DataError, "window_s must be a finite number > 0"),
    ({"step_s": 0}, DataError, "step_s must be a finite number > 0"),
    ({"window_s": 0.2}, DataError, r"window_s=0.2 s is 2 sample\(s\) at 10 Hz; a window needs "
                                   r"at least 256 samples \(25.6 s at 10 Hz\)"),
    ({"window_s": 25.5}, DataError, r"is 255 sample\(s\) at 10 Hz; a window needs at least 256"),
    ({"window_s": 1000}, InsufficientDataError, "longer than the record"),
    ({"window_s": 550, "step_s": 100}, InsufficientDataError, "only 1 window"),
    ({"confidence": 1.5}, DataError, "confidence must be in"),
    ({"level": 0}, DataError, "level must be in"),
])
def test_errors(kwargs: dict, exc: type, match: str) -> None:
    args = {"fs_hz": FS, "window_s": 100.0, "step_s": 50.0} | kwargs
    with pytest.raises(exc, match=match):
        dynamic_allan(_white(6000, 8), **args)


def test_result_set_errors() -> None:
    run = simulate_gyro({"N": 0.01}, fs_hz=FS, duration_s=300, rng=1, n_axes=2)
    res = dynamic_allan(run, window_s=100, step_s=50)
    assert isinstance(res, DynamicAllanResultSet)
    with pytest.raises(DataError, match="axis 'q' not found"):
        res["q"]
    with pytest.raises(DataError, match="axis index must be in"):
        res[5]
    with pytest.raises(DataError, match="index DynamicAllanResultSet by axis name"):
        res[1.5]  # type: ignore[index]
    with pytest.raises(DataError, match="DynamicAllanResultSet needs at least one curve"):
        DynamicAllanResultSet(curves=())


def test_plot_heat_map(tmp_path) -> None:  # type: ignore[no-untyped-def]
    res = dynamic_allan(_step(), fs_hz=FS, window_s=200, step_s=20)
    fig = plot_dynamic_allan(res)
    assert isinstance(fig, Figure) and len(fig.axes) == 3  # strip, heat map, colour bar
    heat = fig.axes[1]
    assert heat.get_yscale() == "log" and heat.get_xlabel().startswith("window centre time")
    path = tmp_path / "davar.png"
    fig.savefig(path)
    assert path.stat().st_size > 10_000
    run = simulate_gyro({"N": 0.01}, fs_hz=FS, duration_s=600, rng=1, n_axes=2)
    fig2 = plot_dynamic_allan(dynamic_allan(run, window_s=100, step_s=50))
    assert len(fig2.axes) == 5  # two strips, two maps, one shared colour bar
