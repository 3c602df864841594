"""A cross-check of fogts' deviations against allantools on the same data and taus."""

from __future__ import annotations

import warnings
from typing import TYPE_CHECKING, Any

import numpy as np

if TYPE_CHECKING:
    from fogts._typing import FloatArray
    from fogts.allan.result import AllanResult

__all__ = ["allantools_check"]

_PEER_FUNCTIONS = {"adev": "adev", "oadev": "oadev", "mdev": "mdev", "hdev": "hdev",
                   "ohdev": "ohdev", "totdev": "totdev"}


def allantools_check(y: FloatArray, res: AllanResult) -> dict[str, Any]:
    """Recompute ``res`` with allantools (``data_type='freq'``) and compare.

    Parameters
    ----------
    y : ndarray
        The rate samples ``res`` was computed from.
    res : AllanResult
        fogts' result; its kind, taus and sample rate are passed to allantools.

    Returns
    -------
    dict
        ``peer`` (allantools' version and call), ``n_compared`` (taus both computed),
        ``max_rel_diff`` and ``tau_at_max`` (the largest relative difference and where),
        ``n_terms_equal`` (whether both used the same number of terms at every tau).
        For a bias-corrected total deviation, allantools' uncorrected value is divided by
        the square root of fogts' bias (Howe 1999) before the comparison.
    """
    import allantools

    func = getattr(allantools, _PEER_FUNCTIONS[res.kind])
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        taus, dev, _, n = func(np.asarray(y, dtype=np.float64), rate=res.fs_hz,
                               data_type="freq", taus=np.asarray(res.tau_s))
    m_peer = np.rint(np.asarray(taus) * res.fs_hz).astype(np.int64)
    common, mine, theirs = np.intersect1d(res.m, m_peer, return_indices=True)
    peer = np.asarray(dev, dtype=np.float64)[theirs]
    label = f"allantools {allantools.__version__} {res.kind}(data_type='freq')"
    if res.bias_corrected:  # allantools' totdev is uncorrected: apply fogts' bias to it
        from fogts.allan.bias import totdev_bias

        peer = peer / np.sqrt(totdev_bias(res.alpha[mine], res.m[mine], res.n_samples + 1))
        label += " / sqrt(fogts' totdev_bias)"
    rel = np.abs(res.dev[mine] - peer) / np.abs(peer)
    worst = int(np.argmax(rel)) if rel.size else -1
    return {"peer": label,
            "n_compared": int(common.size),
            "max_rel_diff": float(rel[worst]) if rel.size else None,
            "tau_at_max": float(res.tau_s[mine][worst]) if rel.size else None,
            "n_terms_equal": bool(np.array_equal(res.n[mine], np.asarray(n)[theirs]))}
