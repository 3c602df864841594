"""The GMWM noise fit (fogts.allan.gmwm, gmwm_core, wv_models): the Haar wavelet-variance
closed forms against exact values, recovery of known parameters, error paths.

Records are short (1 to 2 h at 10 Hz) so the module runs in seconds; the 3 h / 100 Hz
study is ``python -m benchmarks.accuracy.gmwm`` (tests/README.md).
"""

from __future__ import annotations

import math
import warnings
from types import SimpleNamespace

import numpy as np
import pytest
from scipy.signal import lfilter
from scipy.stats import binom

from fogts.allan import allan_deviation
from fogts.allan.estimators import oadev
from fogts.allan.gmwm import fit_gmwm
from fogts.allan.noise import NoiseModel, fit_noise
from fogts.allan.wv_models import GM_PEAK, ar1_wv, power_law_wv, wv_from_avar
from fogts.errors import DataError, InsufficientDataError
from fogts.simulate.gyro import simulate_gyro
from tests.allan.gauss_markov_sum import GaussMarkovGyro, _gm_avar

FS_HZ = 10.0
GM_TRUTH = {"N": 0.01, "K": 1.0, "q_c": 0.3 / math.sqrt(15.0), "T_c": 30.0}


def _quiet_fit(curve: object, **kw: object) -> NoiseModel:
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return fit_gmwm(curve, **kw)  # type: ignore[arg-type]


# --------------------------------------------------------------------------- WV closed forms


def test_haar_modwt_wavelet_variance_is_half_the_overlapping_allan_variance() -> None:
    """The unbiased Haar-MODWT WV at scale m (half-difference of adjacent m-averages over
    the N - 2m + 1 boundary-free coefficients) equals oavar / 2 to rounding
    (Percival & Guttorp 1994)."""
    y = np.random.default_rng(3).standard_normal(4000).cumsum() * 0.01 + 1.0
    m = np.array([1, 2, 4, 8, 16])
    dev = oadev(y, fs_hz=1.0, m=m).dev
    for mi, d in zip(m, dev, strict=True):
        c = np.concatenate([[0.0], np.cumsum(y)])
        first = (c[mi:-mi] - c[:-2 * mi]) / mi
        second = (c[2 * mi:] - c[mi:-mi]) / mi
        wv = np.mean(((second - first) / 2.0) ** 2)
        assert wv == pytest.approx(float(wv_from_avar(np.array([d**2]))[0]), rel=1e-10)


@pytest.mark.parametrize(("fs", "t_c"), [(10.0, 0.05), (10.0, 3.0), (100.0, 30.0),
                                         (100.0, 5000.0), (1000.0, 20.0)])
def test_ar1_wv_matches_the_exact_block_sum_variance(fs: float, t_c: float) -> None:
    """Against the independent exact Allan variance of the sampled AR(1) in
    tests/allan/gauss_markov_sum.py (its own geometric sums): rel. 1e-8 (the reference
    loses digits for T_c >> dt, where 1e-4 is asked)."""
    tau = 2.0 ** np.arange(0, 16) / fs
    ref = _gm_avar(tau, fs, (t_c,), math.sqrt(2.5)) / 2.0
    rtol = 1e-8 if fs * t_c < 1e4 else 1e-4
    np.testing.assert_allclose(ar1_wv(2.5, t_c, tau, 1.0 / fs), ref, rtol=rtol)


@pytest.mark.parametrize("t_c", [2.0, 40.0, 2e4, 1e6])
def test_ar1_wv_matches_guerrier_et_al_form(t_c: float) -> None:
    """Guerrier et al. (2013)'s AR(1) Haar WV in the scale tau_j = 2m with the innovation
    variance sigma^2 = s^2 (1 - phi^2), evaluated in 50-digit arithmetic: rel. 1e-9 on
    both branches (exact form and small-dt/T_c expansion)."""
    mp = pytest.importorskip("mpmath")
    mp.mp.dps = 50
    s2 = 1.7
    phi = mp.e ** (-mp.mpf(1) / t_c)
    sig2 = s2 * (1 - phi**2)
    m = 2 ** np.arange(0, 14)
    ref = []
    for mi in m:
        tj = 2 * int(mi)
        num = 4 * phi ** (tj // 2 + 1) - phi ** (tj + 1) - phi**2 * tj / 2 + mp.mpf(tj) / 2 - 3 * phi
        ref.append(float(2 * sig2 * num / ((1 - phi) ** 2 * (1 - phi**2) * tj**2)))
    np.testing.assert_allclose(ar1_wv(s2, t_c, m.astype(float), 1.0), ref, rtol=1e-9)


def test_gm_peak_and_power_law_forms() -> None:
    """GM_PEAK is the maximum of nu^2 / s^2 (at tau = 1.89 T_c); the power laws are IEEE
    952's Allan variances halved: white sigma^2 dt/(2 tau) is Guerrier et al.'s
    sigma^2/tau_j with tau_j = 2m, drift a tau^2/4 their omega^2 tau_j^2/16."""
    h = np.geomspace(0.1, 10.0, 20001)
    v = ar1_wv(1.0, 1.0, h, 1e-9)
    assert float(np.max(v)) == pytest.approx(GM_PEAK, abs=1e-4)
    assert float(h[np.argmax(v)]) == pytest.approx(1.89, abs=0.01)
    m = np.array([1.0, 4.0, 32.0])
    dt, sigma2, omega = 0.1, 3.0, 0.2   # white variance; drift per sample of the rate
    np.testing.assert_allclose(power_law_wv(sigma2 * dt, -1, m * dt), sigma2 / (2 * m))
    a_r = (omega / dt) ** 2 / 2.0   # sigma_A^2 = R^2 tau^2 / 2 with R = omega / dt per s
    np.testing.assert_allclose(power_law_wv(a_r, 2, m * dt), omega**2 * (2 * m) ** 2 / 16)


def test_ar1_wv_against_fogts_allan_variance_of_simulated_ar1() -> None:
    """fogts' own oadev of simulated sampled AR(1) records (scipy.signal.lfilter) averages
    to the closed form: 8 records, each tau within 4 standard errors of the mean."""
    tau = np.array([0.1, 1.0, 10.0, 40.0])
    t_c, s2 = 5.0, 0.1
    phi = math.exp(-1.0 / (FS_HZ * t_c))
    vals = []
    for seed in range(8):
        e = np.random.default_rng(seed).standard_normal(40_000) * math.sqrt(s2 * (1 - phi**2))
        x, _ = lfilter([1.0], [1.0, -phi], e, zi=[phi * math.sqrt(s2) * 0.0])
        vals.append(oadev(x, fs_hz=FS_HZ, m=np.rint(tau * FS_HZ)).dev ** 2 / 2.0)
    arr = np.array(vals)
    expected = ar1_wv(s2, t_c, tau, 1.0 / FS_HZ)
    se = arr.std(axis=0, ddof=1) / math.sqrt(arr.shape[0])
    assert np.all(np.abs(arr.mean(axis=0) - expected) <= 4 * se + 0.02 * expected)


# --------------------------------------------------------------------------- recovery


@pytest.fixture(scope="module")
def gm_fits() -> list[NoiseModel]:
    """White + RW + one GM, 2 h at 10 Hz, six seeds."""
    out = []
    for seed in range(11, 17):
        run = simulate_gyro(GM_TRUTH, fs_hz=FS_HZ, duration_s=7200, rng=seed)
        out.append(_quiet_fit(allan_deviation(run, taus="octave")))
    return out


def test_white_rw_gm_recovers_n_and_the_markov_term(gm_fits: list[NoiseModel]) -> None:
    """N within 2 %, the GM's correlation time within a factor 2 in most records, and the
    68 % intervals of N and K together cover the truth at least as often as the 1 %
    binomial quantile of 12 draws at p = 0.68 allows."""
    n_ok = sum(abs(m["N"].value / GM_TRUTH["N"] - 1) < 0.02 for m in gm_fits)
    assert n_ok == len(gm_fits)
    t_ok = 0
    for m in gm_fits:
        assert m.gmwm is not None and m.method == "gmwm"
        gms = m.gmwm.gauss_markov
        t_ok += any(0.5 < g.t_c / GM_TRUTH["T_c"] < 2.0 for g in gms)
    assert t_ok >= len(gm_fits) - 1
    covered = sum(m[t].ci_low <= GM_TRUTH[t] <= m[t].ci_high for m in gm_fits for t in "NK")
    assert covered >= binom.ppf(0.01, 2 * len(gm_fits), 0.68)


def test_flicker_as_gm_sum_gives_the_equivalent_b() -> None:
    """White + a five-GM sum (tests/allan/gauss_markov_sum.py, B = flicker-equivalent
    level) + RW, 2 h at 10 Hz, four seeds: the median |relative error| of B below 25 %."""
    gyro = GaussMarkovGyro(N=0.01, B=0.15, K=1.0)
    errs = []
    for seed in range(21, 25):
        rate = gyro.simulate(fs_hz=FS_HZ, duration_s=7200.0, seed=seed)
        curve = allan_deviation(rate, fs_hz=FS_HZ, taus="octave", units="deg/h")
        errs.append(abs(_quiet_fit(curve)["B"].value / 0.15 - 1))
    assert float(np.median(errs)) < 0.25


def test_result_records_method_j_test_and_limits(gm_fits: list[NoiseModel]) -> None:
    m = gm_fits[0]
    d = m.to_dict()
    assert d["method"] == "gmwm" and "gmwm" in d
    assert set(d["gmwm"]) >= {"model", "j_stat", "dof", "p_value", "verdict", "candidates"}
    assert 0 < d["gmwm"]["dof"] < m.tau_s.size
    assert "GMWM J test" in m.summary()
    q = m["Q"]            # not in the simulation: dropped, reported as an upper limit
    assert q.status == "dropped" and q.is_limit and q.value == 0 and q.ci_high > 0
    assert np.all(np.isfinite(m.fitted_dev))


def test_wls_result_has_no_gmwm_block(gm_fits: list[NoiseModel]) -> None:
    run = simulate_gyro(GM_TRUTH, fs_hz=FS_HZ, duration_s=1800, rng=2)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        wls = fit_noise(allan_deviation(run, taus="octave"))
    assert wls.gmwm is None and "gmwm" not in wls.to_dict()


def test_fit_noise_dispatches_and_bootstrap_runs() -> None:
    run = simulate_gyro({"N": 0.01, "K": 1.0}, fs_hz=FS_HZ, duration_s=3600, rng=5)
    curve = allan_deviation(run, taus="octave")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        via = fit_noise(curve, method="gmwm", terms="N,K")
        boot = fit_gmwm(curve, terms="N,K", n_bootstrap=20, rng=1)
    assert via.method == "gmwm" and via["N"].value == pytest.approx(0.01, rel=0.02)
    assert boot.gmwm is not None and boot.gmwm.n_bootstrap == 20
    assert "bootstrap" in boot.stderr_method
    assert boot["N"].stderr == pytest.approx(via["N"].stderr, rel=0.5)


# --------------------------------------------------------------------------- errors


@pytest.fixture(scope="module")
def small_curve() -> object:
    run = simulate_gyro({"N": 0.01, "K": 1.0}, fs_hz=FS_HZ, duration_s=1200, rng=9)
    return allan_deviation(run, taus="octave")


def test_bad_method_lists_gmwm(small_curve: object) -> None:
    with pytest.raises(DataError, match=r"method must be one of wls, gls, ols, gmwm, ml; got 'fast'"):
        fit_noise(small_curve, method="fast")  # type: ignore[arg-type]


@pytest.mark.parametrize(("kw", "match"), [
    ({"terms": "N,M"}, r"terms M .*not fitted by method='gmwm'.*Q, N, B, K, R"),
    ({"terms": "N,X"}, r"terms must be drawn from Q, N, B, K, R; got 'X'"),
    ({"max_gm": 5}, r"max_gm must be an integer in 0\.\.3, got 5"),
    ({"max_gm": 1.5}, r"max_gm must be an integer in 0\.\.3, got 1\.5"),
    ({"n_bootstrap": 5}, r"n_bootstrap must be 0 or at least 20, got 5"),
    ({"significance": 0.7}, r"significance must be in \(0, 0\.5\), got 0\.7"),
])
def test_bad_arguments_name_the_argument(small_curve: object, kw: dict[str, object],
                                         match: str) -> None:
    with pytest.raises(DataError, match=match):
        fit_gmwm(small_curve, **kw)  # type: ignore[arg-type]


def test_curve_without_m_or_of_another_kind_is_refused(small_curve: object) -> None:
    bare = SimpleNamespace(kind="oadev", units="deg/h", axis="x", tau_s=small_curve.tau_s,  # type: ignore[attr-defined]
                           dev=small_curve.dev, edf=small_curve.edf)  # type: ignore[attr-defined]
    with pytest.raises(DataError, match="needs the curve's m, n_samples and fs_hz"):
        fit_gmwm(bare)
    run = simulate_gyro({"N": 0.01}, fs_hz=FS_HZ, duration_s=600, rng=1)
    tot = allan_deviation(run, kind="totdev", taus="octave")
    with pytest.raises(DataError, match="needs an oadev or adev curve, got kind 'totdev'"):
        fit_gmwm(tot)


def test_too_few_taus(small_curve: object) -> None:
    short = small_curve.within(None, 0.4)  # type: ignore[attr-defined]
    with pytest.raises(InsufficientDataError, match=r"usable taus; method='gmwm' needs"):
        fit_gmwm(short)
