"""The start-up compensation workflow: EMD, ARMA + Kalman, thermal fit and compensation."""

from __future__ import annotations

import numpy as np
import pytest

from fogts.errors import DataError
from fogts.io.run import Run
from fogts.startup.simulator import simulate_startup
from fogts.startup.startup_workflow import startup_compensation


def test_workflow_emd_kalman_thermal_improves_bias_stability() -> None:
    sim = simulate_startup(rng=4)
    res = startup_compensation(sim.run, emd=True, arma_model="AR(2)")
    assert res.gyro_split is not None and res.kalman is not None
    assert res.gyro_split.k > 1 and res.arma_model == "AR(2)"
    np.testing.assert_allclose(np.asarray(res.gyro_split.trend) + np.asarray(res.gyro_split.rest),
                               sim.run.rate, atol=1e-10)
    # measured: 0.605 -> 0.132 deg/h (10 s average), 4.6x
    assert res.before.value >= 2.0 * res.after.value
    d = res.to_dict()
    assert d["bias_stability"]["average_s"] == 10.0 and d["emd"]["k"] == res.gyro_split.k
    assert "bias stability (10 s average" in res.summary()
    assert {"raw", "trend", "compensated", "temperature"} <= set(res.to_frame().columns)


def test_summary_of_a_trend_that_is_the_residue_only() -> None:
    # audit2: the MPU6050 record printed "EMD: 15 IMFs, trend from IMF 16" (k = n_imfs + 1
    # means no IMF is in the trend)
    import dataclasses

    res = startup_compensation(simulate_startup(duration_s=1200, rng=4).run, emd=True,
                               arma_model="AR(1)")
    assert res.gyro_split is not None
    n = res.gyro_split.n_imfs
    assert f"trend from IMF {res.gyro_split.k} (mean-energy rule)" in res.summary()
    only = dataclasses.replace(res, gyro_split=dataclasses.replace(res.gyro_split, k=n + 1))
    text = only.summary()
    assert f"EMD: {n} IMFs, trend = the residue only (the mean-energy rule puts no IMF in " \
        "it); rest modelled as AR(1)" in text
    assert f"IMF {n + 1}" not in text


def test_workflow_bad_calibration_runs() -> None:
    sim = simulate_startup(duration_s=600, rng=1)
    other = simulate_startup(duration_s=600, fs_hz=2.0, rng=2).run
    with pytest.raises(DataError, match="sampled at 2 Hz"):
        startup_compensation(sim.run, emd=False, calibration=[other])
    with pytest.raises(DataError, match=r"calibration\[0\] must be a fogts Run"):
        startup_compensation(sim.run, emd=False, calibration=["x.csv"])  # type: ignore[list-item]
    no_temp = Run(rate=sim.run.rate, time=sim.run.time, fs_hz=1.0, units="deg/h", axes=("g",))
    with pytest.raises(DataError, match="has no temperature column") as info:
        startup_compensation(no_temp)
    # read_run's keyword; the command line's --temperature-column: tests/cli/test_compensate.py
    assert str(info.value).endswith("(columns are: g); name it with temperature_column=")
    with pytest.raises(DataError, match="calibration run .* has no temperature column"):
        startup_compensation(sim.run, emd=False, calibration=[no_temp])
    deg_s = Run(rate=sim.run.rate, time=sim.run.time, fs_hz=1.0, units="deg/s", axes=("g",),
                temperature=sim.run.temperature)
    with pytest.raises(DataError, match="is in deg/s, the run in deg/h"):
        startup_compensation(sim.run, emd=False, calibration=[deg_s])
    with pytest.raises(DataError, match="model must be a ThermalModel or None"):
        startup_compensation(sim.run, model={"T": 1.0})  # type: ignore[arg-type]
    with pytest.raises(DataError, match="run must be a fogts Run"):
        startup_compensation(sim.run.rate)  # type: ignore[arg-type]


def test_bad_averaging_and_smoothing_are_refused_before_the_fit() -> None:
    import warnings

    sim = simulate_startup(duration_s=600, rng=1)
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # nothing is fitted, so nothing warns
        with pytest.raises(DataError, match=r"average_s must be a finite number > 0, got -1"):
            startup_compensation(sim.run, average_s=-1)
        with pytest.raises(DataError, match=r"dT_smoothing_s must be a finite number > 0, "
                                            r"got 0"):
            startup_compensation(sim.run, dT_smoothing_s=0)


def test_mpu6050_not_white_warnings_name_gyro_and_temperature() -> None:
    """Audit N6: on the MPU6050 recording neither EMD rest (gyro nor temperature) is
    whitened by a low-order ARMA model; each warning names its series (the bare warning
    did not say that one of them was about the temperature)."""
    import warnings

    import fogts
    from fogts.errors import NotWhiteWarning
    from tests.conftest import shared_path

    path = shared_path("imu", "mpu6050_gyro_temp_converted.csv.gz")
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        startup_compensation(fogts.read_run(path, units="deg/s"))
    texts = [str(w.message) for w in caught if issubclass(w.category, NotWhiteWarning)]
    assert any(t.startswith("ARMA model of the temperature's EMD rest: no candidate")
               for t in texts), texts
    assert all(t.startswith("ARMA model of the ") for t in texts), texts


def test_a_given_measurement_noise_is_the_gyros_only() -> None:
    """``measurement_noise`` is a variance in (rate unit)^2: it sets the gyro rate's Kalman H;
    the temperature's H is estimated whatever it is (a rate variance is meaningless in °C^2)."""
    import dataclasses

    from fogts.startup.startup_workflow import _prepare_fit_run

    sim = simulate_startup(duration_s=1800, rng=4).run
    noisy = np.asarray(sim.temperature) + np.random.default_rng(1).normal(0.0, 0.05, sim.n)
    run = dataclasses.replace(sim, temperature=noisy)  # a temperature rest the Kalman filters
    prep = {h: _prepare_fit_run(run, 0, emd=True, arma_model="AR(1)", measurement_noise=h)
            for h in ("estimate", 10.0)}
    assert prep[10.0].temp_split is not None and prep[10.0].temp_split.k > 1
    np.testing.assert_array_equal(prep[10.0].temp, prep["estimate"].temp)
    assert prep[10.0].kalman is not None and prep[10.0].kalman.measurement_noise == 10.0
    assert prep[10.0].kalman.measurement_noise_source == "given"
    assert not np.array_equal(prep[10.0].gyro, prep["estimate"].gyro)
