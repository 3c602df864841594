"""ARMA series from a model: :func:`simulate_arma`."""

from __future__ import annotations

from typing import Any

import numpy as np

from fogts._typing import FloatArray, RngLike
from fogts._validate import as_rng, check_int
from fogts.arma.spec import ArmaSpec
from fogts.simulate.streams import DEFAULT_CHUNK, ArmaStream

__all__ = ["simulate_arma"]


def simulate_arma(model_or_params: Any, n: int, *, rng: RngLike = None,
                  burn_in: int | None = None) -> FloatArray:
    """Simulate ``n`` samples of an ARMA(p, q) process.

    Parameters
    ----------
    model_or_params : ArmaFit, Selection, mapping, str or ArmaSpec
        Anything :meth:`fogts.arma.spec.ArmaSpec.from_any` accepts: a fitted model (e.g.
        ``Selection.best``), ``{"ar": [...], "ma": [...], "sigma2": ...}``, statsmodels
        parameter names (``ar.L1``, ``ma.L1``, ``sigma2``, ``const``) or
        ``"ar=...;ma=...;sigma2=..."``.  Sign convention of statsmodels:
        x_t = phi_1 x_{t-1} + ... + a_t + theta_1 a_{t-1}.
    n : int
        Number of samples.
    rng : Generator, int or None
        Random source.
    burn_in : int, optional
        Start-up samples discarded; default: enough for the slowest AR pole to decay by
        1e-12 (at least 10 (p + q), at most 10^6).

    Returns
    -------
    ndarray of float64, shape (n,)

    Notes
    -----
    The filter is ``scipy.signal.lfilter([1, theta...], [1, -phi...], a)`` with the state
    carried across chunks and through the burn-in (Box, Jenkins & Reinsel, *Time Series
    Analysis*, ch. 3).

    Examples
    --------
    >>> x = simulate_arma({"ar": [0.9], "sigma2": 1.0}, 200_000, rng=0)
    >>> round(float(np.var(x)), 1)   # 1 / (1 - 0.81) = 5.26
    5.3
    """
    spec = ArmaSpec.from_any(model_or_params)
    n = check_int("n", n, minimum=1)
    stream = ArmaStream(spec, as_rng(rng), burn_in)
    out = np.empty(n, dtype=np.float64)
    for i0 in range(0, n, DEFAULT_CHUNK):
        i1 = min(n, i0 + DEFAULT_CHUNK)
        out[i0:i1] = stream.next(i0, i1 - i0)
    return out
