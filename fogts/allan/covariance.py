"""Covariance of Allan-variance estimates implied by a power-law noise model.

The noise fit (:mod:`fogts.allan.noise`) needs the covariance of the variance estimates at
its taus: overlapping (and, less so, non-overlapping) Allan variances at neighbouring taus
are strongly correlated.  Each random IEEE-952 term is a power-law phase process with a
generalized covariance (Q: white phase, :math:`s^2\\delta(u)`; N: :math:`-|u|/2`; B:
:math:`u^2\\ln|u|/(4\\ln 2)`; K: :math:`|u|^3/4`, for unit coefficients), the covariance of
two second differences is a 9-term sum of it, and for Gaussian data
:math:`\\mathrm{Cov}[d_i^2, d_j^2] = 2\\,\\mathrm{Cov}[d_i, d_j]^2`, summed over all pairs
of terms: exactly for short lags, by Gauss-Legendre quadrature with an Euler-Maclaurin end
correction for long ones.  The method, its checks (SP1065's EDFs, exact phase-covariance
matrices, Monte Carlo) and its limits are described in :mod:`fogts.allan.noise`,
"Standard errors and confidence intervals".

:func:`covariance_basis` computes the basis once per curve (one 4 x 4 block per pair of
taus); :class:`CovarianceModel` turns it and the current coefficients into the covariance
matrix of the estimates.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.polynomial.legendre import leggauss

from fogts._typing import FloatArray, IntArray

__all__ = ["RANDOM_TERMS", "CovarianceModel", "covariance_basis", "model_covariance"]


#: Noise types with a random part, in this order: Q (white phase), N (white rate),
#: B (flicker rate), K (random-walk rate).  R (rate ramp) is deterministic.
RANDOM_TERMS: tuple[int, ...] = (-2, -1, 0, 1)
_W3 = np.array([1.0, -2.0, 1.0])
_WW = (_W3[:, None] * _W3[None, :]).ravel()
_GL_X, _GL_W = leggauss(16)
_EXACT_PIECE = 64      # pieces this short (in lags) are summed exactly
_FFM_REACH = 64        # flicker lags beyond 64 (m_i + m_j) contribute < 1e-6 relative
_MAX_PHASES = 4        # adev: residue classes summed one by one (else averaged)


def covariance_basis(kind: str, m: IntArray, n_samples: int, fs_hz: float,
                     powers: IntArray) -> FloatArray | None:
    """``B[i, j, p, q]`` with Cov[avar_i, avar_j] = sum_pq a_p a_q B[i, j, p, q].

    ``p, q`` index :data:`RANDOM_TERMS` (the coefficients ``a`` of ``sigma^2 = sum a_n
    tau^n`` in the caller's scaling).  For ``adev`` it is that of the non-overlapping
    estimates (:func:`_adev_pair_sums`); for ``oadev`` and ``totdev`` that of the
    overlapping ones (a ``totdev`` fit takes only its correlations,
    :class:`CovarianceModel`).  None when a tau has no term.
    """
    if kind == "adev":
        n_terms = n_samples // m - 1
        pair_sums = _adev_pair_sums
    else:
        n_terms = n_samples - 2 * m + 1
        pair_sums = _pair_sums
    if np.any(n_terms < 1):
        return None
    dt = 1.0 / fs_hz
    present = tuple(p in powers for p in RANDOM_TERMS)
    k = m.size
    basis = np.zeros((k, k, 4, 4))
    for i in range(k):
        for j in range(i, k):
            s = pair_sums(int(m[i]), int(m[j]), int(n_terms[i]), int(n_terms[j]), dt, present)
            s /= 2.0 * (m[i] * dt) ** 2 * (m[j] * dt) ** 2 * float(n_terms[i]) * float(n_terms[j])
            basis[i, j] = basis[j, i] = s
    return basis


def _pair_sums(mi: int, mj: int, ni: int, nj: int, dt: float,
               present: tuple[bool, ...]) -> FloatArray:
    """``S[p, q] = sum_h cnt(h) C_p(h) C_q(h)`` for the second differences at m_i, m_j.

    ``C_p(h)`` is the covariance of ``d_i(t)`` and ``d_j(t + h)`` for unit noise of type p,
    ``cnt(h)`` the number of term pairs at lag h.
    """
    d = (np.array([0.0, mj, 2.0 * mj])[None, :] - np.array([0.0, mi, 2.0 * mi])[:, None]).ravel()
    core_lo, core_hi = -2 * mj, 2 * mi  # the two windows overlap strictly inside
    lo, hi = -(ni - 1), nj - 1
    if present[2]:
        reach = _FFM_REACH * (mi + mj)
        lo, hi = max(lo, -reach), min(hi, reach)
    else:
        lo, hi = max(lo, core_lo + 1), min(hi, core_hi - 1)
    out = np.zeros((4, 4))
    cand = [np.array([lo, hi + 1, nj - ni, 0, core_lo, core_hi, core_lo + 1, core_hi + 1],
                     dtype=np.float64), -d]
    if present[2]:
        steps = 2.0 * (mi + mj) * 2.0 ** np.arange(int(math.log2(_FFM_REACH)))
        cand += [steps, -steps]
    pts = np.unique(np.concatenate(cand))
    pts = pts[(pts >= lo) & (pts <= hi + 1)]
    nodes, weights, _ = _piece_nodes(pts[:-1], pts[1:])
    lags, inverse = np.unique(-d, return_inverse=True)
    lags_ok = (lags >= -(ni - 1)) & (lags <= nj - 1)
    h = np.concatenate([nodes, lags])
    w = np.concatenate([weights, np.zeros(lags.size)])
    cnt = _count(h, ni, nj)
    cc = _continuous_cov(h, d, dt, core_lo, core_hi, present)  # (3, len(h))
    if hi >= lo:
        wt = w * cnt
        out[1:, 1:] = (cc * wt) @ cc.T
    if present[0]:  # white phase: covariance only where two phase points coincide
        cp = np.bincount(inverse, weights=_WW) / 3.0
        wq = np.where(lags_ok, cnt[-lags.size:], 0.0) * cp
        out[0, 0] = float(np.sum(wq * cp))
        out[0, 1:] = out[1:, 0] = cc[:, -lags.size:] @ wq
    return out


def _piece_nodes(p: FloatArray, q: FloatArray) -> tuple[FloatArray, FloatArray, FloatArray]:
    """Nodes x and weights w with ``sum w f(x) = sum_{h=p}^{q-1} f(h)`` over the pieces.

    Short pieces (at most :data:`_EXACT_PIECE`): every integer; long ones: Gauss-Legendre
    for the integral and the Euler-Maclaurin end correction
    ``sum_{h=p}^{q-1} f = integral_p^q f - (f(q) - f(p)) / 2``.  The third array places
    each node inside its own piece (the end node q just below q), for piecewise weights.
    """
    short = q - p <= _EXACT_PIECE
    lens = (q[short] - p[short]).astype(np.int64)
    first = np.repeat(p[short], lens)
    ints = first + (np.arange(int(lens.sum())) - np.repeat(np.cumsum(lens) - lens, lens))
    pl, ql = p[~short], q[~short]
    half = 0.5 * (ql - pl)[:, None]
    gl_h = (half * _GL_X + 0.5 * (ql + pl)[:, None]).ravel()
    gl_w = (half * _GL_W).ravel()
    nodes = np.concatenate([ints, gl_h, pl, ql])
    weights = np.concatenate([np.ones(ints.size), gl_w, np.full(pl.size, 0.5),
                              np.full(ql.size, -0.5)])
    return nodes, weights, np.concatenate([ints, gl_h, pl, np.nextafter(ql, -np.inf)])


def _count(h: FloatArray, ni: int, nj: int) -> FloatArray:
    return np.maximum(0.0, np.minimum(float(ni), nj - h) - np.maximum(0.0, -h))


def _adev_pair_sums(mi: int, mj: int, ni: int, nj: int, dt: float,
                    present: tuple[bool, ...]) -> FloatArray:
    """:func:`_pair_sums` for the non-overlapping estimator (``mi <= mj``).

    Term k of tau_i starts at sample ``k m_i`` (k < n_i), term l of tau_j at ``l m_j``, so
    the lag ``h = l m_j - k m_i`` runs over the lattice ``g Z``, ``g = gcd(m_i, m_j)``,
    ``m_i = g a``, ``m_j = g b``, and the pairs are no longer counted by a linear
    ``cnt(h)``.  Instead, for each l the k-sum runs over an arithmetic progression of step
    ``m_i`` through the residue class ``r = l b mod a`` (``h = g r + m_i t``,
    ``t = (l b - r) / a - k``), i.e. over consecutive t (:func:`_progression_points`).  On
    an octave grid ``a = 1`` and there is one class.  Otherwise the ``min(a, n_j)`` classes
    (``gcd(a, b) = 1``) are summed one by one if there are at most :data:`_MAX_PHASES`,
    else the k-sum is averaged over the ``a`` phases of the fine lattice (a sum over all of
    ``g Z`` with weight 1/a), which the equidistribution of ``l b mod a`` makes accurate
    for N, B and K.  White phase (Q) correlates only where phase points coincide,
    ``h = -d``; those pairs are counted exactly in every case.
    """
    g = math.gcd(mi, mj)
    a, b = mi // g, mj // g
    d = (np.array([0, mj, 2 * mj])[None, :] - np.array([0, mi, 2 * mi])[:, None]).ravel()
    out = np.zeros((4, 4))
    if any(present[1:]):
        reach = _FFM_REACH * (mi + mj) if present[2] else 0
        core = (-2 * mj + 1, 2 * mi - 1)  # where the two windows overlap

        def averaged(h_lo: int, h_hi: int, smooth: bool = False,
                     hole: tuple[int, int] | None = None) -> tuple[FloatArray, FloatArray]:
            # window of l: t = l b - a ni + 1 .. l b on the lattice g Z, weight 1/a
            return _progression_points(mi, mj, g, 0, 1 - a * ni, 0, b, nj, 1.0 / a,
                                       present, h_lo, h_hi, smooth, hole)

        parts: list[tuple[FloatArray, FloatArray]] = []
        if a == 1 or min(a, nj) > _MAX_PHASES:  # a = 1: one class, exact
            parts.append(averaged(*core, smooth=False))
        else:
            for l0 in range(min(a, nj)):  # class of l0: l = l0, l0 + a, ...
                r = (l0 * b) % a
                q0 = (l0 * b - r) // a  # window of l0: t = q0 - ni + 1 .. q0; then + b
                parts.append(_progression_points(mi, mj, mi, g * r, q0 - ni + 1, q0, b,
                                                 (nj - 1 - l0) // a + 1, 1.0, present,
                                                 *core))
        if present[2]:  # flicker beyond the windows' overlap: smooth, phase-averaged
            parts.append(averaged(-reach, reach, smooth=True, hole=core))
        h = np.concatenate([p[0] for p in parts])
        w = np.concatenate([p[1] for p in parts])
        cc = _continuous_cov(h, d.astype(np.float64), dt, -2 * mj, 2 * mi, present)
        out[1:, 1:] = (cc * w) @ cc.T
    if present[0]:  # white phase: exact number of pairs at each coincidence lag -d
        lags, inverse = np.unique(-d, return_inverse=True)
        cnt = np.array([_lattice_count(int(lag), a, b, g, ni, nj) for lag in lags])
        cp = np.bincount(inverse, weights=_WW) / 3.0
        cc = _continuous_cov(lags.astype(np.float64), d.astype(np.float64), dt, -2 * mj,
                             2 * mi, present)
        wq = cnt * cp
        out[0, 0] = float(np.sum(wq * cp))
        out[0, 1:] = out[1:, 0] = cc @ wq
    return out


def _lattice_count(lag: int, a: int, b: int, g: int, ni: int, nj: int) -> float:
    """Number of (k, l), k < ni, l < nj, with ``l b - k a = lag / g`` (g divides every lag)."""
    s = lag // g
    l0 = (s * pow(b, -1, a)) % a if a > 1 else 0  # l b = s (mod a)
    lo = max(0, -((-s) // b))                      # k = (l b - s) / a >= 0
    hi = min(nj - 1, ((ni - 1) * a + s) // b)      # k <= ni - 1
    if hi < lo:
        return 0.0
    return float((hi - l0) // a - (lo - 1 - l0) // a)


def _progression_points(mi: int, mj: int, step: int, phase: int, first: int, last: int,
                        stride: int, count: int, weight: float, present: tuple[bool, ...],
                        h_lo: int, h_hi: int, smooth: bool = False,
                        hole: tuple[int, int] | None = None) -> tuple[FloatArray, FloatArray]:
    """Lags ``x`` and weights ``w`` with ``sum w f(x) = weight sum_c sum_t f(phase + step t)``
    for the N, B, K covariance products f, over the ``count`` windows
    ``t = first + c stride .. last + c stride`` (c = 0, 1, ...; see :func:`_adev_pair_sums`)
    and the lags ``h_lo <= phase + step t <= h_hi`` outside ``hole`` (inclusive; its ends
    must be kinks).  ``smooth`` replaces the staircase number of windows covering t by its
    mean, a linear ramp, where more than :data:`_EXACT_PIECE` window ends fall in the range
    (for the smooth flicker tails, where each end would otherwise cut the t axis).

    As in :func:`_pair_sums`: the t axis is cut at the window ends that fall inside the
    support of f, at the kinks ``h = -d`` and (flicker) at geometric steps; each piece is
    covered by a constant number of windows and summed exactly when at most
    :data:`_EXACT_PIECE` long, by Gauss-Legendre with the Euler-Maclaurin end correction
    otherwise.
    """
    marks = (np.array([0.0, mi, 2.0 * mi])[:, None]
             - np.array([0.0, mj, 2.0 * mj])[None, :]).ravel()  # = -d
    if present[2]:
        steps = 2.0 * (mi + mj) * 2.0 ** np.arange(int(math.log2(_FFM_REACH)))
        marks = np.concatenate([marks, steps, -steps])
    t_min, t_max = -((phase - h_lo) // step), (h_hi - phase) // step

    def ends_inside(start: int) -> IntArray:  # window ends start + c stride in (t_min, t_max]
        c0 = max(0, -((start - t_min - 1) // stride))
        c1 = min(count - 1, (t_max - start) // stride)
        return start + stride * np.arange(c0, c1 + 1, dtype=np.int64)

    def n_started(start: int, at: FloatArray) -> FloatArray:  # windows with start <= at
        if smooth:
            return np.clip((at - start) / stride + 0.5, 0.0, float(count))
        return np.clip(np.floor((at - start) / stride) + 1.0, 0.0, float(count))

    ends = np.concatenate([ends_inside(first), ends_inside(last + 1)])
    smooth = smooth and ends.size > _EXACT_PIECE
    if smooth:  # the ramps' corners
        cuts = np.array([s + c for s in (first, last + 1) for c in (-0.5 * stride,
                                                                    (count - 0.5) * stride)])
        ends = np.floor(cuts[(cuts > t_min) & (cuts <= t_max)])
        ends = np.concatenate([ends, ends + 1])
    kinks = np.floor((marks - phase) / step)
    pts = np.unique(np.concatenate([np.array([t_min, t_max + 1]), ends, kinks, kinks + 1]
                                   ).astype(np.float64))
    pts = pts[(pts >= t_min) & (pts <= t_max + 1)]
    p, q = pts[:-1], pts[1:]
    if hole is not None:
        out = (phase + step * p > hole[1]) | (phase + step * (q - 1) < hole[0])
        p, q = p[out], q[out]
    t, w, at = _piece_nodes(p, q)
    # windows covering each node (constant on a piece, or the smooth ramp)
    w *= weight * (n_started(first, at) - n_started(last + 1, at))
    keep = w != 0
    return phase + step * t[keep], w[keep]


def _continuous_cov(h: FloatArray, d: FloatArray, dt: float, core_lo: int, core_hi: int,
                    present: tuple[bool, ...]) -> FloatArray:
    """Covariance of two second differences at lag h for unit N, B and K noise (3, len(h)).

    Generalized covariances (phase x in rate*s, u in s): N: -|u|/2; B (a_0 = 1):
    u^2 ln|u| / (4 ln 2); K (a_1 = 1): |u|^3 / 4.
    """
    u = (h[:, None] + d[None, :]) * dt
    au = np.abs(u)
    core = (h > core_lo) & (h < core_hi)
    out = np.zeros((3, h.size))
    if present[1]:
        out[0] = np.where(core, (-0.5 * au) @ _WW, 0.0)
    if present[2]:
        safe = np.where(au > 0, au, 1.0)
        out[1] = ((u * u * np.log(safe)) @ _WW) / (4.0 * math.log(2.0))
    if present[3]:
        out[2] = np.where(core, (0.25 * au**3) @ _WW, 0.0)
    return out


def model_covariance(basis: FloatArray, a: FloatArray, powers: IntArray) -> FloatArray:
    coef = np.zeros(4)
    for j, p in enumerate(powers):
        if int(p) in RANDOM_TERMS:
            coef[RANDOM_TERMS.index(int(p))] = a[j]
    return np.asarray(np.einsum("ijpq,p,q->ij", basis, coef, coef), dtype=np.float64)


@dataclass(frozen=True)
class CovarianceModel:
    """Covariance of the variance estimates of one curve, given the fit (module docstring).

    adev and oadev: the model covariance itself.  totdev: its correlations with the
    variances ``2 mu^2 / edf`` of totdev's own EDF (SP1065) on the diagonal; the
    reflected extension is left out of the correlations (the basis is oadev's).
    """

    basis: FloatArray
    powers: IntArray
    kind: str

    @property
    def label(self) -> str:
        if self.kind == "totdev":
            return ("totdev EDF variances with the correlations of the model covariance of "
                    "the oadev estimates")
        return f"the model covariance of the {self.kind} estimates"

    def raw(self, a: FloatArray) -> FloatArray:
        """The model covariance of the adev or oadev estimates for the coefficients ``a``."""
        return model_covariance(self.basis, a, self.powers)

    def __call__(self, a: FloatArray, mu: FloatArray, edf: FloatArray) -> FloatArray:
        cov = self.raw(a)
        if self.kind != "totdev":
            return cov
        sd = np.sqrt(np.maximum(np.diag(cov), 0.0))
        ok = sd > 0
        corr = np.eye(sd.size)
        corr[np.ix_(ok, ok)] = cov[np.ix_(ok, ok)] / np.outer(sd[ok], sd[ok])
        s = mu * np.sqrt(2.0 / edf)
        return np.asarray(corr * np.outer(s, s), dtype=np.float64)
