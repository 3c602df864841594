"""Tests of fogts.arma.fit against statsmodels' exact-ML ARIMA and gretl's reference fits.

Tolerances (the acceptance criteria of issue 4):

* ``PARAM_TOL = 1e-4`` absolute on AR/MA coefficients wherever the model is identified and both
  fits reach the same optimum; sigma2 to ``1e-4`` relative.
* ``AIC_TOL = 0.05``: fogts' AIC is never worse than statsmodels' ``ARIMA(...).fit()`` on the
  standardised series by more than this.
* ``LLF_EXACT = 1e-6``: fogts' log-likelihood equals statsmodels' own ``loglike`` evaluated at
  fogts' parameters (the reported llf is the exact state-space likelihood).
* Standard errors: the observed information, as gretl and statsmodels ``cov_type="approx"``
  report; ``1e-3`` relative below 50,000 samples (finite-difference Hessian of the exact
  gradient), ``20/n`` relative for the analytic Hessian used above that.
* gretl (``arma_refs``): params ``1e-4``, llf ``1e-3`` (the issue's numbers), bse ``3e-3`` relative.
"""

from __future__ import annotations

import doctest
import json
import math
import shutil
import subprocess
import types
import warnings
from pathlib import Path

import numpy as np
import pandas as pd
import pytest
from scipy.signal import lfilter
from statsmodels.tsa.arima.model import ARIMA

import fogts.arma.fit as fitmod
import fogts.arma.optimiser as optimiser
from fogts.arma.fit import ArmaFit, fit_arma, model_name, param_names
from fogts.arma.likelihood import ExactLikelihood
from fogts.arma.start_values import hannan_rissanen
from fogts.errors import ConvergenceWarning, DataError, InsufficientDataError, ModelFitError
from tests.conftest import shared_path

PARAM_TOL = 1e-4
AIC_TOL = 0.05
LLF_EXACT = 1e-6
CANDIDATES = [(1, 0), (2, 0), (3, 0), (1, 1), (2, 1)]


def simulate(ar: list[float], ma: list[float], n: int, seed: int, scale: float) -> np.ndarray:
    """x_t = sum ar_i x_{t-i} + a_t + sum ma_j a_{t-j}, a_t ~ N(0, scale^2), 500 burn-in."""
    e = np.random.default_rng(seed).standard_normal(n + 500) * scale
    x = lfilter(np.r_[1.0, ma], np.r_[1.0, -np.asarray(ar, dtype=float)], e)
    return np.ascontiguousarray(x[500:])


def sm_fit(xs: np.ndarray, p: int, q: int, **kw):
    """statsmodels' reference fit on the standardised series (no covariance unless asked).

    ``low_memory=True`` only stops statsmodels from storing the filter output: the optimiser
    and its answer are the same (checked to 1e-12), at a third of the cost."""
    kw.setdefault("cov_type", "none")
    kw.setdefault("low_memory", True)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return ARIMA(xs, order=(p, 0, q), trend="n").fit(**kw)


def near_redundant(ar: np.ndarray, ma: np.ndarray, gap: float = 0.15) -> bool:
    """An inverse AR root within ``gap`` of an inverse MA root (a near-common factor)."""
    if len(ar) == 0 or len(ma) == 0:
        return False
    ar_roots = np.roots(np.r_[1.0, -np.asarray(ar)])
    ma_roots = np.roots(np.r_[1.0, np.asarray(ma)])
    return bool(np.min(np.abs(ar_roots[:, None] - ma_roots[None, :])) < gap)


def sm_loglike(xs: np.ndarray, fit: ArmaFit) -> float:
    """statsmodels' exact log-likelihood of the standardised series at fogts' parameters."""
    params = np.r_[fit.ar, fit.ma, fit.sigma2 / fit.scale**2]
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return float(ARIMA(xs, order=(fit.p, 0, fit.q), trend="n").loglike(params))


# --------------------------------------------------------------------------------------------
# statsmodels: five candidates on simulated series from each of the five models
# --------------------------------------------------------------------------------------------

SIM_CASES = {
    # name: (ar, ma, n, raw scale, seed)
    "AR(1)": ([0.7], [], 500, 1e-4, 11),
    "AR(2)": ([1.2, -0.5], [], 800, 1e3, 12),
    "AR(3)": ([0.5, 0.1, 0.3], [], 700, 1e-2, 13),
    "ARMA(1,1)": ([0.8], [0.4], 600, 10.0, 14),
    "ARMA(2,1)": ([1.2, -0.5], [0.4], 1000, 3e-3, 15),
}


@pytest.mark.parametrize("case", list(SIM_CASES))
def test_five_candidates_match_statsmodels(case: str) -> None:
    ar, ma, n, scale, seed = SIM_CASES[case]
    x = simulate(ar, ma, n, seed, scale)
    xs = x / np.std(x)
    log_scale = math.log(np.std(x))
    aic_fogts, aic_ref = [], []
    for p, q in CANDIDATES:
        fit = fit_arma(x, p, q)
        assert fit.converged, fit.warnings
        ref = sm_fit(xs, p, q)
        llf_ref = ref.llf - n * log_scale
        # the reported llf is statsmodels' exact likelihood at fogts' parameters
        assert fit.llf == pytest.approx(sm_loglike(xs, fit) - n * log_scale, abs=LLF_EXACT)
        # never worse than statsmodels
        assert fit.aic <= ref.aic + 2 * n * log_scale + AIC_TOL
        if abs(fit.llf - llf_ref) < 1e-3:
            # the same optimum; parameters are compared where the model is identified (on the
            # flat ridge of a nearly cancelling root pair they are not: llf agrees, that's all)
            if not near_redundant(fit.ar, fit.ma):
                np.testing.assert_allclose(np.r_[fit.ar, fit.ma], ref.params[:-1], rtol=0,
                                           atol=PARAM_TOL)
            assert fit.sigma2 == pytest.approx(ref.params[-1] * np.std(x) ** 2, rel=1e-4)
            aic_ref.append(ref.aic + 2 * n * log_scale)
        elif fit.llf > llf_ref:
            # statsmodels stopped in a worse local optimum: restarted at fogts' point it stays
            again = sm_fit(xs, p, q, start_params=np.r_[fit.ar, fit.ma, fit.sigma2 / fit.scale**2])
            np.testing.assert_allclose(again.params[:-1], np.r_[fit.ar, fit.ma], atol=PARAM_TOL)
            assert again.llf - n * log_scale == pytest.approx(fit.llf, abs=1e-3)
            aic_ref.append(again.aic + 2 * n * log_scale)
        else:
            # an over-parameterised candidate with near-equal optima, each a nearly cancelling
            # AR/MA root pair (not identified); the AIC check above bounds the gap
            assert near_redundant(fit.ar, fit.ma)
            assert near_redundant(ref.params[:p], ref.params[p:p + q])
            aic_ref.append(ref.aic + 2 * n * log_scale)
        aic_fogts.append(fit.aic)
        assert fit.aic == pytest.approx(aic_ref[-1], abs=AIC_TOL)
    # the same ranking by AIC
    assert list(np.argsort(aic_fogts)) == list(np.argsort(aic_ref))


def test_statsmodels_default_start_can_miss_the_optimum() -> None:
    """ARMA(2,1) on AR(3) data: statsmodels' default start ends ~4 llf units short; fogts finds
    the better optimum, which statsmodels confirms when started there."""
    e = np.random.default_rng(520).standard_normal(500)
    x = lfilter([1.0], [1.0, -0.5, 0.1, -0.3], e) * 1e-4
    xs = x / np.std(x)
    fit = fit_arma(x, 2, 1)
    ref = sm_fit(xs, 2, 1)
    shift = 500 * math.log(np.std(x))
    assert fit.llf > ref.llf - shift + 1.0
    again = sm_fit(xs, 2, 1, start_params=np.r_[fit.ar, fit.ma, fit.sigma2 / fit.scale**2])
    np.testing.assert_allclose(again.params[:-1], np.r_[fit.ar, fit.ma], atol=PARAM_TOL)
    assert again.llf - shift == pytest.approx(fit.llf, abs=1e-4)


def test_nearly_redundant_fit_tries_more_starts() -> None:
    """ARMA(1,1) on white noise: the likelihood has several maxima along the cancellation
    ridge phi = -theta; from the Hannan-Rissanen start alone Newton ends 0.8 llf lower, the
    extra starts (mirrored pair, statsmodels' start values) find the better maximum."""
    n = 300
    x = np.random.default_rng(22).standard_normal(n)
    xs = x / np.std(x)
    fit = fit_arma(x, 1, 1)
    llf_std = fit.llf + n * math.log(fit.scale)
    model = ExactLikelihood(xs, 1, 1)
    first = optimiser.solve(xs, model, *hannan_rissanen(xs, 1, 1), polish=True)
    llf_first = -0.5 * n * (math.log(2 * math.pi) + 1 + math.log(first.ev.S / n)) - 0.5 * first.ev.D
    assert llf_std > llf_first + 0.5
    ref = sm_fit(xs, 1, 1)
    assert llf_std >= ref.llf - AIC_TOL / 2
    assert near_redundant(fit.ar, fit.ma)


def test_tiny_variance_pitfall_is_avoided() -> None:
    """ARMA(2,1) data with sigma = 3e-3, n = 20,000 (issue 4): statsmodels on the raw series
    ends hundreds of AIC units short for ARMA(1,1) (here without even a warning); the same fit
    on the standardised series reaches the optimum fogts reports."""
    n = 20_000
    e = np.random.default_rng(1).standard_normal(n) * 3e-3
    x = lfilter([1.0, 0.4], [1.0, -1.2, 0.5], e)
    fit = fit_arma(x, 1, 1)
    assert fit.standardized and fit.scale == pytest.approx(np.std(x))
    raw = sm_fit(x, 1, 1)
    assert raw.aic > fit.aic + 100.0
    ref = sm_fit(x / np.std(x), 1, 1)
    np.testing.assert_allclose(np.r_[fit.ar, fit.ma], ref.params[:-1], atol=PARAM_TOL)
    assert fit.aic == pytest.approx(ref.aic + 2 * n * math.log(np.std(x)), abs=AIC_TOL)


def test_long_series_matches_statsmodels() -> None:
    """n = 100,000, the true model ARMA(1,1): analytic-Hessian bse, exact llf."""
    n = 100_000
    x = simulate([0.9], [-0.4], n, 99, 0.02)
    xs = x / np.std(x)
    fit = fit_arma(x, 1, 1)
    ref = sm_fit(xs, 1, 1)
    np.testing.assert_allclose(np.r_[fit.ar, fit.ma], ref.params[:-1], atol=PARAM_TOL)
    assert fit.aic <= ref.aic + 2 * n * math.log(np.std(x)) + AIC_TOL
    assert fit.llf == pytest.approx(sm_loglike(xs, fit) - n * math.log(fit.scale), abs=1e-5)


def test_long_record_path(monkeypatch: pytest.MonkeyPatch) -> None:
    """The long-record path - Newton on a presample, then on the whole series; bse from the
    analytic Hessian (relative error ~20/n) - with its thresholds lowered to run at n = 10,000."""
    monkeypatch.setattr(optimiser, "_PRESAMPLE", 2_000)
    monkeypatch.setattr(fitmod, "_FD_HESSIAN_MAX_N", 5_000)
    n = 10_000
    x = simulate([1.2, -0.5], [0.4], n, 98, 5.0)
    xs = x / np.std(x)
    fit = fit_arma(x, 2, 1)
    ref = sm_fit(xs, 2, 1, cov_type="approx")
    np.testing.assert_allclose(np.r_[fit.ar, fit.ma], ref.params[:-1], atol=PARAM_TOL)
    assert fit.aic <= ref.aic + 2 * n * math.log(np.std(x)) + AIC_TOL
    ref_bse = np.r_[ref.bse[:-1], ref.bse[-1] * np.std(x) ** 2]
    np.testing.assert_allclose(list(fit.bse.values()), ref_bse, rtol=20 / n)


def test_resid_are_statsmodels_innovations() -> None:
    x = simulate([0.8], [0.4], 700, 5, 1e-3)
    fit = fit_arma(x, 1, 1)
    xs = x / fit.scale
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        res = ARIMA(xs, order=(1, 0, 1), trend="n").filter(
            np.r_[fit.ar, fit.ma, fit.sigma2 / fit.scale**2])
    np.testing.assert_allclose(fit.resid, res.resid * fit.scale, rtol=0, atol=1e-9 * fit.scale)
    assert fit.resid.shape == (700,)


_R_FITS = """
con <- file(commandArgs(TRUE)[1], "rb"); y <- readBin(con, "double", n = 1e7); close(con)
for (o in list(c(1,0), c(2,0), c(3,0), c(1,1), c(2,1))) {
  f <- arima(y, order = c(o[1], 0, o[2]), include.mean = FALSE, method = "ML")
  cat(o[1], o[2], format(f$aic, digits = 15), format(coef(f), digits = 15), "\n")
}
"""


def test_never_worse_than_r_arima_ml(tmp_path: Path) -> None:
    """R's arima(method="ML") on the same standardised series (skipped without Rscript).

    fogts' AIC is never worse by more than AIC_TOL; parameters agree within 1e-3 (R's BFGS
    stops at a relative likelihood change of 1e-8, so it is the looser of the two)."""
    rscript = shutil.which("Rscript")
    if rscript is None:
        pytest.skip("R is not installed (Debian: apt-get install r-base-core)")
    n = 1500
    x = simulate([0.8], [0.4], n, 81, 1e-3)
    xs = x / np.std(x)
    xs.astype("<f8").tofile(tmp_path / "y.f64")
    (tmp_path / "fits.R").write_text(_R_FITS)
    out = subprocess.run([rscript, str(tmp_path / "fits.R"), str(tmp_path / "y.f64")],
                         capture_output=True, text=True, check=True, timeout=300).stdout
    rows = [line.split() for line in out.strip().splitlines()]
    assert len(rows) == len(CANDIDATES)
    for (p, q), row in zip(CANDIDATES, rows, strict=True):
        assert (int(row[0]), int(row[1])) == (p, q)
        fit = fit_arma(x, p, q)
        aic_std = fit.aic - 2 * n * math.log(fit.scale)
        assert aic_std <= float(row[2]) + AIC_TOL
        np.testing.assert_allclose(np.r_[fit.ar, fit.ma], [float(v) for v in row[3:]],
                                   atol=1e-3)


# --------------------------------------------------------------------------------------------
# standard errors
# --------------------------------------------------------------------------------------------

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


def test_criteria_as_statsmodels_defines_them() -> None:
    x = simulate([0.6], [], 400, 3, 1.0)
    fit = fit_arma(x, 1, 0, standardize=False)
    ref = sm_fit(x, 1, 0)
    assert fit.scale == 1.0 and not fit.standardized
    for attr in ("aic", "bic", "hqic", "aicc"):
        assert getattr(fit, attr) == pytest.approx(getattr(ref, attr), abs=1e-4)


# --------------------------------------------------------------------------------------------
# gretl reference fits
# --------------------------------------------------------------------------------------------

GRETL_SERIES = ["Y_arma11", "Y_arma14", "Y_arma41", "Y_arma22", "Y_arma50", "Y_arma02"]


@pytest.fixture(scope="module")
def gretl() -> tuple[pd.DataFrame, dict]:
    data = pd.read_csv(shared_path("arma_refs", "y_arma_data.csv"))
    with open(shared_path("arma_refs", "gretl_stata_reference_fits.json")) as fh:
        ref = json.load(fh)["gretl_arma_on_y_arma_data_csv"]["models"]
    return data, ref


@pytest.mark.parametrize("key", GRETL_SERIES)
def test_gretl_exact_ml(key: str, gretl: tuple[pd.DataFrame, dict]) -> None:
    data, ref = gretl
    p, q = int(key[-2]), int(key[-1])
    mle = ref[key]["mle"]
    fit = fit_arma(data[key.lower()], p, q)
    np.testing.assert_allclose(np.r_[fit.ar, fit.ma], mle["params"], rtol=0, atol=1e-4)
    assert fit.llf == pytest.approx(mle["llf"], abs=1e-3)
    assert fit.aic == pytest.approx(mle["aic"], abs=2e-3)
    assert fit.bic == pytest.approx(mle["bic"], abs=2e-3)
    assert fit.sigma2 == pytest.approx(mle["sigma2"], rel=1e-4)
    np.testing.assert_allclose([fit.bse[k] for k in param_names(p, q)[:-1]], mle["bse"],
                               rtol=3e-3)


# --------------------------------------------------------------------------------------------
# interface, methods, input types
# --------------------------------------------------------------------------------------------

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


def test_statsmodels_method_agrees_with_fast() -> None:
    x = simulate([0.8], [0.4], 500, 51, 1e-4)
    fast = fit_arma(x, 1, 1)
    slow = fit_arma(x, 1, 1, method="statsmodels")
    assert slow.method == "statsmodels" and slow.standardized
    np.testing.assert_allclose(np.r_[fast.ar, fast.ma], np.r_[slow.ar, slow.ma], atol=PARAM_TOL)
    assert fast.aic <= slow.aic + AIC_TOL
    np.testing.assert_allclose(list(fast.bse.values()), list(slow.bse.values()), rtol=2e-3)


def test_series_input_equals_array_input() -> None:
    x = simulate([0.7], [], 300, 61, 1.0)
    s = pd.Series(x, index=pd.date_range("2024-01-01", periods=300, freq="100ms"))
    a = fit_arma(x, 1, 0)
    b = fit_arma(s, 1, 0)
    assert a.params == b.params and a.llf == b.llf


def test_ma_only_and_near_noninvertible() -> None:
    """An over-differenced series (MA root on the unit circle) fits exactly, with a note."""
    rng = np.random.default_rng(7)
    x = np.diff(rng.standard_normal(2001))
    fit = fit_arma(x, 0, 1)
    ref = sm_fit(x / np.std(x), 0, 1)
    assert fit.name == "MA(1)"
    assert fit.ma[0] == pytest.approx(ref.params[0], abs=1e-4)
    assert fit.aic <= ref.aic + 2 * 2000 * math.log(np.std(x)) + AIC_TOL
    assert fit.ma[0] < -0.99
    noted = any("nearly non-invertible" in w for w in fit.warnings)
    assert noted == (abs(fit.ma[0]) >= 0.999)


def test_boundary_notes() -> None:
    notes = fitmod._boundary_notes({"ar.L1": 0.9995, "ma.L1": -0.9999}, 1, 1)
    assert len(notes) == 2
    assert "modulus 0.999500" in notes[0] and "nearly non-stationary" in notes[0]
    assert "modulus 0.999900" in notes[1] and "nearly non-invertible" in notes[1]
    assert fitmod._boundary_notes({"ar.L1": 0.5, "ma.L1": 0.3}, 1, 1) == []


def test_docstring_examples_run() -> None:
    result = doctest.testmod(fitmod, verbose=False)
    assert result.attempted > 0 and result.failed == 0


# --------------------------------------------------------------------------------------------
# bad input and failures
# --------------------------------------------------------------------------------------------

def test_too_short() -> None:
    with pytest.raises(InsufficientDataError, match=r"too short for ARMA\(2,1\): need at least 40"):
        fit_arma(np.random.default_rng(0).standard_normal(30), 2, 1)


def test_constant_series() -> None:
    with pytest.raises(InsufficientDataError, match="x is constant"):
        fit_arma(np.full(500, 0.25), 1, 0)


def test_explosive_series() -> None:
    x = lfilter([1.0], [1.0, -1.05], np.random.default_rng(0).standard_normal(300))
    with pytest.raises(ModelFitError, match=r"x looks explosive: .* root of modulus 1\.05"):
        fit_arma(x, 1, 1)


def test_unit_root_is_not_called_explosive() -> None:
    x = np.cumsum(np.random.default_rng(3).standard_normal(2000))
    fit = fit_arma(x - x.mean(), 1, 0)
    assert fit.ar[0] > 0.98


@pytest.mark.parametrize(("kwargs", "exc", "match"), [
    ({"p": 0, "q": 0}, DataError, r"p \+ q must be >= 1"),
    ({"p": -1, "q": 1}, DataError, "p must be >= 0, got -1"),
    ({"p": 1, "q": 1.5}, DataError, "q must be an integer"),
    ({"p": 1, "q": 0, "method": "css"}, DataError, "method must be one of fast, statsmodels"),
])
def test_bad_arguments(kwargs: dict, exc: type, match: str) -> None:
    x = np.random.default_rng(0).standard_normal(200)
    with pytest.raises(exc, match=match):
        fit_arma(x, **kwargs)


def test_bad_data() -> None:
    x = np.random.default_rng(0).standard_normal(200)
    x[17] = np.nan
    with pytest.raises(DataError, match="non-finite value"):
        fit_arma(x, 1, 0)
    with pytest.raises(DataError, match="1-D array"):
        fit_arma(np.ones((100, 2)), 1, 0)


def test_nonstationary_covariance_is_a_fit_error() -> None:
    model = ExactLikelihood(np.random.default_rng(0).standard_normal(600), 1, 0)
    with pytest.raises(ModelFitError, match="not positive definite"):
        model.transient(np.array([[1.5]]), np.zeros((1, 0)))


def test_nonfinite_likelihood_is_a_fit_error() -> None:
    model = ExactLikelihood(np.full(600, 1e200), 1, 0)
    with np.errstate(over="ignore", invalid="ignore"), \
            pytest.raises(ModelFitError, match="likelihood is not finite"):
        model.evaluate(np.array([0.5]), np.zeros(0))


def test_numerical_failure_becomes_model_fit_error(monkeypatch: pytest.MonkeyPatch) -> None:
    def boom(*args: object) -> None:
        raise np.linalg.LinAlgError("Singular matrix")

    monkeypatch.setattr(fitmod, "_fit_fast", boom)
    with pytest.raises(ModelFitError, match=r"AR\(1\): exact ML fit failed \(LinAlgError"):
        fit_arma(np.random.default_rng(0).standard_normal(200), 1, 0)


def test_statsmodels_failure_becomes_model_fit_error(monkeypatch: pytest.MonkeyPatch) -> None:
    def boom(self: object, **kw: object) -> None:
        raise ValueError("Non-stationary starting autoregressive parameters")

    monkeypatch.setattr(ARIMA, "fit", boom)
    with pytest.raises(ModelFitError, match=r"AR\(1\): statsmodels fit failed: Non-stationary"):
        fit_arma(np.random.default_rng(0).standard_normal(200), 1, 0, method="statsmodels")


def test_statsmodels_nonfinite_llf_is_a_fit_error(monkeypatch: pytest.MonkeyPatch) -> None:
    def fake(self: object, **kw: object) -> types.SimpleNamespace:
        return types.SimpleNamespace(params=np.array([0.5, 1.0]), bse=np.array([0.1, 0.1]),
                                     llf=np.nan, resid=np.zeros(200), mle_retvals={})

    monkeypatch.setattr(ARIMA, "fit", fake)
    with pytest.raises(ModelFitError, match="non-finite log-likelihood"):
        fit_arma(np.random.default_rng(0).standard_normal(200), 1, 0, method="statsmodels")


def test_non_convergence_is_attached_and_warned(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(optimiser, "_MAX_ITER", 1)
    monkeypatch.setattr(fitmod, "_FD_HESSIAN_MAX_N", 0)
    monkeypatch.setattr(fitmod, "hannan_rissanen",
                        lambda xs, p, q: (np.array([0.0]), np.array([0.9])))
    x = simulate([0.9], [-0.5], 800, 71, 1.0)
    with pytest.warns(ConvergenceWarning, match=r"ARMA\(1,1\): the likelihood maximisation"):
        fit = fit_arma(x, 1, 1)
    assert not fit.converged
    assert any("did not converge in 1 iterations" in w for w in fit.warnings)
    assert "NOT CONVERGED" in fit.summary()


def test_white_plus_rate_random_walk_fits_near_the_unit_root() -> None:
    """The typical gyro model (white noise + rate random walk) puts the ARMA(1,1) optimum
    within 1e-5 of phi = 1; the derivatives' difference steps used to cross it and raise
    "not positive definite (LAPACK dpbtrf)".  Reference: statsmodels' exact ML on the
    standardised series (AIC shifted by 2 n log s back to the data's scale)."""
    from statsmodels.tsa.arima.model import ARIMA

    r = np.random.default_rng(900107)  # the reproduction
    n = 100_000
    x = 0.1 * r.standard_normal(n) + np.cumsum(1e-4 * r.standard_normal(n))
    x = x - x.mean()
    fit = fit_arma(x, 1, 1)
    assert fit.converged and fit.ar[0] > 0.9999
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        ref = ARIMA(x / x.std(), order=(1, 0, 1), trend="n").fit()
    assert fit.aic <= ref.aic + 2 * n * math.log(x.std()) + 0.05  # the selection's acceptance
    assert fit_arma(x, 2, 1).converged
    for seed in range(5):  # AR(1) with phi = 0.9999: ARMA(2,1) failed in 5 of 10 seeds
        y = lfilter([1.0], [1.0, -0.9999], np.random.default_rng(seed).standard_normal(20_000))
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            fit = fit_arma(y - y.mean(), 2, 1)
        assert np.isfinite(fit.aic)
        # an optimum on the stationarity boundary is fitted, and said to be
        assert fit.converged or any("boundary" in str(w.message) for w in caught)
