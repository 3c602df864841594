"""Which terms are *measured* does not depend on the tau grid: a fitted term with z < 2 is
reported as an upper limit (NoiseTerm.is_limit), never as a value or a drawn line."""

from __future__ import annotations

import math

import pytest

import fogts
from fogts.allan.noise_model import Z_MEASURED
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
