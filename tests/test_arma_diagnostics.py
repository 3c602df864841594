"""Residual diagnostics: seed eqs. 11/12 against direct loops, Ljung-Box, ACF and PACF against
statsmodels, roots against statsmodels' ARIMA results, redundancy flags, the ACF/PACF reading.

Tolerances: statistics computed two ways agree to 1e-12 (relative) or better; roots to 1e-10.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.signal import lfilter
from statsmodels.stats.diagnostic import acorr_ljungbox
from statsmodels.tsa.stattools import acf as sm_acf
from statsmodels.tsa.stattools import pacf as sm_pacf

from fogts.arma.diagnostics import (
    NEAR_CANCEL_TOL,
    arma_roots,
    autocorrelation,
    correlogram,
    insignificant_terms,
    lag_products,
    ljung_box,
    near_cancellations,
    partial_autocorrelation,
    residual_diagnostics,
    rho_a2,
    rho_ax3,
)
from fogts.errors import DataError, InsufficientDataError


def _arma(ar: list[float], ma: list[float], n: int, seed: int, burn: int = 2000) -> np.ndarray:
    e = np.random.default_rng(seed).standard_normal(n + burn)
    return np.asarray(lfilter(np.r_[1.0, ma], np.r_[1.0, -np.asarray(ar)], e)[burn:])


def _rho_a2_loop(a: np.ndarray) -> float:
    """Seed 000 eq. 11 written literally, t = 3..N (1-based)."""
    num = den = 0.0
    for t in range(3, a.size + 1):
        num += a[t - 1] * a[t - 3]
        den += a[t - 1] ** 2
    return num / den


def _rho_ax3_loop(a: np.ndarray, x: np.ndarray) -> float:
    """Seed 000 eq. 12 written literally, t = 4..N (1-based)."""
    num = saa = sxx = 0.0
    for t in range(4, a.size + 1):
        num += a[t - 1] * x[t - 4]
        saa += a[t - 1] ** 2
        sxx += x[t - 4] ** 2
    return num / math.sqrt(saa * sxx)


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_rho_statistics_equal_direct_loops(seed: int) -> None:
    rng = np.random.default_rng(seed)
    x = _arma([0.5], [0.3], 3000, seed)
    a = rng.standard_normal(3000) * 1e-3 + 0.01 * x
    assert rho_a2(a) == pytest.approx(_rho_a2_loop(a), rel=1e-12, abs=1e-15)
    assert rho_ax3(a, x) == pytest.approx(_rho_ax3_loop(a, x), rel=1e-12, abs=1e-15)


def test_residual_diagnostics_band_and_verdict() -> None:
    x = _arma([0.6], [], 4000, 3)
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
    x = _arma([0.2], [0.1], 700, 11)
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


def test_acf_pacf_equal_statsmodels() -> None:
    x = _arma([0.7, -0.2], [0.4], 5000, 5) + 3.0
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


@pytest.mark.parametrize(("ar", "ma"), [([0.5, -0.3], [0.4]), ([0.9, -0.5, 0.1], [-0.4]),
                                         ([1.2, -0.8], [0.5, 0.3])])
def test_roots_equal_statsmodels(ar: list[float], ma: list[float]) -> None:
    from statsmodels.tsa.arima_process import ArmaProcess

    ref = ArmaProcess(ar=np.r_[1.0, -np.asarray(ar)], ma=np.r_[1.0, ma])
    r = arma_roots(ar, ma)
    assert np.allclose(np.sort_complex(r.ar), np.sort_complex(ref.arroots), atol=1e-10)
    assert np.allclose(np.sort_complex(r.ma), np.sort_complex(ref.maroots), atol=1e-10)
    assert np.allclose(np.sort(r.ar_modulus), np.sort(np.abs(ref.arroots)), atol=1e-10)
    assert np.allclose(np.sort_complex(r.ar_inverse), np.sort_complex(1 / ref.arroots),
                       atol=1e-10)
    assert r.stationary == bool(ref.isstationary) and r.invertible == bool(ref.isinvertible)
    d = r.to_dict()
    assert set(d) == {"ar", "ma", "ar_modulus", "ma_modulus", "ar_inverse", "ma_inverse",
                      "stationary", "invertible"}


def test_roots_flag_nonstationary_and_noninvertible() -> None:
    r = arma_roots([1.2], [-1.5])
    assert not r.stationary and not r.invertible
    assert r.ar_radius == pytest.approx(1.2) and r.ma_radius == pytest.approx(1.5)


def test_seed_paper_near_cancellation() -> None:
    # seed 000: x_t = -0.2699 x_{t-1} - 0.002968 x_{t-2} + a_t + 0.277 a_{t-1}
    r = arma_roots([-0.2699, -0.002968], [0.277])
    assert np.allclose(r.ar_inverse.real, [-0.0115, -0.2584], atol=5e-5)
    assert np.allclose(r.ma_inverse.real, [-0.277], atol=1e-12)
    flags = near_cancellations(r)
    assert len(flags) == 1 and flags[0].kind == "near_cancellation"
    assert flags[0].details["distance"] == pytest.approx(0.0186, abs=2e-4)
    assert flags[0].details["distance"] < NEAR_CANCEL_TOL
    assert "nearly cancels" in flags[0].message
    assert flags[0].to_dict()["ar_root"]["real"] == pytest.approx(-0.2584, abs=5e-5)
    # a well-separated ARMA(1,1) is not flagged
    assert near_cancellations(arma_roots([0.6], [0.3])) == ()
    assert near_cancellations(arma_roots([0.6], [])) == ()


def test_insignificant_terms() -> None:
    flags = insignificant_terms({"ar.L1": 0.5, "ar.L2": -0.01, "ma.L1": 0.02, "sigma2": 0.001},
                                {"ar.L1": 0.01, "ar.L2": 0.02, "ma.L1": math.nan,
                                 "sigma2": 1.0})
    assert [f.details["param"] for f in flags] == ["ar.L2"]
    assert flags[0].details["t"] == pytest.approx(-0.5)


@pytest.mark.parametrize(("ar", "ma", "acf_kind", "pacf_text"), [
    ([0.7], [], "tails off", "cuts off after lag 1"),
    ([0.5, 0.3], [], "tails off", "cuts off after lag 2"),
    ([], [0.8], "cuts off", "tails off"),
])
def test_correlogram_reading(ar: list[float], ma: list[float], acf_kind: str,
                             pacf_text: str) -> None:
    c = correlogram(_arma(ar, ma, 20_000, 21))
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
    x = _arma([0.5], [], 800, 1)
    c = correlogram(x, nlags=15)
    r, ci = sm_acf(x, nlags=15, alpha=0.05, fft=False, result_object=False)
    # statsmodels uses the exact 97.5 % quantile 1.95996...; fogts the seed paper's 1.96
    assert np.allclose(c.acf_band[1:] / 1.96, (ci[1:, 1] - r[1:]) / 1.959963984540054,
                       rtol=1e-12)


def test_errors() -> None:
    a = np.random.default_rng(0).standard_normal(100)
    with pytest.raises(DataError, match="lags must name at least one lag"):
        ljung_box(a, lags=[])
    with pytest.raises(DataError, match="lags must be <= 99, got 100"):
        ljung_box(a, lags=[100])
    with pytest.raises(DataError, match="resid and x must have the same length, got 100 and 99"):
        residual_diagnostics(a, a[:99], p=1, q=0)
    with pytest.raises(InsufficientDataError, match="x is constant"):
        autocorrelation(np.ones(50), nlags=3)
    with pytest.raises(DataError, match="nlags must be <= 49, got 50"):
        correlogram(a, nlags=50)
