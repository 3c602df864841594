"""Parameter redundancy of a fitted ARMA model: nearly cancelling roots, insignificant terms.

* *near cancellation*: an AR inverse root and an MA inverse root closer than
  :data:`NEAR_CANCEL_TOL` in the complex plane.  The factor (1 - lambda B) then nearly
  divides both sides, so ARMA(p, q) is close to ARMA(p - 1, q - 1) and the pair is not
  identified.  Example: the drift paper's x_t = -0.2699 x_{t-1} - 0.002968 x_{t-2} + a_t +
  0.277 a_{t-1} has AR inverse roots -0.2584 and -0.0115 and the MA inverse root -0.277:
  distance 0.019;
* *insignificant coefficient*: an AR or MA coefficient with |estimate / stderr| < 1.96.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any, Literal

import numpy as np

from fogts.arma.roots import Roots
from fogts.arma.whiteness import BAND_Z

__all__ = ["NEAR_CANCEL_TOL", "RedundancyFlag", "insignificant_terms", "near_cancellations"]

#: Largest distance between an AR and an MA inverse root called a near cancellation.
NEAR_CANCEL_TOL = 0.1


@dataclass(frozen=True)
class RedundancyFlag:
    """A sign that a candidate has more parameters than the data support.

    Attributes
    ----------
    kind : {"near_cancellation", "insignificant"}
    message : str
        One plain-language sentence.
    details : dict
        ``near_cancellation``: ``ar_root``, ``ma_root`` (inverse roots, complex),
        ``distance``, ``tolerance``; ``insignificant``: ``param``, ``estimate``, ``bse``, ``t``.
    """

    kind: Literal["near_cancellation", "insignificant"]
    message: str
    details: dict[str, Any]

    def to_dict(self) -> dict[str, Any]:
        det: dict[str, Any] = {}
        for k, v in self.details.items():
            det[k] = ({"real": float(v.real), "imag": float(v.imag)}
                      if isinstance(v, complex | np.complexfloating) else v)
        return {"kind": self.kind, "message": self.message, **det}


def _fmt_root(z: complex) -> str:
    if abs(z.imag) < 1e-12:
        return f"{z.real:+.4g}"
    return f"{z.real:+.4g}{z.imag:+.4g}i"


def near_cancellations(roots: Roots, *, tol: float = NEAR_CANCEL_TOL
                       ) -> tuple[RedundancyFlag, ...]:
    """AR/MA inverse-root pairs closer than ``tol``: a common factor that nearly cancels.

    Each MA inverse root is paired with its nearest AR inverse root (each AR root used
    once, closest pairs first).

    Examples
    --------
    >>> from fogts.arma.roots import arma_roots
    >>> f = near_cancellations(arma_roots([-0.2699, -0.002968], [0.277]))
    >>> f[0].kind, round(f[0].details["distance"], 3)
    ('near_cancellation', 0.019)
    """
    lam, mu = roots.ar_inverse, roots.ma_inverse
    if lam.size == 0 or mu.size == 0:
        return ()
    dist = np.abs(lam[:, None] - mu[None, :])
    pairs = sorted((float(dist[i, j]), i, j) for i in range(lam.size) for j in range(mu.size))
    used_i: set[int] = set()
    used_j: set[int] = set()
    flags = []
    for d, i, j in pairs:
        if d >= tol or i in used_i or j in used_j:
            continue
        used_i.add(i)
        used_j.add(j)
        ar_r, ma_r = complex(lam[i]), complex(mu[j])
        flags.append(RedundancyFlag(
            "near_cancellation",
            f"AR root {_fmt_root(ar_r)} nearly cancels MA root {_fmt_root(ma_r)} "
            f"(distance {d:.3g} < {tol:g}): the model is close to one with a lower order",
            {"ar_root": ar_r, "ma_root": ma_r, "distance": d, "tolerance": tol}))
    return tuple(flags)


def insignificant_terms(params: dict[str, float], bse: dict[str, float], *,
                        z: float = BAND_Z) -> tuple[RedundancyFlag, ...]:
    """AR/MA coefficients whose |estimate / standard error| < ``z`` (default 1.96).

    ``sigma2`` is not tested; a coefficient without a finite standard error is skipped.

    Examples
    --------
    >>> f = insignificant_terms({"ar.L1": 0.5, "ar.L2": 0.01, "sigma2": 1.0},
    ...                         {"ar.L1": 0.01, "ar.L2": 0.01, "sigma2": 0.01})
    >>> [x.details["param"] for x in f]
    ['ar.L2']
    """
    flags = []
    for name, est in params.items():
        if not name.startswith(("ar.", "ma.")):
            continue
        se = bse.get(name, math.nan)
        if not (math.isfinite(se) and se > 0):
            continue
        t = est / se
        if abs(t) < z:
            flags.append(RedundancyFlag(
                "insignificant",
                f"{name} = {est:.4g} is not significant (|t| = {abs(t):.2f} < {z:g})",
                {"param": name, "estimate": float(est), "bse": float(se), "t": float(t)}))
    return tuple(flags)

