"""EMD trend separation: own sifting checked on signals with known parts."""

from __future__ import annotations

import numpy as np
import pandas as pd
import pytest
from scipy.signal import lfilter

from fogts.errors import DataError, InsufficientDataError
from fogts.startup.emd import emd, energy_k, separate_trend


def _trend_plus_arma(n: int = 3600, seed: int = 4) -> tuple[np.ndarray, np.ndarray]:
    """Exponential warm-up + linear trend (deg/h) plus ARMA(1,1) noise, 1 Hz."""
    rng = np.random.default_rng(seed)
    t = np.arange(n, dtype=float)
    trend = 3.0 * (1.0 - np.exp(-t / (n / 6))) + 0.5 * t / n
    noise = 0.3 * lfilter([1.0, 0.3], [1.0, -0.5], rng.standard_normal(n))
    return trend, trend + noise


def test_imfs_and_residue_sum_back_exactly() -> None:
    _, x = _trend_plus_arma()
    r = emd(x)
    assert r.n_imfs >= 5
    np.testing.assert_allclose(r.imfs.sum(axis=0) + r.residue, x, rtol=0, atol=1e-10)


def test_pure_tones_are_separated() -> None:
    # two well separated tones (ratio 25) end up in different IMFs, each recovered to 5 %
    t = np.arange(5000) / 100.0
    fast = np.sin(2 * np.pi * 5.0 * t)
    slow = 2.0 * np.sin(2 * np.pi * 0.2 * t)
    r = emd(fast + slow)
    err_fast = np.sqrt(np.mean((r.imfs[0] - fast)[200:-200] ** 2))
    assert err_fast < 0.05
    best_slow = min(np.sqrt(np.mean((imf - slow)[200:-200] ** 2)) for imf in r.imfs[1:])
    assert best_slow < 0.05 * 2.0


@pytest.mark.parametrize("as_series", [False, True])
def test_trend_recovered_within_10_percent(as_series: bool) -> None:
    trend, x = _trend_plus_arma()
    data = pd.Series(x, index=pd.RangeIndex(100, 100 + x.size)) if as_series else x
    s = separate_trend(data, fs_hz=1.0)
    got = np.asarray(s.trend)
    rel = np.sqrt(np.mean((got - trend) ** 2)) / np.sqrt(np.mean((trend - trend.mean()) ** 2))
    assert rel <= 0.10          # relative RMS error <= 10 % (measured ~7 %)
    np.testing.assert_allclose(got + np.asarray(s.rest), x, atol=1e-10)
    if as_series:
        assert isinstance(s.trend, pd.Series) and s.trend.index.equals(data.index)
        assert s.rest.index.equals(data.index)


def test_k_follows_the_energy_rule() -> None:
    _, x = _trend_plus_arma()
    s = separate_trend(x, fs_hz=1.0)
    e = s.imf_energy
    np.testing.assert_allclose(e, np.mean(s.imfs ** 2, axis=1))
    k = s.k  # 1-based
    assert 2 <= k <= s.n_imfs
    assert e[k - 1] > e[k - 2]                           # energy rises at IMF k ...
    assert np.any(np.diff(e[: k - 1]) < 0)               # ... after having fallen
    rises_before = [i for i in range(2, k - 1) if e[i] > e[i - 1] and np.any(np.diff(e[:i]) < 0)]
    assert rises_before == []                            # and k is the first such IMF
    np.testing.assert_allclose(s.trend, s.imfs[k - 1:].sum(axis=0) + s.residue)


def test_energy_k_rule_cases() -> None:
    assert energy_k(np.array([8.0, 4.0, 2.0, 1.0, 3.0, 9.0])) == 5
    assert energy_k(np.array([1.0, 2.0, 1.0, 0.5, 0.7])) == 5   # a rise before any fall is ignored
    assert energy_k(np.array([4.0, 2.0, 1.0])) == 4             # never rises: trend = residue


def test_forced_k_and_summary() -> None:
    _, x = _trend_plus_arma(n=1200)
    s = separate_trend(x, fs_hz=1.0, k=2)
    assert s.k == 2 and s.criterion == "given"
    np.testing.assert_allclose(s.rest, s.imfs[0])
    d = s.to_dict()
    assert d["k"] == 2 and len(d["imf_energy"]) == s.n_imfs
    assert "k = 2" in s.summary()
    frame = s.to_frame()
    assert list(frame.columns[:4]) == ["time", "signal", "trend", "rest"]


def test_monotonic_series_is_all_trend() -> None:
    x = np.arange(100.0) ** 2
    s = separate_trend(x, fs_hz=1.0)
    assert s.n_imfs == 0 and s.k == 1
    np.testing.assert_array_equal(s.trend, x)
    assert not np.any(s.rest)


def test_bad_input() -> None:
    with pytest.raises(InsufficientDataError, match="at least 16"):
        separate_trend(np.arange(5.0), fs_hz=1.0)
    with pytest.raises(InsufficientDataError, match="constant"):
        separate_trend(np.ones(100), fs_hz=1.0)
    with pytest.raises(DataError, match="criterion must be one of energy"):
        separate_trend(np.random.default_rng(0).standard_normal(100), fs_hz=1.0,
                       criterion="corr")  # type: ignore[arg-type]
    with pytest.raises(DataError, match="fs_hz"):
        separate_trend(np.random.default_rng(0).standard_normal(100), fs_hz=0.0)
    with pytest.raises(DataError, match="k must be <="):
        separate_trend(np.random.default_rng(0).standard_normal(100), fs_hz=1.0, k=99)
