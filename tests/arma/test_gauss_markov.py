"""Gauss–Markov equivalents of AR roots (fogts.arma.gauss_markov), from simulations with a
known correlation time and standard deviation (fixed seeds).

Tolerances: at n = 200,000 samples and T_c = 100 samples the AR coefficient has standard
error sqrt((1 - phi^2) / n) = 3e-4, i.e. about 3 % on T_c, and the sample variance of a
process with 1,000 effective independent samples about 2 % on sigma; 10 % is over three
standard errors.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.signal import lfilter

import fogts
from fogts.arma.gauss_markov import GaussMarkov, gauss_markov, root_stderr
from fogts.errors import ModelFitError

DT = 1.0
TAU_C = 100.0
SIGMA = 0.5
N = 200_000


def _gauss_markov_series(seed: int) -> np.ndarray:
    phi = math.exp(-DT / TAU_C)
    rng = np.random.default_rng(seed)
    w = rng.normal(scale=SIGMA * math.sqrt(1 - phi * phi), size=N)
    x = lfilter([1.0], [1.0, -phi], w)
    return np.asarray(x, dtype=np.float64)


def test_ar1_gives_the_correlation_time_and_sigma() -> None:
    sel = fogts.select_arma(_gauss_markov_series(11), fs_hz=1 / DT, candidates=[(1, 0)])
    gm = gauss_markov(sel.selected, 1 / DT, "deg/h")
    assert gm is not None and gm.model == "AR(1)" and gm.white == 0.0
    assert gm.tau_c_s == pytest.approx(TAU_C, rel=0.10)
    assert gm.sigma == pytest.approx(SIGMA, rel=0.10)
    assert gm.q == pytest.approx(gm.sigma * math.sqrt(2 / gm.tau_c_s), rel=1e-12)


def test_arma11_is_split_into_gauss_markov_and_white_noise() -> None:
    white = 1.0
    x = _gauss_markov_series(12) + np.random.default_rng(13).normal(scale=white, size=N)
    sel = fogts.select_arma(x, fs_hz=1 / DT, candidates=[(1, 1)])
    gm = gauss_markov(sel.selected, 1 / DT, "deg/h")
    assert gm is not None and gm.model == "ARMA(1,1)"
    assert gm.tau_c_s == pytest.approx(TAU_C, rel=0.15)  # measured 101-108 over 3 seeds
    assert gm.sigma == pytest.approx(SIGMA, rel=0.15)
    assert gm.white == pytest.approx(white, rel=0.05)
    assert "plus white noise" in gm.summary()


def test_si_values_use_the_unit_table() -> None:
    sel = fogts.select_arma(_gauss_markov_series(14), fs_hz=1.0, candidates=[(1, 0)])
    gm = gauss_markov(sel.selected, 1.0, "deg/h")
    assert gm is not None
    deg_h_to_rad_s = math.pi / 180.0 / 3600.0  # first principles
    assert gm.sigma_si == pytest.approx(gm.sigma * deg_h_to_rad_s, rel=1e-12)
    assert gm.q_si == pytest.approx(gm.q * deg_h_to_rad_s, rel=1e-12)


def test_no_real_root_in_the_unit_interval_gives_none() -> None:
    x = lfilter([1.0], [1.0, 0.6], np.random.default_rng(15).normal(size=20_000))  # phi = -0.6
    sel = fogts.select_arma(x, fs_hz=1.0, candidates=[(1, 0)])
    assert gauss_markov(sel.selected, 1.0, "deg/h") is None
    assert gauss_markov(sel.selected, None, "deg/h") is None


def test_a_failed_candidate_is_named_in_the_verdict(monkeypatch: pytest.MonkeyPatch) -> None:
    import fogts.arma.select as select_module

    real_fit = select_module.fit_arma

    def fit(x: np.ndarray, p: int, q: int, **kwargs: object) -> object:
        if (p, q) == (2, 1):
            raise ModelFitError("simulated failure")
        return real_fit(x, p, q, **kwargs)

    monkeypatch.setattr(select_module, "fit_arma", fit)
    sel = fogts.select_arma(_gauss_markov_series(16)[:20_000], fs_hz=1.0)
    assert "Not compared: ARMA(2,1) could not be fitted (ARMA(2,1): simulated failure)" \
        in sel.verdict
    assert "The simpler ARMA(2,1)" not in sel.verdict


def _largest_real_inverse_root(phi: np.ndarray) -> float:
    r = np.roots(np.r_[1.0, -phi])
    return float(r[np.abs(r.imag) < 1e-12].real.max())


def test_root_stderr_is_the_delta_method_of_numpys_roots() -> None:
    # reference: central differences of numpy.roots (independent of the implicit-function
    # formula); h = 1e-6 gives O(h^2) = 1e-12 truncation, and root rounding ~1e-16 / h
    # = 1e-10 on the slopes, so 1e-6 relative is loose
    phi = np.array([1.2, -0.5, 0.1])
    cov = np.array([[1e-4, 5e-5, 0.0], [5e-5, 2e-4, -3e-5], [0.0, -3e-5, 3e-4]])
    r = _largest_real_inverse_root(phi)
    h = 1e-6
    g = np.empty(3)
    for i in range(3):
        up, down = phi.copy(), phi.copy()
        up[i] += h
        down[i] -= h
        g[i] = (_largest_real_inverse_root(up) - _largest_real_inverse_root(down)) / (2 * h)
    assert root_stderr(r, phi, cov) == pytest.approx(math.sqrt(g @ cov @ g), rel=1e-6)
    assert root_stderr(0.5, [0.5], [[0.01]]) == pytest.approx(0.1, rel=1e-12)  # AR(1): se(phi)
    assert math.isnan(root_stderr(0.5, [0.5], None))


def test_the_interval_of_tau_c_holds_the_true_value() -> None:
    sel = fogts.select_arma(_gauss_markov_series(11), fs_hz=1 / DT, candidates=[(1, 0)])
    gm = gauss_markov(sel.selected, 1 / DT, "deg/h")
    assert gm is not None and gm.identified and not gm.within_one_sample
    assert gm.phi_stderr == pytest.approx(sel.selected.bse["ar.L1"], rel=1e-12)
    low, high = gm.tau_c_interval_s
    assert low < TAU_C < high and low < gm.tau_c_s < high
    d = gm.to_dict()
    assert d["identified"] is True and d["tau_c_interval_s"] == [low, high]
    assert "(95 %: " in gm.summary()


def test_white_noise_identifies_no_gauss_markov_state() -> None:
    # seed 2: ar.L1 = 0.0019 with standard error 0.0045 (measured), the one seed of 1-5
    # whose estimate is positive
    x = np.random.default_rng(2).normal(size=50_000)
    sel = fogts.select_arma(x, fs_hz=100.0, candidates=[(1, 0)])
    gm = gauss_markov(sel.selected, 100.0, "deg/h")
    assert gm is not None and not gm.identified
    assert gm.tau_c_interval_s[0] == 0.0
    assert gm.summary().startswith("Gauss–Markov equivalent of AR(1): none identified")
    assert "T_c" not in gm.summary()
    assert gm.to_dict()["identified"] is False


def test_a_correlation_time_under_one_sample_is_called_white_at_this_rate() -> None:
    x = lfilter([1.0], [1.0, -0.2], np.random.default_rng(17).normal(size=50_000))
    sel = fogts.select_arma(x, fs_hz=10.0, candidates=[(1, 0)])
    gm = gauss_markov(sel.selected, 10.0, "deg/h")
    assert gm is not None and gm.identified and gm.within_one_sample
    assert gm.tau_c_s == pytest.approx(-0.1 / math.log(0.2), rel=0.1)
    assert "under one sample interval (0.1 s)" in gm.summary()


def test_an_interval_reaching_the_unit_root_is_unbounded_above() -> None:
    gm = GaussMarkov(phi=0.9999, dt_s=0.1, tau_c_s=-0.1 / math.log(0.9999), sigma=math.nan,
                     q=math.nan, white=math.nan, units="deg/h", model="ARMA(2,1)",
                     phi_stderr=1e-4, tau_c_interval_s=(600.0, math.inf))
    assert gm.to_dict()["tau_c_interval_s"] == [600.0, None]
    assert "unbounded above" in gm.summary()


def test_an_arma11_with_a_positive_ma_coefficient_is_not_split() -> None:
    # phi = 0.9, theta = +0.5: not a Gauss-Markov process plus white noise (that needs
    # -phi < theta < 0), so sigma and q are not given, and the summary says why
    a = np.random.default_rng(18).normal(size=20_000)
    x = lfilter([1.0, 0.5], [1.0, -0.9], a)
    sel = fogts.select_arma(x, fs_hz=1.0, candidates=[(1, 1)])
    assert sel.selected.params["ma.L1"] > 0.4  # measured 0.50
    gm = gauss_markov(sel.selected, 1.0, "deg/h")
    assert gm is not None and math.isnan(gm.sigma) and math.isnan(gm.q)
    assert "MA coefficient between -phi and 0, and this fit's is not" in gm.summary()
