"""Whiteness checks: rho_a,2 and rho_ax,3 (the drift paper's eqs. 11, 12) against literal
loops, Ljung-Box against statsmodels' acorr_ljungbox (1e-12 relative), the white verdict."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.signal import lfilter
from statsmodels.stats.diagnostic import acorr_ljungbox

from fogts.arma.diagnostics import (
    ljung_box,
    residual_diagnostics,
    rho_a2,
    rho_ax3,
)
from fogts.arma.whiteness import diagnostics_of
from fogts.errors import DataError
from tests.arma.simulated import arma_series


def _rho_a2_loop(a: np.ndarray) -> float:
    """The drift paper's eq. 11 written literally, t = 3..N (1-based)."""
    num = den = 0.0
    for t in range(3, a.size + 1):
        num += a[t - 1] * a[t - 3]
        den += a[t - 1] ** 2
    return num / den


def _rho_ax3_loop(a: np.ndarray, x: np.ndarray) -> float:
    """The drift paper's eq. 12 written literally, t = 4..N (1-based)."""
    num = saa = sxx = 0.0
    for t in range(4, a.size + 1):
        num += a[t - 1] * x[t - 4]
        saa += a[t - 1] ** 2
        sxx += x[t - 4] ** 2
    return num / math.sqrt(saa * sxx)


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_rho_statistics_equal_direct_loops(seed: int) -> None:
    rng = np.random.default_rng(seed)
    x = arma_series([0.5], [0.3], 3000, seed)
    a = rng.standard_normal(3000) * 1e-3 + 0.01 * x
    assert rho_a2(a) == pytest.approx(_rho_a2_loop(a), rel=1e-12, abs=1e-15)
    assert rho_ax3(a, x) == pytest.approx(_rho_ax3_loop(a, x), rel=1e-12, abs=1e-15)


def test_residual_diagnostics_band_and_verdict() -> None:
    x = arma_series([0.6], [], 4000, 3)
    a = lfilter([1.0, -0.6], [1.0], x)          # the true innovations: white
    d = residual_diagnostics(a, x, p=1, q=0, lags=(10, 20))
    assert d.band == pytest.approx(1.96 / math.sqrt(4000), rel=1e-15)
    assert d.rho_a2.value == pytest.approx(_rho_a2_loop(a), rel=1e-12)
    assert d.rho_ax3.value == pytest.approx(_rho_ax3_loop(a, x), rel=1e-12)
    assert d.white and d.reasons == ()
    assert d.mean == pytest.approx(float(np.mean(a))) and d.variance == pytest.approx(np.var(a))
    # the data themselves are far from white: rho_a2 = phi^2 = 0.36
    bad = residual_diagnostics(x, x, p=1, q=0)
    assert not bad.white and not bad.rho_a2.passed
    assert any("rho_a2" in r for r in bad.reasons) and any("Ljung-Box" in r for r in bad.reasons)
    assert set(bad.to_frame().index) == {"rho_a2", "rho_ax3", "ljung_box(10)", "ljung_box(20)"}
    assert bad.to_dict()["ljung_box"][0]["lag"] == 10


@pytest.mark.parametrize("model_df", [0, 2, 3, 10, 12])
def test_ljung_box_equals_statsmodels(model_df: int) -> None:
    x = arma_series([0.2], [0.1], 700, 11)
    lags = [5, 10, 20]
    ours = ljung_box(x, lags=lags, model_df=model_df)
    ref = acorr_ljungbox(x, lags=lags, model_df=model_df, return_df=True)
    for lb, (_, row) in zip(ours, ref.iterrows(), strict=True):
        assert lb.q == pytest.approx(row["lb_stat"], rel=1e-12)
        if np.isnan(row["lb_pvalue"]):
            assert math.isnan(lb.pvalue) and lb.passed is None and lb.df <= 0
        else:
            assert lb.pvalue == pytest.approx(row["lb_pvalue"], rel=1e-9, abs=1e-300)


def test_ljung_box_untestable_lags_are_not_white() -> None:
    a = np.random.default_rng(0).standard_normal(500)
    d = residual_diagnostics(a, a, p=2, q=1, lags=(3,))
    assert not d.white and "not testable" in d.reasons[0]


def test_errors() -> None:
    a = np.random.default_rng(0).standard_normal(100)
    with pytest.raises(DataError, match="lags must name at least one lag"):
        ljung_box(a, lags=[])
    with pytest.raises(DataError, match="lags must be <= 99, got 100"):
        ljung_box(a, lags=[100])
    with pytest.raises(DataError, match="resid and x must have the same length, got 100 and 99"):
        residual_diagnostics(a, a[:99], p=1, q=0)


def test_diagnostics_need_equal_lengths() -> None:
    a = np.random.default_rng(3).standard_normal(100)
    with pytest.raises(DataError, match="resid and x must have the same length, got 100 and 99"):
        residual_diagnostics(a, a[:-1], p=1, q=0)
    with pytest.raises(DataError, match="same length"):
        diagnostics_of(a, a[:-1], p=1, q=0, lags=(10,), x_offset=1.0)
