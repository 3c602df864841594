"""The start-up block in chunks (fogts.arma.startup_stream) against the block held whole."""

from __future__ import annotations

import numpy as np
import pytest

from fogts.arma import startup_stream
from fogts.arma.likelihood import ExactLikelihood
from tests.arma.simulated import arma_series

N = 200_000


def _series() -> np.ndarray:
    return arma_series([0.5, 0.1], [-0.9], N, 31) + 2.0


def _both(monkeypatch: pytest.MonkeyPatch, phi: list[float], theta: list[float], mean: bool,
          cap: int) -> tuple[ExactLikelihood, object, ExactLikelihood, object]:
    """The model and evaluation with the block whole (default CAP), then in chunks of cap."""
    x = _series()
    ph, th = np.array(phi), np.array(theta)
    whole = ExactLikelihood(x, ph.size, th.size, mean=mean)
    ev_w = whole.evaluate(ph, th)
    monkeypatch.setattr(startup_stream, "CAP", cap)
    chunked = ExactLikelihood(x, ph.size, th.size, mean=mean)
    ev_c = chunked.evaluate(ph, th)
    return whole, ev_w, chunked, ev_c


@pytest.mark.parametrize(("phi", "theta"), [([0.5, 0.1], [-0.99999]), ([0.6], [-0.99999])])
@pytest.mark.parametrize("mean", [True, False])
def test_chunked_block_equals_the_whole_block(monkeypatch: pytest.MonkeyPatch, phi: list,
                                              theta: list, mean: bool) -> None:
    """An MA root 1e-5 inside the unit circle: the block never becomes steady within
    n = 2e5 (F_t - 1 ~ theta^2t is still 2 % at the end), so it is the whole series,
    held whole under the default CAP and factored in 13 chunks of 2^14 rows with CAP
    monkeypatched.

    Tolerances: both are the same banded Cholesky, rounded differently at the chunk
    boundaries; a covariance this close to singular (condition number ~ 1/(1 - |theta|)^2
    = 1e10) amplifies rounding, so they differ by more than 1e-16: measured 2e-11 in S, D,
    mu and s11, 4e-11 in the largest innovation, 3e-10 (of the largest component) in the
    gradients, whose start-up parts are central differences with step 1e-6 of such sums.
    Neither is the more accurate: against a long-double banded Cholesky of the same
    ARMA(1,1) problem both are off by 4e-9 in S (float64 rounding of Ansley's z, amplified
    by the conditioning).  Hence 1e-10 relative for the sums and innovations, 1e-9 for the
    gradients."""
    whole, ev_w, chunked, ev_c = _both(monkeypatch, phi, theta, mean, 1 << 14)
    assert ev_w.s == ev_c.s == N
    assert not ev_w.streamed and ev_c.streamed
    assert ev_c.F.size == 0 and ev_c.head.size == 0
    for attr in ("S", "D", "f", "mu", "s11"):
        assert getattr(ev_c, attr) == pytest.approx(getattr(ev_w, attr), rel=1e-10)
    e_w = whole.innovations(ev_w).copy()
    e_c = chunked.innovations(ev_c).copy()
    assert np.max(np.abs(e_c - e_w)) <= 1e-10 * np.max(np.abs(e_w))
    # rebuilt after the workspace is overwritten: bit for bit what evaluate left there
    chunked.evaluate(np.array(phi) * 0.5, np.array(theta) * 0.5)
    np.testing.assert_array_equal(chunked.innovations(ev_c), e_c)
    dS_w, dD_w, _ = whole.derivatives(ev_w, hessian=False)
    dS_c, dD_c, _ = chunked.derivatives(ev_c, hessian=False)
    assert np.max(np.abs(dS_c - dS_w)) <= 1e-9 * np.max(np.abs(dS_w))
    assert np.max(np.abs(dD_c - dD_w)) <= 1e-9 * np.max(np.abs(dD_w))


def test_chunked_hessian_equals_the_whole_blocks(monkeypatch: pytest.MonkeyPatch) -> None:
    """The analytic Hessian of S (its forward pass reads the block chunk by chunk); 1e-9 as
    for the gradients (measured 3e-11)."""
    whole, ev_w, chunked, ev_c = _both(monkeypatch, [0.5, 0.1], [-0.99999], True, 1 << 14)
    _, _, H_w = whole.derivatives(ev_w, hessian=True)
    _, _, H_c = chunked.derivatives(ev_c, hessian=True)
    assert H_w is not None and H_c is not None
    assert np.max(np.abs(H_c - H_w)) <= 1e-9 * np.max(np.abs(H_w))


@pytest.mark.parametrize("mean", [True, False])
def test_chunked_block_still_switches_to_the_steady_filter(monkeypatch: pytest.MonkeyPatch,
                                                           mean: bool) -> None:
    """theta = -0.999: the Cholesky rows reach theta to 1e-13 after ~11,600 rows
    (F_t - 1 ~ theta^2t (1 - theta^2)), so the chunks (2^12 rows) stop at the first chunk
    end past that, s = 12288, and the steady ARMA inversion does the rest; the whole block
    stops at s = 32768 (its 8x growth).  Both switch where the rows are within 1e-13 of the
    steady filter's; a row deviation delta changes the innovations after it by up to
    delta / (1 - |theta|) = 1e-10, decaying at theta's rate, so S agrees to 1e-10
    (measured 6e-12).  D agrees to 1e-8: its dropped tail, sum log F_t ~ theta^2t (1 -
    theta^2) summed from 12288 on, is ~2e-11, but the 12288 log F_t themselves come from two
    factorisations whose rows differ in the last bits, and their rounding adds up (measured
    1.7e-9 under OPENBLAS_CORETYPE=Prescott, below 1e-9 with the default kernel); 1e-8 in
    D is 5e-9 in the log-likelihood, far below the 0.01 AIC units a ranking reads.  The
    gradient's steady part takes the rows after s as the steady filter's, and their
    dependence on theta is O(t theta^2t): both gradients are within 2e-7 of central
    differences of S (measured), so they are compared to 1e-6."""
    whole, ev_w, chunked, ev_c = _both(monkeypatch, [0.5, 0.1], [-0.999], mean, 1 << 12)
    assert ev_w.s == 32768
    assert ev_c.streamed and ev_c.s == 12288
    assert ev_c.S == pytest.approx(ev_w.S, rel=1e-10)
    assert ev_c.D == pytest.approx(ev_w.D, abs=1e-8)
    assert ev_c.mu == pytest.approx(ev_w.mu, rel=1e-10, abs=1e-15)
    dS_w, _, _ = whole.derivatives(ev_w, hessian=False)
    dS_c, _, _ = chunked.derivatives(ev_c, hessian=False)
    assert np.max(np.abs(dS_c - dS_w)) <= 1e-6 * np.max(np.abs(dS_w))


def test_chunks_are_one_banded_cholesky() -> None:
    """startup_stream.chunks against startup_block.banded_innovations on the same block,
    every row (ARMA(3,3): the m x m coupling at its largest)."""
    from fogts.arma.startup_block import banded_innovations

    x = _series()[:50_000]
    phi, theta = np.array([0.3, 0.2, 0.1]), np.array([-0.99, 0.05, 0.01])
    e, F, _ = banded_innovations(phi, theta, x, with_ones=True)
    parts = list(startup_stream.chunks(phi, theta, lambda a, b: x[a:b], x.size,
                                       stop=x.size, with_ones=True, cap=4096))
    assert len(parts) == 13
    np.testing.assert_allclose(np.concatenate([c.F for c in parts]), F, rtol=1e-14)
    e2 = np.concatenate([c.e for c in parts])
    assert np.max(np.abs(e2 - e)) <= 1e-12 * np.max(np.abs(e))


def test_a_rounding_floor_above_tol_floor_still_ends_the_block() -> None:
    """theta = -(1 - 1e-5): the factor's rows settle at a rounding floor |F_t - 1| =
    1.1e-11 from t ~ 1e6 on, above TOL_FLOOR, where the whole-block rule grows the block
    to the series (the 1e8 white + random walk failure).  The chunked rule stops at the
    second chunk end, s = 2^21: settled, and rho^(2 * 2^20) = 8e-10 bounds the exact
    deviation by 1e-20.  Reference: the same block factored to the end (n = 2.6e6) in
    chunks, on a series of this model; S agrees to 1e-10 (measured 1e-12; against a
    long-double banded Cholesky the steady switch is off by 6.0e-12 and the factor to
    the end by 6.9e-12: the floor is the factor's own rounding)."""
    from fogts.arma.startup_block import TOL_FLOOR

    n = (1 << 21) + (1 << 19)
    x = arma_series([0.5], [-(1.0 - 1e-5)], n, 7)
    phi, theta = np.array([0.5]), np.array([-(1.0 - 1e-5)])
    model = ExactLikelihood(x, 1, 1)
    ev = model.evaluate(phi, theta)
    assert ev.streamed and ev.s == 1 << 21
    S = 0.0
    devs: list[float] = []
    for ch in startup_stream.chunks(phi, theta, lambda a, b: x[a:b], n, stop=n):
        S += float(np.sum(ch.e * ch.e / ch.F))
        devs.append(abs(float(ch.F[-1]) - 1.0))
    assert min(devs) > TOL_FLOOR
    assert ev.S == pytest.approx(S, rel=1e-10)
