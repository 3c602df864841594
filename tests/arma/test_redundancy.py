"""Redundancy flags: nearly cancelling roots and insignificant coefficients."""

from __future__ import annotations

import math

import numpy as np
import pytest

from fogts.arma.diagnostics import (
    NEAR_CANCEL_TOL,
    arma_roots,
    insignificant_terms,
    near_cancellations,
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
