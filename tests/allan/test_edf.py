"""Tests of fogts.allan.edf: equivalent degrees of freedom of Allan-family variances.

References nobody here produced: ``allantools.edf_greenhall`` and ``allantools.edf_totdev``
(1e-9 relative); exact EDFs of white phase noise from the covariance matrix of the
estimator's terms (1e-9 relative); 40-digit decimal arithmetic.
"""

from __future__ import annotations

import decimal
import math

import allantools
import numpy as np
import pytest

from fogts.allan import edf as edf_module
from fogts.allan.edf import edf_for
from fogts.errors import DataError

EDF_RTOL = 1e-9
GREENHALL_KINDS = {  # kind -> allantools.edf_greenhall keywords
    "adev": {"d": 2, "overlapping": False, "modified": False},
    "oadev": {"d": 2, "overlapping": True, "modified": False},
    "mdev": {"d": 2, "overlapping": True, "modified": True},
    "hdev": {"d": 3, "overlapping": False, "modified": False},
    "ohdev": {"d": 3, "overlapping": True, "modified": False},
}



# =========================================================================== EDF
_EDF_GRID = [(n, m) for n in (50, 1001, 10001, 241218)
             for m in (1, 2, 3, 5, 8, 16, 33, 34, 50, 64, 100, 128, 1000, 4096)]


@pytest.mark.parametrize("kind", list(GREENHALL_KINDS))
@pytest.mark.parametrize("alpha", [2, 1, 0, -1, -2])
def test_edf_matches_allantools_greenhall(kind: str, alpha: int) -> None:
    checked = 0
    for n, m in _EDF_GRID:
        kw = GREENHALL_KINDS[kind]
        d = int(kw["d"])
        span = (m if kw["modified"] else 1) + m * d
        if span > n:
            continue
        try:
            ref = allantools.edf_greenhall(alpha=alpha, m=m, N=n, **kw)
        except NotImplementedError:  # alpha = 2 with few terms: see the exact test below
            continue
        assert edf_for(kind, alpha, m, n)[0] == pytest.approx(ref, rel=EDF_RTOL), (n, m)
        checked += 1
    assert checked >= 20


def test_edf_flicker_pm_large_m_is_free_of_roundoff() -> None:
    """alpha = 1, F = m: fogts sums the second difference as a series; allantools' direct
    form loses ~m^2 eps (4e-8 at m = 32768); 40-digit decimal arithmetic decides."""
    decimal.getcontext().prec = 40

    def sw(t: decimal.Decimal) -> decimal.Decimal:
        return decimal.Decimal(0) if t == 0 else t * t * abs(t).ln()

    for f in (8, 1000, 32768, 10**6):
        h = decimal.Decimal(1) / f
        for t in (0.0, 1.0 / f, 3.0 / f, 5.0 / f, 0.3, 1.0, 2.5, 7.0):
            td = decimal.Decimal(t)  # the exact binary value of t
            exact = float(f * f * (2 * sw(td) - sw(td - h) - sw(td + h)))
            assert edf_module._sx(np.array([t]), float(f), 1)[0] == pytest.approx(exact, rel=1e-12)
    ref = allantools.edf_greenhall(alpha=1, d=2, m=32768, N=241218, overlapping=False,
                                   modified=False)
    assert edf_for("adev", 1, 32768, 241218)[0] == pytest.approx(ref, rel=1e-6)


def _exact_white_pm_edf(kind: str, m: int, n: int) -> float:
    """EDF = tr(C)^2 / tr(C^2) of the estimator's terms for iid phase (Gaussian quadratic
    form), C = A A^T with A the matrix of the phase differences."""
    d, modified, overlapped = edf_module._FAMILY[kind]
    coef = [(-1) ** k * math.comb(d, k) for k in range(d + 1)]
    rows = []
    if modified:
        for j in range(n - 3 * m + 1):
            row = np.zeros(n)
            for i in range(m):
                for k, c in enumerate(coef):
                    row[j + i + k * m] += c
            rows.append(row)
    else:
        stride = 1 if overlapped else m
        j = 0
        while j + d * m <= n - 1:
            row = np.zeros(n)
            for k, c in enumerate(coef):
                row[j + k * m] += c
            rows.append(row)
            j += stride
    a = np.array(rows)
    c = a @ a.T
    return float(np.trace(c) ** 2 / np.sum(c * c))


@pytest.mark.parametrize("kind", list(GREENHALL_KINDS))
def test_edf_white_pm_is_exact(kind: str) -> None:
    """White phase noise: Greenhall's cases 1 and 4 are exact, including the few-term
    case (K <= d) that allantools does not implement."""
    for n, m in ((41, 1), (41, 3), (41, 7), (41, 13), (60, 19), (97, 24), (130, 32)):
        d, modified, _ = edf_module._FAMILY[kind]
        if (m if modified else 1) + m * d > n:
            continue
        assert edf_for(kind, 2, m, n)[0] == pytest.approx(_exact_white_pm_edf(kind, m, n),
                                                          rel=EDF_RTOL), (n, m)


@pytest.mark.parametrize(("d", "modified", "overlapped"),
                         [(2, False, True), (2, True, True), (3, False, True),
                          (2, False, False), (3, True, True)])
@pytest.mark.parametrize("alpha", [1, 0, -1, -2])
def test_edf_tables_agree_with_the_full_sum(d: int, modified: bool, overlapped: bool,
                                            alpha: int) -> None:
    """Greenhall & Riley's Tables 1-3 (used when J > 100) against the sum evaluated term by
    term (J_max = 1e7): the tables carry 3-4 digits; the approximations are within 3 %
    (largest: 2.6 %, alpha = 1, d = 3, m = 150, N = 1000, the rescaled-sum branch, where
    fogts equals allantools to 1e-12)."""
    for m, n in ((64, 100_000), (200, 200_000), (150, 1_000)):
        if (m if modified else 1) + m * d > n:
            continue
        approx = edf_module._greenhall_edf(alpha, d, m, modified, overlapped, n)
        full = edf_module._greenhall_edf(alpha, d, m, modified, overlapped, n, j_max=10**7)
        assert approx == pytest.approx(full, rel=0.03), (m, n)


@pytest.mark.parametrize("alpha", [2, 1, 0, -1, -2])
def test_totdev_edf_matches_allantools(alpha: int) -> None:
    for n, m in ((1001, 1), (1001, 16), (1001, 500), (19983, 8192), (241218, 65536)):
        ref = allantools.edf_totdev(n, m, alpha)
        assert edf_for("totdev", alpha, m, n)[0] == pytest.approx(ref, rel=EDF_RTOL)


def test_edf_broadcasts_alpha_against_m() -> None:
    edf = edf_for("oadev", [0, -1, -2], 4, 1001)
    assert edf.shape == (3,)
    assert edf[0] == pytest.approx(edf_for("oadev", 0, [4], 1001)[0])
    assert edf_for("hdev", -4, [2, 8], 1001).shape == (2,)  # Hadamard converges to -4



def test_errors_alpha_and_n_phase() -> None:
    with pytest.raises(DataError, match=r"alpha must be an integer in \[-2, 2\] for "
                                        r"kind='oadev', got -3"):
        edf_for("oadev", -3, 1, 100)
    with pytest.raises(DataError, match=r"alpha must be an integer in \[-4, 2\] for "
                                        r"kind='ohdev', got 3"):
        edf_for("ohdev", 3, 1, 100)
    with pytest.raises(DataError, match="alpha must hold integers, got 0.5"):
        edf_for("oadev", 0.5, 1, 100)
    with pytest.raises(DataError, match="alpha must hold integers, got dtype bool"):
        edf_for("oadev", True, 1, 100)
    with pytest.raises(DataError, match="n_phase must be >= 2, got 1"):
        edf_for("oadev", 0, 1, 1)
    with pytest.raises(DataError, match="n_phase must be an integer, got 10.5"):
        edf_for("oadev", 0, 1, 10.5)
