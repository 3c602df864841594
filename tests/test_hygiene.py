"""fogts.preprocess.hygiene: glitches, gaps and the DataQuality record (issue 13, item 4).

Known truth: white Gaussian noise with fixed seeds (nothing may be flagged), the same with
injected spikes, bursts and steps (each found at its time), and the real ADIS16405 run 4
glitch near t = 4046 s (README of ../shared/data)."""

from __future__ import annotations

import numpy as np
import pandas as pd
import pytest

from fogts.errors import DataError
from fogts.io.reader import read_run
from fogts.preprocess.hygiene import (
    GLITCH_SIGMAS,
    assess_run,
    detect_glitches,
    find_gaps,
)
from tests.conftest import shared_path


@pytest.mark.parametrize("seed", [1, 2, 3])
def test_white_noise_flags_nothing(seed: int) -> None:
    x = np.random.default_rng(seed).standard_normal(2_000_000)
    rep = detect_glitches(x, fs_hz=100.0)
    assert rep.n_events == 0 and rep.n_flagged == 0
    assert rep.scale == "MAD"
    # the robust sigma of unit white noise is 1 within its sampling error (~0.1 % here)
    assert rep.sigma_rate == pytest.approx(1.0, rel=5e-3)
    assert rep.sigma_diff == pytest.approx(np.sqrt(2.0), rel=5e-3)


def test_drift_and_random_walk_are_not_glitches() -> None:
    rng = np.random.default_rng(900107)
    n = 1_000_000
    x = rng.standard_normal(n) + 0.05 * np.cumsum(rng.standard_normal(n)) + np.linspace(0, 80, n)
    assert detect_glitches(x, fs_hz=100.0).n_events == 0


def test_spike_burst_and_step_are_found_at_their_times() -> None:
    x = np.random.default_rng(8).standard_normal(1_000_000)
    x[5000] -= 60.0                # one-sample spike at t = 50 s
    x[20_000:20_020] += 48.0       # a 20-sample burst at t = 200 s
    x[700_000:] += 30.0            # a jump to a new level at t = 7000 s
    rep = detect_glitches(x, fs_hz=100.0, units="deg/h", axis="x")
    assert rep.n_events == 3
    spike, burst, step = rep.events
    assert (spike.row, spike.time_s, spike.n_samples) == (5000, 50.0, 1)
    # the level shift widens the MAD of the rate (sigma ~1.8 here): sigmas are relative to it
    assert spike.value < -50 and spike.sigmas < -25
    assert burst.n_samples == 20 and 200.0 <= burst.time_s < 200.2
    assert step.n_samples == 300_000 and step.time_s >= 7000.0
    text = rep.summary()
    assert text.startswith("3 glitches (300021 sample(s)) beyond 7 robust sigmas: ")
    assert "t = 50 s: -59.97 deg/h (-33 sigma, 1 sample)" in text and "level shift lasting 3000 s" in text
    assert list(rep.to_frame().columns) == ["row", "time_s", "n_samples", "value", "sigmas",
                                            "duration_s"]


def test_quantised_data_never_give_a_zero_sigma() -> None:
    rng = np.random.default_rng(3)
    x = np.round(0.3 * rng.standard_normal(100_000) / 0.5) * 0.5  # mostly one grid value
    x[500] = 20.0
    rep = detect_glitches(x, fs_hz=10.0)
    assert rep.sigma_rate > 0 and rep.sigma_diff > 0
    assert rep.scale != "MAD"
    assert [e.row for e in rep.events] == [500]


def test_adis16405_run4_glitch_is_named_with_its_time() -> None:
    data = np.load(shared_path("imu", "adis_16405_imu4_gyro.npz"))
    gyro = data["gyro_deg_s"]
    rep = detect_glitches(gyro[:, 0], fs_hz=float(data["fs_hz"]), units="deg/s",
                          axis="Gyro. X")
    worst = max(rep.events, key=lambda e: abs(e.sigmas))
    assert worst.time_s == pytest.approx(4046.07, abs=0.01)  # README: near t = 4046 s
    assert worst.value == pytest.approx(-17.0)  # on the sensor's 0.05 deg/s grid
    assert rep.summary().split(": ", 1)[1].startswith("t = 4046.07 s: -17 deg/s")
    # the other five runs: no glitch on any axis (a real-data false-alarm check)
    for k in (1, 2, 3, 5, 6):
        other = np.load(shared_path("imu", f"adis_16405_imu{k}_gyro.npz"))["gyro_deg_s"]
        assert all(detect_glitches(other[:, a], fs_hz=100.0).n_events == 0 for a in range(3))


def test_detect_glitches_errors() -> None:
    with pytest.raises(DataError, match=r"x must be one axis of at least 3 samples, got "
                                        r"shape \(2,\)"):
        detect_glitches(np.zeros(2), fs_hz=1.0)
    with pytest.raises(DataError, match="threshold must be a finite number > 0, got -1.0"):
        detect_glitches(np.arange(10.0), fs_hz=1.0, threshold=-1.0)
    x = np.random.default_rng(0).standard_normal(1000)
    x[10] = 100.0
    with pytest.raises(DataError, match="needs time_s or fs_hz"):
        detect_glitches(x)


def test_find_gaps_lists_gaps_and_segments() -> None:
    t = np.r_[np.arange(100), np.arange(150, 200), np.arange(205, 400)] / 10.0
    rep = find_gaps(t, fs_hz=10.0)
    assert rep.n_gaps == 2
    assert [(g.row, g.time_s) for g in rep.gaps] == [(99, 9.9), (149, 19.9)]
    assert rep.gaps[0].length_s == pytest.approx(5.1)
    assert rep.missing_s == pytest.approx(5.0 + 0.5)  # 51 - 1 and 6 - 1 steps of 0.1 s
    assert rep.segments == ((0, 100), (100, 150), (150, 345))
    assert rep.longest_segment() == (150, 345)
    assert "2 gap(s) in the time base (5.5 s missing; first at t = 9.9 s" in rep.summary()


def _gappy_frame() -> pd.DataFrame:
    t = np.r_[np.arange(3000), np.arange(3100, 9000)] / 100.0
    rate = np.random.default_rng(11).standard_normal(t.size)
    return pd.DataFrame({"time": t, "rate_deg_h": rate})


def test_assess_run_gap_policies() -> None:
    run = read_run(_gappy_frame())
    kept, q = assess_run(run)
    assert kept is run and q.gaps.n_gaps == 1
    assert any("analysed as if the samples were regular" in w for w in q.warnings())
    split, q = assess_run(run, gaps="split")
    assert split.n == 5900 and q.segment == (3000, 8900)
    assert split.time[0] == 0.0 and split.sampling is not None and split.sampling.n_gaps == 0
    assert "--gaps split: analysing the longest regular segment, rows 3000..8899" in \
        q.warnings()[0]
    _, q = assess_run(run, gaps="ignore")
    assert q.warnings() == [] and q.to_dict()["gaps"]["n_gaps"] == 1
    with pytest.raises(DataError, match=r"1 gap\(s\) in the time base .*gaps='error' "
                                        r"\(CLI --gaps error\) refuses it"):
        assess_run(run, gaps="error")
    with pytest.raises(DataError, match="gaps must be one of warn, error, split, ignore"):
        assess_run(run, gaps="skip")  # type: ignore[arg-type]


def test_assess_run_units_and_dict() -> None:
    run = read_run(np.random.default_rng(0).standard_normal(500), fs_hz=10.0)
    _, q = assess_run(run)
    assert q.units_source == "assumed"
    assert q.warnings()[0].startswith("no unit in the rate column(s) 'rate'; assuming deg/h")
    d = q.to_dict()
    assert d["units_source"] == "assumed" and d["glitches"][0]["n_events"] == 0
    assert q.glitch_count("rate") == 0 and q.glitch_count("absent") == 0
    run = read_run(np.random.default_rng(0).standard_normal(500), fs_hz=10.0, units="deg/s")
    _, q = assess_run(run)
    assert q.warnings() == [] and q.summary() == "no data-quality issue found"
    assert q.to_frame().empty


def test_default_threshold_is_documented_value() -> None:
    assert GLITCH_SIGMAS == 7.0
