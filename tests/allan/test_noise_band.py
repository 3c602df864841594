"""The intervals of N and K allow for the unknown band limits of bias instability
(fogts/allan/noise_band.py)."""

from __future__ import annotations

import dataclasses
import math
import warnings
from typing import Any

import numpy as np
import pytest
from scipy.integrate import quad
from scipy.stats import norm

from fogts.allan import allan_deviation
from fogts.allan.markov import markov_avar
from fogts.allan.noise import NoiseModel, NoiseTerm, fit_noise
from fogts.allan.noise_band import flicker_share, mixture_interval
from fogts.allan.result import AllanResult
from tests.allan.gauss_markov_sum import GaussMarkovGyro

FS_HZ = 100.0
MEMS = {"N": 0.2, "B": 4.0, "K": 25.0}


def _markov_sum_share(tau: float, t_min: float) -> float:
    """Allan variance of Markov processes with correlation times t_min..inf, equal
    variance per ln T (IEEE 952 Annex C's closed form, integrated numerically), over the
    same integral from 0: the share h(tau / t_min) in closed form."""
    def avar(ln_t: float) -> float:
        t = math.exp(ln_t)
        q_c = math.sqrt(2.0 / t)  # unit stationary variance: sigma^2 = q_c^2 T / 2
        return float(markov_avar(q_c, t, np.array([tau]))[0])

    lo, hi = math.log(tau) - 40.0, math.log(tau) + 40.0
    part = quad(avar, math.log(t_min), hi, limit=400, epsabs=0.0, epsrel=1e-10)[0]
    whole = (quad(avar, lo, math.log(tau), limit=400, epsabs=0.0, epsrel=1e-10)[0]
             + quad(avar, math.log(tau), hi, limit=400, epsabs=0.0, epsrel=1e-10)[0])
    return part / whole


@pytest.mark.parametrize("u", [0.003, 0.0099, 0.0101, 0.1, 1.0, 7.0, 300.0])
def test_flicker_share_is_the_integrated_markov_allan_variance(u: float) -> None:
    """The closed form (and its series below u = 0.01) equals the numerical integral of
    the Markov Allan variance over the correlation times above T to 1e-6 (quadrature)."""
    assert flicker_share(np.array([u]))[0] == pytest.approx(_markov_sum_share(u, 1.0),
                                                            rel=1e-6, abs=1e-9)


def test_flicker_share_limits() -> None:
    """Flat flicker far above the limit, a random walk (slope 1) far below it, and the
    full-band integral 2 ln 2 (the flat level) as normalisation."""
    assert flicker_share(np.array([1e6]))[0] == pytest.approx(1.0, abs=1e-5)
    assert flicker_share(np.array([np.inf]))[0] == 1.0
    assert flicker_share(np.array([0.0]))[0] == 0.0
    u = np.array([1e-4, 2e-4])
    assert flicker_share(u) == pytest.approx(u / (3.0 * math.log(2.0)), rel=1e-3)


def _exact_curve(avar: np.ndarray, like: AllanResult) -> AllanResult:
    return dataclasses.replace(like, dev=np.sqrt(avar))


@pytest.fixture(scope="module")
def mems_record() -> AllanResult:
    rate = _gyro().simulate(fs_hz=FS_HZ, duration_s=10_800.0, seed=7100)
    curve = allan_deviation(rate, fs_hz=FS_HZ, taus="octave", units="deg/h")
    assert isinstance(curve, AllanResult)
    return curve


def _gyro() -> GaussMarkovGyro:
    return GaussMarkovGyro(N=MEMS["N"], B=MEMS["B"], K=MEMS["K"])


def _fit(curve: AllanResult, **kw: Any) -> NoiseModel:
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return fit_noise(curve, **kw)


def _plain(term: NoiseTerm, confidence: float = 0.683) -> tuple[float, float]:
    """The five-term interval a +- z se(a) of ``a = C^2``, in the term's units."""
    z = float(norm.ppf(0.5 + confidence / 2))
    rel = 2.0 * z * term.c_stderr / term.c_coeff
    return term.value * math.sqrt(max(1.0 - rel, 0.0)), term.value * math.sqrt(1.0 + rel)


def test_n_interval_covers_on_the_exact_gauss_markov_curve(mems_record: AllanResult) -> None:
    """On the noise-free Allan curve of the Gauss–Markov-sum simulator (flicker rolled off
    below 1 s) the five-term N is more than a standard error low; its interval, joined with
    the best band-limited fit's, reaches the truth, upwards only."""
    gyro = _gyro()
    model = _fit(_exact_curve(gyro.expected_avar(mems_record.tau_s, FS_HZ), mems_record))
    n = model["N"]
    lo, hi = _plain(n)
    assert (MEMS["N"] - n.value) / n.stderr > 1.0  # the bias the widening allows for
    assert hi < MEMS["N"] <= n.ci_high
    assert n.ci_low == pytest.approx(lo, abs=1e-3 * n.stderr)


def test_flat_flicker_curve_keeps_its_intervals(mems_record: AllanResult) -> None:
    """On the exact five-term curve (flat flicker) the flat line fits best, so every
    interval is the five-term fit's a +- z se(a), and the values are the truth."""
    tau = mems_record.tau_s
    avar = ((60 * MEMS["N"]) ** 2 / tau + 2 * math.log(2) / math.pi * MEMS["B"] ** 2
            + (MEMS["K"] / 60) ** 2 * tau / 3)
    model = _fit(_exact_curve(avar, mems_record))
    for name in ("N", "B", "K"):
        t = model[name]
        assert t.value == pytest.approx(MEMS[name], rel=1e-3)
        assert (t.ci_low, t.ci_high) == pytest.approx(_plain(t), rel=1e-12)


def test_b_and_k_intervals_reach_the_truth_on_the_exact_gauss_markov_curve(
        mems_record: AllanResult) -> None:
    """On the exact Gauss–Markov-sum curve the flat fit has B low and K high (0.70 and
    0.42 standard errors); the equal-weight mixture with the band-limited fit moves B's
    interval up and K's down so that both reach the truth, and each still contains its
    value."""
    model = _fit(_exact_curve(_gyro().expected_avar(mems_record.tau_s, FS_HZ), mems_record))
    b, k = model["B"], model["K"]
    assert b.value < MEMS["B"] and k.value > MEMS["K"]
    assert _plain(b)[1] < b.ci_high and k.ci_low < _plain(k)[0]
    for t in (b, k):
        assert t.ci_low <= MEMS[t.name] <= t.ci_high
        assert t.ci_low <= t.value <= t.ci_high


@pytest.mark.parametrize("shift", [-3.0, -0.5, 0.0, 0.7, 4.0])
def test_mixture_interval_is_the_central_interval_of_the_mixture(shift: float) -> None:
    """The ends are the 15.85 % and 84.15 % quantiles of N(a, se^2)/2 + N(a + d, se^2)/2."""
    a, se = 10.0, 1.0
    lo, hi = mixture_interval(a, se, shift, 0.683)

    def cdf(x: float) -> float:
        return float(0.5 * (norm.cdf(x - a) + norm.cdf(x - a - shift)))

    assert cdf(lo) == pytest.approx(0.1585, abs=1e-9)
    assert cdf(hi) == pytest.approx(0.8415, abs=1e-9)
    assert mixture_interval(a, 0.0, shift, 0.683) == (min(a, a + shift), max(a, a + shift))


@pytest.mark.parametrize("kw", [{"method": "ols"}, {"terms": "N,K"}])
def test_ols_and_a_fit_without_b_are_untouched(mems_record: AllanResult,
                                               kw: dict[str, str]) -> None:
    """The traditional OLS fit keeps its intervals; a fit without B has nothing to widen."""
    model = _fit(mems_record, **kw)
    for name in ("N", "K"):
        t = model[name]
        assert (t.ci_low, t.ci_high) == pytest.approx(_plain(t), rel=1e-12)
