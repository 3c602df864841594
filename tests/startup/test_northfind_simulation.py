"""North seeking during simulated cold starts, with and without thermal compensation."""

from __future__ import annotations

import pytest

from fogts.errors import DataError, InsufficientDataError
from fogts.startup.northfind_simulation import simulate_north_seeking, simulated_calibration
from fogts.startup.simulator import simulate_startup
from fogts.startup.thermal_fit import fit_thermal


def test_compensation_reduces_cold_start_error() -> None:
    cal = simulate_startup(rng=7)
    model = fit_thermal(cal.run.rate, cal.run.temperature, fs_hz=1.0)
    study = simulate_north_seeking(40, model=model, rng=8)
    raw = study.to_dict()["raw"]["rms_deg"]
    comp = study.to_dict()["compensated"]["rms_deg"]
    # measured: raw RMS ~1.3 deg, compensated ~0.6 deg
    assert raw > 0.8 and study.improvement > 1.5
    assert comp < raw
    assert "RMS error reduced" in study.summary()
    assert len(study.to_frame()) == 40


def test_simulation_bad_input() -> None:
    with pytest.raises(DataError, match="model must be a ThermalModel"):
        simulate_north_seeking(3, model="m.json")
    with pytest.raises(DataError, match="ambient_degC must be"):
        simulate_north_seeking(3, ambient_degC=(30.0, 20.0))
    with pytest.raises(InsufficientDataError, match="samples per position"):
        simulate_north_seeking(3, position_s=1.0)


def test_chamber_calibration_reduces_cold_start_error_several_fold() -> None:
    model = simulated_calibration((15.0, 20.0, 25.0), rng=1_000_007)
    study = simulate_north_seeking(50, model=model, rng=4)
    d = study.to_dict()
    # measured: raw RMS 1.31 deg -> 0.27 deg (4.8x)
    assert 1.0 < d["raw"]["rms_deg"] < 1.8
    assert d["compensated"]["rms_deg"] < 0.45 and study.improvement > 3.0
    with pytest.raises(DataError, match="at least one calibration temperature"):
        simulated_calibration(())
