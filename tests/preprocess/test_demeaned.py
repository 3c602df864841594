"""A long input minus its mean held unformed (fogts.preprocess.demeaned) and the ARMA
selection that reads it without forming it.

References: the formed array is ``raw - mean`` itself (numpy's subtraction, compared bit
for bit); the selection of the unformed series is compared with the selection of the
formed array (the path every series took before), which differs only by where the mean is
subtracted (input / scale - mean(input / scale) instead of (input - mean) / scale - ...):
rounding of the series at 1e-16 of the input's magnitude, so 1e-9 relative on AIC and
coefficients, far inside a standard error.
"""

from __future__ import annotations

import pickle
import warnings

import numpy as np
import pytest

import fogts.arma.fit as fitmod
import fogts.arma.fit_result as fit_result
import fogts.preprocess.demeaned as demeaned_mod
from fogts.arma import select_arma
from fogts.arma.whiteness import _rho_ax3_offset, rho_ax3
from fogts.preprocess.demeaned import Demeaned, held
from fogts.preprocess.prepare import prepare
from tests.arma.simulated import arma_series


def test_demeaned_forms_raw_minus_mean_once() -> None:
    raw = np.random.default_rng(1).normal(3.0, 1.0, 1000)
    d = Demeaned(raw, float(raw.mean()))
    assert d.size == 1000 and "n=1000" in repr(d)
    a = d.array()
    assert np.array_equal(a, raw - raw.mean())     # numpy's own subtraction, same values
    assert d.array() is a                          # formed once, shared
    back = pickle.loads(pickle.dumps(d))
    assert back.mean == d.mean and np.array_equal(back.array(), a)


def _long(monkeypatch: pytest.MonkeyPatch, limit: int) -> None:
    """Treat series above ``limit`` samples as long (held unformed, fitted block-wise)."""
    monkeypatch.setattr(demeaned_mod, "UNFORMED_MIN_N", limit)
    monkeypatch.setattr(fitmod, "BLOCKWISE_MIN_N", limit)
    monkeypatch.setattr(fit_result, "BLOCKWISE_MIN_N", limit)


def test_prepare_holds_a_long_input_minus_its_mean(monkeypatch: pytest.MonkeyPatch) -> None:
    x = arma_series([0.6], [0.3], 30000, seed=4) + 7.5
    formed = prepare(x, fs_hz=10.0)           # 30000 samples: below the default limit
    assert isinstance(formed.lazy_x, np.ndarray)
    _long(monkeypatch, 1000)
    p = prepare(x, fs_hz=10.0)
    held_x = p.lazy_x
    assert isinstance(held_x, Demeaned) and held_x.raw is x
    assert p.n == 30000 and p.to_dict()["n"] == 30000
    assert isinstance(p.lazy_x, Demeaned)     # n and to_dict did not form it
    # ADF/KPSS on block means of the input minus the mean: those of the demeaned blocks
    # to rounding
    assert p.stationarity is not None and formed.stationarity is not None
    assert p.stationarity.adf_stat == pytest.approx(formed.stationarity.adf_stat, rel=1e-9)
    assert p.stationarity.kpss_stat == pytest.approx(formed.stationarity.kpss_stat, rel=1e-9)
    assert p.stationarity.adf_lags == formed.stationarity.adf_lags
    assert p.steps[0] == formed.steps[0]
    # exact: formed on access by the very subtraction it replaced (the contract)
    assert np.array_equal(p.x, x - x.mean())
    assert isinstance(p.lazy_x, np.ndarray)
    # a series the preparation copied already (outliers replaced) is demeaned as before
    assert isinstance(prepare(x, fs_hz=10.0, outliers=50.0).lazy_x, np.ndarray)


def test_rho_ax3_of_an_offset_series() -> None:
    r = np.random.default_rng(5)
    a = r.standard_normal(200_003)
    x = r.standard_normal(200_003) + 40.0
    assert _rho_ax3_offset(a, x, 40.0) == pytest.approx(rho_ax3(a, x - 40.0), rel=1e-12)


def test_selection_of_an_unformed_series(monkeypatch: pytest.MonkeyPatch) -> None:
    x = arma_series([0.6], [0.3], 30000, seed=9) + 7.5
    _long(monkeypatch, 1000)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        p = prepare(x, fs_hz=10.0)
        sel = select_arma(p, candidates="AR(1),ARMA(1,1)")
        monkeypatch.setattr(demeaned_mod, "UNFORMED_MIN_N", 10**9)
        ref = select_arma(prepare(x, fs_hz=10.0), candidates="AR(1),ARMA(1,1)")
    assert isinstance(p.lazy_x, Demeaned)     # the selection did not form it ...
    for c in sel.candidates:
        assert isinstance(held(c, "data"), Demeaned)
    assert sel.best.model == ref.best.model == "ARMA(1,1)"
    for c, r in zip(sel.candidates, ref.candidates, strict=True):
        assert c.model == r.model and c.white == r.white
        assert c.aic == pytest.approx(r.aic, rel=1e-9)
        assert c.params == pytest.approx(r.params, rel=1e-8, abs=1e-10)
        assert c.bse == pytest.approx(r.bse, rel=1e-6)
        assert c.diagnostics is not None and r.diagnostics is not None
        assert c.diagnostics.rho_ax3.value == pytest.approx(r.diagnostics.rho_ax3.value,
                                                            rel=1e-7)
    summary = sel.best.prediction_summary()
    assert summary["variance_observed"] == pytest.approx(
        ref.best.prediction_summary()["variance_observed"], rel=1e-12)
    assert isinstance(held(sel.best, "data"), Demeaned)
    # ... until something reads the data: the same array as the formed path's
    pred = sel.best.predict()
    assert np.array_equal(pred.observed, x - x.mean())    # exact: the same subtraction
    np.testing.assert_allclose(pred.predicted, ref.best.predict().predicted, rtol=0,
                               atol=1e-9 * float(np.std(x)))


def test_selection_of_a_long_array(monkeypatch: pytest.MonkeyPatch) -> None:
    """An ndarray input of a long series: neither its demeaned copy nor its time axis is
    formed; the fits equal those of the formed copy to rounding (see the module docstring)."""
    from fogts.io.run import RegularTime

    x = arma_series([0.6], [0.3], 30000, seed=10) - 3.0
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        ref = select_arma(x, candidates="AR(1),ARMA(1,1)", fs_hz=10.0)
        _long(monkeypatch, 1000)
        sel = select_arma(x, candidates="AR(1),ARMA(1,1)", fs_hz=10.0)
    held_data = held(sel.best, "data")
    assert isinstance(held_data, Demeaned) and held_data.raw is x
    assert isinstance(sel.best.time, RegularTime)
    assert sel.preprocessing == ref.preprocessing
    for c, r in zip(sel.candidates, ref.candidates, strict=True):
        assert c.model == r.model and c.white == r.white
        assert c.aic == pytest.approx(r.aic, rel=1e-9)
        assert c.params == pytest.approx(r.params, rel=1e-8, abs=1e-10)
    pred = sel.best.predict()
    # exact: the time axis is formed by the very division it replaced (the contract)
    np.testing.assert_array_equal(pred.time, np.arange(x.size) / 10.0)
    np.testing.assert_allclose(pred.predicted, ref.best.predict().predicted, rtol=0,
                               atol=1e-9 * float(np.std(x)))


def test_the_unformed_limit_is_the_blockwise_one() -> None:
    """A series is held unformed exactly when the ARMA fits read it block by block (both
    paths accept any length; the shared limit keeps the short-series outputs unchanged)."""
    from fogts.arma.blockwise import BLOCKWISE_MIN_N

    assert demeaned_mod.UNFORMED_MIN_N == BLOCKWISE_MIN_N
    n = demeaned_mod.UNFORMED_MIN_N
    assert not demeaned_mod.holds_unformed(np.zeros(n))
    assert demeaned_mod.holds_unformed(np.zeros(n + 1))
    assert not demeaned_mod.holds_unformed(np.zeros(n + 1, dtype=np.float32))
    assert not demeaned_mod.holds_unformed(np.zeros(2 * n + 2)[::2])
