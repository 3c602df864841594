"""The exact Gaussian likelihood of a zero-mean ARMA(p, q) series and its derivatives.

The likelihood (Brockwell & Davis 1991, eqs. 8.7.4-8.7.5) needs the one-step innovations a_t
and their relative variances F_t: the output of the Kalman filter started from the stationary
covariance, which statsmodels' ``ARIMA(order=(p,0,q), trend="n")`` runs.  They are computed in
two pieces:

* a start-up block t < s by Ansley's (1979) transformation: z = (x_1..x_p, phi(B)x_{p+1..}) has
  a banded covariance (bandwidth max(p, q)), so a LAPACK banded Cholesky gives F_t and a_t
  exactly;
* from t = s on, where the filter is steady (F_t = 1 and the Cholesky rows equal theta to
  1e-13; this happens geometrically fast for an invertible model), the filter is the ARMA
  inversion a_t = x_t - sum phi_i x_{t-i} - sum theta_j a_{t-j}: one scipy.signal.lfilter pass
  started from the past of x and a_t (np.convolve for a pure AR).

s starts at 512 and grows by 8x until the block is steady (up to s = n, e.g. an MA root on
the unit circle).  Past ``startup_stream.CAP`` samples :mod:`fogts.arma.startup_stream`
continues the same banded Cholesky in chunks, keeping only sums and the filter's state.

sigma2 is concentrated out (sigma2_hat = S/n), leaving the profile objective

    f(beta) = n/2 log(S(beta)/n) + 1/2 D(beta),   S = sum a_t^2/F_t,  D = sum log F_t.

Its derivatives:

* the exact gradient: the steady part of dS/dbeta from one reverse (adjoint) lfilter pass
  g = theta(B^-1)^-1 a, the start-up block's part by central differences of the block;
* the Hessian of S from the derivatives of a_t = phi(B)/theta(B) x_t:
  da/dphi_i = -u_{t-i}, da/dtheta_j = -v_{t-j} (u = x/theta(B), v = a/theta(B)),
  d2a/dphi_i dtheta_j = w_{t-i-j}, d2a/dtheta_j dtheta_l = 2 z_{t-j-l} (w = u/theta(B),
  z = v/theta(B)), with sum_t a_t w_{t-m} = sum_t g_t u_{t-m} and
  sum_t a_t z_{t-m} = sum_t g_t v_{t-m}; it neglects O(1) start-up terms against O(n) sums;
* the Fisher information, Brockwell & Davis eq. 8.8.3;
* the Hessians of S and D by central differences of the exact gradient.

References
----------
P. J. Brockwell and R. A. Davis, *Time Series: Theory and Methods*, 2nd ed., 1991.
C. F. Ansley, "An algorithm for the exact likelihood of a mixed autoregressive-moving average
process", Biometrika 66 (1979) 59-65.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Iterator, Sequence
from dataclasses import dataclass, field

import numpy as np

from fogts._typing import FloatArray
from fogts.arma.correlation import dot
from fogts.arma.region import admissible, spectral_radius
from fogts.arma.startup_block import banded_innovations
from fogts.arma.worker import Worker
from fogts.arma.workspace import Workspace
from fogts.errors import ModelFitError

__all__ = ["CHUNK", "Evaluation", "ExactLikelihood", "Workspace", "lag_dot"]

CHUNK = 1 << 16           # samples per block of the series-length passes (cache-resident)
_FD_STEP = 1e-6           # central-difference step for the transient's derivatives
_HESS_STEP = 1e-5         # central-difference step of the exact gradient for the Hessians


def _fd_steps(beta: FloatArray, p: int, h: float) -> FloatArray:
    """Central-difference step per parameter: ``h``, halved until both ``beta +- step``
    stay stationary and invertible.  Near the boundary (an AR root within ``h`` of 1, as a
    white + rate-random-walk gyro record gives ARMA(1,1)) a full step would evaluate a
    non-stationary model, whose covariance has no Cholesky factor."""
    steps = np.full(beta.size, h)
    for j in range(beta.size):
        while steps[j] > 1e-12:
            up, down = beta.copy(), beta.copy()
            up[j] += steps[j]
            down[j] -= steps[j]
            if admissible(up[:p], up[p:], margin=0.0) and \
                    admissible(down[:p], down[p:], margin=0.0):
                break
            steps[j] *= 0.5
    return steps


def lag_dot(a: FloatArray, b: FloatArray, i: int, j: int, t0: int) -> float:
    """sum_{t=t0}^{n-1} a_{t-i} b_{t-j}, a dot product of two contiguous slices."""
    m = a.shape[0] - t0
    return dot(a[t0 - i:t0 - i + m], b[t0 - j:t0 - j + m])


@dataclass(eq=False)
class Evaluation:
    """The likelihood at one (phi, theta): S, D, the objective f, and what rebuilds the
    innovations (:meth:`ExactLikelihood.innovations`) without storing a series-length array:
    the start-up block's innovations and the filter state where the steady part starts."""

    phi: FloatArray
    theta: FloatArray
    s: int                 # first index of the steady-state part
    F: FloatArray          # relative innovation variances of the transient, length s
    head: FloatArray       # the block's innovations of the series (s,), or (s, 2) with those of 1
    S: float = math.nan
    D: float = math.nan
    f: float = math.nan
    mu: float = 0.0        # GLS mean (0 without a mean)
    s11: float = 0.0       # sum of the constant's squared innovations / F: Var(mu) = sigma2/s11
    zi: FloatArray | None = None     # lfilter state at s (None for a pure AR)
    ones_tail: FloatArray = field(default_factory=lambda: np.zeros(0))  # e_1 from s on ...
    ones_c: float = 0.0    # ... and the constant it settles to
    streamed: bool = False  # a block too long to hold: F and head are empty (startup_stream)

    @property
    def beta(self) -> FloatArray:
        return np.r_[self.phi, self.theta]


class ExactLikelihood:
    """Exact profile likelihood of an ARMA(p, q) on a fixed series: zero-mean, or with its
    mean profiled out by GLS (``mean=True``, see :meth:`evaluate`).

    The series is ``x / scale - offsets[0] - offsets[1] ...``, formed block by block (the
    same floating-point operations as on a whole standardised copy, without that copy).
    One series-length :class:`Workspace` (``work``; models of the same length may share one)
    holds the innovations of the latest evaluation; every other series-length pass runs in
    cache-sized blocks (``CHUNK``), the filters carrying their state across blocks.
    """

    def __init__(self, x: FloatArray, p: int, q: int, mean: bool = False, *,
                 scale: float = 1.0, offsets: Sequence[float] = (),
                 work: Workspace | None = None) -> None:
        self.x = x
        self.n = x.shape[0]
        self.p = p
        self.q = q
        self.mean = mean
        self.nu = self.n - 1 if mean else self.n   # the observations' degrees of freedom
        self.order = max(p, q, 1)       # lfilter order
        self.scale = float(scale)
        self.offsets = tuple(float(o) for o in offsets)
        self.work = Workspace(self.n) if work is None else work

    def series(self, c0: int, c1: int) -> FloatArray:
        """Samples c0..c1-1 of the modelled series (a view of x when there is nothing to do)."""
        seg = self.x[c0:c1]
        if self.scale != 1.0:
            seg = seg / self.scale
        for off in self.offsets:
            if seg.base is None:      # a new array: the same subtraction in place
                seg -= off
            else:
                seg = seg - off
        return seg

    def bounds(self, s: int) -> list[int]:
        """Block boundaries of a pass: the start-up block [0, s), then ``CHUNK``-long blocks."""
        return [0, *range(s, self.n, CHUNK), self.n] if s < self.n else [0, self.n]

    def transient(self, phis: FloatArray, thetas: FloatArray, s: int | None = None, *,
                  series: FloatArray | None = None, with_ones: bool = False
                  ) -> tuple[int, FloatArray, FloatArray]:
        """Exact innovations for t < s, for B parameter vectors (rows of phis/thetas).

        Ansley (1979), :func:`fogts.arma.startup_block.banded_innovations`.  With ``s=None``
        the length grows (512, x8, ...) until the block is steady, or s = n.  ``series``
        replaces the modelled series (e.g. minus its GLS mean); ``with_ones`` also filters
        the constant series 1 (the innovations of the mean's regressor), as a last axis of 2.

        Returns ``s`` and the innovations, (B, s) or (B, s, 2), and the relative innovation
        variances, (B, s).
        """
        n = self.n

        def head(length: int) -> FloatArray:
            return self.series(0, length) if series is None else series[:length]

        if s is not None:
            block = head(s)
            out = [banded_innovations(phis[b], thetas[b], block, with_ones=with_ones)
                   for b in range(phis.shape[0])]
            return s, np.array([o[0] for o in out]), np.array([o[1] for o in out])
        grown = self._grow(phis[0], thetas[0], head, with_ones, n)
        assert grown is not None
        s_try, block, e, F = grown
        es, fs = [e], [F]
        for b in range(1, phis.shape[0]):
            eb, fb, _ = banded_innovations(phis[b], thetas[b], block, with_ones=with_ones)
            es.append(eb)
            fs.append(fb)
        return s_try, np.array(es), np.array(fs)

    def _grow(self, phi: FloatArray, theta: FloatArray, head: Callable[[int], FloatArray],
              with_ones: bool, cap: int
              ) -> tuple[int, FloatArray, FloatArray, FloatArray] | None:
        """The steady start-up block (s, the series' block, its innovations and F), grown
        512, x8, ... up to n; None if it would grow past ``cap`` samples."""
        n = self.n
        s_try = min(n, max(512, 16 * self.order))
        while True:
            block = head(s_try)
            e, F, steady = banded_innovations(phi, theta, block, check=True,
                                              with_ones=with_ones)
            if steady or s_try >= n:
                return s_try, block, e, F
            s_try = min(n, 8 * s_try)
            if s_try > cap:
                return None

    def polys(self, phi: FloatArray, theta: FloatArray) -> tuple[FloatArray, FloatArray]:
        """lfilter's numerator phi(B) and denominator theta(B), both of length order + 1."""
        L = self.order
        b = np.zeros(L + 1)
        b[0] = 1.0
        b[1:self.p + 1] = -phi
        a = np.zeros(L + 1)
        a[0] = 1.0
        a[1:self.q + 1] = theta
        return b, a

    def evaluate(self, phi: FloatArray, theta: FloatArray) -> Evaluation:
        """Exact innovations (into the workspace), S, D and the profile objective f.

        With ``mean=True`` the mean is removed by generalised least squares and the
        likelihood is the restricted (marginal) one of the n - 1 contrasts free of the mean
        (Harville 1974, *Biometrika* 61, 383-385):

            f = nu/2 log(S/nu) + D/2,  nu = n - 1,  D = sum log F_t + log(s11 / n).

        The innovations are linear in the data, so those of x - mu are e_x - mu e_1 (e_1: the
        innovations of the constant series 1); S(mu) = sum (e_x - mu e_1)^2 / F is least at
        the GLS mean mu = sum(e_x e_1 / F) / s11, s11 = sum(e_1^2 / F) = 1' R^-1 1
        (Brockwell & Davis 2002, *Introduction to Time Series and Forecasting*, 2nd ed.,
        sec. 6.6).  The term log s11 (the information on the mean) is what a fit of demeaned
        data as zero-mean, or the profile likelihood, lacks: without it an MA root on the
        unit circle (theta(1) = 0, where s11 grows like n^3) gains about log(n)/2
        (Tunnicliffe Wilson 1989, *J. R. Statist. Soc. B* 51, 15-27).
        """
        from fogts.arma import startup_stream
        from fogts.arma.likelihood_passes import tail_pass

        grown = self._grow(phi, theta, lambda k: self.series(0, k), self.mean,
                           startup_stream.CAP)
        if grown is None:
            return startup_stream.evaluate(self, phi, theta)
        s, _, head, F = grown
        n = self.n
        ev = Evaluation(phi=phi, theta=theta, s=s, F=F, head=head)
        e = self.work.take()
        e[:s] = ev.head[:, 0] if self.mean else ev.head
        ssq = tail_pass(self, ev, e)
        if self.mean:
            self._remove_gls_mean(ev, e)
        S = float(np.dot(e[:s], e[:s] / F))
        if s < n:
            tail = e[s:]
            S += dot(tail, tail) if ssq is None else ssq
        D = float(np.sum(np.log(F))) + (math.log(ev.s11 / n) if self.mean else 0.0)
        return self.finish(ev, S, D)

    def finish(self, ev: Evaluation, S: float, D: float) -> Evaluation:
        """Set S, D and f = nu/2 log(S/nu) + D/2 on ``ev``, the workspace's latest."""
        if not (math.isfinite(S) and S > 0.0 and math.isfinite(D)):
            raise ModelFitError(f"the likelihood is not finite (S={S}, D={D})")
        ev.S, ev.D, ev.f = S, D, 0.5 * self.nu * math.log(S / self.nu) + 0.5 * D
        self.work.holder = ev
        return ev

    def innovations(self, ev: Evaluation) -> FloatArray:
        """The exact innovations a_t at ``ev`` (unit-sigma2 scale of the modelled series).

        Returns the workspace itself: valid until the next evaluation or derivative; copy
        it to keep it.  Rebuilt (bit for bit) if a later evaluation has overwritten it.
        """
        if self.work.holder is ev and self.work.array is not None:
            return self.work.array
        if ev.streamed:
            from fogts.arma.startup_stream import rebuild

            return rebuild(self, ev)
        e = self.work.take()
        s = ev.s
        e[:s] = ev.head[:, 0] if self.mean else ev.head
        for c0, c1, y in self._tail_chunks(ev):
            e[c0:c1] = y
        if self.mean:
            self._correct(ev, e, 0)
        self.work.holder = ev
        return e

    def innovation_blocks(self, ev: Evaluation) -> Iterator[tuple[int, int, FloatArray]]:
        """The innovations at ``ev`` block by block, (c0, c1, a[c0:c1]), equal to
        :meth:`innovations` without its series-length array: the start-up block with the
        first steady one, then ``CHUNK``-long blocks (a series of up to s + CHUNK samples
        is one block, so sums over it are those over the whole array)."""
        if ev.streamed:
            from fogts.arma.startup_stream import blocks

            yield from blocks(self, ev)
            return
        s = ev.s
        y = (ev.head[:, 0] if self.mean else ev.head).copy()
        if self.mean:
            self._correct(ev, y, 0)
        first = True
        for c0, c1, t in self._tail_chunks(ev):
            if self.mean:
                self._correct(ev, t, c0)
            if first:
                y = np.concatenate((y, t))
                first = False
                yield 0, c1, y
            else:
                yield c0, c1, t
        if first:
            yield 0, s, y

    def _tail_chunks(self, ev: Evaluation, worker: Worker | None = None
                     ) -> Iterator[tuple[int, int, FloatArray]]:
        """The steady-state innovations of the series (before the GLS mean's removal) from s
        on, block by block: the ARMA inversion a_t = x_t - sum phi_i x_{t-i} - sum theta_j
        a_{t-j}, one lfilter started from the block's last innovations (np.convolve for a
        pure AR, a FIR filter of the observed past)."""
        from scipy.signal import lfilter

        s, n, p = ev.s, self.n, self.p
        if s >= n:
            return
        if self.q == 0:
            poly = np.r_[1.0, -ev.phi]
            for c0 in range(s, n, CHUNK):
                c1 = min(n, c0 + CHUNK)
                yield c0, c1, np.convolve(self.series(c0 - p, c1), poly, mode="valid")
            return
        b, a = self.polys(ev.phi, ev.theta)
        if ev.zi is None:
            L = self.order
            e_head = ev.head[:, 0] if self.mean else ev.head
            ev.zi = _steady_zi(b, a, self.series(s - L, s), e_head[s - L:s])
        zi = ev.zi
        # a worker thread forms the next block's series while this block is filtered
        worker = Worker(0) if worker is None else worker
        ahead = worker.submit(self.series, s, min(n, s + CHUNK))
        for c0 in range(s, n, CHUNK):
            c1 = min(n, c0 + CHUNK)
            xs = ahead()
            if c1 < n:
                ahead = worker.submit(self.series, c1, min(n, c1 + CHUNK))
            y, zi = lfilter(b, a, xs, zi=zi)
            yield c0, c1, y

    def _correct(self, ev: Evaluation, y: FloatArray, c0: int) -> None:
        """Subtract mu e_1 in place from the innovations y of samples c0..c0+len(y)-1."""
        s, mu, head = ev.s, ev.mu, ev.ones_tail
        c1 = c0 + y.shape[0]
        if c0 < s:
            y[:min(c1, s) - c0] -= mu * ev.head[c0:min(c1, s), 1]
        lo, hi = max(c0, s), min(c1, s + head.size)
        if lo < hi:
            y[lo - c0:hi - c0] -= mu * head[lo - s:hi - s]
        lo = max(c0, s + head.size)
        if lo < c1:
            y[lo - c0:] -= mu * ev.ones_c

    def _ones_tail(self, phi: FloatArray, theta: FloatArray, s: int,
                   ones_tr: FloatArray) -> tuple[FloatArray, float]:
        """Innovations of the constant series 1 from s on: an explicit head, then the constant
        c = phi(1)/theta(1) they converge to geometrically (at the MA roots' rate), reached
        when the last max(p, q) values are within 1e-14 of it, or settled within 1e-12 of it
        (rounding), or at the end of the series."""
        from scipy.signal import lfilter

        b, a = self.polys(phi, theta)
        c = float(np.sum(b) / np.sum(a))
        if self.q == 0:
            return np.zeros(0), c
        L, total = self.order, self.n - s
        zi = _steady_zi(b, a, np.ones(L), ones_tr[-L:])
        pieces: list[FloatArray] = []
        done, size, last = 0, 4096, math.inf
        while done < total:
            m = min(size, total - done)
            y, zi = lfilter(b, a, np.ones(m), zi=zi)
            pieces.append(y)
            done += m
            if m >= L:
                dev = float(np.max(np.abs(y[-L:] - c)))
                # settled: within 1e-14 of c, or at the rounding floor of the recursion
                # (c = phi(1)/theta(1) ~ 0 near a unit AR root), no closer than a piece ago
                if dev <= 1e-14 * abs(c) or (dev <= 1e-12 and dev >= 0.5 * last):
                    break
                last = dev
            size *= 4
        return np.concatenate(pieces), c

    def _remove_gls_mean(self, ev: Evaluation, e: FloatArray) -> None:
        """Subtract mu e_1 from the innovations e of the series in place, mu the GLS mean;
        sets ev.mu and ev.s11 = sum e_1^2 / F (Var(mu) = sigma2 / s11)."""
        n, s = self.n, ev.s
        ones_tr = ev.head[:, 1]
        w = ones_tr / ev.F
        sx1 = float(np.dot(e[:s], w))
        s11 = float(np.dot(ones_tr, w))
        if s < n:
            ev.ones_tail, ev.ones_c = self._ones_tail(ev.phi, ev.theta, s, ones_tr)
        head, c = ev.ones_tail, ev.ones_c
        m = head.size
        if s < n:
            sx1 += dot(e[s:s + m], head) + c * float(np.sum(e[s + m:]))
            s11 += dot(head, head) + c * c * (n - s - m)
        ev.mu, ev.s11 = sx1 / s11, s11
        self._correct(ev, e, 0)

    def derivatives(self, ev: Evaluation, *, hessian: bool
                    ) -> tuple[FloatArray, FloatArray, FloatArray | None]:
        """Exact dS/dbeta and dD/dbeta, and (optionally) the Hessian of S (see the module
        docstring and :mod:`fogts.arma.likelihood_passes`)."""
        from fogts.arma.likelihood_passes import derivatives

        return derivatives(self, ev, hessian=hessian)

    def information(self, phi: FloatArray, theta: FloatArray) -> FloatArray:
        """Per-observation information matrix of (phi, theta), Brockwell & Davis eq. 8.8.3."""
        from scipy.signal import lfilter

        p, q = self.p, self.q
        rho = max(spectral_radius(phi), spectral_radius(-theta))
        length = 64 if rho < 1e-3 else int(min(200_000, max(64, math.log(1e-18) / math.log(rho))))
        imp = np.zeros(length)
        imp[0] = 1.0
        psi_u = lfilter([1.0], np.r_[1.0, -phi], imp) if p else imp
        psi_v = lfilter([1.0], np.r_[1.0, theta], imp) if q else imp

        def cross(a: FloatArray, b: FloatArray, lag: int) -> float:   # sum_k a_k b_{k+lag}
            if lag >= 0:
                return float(np.dot(a[:length - lag], b[lag:]))
            return float(np.dot(a[-lag:], b[:length + lag]))

        k = p + q
        M = np.empty((k, k))
        for i in range(p):
            for j in range(p):
                M[i, j] = cross(psi_u, psi_u, abs(i - j))
            for j in range(q):
                M[i, p + j] = M[p + j, i] = cross(psi_u, psi_v, i - j)
        for i in range(q):
            for j in range(q):
                M[p + i, p + j] = cross(psi_v, psi_v, abs(i - j))
        return M

    def _s11_perturbed(self, pert: FloatArray, s: int, ones_tr: FloatArray,
                       f_tr: FloatArray) -> FloatArray:
        """s11 = 1' R^-1 1 at each row of ``pert`` (the start-up block's innovations of 1
        given); it depends on the parameters only, not on the data."""
        out = np.sum(ones_tr * ones_tr / f_tr, axis=1)
        if s < self.n:
            p = self.p
            for b in range(pert.shape[0]):
                head, c = self._ones_tail(pert[b, :p], pert[b, p:], s, ones_tr[b])
                out[b] += dot(head, head) + c * c * (self.n - s - head.size)
        return out

    def hessian_f(self, ev: Evaluation, dS: FloatArray, HS: FloatArray) -> FloatArray:
        """Hessian of the profile objective f = nu/2 log S + D/2 (D's O(1) curvature dropped)."""
        n, S = self.nu, ev.S
        return 0.5 * n / S * HS - 0.5 * n / S**2 * np.outer(dS, dS)

    def fd_hessians(self, ev: Evaluation) -> tuple[FloatArray, FloatArray]:
        """Hessians of S and D by central differences of the exact gradient (cost 4k passes)."""
        p, k = self.p, self.p + self.q
        beta = ev.beta
        steps = _fd_steps(beta, p, _HESS_STEP)
        d2S = np.empty((k, k))
        d2D = np.empty((k, k))
        for j in range(k):
            grads = []
            hs = float(steps[j])
            for sgn in (1.0, -1.0):
                b2 = beta.copy()
                b2[j] += sgn * hs
                ev2 = self.evaluate(b2[:p], b2[p:])
                dS2, dD2, _ = self.derivatives(ev2, hessian=False)
                grads.append((dS2, dD2))
            d2S[:, j] = (grads[0][0] - grads[1][0]) / (2 * hs)
            d2D[:, j] = (grads[0][1] - grads[1][1]) / (2 * hs)
        return 0.5 * (d2S + d2S.T), 0.5 * (d2D + d2D.T)


def _steady_zi(b: FloatArray, a: FloatArray, x_prev: FloatArray,
               e_prev: FloatArray) -> FloatArray:
    """lfilter's state (direct form II transposed) at s from the last L = len(b) - 1 inputs
    and outputs before s."""
    L = b.shape[0] - 1
    zi = np.zeros(L)
    for i in range(L):
        for k in range(i + 1, L + 1):
            zi[i] += b[k] * x_prev[L + i - k] - a[k] * e_prev[L + i - k]
    return zi
