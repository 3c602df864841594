"""Tests for fogts.allan.noise_model: NoiseModel access, curves and exports."""

from __future__ import annotations

import numpy as np
import pytest

from fogts.report.text import json_dumps
from tests.allan.noise_cases import avar, make_result, quiet_fit


def test_exports() -> None:
    tau = 2.0 ** np.arange(-6, 14)
    res = make_result(tau, np.sqrt(avar(tau, N=0.02, B=0.1, K=0.05)))
    # with n_samples = 4 m_max + 10, K (at most 30 % of sigma^2) is not significant: z = 0.32
    selected = quiet_fit(res)
    assert selected.dropped == ("K",) and 0 < selected["K"].z_score < 1
    assert selected.to_dict()["fit"]["dropped"] == ["K"]
    assert selected.to_dict()["terms"]["K"]["status"] == "dropped"
    assert "dropped, z(C²) = 0.32" in selected.summary()
    assert "term selection: one-sided tests at 5 %" in selected.summary()
    model = quiet_fit(res, significance=None)  # every term kept: the exact curve back
    assert model.significance is None and "term selection" not in model.summary()
    frame = model.to_frame()
    assert list(frame.index) == ["Q", "N", "B", "K", "R"]
    assert frame.loc["N", "unit"] == "deg/sqrt(h)" and frame.loc["Q", "unit"] == "arcsec"
    assert frame.loc["K", "slope"] == 0.5
    d = model.to_dict()
    assert set(d) >= {"method", "confidence", "terms", "readoff", "fit", "warnings"}
    assert d["fit"]["stderr_method"] == model.stderr_method
    assert json_dumps(d) == json_dumps(model.to_dict())  # deterministic
    text = model.summary()
    assert "IEEE-952 noise terms" in text and "deg/h^1.5" in text and "read-offs" in text
    assert model.values["N"] == pytest.approx(0.02, rel=1e-6)
    with pytest.raises(KeyError, match="term 'X' was not fitted"):
        model["X"]


def test_term_table_caption_states_the_squared_coefficients() -> None:
    """The table's C_n column holds the square roots of the sigma^2 coefficients
    (DESIGN.md: N = C_-1/60, B = C_0/0.664); its caption must say so, and the closed form it
    states must give back the fitted curve from the printed C_n (rate in deg/h)."""
    tau = 2.0 ** np.arange(-4, 12)
    model = quiet_fit(make_result(tau, np.sqrt(avar(tau, N=0.02, B=0.1, K=0.5))),
                      significance=None)
    table = model.term_table()
    assert "sum C_n^2 tau^n" in table.to_text()
    assert "sum C_n tau^n" not in table.to_text()
    # the intervals are not value +- z stderr (C_n^2 scale, band-limit allowance): said so
    assert "it can be wider than value ± k·stderr" in table.to_text()
    c = {t.power: t.c_coeff for t in model.terms}
    # the B term is C_0^2 * (2 ln 2 / pi) / 0.664^2 ~ C_0^2 (0.04 % apart, DESIGN.md); the
    # power-law sum is checked on the terms whose coefficient is exactly C_n^2
    at = 10.0
    n_term = c[-1] ** 2 / at
    assert n_term == pytest.approx(avar(np.array([at]), N=0.02)[0], rel=1e-6)


def test_the_chi2_line_says_the_model_error_is_in_it() -> None:
    """With a model error fitted into the weights, chi2 lands near its dof whatever the
    misfit (ADIS16405 run 1 X: "chi2 = 14.91 on 17 dof" printed beside "misses"); the
    sentence says so, and says when no model error was needed (an exact curve)."""
    from fogts.allan.noise_lsq import chi2_sentence

    tau = 2.0 ** np.arange(-4, 12)
    # every term kept (significance=None): the exact curve comes back, no model error
    exact = quiet_fit(make_result(tau, np.sqrt(avar(tau, N=0.02, B=0.1, K=0.5))),
                      significance=None)
    assert exact.model_error == 0.0
    assert "no model error needed" in exact.summary()
    bent = np.sqrt(avar(tau, N=0.02, B=0.1, K=0.5)) * (1 + 0.1 * np.sin(np.arange(tau.size)))
    model = quiet_fit(make_result(tau, bent), significance=None)
    assert model.model_error > 0
    text = chi2_sentence(model.chi2, model.dof, model.model_error, model.model_error_lr,
                         model.significance)
    assert f"after adding the fitted model error {model.model_error:.3g}" in text
    assert "brings chi2 near its dof" in text and text in model.summary()
    assert chi2_sentence(3.0, 4.0, float("nan")).endswith("(unweighted residual sum of squares)")


def test_the_limit_note_says_what_z_is_and_why_an_interval_clear_of_zero_is_a_limit() -> None:
    """z in the notes is the Wald z of C_n^2 (about value / (2 stderr)), which the caption
    must say; a term whose interval excludes 0 but whose z(C^2) < 2 is only a limit, and
    the caption must say why (the rule is z(C^2) >= 2, stricter than a 68.3 % interval)."""
    import dataclasses

    tau = 2.0 ** np.arange(-4, 12)
    model = quiet_fit(make_result(tau, np.sqrt(avar(tau, N=0.02, B=0.1, K=0.5))),
                      significance=None)
    text = model.term_table().to_text()
    assert "z(C²) = C_n²/se(C_n²) ≈ value/(2·stderr)" in " ".join(text.split())
    clear = [t.name for t in model.terms if t.is_limit and not t.at_bound and t.ci_low > 0]
    assert ("excludes 0, yet only a limit" in text) == bool(clear)
    model = dataclasses.replace(model, terms=tuple(
        dataclasses.replace(t, ci_low=0.0) if t.name in clear else t for t in model.terms))
    assert "excludes 0, yet only a limit" not in model.term_table().to_text()
    k = model["K"]
    weak = dataclasses.replace(k, z_score=1.89, status="fitted", at_bound=False,
                               ci_low=0.5 * k.value, ci_high=1.5 * k.value)
    assert weak.is_limit
    limited = dataclasses.replace(model, terms=tuple(weak if t.name == "K" else t
                                                     for t in model.terms))
    flat = " ".join(limited.term_table().to_text().split())
    assert "(95 % upper limit; z(C²) = 1.89 < 2)" in flat
    pct = f"{100 * limited.confidence:.1f} %"
    assert (f"K: the {pct} interval excludes 0, yet only a limit: the rule asks for "
            f"z(C²) ≥ 2, a stricter test than a {pct} interval.") in flat
    # at 95 % confidence the interval is not the weaker test: the clause is left out
    wide = dataclasses.replace(limited, confidence=0.95)
    flat = " ".join(wide.term_table().to_text().split())
    assert "K: the 95.0 % interval excludes 0, yet only a limit: the rule asks for z(C²) ≥ 2." \
        in flat
