"""Which terms are *measured* does not depend on the tau grid: a fitted term with z < 2 is
reported as an upper limit (NoiseTerm.is_limit), never as a value or a drawn line; so is a
term that dominates the fitted sigma^2 only at points with EDF < 10 (NoiseTerm.low_edf_taus),
whatever its z, while a term that is present and dominates at trusted points stays measured."""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest

import fogts
from fogts.allan.noise_model import Z_MEASURED
from fogts.allan.noise_term import NoiseTerm
from fogts.allan.readout import MIN_EDF_FOR_MINIMUM
from fogts.errors import UnidentifiableTermWarning
from tests.allan.noise_cases import avar, make_result, quiet_fit
from tests.conftest import shared_path

GRIDS = ("octave", "decade", "dense")


def _measured(res: fogts.AllanResult) -> set[str]:
    with pytest.warns(fogts.errors.FogtsWarning):
        model = fogts.fit_noise(res)
    return {t.name for t in model.terms if not t.is_limit}


def test_adis16405_y_measures_the_same_terms_on_every_grid() -> None:
    """The issue's case: the dense grid kept R = 65.6 +- 123 (z = 0.27) as a fitted value."""
    run = fogts.read_run(shared_path("imu", "adis_16405_imu1_gyro.npz"), units="deg/s")
    sets = [_measured(fogts.allan_deviation(run, axis="Gyro. Y", taus=g)) for g in GRIDS]
    assert sets[0] == sets[1] == sets[2] == {"N", "B"}


def test_a_simulated_white_plus_rrw_record_measures_n_and_k_on_every_grid() -> None:
    sim = fogts.simulate_gyro({"N": 0.01, "K": 1.0}, fs_hz=100, duration_s=3 * 3600, rng=1)
    sets = [_measured(fogts.allan_deviation(sim, taus=g)) for g in GRIDS]
    assert sets[0] == sets[1] == sets[2] == {"N", "K"}


def test_a_weak_term_is_a_limit_with_a_one_sided_bound() -> None:
    run = fogts.read_run(shared_path("imu", "adis_16405_imu1_gyro.npz"), units="deg/s")
    with pytest.warns(fogts.errors.FogtsWarning):
        model = fogts.fit_noise(fogts.allan_deviation(run, axis="Gyro. Y", taus="dense"))
    r = model["R"]
    assert r.status == "fitted" and r.value > 0 and r.z_score < Z_MEASURED and r.is_limit
    expected = math.sqrt(r.value**2 + 2 * 1.6448536269514722 * r.value * r.stderr)
    assert model.upper_limit("R") == pytest.approx(expected, rel=1e-9)
    assert f"z(C²) = {r.z_score:.2f} < 2" in model.term_table().to_text()


# --------------------------------------------------------------- terms seen only at low EDF

#: An MPU6050-like curve (N = 0.55 deg/sqrt(h), R = 265 deg/h^2) on 15 octave taus from
#: 0.01 s: R's line is the largest only at the last two taus, 82 and 164 s.
TAU = 0.01 * 2.0 ** np.arange(15)
EXACT = np.sqrt(avar(TAU, N=0.55, R=265.0))
LOW_EDF = np.r_[50_000.0 / 2.0 ** np.arange(13), 7.5, 3.0]  # ..., 24.4, 12.2, 7.5, 3.0


def test_a_term_dominant_only_at_low_edf_points_is_an_upper_limit() -> None:
    """Exact curve, so R's z is large; it is still a limit, said in the note and the JSON."""
    with pytest.warns(UnidentifiableTermWarning, match=r"noise term R \(rate ramp, slope \+1\) "
                      r"dominates the fitted sigma\^2 only at tau 81.92, 163.8 s, where the "
                      r"points have EDF < 10 \(7.5, 3\): too few degrees of freedom to measure it; "
                      r"treat its value as an upper limit"):
        model = fogts.fit_noise(make_result(TAU, EXACT, edf=LOW_EDF))
    r = model["R"]
    assert r.status == "fitted" and r.z_score >= Z_MEASURED and r.is_limit
    assert r.low_edf_taus == pytest.approx((81.92, 163.84))
    assert r.value == pytest.approx(265.0, rel=1e-3)
    assert r.limit_reason == ("R dominates only at tau 81.92 .. 163.8 s, where the points have "
                              "EDF < 10")
    limit = model.upper_limit("R")
    assert limit == pytest.approx(math.sqrt(r.value**2 + 2 * 1.6448536269514722 * r.value
                                            * r.stderr), rel=1e-9)
    text = model.term_table().to_text()
    assert f"< {limit:.3g} (95 % upper limit; R dominates only at tau" in " ".join(text.split())
    assert "R: only a limit whatever its z" in " ".join(text.split())
    d = model.to_dict()["terms"]["R"]
    assert d["measured"] is False and d["status"] == "fitted"
    assert d["limit_reason"] == r.limit_reason and d["upper_limit_95"] == pytest.approx(limit)
    assert model.to_dict()["terms"]["N"]["measured"] is True
    assert model.to_dict()["terms"]["N"]["limit_reason"] is None
    assert "R < " in model._view_headline()
    readout = make_result(TAU, EXACT, edf=LOW_EDF).readout(model)
    assert [(d.term, d.measured) for d in readout.dominant] == [("N", True), ("R", False)]


def test_the_same_term_at_trusted_points_is_measured() -> None:
    """The same curve with EDF >= 10 at the taus where R dominates: R is measured."""
    edf = np.maximum(LOW_EDF, MIN_EDF_FOR_MINIMUM)
    model = quiet_fit(make_result(TAU, EXACT, edf=edf))
    r = model["R"]
    assert not r.is_limit and r.low_edf_taus == () and r.limit_reason == ""
    assert r.value == pytest.approx(265.0, rel=1e-3)
    assert model.to_dict()["terms"]["R"]["measured"] is True


def test_a_simulated_rrw_that_is_present_and_well_measured_stays_measured() -> None:
    """Known truth (N = 0.01 deg/sqrt(h), K = 1 deg/h^1.5, 3 h at 10 Hz, seed 7): K dominates
    from about a minute on, at trusted points and at the low-EDF points of the longest taus;
    it stays measured, near its true value."""
    sim = fogts.simulate_gyro({"N": 0.01, "K": 1.0}, fs_hz=10, duration_s=3 * 3600, rng=7)
    res = fogts.allan_deviation(sim)
    model = quiet_fit(res)
    k = model["K"]
    assert not k.is_limit and k.low_edf_taus == () and k.status == "fitted"
    assert abs(k.value - 1.0) < 3 * k.stderr and abs(k.value - 1.0) < 0.3
    dominant = [d for d in res.readout(model).dominant if d.term == "K"]
    assert len(dominant) == 1 and dominant[0].measured
    taus = (res.tau_s >= dominant[0].tau_from_s) & (res.tau_s <= dominant[0].tau_to_s)
    assert np.any(res.edf[taus] >= MIN_EDF_FOR_MINIMUM) and np.any(res.edf[taus] < 10)


# --------------------------------------------------------------- terms not identifiable

def test_a_fitted_term_that_is_not_identifiable_is_a_limit() -> None:
    """audit3: GMWM on the first 60 s of ADIS run 1 (X) fits R = 3.61 +- 0.71 deg/h^2
    (z = 2.5) where R reaches 25 % of sigma^2 at no data tau; the warning said 'not
    identifiable ... treat its value as an upper limit' while the table printed the value
    and the JSON said measured: true.  Since B no longer counts the Gauss-Markov term at
    T_c = 0.01 s (one sample period, white noise: fogts.allan.gmwm), B no longer hides R's
    share: R dominates at 20.48 s, a point with EDF 2.5, and is a limit by that rule; the
    not-identifiable rule is pinned on a constructed term."""
    weak = dataclasses.replace(NoiseTerm(
        name="R", value=3.6, stderr=0.7, ci_low=2.9, ci_high=4.4, unit="deg/h^2",
        c_coeff=1e-3, c_stderr=2e-4, c_unit="deg/h^2", power=2, at_bound=False,
        identifiable=True, n_covered=0, region_tau_s=(math.nan, math.nan), z_score=2.5),
        identifiable=False)
    assert weak.is_limit and "not identifiable" in weak.limit_reason
    run = fogts.read_run(shared_path("imu", "adis_16405_imu1_gyro.npz"), units="deg/s")
    x = run.rate[:6000, 0]
    res = fogts.allan_deviation(np.asarray(x), fs_hz=100.0)
    with pytest.warns(UnidentifiableTermWarning,
                      match="R .*(not identifiable|EDF <).*upper limit"):
        model = fogts.fit_noise(res, method="gmwm")
    r = model["R"]
    assert r.status == "fitted" and r.z_score >= Z_MEASURED
    assert r.is_limit and ("not identifiable" in r.limit_reason or "EDF <" in r.limit_reason)
    assert model.noise_dict()["R"]["measured"] is False
    assert model.upper_limit("R") > r.value
    row = next(line for line in model.term_table().to_text().splitlines() if "rate ramp" in line)
    assert "< " in row
