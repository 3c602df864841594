"""The derivatives of the exact ARMA likelihood, in block-wise passes over the series.

The formulas are those of :mod:`fogts.arma.likelihood` (Brockwell & Davis 1991, ch. 8; the
adjoint of the ARMA inversion for the exact gradient).  What this module adds is the order
of the work, so that no pass allocates a series-length array:

* the adjoint g = theta(B^-1)^-1 a runs backward over the model's workspace, block by block,
  overwriting the innovations a it has consumed (the gradient's sums sum_t g_t x_{t-i} and
  sum_t g_t a_{t-j} are taken block by block before a block is overwritten);
* the Hessian's filters u = x / theta(B) and v = a / theta(B) run forward, block by block,
  their lagged sums with each other and with g (now in the workspace) accumulated as they
  go; the innovations are rebuilt block by block from the evaluation's filter state.

Each block is ``CHUNK`` samples (cache-resident); the filters carry their state across
blocks, so every filtered value equals that of a whole-series pass.

References
----------
P. J. Brockwell and R. A. Davis, *Time Series: Theory and Methods*, 2nd ed., 1991.
"""

from __future__ import annotations

from collections import deque
from collections.abc import Callable
from itertools import pairwise
from typing import TYPE_CHECKING

import numpy as np

from fogts._typing import FloatArray
from fogts.arma.correlation import EINSUM_BLOCK, dot, fused_squares, sum_squares

if TYPE_CHECKING:
    from fogts.arma.likelihood import Evaluation, ExactLikelihood

__all__ = ["block_bounds", "derivatives", "tail_pass"]

_U_AHEAD = 2      # blocks of u the worker may be ahead of the Hessian pass


def tail_pass(model: ExactLikelihood, ev: Evaluation, e: FloatArray) -> float | None:
    """The steady part of :meth:`~fogts.arma.likelihood.ExactLikelihood.evaluate`: the
    innovations from s on into the workspace ``e``; returns their sum of squares (without
    a mean, else None), summed in cache in dot's own order (``sum_squares``).

    The worker thread forms the series ahead of the filter and stores its output.
    """
    from fogts.arma.likelihood import CHUNK
    from fogts.arma.worker import Worker

    # the blocks from s are CHUNK long: whole numbers of einsum's pieces
    ssq = [0.0] if not model.mean and fused_squares() and CHUNK % EINSUM_BLOCK == 0 else None

    def store(c0: int, c1: int, y: FloatArray) -> None:
        e[c0:c1] = y
        if ssq is not None:
            ssq[0] = sum_squares(ssq[0], y)

    with Worker(model.n) as worker:
        for c0, c1, y in model._tail_chunks(ev, worker):
            worker.submit(store, c0, c1, y)
    return None if ssq is None else ssq[0]


def block_bounds(model: ExactLikelihood, ev: Evaluation) -> list[tuple[int, int]]:
    """The blocks (c0, c1) :meth:`~fogts.arma.likelihood.ExactLikelihood.innovation_blocks`
    yields for a start-up block held whole (not streamed)."""
    from fogts.arma.likelihood import CHUNK

    s, n = ev.s, model.n
    if s >= n:
        return [(0, s)]
    return [(0, min(n, s + CHUNK))] + [(c0, min(n, c0 + CHUNK))
                                       for c0 in range(s + CHUNK, n, CHUNK)]


def _startup_part(model: ExactLikelihood, ev: Evaluation
                  ) -> tuple[FloatArray, FloatArray, FloatArray, FloatArray]:
    """The start-up block's contributions to dS and dD by central differences, the steps,
    and the block's innovations at the perturbed parameters (rows +h, -h per parameter;
    for a streamed block only its last q)."""
    from fogts.arma.likelihood import _FD_STEP, _fd_steps

    p, q, n, s = model.p, model.q, model.n, ev.s
    k = p + q
    beta = ev.beta
    h = _fd_steps(beta, p, _FD_STEP)
    if ev.streamed:
        from fogts.arma.startup_stream import perturbed_sums

        dS, dD, e_last = perturbed_sums(model, ev, h)
        return dS, dD, h, e_last
    pert = np.repeat(beta[None, :], 2 * k, axis=0)
    idx = np.arange(k)
    pert[2 * idx, idx] += h
    pert[2 * idx + 1, idx] -= h
    # with the GLS mean, the derivatives of S at the fixed mu = mu_hat are those of the
    # profile (envelope theorem: dS/dmu = 0 there): the series is x - mu_hat, used as such
    # in the start-up block and through its linearity in the steady sums
    _, e_tr, f_tr = model.transient(pert[:, :p], pert[:, p:], s=s,
                                    series=model.series(0, s) - ev.mu, with_ones=model.mean)
    d_tr = np.sum(np.log(f_tr), axis=1)
    if model.mean:
        d_tr += np.log(model._s11_perturbed(pert, s, e_tr[:, :, 1], f_tr) / n)
        e_tr = e_tr[:, :, 0]
    s_tr = np.sum(e_tr * e_tr / f_tr, axis=1)
    dS = (s_tr[0::2] - s_tr[1::2]) / (2 * h)
    dD = (d_tr[0::2] - d_tr[1::2]) / (2 * h)
    return dS, dD, h, e_tr


def _adjoint_pass(model: ExactLikelihood, ev: Evaluation, e: FloatArray
                  ) -> tuple[FloatArray, FloatArray, float, FloatArray]:
    """Backward over the workspace e (the innovations): g = theta(B^-1)^-1 e in place.

    Returns sum_{t>=s} g_t x_{t-i} (i = 1..p), sum_{t>=s} g_t e_{t-j} (j = 1..q),
    sum_{t>=s} g_t, and g_s..g_{s+q-1}.  For a pure AR g = e, left in place.  A block's
    sums and its write-back run on the :class:`~fogts.arma.worker.Worker` thread (in block
    order, as in one thread) while this one filters the block before it.
    """
    from scipy.signal import lfilter

    from fogts.arma.likelihood import CHUNK
    from fogts.arma.worker import Worker

    p, q, s = model.p, model.q, ev.s
    a_poly = np.r_[1.0, ev.theta]
    # the start-up block too in CHUNK-long blocks: a streamed one can be as long as the
    # series, and a block's copy and reversed filter output are three of its length
    bounds = sorted({*range(0, s, CHUNK), *model.bounds(s)})
    gx, ge = np.zeros(p), np.zeros(q)
    g_sum = [0.0]                  # sum_{t>=s} g_t
    g_first = [np.zeros(0)]        # g_s..g_{s+q-1}

    def block_sums(c0: int, c1: int, g: FloatArray, ext: FloatArray, off: int) -> None:
        if q:
            g = np.ascontiguousarray(g[::-1])      # g was filtered reversed
        if c0 >= s and c0 < c1:
            m = c1 - c0
            g_sum[0] += float(np.sum(g))
            xs = model.series(c0 - p, c1)
            for i in range(1, p + 1):
                gx[i - 1] += dot(g, xs[p - i:p - i + m])
            for j in range(1, q + 1):
                ge[j - 1] += dot(g, ext[off - j:off - j + m])
            if c0 == s:
                g_first[0] = g[:q].copy()
        if q:
            e[c0:c1] = g

    zr = np.zeros(q)
    with Worker(model.n) as worker:
        for c0, c1 in reversed(list(pairwise(bounds))):
            lo = max(0, c0 - q)
            ext = e[lo:c1].copy()            # the block's innovations and the q before it
            off = c0 - lo
            if q:
                gr, zr = lfilter([1.0], a_poly, ext[off:][::-1], zi=zr)
            else:
                gr = ext[off:]
            worker.submit(block_sums, c0, c1, gr, ext, off)
    return gx, ge, g_sum[0], g_first[0]


def _hessian_pass(model: ExactLikelihood, ev: Evaluation, g_buf: FloatArray | None
                  ) -> FloatArray:
    """Forward: the Hessian of S from u = x/theta(B), v = a/theta(B) and g (``g_buf``;
    None for a pure AR, where g = a), sums over t >= max(p + q, 2q).

    u does not depend on the innovations: its filter and its sums that need no v run on
    the :class:`~fogts.arma.worker.Worker` thread, ahead, while this one rebuilds a and
    filters v (the same operations and sums either way)."""
    from scipy.signal import lfilter

    from fogts.arma.worker import Worker

    p, q = model.p, model.q
    k = p + q
    t0 = max(p + q, 2 * q)      # the largest lag used below
    K = max(t0, 1)
    a_poly = np.r_[1.0, ev.theta]
    lag = [i for i in range(1, p + 1)] + [j for j in range(1, q + 1)]
    HS = np.zeros((k, k))
    zv = np.zeros(q)
    prev_v = np.zeros(K)
    # the blocks of innovation_blocks, known ahead (a streamed start-up block's are its
    # own; a pure AR's g is a, rebuilt here: one thread)
    bounds = None if ev.streamed or g_buf is None else block_bounds(model, ev)
    u_state = [np.zeros(q), np.zeros(K)]     # u's filter state and last K values

    def u_block(c0: int, c1: int, g: FloatArray) -> tuple[FloatArray, FloatArray]:
        """u of a block with the K before it (filtered on from the block before), and the
        block's (phi_i, phi_j) sums and (phi_i, theta_j) g-terms."""
        xs = model.series(c0, c1)
        if q:
            uc, u_state[0] = lfilter([1.0], a_poly, xs, zi=u_state[0])
        else:
            uc = xs
        ext_u = np.concatenate((u_state[1], uc))
        u_state[1] = ext_u[-K:].copy()
        return ext_u, _pair_sums(True, ext_u, None, g, None, c0, c1, p, K, t0, lag)

    with Worker(0 if bounds is None else model.n) as worker:
        # the worker's u of the next blocks is under way while this thread works on one
        ahead: deque[tuple[int, int, Callable[[], tuple[FloatArray, FloatArray]]]] = deque()
        todo = iter([] if bounds is None else [(c0, c1) for c0, c1 in bounds if c1 > c0])

        def queue_next() -> None:
            for c0, c1 in todo:
                assert g_buf is not None
                ahead.append((c0, c1, worker.submit(u_block, c0, c1, g_buf[c0:c1])))
                return

        for _ in range(_U_AHEAD):
            queue_next()
        for c0, c1, e in model.innovation_blocks(ev):
            if c1 <= c0:
                continue
            g = e if g_buf is None else g_buf[c0:c1]
            if bounds is not None:
                cu0, cu1, u_part = ahead.popleft()
                assert (cu0, cu1) == (c0, c1)
                queue_next()
            else:
                u_part = worker.submit(u_block, c0, c1, g)     # inline
            if q:
                vc, zv = lfilter([1.0], a_poly, e, zi=zv)
            else:
                vc = e
            ext_v = np.concatenate((prev_v, vc))
            ext_u, W = u_part()
            HS += _pair_sums(False, ext_u, ext_v, g, W, c0, c1, p, K, t0, lag)
            prev_v = ext_v[-K:].copy()
    return np.triu(HS) + np.triu(HS, 1).T


def _pair_sums(u_only: bool, ext_u: FloatArray, ext_v: FloatArray | None, g: FloatArray,
               W: FloatArray | None, c0: int, c1: int, p: int, K: int, t0: int,
               lag: list[int]) -> FloatArray:
    """A block's Hessian sums (``ext_u``, ``ext_v``: its u and v with the K before them).

    ``u_only``: those that need u and g only (the worker's share), (phi_i, phi_j)
    sum u_{t-i} u_{t-j} and (phi_i, theta_j) sum g_t u_{t-i-j}.  Otherwise the block's
    terms 2 val of the Hessian of S, the u-only sums ``W`` (the worker's) included."""
    k = len(lag)
    out = np.zeros((k, k))
    ta = max(c0, t0)
    if ta >= c1:
        return out
    a0, a1 = K + ta - c0, K + c1 - c0      # positions of t = ta, c1 in ext_u, ext_v
    for i in range(p if u_only else k):
        li = lag[i]
        for j in range(i, k):
            lj = lag[j]
            if u_only:
                out[i, j] = (dot(ext_u[a0 - li:a1 - li], ext_u[a0 - lj:a1 - lj]) if j < p
                             else dot(g[ta - c0:], ext_u[a0 - li - lj:a1 - li - lj]))
                continue
            assert W is not None and ext_v is not None
            if j < p:                          # phi_i, phi_j
                val = W[i, j]
            elif i < p:                        # phi_i, theta_j
                val = dot(ext_u[a0 - li:a1 - li], ext_v[a0 - lj:a1 - lj])
                val += W[i, j]
            else:                              # theta_i, theta_j
                val = dot(ext_v[a0 - li:a1 - li], ext_v[a0 - lj:a1 - lj])
                val += 2.0 * dot(g[ta - c0:], ext_v[a0 - li - lj:a1 - li - lj])
            out[i, j] = 2.0 * val
    return out


def derivatives(model: ExactLikelihood, ev: Evaluation, *, hessian: bool
                ) -> tuple[FloatArray, FloatArray, FloatArray | None]:
    """Exact dS/dbeta and dD/dbeta at ``ev``, and (optionally) the Hessian of S.

    The gradient: the start-up block's part by central differences of the block, the steady
    part from the adjoint; the Hessian from the derivatives of a_t = phi(B)/theta(B) x_t
    (see :mod:`fogts.arma.likelihood`), neglecting O(1) start-up terms against O(n) sums.
    The Hessian uses the series itself, not minus mu_hat (an O(mu_hat) approximation;
    ``fit_arma`` passes a series whose sample mean is removed, so mu_hat is O(n^-1/2)).
    """
    p, q, n, s = model.p, model.q, model.n, ev.s
    theta, mu = ev.theta, ev.mu
    k = p + q
    dS, dD, h, e_tr = _startup_part(model, ev)
    e = model.innovations(ev)
    gx, ge, g_sum, g_first = _adjoint_pass(model, ev, e)
    if q:
        model.work.holder = None      # the workspace now holds the adjoint g
    if s < n:
        grad_ss = np.empty(k)
        g_sum = g_sum if mu else 0.0
        for i in range(1, p + 1):
            grad_ss[i - 1] = -gx[i - 1] + mu * g_sum
        for j in range(1, q + 1):
            grad_ss[p + j - 1] = -ge[j - 1]
        if q:
            # start-up terms: the steady recursion starts from the block's last innovations
            de = (e_tr[0::2, -q:] - e_tr[1::2, -q:]) / (2 * h[:, None])  # (k, q)
            for u in range(min(q, n - s)):
                c = np.zeros(k)
                for j in range(u + 1, q + 1):
                    c -= theta[j - 1] * de[:, q + u - j]
                grad_ss += g_first[u] * c
        dS = dS + 2.0 * grad_ss
    if not hessian:
        return dS, dD, None
    return dS, dD, _hessian_pass(model, ev, e if q else None)

