"""Redundancy flags: nearly cancelling roots, a common AR/MA factor, insignificant
coefficients."""

from __future__ import annotations

import math

import numpy as np
import pytest

from fogts.arma.diagnostics import (
    NEAR_CANCEL_TOL,
    arma_roots,
    common_factor,
    common_factor_z,
    insignificant_terms,
    near_cancellations,
    resultant,
)


def test_drift_paper_near_cancellation() -> None:
    # the drift paper's model: x_t = -0.2699 x_{t-1} - 0.002968 x_{t-2} + a_t + 0.277 a_{t-1}
    r = arma_roots([-0.2699, -0.002968], [0.277])
    assert np.allclose(r.ar_inverse.real, [-0.0115, -0.2584], atol=5e-5)
    assert np.allclose(r.ma_inverse.real, [-0.277], atol=1e-12)
    flags = near_cancellations(r)
    assert len(flags) == 1 and flags[0].kind == "near_cancellation"
    assert flags[0].details["distance"] == pytest.approx(0.0186, abs=2e-4)
    assert flags[0].details["distance"] < NEAR_CANCEL_TOL
    assert "nearly cancels" in flags[0].message
    assert flags[0].to_dict()["ar_root"]["real"] == pytest.approx(-0.2584, abs=5e-5)
    # a well-separated ARMA(1,1) is not flagged
    assert near_cancellations(arma_roots([0.6], [0.3])) == ()
    assert near_cancellations(arma_roots([0.6], [])) == ()


def test_insignificant_terms() -> None:
    flags = insignificant_terms({"ar.L1": 0.5, "ar.L2": -0.01, "ma.L1": 0.02, "sigma2": 0.001},
                                {"ar.L1": 0.01, "ar.L2": 0.02, "ma.L1": math.nan,
                                 "sigma2": 1.0})
    assert [f.details["param"] for f in flags] == ["ar.L2"]
    assert flags[0].details["t"] == pytest.approx(-0.5)


@pytest.mark.parametrize(("ar", "ma"), [([0.5, 0.2], [0.5]), ([1.2, -0.5], [-0.3]),
                                        ([0.3, -0.2, 0.1], [0.4, 0.2]), ([0.6], [0.4])])
def test_resultant_is_the_product_of_root_differences(ar: list[float], ma: list[float]) -> None:
    # reference: numpy's polynomial roots (complex pairs included); the Sylvester
    # determinant agrees to rounding (relative 1e-10)
    lam = np.roots(np.r_[1.0, -np.asarray(ar)])
    mu = np.roots(np.r_[1.0, np.asarray(ma)])
    ref = np.prod(lam[:, None] - mu[None, :])
    assert abs(ref.imag) < 1e-12
    assert resultant(ar, ma) == pytest.approx(ref.real, rel=1e-10)


def test_resultant_vanishes_on_a_shared_root() -> None:
    # phi(B) = (1 - 0.7 B)(1 - 0.3 B), theta(B) = 1 - 0.3 B
    assert abs(resultant([1.0, -0.21], [-0.3])) < 1e-12
    assert resultant([0.6], []) == 1.0 and resultant([], [0.4]) == 1.0


def test_common_factor_z_matches_the_closed_form_with_statsmodels_covariance() -> None:
    """For ARMA(2,1) the resultant is theta^2 + phi_1 theta - phi_2 with gradient
    (theta, -1, 2 theta + phi_1); statsmodels' own estimates and covariance go in."""
    import warnings

    from statsmodels.tsa.arima.model import ARIMA

    from tests.arma.simulated import arma_series

    x = arma_series([0.5, 0.2], [0.5], 2000, 0)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        res = ARIMA(x, order=(2, 0, 1), trend="n").fit(cov_type="approx")
    f1, f2, t1 = np.asarray(res.params)[:3]
    cov = np.asarray(res.cov_params())[:3, :3]
    g = np.array([t1, -1.0, 2 * t1 + f1])
    ref = (t1 * t1 + f1 * t1 - f2) / math.sqrt(g @ cov @ g)
    assert common_factor_z([f1, f2], [t1], cov) == pytest.approx(ref, rel=1e-6)
    assert abs(ref) > 5.0 and common_factor([f1, f2], [t1], cov) == ()


def test_common_factor_flag_states_its_numbers() -> None:
    cov = np.diag([0.03, 0.03, 0.03]) ** 2
    (flag,) = common_factor([1.0, -0.21], [-0.3], cov)      # AR 0.7, 0.3; MA 0.3: shared
    assert flag.kind == "common_factor" and flag.details["reduced"] == "AR(1)"
    assert abs(flag.details["z"]) < 1e-9 and flag.details["critical"] == pytest.approx(1.96)
    assert flag.details["ma_root"] == pytest.approx(0.3) and flag.details["ar_root"] == \
        pytest.approx(0.3)
    assert "standard errors" in flag.message and "AR(1) with a cancelled factor" in flag.message
    d = flag.to_dict()
    assert d["ar_root"] == {"real": pytest.approx(0.3), "imag": 0.0}
    # ARMA(1,1) reduces to white noise; no covariance: no test; a singular one: flagged
    (wn,) = common_factor([0.5], [-0.45], np.array([[0.01, 0.0], [0.0, 0.01]]))
    assert wn.details["reduced"] == "white noise"
    assert common_factor([0.5], [-0.45], None) == ()
    (nan,) = common_factor([0.5, 0.2], [0.5], np.full((3, 3), np.nan))
    assert math.isnan(nan.details["z"]) and "no standard error" in nan.message
    assert math.isnan(common_factor_z([0.5], [], None))


def test_common_factor_on_the_unit_circle_takes_theta_as_known() -> None:
    """phi(B) = (1 - 0.6 B)(1 + 0.99 B), theta = 1 (MA inverse root -1, on the circle): the
    resultant is 1.6 * 0.01 = 0.016 and, with theta known, its gradient in phi is (theta, -1),
    so se = 0.003 * sqrt(2) and z = 3.77.  theta's own (meaningless) variance of 1 would
    give z = 0.01 and a flag; with nobs the boundary case ignores it."""
    cov = np.diag([0.003 ** 2, 0.003 ** 2, 1.0])
    ar, ma = [0.6 - 0.99, 0.594], [1.0]
    assert resultant(ar, ma) == pytest.approx(0.016, rel=1e-9)
    assert common_factor_z(ar, ma, cov, nobs=2000) == pytest.approx(
        0.016 / (0.003 * math.sqrt(2.0)), rel=1e-6)
    assert common_factor(ar, ma, cov, nobs=2000) == ()
    (flag,) = common_factor(ar, ma, cov)             # without nobs: theta's variance used
    assert abs(flag.details["z"]) < 0.05 and not flag.details["ma_on_unit_circle"]
    # a unit-circle flag says so
    (edge,) = common_factor(ar, ma, np.diag([0.03 ** 2, 0.03 ** 2, 1.0]), nobs=2000)
    assert edge.details["ma_on_unit_circle"] and "on the unit circle taken as known" in \
        edge.message
