"""The stationarity/invertibility region against statsmodels' ``ArmaProcess`` (an
independent root computation with the same sign convention)."""

from __future__ import annotations

import numpy as np
import pytest
from statsmodels.tsa.arima_process import ArmaProcess

from fogts.arma.region import admissible, shrink_into_region, spectral_radius, unit_root_gap


def _draws(seed: int, k: int, count: int) -> np.ndarray:
    return np.random.default_rng(seed).uniform(-2.0, 2.0, size=(count, k))


@pytest.mark.parametrize("k", [1, 2, 3])
def test_admissible_agrees_with_statsmodels(k: int) -> None:
    """500 random AR and MA polynomials per order: fogts' region is statsmodels'
    (``isstationary`` and ``isinvertible``), except within 1e-6 of the boundary, where a
    root's last bits decide and the draws are skipped."""
    agree = 0
    for c in _draws(3100 + k, k, 500):
        rho = spectral_radius(c)
        if abs(rho - 1.0) < 1e-6:
            continue
        proc = ArmaProcess(ar=np.r_[1.0, -c], ma=np.r_[1.0, -c])  # theta = -c: same roots
        assert admissible(c, np.zeros(0)) == proc.isstationary
        assert admissible(np.zeros(0), -c) == proc.isinvertible
        agree += 1
    assert agree > 450


def test_spectral_radius_is_the_largest_inverse_root() -> None:
    """phi(B) = (1 - 0.5B)(1 + 0.9B): inverse roots 0.5 and -0.9."""
    phi = np.array([0.5 - 0.9, 0.45])
    assert spectral_radius(phi) == pytest.approx(0.9, rel=1e-12)
    assert spectral_radius(np.zeros(2)) == 0.0
    assert spectral_radius(np.zeros(0)) == 0.0


def test_shrink_brings_every_draw_inside() -> None:
    """Whatever the coefficients, the shrunk model is admissible with the start values'
    2 % margin, and an admissible model inside 0.98 is left alone."""
    for c in _draws(3200, 3, 300):
        phi, theta = shrink_into_region(c, c[:2])
        assert admissible(phi, theta, margin=0.02 - 1e-9)
    phi, theta = shrink_into_region(np.array([0.5]), np.array([0.3]))
    assert phi[0] == 0.5 and theta[0] == 0.3


def test_unit_root_gap() -> None:
    """(1 - 0.9999B)(1 - 0.3B): gap 1e-4; a complex or negative inverse root has none."""
    phi = np.array([0.9999 + 0.3, -0.9999 * 0.3])
    assert unit_root_gap(phi) == pytest.approx(1e-4, rel=1e-6)
    assert unit_root_gap(np.array([-0.5])) == float("inf")
    assert unit_root_gap(np.array([0.0, -0.81])) == float("inf")   # roots +-0.9i
    assert unit_root_gap(np.zeros(0)) == float("inf")
