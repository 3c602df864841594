"""Block-wise statistics of long series, and fit_arma's block-wise path above
BLOCKWISE_MIN_N against its whole-array path."""

from __future__ import annotations

import warnings

import numpy as np
import pytest

import fogts.arma.fit as fitmod
import fogts.arma.fit_result as fit_result
from fogts.arma.blockwise import lagged_products, mean_of, scale_and_offsets, std
from fogts.arma.fit import fit_arma

# Block sums added one after another instead of numpy's pairwise sum: the relative rounding
# error of either is at most ~(n / BLOCK + log2 n) eps < 1e-14 here; 1e-12 leaves room.
RTOL = 1e-12


def test_statistics_equal_numpys_to_rounding() -> None:
    x = np.random.default_rng(5).standard_normal(200_003) * 3.0 + 1.5
    assert std(x) == pytest.approx(float(np.std(x)), rel=RTOL)
    assert mean_of(x, 2.0, 0.25) == pytest.approx(float(np.mean(x / 2.0 - 0.25)), rel=RTOL)
    scale, off, off2 = scale_and_offsets(x, True, True)
    assert off == pytest.approx(float(np.mean(x / scale)), rel=RTOL)
    assert abs(off2) < 1e-12
    y = x / scale - off
    M = lagged_products(x, scale, off, 3)
    n = y.size
    for i in range(4):
        for j in range(4):
            ref = float(np.dot(y[3 - i:n - i], y[3 - j:n - j]))
            assert M[i, j] == pytest.approx(ref, rel=RTOL, abs=RTOL * n)


@pytest.mark.parametrize(("p", "q"), [(1, 0), (2, 1)])
def test_fit_on_the_blockwise_path_equals_the_whole_array_path(
        monkeypatch: pytest.MonkeyPatch, p: int, q: int) -> None:
    """The two paths differ in the rounding of the scale and mean only (relative 1e-15):
    the optimum moves by far less than Newton's stopping step (1e-7 on the exact polish),
    so parameters agree to 1e-6 of their standard errors and the AIC to 1e-6."""
    x = _series(20_000)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        ref = fit_arma(x, p, q, mean=True)
        monkeypatch.setattr(fitmod, "BLOCKWISE_MIN_N", 1000)
        monkeypatch.setattr(fit_result, "BLOCKWISE_MIN_N", 1000)
        got = fit_arma(x, p, q, mean=True)
        resid = got.resid
    for k, v in ref.params.items():
        assert abs(got.params[k] - v) <= 1e-6 * ref.bse[k], k
    assert got.aic == pytest.approx(ref.aic, abs=1e-6)
    assert np.allclose(resid, ref.resid, rtol=0.0, atol=1e-9 * float(np.std(x)))


def _series(n: int) -> np.ndarray:
    from scipy.signal import lfilter

    e = np.random.default_rng(11).standard_normal(n + 500)
    return np.asarray(lfilter([1.0, 0.5], [1.0, -0.5, -0.2], e)[500:] + 3.0)
