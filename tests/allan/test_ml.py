"""Exact Gaussian maximum likelihood of the noise model (fogts.allan.ml, ml_model)."""

from __future__ import annotations

import math
import warnings

import numpy as np
import pytest
from scipy.stats import binom, multivariate_normal
from statsmodels.tsa.statespace.sarimax import SARIMAX

from fogts.allan import allan_deviation
from fogts.allan.ml import fit_noise_ml
from fogts.allan.ml_model import BlockData, Structure, block_data, block_loglike
from fogts.allan.noise import fit_noise
from fogts.errors import DataError
from fogts.simulate.gyro import simulate_gyro

#: white + RW + one GM, scaled so that each dominates part of the record at 5 Hz
#: (8000 s; N 0.01 deg/sqrt(h), K 1 deg/h^1.5, GM sigma 0.3 deg/h, T_c 30 s)
GM_CASE = {"N": 0.01, "K": 1.0, "q_c": 0.3 / math.sqrt(15.0), "T_c": 30.0}
GM_SIGMA = 0.3
FS = 5.0


def _fit(seed: int, **kwargs: object) -> object:
    run = simulate_gyro(GM_CASE, fs_hz=FS, duration_s=8000, rng=seed)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return fit_noise_ml(run.rate, FS, terms="N,B,K", b_model="gm", max_gm=1,
                            **kwargs)  # type: ignore[arg-type]


def _dense_cov(n: int, delta: float, a_white: float, k2: float, p0: float,
               gms: list[tuple[float, float]]) -> np.ndarray:
    """Covariance of interval means over ``delta`` of white + Brownian motion (start
    variance ``p0``) + Gauss-Markov terms, from the continuous-time covariances."""
    i = np.arange(1, n + 1)
    ii, jj = np.meshgrid(i, i, indexing="ij")
    cov = p0 + k2 * delta * (np.minimum(ii, jj) - 0.5)
    cov[np.diag_indices(n)] = p0 + k2 * delta * (i - 2.0 / 3.0)
    lag = np.abs(ii - jj)
    for s2, t_c in gms:
        h = delta / t_c
        g = s2 * (-math.expm1(-h) / h) ** 2 * np.exp(-h * np.maximum(lag - 1, 0))
        g[lag == 0] = s2 * 2 * (h + math.expm1(-h)) / h**2
        cov = cov + g
    return cov + np.eye(n) * a_white / delta


def test_block_loglike_equals_dense_gaussian_density() -> None:
    """The Kalman filter of the aggregated model against the dense Gaussian density of the
    same block means (scipy), covariance from the continuous-time processes: agreement
    to rounding, far below 1e-8 relative (both are exact; only the order of the floating
    point operations differs)."""
    n, delta, gms = 80, 0.5, [(2.0, 1.3), (0.5, 40.0)]
    cov = _dense_cov(n, delta, 0.7, 0.3, 5.0, gms)
    y = np.random.default_rng(1).multivariate_normal(np.zeros(n), cov)
    theta = np.log([0.7, 0.3, 2.0, 1.3, 0.5, 40.0])
    ll = block_loglike(theta, Structure(True, True, 2, False), BlockData(y, 1, delta, 1.0,
                                                                        0.0, n), level_var=5.0)
    ref = multivariate_normal(np.zeros(n), cov).logpdf(y)
    assert ll == pytest.approx(ref, rel=1e-8)


def test_diffuse_loglike_equals_statsmodels_sarimax_of_differences() -> None:
    """White + RW with a diffuse bias: the first differences are an MA(1) with
    ``gamma_0 = 2 k^2 D / 3 + 2 a / D``, ``gamma_1 = k^2 D / 6 - a / D``; statsmodels'
    SARIMAX likelihood of the differences equals the diffuse likelihood up to the
    ``-ln(2 pi) / 2`` statsmodels gives the one diffuse observation.  1e-8 relative: both
    are exact recursions in double precision (seen: 6e-15)."""
    delta, k2, a_white = 0.5, 0.3, 0.7
    g = np.random.default_rng(2)
    y = np.cumsum(g.standard_normal(300)) * 0.3 + g.standard_normal(300)
    ll = block_loglike(np.log([a_white, k2]), Structure(True, True, 0, False),
                       BlockData(y, 1, delta, 1.0, 0.0, y.size))
    g0 = 2 * k2 * delta / 3 + 2 * a_white / delta
    g1 = k2 * delta / 6 - a_white / delta
    r = g1 / g0
    ma = (1 - math.sqrt(1 - 4 * r * r)) / (2 * r)
    ref = SARIMAX(np.diff(y), order=(0, 0, 1), trend="n").loglike(np.array([ma, g1 / ma]))
    assert ll + 0.5 * math.log(2 * math.pi) == pytest.approx(ref, rel=1e-8)


def test_steady_state_gain_matches_the_full_filter() -> None:
    """statsmodels' steady-state shortcut (its ``tolerance``) against the full recursion."""
    run = simulate_gyro(GM_CASE, fs_hz=FS, duration_s=2000, rng=3)
    data = block_data(run.rate, 1 / FS, 2)
    theta = np.log([1.0, 1e-3, 0.2, 30.0])
    st = Structure(True, True, 1, False)
    fast = block_loglike(theta, st, data)
    assert fast == pytest.approx(block_loglike(theta, st, data, tolerance=0.0), rel=1e-8)


def test_recovery_and_pooled_coverage() -> None:
    """N, K and the GM's sigma and T_c over 10 records: median errors small, and the 40
    68.3 % intervals cover the truth as often as a binomial(40, 0.683) allows (0.1 %
    two-sided bounds)."""
    truth = {"N": 0.01, "K": 1.0, "sigma": GM_SIGMA, "T_c": 30.0}
    hits, errors = 0, {k: [] for k in truth}
    for seed in range(10):
        model = _fit(100 + seed, max_blocks=1024)
        gm = model.ml.gauss_markov[0]  # type: ignore[attr-defined]
        est = {"N": (model["N"].value, model["N"].ci_low, model["N"].ci_high),  # type: ignore[index]
               "K": (model["K"].value, model["K"].ci_low, model["K"].ci_high)}  # type: ignore[index]
        for key, v, se in (("sigma", gm.sigma, gm.sigma_stderr), ("T_c", gm.t_c, gm.t_c_stderr)):
            est[key] = (v, v * math.exp(-se / v), v * math.exp(se / v))
        for key, (v, lo, hi) in est.items():
            errors[key].append(abs(v / truth[key] - 1))
            hits += int(lo <= truth[key] <= hi)
    lo, hi = binom.ppf(0.0005, 40, 0.683), binom.ppf(0.9995, 40, 0.683)
    assert lo <= hits <= hi
    assert np.median(errors["N"]) < 0.01
    assert np.median(errors["sigma"]) < 0.15
    assert np.median(errors["T_c"]) < 0.4
    assert np.median(errors["K"]) < 0.3


def test_decimated_fit_agrees_with_the_undecimated_one() -> None:
    """Block means of 4 (with the within-block likelihood) against every sample: the
    estimates differ by a fraction of their standard errors.  K (truth 1 deg/h^1.5) is
    unidentifiable in 1600 s: it lands within 0.02 of its bound 0 (standard error 0.25), on
    the bound or just above it as the BLAS kernel and thread count move the last bits.  A
    term on its bound has no standard error, so the scale is the other fit's."""
    run = simulate_gyro(GM_CASE, fs_hz=FS, duration_s=1600, rng=11)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        full = fit_noise_ml(run.rate, FS, terms="N,B,K", b_model="gm", max_gm=1, decimate=1)
        dec = fit_noise_ml(run.rate, FS, terms="N,B,K", b_model="gm", max_gm=1, decimate=4)
    assert full.ml is not None and dec.ml is not None
    assert (full.ml.decimation, dec.ml.decimation) == (1, 4)
    for name in ("N", "B", "K"):
        a, b = full[name], dec[name]
        scale = [se for se in (a.stderr, b.stderr) if math.isfinite(se)]
        if scale:
            assert abs(b.value - a.value) < 0.5 * max(scale)
        else:
            assert a.at_bound and b.at_bound and a.value == b.value
    g_full, g_dec = full.ml.gauss_markov[0], dec.ml.gauss_markov[0]
    assert abs(g_dec.t_c - g_full.t_c) < 0.5 * g_full.t_c_stderr


def test_flicker_model_and_summary() -> None:
    """A white + flicker + RW record: the flicker model wins, B near the truth, and the
    summary shows the likelihood, not the least-squares term selection."""
    run = simulate_gyro({"N": 0.01, "B": 0.15, "K": 1.0}, fs_hz=FS, duration_s=4000, rng=5)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        model = fit_noise_ml(run.rate, FS, max_blocks=1024, axis="x")
    assert model.method == "ml" and model.ml is not None
    assert model.ml.model == "N + B + K"
    assert abs(model["B"].value / 0.15 - 1) < 0.3
    text = model.summary()
    assert "ML model: N + B + K" in text and "term selection" not in text
    assert model.to_dict()["ml"]["decimation"] == model.ml.decimation
    assert model.axis == "x"


def test_an_unmeasured_rate_random_walk_is_an_upper_limit() -> None:
    """White + GM without a random walk, fitted with K: K is reported as a limit (at zero
    with a likelihood-ratio bound, or fitted with z < 2), never as a measured value."""
    run = simulate_gyro({"N": 0.01, "q_c": GM_CASE["q_c"], "T_c": 30.0}, fs_hz=FS,
                        duration_s=2000, rng=1)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        model = fit_noise_ml(run.rate, FS, b_model="gm", max_gm=1)
    assert model["K"].is_limit and 0 < model.upper_limit("K") < 1.0
    assert not model["N"].is_limit


def test_gmwm_summary_has_no_term_selection_line() -> None:
    run = simulate_gyro({"N": 0.01, "K": 1.0}, fs_hz=FS, duration_s=2000, rng=1)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        model = fit_noise(allan_deviation(run, taus="octave"), terms="N,B,K", method="gmwm")
    assert "term selection" not in model.summary()
    assert "GMWM model" in model.summary()


def test_fit_noise_method_ml_names_fit_noise_ml() -> None:
    run = simulate_gyro({"N": 0.01}, fs_hz=FS, duration_s=200, rng=1)
    with pytest.raises(DataError, match="fit_noise_ml"):
        fit_noise(allan_deviation(run, taus="octave"), method="ml")


@pytest.mark.parametrize(("kwargs", "match"), [
    ({"terms": "Q,N"}, r"terms Q .*use terms from N, B, K, R, got 'Q,N'"),
    ({"terms": "R"}, r"at least one of N, B, K, got 'R'"),
    ({"decimate": "often"}, r"decimate must be 'auto' or an integer >= 1, got 'often'"),
    ({"decimate": 0}, r"decimate"),
    ({"decimate": 100}, r"10 blocks of decimate = 100; .* at least 64 blocks"),
    ({"b_model": "pink"}, r"b_model must be one of auto, flicker, gm; got 'pink'"),
    ({"max_gm": 4}, r"max_gm"),
    ({"confidence": 1.5}, r"confidence"),
    ({"fs_hz": -1.0}, r"fs_hz"),
])
def test_bad_arguments_are_named(kwargs: dict[str, object], match: str) -> None:
    rate = np.random.default_rng(0).standard_normal(1000)
    args: dict[str, object] = {"fs_hz": 10.0, **kwargs}
    fs = args.pop("fs_hz")
    with pytest.raises(DataError, match=match):
        fit_noise_ml(rate, fs, **args)  # type: ignore[arg-type]


def test_observed_cov_holds_an_unidentified_parameter_fixed(
        monkeypatch: pytest.MonkeyPatch) -> None:
    """-log L = x'Hx / 2 with H indefinite in its middle parameter (negative curvature, as
    a variance the data do not identify, seen on ADIS16405 run 4 Z): that parameter is
    held fixed (zero row) and the others' covariance is the inverse of their own 2x2 block
    of H, not a block of the inverse of the whole (whose diagonal is negative there).  A
    parameter at its bound (``free`` False) is held too.  Tolerance 1e-6: approx_hess3's
    central differences are exact on a quadratic up to rounding."""
    import fogts.allan.ml_model as mm

    h = np.array([[4.0, 0.3, 1.0], [0.3, -0.01, 0.2], [1.0, 0.2, 2.0]])
    monkeypatch.setattr(mm, "log_likelihood", lambda t, st, data: -0.5 * float(t @ h @ t))
    theta = np.array([0.1, -0.2, 0.3])
    assert np.any(np.diag(np.linalg.inv(h)) < 0)
    cov = mm.observed_cov(theta, None, None, np.ones(3, dtype=bool))  # type: ignore[arg-type]
    keep = np.ix_([0, 2], [0, 2])
    np.testing.assert_allclose(cov[keep], np.linalg.inv(h[keep]), rtol=1e-6)
    assert np.all(cov[1] == 0.0) and np.all(cov[:, 1] == 0.0)
    bound = mm.observed_cov(theta, None, None,  # type: ignore[arg-type]
                            np.array([True, True, False]))
    assert np.all(bound[2] == 0.0)
    np.testing.assert_allclose(bound[0, 0], 1.0 / 4.0, rtol=1e-6)  # then b drops: a alone
