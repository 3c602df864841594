"""Candidate: the fit's numbers as properties, the equation's signs, a failed candidate."""

from __future__ import annotations

import math

import numpy as np
import pytest

from fogts.arma import select_arma
from tests.arma.simulated import arma_series


@pytest.mark.parametrize(("theta", "sign"), [(0.6, "+"), (-0.6, "-")])
def test_equation_shows_ma_sign(theta: float, sign: str) -> None:
    sel = select_arma(arma_series([0.3], [theta], 5000, 3), candidates="ARMA(1,1)")
    assert sel.best is not None
    ma = sel.best.params["ma.L1"]
    assert np.sign(ma) == np.sign(theta)
    assert f"+ a_t {sign} {abs(ma):.4g} a_{{t-1}}" in sel.best.equation()


def test_the_fits_numbers_are_properties_of_the_candidate() -> None:
    x = arma_series([0.6], [0.3], 3000, 12)
    sel = select_arma(x, candidates="AR(1),ARMA(1,1)")
    for c in sel.candidates:
        fit = c.fit
        assert fit is not None and c.ok and c.converged == fit.converged
        assert c.params is fit.params and c.bse is fit.bse
        names = ("llf", "aic", "bic", "hqic", "aicc", "sigma2")
        assert all(getattr(c, k) is getattr(fit, k) for k in names)     # the fit's own numbers
        np.testing.assert_array_equal(c.ar, fit.ar)
        np.testing.assert_array_equal(c.ma, fit.ma)
        d = c.to_dict()
        assert d["params"] == fit.params and all(d[k] is getattr(fit, k) for k in names)
        assert [lb["lag"] for lb in d["ljung_box"]] == [10, 20]
        assert "sigma2" in c.summary() and c.fit.name == c.model


def test_a_failed_candidate_has_no_numbers() -> None:
    x = arma_series([1.1], [], 300, 0, burn=0)
    c = select_arma(x, candidates="AR(1)").candidates[0]
    assert c.status == "failed" and c.fit is None and not c.converged
    assert c.params == {} and c.bse == {}
    assert all(math.isnan(v) for v in (c.llf, c.aic, c.bic, c.hqic, c.aicc, c.sigma2))
    assert c.ar.size == 0 and c.ma.size == 0 and c.resid is None
    assert c.to_frame().empty and c.summary().startswith("AR(1): FAILED")
