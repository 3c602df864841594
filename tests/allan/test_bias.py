"""Tests of fogts.allan.bias: the noise-dependent bias of the total variance (Howe 1999)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from fogts.allan.bias import totdev_bias
from fogts.errors import DataError, InsufficientDataError


def test_totdev_bias_values() -> None:
    """B = 1 - a m/(N-1): a = 1/(3 ln 2) flicker FM, 3/4 random-walk FM, else 1 (Howe 1999)."""
    b = totdev_bias([2, 1, 0, -1, -2], 250, 1001)
    expected = [1.0, 1.0, 1.0, 1.0 - 0.25 / (3.0 * math.log(2.0)), 1.0 - 0.75 * 0.25]
    np.testing.assert_allclose(b, expected, rtol=1e-15, atol=0)
    assert totdev_bias(-2, [1, 10], 101).tolist() == pytest.approx([0.9925, 0.925], rel=1e-15)


def test_totdev_bias_errors() -> None:
    with pytest.raises(DataError, match=r"alpha must be an integer in \[-2, 2\] for "
                                        r"kind='totdev', got -3"):
        totdev_bias(-3, 1, 100)
    with pytest.raises(DataError, match="m must hold integers >= 1, got 0"):
        totdev_bias(0, [1, 0], 100)
    with pytest.raises(DataError, match="n_phase must be >= 2, got 1"):
        totdev_bias(0, 1, 1)
    with pytest.raises(InsufficientDataError,
                       match=r"m=50 is too large for totdev with n_phase=100: needs 2\*m <= "
                             "n_phase - 1 = 99"):
        totdev_bias(-1, [10, 50], 100)
