"""Noise fits side by side (fogts.allan.noise_compare): every method's estimates and
standard errors as the fits themselves report them, terms a method does not model marked,
the error paths.  A 2 h record at 10 Hz (white + flicker + rate random walk, seed 3) keeps
the three fits to about a second."""

from __future__ import annotations

import math
import warnings

import pandas as pd
import pytest

from fogts.allan import allan_deviation
from fogts.allan.ml import fit_noise_ml
from fogts.allan.noise import NoiseModel, fit_noise
from fogts.allan.noise_compare import MethodComparison, model_label, side_by_side
from fogts.errors import DataError
from fogts.simulate.gyro import simulate_gyro


@pytest.fixture(scope="module")
def fits() -> dict[str, NoiseModel]:
    run = simulate_gyro({"N": 0.01, "B": 0.15, "K": 1.0}, fs_hz=10, duration_s=7200, rng=3)
    curve = allan_deviation(run, taus="octave")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return {"wls": fit_noise(curve), "gmwm": fit_noise(curve, method="gmwm"),
                "ml": fit_noise_ml(run.rate, 10.0, axis=curve.axis, terms="N,K",
                                   b_model="flicker")}


@pytest.fixture(scope="module")
def both(fits: dict[str, NoiseModel]) -> MethodComparison:
    return side_by_side([fits["wls"], fits["gmwm"], fits["ml"]])


def test_methods_terms_and_primary(both: MethodComparison,
                                   fits: dict[str, NoiseModel]) -> None:
    assert both.methods == ("wls", "gmwm", "ml")
    assert both.primary is fits["wls"]
    assert both.terms == ("Q", "N", "B", "K", "R")  # the union, in IEEE 952's order


def test_each_estimate_is_the_fits_own(both: MethodComparison,
                                       fits: dict[str, NoiseModel]) -> None:
    """The side-by-side values are copied from each fit, not recomputed (rel. 1e-15: a
    copy; the unit scale is 1 in degree units)."""
    for method, model in fits.items():
        for name in model.names:
            est = both.estimate(method, name)
            assert est is not None
            term = model[name]
            assert est["measured"] is (not term.is_limit) and est["status"] == term.status
            assert est["value"] == pytest.approx(term.value, rel=1e-15)
            if term.is_limit:
                assert est["upper_limit_95"] == pytest.approx(model.upper_limit(name),
                                                              rel=1e-15)
            else:
                assert est["stderr"] == pytest.approx(term.stderr, rel=1e-15)
                assert est["upper_limit_95"] is None
    assert both.estimate("ml", "Q") is None and both.estimate("ml", "B") is None


def test_to_dict_is_json_safe_and_keyed_by_term_then_method(both: MethodComparison) -> None:
    import json

    doc = both.to_dict()
    assert doc["primary"] == "wls" and doc["order"] == ["wls", "gmwm", "ml"]
    assert doc["models"]["ml"] == "N + K"
    assert set(doc["terms"]) == {"Q", "N", "B", "K", "R"}
    assert doc["terms"]["N"]["unit"] == "deg/sqrt(h)"
    assert doc["terms"]["Q"]["ml"] is None
    assert set(doc["terms"]["N"]["gmwm"]) == {"value", "stderr", "ci_low", "ci_high",
                                              "upper_limit_95", "measured", "status"}
    json.dumps(doc, allow_nan=False)  # NaN (a stderr at zero) became null
    si = both.to_dict("si")
    assert si["terms"]["N"]["unit"] != "deg/sqrt(h)"


def test_table_and_frame(both: MethodComparison, fits: dict[str, NoiseModel]) -> None:
    table = both.table()
    assert table.titles == ["term", "unit", "WLS (primary)", "GMWM", "ML"]
    rows = {r[0]: r for r in table.rows}
    assert rows["Q"][4] == "not modelled" and rows["Q"][2].startswith("< ")
    wls_n = fits["wls"]["N"]
    assert rows["N"][2] == f"{wls_n.value:.4g} ± {wls_n.stderr:.2g}"
    assert rows["model"][2:] == (model_label(fits["wls"]), model_label(fits["gmwm"]), "N + K")
    assert "side by side" in both.summary() and repr(both).startswith("<MethodComparison:")
    frame = both.to_frame()
    assert isinstance(frame.columns, pd.MultiIndex) and frame.shape == (5, 15)
    assert math.isnan(float(frame.loc["B", ("ml", "value")]))
    assert frame.loc["N", ("gmwm", "value")] == pytest.approx(fits["gmwm"]["N"].value,
                                                             rel=1e-15)


def test_model_label_of_a_least_squares_fit_lists_its_kept_terms(
        fits: dict[str, NoiseModel]) -> None:
    kept = [t.name for t in fits["wls"].terms if t.status == "fitted" and t.value > 0]
    assert model_label(fits["wls"]) == " + ".join(kept)


def test_errors(fits: dict[str, NoiseModel]) -> None:
    with pytest.raises(DataError, match=r"models must be one or more NoiseModel, got \(\)"):
        side_by_side([])
    with pytest.raises(DataError, match="models must be one or more NoiseModel, got"):
        side_by_side(["wls"])  # type: ignore[list-item]
    with pytest.raises(DataError, match=r"distinct methods; wls appears more than once in "
                                        r"wls, gmwm, wls"):
        side_by_side([fits["wls"], fits["gmwm"], fits["wls"]])
    import dataclasses

    other = dataclasses.replace(fits["gmwm"], axis="y")
    with pytest.raises(DataError, match=r"models must be fits of one axis; got \[\('rate'"):
        side_by_side([fits["wls"], other])


def test_a_gmwm_model_its_j_test_rejects_is_marked(fits: dict[str, NoiseModel]) -> None:
    """CH104 z (the audit): the GMWM column showed Q and N with small standard errors from
    a model its J test rejected (p = 4e-71), unmarked."""
    import dataclasses

    gmwm = fits["gmwm"]
    assert gmwm.gmwm is not None
    rejected = dataclasses.replace(gmwm, gmwm=dataclasses.replace(gmwm.gmwm, p_value=4e-71))
    titles = side_by_side([fits["wls"], rejected]).table().titles
    assert titles[2:] == ["WLS (primary)", "GMWM (model rejected: J test p = 4e-71)"]
    if gmwm.gmwm.consistent:
        assert side_by_side([fits["wls"], gmwm]).table().titles[3] == "GMWM"
