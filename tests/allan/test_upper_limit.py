"""One-sided 95 % upper limits of terms fitted to zero (NoiseModel.upper_limit): in the
term table, the JSON and the batch summary."""

from __future__ import annotations

import math
from pathlib import Path

import pytest
from scipy.stats import norm

import fogts

EXAMPLE = Path(__file__).resolve().parents[2] / "data" / "example_fog_10hz_3h.csv"


@pytest.fixture(scope="module")
def model() -> fogts.NoiseModel:
    res = fogts.allan_deviation(fogts.read_run(EXAMPLE))
    with pytest.warns(fogts.errors.FogtsWarning):
        return fogts.fit_noise(res)


def test_a_term_at_zero_has_the_rescaled_interval_end(model: fogts.NoiseModel) -> None:
    q = model["Q"]
    assert q.at_bound and q.value == 0.0
    z68 = norm.ppf(0.5 + model.confidence / 2)
    expected = q.ci_high * math.sqrt(norm.ppf(0.95) / z68)  # sqrt(z se) scales with sqrt(z)
    assert model.upper_limit("Q") == pytest.approx(expected, rel=1e-12)
    assert model.upper_limit("Q", level=0.99) > model.upper_limit("Q") > q.ci_high


def test_a_fitted_term_has_none(model: fogts.NoiseModel) -> None:
    assert not model["N"].at_bound and math.isnan(model.upper_limit("N"))


def test_the_table_and_the_json_carry_it(model: fogts.NoiseModel) -> None:
    text = model.term_table().to_text()
    assert f"< {model.upper_limit('Q'):.3g} (95 % upper limit; fit at zero)" in text
    assert model.noise_dict()["Q"]["upper_limit_95"] == pytest.approx(model.upper_limit("Q"))
    assert math.isnan(model.noise_dict()["N"]["upper_limit_95"])
