"""Out-of-sample gain of the thermal model (fogts.startup.thermal_cv).

Truth: a rate that is exactly a thermal drift plus white noise leaves, out of sample, the
white noise's own bias stability ``sigma / sqrt(m)`` (``m`` samples per average); simulated
cold starts at three ambients (``simulate_startup``) are validated on held-out runs; the
bundled cold starts give the figures in ``tests/README.md``.  The interval is compared
with scipy's Student-t interval on the log ratios.
"""

from __future__ import annotations

import json
import math
import re
from pathlib import Path

import numpy as np
import pytest
import scipy.stats
from typer.testing import CliRunner

import fogts
from fogts.cli import app
from fogts.errors import DataError, InsufficientDataError
from fogts.startup.simulator import simulate_startup
from fogts.startup.thermal_cv import thermal_cross_validation

ROOT = Path(__file__).resolve().parents[2]
COLD = [ROOT / "data" / f for f in ("startup_cold_1hz.csv", "startup_cold_15c_1hz.csv",
                                    "startup_cold_25c_1hz.csv")]


def _ramp_run(seed: int, n: int = 7200, sigma: float = 0.5) -> tuple[np.ndarray, np.ndarray]:
    """1 Hz: temperature up and down twice between 20 and 40 °C (each block sees the whole
    range), rate = 0.8 T + white noise of sd ``sigma``."""
    t = np.arange(n, dtype=float)
    temp = 30.0 - 10.0 * np.cos(2 * np.pi * t / (n / 2))
    rate = 0.8 * temp + np.random.default_rng(seed).normal(0.0, sigma, n)
    return rate, temp


@pytest.mark.parametrize("seed", [1, 2])
def test_held_out_blocks_leave_the_white_noise(seed: int) -> None:
    """After compensation out of sample only the white noise is left: bias stability
    sigma / sqrt(10) per 10 s average.  Each block holds 144 windows, so the estimated
    std has a relative standard error 1 / sqrt(2 * 143) = 6 %; tolerance 20 % (3.4 SE)."""
    rate, temp = _ramp_run(seed)
    cv = thermal_cross_validation([(rate, temp)], fs_hz=1.0, terms=("T", "1"))
    assert cv.scheme == "time blocks" and cv.n_scored == 5
    for fold in cv.folds:
        assert fold.after == pytest.approx(0.5 / math.sqrt(10.0), rel=0.2)
        assert fold.before > 10 * fold.after  # the 16 deg/h swing of 0.8 T dominates
    assert cv.low < cv.ratio < cv.high


def test_the_interval_is_a_t_interval_on_the_log_ratios() -> None:
    rate, temp = _ramp_run(3)
    cv = thermal_cross_validation([(rate, temp)], fs_hz=1.0, terms=("T", "1"), blocks=4,
                                  confidence=0.9)
    logs = np.log([f.ratio for f in cv.folds])
    lo, hi = scipy.stats.t.interval(0.9, logs.size - 1, loc=logs.mean(),
                                    scale=scipy.stats.sem(logs))
    assert cv.ratio == pytest.approx(math.exp(logs.mean()), rel=1e-12)
    assert (cv.low, cv.high) == pytest.approx((math.exp(lo), math.exp(hi)), rel=1e-12)


def test_simulated_cold_starts_on_held_out_runs() -> None:
    """Three cold starts (15, 20, 25 °C ambient) of one simulated gyro: each compensated by
    the model of the other two keeps most of the in-sample gain (above 2x)."""
    runs = [simulate_startup(duration_s=3600, ambient_degC=a, rng=s).run
            for a, s in ((15.0, 11), (20.0, 12), (25.0, 13))]
    cv = thermal_cross_validation([(r.axis(0), r.temperature) for r in runs], fs_hz=1.0,
                                  labels=["a", "b", "c"])
    assert cv.scheme == "held-out runs" and cv.guard_s == 0 and cv.n_scored == 3
    assert [f.label for f in cv.folds] == ["a", "b", "c"]
    assert all(f.ratio > 2.0 for f in cv.folds)
    assert cv.low < cv.ratio < cv.high
    assert cv.to_frame().shape == (3, 5)


def test_a_warm_up_block_outside_the_training_range_is_not_scored() -> None:
    """The bundled cold start: the blocks follow the temperature travel (0-210-482-1027-
    2177-3600 s); the first (20-28.8 °C) lies below every other block's temperatures
    (31.2-45.8 °C), so it is reported, not scored; the warm-up blocks it leaves gain out of
    sample (measured 3.31, 1.52x), the plateau blocks not (1.07, 0.99x)."""
    run = fogts.read_run(COLD[0])
    cv = thermal_cross_validation([(run.axis(0), run.temperature)], fs_hz=1.0)
    assert [f.scored for f in cv.folds] == [False, True, True, True, True]
    assert cv.folds[0].label == "block 1 (0-210 s)"
    assert cv.folds[0].ratio < 0.1  # extrapolated, the quadratic model is far off
    assert cv.folds[1].ratio > 2.0 and cv.folds[2].ratio > 1.2
    assert 1.2 < cv.ratio < 2.0 and cv.low < 1.0 < cv.high
    assert cv.covers_fit and cv.coverage("temperature") == pytest.approx(0.66, abs=0.02)
    text = cv.summary()
    assert "not scored" in text and "--calibration" in text
    assert cv.to_dict()["folds"][0]["scored"] is False


def test_workflow_measures_out_of_sample_only_when_significant() -> None:
    runs = [fogts.read_run(p) for p in COLD]
    res = fogts.startup_compensation(runs[0], emd=False, calibration=runs[1:])
    cv = res.out_of_sample
    assert cv is not None and cv.scheme == "held-out runs"
    # measured: 4.28, 4.89, 4.02x; 4.38x [3.42, 5.61]
    assert [round(f.ratio, 1) for f in cv.folds] == [4.3, 4.9, 4.0]
    assert 3.0 < cv.low < cv.ratio < cv.high < 7.0
    assert "out of sample (3 held-out runs" in res.summary()
    example = fogts.read_run(ROOT / "data" / "example_fog_10hz_3h.csv")
    with pytest.warns(fogts.errors.UnidentifiableTermWarning):
        null = fogts.startup_compensation(example, emd=False)
    assert null.out_of_sample is None and null.to_dict()["out_of_sample"] is None


def test_cli_json_gains_out_of_sample(tmp_path: Path) -> None:
    res = CliRunner().invoke(app, ["compensate", str(COLD[0]), "--no-emd", "--json", "-"])
    assert res.exit_code == 0, res.stderr
    doc = json.loads(res.stdout)
    oos = doc["out_of_sample"]
    assert oos["scheme"] == "time blocks" and oos["n_folds"] == 5 and oos["n_scored"] == 4
    assert oos["low"] < oos["improvement"] < oos["high"]
    assert doc["bias_stability"]["improvement"] == pytest.approx(4.3, abs=0.05)


def test_short_records_are_noted_not_fatal() -> None:
    sim = simulate_startup(duration_s=80, rng=5)
    rate, temp = sim.run.axis(0), sim.run.temperature
    with pytest.raises(InsufficientDataError, match="5 time blocks of a 80 s record"):
        thermal_cross_validation([(rate, temp)], fs_hz=1.0)


@pytest.mark.parametrize(("kwargs", "match"), [
    ({"blocks": 2}, "blocks must be"),
    ({"confidence": 1.5}, "confidence"),
    ({"guard_s": -1.0}, "guard_s must be a finite number >= 0"),
])
def test_bad_options_are_named(kwargs: dict, match: str) -> None:
    rate, temp = _ramp_run(4, n=1200)
    with pytest.raises(DataError, match=match):
        thermal_cross_validation([(rate, temp)], fs_hz=1.0, **kwargs)


def test_bad_runs_are_named() -> None:
    with pytest.raises(DataError, match="at least one"):
        thermal_cross_validation([], fs_hz=1.0)
    with pytest.raises(DataError, match=r"runs\[0\]: rate and temperature must have the same"):
        thermal_cross_validation([(np.zeros(10), np.zeros(9))], fs_hz=1.0)


def test_audit_cs2_warm_up_is_scored_and_covered() -> None:
    """Audit N5: a 2 h simulated cold start (``fogts simulate startup --seed 4``: warm-up
    20 -> 45.8 °C in the first ~20 min, the true drift of DEFAULT_STARTUP_COEFFICIENTS).
    Blocks of equal time put the whole warm-up in block 1 (0-1440 s, not scored), so the
    scored blocks spanned 45.05-45.83 °C and tested nothing of the model (1.01x).  Blocks
    cut by the temperature travel score two warm-up blocks, where the true thermal drift
    is removed out of sample (measured 2.31x and 1.74x)."""
    sim = simulate_startup(duration_s=7200, rng=4)
    rate, temp = sim.run.axis(0), sim.run.temperature
    cv = thermal_cross_validation([(rate, temp)], fs_hz=1.0)
    assert [f.scored for f in cv.folds] == [False, True, True, True, True]
    assert cv.folds[1].ratio > 1.5 and cv.folds[2].ratio > 1.3
    lo, hi = cv.scored_range("temperature")
    assert 25.0 < lo < 35.0 and hi == pytest.approx(45.83, abs=0.05)
    assert cv.covers_fit and cv.coverage_text() == ""
    # the warm-up blocks gain, the plateau blocks do not: over four folds the 95 % interval
    # reaches below 1, which is no evidence of an improvement out of sample
    assert cv.ratio > 1.2 and cv.low < 1.0
    assert re.fullmatch(r"out of sample 1\.\d+x, but its 95 % interval \[0\.\d+, \d\.\d+\] "
                        "reaches 1", cv.claim_gap())
    doc = cv.to_dict()
    assert doc["covers_fit"] is True and doc["fitted_temperature_degC"] == [20.0, 45.83]


def test_scored_folds_on_the_plateau_only_say_so() -> None:
    """A fast warm-up (time constants 30 s and 10 s: 20 -> 22.6 °C in a minute) in a 2 h
    record: the warm-up blocks all extrapolate, the scored ones sit on the plateau; the
    figure says it does not test the warm-up and supports no claim."""
    sim = simulate_startup(duration_s=7200, tau_s=(30.0, 10.0), rng=4)
    cv = thermal_cross_validation([(sim.run.axis(0), sim.run.temperature)], fs_hz=1.0)
    assert cv.n_scored >= 1 and not cv.covers_fit
    gap = cv.coverage_text()
    assert gap.startswith("not tested over the warm-up: the scored folds span 22.6-22.6 °C "
                          "of the 20-22.6 °C fitted")
    assert gap in cv.summary() and gap in cv.gain_text()
    assert cv.claim_gap() == f"out of sample {gap}"
    assert cv.to_dict()["covers_fit"] is False


def test_workflow_claim_rests_on_a_covering_out_of_sample_test() -> None:
    """The fast warm-up above: significant, 1.5x in sample, but the out-of-sample test does
    not cover the warm-up, so the claim is "in sample only"; the 2 h cold start's blocks
    cover it, but their interval reaches 1 (the plateau blocks gain nothing): not claimed
    either; three cold starts at 20, 5 and 35 °C, each held out in turn, are claimed
    (3.3x, 95 % interval about [1.5, 7.5])."""
    import warnings

    with warnings.catch_warnings():
        warnings.simplefilter("ignore", fogts.errors.UnidentifiableTermWarning)
        fast = fogts.startup_compensation(
            simulate_startup(duration_s=7200, tau_s=(30.0, 10.0), rng=4).run, emd=False)
        slow = fogts.startup_compensation(simulate_startup(duration_s=7200, rng=4).run,
                                          emd=False)
    assert fast.significance is not None and fast.significance.significant
    assert fast.improvement > 1.2 and not fast.claims_improvement
    assert fast.claim_basis == "in sample only"
    assert fast.to_dict()["bias_stability"]["claim_basis"] == "in sample only"
    assert "not claimed as an improvement: in sample only: out of sample not tested over " \
           "the warm-up" in fast.summary()
    assert not slow.claims_improvement and slow.claim_basis == "in sample only"
    assert re.search(r"\(3\.\d+x in sample\); not claimed as an improvement: in sample only: "
                     r"out of sample 1\.\d+x, but its 95 % interval \[0\.\d+, \d\.\d+\] "
                     "reaches 1", slow.summary())
    runs = [simulate_startup(duration_s=7200, ambient_degC=a, rng=seed).run
            for a, seed in ((20.0, 4), (5.0, 5), (35.0, 6))]
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", fogts.errors.UnidentifiableTermWarning)
        several = fogts.startup_compensation(runs[0], calibration=runs[1:], emd=False)
    cv = several.out_of_sample
    assert cv is not None and cv.scheme == "held-out runs" and cv.low > 1.0
    assert several.claims_improvement and several.claim_basis == "out of sample"
    assert "in sample; out of sample 3." in several.summary()
