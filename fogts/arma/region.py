"""The stationarity and invertibility region of ARMA coefficients.

Sign convention (statsmodels): phi(B) = 1 - phi_1 B - ... - phi_p B^p and
theta(B) = 1 + theta_1 B + ... + theta_q B^q.  The model is stationary (invertible) when every
inverse root of phi (theta) lies inside the unit circle.
"""

from __future__ import annotations

import numpy as np

from fogts._typing import FloatArray

__all__ = ["UNIT_ROOT_GAP", "admissible", "shrink_into_region", "spectral_radius",
           "unit_root_gap"]

#: An inverse AR root of a restricted-likelihood fit this close to 1 is taken as a unit root
#: (see :func:`fogts.arma.fit.fit_arma`, ``mean=True``).
UNIT_ROOT_GAP = 1e-4


def spectral_radius(c: FloatArray) -> float:
    """Largest modulus of the roots of z^k - c_1 z^{k-1} - ... - c_k (inverse-root modulus)."""
    c = np.asarray(c, dtype=float)
    if c.size == 0 or not np.any(c):
        return 0.0
    return float(np.max(np.abs(np.roots(np.r_[1.0, -c]))))


def admissible(phi: FloatArray, theta: FloatArray, margin: float = 1e-9) -> bool:
    """Stationary AR part and invertible MA part (statsmodels' enforced region)."""
    if not (np.all(np.isfinite(phi)) and np.all(np.isfinite(theta))):
        return False
    return (spectral_radius(phi) < 1.0 - margin) and (spectral_radius(-theta) < 1.0 - margin)


def shrink_into_region(phi: FloatArray, theta: FloatArray) -> tuple[FloatArray, FloatArray]:
    """Scale c_j -> lam^j c_j (every inverse root times lam) until the model is admissible."""
    out = []
    for c, sign in ((phi.copy(), 1.0), (theta.copy(), -1.0)):
        rho = spectral_radius(sign * c)
        if rho >= 0.98:
            c *= (0.98 / rho) ** np.arange(1, c.size + 1)
        out.append(c)
    return out[0], out[1]


def unit_root_gap(phi: FloatArray) -> float:
    """1 minus the largest real positive inverse root of phi(B) (inf without one)."""
    phi = np.asarray(phi, dtype=float)
    if phi.size == 0 or not np.any(phi):
        return float("inf")
    roots = np.roots(np.r_[1.0, -phi])
    real = roots.real[(np.abs(roots.imag) < 1e-9) & (roots.real > 0.0)]
    return float(1.0 - real.max()) if real.size else float("inf")
