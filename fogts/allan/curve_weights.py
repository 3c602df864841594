"""The weights of a published Allan curve's points: each point's equivalent degrees of
freedom (EDF), which the noise fit needs (:mod:`fogts.allan.noise_lsq`), and the record
length they imply.  Used by :mod:`fogts.allan.curve_input`.

Sources, in order: an ``edf`` column; an ``errors`` column (IEEE Std 952-1997 C.3's
relative error of sigma, ``1/sqrt(2 (N/m - 1))``, as SMAC-Group/avar writes it, so
``edf = 1/(2 errors^2)``); an ``alpha`` column (Stable32's noise identification) with the
record length; the record length with alpha from the curve's local slope
(:func:`slope_alpha`).  The last two use :func:`fogts.allan.edf.edf_for` (Greenhall & Riley
2003; NIST SP1065 sec. 5.3).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from fogts._typing import FloatArray, IntArray
from fogts.allan.edf import edf_for
from fogts.errors import DataError, InsufficientDataError
from fogts.io.curve_table import CurveTable

__all__ = ["CurveWeights", "curve_weights", "record_length", "slope_alpha"]


@dataclass(frozen=True)
class CurveWeights:
    """Each point's EDF and the alpha at it (``alpha_method``: ``"file"`` or ``"slope"``,
    :func:`slope_alpha`; an edf or errors column gives the EDF without it), what they came
    from, and the record
    length ``m (edf + 1)`` at the shortest tau (IEEE 952 C.3 inverted)."""

    edf: FloatArray
    alpha: IntArray
    alpha_method: tuple[str, ...]
    description: str
    n_estimate: int


def slope_alpha(tau: FloatArray, dev: FloatArray, kind: str) -> IntArray:
    """Power-law exponent alpha of the rate spectrum at each tau from the curve's local
    log-log slope.

    The variance of the Allan family goes as ``tau^mu`` with ``mu = -alpha - 1`` (NIST
    SP1065 sec. 5.2.4, Table 5; the modified variance down to alpha = 2 at mu = -3), so
    ``alpha = round(-mu - 1)`` with ``mu`` the central difference of ``log sigma^2``
    against ``log tau`` (one-sided at the ends), clipped to the estimator's range
    ([-2, 2]; [-4, 2] for the Hadamard variances).  The unmodified variances cannot tell
    alpha = 1 from 2 (both give mu = -2): a slope steeper than -1.5 is taken as white
    phase noise, alpha = 2 (a gyro's angle quantization, IEEE Std 952-1997 Annex C).

    Examples
    --------
    >>> tau = np.array([1.0, 2, 4, 8, 16])
    >>> slope_alpha(tau, tau**-0.5, "oadev").tolist(), slope_alpha(tau, tau**0.5, "oadev").tolist()
    ([0, 0, 0, 0, 0], [-2, -2, -2, -2, -2])
    """
    if tau.size < 2:
        return np.zeros(tau.size, dtype=np.int64)
    mu = np.gradient(np.log(np.maximum(dev, np.finfo(float).tiny) ** 2), np.log(tau))
    raw = np.rint(-mu - 1.0)
    lowest = -4 if kind in ("hdev", "ohdev") else -2
    if kind != "mdev":
        raw = np.where(raw >= 1, 2, raw)
    return np.clip(raw, lowest, 2).astype(np.int64)


def record_length(table: CurveTable, rows: np.ndarray, kind: str, m: IntArray,
                  given: int | None) -> tuple[int | None, str]:
    """The number of rate samples behind the curve and its source: given, the file's
    header, or an oadev ``n`` (number of terms) column (``N = n + 2m - 1``, SP1065 eq. 11),
    else ``(None, "")``."""
    if given is not None:
        return given, "given"
    if "n_samples" in table.meta:
        return int(table.meta["n_samples"]), "file"
    terms = table.numbers.get("terms")
    if terms is not None and kind == "oadev" and np.all(np.isfinite(terms[rows])):
        implied = terms[rows] + 2 * m - 1
        if np.all(implied == implied[0]) and implied[0] >= 2:
            return int(implied[0]), "file (number of terms)"
    return None, ""


def curve_weights(table: CurveTable, rows: np.ndarray, kind: str, tau: FloatArray,
                  dev: FloatArray, m: IntArray, n: int | None) -> CurveWeights:
    """The EDF of each point from the first source the file or ``n`` allows (module
    docstring).

    Raises
    ------
    DataError
        A non-finite or non-positive ``edf`` or ``errors`` cell, an alpha outside the
        estimator's range, or no source at all (the message names what to give).
    """
    alpha = slope_alpha(tau, dev, kind)
    sloped = ("slope",) * tau.size
    for role, text in (("edf", "the edf column"),
                       ("errors", "the errors column: IEEE 952 C.3 edf = 1/(2 errors^2)")):
        if role in table.numbers:
            values = _positive(table, rows, role)
            edf = values if role == "edf" else 1.0 / (2.0 * values**2)
            return CurveWeights(edf, alpha, sloped, text, _n_estimate(edf, m))
    if n is None:
        raise DataError(f"{table.source}: the noise fit needs each point's weight, and "
                        "this curve has neither an edf nor an errors column, nor the record "
                        "length to compute them: give n_samples=N (the number of rate "
                        "samples the curve was computed from), or add an edf or errors "
                        "column")
    file_alpha = table.numbers.get("alpha")
    if file_alpha is not None and np.all(np.isfinite(file_alpha[rows])):
        alpha, method = file_alpha[rows].astype(np.int64), "file"
        text = f"Greenhall-Riley EDF of {kind} from the file's alpha and N = {n:,}"
    else:
        method = "slope"
        text = (f"Greenhall-Riley EDF of {kind} with alpha from the curve's local slope and "
                f"N = {n:,}")
    try:
        edf = edf_for(kind, alpha, m, n + 1)
    except InsufficientDataError as exc:
        raise DataError(f"{table.source}: n_samples = {n:,} is too short for this curve "
                        f"({exc}); give the record's own n_samples=N") from None
    except DataError as exc:  # an alpha column outside the estimator's range
        raise DataError(f"{table.source}: column {table.columns.get('alpha', 'alpha')!r}: "
                        f"{exc}") from None
    return CurveWeights(edf, alpha, (method,) * tau.size, text, n)


def _positive(table: CurveTable, rows: np.ndarray, role: str) -> FloatArray:
    values = table.numbers[role][rows]
    bad = np.flatnonzero(~np.isfinite(values) | (values <= 0))
    if bad.size:
        raise DataError(f"{table.source}: column {table.columns[role]!r} has "
                        f"{float(values[bad[0]])!r} at {table.where(rows[bad[0]])}; {role} "
                        "must be a finite number > 0")
    return values


def _n_estimate(edf: FloatArray, m: IntArray) -> int:
    """IEEE 952 C.3 inverted at the shortest tau: ``edf = N/m - 1`` -> ``N = m (edf + 1)``."""
    return round(float(m[0]) * (float(edf[0]) + 1.0))
