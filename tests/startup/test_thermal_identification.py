"""Are the thermal coefficients separately identified?  Variance inflation factors, the
note on a jointly significant model of individually insignificant, collinear coefficients,
the note on a model that is not significant at all, the notes' way through a saved model,
and the in-sample / out-of-sample headline.

Truth: a VIF is ``1 / (1 - R²)`` of one column regressed on the others (computed here with
numpy's least squares, independently of statsmodels); the bundled cold starts
(``data/startup_cold*_1hz.csv``) are one warm-up at 20 °C, whose six coefficients are not
separately identified, and three ambients (15, 20, 25 °C), whose are.
"""

from __future__ import annotations

import dataclasses
import json
import math
import warnings
from pathlib import Path

import numpy as np
import pytest

import fogts
from fogts.errors import UnidentifiableTermWarning
from fogts.startup.thermal_cv import CvFold, ThermalCrossValidation
from fogts.startup.thermal_identification import (
    NOT_SIGNIFICANT,
    T_CRITICAL,
    collinearity,
    identification_note,
    note_in_brief,
    reuse_warning,
    significance_note,
)
from fogts.startup.thermal_model import ThermalModel

ROOT = Path(__file__).resolve().parents[2]
COLD = [ROOT / "data" / f for f in ("startup_cold_1hz.csv", "startup_cold_15c_1hz.csv",
                                    "startup_cold_25c_1hz.csv")]


def _vif_by_lstsq(X: np.ndarray, j: int) -> float:
    y = X[:, j]
    others = np.delete(X, j, axis=1)
    beta = np.linalg.lstsq(others, y, rcond=None)[0]
    resid = y - others @ beta
    r2 = 1.0 - resid @ resid / np.sum((y - y.mean()) ** 2)
    return 1.0 / (1.0 - r2)


def test_vif_and_condition_number_against_their_definitions() -> None:
    rng = np.random.default_rng(7)
    a = rng.standard_normal(400)
    b = 0.9 * a + 0.3 * rng.standard_normal(400)
    c = rng.standard_normal(400)
    X = np.column_stack([a, b, c, np.ones(400)])
    d = collinearity(X, ["T", "T2", "dT", "1"])
    for j, term in enumerate(["T", "T2", "dT"]):
        assert d["vif"][term] == pytest.approx(_vif_by_lstsq(X, j), rel=1e-8)
    assert set(d["vif"]) == {"T", "T2", "dT"} and d["max_vif_term"] in ("T", "T2")
    scaled = X / np.linalg.norm(X, axis=0)
    assert d["condition_number"] == pytest.approx(np.linalg.cond(scaled), rel=1e-10)
    # orthogonal columns inflate nothing; a lone column has VIF 1 by definition
    # (centred: orthogonal to the offset and to each other)
    q = np.linalg.qr(np.column_stack([np.ones(50), rng.standard_normal((50, 3))]))[0][:, 1:]
    centred = np.column_stack([q, np.ones(50)])
    assert collinearity(centred, ["T", "dT", "T2", "1"])["max_vif"] == pytest.approx(1.0, abs=1e-9)
    assert collinearity(q[:, :1], ["T"])["vif"] == {"T": 1.0}
    only_offset = collinearity(np.ones((10, 1)), ["1"])
    assert math.isnan(only_offset["max_vif"]) and only_offset["max_vif_term"] is None


def _model(t_values: dict[str, float], max_vif: float) -> ThermalModel:
    return ThermalModel(terms=(*t_values, "1"),
                        coefficients={**t_values, "1": 1.0},
                        stderr={**dict.fromkeys(t_values, 1.0), "1": 1.0}, dropped={},
                        r2=0.5, r2_adj=0.5, residual_std=0.1, units="deg/h", fs_hz=1.0,
                        dT_smoothing_s=60.0, t_ref_degC=40.0,
                        temperature_range_degC=(20.0, 45.0), errors="ar", error_params={},
                        n=3600, collinearity={"max_vif": max_vif, "max_vif_term": "T2"})


def test_the_rule_joint_significance_collinearity_and_too_few_significant() -> None:
    weak = {"T*dT": 1.2, "T2": 1.3, "T": -1.3, "dT2": -0.9, "dT": 0.4}
    note = identification_note(_model(weak, 5e5), jointly_significant=True)
    assert note is not None and note.startswith("the coefficients are not separately identified")
    assert "largest variance inflation factor 5e+05 (T2), above 10" in note
    assert "0 of 5 thermal coefficients individually significant" in note
    assert note.endswith("do not reuse it on another ambient or warm-up without a calibration run")
    assert identification_note(_model(weak, 5e5), jointly_significant=False) is None
    assert identification_note(_model(weak, 9.0), jointly_significant=True) is None
    # two of five significant is too few; three of five is not
    two = {**weak, "T2": 2.5, "T": -3.0}
    assert "2 of 5" in (identification_note(_model(two, 5e5), True) or "")
    assert identification_note(_model({**two, "dT": 2.0}, 5e5), True) is None
    # |t| just above the 5 % critical value counts as significant
    assert T_CRITICAL == pytest.approx(1.959964, abs=1e-6)
    one = {"T": T_CRITICAL * 1.001, "dT": 0.1}
    assert identification_note(_model(one, 50.0), True) is None


def test_one_warm_up_gets_the_note_and_a_saved_model_carries_it(tmp_path: Path) -> None:
    run = fogts.read_run(COLD[0])
    with pytest.warns(UnidentifiableTermWarning, match="not separately identified"):
        res = fogts.startup_compensation(run, emd=False)
    model = res.model
    assert res.significance is not None and res.significance.significant
    assert model.identification_note is not None
    assert model.collinearity["max_vif"] > 1e4       # measured: 4.6e5 (T2)
    assert "coefficients not separately identified: largest VIF" in model.summary()
    d = model.to_dict()
    assert d["identification_note"] == model.identification_note
    assert set(d["collinearity"]) >= {"vif", "max_vif", "condition_number", "vif_threshold"}
    back = ThermalModel.from_dict(json.loads(json.dumps(d)))
    assert back.identification_note == model.identification_note
    assert back.collinearity["max_vif"] == pytest.approx(model.collinearity["max_vif"])
    # applied to another warm-up, the saved model warns
    other = fogts.read_run(COLD[1])
    with pytest.warns(UnidentifiableTermWarning, match="fitted on another run and saved with "
                                                       "this note: the coefficients are not"):
        applied = fogts.startup_compensation(other, model=back)
    assert "by the given model: out of sample unless it was fitted on this run" \
        in applied.summary()
    assert reuse_warning(dataclasses.replace(back, identification_note=None)) is None


def test_three_ambients_identify_the_coefficients_and_reuse_is_quiet() -> None:
    runs = [fogts.read_run(p) for p in COLD]
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        res = fogts.startup_compensation(runs[0], emd=False, calibration=runs[1:])
        fogts.startup_compensation(runs[1], model=res.model)
    assert res.model.identification_note is None
    assert not [w for w in caught if issubclass(w.category, UnidentifiableTermWarning)]
    # measured: VIFs still above 10 (T2 and T over 15-51 degC), but 3 of 5 coefficients |t| > 2
    assert res.model.collinearity["max_vif"] > 10
    assert res.to_dict()["thermal"]["model"]["identification_note"] is None


def test_the_headline_names_in_sample_and_shows_out_of_sample() -> None:
    with pytest.warns(UnidentifiableTermWarning):
        res = fogts.startup_compensation(fogts.read_run(COLD[0]), emd=False)
    cv = res.out_of_sample
    assert cv is not None
    line = next(x for x in res.summary().splitlines() if x.startswith("bias stability"))
    # one warm-up: the blocks over it gain, those on the plateau do not, and the interval
    # reaches 1: shown, and not claimed
    assert cv.low < 1.0 < cv.ratio and not res.claims_improvement
    assert line.endswith(f"({res.improvement:.2f}x in sample); not claimed as an improvement: "
                         f"in sample only: out of sample {cv.ratio:.3g}x, but its 95 % "
                         f"interval [{cv.low:.3g}, {cv.high:.3g}] reaches 1")
    assert "out of sample" in res._view_headline()
    rows = [r[0] for r in res._view_table().rows]
    assert "improvement in sample" in rows and "improvement out of sample" in rows


def test_gain_text_without_an_interval() -> None:
    fold = CvFold("block 2", 1.0, 0.5, (30.0, 40.0), (20.0, 45.0))
    one = ThermalCrossValidation("time blocks", (fold,), 2.0, math.nan, math.nan, 0.95, 10.0, 60.0)
    assert one.gain_text() == "2x, one fold" and one.interval_text() == ""
    none = dataclasses.replace(one, folds=(dataclasses.replace(fold, scored=False),),
                               ratio=math.nan)
    assert none.gain_text() == "not measured"


def test_a_given_model_that_makes_the_rate_less_stable_is_not_an_improvement() -> None:
    """A model fitted on a warm-up, applied to a run whose rate has no thermal drift (white
    noise under the same temperature record): the compensation adds the model's drift, the
    bias stability gets worse, and that is said instead of 'Nx by the given model'."""
    import pandas as pd

    warm = fogts.read_run(COLD[0])
    with pytest.warns(UnidentifiableTermWarning):
        model = fogts.startup_compensation(warm, emd=False).model
    white = np.random.default_rng(7).normal(scale=0.05, size=warm.n)
    flat = fogts.read_run(pd.DataFrame({"time": warm.time, "rate_deg_h": white,
                                        "temperature": warm.temperature}))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", UnidentifiableTermWarning)
        res = fogts.startup_compensation(flat, emd=False, model=model)
    assert res.improvement < 1.0 and not res.claims_improvement
    assert res.to_dict()["bias_stability"]["improvement_claimed"] is False
    assert f"not claimed as an improvement: the bias stability is {res.improvement:.2f}x, " \
           "no better after the given model: it does not describe this run's thermal " \
           "drift" in res.summary()


def _no_thermal_effect(seed: int = 700) -> fogts.Run:
    """A 1 h record with a warm-up temperature (22 -> 26 degC) and no thermal drift."""
    from fogts.simulate import TemperatureProfile

    return fogts.simulate_gyro({"N": 0.002, "B": 0.01, "K": 0.05}, fs_hz=1, duration_s=3600,
                               rng=seed, temperature=TemperatureProfile.parse("warmup:22,26,15min"))


def test_a_model_that_is_not_significant_carries_the_note_and_warns_when_reused() -> None:
    """No thermal drift under a warm-up: the likelihood-ratio test finds nothing (measured
    p = 0.23), the fitted model is saved with a note quoting the test, and reusing it on
    another run warns with that note."""
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        res = fogts.startup_compensation(_no_thermal_effect(), emd=False)
    sig = res.significance
    assert sig is not None and sig.testable and not sig.significant
    # the verdict says it: no warning at the fit (only the dropped collinear term's)
    assert not [w for w in caught if "not significant" in str(w.message)]
    note = res.model.identification_note
    assert note == significance_note(sig)
    assert note is not None and note.startswith(f"{NOT_SIGNIFICANT} (likelihood-ratio test")
    assert f"p = {sig.pvalue:.2g}, chi2 = {sig.statistic:.3g} on {sig.df} df" in note
    assert note.endswith("do not reuse it to compensate another run")
    assert res.to_dict()["thermal"]["model"]["identification_note"] == note
    assert note_in_brief(res.model) == "not significant, not for reuse on another run"
    back = ThermalModel.from_dict(json.loads(json.dumps(res.model.to_dict())))
    assert back.identification_note == note and note in back.summary()
    with pytest.warns(UnidentifiableTermWarning, match="fitted on another run and saved with "
                                                       "this note: the model is not significant"):
        fogts.startup_compensation(fogts.read_run(COLD[0]), model=back)


def test_the_significance_note_of_an_untestable_and_of_a_significant_record() -> None:
    from fogts.startup.thermal_test import ThermalSignificance

    flat = ThermalSignificance(False, False, math.nan, 5, math.nan, 0.001, 0.471, 3000, 1.0)
    note = significance_note(flat)
    assert note is not None and note.startswith(
        "the model is not significant (the temperature spans only 0.471 °C: the coefficients "
        "cannot be identified)")
    assert significance_note(dataclasses.replace(flat, testable=True, significant=True)) is None
    # the collinearity note keeps its brief
    assert note_in_brief(_model({"T": 1.0}, 5e5)) is None
    noted = dataclasses.replace(_model({"T": 1.0}, 5e5), identification_note="the coefficients")
    assert note_in_brief(noted) == ("not separately identified, not for reuse on another "
                                    "ambient or warm-up")
