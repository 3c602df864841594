"""AR and MA roots of an ARMA model and its stationarity and invertibility.

Convention (statsmodels): roots z of phi(z) = 1 - phi_1 z - ... - phi_p z^p and of
theta(z) = 1 + theta_1 z + ... + theta_q z^q; the model is stationary (invertible) when every
|z| > 1.  The inverse roots lambda = 1/z factor the polynomials: phi(B) = prod (1 - lambda_i B).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

from fogts._typing import FloatArray

__all__ = ["Roots", "arma_roots", "unit_circle_root"]


def _sorted_roots(r: np.ndarray) -> np.ndarray:
    r = np.asarray(r, dtype=np.complex128)
    if r.size == 0:
        return r
    order = np.lexsort((np.round(r.imag, 12), np.round(r.real, 12), np.round(np.abs(r), 12)))
    return r[order]


@dataclass(frozen=True)
class Roots:
    """AR and MA roots of a fitted ARMA model (statsmodels' convention).

    Attributes
    ----------
    ar, ma : ndarray of complex128
        Roots z of phi(z) = 1 - phi_1 z - ... - phi_p z^p and theta(z) = 1 + theta_1 z + ...
        (statsmodels' ``arroots``/``maroots``); sorted by modulus.
    ar_inverse, ma_inverse : ndarray of complex128
        Inverse roots lambda = 1/z: phi(B) = prod (1 - lambda_i B), theta(B) = prod (1 - mu_j B).
    stationary, invertible : bool
        Every AR (MA) root outside the unit circle, i.e. every |lambda| < 1.
    """

    ar: np.ndarray
    ma: np.ndarray
    ar_inverse: np.ndarray
    ma_inverse: np.ndarray
    stationary: bool
    invertible: bool

    @property
    def ar_modulus(self) -> FloatArray:
        return np.abs(self.ar).astype(np.float64)

    @property
    def ma_modulus(self) -> FloatArray:
        return np.abs(self.ma).astype(np.float64)

    @property
    def ar_radius(self) -> float:
        """Largest |AR inverse root| (< 1: stationary)."""
        return float(np.max(np.abs(self.ar_inverse))) if self.ar_inverse.size else 0.0

    @property
    def ma_radius(self) -> float:
        """Largest |MA inverse root| (< 1: invertible)."""
        return float(np.max(np.abs(self.ma_inverse))) if self.ma_inverse.size else 0.0

    def to_dict(self) -> dict[str, Any]:
        def cl(v: np.ndarray) -> list[dict[str, float]]:
            return [{"real": float(z.real), "imag": float(z.imag)} for z in v]

        return {"ar": cl(self.ar), "ma": cl(self.ma),
                "ar_modulus": self.ar_modulus.tolist(), "ma_modulus": self.ma_modulus.tolist(),
                "ar_inverse": cl(self.ar_inverse), "ma_inverse": cl(self.ma_inverse),
                "stationary": self.stationary, "invertible": self.invertible}


def arma_roots(ar: Any, ma: Any) -> Roots:
    """Roots and inverse roots of phi(z) and theta(z) (statsmodels sign convention).

    Parameters
    ----------
    ar : array_like
        phi_1..phi_p in x_t = phi_1 x_{t-1} + ... + a_t + theta_1 a_{t-1} + ...
    ma : array_like
        theta_1..theta_q.

    Examples
    --------
    >>> r = arma_roots([-0.2699, -0.002968], [0.277])
    >>> np.round(r.ar_inverse.real, 4).tolist(), np.round(r.ma_inverse.real, 4).tolist()
    ([-0.0115, -0.2584], [-0.277])
    """
    phi = np.atleast_1d(np.asarray(ar, dtype=np.float64))
    theta = np.atleast_1d(np.asarray(ma, dtype=np.float64))
    lam = np.roots(np.r_[1.0, -phi]) if phi.size else np.zeros(0, complex)
    mu = np.roots(np.r_[1.0, theta]) if theta.size else np.zeros(0, complex)
    z_ar = np.roots(np.r_[1.0, -phi][::-1]) if phi.size else np.zeros(0, complex)
    z_ma = np.roots(np.r_[1.0, theta][::-1]) if theta.size else np.zeros(0, complex)
    return Roots(ar=_sorted_roots(z_ar), ma=_sorted_roots(z_ma),
                 ar_inverse=_sorted_roots(lam), ma_inverse=_sorted_roots(mu),
                 stationary=bool(np.all(np.abs(lam) < 1.0)),
                 invertible=bool(np.all(np.abs(mu) < 1.0)))


def unit_circle_root(inverse_roots: np.ndarray, nobs: int) -> complex | None:
    """The largest inverse root if it lies on the unit circle, within 1/n of it; else None.

    Within 1/n an MA(1) coefficient theta = -1 + gamma/n cannot be told from theta = -1
    (local-to-unity asymptotics, Davis & Dunsmuir 1996, *Econometric Theory* 12, 1-29): its
    ML estimate converges at rate n and is not asymptotically normal, and it is where ML
    estimates pile up by chance.

    Examples
    --------
    >>> unit_circle_root(arma_roots([], [-1.0]).ma_inverse, 2000)
    (1+0j)
    >>> unit_circle_root(arma_roots([], [-0.99]).ma_inverse, 2000) is None
    True
    """
    r = np.asarray(inverse_roots, dtype=np.complex128)
    if r.size == 0:
        return None
    top = complex(r[int(np.argmax(np.abs(r)))])
    return top if 1.0 - abs(top) <= 1.0 / nobs else None
