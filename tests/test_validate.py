"""Tests of fogts._validate's finiteness checks (the plain numpy definitions as reference)."""

from __future__ import annotations

import numpy as np
import pytest

from fogts._validate import all_finite, checked_sum, finite_sum, to_float_array
from fogts.errors import DataError


@pytest.mark.parametrize("n", [1, 2, 7, 129, 4097, 1_000_003])
def test_the_checking_sum_is_the_one_the_mean_divides(n: int) -> None:
    """``finite_sum(a) / a.size`` is ``numpy.mean(a)`` bit for bit (asserted exactly: the
    phase of the Allan estimators removes this mean, and their outputs must not move)."""
    a = np.random.default_rng(n).normal(size=n) * 3.0 + 11.0
    total = finite_sum(a)
    assert total is not None and total / n == float(np.mean(a))
    assert checked_sum(a) == total and all_finite(a)


def test_non_finite_values() -> None:
    assert finite_sum(np.array([1.0, np.nan])) is None
    assert finite_sum(np.array([np.inf, -np.inf])) is None
    assert not all_finite(np.array([0.0, -np.inf]))
    big = np.array([1e308, 1e308])  # finite values whose sum overflows
    assert all_finite(big) and finite_sum(big) == np.inf
    with pytest.raises(DataError, match=r"y contains a non-finite value \(nan\) at position 2"):
        checked_sum(np.array([0.0, 1.0, np.nan, np.inf]), "y")
    with pytest.raises(DataError, match=r"x contains a non-finite value \(inf\) at position 1"):
        to_float_array([0.0, np.inf, 1.0])
