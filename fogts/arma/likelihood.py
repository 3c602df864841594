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

s starts at 512 and grows by 8x until the block is steady (up to s = n: then it is all exact
banded Cholesky, e.g. an MA root on the unit circle).

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
from dataclasses import dataclass

import numpy as np

from fogts._typing import FloatArray
from fogts.arma.correlation import dot
from fogts.arma.region import admissible, spectral_radius
from fogts.errors import ModelFitError

__all__ = ["Evaluation", "ExactLikelihood", "lag_dot"]

_TOL_P = 1e-13            # the start-up block is steady when its last row is this close
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


def _psi_weights(phi: FloatArray, theta: FloatArray, nlag: int) -> FloatArray:
    """psi_0..psi_nlag of x_t = sum psi_j a_{t-j} (psi_j = theta_j + sum_k phi_k psi_{j-k})."""
    psi = np.zeros(nlag + 1)
    psi[0] = 1.0
    for j in range(1, nlag + 1):
        acc = theta[j - 1] if j <= theta.size else 0.0
        for k in range(1, min(j, phi.size) + 1):
            acc += phi[k - 1] * psi[j - k]
        psi[j] = acc
    return psi


def _arma_acov(phi: FloatArray, theta: FloatArray, psi: FloatArray, nlag: int) -> FloatArray:
    """Autocovariances gamma(0..nlag-1) of a unit-variance ARMA (Brockwell & Davis eq. 3.3.8)."""
    p, q = phi.size, theta.size
    if nlag == 0:
        return np.zeros(0)
    th = np.r_[1.0, theta]
    c = np.array([float(np.dot(th[k:q + 1], psi[:q + 1 - k])) if k <= q else 0.0
                  for k in range(p + 1)])
    A = np.eye(p + 1)
    for k in range(p + 1):
        for i in range(1, p + 1):
            A[k, abs(k - i)] -= phi[i - 1]
    gam = np.linalg.solve(A, c)
    return gam[:nlag]


@dataclass
class Evaluation:
    """The likelihood's pieces at one (phi, theta): innovations, S, D and the objective f."""

    phi: FloatArray
    theta: FloatArray
    s: int                 # first index of the steady-state part
    e: FloatArray          # innovations a_t (unit sigma2 scale: x is fixed, F_t relative)
    F: FloatArray          # relative innovation variances of the transient, length s
    S: float
    D: float
    f: float
    mu: float = 0.0        # GLS mean (0 without a mean)
    s11: float = 0.0       # sum of the constant's squared innovations / F: Var(mu) = sigma2/s11

    @property
    def beta(self) -> FloatArray:
        return np.r_[self.phi, self.theta]


class ExactLikelihood:
    """Exact profile likelihood of an ARMA(p, q) on a fixed series x: zero-mean, or with its
    mean profiled out by GLS (``mean=True``, see :meth:`evaluate`)."""

    def __init__(self, x: FloatArray, p: int, q: int, mean: bool = False) -> None:
        self.x = x
        self.n = x.shape[0]
        self.p = p
        self.q = q
        self.mean = mean
        self.nu = self.n - 1 if mean else self.n   # the observations' degrees of freedom
        self.order = max(p, q, 1)       # lfilter order

    def transient(self, phis: FloatArray, thetas: FloatArray, s: int | None = None, *,
                  series: FloatArray | None = None, with_ones: bool = False
                  ) -> tuple[int, FloatArray, FloatArray]:
        """Exact innovations for t < s, for B parameter vectors (rows of phis/thetas).

        Ansley (1979): z = (x_1..x_p, W_{p+1}..W_n) with W_t = phi(B) x_t has a banded
        covariance (bandwidth max(p, q)) and the same innovations as x; its banded Cholesky
        factor L gives the innovation variances F_t = L_tt^2 and innovations e_t = L_tt (L^-1 z)_t
        (this is the Kalman filter's output, computed by LAPACK dpbtrf/dtbtrs).  With ``s=None``
        the length grows (512, x8, ...) until the last row is steady: |F - 1| and the distance of
        the last Cholesky row from (theta_q..theta_1, 1) below 1e-13, or s = n.

        ``series`` replaces x (e.g. x minus its GLS mean); ``with_ones`` also filters the
        constant series 1 (the innovations of the mean's regressor), as a last axis of 2.

        Returns ``s`` and the innovations, (B, s) or (B, s, 2), and the relative innovation
        variances, (B, s).
        """
        n = self.n
        if s is not None:
            out = [self._banded(phis[b], thetas[b], s, series=series, with_ones=with_ones)
                   for b in range(phis.shape[0])]
            return s, np.array([o[0] for o in out]), np.array([o[1] for o in out])
        s_try = min(n, max(512, 16 * self.order))
        while True:
            e, F, steady = self._banded(phis[0], thetas[0], s_try, check=True, series=series,
                                        with_ones=with_ones)
            if steady or s_try >= n:
                break
            s_try = min(n, 8 * s_try)
        es, fs = [e], [F]
        for b in range(1, phis.shape[0]):
            eb, fb, _ = self._banded(phis[b], thetas[b], s_try, series=series,
                                     with_ones=with_ones)
            es.append(eb)
            fs.append(fb)
        return s_try, np.array(es), np.array(fs)

    def _banded(self, phi: FloatArray, theta: FloatArray, s: int, check: bool = False,
                series: FloatArray | None = None, with_ones: bool = False
                ) -> tuple[FloatArray, FloatArray, bool]:
        from scipy.linalg import lapack

        p, q, m = self.p, self.q, self.order
        x = (self.x if series is None else series)[:s]
        z = np.column_stack((x, np.ones(s))) if with_ones else x.copy()
        if p:
            b = np.empty(p + 1)
            b[0] = 1.0
            b[1:] = -phi
            if with_ones:
                z[p:, 0] = np.convolve(x, b, mode="valid")
                z[p:, 1] = float(np.sum(b))
            else:
                z[p:] = np.convolve(x, b, mode="valid")
        ab = self._band_covariance(phi, theta, s)
        c, info = lapack.dpbtrf(ab, lower=1)
        if info != 0:
            raise ModelFitError(f"the covariance of the first {s} samples is not positive "
                                f"definite (LAPACK dpbtrf info={info})")
        w, info = lapack.dtbtrs(c, z, uplo="L")
        diag = c[0]
        e = np.asarray(w) * diag[:, None] if with_ones else np.asarray(w).ravel() * diag
        F = diag * diag
        steady = False
        if check:
            t = s - 1
            dev = abs(F[t] - 1.0)
            for d in range(1, m + 1):
                target = theta[d - 1] if d <= q else 0.0
                dev = max(dev, abs(c[d, t - d] / diag[t - d] - target))
            steady = dev < _TOL_P and s > p + q
        return e, F, steady

    def _band_covariance(self, phi: FloatArray, theta: FloatArray, s: int) -> FloatArray:
        """The band of Cov(z) in LAPACK's lower storage: ab[d, j] = Cov(z_{j+d}, z_j)."""
        p, q, m = self.p, self.q, self.order
        th = np.empty(q + 1)
        th[0] = 1.0
        th[1:] = theta
        psi = _psi_weights(phi, theta, q)
        gam_x = _arma_acov(phi, theta, psi, p)
        # the MA(q) autocovariance of W_t = phi(B)x_t everywhere but in the first p columns
        # (x-x and x-W covariances, Ansley 1979)
        ab = np.zeros((m + 1, s))
        for d in range(min(q, m) + 1):
            ab[d, :s - d] = float(np.dot(th[:q + 1 - d], th[d:q + 1]))
        for j in range(min(p, s)):
            for d in range(min(m, s - 1 - j) + 1):
                if j + d < p:
                    ab[d, j] = gam_x[d]
                elif d <= q:
                    ab[d, j] = float(np.dot(th[d:q + 1], psi[:q + 1 - d]))
                else:
                    ab[d, j] = 0.0
        return ab

    def _polys(self, phi: FloatArray, theta: FloatArray) -> tuple[FloatArray, FloatArray]:
        L = self.order
        b = np.zeros(L + 1)
        b[0] = 1.0
        b[1:self.p + 1] = -phi
        a = np.zeros(L + 1)
        a[0] = 1.0
        a[1:self.q + 1] = theta
        return b, a

    def evaluate(self, phi: FloatArray, theta: FloatArray) -> Evaluation:
        """Exact innovations, S, D and the profile objective f at (phi, theta).

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
        s, e_tr, f_tr = self.transient(phi[None, :], theta[None, :], with_ones=self.mean)
        n, F = self.n, f_tr[0]
        e = np.empty(n)
        e[:s] = e_tr[0][:, 0] if self.mean else e_tr[0]
        if s < n:
            self._steady_innovations(phi, theta, s, e)
        mu = s11 = 0.0
        if self.mean:
            mu, s11 = self._remove_gls_mean(phi, theta, s, e, F, e_tr[0][:, 1])
        S = float(np.dot(e[:s], e[:s] / F))
        if s < n:
            tail = e[s:]
            S += dot(tail, tail)
        D = float(np.sum(np.log(F))) + (math.log(s11 / n) if self.mean else 0.0)
        if not (math.isfinite(S) and S > 0.0 and math.isfinite(D)):
            raise ModelFitError(f"the likelihood is not finite (S={S}, D={D})")
        fval = 0.5 * self.nu * math.log(S / self.nu) + 0.5 * D
        return Evaluation(phi=phi, theta=theta, s=s, e=e, F=F, S=S, D=D, f=fval, mu=mu,
                          s11=s11)

    def _steady_zi(self, b: FloatArray, a: FloatArray, x: FloatArray, e: FloatArray,
                   s: int) -> FloatArray:
        """lfilter's state (direct form II transposed) at s from the past of input and output."""
        L = self.order
        zi = np.zeros(L)
        for i in range(L):
            for k in range(i + 1, L + 1):
                zi[i] += b[k] * x[s + i - k] - a[k] * e[s + i - k]
        return zi

    def _steady_innovations(self, phi: FloatArray, theta: FloatArray, s: int,
                            e: FloatArray) -> None:
        """Fill e[s:] with the steady-state innovations of x (e[:s] already exact)."""
        from scipy.signal import lfilter

        x = self.x
        if self.q == 0:
            # pure AR: a_t = phi(B) x_t is a FIR filter of the observed past (s >= p)
            e[s:] = np.convolve(x[s - self.p:], np.r_[1.0, -phi], mode="valid")
            return
        b, a = self._polys(phi, theta)
        e[s:] = lfilter(b, a, x[s:], zi=self._steady_zi(b, a, x, e, s))[0]

    def _ones_tail(self, phi: FloatArray, theta: FloatArray, s: int,
                   ones_tr: FloatArray) -> tuple[FloatArray, float]:
        """Innovations of the constant series 1 from s on: an explicit head, then the constant
        c = phi(1)/theta(1) they converge to geometrically (at the MA roots' rate), reached
        when the last max(p, q) values are within 1e-14 of it (or at the end of the series)."""
        from scipy.signal import lfilter

        b, a = self._polys(phi, theta)
        c = float(np.sum(b) / np.sum(a))
        if self.q == 0:
            return np.zeros(0), c
        L, total = self.order, self.n - s
        zi = self._steady_zi(b, a, np.ones(s), ones_tr, s)
        pieces: list[FloatArray] = []
        done, size = 0, 4096
        while done < total:
            m = min(size, total - done)
            y, zi = lfilter(b, a, np.ones(m), zi=zi)
            pieces.append(y)
            done += m
            if m >= L and float(np.max(np.abs(y[-L:] - c))) <= 1e-14 * abs(c):
                break
            size *= 4
        return np.concatenate(pieces), c

    def _remove_gls_mean(self, phi: FloatArray, theta: FloatArray, s: int, e: FloatArray,
                         F: FloatArray, ones_tr: FloatArray) -> tuple[float, float]:
        """Subtract mu e_1 from the innovations e of x in place, mu the GLS mean; returns
        mu and s11 = sum e_1^2 / F (Var(mu) = sigma2 / s11)."""
        n = self.n
        w = ones_tr / F
        sx1 = float(np.dot(e[:s], w))
        s11 = float(np.dot(ones_tr, w))
        head, c = (self._ones_tail(phi, theta, s, ones_tr) if s < n else (np.zeros(0), 0.0))
        m = head.size
        if s < n:
            sx1 += dot(e[s:s + m], head) + c * float(np.sum(e[s + m:]))
            s11 += dot(head, head) + c * c * (n - s - m)
        mu = sx1 / s11
        e[:s] -= mu * ones_tr
        e[s:s + m] -= mu * head
        e[s + m:] -= mu * c
        return mu, s11

    def derivatives(self, ev: Evaluation, *, hessian: bool
                    ) -> tuple[FloatArray, FloatArray, FloatArray | None]:
        """Exact dS/dbeta and dD/dbeta, and (optionally) the Hessian of S (see the module docstring)."""
        from scipy.signal import lfilter

        theta, s, e = ev.theta, ev.s, ev.e
        p, q, n = self.p, self.q, self.n
        # with the GLS mean, the derivatives of S at the fixed mu = mu_hat are those of the
        # profile (envelope theorem: dS/dmu = 0 there): the series is x - mu_hat, used as such
        # in the start-up block and through its linearity in the steady sums (no copy of x);
        # the Hessian below uses x itself, an O(mu_hat) approximation (fit_arma passes a
        # series whose sample mean is removed, so mu_hat is O(n^-1/2))
        x, mu = self.x, ev.mu
        k = p + q
        beta = ev.beta
        h = _fd_steps(beta, p, _FD_STEP)
        pert = np.repeat(beta[None, :], 2 * k, axis=0)
        idx = np.arange(k)
        pert[2 * idx, idx] += h
        pert[2 * idx + 1, idx] -= h
        _, e_tr, f_tr = self.transient(pert[:, :p], pert[:, p:], s=s, series=x[:s] - mu,
                                       with_ones=self.mean)
        d_tr = np.sum(np.log(f_tr), axis=1)
        if self.mean:
            d_tr += np.log(self._s11_perturbed(pert, s, e_tr[:, :, 1], f_tr) / n)
            e_tr = e_tr[:, :, 0]
        s_tr = np.sum(e_tr * e_tr / f_tr, axis=1)
        dS = (s_tr[0::2] - s_tr[1::2]) / (2 * h)
        dD = (d_tr[0::2] - d_tr[1::2]) / (2 * h)
        a_poly = np.r_[1.0, theta]
        # adjoint g = theta(B^-1)^-1 a, run back from the end over the whole series: on [s, n)
        # it is exactly the adjoint of the steady block (for the gradient); before s it serves
        # the Hessian approximation
        gfull = np.ascontiguousarray(lfilter([1.0], a_poly, e[::-1])[::-1]) if q else e
        if s < n:
            g = gfull[s:]
            grad_ss = np.empty(k)
            g_sum = float(np.sum(g)) if mu else 0.0
            for i in range(1, p + 1):
                grad_ss[i - 1] = -lag_dot(gfull, x, 0, i, s) + mu * g_sum
            for j in range(1, q + 1):
                grad_ss[p + j - 1] = -lag_dot(gfull, e, 0, j, s)
            if q:
                # start-up terms: the steady recursion starts from the block's last innovations
                de = (e_tr[0::2, s - q:s] - e_tr[1::2, s - q:s]) / (2 * h[:, None])  # (k, q)
                for u in range(min(q, n - s)):
                    c = np.zeros(k)
                    for j in range(u + 1, q + 1):
                        c -= theta[j - 1] * de[:, q + u - j]
                    grad_ss += g[u] * c
            dS = dS + 2.0 * grad_ss
        if not hessian:
            return dS, dD, None
        u_ = lfilter([1.0], a_poly, x) if q else x
        v_ = lfilter([1.0], a_poly, e) if q else e
        t0 = max(p + q, 2 * q)      # the largest lag used below
        jac = [(u_, i) for i in range(1, p + 1)] + [(v_, j) for j in range(1, q + 1)]
        HS = np.empty((k, k))
        for i in range(k):
            for j in range(i, k):
                val = lag_dot(jac[i][0], jac[j][0], jac[i][1], jac[j][1], t0)
                if i < p <= j:          # phi_i, theta_j
                    val += lag_dot(gfull, u_, 0, jac[i][1] + jac[j][1], t0)
                elif i >= p:            # theta_i, theta_j
                    val += 2.0 * lag_dot(gfull, v_, 0, jac[i][1] + jac[j][1], t0)
                HS[i, j] = HS[j, i] = 2.0 * val
        return dS, dD, HS

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


