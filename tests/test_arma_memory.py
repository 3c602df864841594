"""Memory of ARMA selection on long records, and the innovations it recomputes on demand.

``select_arma`` stores the series-length innovations of the selected candidate only; every
other candidate's ``ArmaFit.resid`` is recomputed on access from its parameters and the
fitted series by the fit's own exact-innovations code.  These tests pin that the recomputed
arrays are the fit's innovations bit for bit (against a fresh ``fit_arma`` of the same series,
and through every public way of reaching them), and that a Selection retains about three
series-length arrays (the demeaned data, the time axis, the selected innovations), measured
with tracemalloc (numpy allocations included).
"""

from __future__ import annotations

import copy
import dataclasses
import gc
import pickle
import tracemalloc
import warnings

import numpy as np
import pytest
from scipy.signal import lfilter

import fogts.arma.fit as fitmod
import fogts.arma.optimiser as optimiser
from fogts.arma import select_arma
from fogts.arma.fit import fit_arma
from fogts.errors import NotWhiteWarning


def _arma(ar: list[float], ma: list[float], n: int, seed: int, scale: float = 1.0) -> np.ndarray:
    e = np.random.default_rng(seed).standard_normal(n + 2000) * scale
    return np.asarray(lfilter(np.r_[1.0, ma], np.r_[1.0, -np.asarray(ar)], e)[2000:])


def _stored(fit: fitmod.ArmaFit) -> bool:
    return fit.__dict__.get("_resid") is not None


@pytest.fixture(scope="module")
def arma_selection() -> tuple[np.ndarray, object]:
    x = _arma([0.6, -0.2], [0.3], 20_000, 11, scale=1e-3)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", NotWhiteWarning)
        sel = select_arma(x, candidates="AR(1),AR(2),AR(3),ARMA(1,1),ARMA(2,1),MA(2)",
                          fs_hz=10.0)
    return x, sel


def test_only_the_selected_candidate_stores_its_innovations(arma_selection: tuple) -> None:
    _, sel = arma_selection
    ok = [c for c in sel.candidates if c.ok]
    assert len(ok) == 6
    assert _stored(sel.best.fit)
    assert not any(_stored(c.fit) for c in ok if c is not sel.best)


def test_recomputed_innovations_equal_a_fresh_fit_bit_for_bit(arma_selection: tuple) -> None:
    """Every candidate's resid (stored or recomputed) equals fit_arma's on the same series:
    tolerance zero (np.array_equal on float64)."""
    x, sel = arma_selection
    xd = x - x.mean()
    for c in sel.candidates:
        ref = fit_arma(xd, c.p, c.q)
        assert c.params == ref.params and c.llf == ref.llf and c.aic == ref.aic
        for a in (c.resid, c.fit.resid):
            assert a.dtype == np.float64 and a.shape == ref.resid.shape
            assert np.array_equal(a, ref.resid), c.model
        pred = c.predict()
        assert np.array_equal(pred.residual, ref.resid)
        assert np.array_equal(pred.predicted, xd - ref.resid)


@pytest.mark.parametrize("order", [(1, 0), (3, 0), (0, 2), (2, 1)])
@pytest.mark.parametrize("standardize", [True, False])
def test_fit_without_resid_recomputes_exactly(order: tuple[int, int], standardize: bool) -> None:
    """Short series (exact finite-difference polish, n <= 50,000) with and without scaling."""
    x = _arma([0.5, 0.2], [0.4], 3_000, 5, scale=2e-3)
    fit = fit_arma(x, *order, standardize=standardize)
    lazy = fit._without_resid(x)
    assert not _stored(lazy) and _stored(fit)
    assert np.array_equal(lazy.resid, fit.resid)
    assert repr(lazy) == repr(fit) and lazy.to_dict() == fit.to_dict()


def test_long_record_path_recomputes_exactly(monkeypatch: pytest.MonkeyPatch) -> None:
    """The presample-then-full-series Newton path (thresholds lowered as in test_arma_fit)."""
    monkeypatch.setattr(optimiser, "_PRESAMPLE", 2_000)
    monkeypatch.setattr(fitmod, "_FD_HESSIAN_MAX_N", 5_000)
    x = _arma([1.2, -0.5], [0.4], 10_000, 98, scale=5.0)
    for p, q in ((2, 1), (1, 1), (2, 0)):
        fit = fit_arma(x, p, q)
        assert np.array_equal(fit._without_resid(x).resid, fit.resid)


def test_lazy_fit_behaves_like_a_stored_one() -> None:
    x = _arma([0.6], [0.3], 2_000, 3)
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


def test_statsmodels_fits_keep_their_innovations() -> None:
    """statsmodels' Kalman innovations cannot be recomputed bit for bit: they stay stored."""
    x = _arma([0.6], [], 600, 4)
    sel = select_arma(x, candidates="AR(1),AR(2)", method="statsmodels")
    assert all(_stored(c.fit) for c in sel.candidates)


def _traced(fn: object, *args: object, **kwargs: object) -> tuple[object, int, int]:
    gc.collect()
    tracemalloc.start()
    try:
        out = fn(*args, **kwargs)  # type: ignore[operator]
        current, peak = tracemalloc.get_traced_memory()
    finally:
        tracemalloc.stop()
    return out, current, peak


def test_selection_memory_on_a_long_record() -> None:
    """n = 2e5 (1.6 MB): the Selection retains the demeaned data, the time axis and the
    selected innovations (3.0x the input measured; before the change 7.0x, one innovations
    array per candidate), and the call peaks at 7.1x (before: 11.1x)."""
    x = _arma([0.6, -0.2], [0.3], 200_000, 1, scale=1e-3)
    select_arma(x[:5_000], fs_hz=10.0)           # lazy imports outside the measurement
    sel, retained, peak = _traced(select_arma, x, fs_hz=10.0)
    assert sel.best is not None                  # type: ignore[attr-defined]
    assert retained < 3.3 * x.nbytes, retained / x.nbytes
    assert peak < 7.5 * x.nbytes, peak / x.nbytes
    # without a time axis one array less
    _, retained, _ = _traced(select_arma, x)
    assert retained < 2.3 * x.nbytes, retained / x.nbytes
