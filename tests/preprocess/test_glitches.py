"""fogts.preprocess.glitches.

Known truth: white Gaussian noise with fixed seeds (nothing may be flagged), the same with
injected spikes, bursts and steps (each found at its time), and the real ADIS16405 run 4
glitch near t = 4046 s (README of ../shared/data)."""

from __future__ import annotations

import numpy as np
import pytest

from fogts.errors import DataError
from fogts.preprocess.glitches import GLITCH_SIGMAS, detect_glitches
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


def test_quantized_data_never_give_a_zero_sigma() -> None:
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


def test_default_threshold_is_documented_value() -> None:
    assert GLITCH_SIGMAS == 7.0


@pytest.mark.parametrize("n", [3, 1000, 2_000_001, 8_000_000, 8_000_001, 24_000_011])
def test_thinned_steps_are_those_of_the_thinned_difference(n: int) -> None:
    """The difference's scale is taken from steps read straight from the record: the same
    values as thinning, differencing and thinning again (bit for bit, asserted exactly:
    the same subtractions of the same samples)."""
    from fogts.preprocess import glitches

    x = np.random.default_rng(n).standard_normal(n)
    thinned = glitches._strided(x, 4 * glitches.SCALE_SAMPLES)
    want = glitches._strided(np.diff(thinned))
    got = glitches._strided_steps(x)
    assert got.shape == want.shape and np.array_equal(got, want)


def test_far_rows_at_the_threshold_and_across_blocks(monkeypatch: pytest.MonkeyPatch) -> None:
    """Blocks whose extremes stay within the limit are skipped; the rows found are those of
    ``|x - med| > limit`` over every sample, also for values at the limit itself and for
    NaN, in any block."""
    from fogts.preprocess import glitches

    monkeypatch.setattr(glitches, "CHUNK", 1000)
    x = np.random.default_rng(5).standard_normal(10_500)
    med, limit = 0.25, 5.0
    x[[10, 999, 1000, 4321, 10_499]] = [med + limit, med - 6.0, 9.0, -20.0, 30.0]
    x[7000] = np.nextafter(med + limit, np.inf)
    x[8000] = np.nan
    far = np.flatnonzero(np.abs(x - med) > limit)
    want = far[glitches._steps_beyond(x, far, 3.0)]
    got = glitches._jump_rows(x, med, limit, 3.0)
    np.testing.assert_array_equal(got, want)
    assert 10 not in got and {999, 1000, 4321, 10_499} <= set(got.tolist())
