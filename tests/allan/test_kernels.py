"""Tests of fogts.allan.kernels: the phase and the differences the estimators are built from.

The kernels' sums themselves are checked through the estimators against Stable32 and
allantools (``tests/allan/test_estimators.py``, also with tiny chunks); here the phase and
the difference helpers are checked against their plain numpy definitions.
"""

from __future__ import annotations

import numpy as np
import pytest

from fogts.allan import kernels
from fogts.allan.estimators import phase_deviations
from fogts.allan.estimators import phase_from_rate as phase_from_estimators
from fogts.allan.kernels import (
    NORMALISATION,
    phase_from_rate,
    second_difference,
    third_difference,
)
from fogts.allan.taus import KINDS


def test_phase_from_rate_is_the_mean_removed_cumulative_sum() -> None:
    y = np.random.default_rng(0).normal(size=100_003) + 3.0
    x = phase_from_rate(y)
    assert x.shape == (100_004,) and x[0] == 0.0
    np.testing.assert_allclose(x[1:], np.cumsum(y - y.mean()), atol=1e-9)
    assert abs(x[-1]) < 1e-8



def test_phase_from_a_given_mean() -> None:
    """A caller's mean (the sum of the finiteness check over n) gives the same phase: the
    same float as numpy.mean, so asserted bit for bit."""
    y = np.random.default_rng(2).normal(size=10_007) + 4.0
    given = phase_from_rate(y, mean=float(np.sum(y)) / y.size)
    assert np.array_equal(given, phase_from_rate(y))

def test_phase_from_rate_is_importable_from_the_estimators() -> None:
    assert phase_from_estimators is phase_from_rate



@pytest.mark.parametrize("n", [5 * 64 + 17, 6 * 64])
def test_phase_integrated_in_halves(monkeypatch: pytest.MonkeyPatch, n: int) -> None:
    """Long records are integrated in two halves at once.  The first half is a whole
    number of chunks, so it equals the one-thread phase bit for bit (asserted exactly:
    the same operations); the second half and every deviation agree to 1e-12 relative."""
    monkeypatch.setattr(kernels, "CHUNK", 64)
    y = np.random.default_rng(4).normal(size=n) + 2.5 + np.cumsum(
        np.random.default_rng(5).normal(scale=0.05, size=n))
    monkeypatch.setattr(kernels, "HALVES_FROM", n + 1)
    one = phase_from_rate(y)
    monkeypatch.setattr(kernels, "HALVES_FROM", n)
    two = phase_from_rate(y)
    half = (n // 2) // 64 * 64
    assert np.array_equal(two[: half + 1], one[: half + 1])
    np.testing.assert_allclose(two, one, rtol=0, atol=1e-12 * np.abs(one).max())
    m = np.array([1, 2, 5, 16, 40, 100])
    for kind in ("oadev", "mdev", "ohdev", "totdev"):
        np.testing.assert_allclose(phase_deviations(kind, two, m),
                                   phase_deviations(kind, one, m), rtol=1e-12, atol=0)


def test_halves_start_above_two_chunks() -> None:
    assert kernels.HALVES_FROM >= 2 * kernels.CHUNK

def test_differences_match_their_definitions() -> None:
    x = np.cumsum(np.random.default_rng(3).normal(size=500))
    lag, c0, c1 = 7, 11, 400
    i = np.arange(c0, c1)
    out, tmp = np.empty(c1 - c0), np.empty(c1 - c0)
    second = second_difference(x, lag, c0, c1, out, tmp)
    assert second is out
    np.testing.assert_allclose(second, x[i + 2 * lag] - 2 * x[i + lag] + x[i], rtol=1e-12,
                               atol=1e-12)
    third = third_difference(x, lag, c0, c1, np.empty(c1 - c0), np.empty(c1 - c0))
    np.testing.assert_allclose(third, x[i + 3 * lag] - 3 * x[i + 2 * lag] + 3 * x[i + lag]
                               - x[i], rtol=1e-12, atol=1e-12)


def test_normalisation_covers_every_kind() -> None:
    assert sorted(NORMALISATION) == sorted(KINDS)
    # 2 m^2 n (Allan, total), 6 m^2 n (Hadamard), 2 m^4 n (modified Allan)
    assert NORMALISATION["oadev"](3, 10) == pytest.approx(180.0, rel=1e-15)
    assert NORMALISATION["ohdev"](3, 10) == pytest.approx(540.0, rel=1e-15)
    assert NORMALISATION["mdev"](3, 10) == pytest.approx(1620.0, rel=1e-15)


@pytest.mark.parametrize("chunk", [7, 50, kernels.CHUNK])
def test_shared_walk_gives_each_lags_own_sum(monkeypatch: pytest.MonkeyPatch,
                                             chunk: int) -> None:
    """ss_second_lags forms the blocks of ss_second in the same order, so each lag's sum
    is that of ss_second (1e-15 relative: the same operations; a reordering would show at
    about 1e-13 on 4e4 terms)."""
    monkeypatch.setattr(kernels, "CHUNK", chunk)
    x = phase_from_rate(np.random.default_rng(8).normal(size=40_000) + 0.1)
    lags = [m for m in (1, 2, 3, 6, 17, 40, 49) if kernels.hook_sees_chunks(m, x.size - 2 * m)]
    terms = [x.size - 2 * m for m in lags]
    got = kernels.ss_second_lags(x, lags, terms, [None] * len(lags))
    want = [kernels.ss_second(x, m, t) for m, t in zip(lags, terms, strict=True)]
    np.testing.assert_allclose(got, want, rtol=1e-15, atol=0)


@pytest.mark.parametrize("n", [1, kernels.DOT_BLOCK, kernels.DOT_BLOCK + 1, 4 * kernels.DOT_BLOCK,
                               4 * kernels.DOT_BLOCK + 77])
def test_sum_of_squares_by_vecdot_equals_the_block_loop(monkeypatch: pytest.MonkeyPatch,
                                                        n: int) -> None:
    """The rows of ``numpy.vecdot`` are the same BLAS ``ddot`` calls as ``numpy.dot`` of each
    block, added in the same order: equal exactly (also from an unaligned start)."""
    v = np.random.default_rng(8).normal(size=n + 1)[1:] * 1e3
    with_vecdot = kernels._sumsq(v)
    monkeypatch.setattr(kernels, "_VECDOT", None)
    assert kernels._sumsq(v) == with_vecdot
    blocks = [float(np.dot(v[s:s + kernels.DOT_BLOCK], v[s:s + kernels.DOT_BLOCK]))
              for s in range(0, n, kernels.DOT_BLOCK)]
    assert with_vecdot == pytest.approx(sum(blocks), rel=1e-15)
