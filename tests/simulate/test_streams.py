"""Tests of fogts.simulate.streams: every synthesis against its closed-form Allan variance.

Truth comes from the closed forms of IEEE Std 952-1997, Annex C, Table C.1
(:meth:`NoiseSpec.avar`), and the Allan deviations are computed by allantools (an
independent implementation).  Statistical tolerance: each term is simulated as 64
independent replicas (independent axes), and at every tau the closed form must lie within
4 standard errors of the replicas' mean Allan variance (the standard error estimated from
the replicas themselves), so the test needs no EDF approximation.
"""

from __future__ import annotations

import math

import allantools
import numpy as np
import pytest

from fogts.simulate.gyro import simulate_gyro
from fogts.simulate.noise_spec import NoiseSpec, markov_avar
from fogts.simulate.streams import flicker_poles

FS = 100.0
REPLICAS = 64
N_REP = 1 << 14  # samples per replica (163.84 s at 100 Hz)


def _replica_avar(spec: dict | NoiseSpec, m: np.ndarray, *, seed: int = 11,
                  flicker: str = "markov") -> tuple[np.ndarray, np.ndarray]:
    run = simulate_gyro(spec, fs_hz=FS, duration_s=N_REP / FS, rng=seed, n_axes=REPLICAS,
                        flicker=flicker)
    av = np.empty((REPLICAS, m.size))
    for i in range(REPLICAS):
        taus, dev, _, _ = allantools.oadev(run.rate[:, i], rate=FS, data_type="freq",
                                           taus=m / FS)
        assert np.allclose(taus * FS, m)
        av[i] = dev**2
    return av.mean(axis=0), av.std(axis=0, ddof=1) / math.sqrt(REPLICAS)


M_OCT = 2 ** np.arange(0, 12)  # 1 .. 2048 samples (0.01 .. 20.48 s)


@pytest.mark.parametrize("spec", [
    {"N": 0.05},
    {"Q": 2.0},
    {"K": 5.0},
    {"q_c": 3.0, "T_c": 0.5},
    {"Omega_0": 2.0, "f_0": 0.37},
    {"N": 0.02, "K": 3.0, "Q": 0.5, "q_c": 1.0, "T_c": 2.0},
])
def test_exact_terms_match_closed_form(spec: dict) -> None:
    mean, se = _replica_avar(spec, M_OCT)
    theory = NoiseSpec.from_any(spec).avar(M_OCT / FS)
    z = (mean - theory) / se
    assert np.all(np.abs(z) < 4.0), np.round(z, 2)


def test_ramp_is_deterministic_and_exact() -> None:
    run = simulate_gyro({"R": 50.0}, fs_hz=FS, duration_s=600, rng=0)
    _, dev, _, _ = allantools.oadev(run.rate, rate=FS, data_type="freq", taus=M_OCT / FS)
    theory = NoiseSpec(R=50.0).adev(M_OCT / FS)
    np.testing.assert_allclose(dev, theory, rtol=1e-9)
    # the ramp is R t in deg/h with t in hours, evaluated at the sample-interval centre
    np.testing.assert_allclose(run.rate[-1], 50.0 * (run.time[-1] + 0.005) / 3600.0)


def test_flicker_markov_sum_matches_its_exact_avar_and_plateau() -> None:
    b = 0.5
    mean, se = _replica_avar({"B": b}, M_OCT)
    T, q = flicker_poles(FS, N_REP / FS)
    exact = sum(markov_avar(qi * b, Ti, M_OCT / FS) for qi, Ti in zip(q, T, strict=True))
    z = (mean - exact) / se
    assert np.all(np.abs(z) < 4.0), np.round(z, 2)
    # the exact expectation is the IEEE plateau (2 ln2 / pi) B^2 within 1 % (0.5 % in dev)
    plateau = 2 * math.log(2) / math.pi * b * b
    np.testing.assert_allclose(exact, plateau, rtol=0.01)


def test_flicker_plateau_over_a_long_record() -> None:
    """The designed ripple: the plateau sqrt(2 ln2 / pi) B = 0.66428 B within 0.5 % from 1/fs
    to half of a 3 h record."""
    T, q = flicker_poles(100.0, 10800.0)
    tau = np.logspace(-2, math.log10(5400), 200)
    exact = sum(markov_avar(qi, Ti, tau) for qi, Ti in zip(q, T, strict=True))
    np.testing.assert_allclose(np.sqrt(exact), 0.664282, rtol=0.005)


def test_flicker_kasdin_plateau() -> None:
    """Kasdin-Walter sampled flicker: plateau at m >= 8 (its discrete excess there is
    below 1.6 % in variance), and the excess of 44.3 % at m = 1 that its discrete
    spectrum predicts."""
    b = 0.5
    m = 2 ** np.arange(0, 10)
    mean, se = _replica_avar({"B": b}, m, flicker="kasdin")
    plateau = 2 * math.log(2) / math.pi * b * b
    big = m >= 8
    assert np.all(np.abs(mean[big] - plateau) < 4 * se[big] + 0.016 * plateau)
    assert abs(mean[0] - 1.44270 * plateau) < 4 * se[0]


def test_output_independent_of_chunk_size_and_seeded() -> None:
    spec = {"N": 0.01, "B": 0.01, "K": 0.1, "Q": 0.1, "R": 1.0, "q_c": 0.1, "T_c": 1.0,
            "Omega_0": 0.01, "f_0": 0.5}
    arma = {"ar": [0.5], "sigma2": 1e-4}
    a = simulate_gyro(spec, fs_hz=50, duration_s=200, rng=5, arma=arma)
    b = simulate_gyro(spec, fs_hz=50, duration_s=200, rng=5, arma=arma, chunk_size=777)
    # same random draws; only the rounding of running sums across chunk edges differs
    np.testing.assert_allclose(a.rate, b.rate, rtol=0, atol=1e-11 * np.max(np.abs(a.rate)))
    c = simulate_gyro(spec, fs_hz=50, duration_s=200, rng=6, arma=arma)
    assert not np.array_equal(a.rate, c.rate)


def test_terms_have_independent_streams() -> None:
    """Toggling a term leaves the other terms' realisations unchanged."""
    n_only = simulate_gyro({"N": 0.01}, fs_hz=20, duration_s=100, rng=9).rate
    k_only = simulate_gyro({"K": 0.5}, fs_hz=20, duration_s=100, rng=9).rate
    both = simulate_gyro({"N": 0.01, "K": 0.5}, fs_hz=20, duration_s=100, rng=9).rate
    np.testing.assert_allclose(both, n_only + k_only, rtol=0, atol=1e-12)
