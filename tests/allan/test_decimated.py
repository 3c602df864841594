"""Tests of fogts.allan.decimated: the lag-1 ACF noise identification from sums.

The reference is the identification on the decimated phase itself
(``noise_identification._acf_alpha``: ``numpy.diff`` of ``x[::m]``, centred, detrended),
which the Stable32 alpha tests of ``test_noise_identification.py`` check.  The sums path
forms the same ``z`` values (the same subtractions) and sums them in another order, so the
estimate ``p`` (of order 1) agrees to rounding: ``1e-12`` absolute is a thousand times the
largest difference seen on these cases (8e-15), and far below the distance of any ``p``
here to a rounding boundary of the type (checked, so no identified alpha can differ).
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from fogts.allan import kernels
from fogts.allan import noise_identification as ni
from fogts.allan.api import allan_deviation
from fogts.allan.decimated import (
    GATHER_FROM_M,
    DecimatedSums,
    SumsCollector,
    acf_alpha_from_sums,
    decimated_sums,
)
from fogts.allan.estimators import ESTIMATORS, estimate_with_sums
from fogts.allan.kernels import phase_from_rate, ss_second
from fogts.allan.taus import KINDS, tau_grid
from tests.allan.references import power_law_noise

P_TOL = 1e-12


def _reference(x: np.ndarray, m: int, d_max: int) -> tuple[float, float]:
    blocks = (x.size - 1) // m
    return ni._acf_alpha(x[: blocks * m + 1 : m], d_max)


def _ms(n: int) -> list[int]:
    """Averaging factors with at least 29 blocks: small, odd, chunk-sized, the last ones."""
    ms = {1, 2, 3, 7, 8, 9, 31, 127, 128, 1000, 4097, n // 100, n // 30, n // 29}
    return sorted(m for m in ms if 1 <= m and n // m >= 29)


@pytest.mark.parametrize("alpha", [2, 1, 0, -1, -2])
@pytest.mark.parametrize("d_max", [1, 2])
def test_sums_give_the_reference_estimate(alpha: int, d_max: int) -> None:
    n = 60_013
    x = phase_from_rate(power_law_noise(alpha, n, 40 + alpha) + 5.0)
    for m in _ms(n):
        p_ref, se_ref = _reference(x, m, d_max)
        p, se = acf_alpha_from_sums(decimated_sums(x, m, d_max), d_max)
        assert abs(p - p_ref) <= P_TOL, (m, p, p_ref)
        assert math.isclose(se, se_ref, rel_tol=1e-15)
        # far from a boundary of the rounded type, so the type itself cannot differ
        assert abs(abs(p_ref - math.floor(p_ref)) - 0.5) > 1e3 * P_TOL


def _assert_same_sums(got: DecimatedSums, ref: DecimatedSums) -> None:
    """Equal up to summation order (1e-12 relative to the sums' own magnitude)."""
    assert (got.m, got.blocks) == (ref.m, ref.blocks)
    scale = abs(ref.xd_sum) + ref.blocks * max(abs(ref.xd_first), abs(ref.xd_last))
    assert abs(got.xd_sum - ref.xd_sum) <= 1e-12 * scale
    for a, b in zip(got.orders, ref.orders, strict=True):
        assert a.count == b.count
        assert math.isclose(a.sumsq, b.sumsq, rel_tol=1e-12)
        assert abs(a.lag1 - b.lag1) <= 1e-12 * b.sumsq
        np.testing.assert_allclose([a.first, a.last], [b.first, b.last], rtol=1e-15)


@pytest.mark.parametrize("chunk", [7, 64, kernels.CHUNK])
def test_the_kernel_collects_the_same_sums(monkeypatch: pytest.MonkeyPatch,
                                           chunk: int) -> None:
    """Per chunk (m below GATHER_FROM_M) and gathered, over chunk boundaries that cut the
    decimated points anywhere; the deviation is untouched by the hook."""
    monkeypatch.setattr(kernels, "CHUNK", chunk)
    monkeypatch.setattr(kernels, "DOT_BLOCK", 5)
    n = 3001
    x = phase_from_rate(power_law_noise(-2, n, 3) + 0.3 * power_law_noise(0, n, 4))
    for m in (1, 2, 3, 5, GATHER_FROM_M - 1, GATHER_FROM_M, 9, 50, 63):
        terms = n + 1 - 2 * m
        if not kernels.hook_sees_chunks(m, terms):
            continue
        collector = SumsCollector(x, m)
        total = ss_second(x, m, terms, collector.add)
        assert math.isclose(total, ss_second(x, m, terms), rel_tol=1e-15)
        _assert_same_sums(collector.result(), decimated_sums(x, m, 1))


@pytest.mark.parametrize("kind", KINDS)
def test_estimate_with_sums_keeps_the_deviations(kind: str) -> None:
    y = power_law_noise(-1, 20_000, 9) + 0.1 * power_law_noise(0, 20_000, 10)
    m = tau_grid("dense", fs_hz=1.0, n_samples=y.size, kind=kind, per_decade=7).m
    got = estimate_with_sums(kind, y, fs_hz=1.0, m=m, d_max=ni.acf_orders(kind), workers=2)
    ref = ESTIMATORS[kind](y, fs_hz=1.0, m=m, workers=1)
    np.testing.assert_allclose(got.output.dev, ref.dev, rtol=1e-15, atol=0)
    np.testing.assert_allclose(got.phase, phase_from_rate(y), rtol=0, atol=0)
    for mi, sums in zip(m.tolist(), got.sums, strict=True):
        assert (sums is None) == (y.size // mi < 3)
        if sums is not None:
            _assert_same_sums(sums, decimated_sums(got.phase, mi, ni.acf_orders(kind)))


@pytest.mark.parametrize("kind", KINDS)
@pytest.mark.parametrize("alpha", [1, 0, -2])
def test_allan_deviation_equals_the_reference_path(monkeypatch: pytest.MonkeyPatch,
                                                   kind: str, alpha: int) -> None:
    """The default CIs (sums from the estimator's pass) against the identification done
    on the decimated phase by the reference ``_acf_alpha``."""
    y = power_law_noise(alpha, 30_000, 21) + 0.05 * power_law_noise(0, 30_000, 22)
    fast = allan_deviation(y, fs_hz=10.0, kind=kind, taus="dense", per_decade=9)
    x = phase_from_rate(y)

    def reference(sums: DecimatedSums, d_max: int) -> tuple[float, float]:
        return _reference(x, sums.m, d_max)

    monkeypatch.setattr(ni, "acf_alpha_from_sums", reference)
    ref = allan_deviation(y, fs_hz=10.0, kind=kind, taus="dense", per_decade=9)
    assert fast.alpha_method == ref.alpha_method
    np.testing.assert_array_equal(fast.alpha, ref.alpha)
    for name in ("dev", "edf", "ci_low", "ci_high"):
        np.testing.assert_allclose(getattr(fast, name), getattr(ref, name), rtol=1e-12)


def test_estimate_with_sums_names_a_bad_kind() -> None:
    with pytest.raises(ValueError, match="kind must be one of .*got 'avar'"):
        estimate_with_sums("avar", np.ones(10), fs_hz=1.0, m=[1], d_max=1)
