"""Four-position north seeking: the azimuth estimator, its error budget and bad inputs."""

from __future__ import annotations

import math

import numpy as np
import pandas as pd
import pytest

from fogts.errors import DataError, InsufficientDataError
from fogts.startup.northfind import angle_error_deg, four_position, positions_from_frame
from fogts.units import EARTH_RATE_RAD_S, earth_rate_component

LAT = 32.05


def _rates(psi: float, lat: float = LAT, bias: float = 0.7, n: int = 60,
           noise: float = 0.0, seed: int = 0) -> dict[int, np.ndarray]:
    om = EARTH_RATE_RAD_S * 180.0 / math.pi * 3600.0 * math.cos(math.radians(lat))
    rng = np.random.default_rng(seed)
    return {k: om * math.cos(math.radians(psi + k)) + bias + noise * rng.standard_normal(n)
            for k in (0, 90, 180, 270)}


@pytest.mark.parametrize("psi", [0.0, 1e-7, 359.9999999, 45.0, 89.999, 90.0, 135.0, 180.0,
                                 225.0, 270.0, 271.3, 315.0, 359.0])
def test_noiseless_azimuth_to_1e_9_deg(psi: float) -> None:
    for lat in (-60.0, 0.0, LAT, 88.9):
        res = four_position(_rates(psi, lat), latitude_deg=lat)
        assert abs(float(angle_error_deg(res.azimuth_deg, psi))) < 1e-9
        assert 0.0 <= res.azimuth_deg < 360.0
        assert res.bias_deg_h == pytest.approx(0.7, abs=1e-9)
        assert res.scale_check == pytest.approx(1.0, abs=1e-9)


def test_noise_error_matches_predicted_sigma() -> None:
    # white noise 0.5 deg/h per 1 Hz sample, 60 s per position: the predicted 1-sigma is
    # 0.5/sqrt(60)/(sqrt(2) Omega_h) rad; the RMS error over 200 trials must agree within 20 %
    errs, sigmas = [], []
    for seed in range(200):
        res = four_position(_rates(123.0, noise=0.5, seed=seed), latitude_deg=LAT)
        errs.append(float(angle_error_deg(res.azimuth_deg, 123.0)))
        sigmas.append(res.budget_deg["arw"])
    predicted = math.degrees(0.5 / math.sqrt(60) / (math.sqrt(2) * earth_rate_component(LAT, axis="north")))
    assert np.median(sigmas) == pytest.approx(predicted, rel=0.1)
    assert np.sqrt(np.mean(np.square(errs))) == pytest.approx(predicted, rel=0.2)


def test_linear_bias_drift_error_is_predicted() -> None:
    rates = _rates(40.0, n=60)
    t = np.arange(240.0)
    drift = 0.002 * t                              # deg/h per s, positions back to back
    for i, k in enumerate((0, 90, 180, 270)):
        rates[k] = rates[k] + drift[60 * i: 60 * (i + 1)]
    res = four_position(rates, latitude_deg=LAT)
    err = float(angle_error_deg(res.azimuth_deg, 40.0))
    assert res.drift_rate_deg_h_per_s == pytest.approx(0.002, rel=1e-9)
    assert res.drift_error_deg == pytest.approx(err, rel=0.02)   # first-order prediction


def test_frame_input_and_outputs() -> None:
    rates = _rates(200.0)
    df = pd.DataFrame({"position_deg": np.repeat([0, 90, 180, 270], 60),
                       "rate": np.concatenate([rates[k] for k in (0, 90, 180, 270)])})
    res = four_position(df, latitude_deg=LAT)
    assert res.azimuth_deg == pytest.approx(200.0, abs=1e-9)
    d = res.to_dict()
    assert {"azimuth_deg", "sigma_deg", "mean_rates", "positions"} <= set(d)
    assert [p["position_deg"] for p in d["positions"]] == [0, 90, 180, 270]
    assert "azimuth" in res.summary() and len(res.to_frame()) == 4
    assert positions_from_frame(df)[90].size == 60


def test_bad_input() -> None:
    rates = _rates(10.0)
    with pytest.raises(DataError, match="within 1° of the pole"):
        four_position(rates, latitude_deg=89.5)
    # audit2: the range said [-90, 90], and 90 was then refused as too near the pole
    with pytest.raises(DataError, match=r"latitude_deg must be in \[-89, 89\] \(north finding "
                                        r"needs the horizontal Earth rate\), got 95.0"):
        four_position(rates, latitude_deg=95.0)
    with pytest.raises(DataError, match="latitude_deg must be a number"):
        four_position(rates, latitude_deg="north")  # type: ignore[arg-type]
    missing = {k: v for k, v in rates.items() if k != 180}
    with pytest.raises(DataError, match="positions 180 are missing"):
        four_position(missing, latitude_deg=LAT)
    with pytest.raises(DataError, match="position 45 is not one of"):
        four_position({**rates, 45: rates[0]}, latitude_deg=LAT)
    with pytest.raises(DataError, match="is not a number of degrees"):
        four_position({**rates, "east": rates[0]}, latitude_deg=LAT)
    with pytest.raises(InsufficientDataError, match="at least 3 samples"):
        four_position({**rates, 90: rates[90][:2]}, latitude_deg=LAT)
    with pytest.raises(DataError, match="must map each position"):
        four_position([1, 2, 3], latitude_deg=LAT)  # type: ignore[arg-type]
    with pytest.raises(DataError, match="position_time_s lacks position 270"):
        four_position(rates, latitude_deg=LAT, position_time_s={0: 0, 90: 1, 180: 2})
    df = pd.DataFrame({"position_deg": [0, 90, 180, 45], "rate": [1.0, 2, 3, 4]})
    with pytest.raises(DataError, match="row 3 has 45.0"):
        positions_from_frame(df)
    with pytest.raises(DataError, match="column 'rate' not found"):
        positions_from_frame(df.rename(columns={"rate": "w"}))
