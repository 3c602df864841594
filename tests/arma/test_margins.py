"""A simpler candidate that fails the residual checks only marginally (fogts.arma.margins)."""

from __future__ import annotations

import dataclasses
import json
import re

import pytest

from fogts.arma import margins, select_arma
from fogts.arma.candidate import Candidate
from fogts.arma.margins import MarginCheck, equivalent_simpler
from fogts.arma.selection import Selection
from fogts.arma.whiteness import CorrelationCheck, LjungBoxLag
from fogts.report.text import json_dumps


@pytest.fixture(scope="module")
def adis4_z() -> Selection:
    """ADIS16405 run 4, axis Z at 1 Hz: ARMA(2,1) passes Ljung-Box at lag 10 with p = 0.0505,
    ARMA(1,1) fails it with p = 0.0496, ar.L2 has t = -1.56 and ARMA(1,1) is 0.43 AIC
    units worse."""
    from fogts.io.reader import read_run
    from fogts.preprocess.prepare import prepare
    from tests.conftest import shared_path

    run = read_run(shared_path("imu", "adis_16405_imu4_gyro.npz"))
    return select_arma(prepare(run, axis="Gyro. Z", decimate=100))


def _lb(c: Candidate, lag: int, p: float) -> Candidate:
    """``c`` with its Ljung-Box p value at ``lag`` replaced (pass/fail judged at 0.05)."""
    d = c.diagnostics
    assert d is not None
    lbs = tuple(dataclasses.replace(x, pvalue=p, passed=p >= 0.05) if x.lag == lag else x
                for x in d.ljung_box)
    reasons = tuple(r for r in d.reasons if "Ljung" not in r)
    if p < 0.05:
        reasons += (f"Ljung-Box p({lag}) = {p} < 0.05",)
    return dataclasses.replace(c, diagnostics=dataclasses.replace(d, ljung_box=lbs,
                                                                   reasons=reasons))


def _rho(c: Candidate, value: float) -> Candidate:
    """``c`` with rho_a2 replaced (pass/fail judged against its band)."""
    d = c.diagnostics
    assert d is not None
    check = CorrelationCheck("rho_a2", value, d.band, abs(value) <= d.band)
    reasons = tuple(r for r in d.reasons if "rho_a2" not in r)
    if not check.passed:
        reasons += ("rho_a2 outside the band",)
    return dataclasses.replace(c, diagnostics=dataclasses.replace(d, rho_a2=check,
                                                                   reasons=reasons))


def test_a_knife_edge_whiteness_verdict_is_reported_with_its_numbers(adis4_z: Selection) -> None:
    sel = adis4_z
    best = sel.selected
    assert best is not None and best.model == "ARMA(2,1)" and best.white    # rule unchanged
    eq = sel.equivalent_simpler
    assert eq is not None and eq.model == "ARMA(1,1)"
    # the numbers of the audit (values printed to 3-4 digits in the table and the notes)
    assert [c.check for c in eq.checks] == ["ljung_box(10)"]
    assert eq.checks[0].selected == pytest.approx(0.0505, abs=5e-5)
    assert eq.checks[0].simpler == pytest.approx(0.0496, abs=5e-5)
    assert [name for name, _ in eq.extra] == ["ar.L2"]
    assert eq.extra[0][1] == pytest.approx(-1.558, abs=5e-3)
    assert eq.delta == pytest.approx(0.43, abs=0.01)
    text = sel.verdict
    assert "keep ARMA(2,1)" not in text and "no lower order does as well" not in text
    assert re.search(r"ARMA\(1,1\) fails the residual checks only marginally \(Ljung-Box "
                     r"p\(10\) = 0\.0496 against 0\.0505 for ARMA\(2,1\)\), ar\.L2 "
                     r"\(t = -1\.56\) is not significant and ARMA\(1,1\) is \+0\.4 AIC units",
                     text), text
    assert "the simpler ARMA(1,1) is as good a choice" in text
    # JSON: one added key at the end of "selected", nothing renamed
    d = json.loads(json_dumps(sel.to_dict()))
    assert list(d["selected"])[-1] == "equivalent_simpler"
    assert d["selected"]["equivalent_simpler"]["model"] == "ARMA(1,1)"
    assert set(d["selected"]["equivalent_simpler"]["extra_params"]) == {"ar.L2"}
    # the table marks the simpler candidate
    row = sel.candidate_table().to_text()
    assert "marginally not white" in row


def test_no_equivalent_when_the_simpler_model_fails_clearly(adis4_z: Selection) -> None:
    sel, ranked = adis4_z.selected, list(adis4_z.candidates)
    assert sel is not None
    i = next(k for k, c in enumerate(ranked) if c.model == "ARMA(1,1)")
    ranked[i] = _lb(ranked[i], 10, 0.02)                     # below the margin band
    assert equivalent_simpler(sel, ranked, "aic") is None


def test_no_equivalent_when_the_selected_model_passes_clearly(adis4_z: Selection) -> None:
    sel, ranked = adis4_z.selected, list(adis4_z.candidates)
    assert sel is not None
    sel = _lb(sel, 10, 0.3)                                   # above the margin band
    ranked[0] = sel
    assert equivalent_simpler(sel, ranked, "aic") is None


def test_no_equivalent_when_the_extra_coefficient_is_significant(adis4_z: Selection) -> None:
    sel, ranked = adis4_z.selected, list(adis4_z.candidates)
    assert sel is not None and sel.fit is not None
    bse = dict(sel.fit.bse, **{"ar.L2": abs(sel.params["ar.L2"]) / 2.5})       # t = -2.5
    sel = dataclasses.replace(sel, fit=dataclasses.replace(sel.fit, bse=bse))
    assert equivalent_simpler(sel, ranked, "aic") is None


def test_no_equivalent_beyond_the_close_call(adis4_z: Selection,
                                             monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(margins, "CLOSE_CALL", 0.4)           # the gap is 0.43
    assert equivalent_simpler(adis4_z.selected, adis4_z.candidates, "aic") is None


def test_no_equivalent_without_a_white_selection(adis4_z: Selection) -> None:
    sel = adis4_z.selected
    assert sel is not None
    assert equivalent_simpler(None, adis4_z.candidates, "aic") is None
    worse = _lb(sel, 10, 0.01)
    assert not worse.white
    assert equivalent_simpler(worse, adis4_z.candidates, "aic") is None


def test_a_marginal_rho_failure_is_named(adis4_z: Selection) -> None:
    sel, ranked = adis4_z.selected, list(adis4_z.candidates)
    assert sel is not None and sel.diagnostics is not None
    band = sel.diagnostics.band
    sel = _rho(sel, -0.95 * band)
    i = next(k for k, c in enumerate(ranked) if c.model == "ARMA(1,1)")
    ranked[0] = sel
    ranked[i] = _lb(_rho(ranked[i], -1.05 * band), 10, 0.06)  # Ljung-Box now passes
    eq = equivalent_simpler(sel, ranked, "aic")
    assert eq is not None and [c.check for c in eq.checks] == ["rho_a2"]
    assert "rho_a2 = -0.0" in eq.sentence(sel.model)
    ranked[i] = _lb(_rho(ranked[i], -1.2 * band), 10, 0.06)   # outside 10 % of the band
    assert equivalent_simpler(sel, ranked, "aic") is None


def test_numbers_that_print_alike_get_more_digits() -> None:
    c = MarginCheck("ljung_box(10)", 0.050004, 0.049996)
    text = margins.EquivalentSimpler("AR(1)", "aic", 0.1, (c,), (("ar.L2", 0.5),)).sentence(
        "AR(2)")
    assert "p(10) = 0.049996 against 0.050004" in text
    assert "ar.L2 (t = 0.50) is not significant" in text


def test_an_untestable_lag_is_not_a_marginal_failure(adis4_z: Selection) -> None:
    """A simpler candidate not white for a reason other than a marginal check (here: no
    marginal failure recorded at all) is not declared equivalent."""
    sel, ranked = adis4_z.selected, list(adis4_z.candidates)
    assert sel is not None
    i = next(k for k, c in enumerate(ranked) if c.model == "ARMA(1,1)")
    d = ranked[i].diagnostics
    assert d is not None
    lbs = tuple(dataclasses.replace(x, passed=None) if not x.passed else x
                for x in d.ljung_box)
    ranked[i] = dataclasses.replace(ranked[i], diagnostics=dataclasses.replace(d, ljung_box=lbs))
    assert not ranked[i].white
    assert equivalent_simpler(sel, ranked, "aic") is None
    assert isinstance(lbs[0], LjungBoxLag)
