"""The verdict of a selection and the notes on its data."""

from __future__ import annotations

import json
import re
import warnings

import numpy as np
import pytest

from fogts.arma import select_arma
from fogts.report.text import json_dumps
from tests.arma.simulated import arma_series


def test_quantized_raw_rate_is_noted() -> None:
    from fogts.preprocess.prepare import prepare

    x = np.round(arma_series([0.6], [], 3000, 1) * 2.0) / 2.0        # a 0.5 deg/h output step
    sel = select_arma(x)
    assert len(sel.notes) == 1 and "distinct values (step 0.5)" in sel.notes[0]
    assert sel.notes[0] in sel.verdict
    assert json.loads(json_dumps(sel.to_dict()))["notes"] == list(sel.notes)
    # block-averaged data are no longer quantized: no note
    assert select_arma(prepare(x, fs_hz=10.0, decimate=2, stationarity=False)).notes == ()
    assert select_arma(arma_series([0.6], [], 3000, 1)).notes == ()


def test_nearly_white_series_says_so() -> None:
    sel = select_arma(np.random.default_rng(2).standard_normal(5000))
    assert sel.best is not None
    assert "nearly white at this sample rate" in sel.verdict


def test_verdict_names_a_simpler_model_within_two_units() -> None:
    for seed in range(12):
        sel = select_arma(arma_series([0.6], [], 4000, seed))
        best = sel.best
        assert best is not None
        close = [c for c in sel.candidates if c.white and c.p + c.q < best.p + best.q
                 and c.aic - best.aic < 2.0]
        assert ("The simpler" in sel.verdict) == bool(close)
        if close:
            return
    pytest.fail("no seed produced an over-fitted selection with a simpler model close by")


def test_cancellation_verdict_follows_the_numbers() -> None:
    """ADIS16405 run 1, axis Z at 1 Hz: ARMA(1,1) has nearly cancelling roots, yet AR(1) is
    ~2185 AIC units worse and not white, so the verdict must not say a lower order does as
    well, and must show the numbers it rests on."""

    from fogts.io.reader import read_run
    from fogts.preprocess.prepare import prepare
    from tests.conftest import shared_path

    run = read_run(shared_path("imu", "adis_16405_imu1_gyro.npz"))
    sel = select_arma(prepare(run, axis="Gyro. Z", decimate=100))
    assert sel.selected is not None and sel.selected.model == "ARMA(1,1)"
    assert sel.selected.flagged("near_cancellation")
    assert "a lower order would do as well" not in sel.verdict
    m = re.search(r"yet no lower order does as well: the best lower-order candidate, AR\(1\), "
                  r"is \+(\d+\.\d) AIC units and is not white; keep ARMA\(1,1\)", sel.verdict)
    assert m is not None, sel.verdict
    assert float(m.group(1)) == pytest.approx(2185.0, rel=0.01)


def test_a_non_invertible_selection_is_not_said_to_describe_the_drift() -> None:
    """Over-differenced white noise is MA(1) with theta = -1 exactly: the selected MA(1)'s
    root lies on the unit circle (seed 0: theta = -1 to 1e-9), and the verdict says what
    that means instead of "describes the drift".  Seed 2 stops at theta = -0.99916, 8e-4
    inside the circle (more than 1/n = 3.3e-4): that one is an ordinary invertible model."""
    from fogts.arma.verdict import on_unit_circle

    verdicts = {}
    for seed in (0, 2):
        w = np.random.default_rng(seed).standard_normal(3001)
        sel = select_arma(np.diff(w), candidates="AR(1),AR(2),MA(1),ARMA(1,1)")
        assert sel.best is not None and sel.best.model == "MA(1)" and sel.best.white
        verdicts[seed] = (on_unit_circle(sel.best), sel.verdict)
    mu, text = verdicts[0]
    assert mu is not None and mu.real == pytest.approx(1.0, abs=1e-6)
    assert "describes the drift" not in text
    assert "MA(1) has the lowest AIC among the white candidates, but it is not invertible" in text
    assert "a zero of the spectrum at frequency 0" in text
    assert "MA(1) does not describe the drift" in text
    assert "No white candidate is invertible." in text      # ARMA(1,1) is on the circle too
    mu, text = verdicts[2]
    assert mu is None and text.startswith("MA(1) describes the drift")


def test_a_candidate_ranked_down_for_a_common_factor_is_explained_with_its_numbers() -> None:
    """AR(1) data, phi = 0.6, n = 2000, seed 17: ARMA(2,1) has the lower AIC (by 1.45) but its
    AR root -0.9999 and MA root -0.999 may coincide (resultant 0.56 standard errors from 0):
    AR(1) is selected, and every number the verdict gives follows from the candidates."""
    import warnings

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        sel = select_arma(arma_series([0.6], [], 2000, 17))
    arma21 = sel["ARMA(2,1)"]
    assert sel.best is not None and sel.best.model == "AR(1)"
    # ranked after every white candidate without a common-factor flag
    assert arma21.rank == max(c.rank for c in sel.candidates if c.white)   # type: ignore[type-var]
    (flag,) = arma21.flagged("common_factor")
    assert "may reduce to AR(1)" in arma21.notes
    m = re.search(r"ARMA\(2,1\) has a lower AIC \(by (\d+\.\d)\) but ranks below it: the AR and "
                  r"MA parts may share a root \(closest pair: AR (\S+), MA (\S+)\): their "
                  r"resultant (\S+) is (\d+\.\d\d) standard errors \((\S+)\) from 0, < 1\.96; "
                  r"the model is then AR\(1\) with a cancelled factor, not identified\.",
                  sel.verdict)
    assert m is not None, sel.verdict
    assert "lowest AIC among the white candidates without a possible common" in sel.verdict
    # the printed numbers, to their printed precision
    assert float(m.group(1)) == pytest.approx(sel.best.aic - arma21.aic, abs=0.05)
    assert float(m.group(2)) == pytest.approx(flag.details["ar_root"].real, abs=1e-4)
    assert float(m.group(3)) == pytest.approx(flag.details["ma_root"].real, abs=1e-4)
    r, z, se = float(m.group(4)), float(m.group(5)), float(m.group(6))
    assert abs(r) / se == pytest.approx(z, rel=0.03)       # 3 and 2 significant digits
    assert z < 1.96 and z == pytest.approx(abs(flag.details["z"]), abs=0.005)


def test_a_candidate_on_the_unit_circle_ranks_down_and_is_named() -> None:
    """AR(1) data, phi = 0.6, n = 2000, seed 78: ARMA(2,1)'s restricted-likelihood estimate
    piles up at theta = 1 (MA inverse root -1) with the lowest AIC (1.9 below AR(1)).  A
    model whose innovations cannot be recovered from the data cannot drive a prediction, so
    it ranks after the invertible white candidates: AR(1) is selected, the table notes the
    root and the verdict names the ranked-down model with its AIC gap."""
    x = arma_series([0.6], [], 2000, 78)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        sel = select_arma(x)
    assert sel.best is not None and sel.best.model == "AR(1)"
    last = sel.candidates[-1]
    assert last.model == "ARMA(2,1)" and last.aic < sel.best.aic
    assert "MA root on the unit circle" in last.notes
    m = re.search(r"ARMA\(2,1\) has a lower AIC \(by (\d+\.\d)\) but ranks below it: its MA "
                  r"inverse root -1\+0j lies on the unit circle", sel.verdict)
    assert m is not None, sel.verdict
    assert float(m.group(1)) == pytest.approx(sel.best.aic - last.aic, abs=0.05)
    assert "without an MA root on the unit circle" in sel.verdict
