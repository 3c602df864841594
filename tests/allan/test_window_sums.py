"""Tests of fogts.allan.window_sums: every sliding window's deviation.

Reference: the running-sum path (one pass per tau) against the estimators of
:mod:`fogts.allan.estimators` run on each window separately (1e-9 relative: the two sum the
same squared terms in a different order), with cache-sized and with tiny pieces (with
tiny ones, most blocks are "long": oadev and ohdev sum them by the estimators' kernels,
mdev by chunks).
"""

from __future__ import annotations

import numpy as np
import pytest

from fogts.allan import window_sums
from fogts.allan.taus import n_terms
from fogts.allan.window_sums import CUMSUM_KINDS, cumsum_devs, kernel_devs


@pytest.mark.parametrize("kind", CUMSUM_KINDS)
@pytest.mark.parametrize("chunk", [5, 1 << 16])
def test_running_sums_equal_the_estimator_on_each_window(monkeypatch: pytest.MonkeyPatch,
                                                         kind: str, chunk: int) -> None:
    monkeypatch.setattr(window_sums, "_CHUNK", chunk)  # 5: many pieces per window
    y = np.random.default_rng(9).normal(size=3000) + 7.0
    win_n, step = 400, 37
    m = np.array([1, 2, 5, 13, 40, 120])
    starts = np.arange((y.size - win_n) // step + 1, dtype=np.int64) * step
    fast = cumsum_devs(y, kind=kind, m=m, terms=n_terms(kind, m, win_n), starts=starts)
    slow = kernel_devs(y, kind=kind, m=m, starts=starts, win_n=win_n, fs=1.0)
    assert fast.shape == slow.shape == (starts.size, m.size)
    np.testing.assert_allclose(fast, slow, rtol=1e-9)


def test_kernel_devs_of_one_window_is_the_estimator() -> None:
    from fogts.allan.estimators import hdev

    y = np.random.default_rng(10).normal(size=1000)
    m = np.array([1, 4, 16])
    out = kernel_devs(y, kind="hdev", m=m, starts=np.array([0, 300]), win_n=500, fs=2.0)
    np.testing.assert_allclose(out[1], hdev(y[300:800], fs_hz=2.0, m=m).dev, rtol=1e-15)


@pytest.mark.parametrize("kind", CUMSUM_KINDS)
def test_taus_on_threads_give_the_serial_numbers(monkeypatch: pytest.MonkeyPatch,
                                                 kind: str) -> None:
    """Each tau's column is computed alone, so the thread pool changes no sum: the same
    array bit for bit as one thread (the pool runs whenever the machine has two cores)."""
    y = np.random.default_rng(11).normal(size=20_000)
    win_n, step = 4000, 1000
    m = np.array([1, 3, 10, 30, 100, 300])
    starts = np.arange((y.size - win_n) // step + 1, dtype=np.int64) * step
    terms = n_terms(kind, m, win_n)
    monkeypatch.setattr(window_sums, "thread_count", lambda *_: 3)
    threaded = cumsum_devs(y, kind=kind, m=m, terms=terms, starts=starts)
    monkeypatch.setattr(window_sums, "thread_count", lambda *_: 1)
    serial = cumsum_devs(y, kind=kind, m=m, terms=terms, starts=starts)
    assert np.array_equal(threaded, serial)
