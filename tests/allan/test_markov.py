"""fogts.allan.markov: the closed forms of the Markov and sinusoid Allan variances, the
term parsing, and the Markov covariance's limits."""

from __future__ import annotations

import math

import numpy as np
import pytest

from fogts.allan.covariance import CovarianceModel, covariance_basis
from fogts.allan.markov import (
    EXTRA_POWER,
    ExtendedCovariance,
    markov_avar,
    sinusoid_avar,
    split_terms,
)
from fogts.errors import DataError


def test_markov_limits() -> None:
    """IEEE 952 Annex C: tau >> T_c gives white rate noise (q_c T_c)^2 / tau; tau << T_c a
    rate random walk q_c^2 tau / 3 (both to 1e-3 relative at 1e4 and 1e-4 T_c)."""
    q, tc = 0.3, 5.0
    assert markov_avar(q, tc, 5e4)[0] == pytest.approx((q * tc) ** 2 / 5e4, rel=1e-3)
    assert markov_avar(q, tc, 5e-4)[0] == pytest.approx(q * q * 5e-4 / 3, rel=1e-3)


def test_sinusoid_zeros_and_peak() -> None:
    """sin^4(pi f0 tau)/(pi f0 tau)^2: zero at tau = k/f0; the Allan deviation peaks at
    0.7246 Omega_0 near tau = 0.371/f0 (IEEE 952 Annex C, sinusoidal noise)."""
    f0 = 2.0
    assert sinusoid_avar(3.0, f0, [0.5, 1.0]) == pytest.approx([0.0, 0.0], abs=1e-25)
    tau = np.linspace(0.05, 0.45, 4001) / f0
    av = sinusoid_avar(1.0, f0, tau)
    assert tau[np.argmax(av)] * f0 == pytest.approx(0.371, abs=1e-3)
    assert math.sqrt(av.max()) == pytest.approx(0.7246, abs=1e-4)


@pytest.mark.parametrize(("terms", "five", "extras"), [
    ("N,B,K,M", ("N", "B", "K"), ("M",)),
    ("s, m, q, n", ("Q", "N"), ("M", "S")),
    (("R", "N"), ("N", "R"), ()),
])
def test_split_terms(terms: object, five: tuple[str, ...], extras: tuple[str, ...]) -> None:
    assert split_terms(terms) == (five, extras)  # type: ignore[arg-type]


@pytest.mark.parametrize(("terms", "match"), [
    ("M", "at least one of Q, N, B, K, R besides M, got 'M'"),
    ("N,M,m", "must not repeat a term, got 'N,M,m'"),
    ("N,X", r"terms must be drawn from Q, N, B, K, R; got 'X' \(M and S may be added\)"),
    (3, r"terms must be a sequence of Q, N, B, K, R, got 3 \(M and S may be added\)"),
])
def test_split_terms_errors(terms: object, match: str) -> None:
    with pytest.raises(DataError, match=match):
        split_terms(terms)  # type: ignore[arg-type]


def test_markov_covariance_is_white_noise_far_above_t_c() -> None:
    """With T_c far below every tau the Markov term is white rate noise of coefficient
    (q_c T_c)^2, so its covariance equals the N term's (1e-5 relative: the closed form's
    bracket is 1 - 1.5 T_c/tau, squared in the covariance: 3e-6 at tau = 0.1 s)."""
    m = np.array([10, 20, 40, 80], dtype=np.int64)
    tau = m / 100.0
    basis = covariance_basis("oadev", m, 100_000, 100.0, np.array([-1, 1]))
    assert basis is not None
    tc = 1e-7
    a_markov = 1.0 / tc**2  # (q_c T_c)^2 = 1
    ext = ExtendedCovariance(basis, np.array([-1, EXTRA_POWER]), "oadev", tau=tau,
                             markov=(1, tc))
    white = CovarianceModel(basis, np.array([-1]), "oadev")
    np.testing.assert_allclose(ext.raw(np.array([0.0, a_markov])), white.raw(np.array([1.0])),
                               rtol=1e-5)
    # and a rate random walk far below T_c: K^2 tau / 3 with K^2 = q_c^2
    tc = 1e7
    slow = ExtendedCovariance(basis, np.array([-1, EXTRA_POWER]), "oadev", tau=tau,
                              markov=(1, tc))
    walk = CovarianceModel(basis, np.array([1]), "oadev")
    np.testing.assert_allclose(slow.raw(np.array([0.0, 1.0])), walk.raw(np.array([1.0])),
                               rtol=1e-5)
    assert math.isfinite(float(np.sum(slow.raw(np.array([0.5, 1.0])))))
