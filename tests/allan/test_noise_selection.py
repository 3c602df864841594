"""Tests for fogts.allan.noise_selection: upper limits and identifiability of the terms."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest

from fogts.allan.noise import fit_noise
from fogts.errors import UnidentifiableTermWarning
from fogts.report.text import json_dumps
from tests.allan.noise_cases import avar, make_result


def test_bound_terms_identifiability_and_warnings() -> None:
    tau = 2.0 ** np.arange(-6, 10)
    res = make_result(tau, np.sqrt(avar(tau, N=0.02)), edf=500.0)
    with pytest.warns(UnidentifiableTermWarning, match=r"noise term K .* not identifiable"):
        model = fit_noise(res, terms=["n", "K"])
    k = model["K"]
    assert k.at_bound and not k.identifiable and k.value == 0.0
    assert math.isnan(k.stderr) and k.ci_low == 0.0 and k.ci_high > 0
    assert any("noise term K" in w for w in model.warnings)
    assert model["N"].identifiable and not model["N"].at_bound
    d = model.to_dict()
    assert d["terms"]["K"]["stderr"] is not None  # NaN survives to_dict; JSON makes it null
    payload = json.loads(json_dumps(d))
    assert payload["terms"]["K"]["stderr"] is None
    assert set(payload["terms"]["N"]) >= {"value", "stderr", "unit", "ci_low", "ci_high",
                                          "c_coeff", "identifiable"}


def test_a_term_dropped_for_visibility_alone_is_not_called_insignificant() -> None:
    """A term visible at no data tau is dropped whatever its z (module docstring of
    noise_selection); with z above the one-sided level-0.05 critical value (1.645) the
    message says so instead of 'not significant'."""
    import dataclasses

    from fogts.allan.noise_selection import _drop_reason

    tau = np.logspace(-1, 3, 20)
    model = fit_noise(make_result(tau, np.sqrt(avar(tau, N=1.0, B=0.2, K=0.01))),
                      terms=("N", "B", "K"))
    term = dataclasses.replace(model["N"], status="dropped", z_score=2.30)
    assert _drop_reason(term, 0.05).startswith(
        "it was dropped although z(C²) = 2.30 passes the level-0.05 test: it reaches 25 % of "
        "sigma^2 at no data tau")
    weak = dataclasses.replace(term, z_score=1.60)
    assert _drop_reason(weak, 0.05) == "it was dropped as not significant, z(C²) = 1.60 at level 0.05"
