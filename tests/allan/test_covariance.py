"""Tests for fogts.allan.covariance: the model covariance of Allan-variance estimates.

Checked against NIST SP1065's EDF formulas, exact quadratic forms of the phase covariance,
and Monte-Carlo variances and correlations (allantools, simulate_gyro; fixed seeds).
"""

from __future__ import annotations

import math
from collections.abc import Callable

import allantools
import numpy as np
import pytest

import fogts.allan.covariance as covariance_module
from fogts.allan.covariance import CovarianceModel, model_covariance
from fogts.allan.noise_lsq import curve_covariance_basis
from tests.allan.noise_cases import unit_curve


def test_covariance_model_reproduces_sp1065_edf() -> None:
    """White FM: SP1065 Table 5 overlapping-ADEV EDF [3(N-1)/2m - 2(N-2)/N] 4m^2/(4m^2+5);
    white PM: the exact discrete value 36 M^2 / (70 M - 36 m), M = N - 2m + 1 terms
    (SP1065's (N+1)(N-2m)/2(N-m) is an approximation of it)."""
    n = 100_000
    m = np.array([1, 2, 4, 16, 64, 256])
    curve = unit_curve(m, kind="oadev", n_samples=n)
    powers = np.array([-2, -1], dtype=np.int64)
    basis = curve_covariance_basis(curve, powers)
    assert basis is not None
    var_wfm = np.diag(model_covariance(basis, np.array([0.0, 1.0]), powers))
    edf_wfm = 2 * (1.0 / m) ** 2 / var_wfm
    big_n = n + 1
    sp1065 = (3 * (big_n - 1) / (2 * m) - 2 * (big_n - 2) / big_n) * 4 * m**2 / (4 * m**2 + 5)
    np.testing.assert_allclose(edf_wfm, sp1065, rtol=5e-4)
    var_wpm = np.diag(model_covariance(basis, np.array([1.0, 0.0]), powers))
    edf_wpm = 2 * (1.0 / m**2) ** 2 / var_wpm
    terms = n - 2 * m + 1  # cnt(h) = M - |h| pairs at lags 0, +-m, +-2m: 36, 16, 1 (s^4)
    np.testing.assert_allclose(edf_wpm, 36 * terms**2 / (70 * terms - 36 * m), rtol=1e-9)


def test_covariance_model_matches_monte_carlo_correlations() -> None:
    """Correlation of OAVAR estimates at m = 16, 32, 64, 128 against 400 allantools runs."""
    n, reps = 4000, 400
    m = np.array([16, 32, 64, 128])
    curve = unit_curve(m, kind="oadev", n_samples=n)
    rng = np.random.default_rng(7)
    # unit white rate noise: sigma^2 = 1/tau (a_-1 = 1); a rate random walk with unit steps:
    # sigma^2 = tau/3 (a_1 = 1/3)
    for power, coef, make in ((-1, 1.0, lambda: rng.standard_normal(n)),
                              (1, 1.0 / 3.0, lambda: np.cumsum(rng.standard_normal(n)))):
        sims = np.array([allantools.oadev(make(), rate=1.0, data_type="freq",
                                          taus=m.astype(float))[1] ** 2 for _ in range(reps)])
        powers = np.array([power], dtype=np.int64)
        basis = curve_covariance_basis(curve, powers)
        assert basis is not None
        cov = model_covariance(basis, np.array([coef]), powers)
        model_corr = cov / np.sqrt(np.outer(np.diag(cov), np.diag(cov)))
        np.testing.assert_allclose(np.corrcoef(sims.T), model_corr, atol=0.1)
        # variance itself within the Monte-Carlo error (sd of a variance ~ sqrt(2/reps))
        scale = sims.mean(axis=0)
        emp = sims.var(axis=0, ddof=1) / scale**2
        mod = np.diag(cov) / (coef * m.astype(float) ** power) ** 2
        np.testing.assert_allclose(emp, mod, rtol=0.3)


def _adev_cov_exact(m: np.ndarray, n: int, sigma: np.ndarray) -> np.ndarray:
    """Cov of non-overlapping Allan variances straight from the phase covariance matrix:
    q_i = x' A_i x with A_i = D_i' D_i / (2 m_i^2 n_i), Cov[q_i, q_j] = 2 tr(A_i S A_j S)."""
    mats = []
    for mm in m:
        terms = n // mm - 1
        d = np.zeros((terms, n + 1))
        k = np.arange(terms)
        d[k, k * mm] += 1.0
        d[k, (k + 1) * mm] -= 2.0
        d[k, (k + 2) * mm] += 1.0
        mats.append(d.T @ d / (2.0 * mm**2 * terms))
    return np.array([[2.0 * np.trace(a @ sigma @ b @ sigma) for b in mats] for a in mats])


def test_adev_covariance_matches_exact_quadratic_forms(monkeypatch: pytest.MonkeyPatch) -> None:
    """Non-overlapping estimates at m = 1, 2, 3, 5, 7, 12 (61 phase points): the lattice sums
    against 2 tr(A S B S) with the exact phase covariance S of unit white PM (s^2 = 1/3,
    a_-2 = 1), white FM (random walk, min(s, t)) and interval-averaged RW FM
    (K'^2 (s^2 t / 2 - s^3 / 6), K'^2 = 3 a_1).  The grid has octave pairs (one residue
    class), pairs summed class by class and pairs averaged over the phases (5, 7)."""
    n = 60
    m = np.array([1, 2, 3, 5, 7, 12])
    curve = unit_curve(m, kind="adev", n_samples=n)
    s, t = np.meshgrid(np.arange(n + 1.0), np.arange(n + 1.0), indexing="ij")
    lo, hi = np.minimum(s, t), np.maximum(s, t)
    phase_cov = {-2: np.eye(n + 1) / 3.0, -1: lo, 1: 3.0 * (lo**2 * hi / 2 - lo**3 / 6)}

    def worst(power: int) -> float:
        powers = np.array([power], dtype=np.int64)
        basis = curve_covariance_basis(curve, powers)
        assert basis is not None
        model = model_covariance(basis, np.array([1.0]), powers)
        exact = _adev_cov_exact(m, n, phase_cov[power])
        return float(np.max(np.abs(model - exact)
                            / np.sqrt(np.outer(np.diag(exact), np.diag(exact)))))

    # default: the (5, 7) pair is phase-averaged; within 3 % on the correlation scale
    assert max(worst(p) for p in phase_cov) < 0.03
    monkeypatch.setattr(covariance_module, "_MAX_PHASES", 10**9)  # every residue class summed
    for power in phase_cov:
        assert worst(power) < 1e-9


def test_lattice_count_matches_enumeration() -> None:
    """Pairs (k, l) with l m_j - k m_i = lag, counted in closed form and by enumeration."""
    from fogts.allan.covariance import _lattice_count

    for mi, mj, ni, nj in [(1, 4, 50, 11), (4, 6, 20, 13), (5, 7, 11, 7), (7, 8, 2, 2),
                           (3, 3, 9, 9), (6, 15, 40, 15)]:
        g = math.gcd(mi, mj)
        k, l_ = np.meshgrid(np.arange(ni), np.arange(nj), indexing="ij")
        lags = l_ * mj - k * mi
        for c in range(3):
            for c2 in range(3):
                lag = c * mi - c2 * mj
                assert _lattice_count(lag, mi // g, mj // g, g, ni, nj) == np.count_nonzero(
                    lags == lag), (mi, mj, lag)


def _mc_study(kind: str, make: Callable[[], np.ndarray], m: np.ndarray, reps: int
              ) -> tuple[np.ndarray, np.ndarray]:
    from fogts.allan.estimators import adev, totdev
    est = {"adev": adev, "totdev": totdev}[kind]
    sims = np.array([est(make(), fs_hz=1.0, m=m).dev ** 2 for _ in range(reps)])
    return sims.mean(axis=0), np.cov(sims.T)


@pytest.mark.parametrize("noise", ["N", "B", "K"])
def test_adev_and_totdev_covariance_match_monte_carlo(noise: str) -> None:
    """800 records of 1024 samples (simulate_gyro, fixed seed) of white, flicker or RW FM.

    adev: the model covariance's relative variances within 25 % and correlations within
    0.15 of the Monte-Carlo ones (sampling errors ~5 % and <= 0.035, max over 28 pairs).
    totdev (EDF variances + oadev correlations): the same, from m = 4 on (SP1065's totdev
    EDF is for larger m: at m = 1 totdev *is* oadev, and the EDF understates its variance
    for white FM)."""
    from fogts.allan.edf import edf_for
    from fogts.simulate.gyro import simulate_gyro

    n, reps = 1024, 800
    m = 2 ** np.arange(0, 8)
    rng = np.random.default_rng(11)
    power, alpha = {"N": (-1, 0), "B": (0, -1), "K": (1, -2)}[noise]

    def make() -> np.ndarray:
        run = simulate_gyro({noise: 1.0}, fs_hz=1.0, duration_s=float(n), rng=rng)
        return np.asarray(run.rate, dtype=np.float64).ravel()

    powers = np.array([power], dtype=np.int64)
    for kind, first in (("adev", 0), ("totdev", 2)):
        mean, cov = _mc_study(kind, make, m, reps)
        basis_kind = "adev" if kind == "adev" else "oadev"
        curve = unit_curve(m, kind=basis_kind, n_samples=n)
        basis = curve_covariance_basis(curve, powers)
        assert basis is not None
        a = np.array([float(np.median(mean / m.astype(float) ** power))])
        edf = edf_for("totdev", np.full(m.size, alpha), m, n + 1)
        model = CovarianceModel(basis, powers, kind)(a, mean, edf)
        keep = slice(first, None)
        rel_emp = np.diag(cov)[keep] / mean[keep] ** 2
        rel_mod = np.diag(model)[keep] / mean[keep] ** 2
        np.testing.assert_allclose(rel_emp, rel_mod, rtol=0.25)
        corr_emp = cov / np.sqrt(np.outer(np.diag(cov), np.diag(cov)))
        corr_mod = model / np.sqrt(np.outer(np.diag(model), np.diag(model)))
        np.testing.assert_allclose(corr_emp[keep, keep], corr_mod[keep, keep], atol=0.15)


def test_totdev_covariance_model() -> None:
    """totdev: EDF variances 2 mu^2 / edf on the diagonal, oadev's correlations off it; a
    model without random terms (R only) leaves the diagonal alone."""

    m = np.array([1, 2, 4, 8, 16])
    curve = unit_curve(m, kind="totdev", n_samples=1000)
    powers = np.array([-1, 1], dtype=np.int64)
    basis = curve_covariance_basis(curve, powers)
    assert basis is not None
    a = np.array([1.0, 0.01])
    mu = a[0] / m + a[1] * m
    edf = 1000.0 / m
    tot = CovarianceModel(basis, powers, "totdev")(a, mu, edf)
    np.testing.assert_allclose(np.diag(tot), 2 * mu**2 / edf, rtol=1e-12)
    oad = CovarianceModel(basis, powers, "oadev")(a, mu, edf)
    np.testing.assert_allclose(tot / np.sqrt(np.outer(np.diag(tot), np.diag(tot))),
                               oad / np.sqrt(np.outer(np.diag(oad), np.diag(oad))), rtol=1e-12)
    ramp = CovarianceModel(basis, np.array([2], dtype=np.int64), "totdev")
    np.testing.assert_allclose(ramp(np.array([1.0]), mu, edf), np.diag(2 * mu**2 / edf))
    assert "totdev EDF variances" in CovarianceModel(basis, powers, "totdev").label
