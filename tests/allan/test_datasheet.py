"""Datasheet limits (fogts.allan.datasheet): the specification's checks and the PASS, FAIL or
INCONCLUSIVE of a fitted model by each term's one-sided 95 % bounds."""

from __future__ import annotations

import math
import warnings
from pathlib import Path
from typing import Any

import pytest

import fogts
from fogts.allan.datasheet import NoiseSpec, check_spec
from fogts.errors import DataError
from fogts.units import TERM_SI_FACTOR

EXAMPLE = Path(__file__).resolve().parents[2] / "data" / "example_fog_10hz_3h.csv"


@pytest.fixture(scope="module")
def model() -> fogts.NoiseModel:
    """The example FOG record's fit: N and B measured, K only bounded (z < 2)."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        fit = fogts.fit_noise(fogts.allan_deviation(fogts.read_run(EXAMPLE)))
    assert not fit["N"].is_limit and not fit["B"].is_limit and fit["K"].is_limit
    return fit


def test_a_measured_term_is_judged_by_its_one_sided_95_bounds(model: fogts.NoiseModel
                                                               ) -> None:
    """The bounds are sqrt(C^2 -+ 1.645 * 2 C se(C)) (module docstring, 1e-12: the same
    formula); a limit above the upper bound PASSes, below the lower bound FAILs, and one
    between them, on either side of the value, is INCONCLUSIVE."""
    n, se = model["N"].value, model["N"].stderr
    spread = 2 * 1.6448536269514722 * n * se
    low, high = math.sqrt(n * n - spread), math.sqrt(n * n + spread)
    checks = {lim: check_spec(model, NoiseSpec.from_mapping({"N": lim}))["N"]
              for lim in (high * 1.001, (n + high) / 2, (low + n) / 2, low * 0.999)}
    assert [c.verdict for c in checks.values()] == ["PASS", "INCONCLUSIVE", "INCONCLUSIVE",
                                                    "FAIL"]
    first = next(iter(checks.values()))
    assert first.bounds_deg == pytest.approx((low, high), rel=1e-12)
    assert first.compared_deg == pytest.approx(n, rel=1e-15) and not first.by_upper_limit
    assert [c.passed for c in checks.values()] == [True, None, None, False]


def test_a_bounded_term_passes_only_below_its_upper_limit(model: fogts.NoiseModel) -> None:
    """K's fitted value is below a limit its 95 % upper limit exceeds: the data cannot
    decide (INCONCLUSIVE); a term that is only a limit never FAILs (its lower bound is 0)."""
    k, upper = model["K"].value, model.upper_limit("K")
    between = (k + upper) / 2
    assert k < between < upper
    open_ = check_spec(model, NoiseSpec.from_mapping({"K": between}))["K"]
    assert open_.verdict == "INCONCLUSIVE" and open_.by_upper_limit and open_.passed is None
    assert open_.compared_deg == pytest.approx(upper, rel=1e-15)
    assert open_.bounds_deg == (0.0, open_.compared_deg)
    assert check_spec(model, NoiseSpec.from_mapping({"K": upper * 1.01}))["K"].passed
    assert check_spec(model, NoiseSpec.from_mapping({"K": k * 0.01}))["K"].verdict == \
        "INCONCLUSIVE"


def test_si_limits_are_converted_with_the_units_table(model: fogts.NoiseModel) -> None:
    n = model["N"].value
    si = NoiseSpec.from_mapping({"units": "si", "N": n * 1.01 * TERM_SI_FACTOR["N"]})
    assert si.limit_deg("N") == pytest.approx(n * 1.01, rel=1e-12)
    assert check_spec(model, si)["N"].verdict == "PASS"
    assert si.to_dict()["limits"]["N"]["unit"] == "rad/s/sqrt(Hz)"


def test_a_number_yaml_reads_as_text_is_a_number() -> None:
    """PyYAML (YAML 1.1) reads 5e-5 without a decimal point as the string '5e-5'."""
    assert NoiseSpec.from_mapping({"B": "5e-5"}).limit("B") == pytest.approx(5e-5, rel=1e-15)


def test_a_term_not_fitted_has_no_verdict() -> None:
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        fit = fogts.fit_noise(fogts.allan_deviation(fogts.read_run(EXAMPLE)), terms="N,B")
    check = check_spec(fit, NoiseSpec.from_mapping({"K": 1.0}))["K"]
    assert check.passed is None and check.verdict == "not fitted"


@pytest.mark.parametrize(("data", "message"), [
    ([0.15, 10], r"spec must be a mapping of noise terms to limits such as 'N: 0.15', "
                 r"got list: \[0.15, 10\]"),
    ("N 0.15", r"spec must be a mapping .* got str: 'N 0.15'"),
    ({"N": 0.15, "units": "mrad"}, r"spec: units must be one of deg, si; got 'mrad'"),
    ({"N": 0.15, "ARW": 1}, r"spec: unknown key\(s\) 'ARW'; allowed are N, B, K and units"),
    ({"Q": 1.0}, r"unknown key\(s\) 'Q'"),
    ({"N": "fast"}, r"spec: the limit of N must be a number, got 'fast'"),
    ({"N": True}, r"the limit of N must be a number, got True"),
    ({"B": 0}, r"spec: the limit of B must be finite and > 0, got 0"),
    ({"K": float("inf")}, r"the limit of K must be finite and > 0, got inf"),
    ({"units": "deg"}, r"spec gives no limit: give at least one of N, B, K"),
    (None, r"spec must be a mapping .* got NoneType"),
])
def test_bad_specifications_are_named(data: Any, message: str) -> None:
    with pytest.raises(DataError, match=message):
        NoiseSpec.from_mapping(data)


def test_a_spec_without_units_says_which_units_it_assumes() -> None:
    """audit: 'N: 1e-5' without 'units:' was read silently as 1e-5 deg/sqrt(h) (meant, by
    its size, in rad/s/sqrt(Hz)): the spec warns, as a rate column without a unit does,
    naming the units assumed for each term and how to set them; with units, no warning."""
    from fogts.errors import DataQualityWarning

    with pytest.warns(DataQualityWarning) as caught:
        spec = NoiseSpec.from_mapping({"N": 1e-5, "K": 0.5}, source="k.yaml")
    assert spec.units == "deg" and spec.limit_deg("N") == pytest.approx(1e-5, rel=1e-15)
    assert [str(w.message) for w in caught] == [
        "k.yaml: no units in the spec; assuming deg (N in deg/sqrt(h), K in deg/h^1.5); give "
        "'units: deg' or 'units: si' (N in rad/s/sqrt(Hz), K in rad/s^2/sqrt(Hz))"]
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        NoiseSpec.from_mapping({"N": 1e-5, "units": "si"})
        NoiseSpec.from_mapping({"N": 0.15, "units": "deg"})
