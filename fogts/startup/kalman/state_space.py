"""Harvey state-space form of an ARMA model: :func:`arma_state_space`.

With r = max(p, q + 1): α_{t+1} = T α_t + R a_{t+1}, y_t = Z α_t + ε_t, where
T = [φ | I_{r-1}; 0], R = (1, θ₁, …, θ_{r-1})' and Z = (1, 0, …, 0) (Harvey, 1989, §3.4;
Durbin & Koopman, 2012, §3.4).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import numpy as np

from fogts._typing import FloatArray
from fogts.arma.fit import model_name
from fogts.arma.spec import ArmaSpec
from fogts.errors import DataError

__all__ = ["ArmaStateSpace", "arma_state_space", "mle_model"]


@dataclass(frozen=True)
class ArmaStateSpace:
    """Harvey state-space matrices of an ARMA(p, q) model.

    Attributes
    ----------
    ar, ma : ndarray
        φ and θ (statsmodels sign).
    sigma2 : float
        Innovation variance.
    T, R, Z : ndarray
        Transition (r×r), selection (r×1) and design (1×r) matrices.
    name : str
        ``"AR(p)"``, ``"ARMA(p,q)"``...
    """

    ar: FloatArray
    ma: FloatArray
    sigma2: float
    T: FloatArray = field(repr=False)
    R: FloatArray = field(repr=False)
    Z: FloatArray = field(repr=False)
    name: str = ""

    @property
    def k_states(self) -> int:
        return int(self.T.shape[0])


def arma_state_space(model: Any) -> ArmaStateSpace:
    """Harvey state-space form of an ARMA model (see the module docstring).

    Parameters
    ----------
    model : ArmaFit, Selection, Candidate, mapping or ArmaSpec
        Anything :meth:`fogts.arma.spec.ArmaSpec.from_any` accepts
        (``{"ar.L1": 0.9, "sigma2": 1.0}`` works).

    Raises
    ------
    DataError
        Non-stationary AR part, non-positive σ², or an unrecognised model.

    Examples
    --------
    >>> ss = arma_state_space({"ar.L1": 0.5, "ar.L2": 0.2, "ma.L1": 0.3, "sigma2": 1.0})
    >>> ss.T.tolist(), ss.R.ravel().tolist()
    ([[0.5, 1.0], [0.2, 0.0]], [1.0, 0.3])
    """
    spec = ArmaSpec.from_any(model)
    ar, ma, sigma2 = np.asarray(spec.ar, float), np.asarray(spec.ma, float), spec.sigma2
    if ar.size:
        roots = np.roots(np.r_[1.0, -ar][::-1])
        if roots.size and np.min(np.abs(roots)) <= 1.0 + 1e-10:
            raise DataError(f"the AR part {ar.tolist()} is not stationary (a root of "
                            "1 - Σφ_i z^i lies on or inside the unit circle); the Kalman filter "
                            "needs a stationary model")
    p, q = ar.size, ma.size
    r = max(p, q + 1)
    T = np.zeros((r, r))
    T[:p, 0] = ar
    if r > 1:
        T[:-1, 1:] = np.eye(r - 1)
    R = np.zeros((r, 1))
    R[0, 0] = 1.0
    R[1:q + 1, 0] = ma
    Z = np.zeros((1, r))
    Z[0, 0] = 1.0
    return ArmaStateSpace(ar=ar, ma=ma, sigma2=sigma2, T=T, R=R, Z=Z, name=model_name(p, q))


def mle_model(y: FloatArray, ss: ArmaStateSpace, h: float) -> Any:
    """statsmodels ``MLEModel`` with the Harvey matrices, measurement variance ``h`` and a
    stationary initialisation."""
    from statsmodels.tsa.statespace.mlemodel import MLEModel

    mod = MLEModel(y, k_states=ss.k_states, k_posdef=1, initialization="stationary")
    mod["design"] = ss.Z
    mod["transition"] = ss.T
    mod["selection"] = ss.R
    mod["state_cov"] = np.array([[ss.sigma2]])
    mod["obs_cov"] = np.array([[h]])
    return mod
