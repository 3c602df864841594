"""The Box-Jenkins reading of the ACF and PACF, and the Bartlett band against statsmodels."""

from __future__ import annotations

import math

import numpy as np
import pytest
from statsmodels.tsa.stattools import acf as sm_acf

from fogts.arma.diagnostics import (
    correlogram,
)
from fogts.errors import DataError
from tests.arma.simulated import arma_series


@pytest.mark.parametrize(("ar", "ma", "acf_kind", "pacf_text"), [
    ([0.7], [], "tails off", "cuts off after lag 1"),
    ([0.5, 0.3], [], "tails off", "cuts off after lag 2"),
    ([], [0.8], "cuts off", "tails off"),
])
def test_correlogram_reading(ar: list[float], ma: list[float], acf_kind: str,
                             pacf_text: str) -> None:
    c = correlogram(arma_series(ar, ma, 20_000, 21))
    assert c.acf_pattern.kind == acf_kind
    assert c.pacf_pattern.describe().startswith(pacf_text)
    assert c.nlags == 40 and c.band == pytest.approx(1.96 / math.sqrt(20_000))
    assert c.acf_band[1] == pytest.approx(c.band)          # Bartlett band at lag 1
    assert np.all(np.diff(c.acf_band[1:]) >= 0)
    assert list(c.to_frame().columns) == ["acf", "acf_band", "pacf", "pacf_band"]


def test_correlogram_of_white_noise() -> None:
    c = correlogram(np.random.default_rng(3).standard_normal(20_000))
    assert c.acf_pattern.kind == "none" and c.pacf_pattern.kind == "none"
    assert "white" in c.suggestion


def test_acf_bartlett_band_equals_statsmodels() -> None:
    x = arma_series([0.5], [], 800, 1)
    c = correlogram(x, nlags=15)
    r, ci = sm_acf(x, nlags=15, alpha=0.05, fft=False, result_object=False)
    # statsmodels uses the exact 97.5 % quantile 1.95996...; fogts the drift paper's 1.96
    assert np.allclose(c.acf_band[1:] / 1.96, (ci[1:, 1] - r[1:]) / 1.959963984540054,
                       rtol=1e-12)


def test_too_many_lags() -> None:
    a = np.random.default_rng(0).standard_normal(100)
    with pytest.raises(DataError, match="nlags must be <= 49, got 50"):
        correlogram(a, nlags=50)
