"""Tests of fogts.simulate.noise_spec: the coefficients, their coercion and closed forms."""

from __future__ import annotations

import math
from types import SimpleNamespace

import numpy as np
import pandas as pd
import pytest

from fogts.allan.terms import B_PLATEAU
from fogts.errors import DataError
from fogts.simulate.gyro import simulate_gyro
from fogts.simulate.noise_spec import NoiseSpec, markov_avar


def test_noise_spec_closed_form_matches_design_definitions() -> None:
    """DESIGN.md "Definitions": the C_n of a reference fit convert to N, B, K, R, Q; the
    closed form in deg/h and seconds is sum C_n^2 tau^n."""
    c = {-2: 1.1754e-5, -1: 1.0228e-2, 0: 3.835e-3, 1: 1.196e-3, 2: 1.827e-4}
    spec = NoiseSpec(Q=c[-2] / math.sqrt(3), N=c[-1] / 60, B=c[0] / B_PLATEAU,
                     K=60 * math.sqrt(3) * c[1], R=3600 * math.sqrt(2) * c[2])
    assert (spec.N, spec.B, spec.K, spec.R, spec.Q) == pytest.approx(
        (1.704e-4, 5.776e-3, 0.1243, 0.9303, 6.786e-6), rel=1e-3)
    tau = np.array([0.1, 1.0, 10.0, 100.0])
    expected = sum(cn**2 * tau**n for n, cn in c.items())
    # B_PLATEAU = 0.664 approximates sqrt(2 ln2 / pi) = 0.66428
    np.testing.assert_allclose(spec.avar(tau), expected, rtol=1e-3)
    assert spec.adev([1.0], units="deg/s")[0] == pytest.approx(
        math.sqrt(expected[1]) / 3600, rel=1e-3)


def test_noise_spec_from_mappings_and_models() -> None:
    assert NoiseSpec.from_any({"n": 0.1, "Markov_Q": 1, "tc": 5}) == NoiseSpec(
        N=0.1, q_c=1.0, T_c=5.0)
    assert NoiseSpec.from_any({"N": {"value": 0.1, "stderr": 0.01, "unit": "deg/sqrt(h)"},
                               "K": {"value": None}, "B": float("nan")}) == NoiseSpec(N=0.1)
    assert NoiseSpec.from_any({"noise": {"N": 0.2}}) == NoiseSpec(N=0.2)
    model = SimpleNamespace(to_dict=lambda: {"method": "wls", "terms": {
        "N": {"value": 0.3}, "B": {"value": 0.02}}})
    assert NoiseSpec.from_any(model) == NoiseSpec(N=0.3, B=0.02)
    attrs = SimpleNamespace(N=0.1, K=0.2)
    assert NoiseSpec.from_any(attrs) == NoiseSpec(N=0.1, K=0.2)
    spec = NoiseSpec(N=0.1)
    assert NoiseSpec.from_any(spec) is spec
    assert NoiseSpec(N=0.1, B=0.2, q_c=1, T_c=1, Omega_0=1, f_0=1, bias=1).terms == (
        "N", "B", "markov", "sine", "bias")
    frame = spec.to_frame()
    assert isinstance(frame, pd.DataFrame) and set(frame["term"]) >= {"N", "B", "q_c"}
    assert "angle random walk" in spec.summary()
    assert "noiseless" in NoiseSpec().summary()


def test_a_term_the_fit_only_bounds_is_taken_with_a_warning() -> None:
    """audit2: ``simulate noise --from-json`` of an allan JSON took K = 0.787 (given there
    as '< 1.34', not measured) as the truth without a word."""
    import warnings

    from fogts.errors import DataQualityWarning

    doc = {"noise": {"N": {"value": 0.05, "upper_limit_95": None},
                     "K": {"value": 0.7872, "upper_limit_95": 1.345},
                     "R": {"value": 0.0, "upper_limit_95": 1.12}}}
    with pytest.warns(DataQualityWarning) as caught:
        spec = NoiseSpec.from_any(doc)
    assert spec == NoiseSpec(N=0.05, K=0.7872)
    assert [str(w.message) for w in caught] == [
        "the fit did not measure K = 0.7872 (its 95 % upper limit is 1.345): the data only "
        "bound it, yet its fitted value is taken as the truth to simulate; give K explicitly "
        "to simulate another value"]
    with warnings.catch_warnings():
        warnings.simplefilter("error", DataQualityWarning)  # R is 0: nothing taken
        assert NoiseSpec.from_any({"noise": {"R": doc["noise"]["R"]}}) == NoiseSpec()
        # a fitted model's to_dict() marks a measured term with NaN, the JSON with null
        measured = {"terms": {"K": {"value": 0.49, "upper_limit_95": float("nan")}}}
        assert NoiseSpec.from_any(measured) == NoiseSpec(K=0.49)


def test_noise_spec_from_fitted_noise_model() -> None:
    from fogts.allan import allan_deviation
    from fogts.allan.noise import fit_noise

    run = simulate_gyro({"N": 0.01, "K": 0.5}, fs_hz=10, duration_s=3600, rng=1)
    model = fit_noise(allan_deviation(run, taus="octave"), terms=("N", "K"))
    spec = NoiseSpec.from_any(model)
    assert spec.N == pytest.approx(0.01, rel=0.1) and spec.K == pytest.approx(0.5, rel=0.6)


@pytest.mark.parametrize("kwargs, match", [
    ({"N": -1.0}, "N .angle random walk. must be >= 0"),
    ({"B": "x"}, "B must be a number"),
    ({"K": float("inf")}, "K must be finite"),
    ({"q_c": 1.0}, "Markov term needs T_c > 0"),
    ({"Omega_0": 1.0}, "sinusoid needs f_0 > 0"),
])
def test_noise_spec_errors(kwargs: dict, match: str) -> None:
    with pytest.raises(DataError, match=match):
        NoiseSpec(**kwargs)


def test_noise_spec_from_any_errors() -> None:
    with pytest.raises(DataError, match="unknown noise term 'Z'"):
        NoiseSpec.from_any({"Z": 1.0})
    with pytest.raises(DataError, match="noise term values must be numbers"):
        NoiseSpec.from_any({"N": "abc"})
    with pytest.raises(DataError, match="noise must be a NoiseSpec"):
        NoiseSpec.from_any(42)
    with pytest.raises(DataError, match="tau_s must be finite and > 0"):
        NoiseSpec(N=1).avar([0.0])


def test_markov_avar_limits_and_series_continuity() -> None:
    q, T = 2.0, 10.0
    assert markov_avar(q, T, 1e5)[0] == pytest.approx((q * T) ** 2 / 1e5, rel=1e-3)
    assert markov_avar(q, T, 1e-3)[0] == pytest.approx(q * q * 1e-3 / 3, rel=1e-3)
    h = np.array([0.0999999, 0.1000001])  # the switch between series and exact form
    below, above = markov_avar(q, T, h)
    assert below == pytest.approx(above, rel=1e-5)


def test_a_several_axis_allan_document_says_which_axis_is_taken() -> None:
    """``fogts allan --json`` of a three-axis file has the first axis' terms at its top
    level; taking them says so (and one-axis documents stay silent)."""
    import warnings

    from fogts.errors import DataQualityWarning

    noise = {"N": {"value": 0.1}, "B": {"value": 2.0}}
    doc = {"noise": noise, "axes": [{"axis": a, "noise": noise} for a in ("gx", "gy", "gz")]}
    with pytest.warns(DataQualityWarning, match=r"^the noise terms are those of axis 'gx', the "
                                                r"first of 3 in the document \(gx, gy, gz\)"):
        spec = NoiseSpec.from_any(doc)
    assert spec.N == pytest.approx(0.1, rel=1e-15) and spec.B == pytest.approx(2.0, rel=1e-15)
    with warnings.catch_warnings():
        warnings.simplefilter("error", DataQualityWarning)
        NoiseSpec.from_any({"noise": noise, "axes": [{"axis": "gx", "noise": noise}]})
