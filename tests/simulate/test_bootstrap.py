"""Parametric bootstrap by re-simulating the record (fogts.simulate.bootstrap, issue 15):
a round trip with known truth (the bootstrap standard error against the spread of fits to
independent records of the truth), the simulated specification, determinism, errors.

Records are 1 h at 10 Hz of white rate noise + rate random walk (N = 0.01 deg/sqrt(h),
K = 1 deg/h^1.5), fitted with N and K only, so that 40 + 40 GMWM fits take a few seconds.
"""

from __future__ import annotations

import dataclasses
import math
import warnings

import numpy as np
import pytest

import fogts.simulate.bootstrap as bootstrap_module
from fogts.allan import allan_deviation
from fogts.allan.gmwm_result import GaussMarkovTerm
from fogts.allan.ml import fit_noise_ml
from fogts.allan.noise import NoiseModel, fit_noise
from fogts.allan.result import AllanResult
from fogts.errors import DataError
from fogts.simulate.bootstrap import NoiseBootstrap, bootstrap_noise, simulation_specs
from fogts.simulate.gyro import simulate_gyro

TRUTH = {"N": 0.01, "K": 1.0}
FS, DURATION = 10.0, 3600.0
REPLICATES = 40


def _curve(seed: int) -> AllanResult:
    run = simulate_gyro(TRUTH, fs_hz=FS, duration_s=DURATION, rng=seed)
    curve = allan_deviation(run, taus="octave")
    assert isinstance(curve, AllanResult)
    return curve


def _gmwm(curve: AllanResult) -> NoiseModel:
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return fit_noise(curve, method="gmwm", terms="N,K")


@pytest.fixture(scope="module")
def fitted() -> tuple[AllanResult, NoiseModel, NoiseBootstrap]:
    curve = _curve(11)
    model = _gmwm(curve)
    return curve, model, bootstrap_noise(curve, model, n_replicates=REPLICATES, rng=5)


def test_round_trip_bootstrap_stderr_matches_the_truths_spread(
        fitted: tuple[AllanResult, NoiseModel, NoiseBootstrap]) -> None:
    """The bootstrap standard error from one record against the standard deviation of the
    GMWM fit over 40 independent records of the truth.  Each of the two is a standard
    deviation of 40 draws (relative error about 1/sqrt(2 x 39) = 11 %), so their ratio has
    a log-sd of about 0.16: [0.6, 1.6] is three of them.  K's bootstrap starts from the
    fitted K (its own error 15-20 %, and K's spread scales with K): [0.45, 1.8]."""
    _, model, boot = fitted
    spread = np.array([[m[t].value for t in ("N", "K")]
                       for m in (_gmwm(_curve(1000 + s)) for s in range(REPLICATES))])
    sd = spread.std(axis=0, ddof=1)
    assert 0.6 < boot.boot_stderr_of("N") / sd[0] < 1.6
    assert 0.45 < boot.boot_stderr_of("K") / sd[1] < 1.8
    # the replicates are centred on the fit they were drawn from: no bias beyond the
    # Monte-Carlo error of their mean (4 standard errors of a 40-draw mean)
    for i, t in enumerate(boot.terms):
        mc_se = boot.boot_stderr[i] / math.sqrt(REPLICATES)
        assert abs(boot.boot_mean[i] - model[t].value) < 4 * mc_se + 0.05 * model[t].value
    assert boot.n_failed == 0 and boot.replicates.shape == (REPLICATES, 2)


def test_the_result_presents_itself(
        fitted: tuple[AllanResult, NoiseModel, NoiseBootstrap]) -> None:
    _, model, boot = fitted
    assert boot.method == "gmwm" and boot.terms == ("N", "K")
    assert boot.estimate[0] == pytest.approx(model["N"].value, rel=1e-15)  # a copy
    frame = boot.to_frame()
    assert list(frame.index) == ["N", "K"] and "boot_stderr" in frame.columns
    doc = boot.to_dict()
    assert doc["terms"]["N"]["boot_stderr"] == pytest.approx(boot.boot_stderr[0], rel=1e-15)
    assert doc["n_replicates"] == REPLICATES and "36000 samples at 10 Hz" in doc["simulated"]
    assert "Parametric bootstrap of the GMWM fit (40 of 40" in boot.summary()
    for i in range(2):
        assert boot.ci_low[i] <= boot.boot_mean[i] <= boot.ci_high[i]
    with pytest.raises(DataError, match=r"term 'B' is not in the bootstrap; terms are: N, K"):
        boot.boot_stderr_of("B")


def test_a_fixed_seed_gives_the_same_replicates() -> None:
    """Same seed, same replicates (rel. 1e-12: the same arithmetic, run twice)."""
    curve = _curve(12)
    model = _gmwm(curve)
    a = bootstrap_noise(curve, model, n_replicates=10, rng=3)
    b = bootstrap_noise(curve, model, n_replicates=10, rng=3)
    np.testing.assert_allclose(a.replicates, b.replicates, rtol=1e-12)


def test_gauss_markov_terms_are_simulated_as_further_axes() -> None:
    """Two fitted Gauss-Markov terms: the first rides with the power laws, the second is a
    second spec; q_c = sigma sqrt(2 / T_c), so that the simulator's stationary sigma
    q_c sqrt(T_c / 2) (IEEE 952 Table C.1) is the fitted one (rel. 1e-12); B is 0 (the GM
    terms are the bias instability)."""
    model = _gmwm(_curve(13))
    assert model.gmwm is not None
    gms = (GaussMarkovTerm(0.3, 0.01, 30.0, 1.0), GaussMarkovTerm(0.2, 0.01, 300.0, 9.0))
    two = dataclasses.replace(model, gmwm=dataclasses.replace(model.gmwm, gauss_markov=gms))
    specs = simulation_specs(two)
    assert len(specs) == 2 and specs[0].B == 0.0 and specs[1].N == 0.0
    assert specs[0].N == pytest.approx(model["N"].value, rel=1e-12)
    for spec, g in zip(specs, gms, strict=True):
        assert spec.T_c == pytest.approx(g.t_c, rel=1e-12)
        assert spec.q_c * math.sqrt(spec.T_c / 2.0) == pytest.approx(g.sigma, rel=1e-12)


def test_least_squares_and_ml_fits_bootstrap_too() -> None:
    """WLS refits the curve, ML the simulated series; both give finite standard errors of
    N within a factor 2 of the fit's own (their ratio is about 1 with a 20-25 % scatter at
    10 replicates)."""
    curve = _curve(14)
    run = simulate_gyro(TRUTH, fs_hz=FS, duration_s=DURATION, rng=14)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        wls = fit_noise(curve, terms="N,K")
        ml = fit_noise_ml(run.rate, FS, terms="N,K", axis=curve.axis)
    for model in (wls, ml):
        boot = bootstrap_noise(curve, model, n_replicates=10, rng=4)
        assert boot.method == model.method
        assert 0.5 < boot.boot_stderr_of("N") / model["N"].stderr < 2.0


def test_failed_refits_are_counted_and_named(monkeypatch: pytest.MonkeyPatch,
                                             fitted: tuple[AllanResult, NoiseModel,
                                                           NoiseBootstrap]) -> None:
    curve, model, _ = fitted
    real = bootstrap_module._refit
    calls = {"n": 0}

    def flaky(*args: object) -> list[float]:
        calls["n"] += 1
        if calls["n"] % 4 == 0:
            raise DataError("simulated refit failure")
        return real(*args)  # type: ignore[arg-type]

    monkeypatch.setattr(bootstrap_module, "_refit", flaky)
    boot = bootstrap_noise(curve, model, n_replicates=16, rng=1)
    assert boot.n_failed == 4 and boot.replicates.shape == (12, 2)
    assert boot.failures == ("DataError: simulated refit failure",)
    def always(*args: object) -> list[float]:
        raise DataError("always")

    monkeypatch.setattr(bootstrap_module, "_refit", always)
    with pytest.raises(DataError, match=r"only 0 of 10 bootstrap refits succeeded \(at least "
                                        r"10 are needed\); first failure: DataError: always"):
        bootstrap_noise(curve, model, n_replicates=10, rng=1)


def test_bad_arguments(fitted: tuple[AllanResult, NoiseModel, NoiseBootstrap]) -> None:
    curve, model, _ = fitted
    with pytest.raises(DataError, match="n_replicates must be"):
        bootstrap_noise(curve, model, n_replicates=5)
    with pytest.raises(DataError, match="curve must be one AllanResult .one axis., got list"):
        bootstrap_noise([], model)  # type: ignore[arg-type]
    with pytest.raises(DataError, match="model must be a NoiseModel, got dict"):
        bootstrap_noise(curve, {})  # type: ignore[arg-type]
    other = dataclasses.replace(model, units="deg/s")
    with pytest.raises(DataError, match=r"model and curve disagree: the model was fitted to "
                                        r"oadev in deg/s, the curve is oadev in deg/h"):
        bootstrap_noise(curve, other)
