"""ArmaFit: its interface, criteria, and innovations recomputed on access bit for bit."""

from __future__ import annotations

import copy
import dataclasses
import json
import pickle

import numpy as np
import pytest

import fogts.arma.fit as fitmod
import fogts.arma.optimiser as optimiser
from fogts.arma.fit import ArmaFit, fit_arma, model_name
from tests.arma.references import (
    CANDIDATES,
    simulate,
    sm_fit,
)
from tests.arma.simulated import arma_series


def test_result_interface() -> None:
    x = simulate([1.2, -0.5], [0.4], 600, 41, 2e-3)
    fit = fit_arma(x, 2, 1)
    assert fit.name == "ARMA(2,1)" and fit.method == "fast" and fit.nobs == 600
    assert list(fit.params) == ["ar.L1", "ar.L2", "ma.L1", "sigma2"]
    assert list(fit.bse) == list(fit.params)
    assert fit.sigma2 == fit.params["sigma2"] and fit.k_params == 4
    assert fit.ar.shape == (2,) and fit.ma.shape == (1,)
    d = fit.to_dict()
    assert json.loads(json.dumps(d)) == d
    assert d["standardized"] is True and d["model"] == "ARMA(2,1)"
    frame = fit.to_frame()
    assert list(frame.index) == list(fit.params) and list(frame.columns) == ["estimate", "bse"]
    text = fit.summary()
    assert "x_t = " in text and "a_{t-1}" in text and "fitted on x /" in text
    # the equation carries statsmodels' sign: + theta_1 a_{t-1}
    sign = "+" if fit.ma[0] > 0 else "-"
    assert f"{sign} {abs(fit.ma[0]):.6g} a_{{t-1}}" in fit.equation()
    with pytest.raises(AttributeError):
        fit.p = 3  # type: ignore[misc]


def test_model_names() -> None:
    assert [model_name(p, q) for p, q in CANDIDATES] == [
        "AR(1)", "AR(2)", "AR(3)", "ARMA(1,1)", "ARMA(2,1)"]
    assert model_name(0, 2) == "MA(2)"


def test_criteria_as_statsmodels_defines_them() -> None:
    x = simulate([0.6], [], 400, 3, 1.0)
    fit = fit_arma(x, 1, 0, standardize=False)
    ref = sm_fit(x, 1, 0)
    assert fit.scale == 1.0 and not fit.standardized
    for attr in ("aic", "bic", "hqic", "aicc"):
        assert getattr(fit, attr) == pytest.approx(getattr(ref, attr), abs=1e-4)


def _stored(fit: ArmaFit) -> bool:
    return fit.__dict__.get("_resid") is not None


@pytest.mark.parametrize("order", [(1, 0), (3, 0), (0, 2), (2, 1)])
@pytest.mark.parametrize("standardize", [True, False])
def test_fit_without_resid_recomputes_exactly(order: tuple[int, int], standardize: bool) -> None:
    """Short series (exact finite-difference polish, n <= 50,000) with and without scaling."""
    x = arma_series([0.5, 0.2], [0.4], 3_000, 5, scale=2e-3)
    fit = fit_arma(x, *order, standardize=standardize)
    lazy = fit._without_resid(x)
    assert not _stored(lazy) and _stored(fit)
    assert np.array_equal(lazy.resid, fit.resid)
    assert repr(lazy) == repr(fit) and lazy.to_dict() == fit.to_dict()


def test_long_record_path_recomputes_exactly(monkeypatch: pytest.MonkeyPatch) -> None:
    """The presample-then-full-series Newton path (thresholds lowered as in tests/arma/test_optimiser.py)."""
    monkeypatch.setattr(optimiser, "PRESAMPLE", 2_000)
    monkeypatch.setattr(fitmod, "_FD_HESSIAN_MAX_N", 5_000)
    x = arma_series([1.2, -0.5], [0.4], 10_000, 98, scale=5.0)
    for p, q in ((2, 1), (1, 1), (2, 0)):
        fit = fit_arma(x, p, q)
        assert np.array_equal(fit._without_resid(x).resid, fit.resid)


def test_lazy_fit_behaves_like_a_stored_one() -> None:
    x = arma_series([0.6], [0.3], 2_000, 3)
    fit = fit_arma(x, 1, 1)
    lazy = fit._without_resid(x)
    assert np.array_equal(pickle.loads(pickle.dumps(lazy)).resid, fit.resid)
    assert np.array_equal(copy.deepcopy(lazy).resid, fit.resid)
    again = dataclasses.replace(lazy, converged=False)     # replace() stores what it read
    assert _stored(again) and np.array_equal(again.resid, fit.resid)
    stored = lazy._with_resid()
    assert _stored(stored) and np.array_equal(stored.resid, fit.resid)
    assert fit._with_resid() is fit
    with pytest.raises(dataclasses.FrozenInstanceError, match="cannot assign to field 'resid'"):
        lazy.resid = fit.resid  # type: ignore[misc]
    assert fit._without_resid(x[:-1]) is fit              # not the fitted series: kept as is
    assert fit._without_resid(x.astype(np.float32)) is fit
    bare = copy.copy(lazy)
    bare.__dict__.pop("_resid_source")
    with pytest.raises(AttributeError, match="neither its innovations nor the series"):
        _ = bare.resid


def test_a_coefficient_near_a_unit_root_is_not_printed_as_one() -> None:
    from fogts.arma.fit_result import coefficient_text

    assert coefficient_text(0.99996, 4) == "0.99996"
    assert coefficient_text(-1.00004, 4) == "-1.00004"
    assert coefficient_text(1.0, 4) == "1"           # exactly one stays "1"
    assert coefficient_text(0.5123456, 4) == "0.5123"  # elsewhere: the digits asked for
    fit = fit_arma(simulate([0.6], [], 400, 3, 1.0), 1, 0)
    near = dataclasses.replace(fit, params={**fit.params, "ar.L1": 0.99996})
    assert near.equation(4).startswith("x_t = 0.99996 x_{t-1} + a_t")
