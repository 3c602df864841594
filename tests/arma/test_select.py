"""ARMA candidate selection: selection rate on simulated data with known order, the drift
paper's ARMA(2,1), the ranking rule, the JSON contract, bad input, and the memory a selection
keeps (only the selected candidate stores its innovations; the others recompute them bit for
bit; retained memory measured with tracemalloc, numpy allocations included).

Truth comes from simulation with fixed seeds (scipy.signal.lfilter with a 2000-sample burn-in).
"""

from __future__ import annotations

import dataclasses
import gc
import json
import tracemalloc
import warnings

import numpy as np
import pandas as pd
import pytest
from scipy.signal import lfilter

import fogts.arma.select as select_mod
from fogts.arma import select_arma
from fogts.arma.fit import ArmaFit, fit_arma
from fogts.errors import (
    ConvergenceWarning,
    DataError,
    InsufficientDataError,
    ModelFitError,
    NotWhiteWarning,
)
from fogts.io.run import Run
from fogts.preprocess.prepare import prepare
from fogts.report.text import json_dumps
from tests.arma.simulated import arma_series

#: The drift paper's five candidates with clearly identified coefficients.
TRUE_MODELS = {
    "AR(1)": ([0.6], []),
    "AR(2)": ([0.5, 0.3], []),
    "AR(3)": ([0.5, -0.3, 0.2], []),
    "ARMA(1,1)": ([0.6], [0.4]),
    "ARMA(2,1)": ([0.5, 0.2], [0.5]),
}


#: Seeds per model in the test (benchmarks/bench_selection_rate.py runs 50).
RATE_SEEDS = 12


CONTRACT_KEYS = {"model", "p", "q", "status", "rank", "aic", "bic", "llf", "sigma2", "params",
                 "bse", "rho_a2", "rho_ax3", "ljung_box", "white", "roots", "warnings"}


@pytest.fixture(scope="module")
def ar1_selection() -> select_mod.Selection:
    return select_arma(arma_series([0.6], [], 3000, 1, scale=2e-3), fs_hz=10.0)


def test_selection_rate_true_order_ranks_first() -> None:
    rates = {}
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", NotWhiteWarning)
        for name, (ar, ma) in TRUE_MODELS.items():
            hits = sum(select_arma(arma_series(ar, ma, 10_000, seed)).best.model == name  # type: ignore[union-attr]
                       for seed in range(RATE_SEEDS))
            rates[name] = hits / RATE_SEEDS
    table = ", ".join(f"{k}: {v:.0%}" for k, v in rates.items())
    print(f"\nselection rate by AIC, n = 10^4, {RATE_SEEDS} seeds each: {table}")
    assert all(r > 0.5 for r in rates.values()), table           # a majority for each model
    assert sum(rates.values()) / len(rates) >= 0.7, table        # and clearly overall


def test_drift_paper_arma21_near_cancellation_prefers_low_order() -> None:
    # the drift paper's fitted drift: x_t = -0.2699 x_{t-1} - 0.002968 x_{t-2} + a_t + 0.277 a_{t-1},
    # 10 Hz x 3 h = 108,000 samples
    chosen = []
    for seed in range(3):
        sel = select_arma(arma_series([-0.2699, -0.002968], [0.277], 108_000, seed, scale=1e-3))
        arma21 = sel["ARMA(2,1)"]
        assert arma21.ok and arma21.flagged("near_cancellation"), arma21.flags
        assert sel.best is not None and sel.best.model != "ARMA(2,1)"
        chosen.append(sel.best.p + sel.best.q)
    assert sorted(chosen)[1] == 1, chosen      # a one-parameter model in most runs


def test_ranking_white_first_then_by_criterion() -> None:
    x = arma_series([0.5], [0.3], 20_000, 0, scale=3e-3)
    for criterion in ("aic", "bic", "hqic", "aicc"):
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", NotWhiteWarning)
            sel = select_arma(x, criterion=criterion)  # type: ignore[arg-type]
        ranked = [c for c in sel.candidates if c.ok]
        assert [c.rank for c in ranked] == list(range(1, len(ranked) + 1))
        keys = [(not c.white, getattr(c, criterion)) for c in ranked]
        assert keys == sorted(keys)
        assert sel.best is ranked[0]
        assert sel.all_white_failed == (not any(c.white for c in ranked))


def test_selected_model_parameters_and_units(ar1_selection: select_mod.Selection) -> None:
    best = ar1_selection.best
    assert best is not None and best.model == "AR(1)" and best.white
    assert best.params["ar.L1"] == pytest.approx(0.6, abs=0.05)
    assert best.sigma2 == pytest.approx(4e-6, rel=0.1)          # original units, not scaled
    assert best.fit is not None and best.fit.standardized
    assert ar1_selection.exit_code == 0 and not ar1_selection.all_white_failed
    # the mean is estimated in the (restricted) likelihood: the equation is in y_t = x_t - mean
    assert best.equation().startswith("y_t = 0.") and "y_t = x_t " in best.equation()
    frame = best.to_frame()
    assert list(frame.index) == ["mean", "ar.L1", "sigma2"] and list(frame.columns) == ["estimate",
                                                                               "bse", "t"]
    assert "AR(1)" in best.summary() and "AR(1)" in ar1_selection.summary()
    assert ar1_selection["ar(1)"] is best
    with pytest.raises(KeyError, match="no candidate 'MA.9.'"):
        ar1_selection["MA(9)"]


def test_json_contract_and_determinism(ar1_selection: select_mod.Selection) -> None:
    d = json.loads(json_dumps(ar1_selection.to_dict()))
    assert {"input", "preprocessing", "candidates", "selected"} <= set(d)
    assert len(d["candidates"]) == 5
    for c in d["candidates"]:
        assert CONTRACT_KEYS <= set(c), CONTRACT_KEYS - set(c)
        assert set(c["params"]) == set(c["bse"])
        assert all(set(lb) >= {"lag", "q", "pvalue"} for lb in c["ljung_box"])
        assert [lb["lag"] for lb in c["ljung_box"]] == [10, 20]
    assert d["candidates"][0]["rank"] == 1
    assert d["selected"]["model"] == d["candidates"][0]["model"] == "AR(1)"
    assert d["input"]["fs_hz"] == 10.0
    assert d["preprocessing"]["steps"][0].startswith("removed the mean")
    again = select_arma(arma_series([0.6], [], 3000, 1, scale=2e-3), fs_hz=10.0)
    assert json_dumps(again.to_dict()) == json_dumps(ar1_selection.to_dict())


def test_frame_has_one_row_per_candidate(ar1_selection: select_mod.Selection) -> None:
    f = ar1_selection.to_frame()
    assert list(f.index) == [c.model for c in ar1_selection.candidates]
    assert {"rank", "aic", "rho_a2", "rho_ax3", "lb_p_10", "lb_p_20", "white"} <= set(f.columns)


def test_prepared_input() -> None:

    x = arma_series([0.6], [], 4000, 2) + 1e-3 * np.arange(4000)
    prep = prepare(x, fs_hz=10.0, detrend=1, stationarity=False)
    sel = select_arma(prep)
    assert sel.preprocessing == prep.to_dict()
    assert sel.input["fs_hz"] == 10.0 and sel.fs_hz == 10.0
    assert sel.best is not None
    pred = sel.best.predict()
    assert np.array_equal(pred.time, prep.time)


def test_series_input_keeps_index() -> None:
    idx = pd.date_range("2024-01-01", periods=3000, freq="100ms")
    s = pd.Series(arma_series([0.6], [], 3000, 4), index=idx, name="fog")
    sel = select_arma(s, candidates=["AR(1)", (1, 1)])
    assert sel.input["axis"] == "fog"
    assert sel.best is not None
    frame = sel.best.predict().to_frame()
    assert frame.index.equals(idx)


def test_none_white_warns_and_reports_best() -> None:
    x = arma_series([0.5, -0.3, 0.3], [], 5000, 5)
    with pytest.warns(NotWhiteWarning, match="no candidate leaves white residuals"):
        sel = select_arma(x, candidates="AR(1)")
    assert sel.all_white_failed and sel.exit_code == 1
    assert sel.best is not None and sel.best.model == "AR(1)" and sel.best.rank == 1
    assert sel.verdict.startswith("No candidate leaves white residuals")


def test_explosive_series_gives_failed_rows_not_a_crash() -> None:
    x = arma_series([1.1], [], 300, 0, burn=0)
    sel = select_arma(x)
    assert all(c.status == "failed" and c.rank is None for c in sel.candidates)
    assert all("explosive" in (c.reason or "") for c in sel.candidates)
    assert sel.best is None and sel.all_white_failed and sel.exit_code == 1
    assert sel.verdict.startswith("No candidate could be fitted")
    d = json.loads(json_dumps(sel.to_dict()))
    assert d["selected"] is None and d["candidates"][0]["status"] == "failed"
    with pytest.raises(ModelFitError, match="explosive"):
        sel.require_best()
    with pytest.raises(ModelFitError, match="was not fitted"):
        sel.candidates[0].predict()


def test_a_failed_fit_stays_in_the_table(monkeypatch: pytest.MonkeyPatch) -> None:
    real = fit_arma

    def flaky(x: np.ndarray, p: int, q: int, **kw: object) -> object:
        if (p, q) == (2, 1):
            raise ModelFitError("ARMA(2,1): the likelihood could not be maximised")
        return real(x, p, q, **kw)  # type: ignore[arg-type]

    monkeypatch.setattr(select_mod, "fit_arma", flaky)
    sel = select_arma(arma_series([0.6], [], 2000, 6))
    failed = sel["ARMA(2,1)"]
    assert failed.status == "failed" and failed.rank is None
    assert failed.reason == "ARMA(2,1): the likelihood could not be maximised"
    assert sel.candidates[-1] is failed and len(sel.candidates) == 5
    assert sel.to_frame().loc["ARMA(2,1)", "reason"] == failed.reason


def test_non_converged_fit_is_a_warning_on_the_candidate(monkeypatch: pytest.MonkeyPatch) -> None:
    real = fit_arma

    def stalled(x: np.ndarray, p: int, q: int, **kw: object) -> object:
        return dataclasses.replace(real(x, p, q, **kw), converged=False)  # type: ignore[arg-type]

    monkeypatch.setattr(select_mod, "fit_arma", stalled)
    with pytest.warns(ConvergenceWarning, match="AR.1.: the optimiser did not converge"):
        sel = select_arma(arma_series([0.6], [], 2000, 7), candidates="AR(1)")
    c = sel["AR(1)"]
    assert c.ok and not c.converged and any("did not converge" in w for w in c.warnings)


def test_statsmodels_path_gives_the_same_ranking() -> None:
    x = arma_series([0.6], [0.3], 1500, 8)
    fast = select_arma(x, candidates="AR(1),AR(2),ARMA(1,1)")
    slow = select_arma(x, candidates="AR(1),AR(2),ARMA(1,1)", method="statsmodels")
    assert [c.model for c in fast.candidates] == [c.model for c in slow.candidates]
    for a, b in zip(fast.candidates, slow.candidates, strict=True):
        assert a.aic <= b.aic + 0.05


def test_bad_input() -> None:

    x = arma_series([0.5], [], 500, 9)
    with pytest.raises(InsufficientDataError,
                       match="too short for ARMA selection: 30 samples, need at least 50"):
        select_arma(x[:30])
    with pytest.raises(InsufficientDataError, match="need at least 60"):
        select_arma(x[:55], lags=(30,))
    with pytest.raises(InsufficientDataError, match="x is constant"):
        select_arma(np.full(500, 3.0))
    with pytest.raises(DataError, match="non-finite value"):
        select_arma(np.r_[x[:100], np.nan, x[100:]])
    with pytest.raises(DataError, match="criterion must be one of aic, bic, hqic, aicc; got 'foo'"):
        select_arma(x, criterion="foo")  # type: ignore[arg-type]
    with pytest.raises(DataError, match="method must be one of fast, statsmodels"):
        select_arma(x, method="exact")  # type: ignore[arg-type]
    with pytest.raises(DataError, match="lags must be >= 1, got 0"):
        select_arma(x, lags=(0, 10))
    with pytest.raises(DataError, match="lags must be a non-empty sequence"):
        select_arma(x, lags=())
    with pytest.raises(DataError, match="got a DataFrame"):
        select_arma(pd.DataFrame({"a": x}))
    with pytest.raises(DataError, match="fs_hz must be a finite number > 0"):
        select_arma(x, fs_hz=-1.0)
    run3 = Run(rate=np.column_stack([x, x, x]), time=np.arange(500) / 10.0, fs_hz=10.0,
               units="deg/h", axes=("x", "y", "z"), columns=("time", "x", "y", "z"))
    with pytest.raises(DataError, match=r"x is a Run with 3 axes \(x, y, z\); select one"):
        select_arma(run3)


def test_a_one_axis_run_is_prepared_with_the_defaults() -> None:
    x = lfilter([1.0], [1.0, -0.6], np.random.default_rng(3).standard_normal(800))
    run = Run(rate=x, time=np.arange(800) / 10.0, fs_hz=10.0, units="deg/h", axes=("x",),
              columns=("time", "x"))
    direct, via = select_arma(run), select_arma(prepare(run))
    assert via.best.model == direct.best.model
    assert direct.best.aic == pytest.approx(via.best.aic, rel=1e-12)  # the same input
    assert direct.to_dict()["preprocessing"] == via.to_dict()["preprocessing"]


def _stored(fit: ArmaFit) -> bool:
    return fit.__dict__.get("_resid") is not None


@pytest.fixture(scope="module")
def arma_selection() -> tuple[np.ndarray, object]:
    x = arma_series([0.6, -0.2], [0.3], 20_000, 11, scale=1e-3)
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
        ref = fit_arma(xd, c.p, c.q, mean=True)
        assert c.params == ref.params and c.llf == ref.llf and c.aic == ref.aic
        for a in (c.resid, c.fit.resid):
            assert a.dtype == np.float64 and a.shape == ref.resid.shape
            assert np.array_equal(a, ref.resid), c.model
        pred = c.predict()
        assert np.array_equal(pred.residual, ref.resid)
        assert np.array_equal(pred.predicted, xd - ref.resid)


def test_statsmodels_fits_keep_their_innovations() -> None:
    """statsmodels' Kalman innovations cannot be recomputed bit for bit: they stay stored."""
    x = arma_series([0.6], [], 600, 4)
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
    selected innovations (bound: 3.3x the input), and the call peaks below 7.5x."""
    x = arma_series([0.6, -0.2], [0.3], 200_000, 1, scale=1e-3)
    select_arma(x[:5_000], fs_hz=10.0)           # lazy imports outside the measurement
    sel, retained, peak = _traced(select_arma, x, fs_hz=10.0)
    assert sel.best is not None                  # type: ignore[attr-defined]
    assert retained < 3.3 * x.nbytes, retained / x.nbytes
    assert peak < 7.5 * x.nbytes, peak / x.nbytes
    # without a time axis one array less
    _, retained, _ = _traced(select_arma, x)
    assert retained < 2.3 * x.nbytes, retained / x.nbytes


def _statsmodels_aic_loop(x: np.ndarray) -> tuple[tuple[int, int], dict]:
    """The peer: ``ARIMA(x, order=(p,0,q), trend="c").fit()`` for the five candidates, the
    lowest AIC wins."""
    from statsmodels.tsa.arima.model import ARIMA

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        fits = {(p, q): ARIMA(x, order=(p, 0, q), trend="c").fit()
                for p, q in [(1, 0), (2, 0), (3, 0), (1, 1), (2, 1)]}
    return min(fits, key=lambda k: fits[k].aic), fits


@pytest.mark.slow
def test_ar1_data_pick_arma21_no_more_often_than_statsmodels() -> None:
    """AR(1), phi = 0.6, n = 2000, seeds 0-19: ``select_arma`` selects ARMA(2,1) no more often
    than statsmodels' ``trend="c"`` AIC loop on the same series.  An ARMA(2,1) whose AR and
    MA parts may share a root (the common-factor Wald test does not reject) is AR(1) with a
    cancelled factor and ranks after the identified candidates; a genuine ARMA(2,1) is kept
    (test below)."""
    fogts_picks, sm_picks = [], []
    for seed in range(20):
        x = arma_series([0.6], [], 2000, seed)
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            sel = select_arma(x)
        assert sel.best is not None
        if sel.best.model == "ARMA(2,1)":
            fogts_picks.append(seed)
            assert not sel.best.flagged("common_factor")
        if _statsmodels_aic_loop(x)[0] == (2, 1):
            sm_picks.append(seed)
        arma21 = sel["ARMA(2,1)"]
        if arma21.flagged("common_factor") and arma21.aic < sel.best.aic:
            # ranked down: the verdict says so with the numbers of the test
            assert "ARMA(2,1) has a lower AIC" in sel.verdict and "standard errors" in sel.verdict
    # measured: fogts [4], statsmodels [17] (seed 17: fogts' ARMA(2,1) is 1.45 AIC units
    # below AR(1), but its resultant is 0.56 standard errors from 0: ranked down)
    assert len(fogts_picks) <= len(sm_picks), (fogts_picks, sm_picks)


def test_arma21_with_well_separated_roots_is_still_selected() -> None:
    """The common-factor rule keeps a genuine ARMA(2,1): x_t = 0.5 x_{t-1} + 0.2 x_{t-2} + a_t
    + 0.5 a_{t-1} (inverse AR roots 0.76, -0.26, MA root -0.5; resultant 0.3), n = 2000,
    seeds 0-9: never flagged, and selected in most seeds (measured over seeds 0-29: 27,
    the same as without the rule; the other 3 select ARMA(1,1))."""
    picks = 0
    for seed in range(10):
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            sel = select_arma(arma_series([0.5, 0.2], [0.5], 2000, seed))
        assert not sel["ARMA(2,1)"].flagged("common_factor"), seed
        picks += sel.best is not None and sel.best.model == "ARMA(2,1)"
    assert picks >= 8, picks


def test_zero_mean_fit_of_demeaned_data_favours_a_unit_ma_root() -> None:
    """The effect the restricted likelihood removes, on the seed where it decided the
    selection: zero-mean ML on demeaned AR(1) data puts ARMA(2,1)'s MA root on the unit
    circle and ranks it first; the GLS mean with the restricted likelihood does not."""
    x = arma_series([0.6], [], 2000, 7)
    xd = x - x.mean()
    zero_mean = {pq: fit_arma(xd, *pq) for pq in [(1, 0), (2, 1)]}
    assert zero_mean[(2, 1)].ma[0] < -0.9999
    assert zero_mean[(2, 1)].aic < zero_mean[(1, 0)].aic          # measured: by 1.3
    restricted = {pq: fit_arma(xd, *pq, mean=True) for pq in [(1, 0), (2, 1)]}
    assert restricted[(2, 1)].aic > restricted[(1, 0)].aic + 1.0  # measured: by 1.7
    # the restricted likelihood does not depend on the mean subtracted first
    assert fit_arma(x + 5.0, 1, 0, mean=True).llf == pytest.approx(restricted[(1, 0)].llf,
                                                                   abs=1e-6)
