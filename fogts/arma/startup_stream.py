"""Start-up blocks longer than ``CAP`` samples: Ansley's banded Cholesky in chunks.

The start-up block of :class:`fogts.arma.likelihood.ExactLikelihood` (the samples t < s
before the Kalman filter is steady) is held in memory whole while it is at most ``CAP``
samples long.  An MA root near the unit circle (or a rounding floor above the steadiness
test's) can make it as long as the series; beyond ``CAP`` it is computed here in chunks of
``CAP`` rows, still exactly: the same factor and innovations as one banded Cholesky of the
whole block, up to rounding.

For the banded covariance A of Ansley's z (bandwidth m = max(p, q)) split after the rows
of the chunks done so far, A = [[A11, A21'], [A21, A22]], the Cholesky factor is
[[L11, 0], [L21, L22]] with

* L21 non-zero only in its top-right m x m corner (A21 is): L21_c = A21_c T^-T, T the
  trailing m x m block of L11 (forward substitution in L11 of a right-hand side that is
  zero but for its last m entries stays zero but for its last m entries);
* L22 the banded Cholesky factor of A22 - L21 L21', which differs from A22 only in its
  top-left m x m block;
* the forward solution w2 = L22^-1 (z2 - L21 w1), where L21 w1 needs only the last m
  entries of w1.

So a chunk needs from the previous one only T and the last m entries of w: an m x m state,
m <= 3 for fogts' candidates (Ansley 1979, sec. 3; Brockwell & Davis 1991, sec. 5.2: the
innovations algorithm's recursions for an ARMA process are those of this factor).  Past
the first p columns the band is the MA(q) autocovariance of W_t = phi(B) x_t, the same in
every chunk.  The innovations are e_t = L_tt w_t and F_t = L_tt^2, as in one block.

What the callers need is accumulated chunk by chunk (S, D, the GLS mean's sums, the last
innovations for the steady filter's state) or written straight into the model's
series-length workspace; nothing series-length is allocated here.  The chunked factor
differs from the whole-block one by rounding only (relative 1e-16 per operation; the
chunk boundaries change the order of a handful of operations in m rows per chunk).

References
----------
C. F. Ansley, "An algorithm for the exact likelihood of a mixed autoregressive-moving average
process", Biometrika 66 (1979) 59-65.
P. J. Brockwell and R. A. Davis, *Time Series: Theory and Methods*, 2nd ed., 1991.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Iterator
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from fogts._typing import FloatArray
from fogts.arma.correlation import dot
from fogts.arma.region import spectral_radius
from fogts.arma.startup_block import (
    TOL_FLOOR,
    TOL_STEADY,
    _band_covariance,
    ansley_z,
    band_orders,
    factor_solve,
    row_deviation,
)

if TYPE_CHECKING:
    from fogts.arma.likelihood import Evaluation, ExactLikelihood

__all__ = ["CAP", "Chunk", "blocks", "chunks", "evaluate", "perturbed_sums", "rebuild"]

#: Rows of a start-up block held in memory at once (a pass over 2^20-row chunks peaks at
#: 187 MB with the constant's column, 134 MB without; tracemalloc).  Longer blocks are
#: factored in chunks of this length.
CAP = 1 << 20

SeriesFn = Callable[[int, int], FloatArray]


@dataclass
class Chunk:
    """Rows c0..c1-1 of a start-up block: innovations ``e`` ((c1 - c0,) or with the
    constant's as a second column) and relative variances ``F``."""

    c0: int
    c1: int
    e: FloatArray
    F: FloatArray


def _ma_acov(theta: FloatArray, m: int) -> FloatArray:
    """gamma_W(0..m) of W_t = theta(B) a_t at unit variance (zero beyond lag q)."""
    q = theta.size
    th = np.r_[1.0, theta]
    g = np.zeros(m + 1)
    for d in range(min(q, m) + 1):
        g[d] = float(np.dot(th[:q + 1 - d], th[d:q + 1]))
    return g


def _trailing(c: FloatArray, m: int) -> FloatArray:
    """The trailing m x m block of a factor in LAPACK's lower band storage, as a full
    lower-triangular matrix."""
    L = c.shape[1]
    T = np.zeros((m, m))
    for i in range(m):
        for j in range(i + 1):
            T[i, j] = c[i - j, L - m + j]
    return T


def _coupling(g: FloatArray, T: FloatArray, rows: int) -> FloatArray:
    """L21's corner, (rows, m): A21_c T^-T, A21_c[i, j] = gamma_W(m + i - j) (j >= i)."""
    from scipy.linalg import solve_triangular

    m = T.shape[0]
    A21 = np.zeros((rows, m))
    for i in range(rows):
        for j in range(i, m):
            A21[i, j] = g[m + i - j]
    return np.asarray(solve_triangular(T, A21.T, lower=True)).T


def _next_chunk(g: FloatArray, b: FloatArray, series: SeriesFn, c0: int, c1: int,
                state: tuple[FloatArray, FloatArray], with_ones: bool
                ) -> tuple[FloatArray, FloatArray]:
    """The band and right-hand side of rows c0..c1-1 (c0 >= p + m), reduced by the
    coupling to the rows before them (``state``: T and the last m entries of w)."""
    T, w_last = state
    m, L = T.shape[0], c1 - c0
    ab = np.repeat(g[:, None], L, axis=1)
    p = b.size - 1
    xs = series(c0 - p, c1)
    W = np.convolve(xs, b, mode="valid") if p else xs.copy()
    z = np.column_stack((W, np.full(L, float(np.sum(b))))) if with_ones else W
    r = min(m, L)
    L21 = _coupling(g, T, r)
    M = L21 @ L21.T
    for i in range(r):
        for j in range(i + 1):
            ab[i - j, j] -= M[i, j]
    z[:r] -= L21 @ w_last
    return ab, z


#: A settled deviation above ``TOL_FLOOR`` but at most this is taken as a rounding floor
#: when the exact deviation has provably decayed below it (see :func:`_is_steady`).
FLOOR_MAX = 1e-8


def _is_steady(c: FloatArray, F: FloatArray, theta: FloatArray, c1: int,
               devs: list[tuple[int, float]], rho: float) -> bool:
    """Whether row c1 - 1 (the chunk's last) is the steady filter's.

    As :func:`fogts.arma.startup_block.banded_innovations`: the deviation is below
    ``TOL_STEADY``, or below ``TOL_FLOOR`` and settled (no smaller than half the deviation
    at the last chunk end at most half-way; ``devs`` is appended to).  Beyond that, a
    settled deviation up to ``FLOOR_MAX`` is a rounding floor when the exact one is known
    to be below ``TOL_STEADY``: the Riccati recursion of the factor's rows converges
    geometrically at rate rho^2, rho the largest inverse MA root modulus (Brockwell & Davis
    1991, sec. 5.3), so the exact deviation at c1 is at most rho^(2 (c1 - t1)) times that
    at the first chunk end t1; this is required to be 1e-3 TOL_STEADY (a margin for the
    computed deviation at t1 and for a polynomial factor).  Near the unit circle the
    floor, the recursion's rounding amplified by ~1/(1 - rho^2), is quantised and not
    monotone in rho: 1.1e-11 at rho = 1 - 1e-5 (above ``TOL_FLOOR``, where the whole-block
    rule never stops), 7.7e-12 at 1 - 3e-6.  Switching there changes the innovations by
    the exact deviation, not by the floor, which is the block's own rounding.
    """
    L, m = c.shape[1], c.shape[0] - 1
    if L <= m:
        return False
    dev = row_deviation(c, F, theta, L - 1)
    half = [d for t, d in devs if t <= c1 // 2]
    devs.append((c1, dev))
    if dev < TOL_STEADY:
        return True
    if not half or dev < 0.5 * half[-1]:
        return False
    t1, d1 = devs[0]
    return dev < TOL_FLOOR or (dev <= FLOOR_MAX
                               and rho ** (2 * (c1 - t1)) * d1 <= 1e-3 * TOL_STEADY)


def chunks(phi: FloatArray, theta: FloatArray, series: SeriesFn, n: int, *,
           stop: int | None = None, with_ones: bool = False, cap: int | None = None
           ) -> Iterator[Chunk]:
    """The exact start-up block of an ARMA(p, q) series in chunks of ``cap`` rows.

    Parameters
    ----------
    phi, theta
        The coefficients (statsmodels' signs).
    series
        ``series(c0, c1)``: samples c0..c1-1 of the series.
    n
        The series' length.
    stop
        The block's length s; ``None``: until a chunk's last row passes the steadiness test
        (the last chunk yielded ends at s; see :func:`_is_steady`), or n.
    with_ones
        Also the innovations of the constant series 1, as a second column.
    cap
        Rows per chunk (default: the module's ``CAP`` at the call).

    Raises
    ------
    ModelFitError
        A chunk's covariance is not positive definite (a non-stationary phi).
    """
    p, q, m = band_orders(phi, theta)
    size = max(CAP if cap is None else cap, 2 * (p + m))
    end = n if stop is None else stop
    g = _ma_acov(theta, m)
    b = np.r_[1.0, -phi]
    state: tuple[FloatArray, FloatArray] | None = None
    devs: list[tuple[int, float]] = []
    rho = spectral_radius(-theta)
    c0 = 0
    while c0 < end:
        c1 = min(end, c0 + size)
        if state is None:
            ab = _band_covariance(phi, theta, c1)
            z = ansley_z(phi, series(0, c1), with_ones)
        else:
            ab, z = _next_chunk(g, b, series, c0, c1, state, with_ones)
        c, e, F, w = factor_solve(ab, z, c1)
        steady = stop is None and c1 > p + q and _is_steady(c, F, theta, c1, devs, rho)
        if c1 - c0 >= m:
            w2 = w.reshape(c1 - c0, -1)[-m:]
            state = (_trailing(c, m), w2.copy() if with_ones else w2[:, 0].copy())
        yield Chunk(c0, c1, e, F)
        if steady:
            return
        c0 = c1


def _last(prev: FloatArray, new: FloatArray, k: int) -> FloatArray:
    """The last k values of prev followed by new."""
    return np.concatenate((prev, new))[-k:] if k else np.zeros(0)


def evaluate(model: ExactLikelihood, phi: FloatArray, theta: FloatArray) -> Evaluation:
    """:meth:`ExactLikelihood.evaluate` with the start-up block in chunks (see the module
    docstring): the block's innovations go into the workspace, S, D and the GLS mean's sums
    are accumulated; with a mean, a second pass over the block subtracts mu e_1 (the
    constant's innovations, recomputed rather than stored) and sums S."""
    from fogts.arma.likelihood import Evaluation, _steady_zi

    n, L, mean = model.n, model.order, model.mean
    e = model.work.take()
    S = D = sx1 = s11 = 0.0
    ones_last = np.zeros(0)
    s = 0
    for ch in chunks(phi, theta, model.series, n, with_ones=mean):
        s = ch.c1
        ex = ch.e[:, 0] if mean else ch.e
        e[ch.c0:s] = ex
        D += float(np.sum(np.log(ch.F)))
        if mean:
            e1 = ch.e[:, 1]
            w1 = e1 / ch.F
            sx1 += dot(ex, w1)
            s11 += dot(e1, w1)
            ones_last = _last(ones_last, e1, L)
        else:
            S += dot(ex, ex / ch.F)
    ev = Evaluation(phi=phi, theta=theta, s=s, F=np.zeros(0), head=np.zeros(0),
                    streamed=True)
    if model.q:
        b, a = model.polys(phi, theta)
        ev.zi = _steady_zi(b, a, model.series(s - L, s), e[s - L:s].copy())
    for c0, c1, y in model._tail_chunks(ev):
        e[c0:c1] = y
    if mean:
        S = _remove_mean(model, ev, e, sx1, s11, ones_last)
        D += math.log(ev.s11 / n)
    if s < n:
        S += dot(e[s:], e[s:])
    return model.finish(ev, S, D)


def _remove_mean(model: ExactLikelihood, ev: Evaluation, e: FloatArray, sx1: float,
                 s11: float, ones_last: FloatArray) -> float:
    """Set ev.mu, ev.s11 (and the constant's steady innovations) from the block's sums and
    the tail's, subtract mu e_1 from the workspace e, return the block's part of S."""
    n, s = model.n, ev.s
    if s < n:
        ev.ones_tail, ev.ones_c = model._ones_tail(ev.phi, ev.theta, s, ones_last)
        head, c = ev.ones_tail, ev.ones_c
        m = head.size
        sx1 += dot(e[s:s + m], head) + c * float(np.sum(e[s + m:]))
        s11 += dot(head, head) + c * c * (n - s - m)
    ev.mu, ev.s11 = sx1 / s11, s11
    S = 0.0
    for ch in chunks(ev.phi, ev.theta, model.series, n, stop=s, with_ones=True):
        y = e[ch.c0:ch.c1]
        y -= ev.mu * ch.e[:, 1]
        S += dot(y, y / ch.F)
    if s < n:
        model._correct(ev, e[s:], s)
    return S


def _block_chunks(model: ExactLikelihood, ev: Evaluation) -> Iterator[tuple[int, int, FloatArray]]:
    """The start-up block's innovations at ``ev`` chunk by chunk, the GLS mean removed."""
    for ch in chunks(ev.phi, ev.theta, model.series, model.n, stop=ev.s,
                     with_ones=model.mean):
        yield ch.c0, ch.c1, (ch.e[:, 0] - ev.mu * ch.e[:, 1]) if model.mean else ch.e


def rebuild(model: ExactLikelihood, ev: Evaluation) -> FloatArray:
    """:meth:`ExactLikelihood.innovations` of a streamed evaluation: the workspace,
    refilled with the same values :func:`evaluate` left there."""
    e = model.work.take()
    for c0, c1, y in _block_chunks(model, ev):
        e[c0:c1] = y
    for c0, c1, y in model._tail_chunks(ev):
        e[c0:c1] = y
    if model.mean and ev.s < model.n:
        model._correct(ev, e[ev.s:], ev.s)
    model.work.holder = ev
    return e


def blocks(model: ExactLikelihood, ev: Evaluation) -> Iterator[tuple[int, int, FloatArray]]:
    """:meth:`ExactLikelihood.innovation_blocks` of a streamed evaluation: the block's
    chunks, then the steady part's ``CHUNK``-long blocks."""
    yield from _block_chunks(model, ev)
    for c0, c1, t in model._tail_chunks(ev):
        if model.mean:
            model._correct(ev, t, c0)
        yield c0, c1, t


def perturbed_sums(model: ExactLikelihood, ev: Evaluation, h: FloatArray
                   ) -> tuple[FloatArray, FloatArray, FloatArray]:
    """The start-up block's parts of dS and dD by central differences (steps ``h``), and
    the block's last q innovations at the perturbed parameters (rows +h, -h per
    parameter): :func:`fogts.arma.likelihood_passes._startup_part` one perturbed
    parameter vector at a time, each block in chunks."""
    p, q, k = model.p, model.q, model.p + model.q
    s_tr, d_tr = np.zeros(2 * k), np.zeros(2 * k)
    e_last = np.zeros((2 * k, q))
    for r in range(2 * k):
        beta = ev.beta
        beta[r // 2] += h[r // 2] if r % 2 == 0 else -h[r // 2]
        s_tr[r], d_tr[r], e_last[r] = _perturbed_block(model, ev, beta[:p], beta[p:])
    dS = (s_tr[0::2] - s_tr[1::2]) / (2 * h)
    dD = (d_tr[0::2] - d_tr[1::2]) / (2 * h)
    return dS, dD, e_last


def _perturbed_block(model: ExactLikelihood, ev: Evaluation, phi: FloatArray,
                     theta: FloatArray) -> tuple[float, float, FloatArray]:
    """S and D of the block t < s of x - mu_hat at (phi, theta) (D with the GLS mean's
    log(s11/n), s11 with the constant's steady tail) and its last q innovations."""
    n, s, L, q, mean = model.n, ev.s, model.order, model.q, model.mean

    def series(c0: int, c1: int) -> FloatArray:
        return model.series(c0, c1) - ev.mu

    S = D = s11 = 0.0
    x_last, ones_last = np.zeros(0), np.zeros(0)
    for ch in chunks(phi, theta, series, n, stop=s, with_ones=mean):
        ex = ch.e[:, 0] if mean else ch.e
        S += dot(ex, ex / ch.F)
        D += float(np.sum(np.log(ch.F)))
        x_last = _last(x_last, ex, q)
        if mean:
            e1 = ch.e[:, 1]
            s11 += dot(e1, e1 / ch.F)
            ones_last = _last(ones_last, e1, L)
    if mean:
        if s < n:
            head, c = model._ones_tail(phi, theta, s, ones_last)
            s11 += dot(head, head) + c * c * (n - s - head.size)
        D += math.log(s11 / n)
    return S, D, x_last
