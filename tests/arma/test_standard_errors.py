"""Standard errors from the observed information, against statsmodels' cov_type="approx",
and how they scale with the data."""

from __future__ import annotations

import math

import numpy as np
import pytest

import fogts.arma.fit as fitmod
from fogts.arma.fit import fit_arma
from tests.arma.references import (
    simulate,
    sm_fit,
)


@pytest.mark.parametrize("order", [(2, 0), (2, 1)])
def test_bse_match_statsmodels_observed_information(order: tuple[int, int],
                                                    monkeypatch: pytest.MonkeyPatch) -> None:
    p, q = order
    n = 3000
    x = simulate([1.2, -0.5], [0.4], n, 21, 1.0)
    xs = x / np.std(x)
    ref = sm_fit(xs, p, q, cov_type="approx")
    ref_bse = np.r_[ref.bse[:-1], ref.bse[-1] * np.std(x) ** 2]
    fit = fit_arma(x, p, q)
    np.testing.assert_allclose(list(fit.bse.values()), ref_bse, rtol=1e-3)
    # the analytic Hessian of the long-record path: relative error about 20/n
    monkeypatch.setattr(fitmod, "_FD_HESSIAN_MAX_N", 0)
    fit2 = fit_arma(x, p, q)
    np.testing.assert_allclose(list(fit2.bse.values()), ref_bse, rtol=20 / n)


def test_units_and_scaling() -> None:
    """AR/MA and their bse are scale-free; sigma2 scales by c^2; llf shifts by -n log c."""
    x = simulate([1.2, -0.5], [0.4], 1200, 31, 1.0)
    a = fit_arma(x, 2, 1)
    b = fit_arma(1e3 * x, 2, 1)
    np.testing.assert_allclose(np.r_[a.ar, a.ma], np.r_[b.ar, b.ma], atol=1e-10)
    assert b.sigma2 == pytest.approx(1e6 * a.sigma2, rel=1e-9)
    assert b.bse["sigma2"] == pytest.approx(1e6 * a.bse["sigma2"], rel=1e-4)
    for k in ("ar.L1", "ar.L2", "ma.L1"):
        assert b.bse[k] == pytest.approx(a.bse[k], rel=1e-4)
    assert b.llf == pytest.approx(a.llf - 1200 * math.log(1e3), abs=1e-6)
    assert b.aic == pytest.approx(-2 * b.llf + 2 * 4)
    assert b.bic == pytest.approx(-2 * b.llf + 4 * math.log(1200))
    assert b.hqic == pytest.approx(-2 * b.llf + 2 * 4 * math.log(math.log(1200)))
    assert b.aicc == pytest.approx(b.aic + 2 * 4 * 5 / (1200 - 5))
