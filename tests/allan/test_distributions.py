"""Tests of fogts.allan.distributions against scipy.stats, the reference it replaces.

The functions evaluate the special functions that ``scipy.stats.norm`` and
``scipy.stats.chi2`` evaluate, so the comparison asserts bit equality deliberately: the
golden outputs of ``fogts allan`` (confidence intervals, z thresholds) must not move when
the analysis stops importing ``scipy.stats``.
"""

from __future__ import annotations

import numpy as np
import pytest
from scipy import stats

from fogts.allan.distributions import chi2_ppf, chi2_sf, norm_cdf, norm_ppf

PROBS = np.array([0.0, 1e-300, 1e-12, 0.0013, 0.025, 0.1585, 0.3415, 0.5, 0.6585, 0.8415,
                  0.95, 0.975, 1 - 1e-12, 1.0])
DFS = np.array([1e-3, 0.5, 1.0, 2.0, 2.7, 10.0, 37.4, 782.03, 1e4, 9.9e7])


def _same(got: object, want: object) -> None:
    np.testing.assert_array_equal(np.asarray(got), np.asarray(want), strict=True)


def test_norm_matches_scipy_stats() -> None:
    x = np.array([-40.0, -8.0, -1.0, -1e-9, 0.0, 0.3, 1.0, 5.0, 40.0, np.inf, -np.inf, np.nan])
    _same(norm_ppf(PROBS), stats.norm.ppf(PROBS))
    _same(norm_cdf(x), stats.norm.cdf(x))
    _same(norm_ppf(0.975), stats.norm.ppf(0.975))  # a scalar stays a numpy scalar
    assert np.isnan(norm_ppf([-0.1, 1.1, np.nan])).all()


def test_chi2_ppf_matches_scipy_stats() -> None:
    q, df = np.meshgrid(PROBS, DFS)
    _same(chi2_ppf(q, df), stats.chi2.ppf(q, df))
    _same(chi2_ppf(0.8415, 782.03), stats.chi2.ppf(0.8415, 782.03))
    bad = chi2_ppf([0.5, 0.5, 0.5, -0.1, 1.1], [np.nan, 0.0, -2.0, 3.0, 3.0])
    _same(bad, stats.chi2.ppf([0.5, 0.5, 0.5, -0.1, 1.1], [np.nan, 0.0, -2.0, 3.0, 3.0]))


def test_chi2_sf_matches_scipy_stats() -> None:
    x, df = np.meshgrid(np.array([-1.0, 0.0, 1e-8, 0.5, 2.0, 3.84, 30.0, 1e3, np.inf]), DFS)
    _same(chi2_sf(x, df), stats.chi2.sf(x, df))
    edge = ([np.nan, 1.0, 1.0], [2.0, 0.0, np.nan])
    _same(chi2_sf(*edge), stats.chi2.sf(*edge))


@pytest.mark.parametrize("seed", [0, 1])
def test_random_arguments_match(seed: int) -> None:
    rng = np.random.default_rng(seed)
    q, df = rng.uniform(size=2000), np.exp(rng.uniform(-3, 12, size=2000))
    _same(chi2_ppf(q, df), stats.chi2.ppf(q, df))
    _same(chi2_sf(df * q * 2, df), stats.chi2.sf(df * q * 2, df))
    _same(norm_ppf(q), stats.norm.ppf(q))

