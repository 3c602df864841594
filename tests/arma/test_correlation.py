"""Lag products, ACF and PACF against direct sums and statsmodels (to 1e-12 or better)."""

from __future__ import annotations

import numpy as np
import pytest
from statsmodels.tsa.stattools import acf as sm_acf
from statsmodels.tsa.stattools import pacf as sm_pacf

from fogts.arma.diagnostics import (
    autocorrelation,
    lag_products,
    partial_autocorrelation,
)
from fogts.errors import InsufficientDataError
from tests.arma.simulated import arma_series


def test_acf_pacf_equal_statsmodels() -> None:
    x = arma_series([0.7, -0.2], [0.4], 5000, 5) + 3.0
    assert np.allclose(autocorrelation(x, nlags=40), sm_acf(x, nlags=40, fft=False),
                       rtol=0, atol=1e-13)
    assert np.allclose(partial_autocorrelation(x, nlags=40),
                       sm_pacf(x, nlags=40, method="ldb"), rtol=0, atol=1e-12)


def test_lag_products_equal_direct_sums() -> None:
    x = np.random.default_rng(9).standard_normal(150_000)   # spans several kernel blocks
    y = np.random.default_rng(10).standard_normal(150_000)
    got = lag_products(x, 25, y)
    ref = np.array([np.sum(x[k:] * y[:x.size - k]) for k in range(26)])
    assert np.allclose(got, ref, rtol=1e-12, atol=1e-9)
    assert lag_products(x, 0)[0] == pytest.approx(float(np.sum(x * x)), rel=1e-12)


def test_constant_series_has_no_autocorrelation() -> None:
    with pytest.raises(InsufficientDataError, match="x is constant"):
        autocorrelation(np.ones(50), nlags=3)


def test_sum_squares_block_by_block_is_dot_bit_for_bit() -> None:
    """Continued over blocks of whole 8192-long pieces (the last one shorter), the running
    sum is dot's of the whole array, which the likelihood's evaluation relies on."""
    from fogts.arma.correlation import EINSUM_BLOCK, dot, fused_squares, sum_squares

    assert fused_squares()
    a = np.random.default_rng(3).standard_normal(5 * 65536 + 777)[3:]   # unaligned start
    total = 0.0
    for c0 in range(0, a.shape[0], 8 * EINSUM_BLOCK):
        total = sum_squares(total, a[c0:c0 + 8 * EINSUM_BLOCK])
    assert total == dot(a, a)
