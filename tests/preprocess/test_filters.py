"""Tests for fogts.preprocess.filters (zero-phase IIR low-pass and moving average)."""

from __future__ import annotations

import numpy as np
import pandas as pd
import pytest
from scipy import signal

from fogts.errors import DataError, InsufficientDataError
from fogts.preprocess.filters import lowpass, moving_average

FS = 100.0


def _white(n: int = 20_000, seed: int = 0) -> np.ndarray:
    return np.random.default_rng(seed).normal(size=n)


@pytest.mark.parametrize("order", [1, 2, 4, 8])
@pytest.mark.parametrize("cutoff", [0.5, 5.0, 20.0, 45.0])
def test_butterworth_zero_phase_is_minus_3db_at_cutoff(order: int, cutoff: float) -> None:
    r = lowpass(_white(2000), fs_hz=FS, cutoff_hz=cutoff, order=order)
    # the forward-backward amplitude is |H|^2 of the stored single-pass filter (scipy)
    _, h = signal.sosfreqz(r.sos, worN=[cutoff], fs=FS)
    gain_db = 20 * np.log10(abs(h[0]) ** 2)
    assert gain_db == pytest.approx(-3.0103, abs=0.1)  # -3 dB +- 0.1 dB
    assert r.frequency_response(np.array([cutoff]))[0] == pytest.approx(abs(h[0]) ** 2)


def test_filtered_white_noise_variance_matches_response() -> None:
    # Var(out)/Var(in) = (2/fs) * integral_0^{fs/2} |H_ff(f)|^2 df for white input.
    x = _white(200_000, 1)
    r = lowpass(x, fs_hz=FS, cutoff_hz=10.0, order=4)
    f = np.linspace(0, FS / 2, 100_001)
    expected = np.trapezoid(r.frequency_response(f) ** 2, f) * 2 / FS
    assert np.var(r.filtered[1000:-1000]) / np.var(x) == pytest.approx(expected, rel=0.02)


def test_zero_phase_no_lag() -> None:
    t = np.arange(5000) / FS
    x = np.sin(2 * np.pi * 0.5 * t)
    r = lowpass(x, fs_hz=FS, cutoff_hz=10.0)
    lag = np.argmax(np.correlate(r.filtered, x, "full")) - (x.size - 1)
    assert lag == 0
    np.testing.assert_allclose(r.filtered[500:-500], x[500:-500], atol=1e-3)


@pytest.mark.parametrize("design", ["cheby1", "ellip"])
def test_other_designs_measure_their_cutoff(design: str) -> None:
    r = lowpass(_white(3000), fs_hz=FS, cutoff_hz=5.0, order=4, design=design)  # type: ignore[arg-type]
    assert 4.0 < r.cutoff_hz < 6.0
    assert 20 * np.log10(r.frequency_response(np.array([r.cutoff_hz]))[0]) == pytest.approx(
        -3.0103, abs=0.05)


def test_series_index_kept() -> None:
    idx = pd.date_range("2026-01-01", periods=500, freq="10ms")
    s = pd.Series(_white(500), index=idx)
    r = lowpass(s, fs_hz=FS, cutoff_hz=5.0)
    assert r.series().index.equals(idx)
    assert r.to_frame().index.equals(idx)
    assert r.to_dict()["method"] == "iir" and "1/cutoff" in r.summary()


def test_moving_average_matches_pandas_rolling_in_interior() -> None:
    x = _white(1000, 3)
    r = moving_average(x, fs_hz=FS, window_s=0.1)  # 10 samples -> 11 (odd, centred)
    assert r.params["window"] == 11
    ref = pd.Series(x).rolling(11, center=True).mean().to_numpy()
    np.testing.assert_allclose(r.filtered[5:-5], ref[5:-5], rtol=1e-12, atol=1e-12)
    # the -3 dB point of an 11-tap boxcar, from scipy.signal.freqz of the taps
    from scipy.optimize import brentq

    def gain(f: float) -> float:
        return float(abs(signal.freqz(np.ones(11) / 11, worN=[f], fs=FS)[1][0]) - np.sqrt(0.5))

    assert r.cutoff_hz == pytest.approx(brentq(gain, 0.1, FS / 11), rel=1e-3)


@pytest.mark.parametrize(("kwargs", "match"), [
    ({"cutoff_hz": 50.0}, r"cutoff_hz must be below the Nyquist frequency 50 Hz "
                          r"\(half the sample rate\), got 50.0"),
    ({"cutoff_hz": 80.0}, "cutoff_hz must be below the Nyquist frequency 50 Hz"),
    ({"cutoff_hz": 0.0}, "cutoff_hz must be a finite number > 0, got 0.0"),
    ({"cutoff_hz": 5.0, "order": 0}, "order must be >= 1, got 0"),
    ({"cutoff_hz": 5.0, "order": -2}, "order must be >= 1, got -2"),
    ({"cutoff_hz": 5.0, "design": "bessel"}, "design must be one of butter, cheby1, ellip; got 'bessel'"),
    ({"cutoff_hz": 5.0, "fs_hz": -1.0}, "fs_hz must be a finite number > 0, got -1.0"),
])
def test_lowpass_bad_arguments(kwargs: dict[str, object], match: str) -> None:
    kw: dict[str, object] = {"fs_hz": FS, **kwargs}
    with pytest.raises(DataError, match=match):
        lowpass(_white(1000), **kw)  # type: ignore[arg-type]


def test_lowpass_bad_data() -> None:
    with pytest.raises(DataError, match="x needs more than 27 samples"):
        lowpass(_white(20), fs_hz=FS, cutoff_hz=5.0, order=8)
    with pytest.raises(InsufficientDataError, match="x needs at least 2 samples"):
        lowpass(np.ones(1), fs_hz=FS, cutoff_hz=5.0)
    with pytest.raises(DataError, match="non-finite value"):
        lowpass(np.r_[_white(100), np.inf], fs_hz=FS, cutoff_hz=5.0)


def test_moving_average_bad_arguments() -> None:
    with pytest.raises(DataError, match="shorter than 3 samples"):
        moving_average(_white(100), fs_hz=FS, window_s=0.01)
    with pytest.raises(DataError, match="is longer than the record"):
        moving_average(_white(100), fs_hz=FS, window_s=5.0)
    with pytest.raises(DataError, match="window_s must be a finite number > 0"):
        moving_average(_white(100), fs_hz=FS, window_s=-1)
