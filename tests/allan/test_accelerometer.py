"""Accelerometer axes end to end: a 6-axis IMU CSV (gyro + accelerometer columns) written
here from a simulation with known terms gives six rows in ``fogts allan``, the
accelerometer's terms in m/s/sqrt(h) and ug within their intervals of the truth, and
Kalibr's accelerometer pair in the export.

The accelerometer record is drawn with :func:`fogts.simulate_gyro` in deg/h and read as
m/s^2: the Allan variance only sees numbers and seconds, so a gyro spec with N = n/60
(deg/sqrt(h) -> deg/h sqrt(s), :data:`fogts.allan.terms.TO_SECONDS`), B = b and K = 60 k is a
specific force with C-coefficients n (m/s/sqrt(s)), b (m/s^2) and k (m/s^2/sqrt(s)), i.e.
VRW = 60 n m/s/sqrt(h), B = b / 9.80665e-6 ug and K = 60^3 k m/s/h^1.5.
"""

from __future__ import annotations

import json
import warnings
from pathlib import Path

import numpy as np
import pandas as pd
import pytest
import yaml
from typer.testing import CliRunner

import fogts
from fogts.cli import app
from fogts.units import STANDARD_GRAVITY_MPS2

FS = 10.0
DURATION_S = 4 * 3600
#: Accelerometer truth in m/s^2-and-seconds units: white 1e-3 m/s/sqrt(s) (0.06 m/s/sqrt(h)),
#: flicker floor b = 2e-4 m/s^2 (20.4 ug), random walk 5e-6 m/s^2/sqrt(s).
ACC_SECONDS = {"N": 1e-3, "B": 2e-4, "K": 5e-6}
ACC_TRUTH = {"N": 60 * 1e-3, "B": 2e-4 / (STANDARD_GRAVITY_MPS2 * 1e-6), "K": 60**3 * 5e-6}
GYRO_TRUTH = {"N": 0.05, "B": 1.0, "K": 0.5}   # deg/sqrt(h), deg/h, deg/h^1.5; written in deg/s
LEVEL = 0.95

runner = CliRunner()


def _write_imu_csv(path: Path) -> None:
    acc_spec = {"N": ACC_SECONDS["N"] / 60, "B": ACC_SECONDS["B"], "K": 60 * ACC_SECONDS["K"]}
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        gyro = fogts.simulate_gyro([GYRO_TRUTH] * 3, fs_hz=FS, duration_s=DURATION_S,
                                   rng=11, units="deg/s")
        acc = fogts.simulate_gyro([acc_spec] * 3, fs_hz=FS, duration_s=DURATION_S, rng=12)
    frame = pd.DataFrame({"time_s": gyro.time})
    for i, c in enumerate("xyz"):
        frame[f"gyro_{c}_deg_s"] = gyro.rate[:, i]
    for i, c in enumerate("xyz"):
        frame[f"acc_{c}_mps2"] = acc.rate[:, i] + (STANDARD_GRAVITY_MPS2 if c == "z" else 0.0)
    frame.to_csv(path, index=False, float_format="%.10e")


@pytest.fixture(scope="module")
def imu_json(tmp_path_factory: pytest.TempPathFactory) -> dict:
    folder = tmp_path_factory.mktemp("imu")
    csv = folder / "imu6.csv"
    _write_imu_csv(csv)
    out = folder / "a.json"
    result = runner.invoke(app, ["allan", str(csv), "--confidence", str(LEVEL), "--json",
                                 str(out), "--export", "kalibr", str(folder / "imu.yaml")])
    assert result.exit_code == 0, result.output
    doc = json.loads(out.read_text())
    doc["_kalibr"] = yaml.safe_load((folder / "imu.yaml").read_text())
    return doc


def test_six_axes_with_their_units(imu_json: dict) -> None:
    axes = imu_json["axes"]
    assert [a["axis"] for a in axes] == [f"gyro_{c}_deg_s" for c in "xyz"] + \
        [f"acc_{c}_mps2" for c in "xyz"]
    assert [a["units"] for a in axes] == ["deg/s"] * 3 + ["m/s^2"] * 3
    for a in axes[3:]:
        assert {n: a["noise"][n]["unit"] for n in "NBK"} == \
            {"N": "m/s/sqrt(h)", "B": "ug", "K": "m/s/h^1.5"}
        assert a["noise_si"]["N"]["unit"] == "m/s^2/sqrt(Hz)"


@pytest.mark.parametrize("axis", range(6))
def test_terms_lie_within_their_intervals_of_the_truth(imu_json: dict, axis: int) -> None:
    """Each of N, B, K on each axis: the simulated value inside the fit's 95 % interval."""
    block = imu_json["axes"][axis]
    truth = GYRO_TRUTH if axis < 3 else ACC_TRUTH
    for name, value in truth.items():
        term = block["noise"][name]
        assert term["ci_low"] <= value <= term["ci_high"], (block["axis"], name, term, value)


def _exported(term: dict) -> float:
    """The value a filter gets: the fit, or the 95 % upper limit of a term not measured."""
    limit = term["upper_limit_95"]
    return term["value"] if limit is None or not np.isfinite(limit) else limit


def test_kalibr_accelerometer_pair_is_the_largest_accelerometer_axis(imu_json: dict) -> None:
    kalibr = imu_json["_kalibr"]
    acc = imu_json["axes"][3:]
    assert kalibr["accelerometer_noise_density"] == pytest.approx(
        max(_exported(a["noise_si"]["N"]) for a in acc), rel=1e-12)
    # N in SI is the white-noise level in m/s^2/sqrt(Hz) = m/s/sqrt(s): the truth is 1e-3
    assert kalibr["accelerometer_noise_density"] == pytest.approx(ACC_SECONDS["N"], rel=0.05)
    assert kalibr["accelerometer_random_walk"] == pytest.approx(
        max(_exported(a["noise_si"]["K"]) for a in acc), rel=1e-12)
    assert kalibr["gyroscope_noise_density"] == pytest.approx(
        max(_exported(a["noise_si"]["N"]) for a in imu_json["axes"][:3]), rel=1e-12)


def test_ch104_gives_its_accelerometer_axes_in_g() -> None:
    from tests.conftest import shared_path

    path = shared_path("imu", "ch104.mat")
    result = runner.invoke(app, ["allan", str(path), "--fs", "100", "--units", "deg/s",
                                 "--json", "-"])
    assert result.exit_code == 0, result.output
    doc = json.loads(result.stdout)
    axes = doc["axes"]
    assert len(axes) == 6
    assert [a["units"] for a in axes[3:]] == ["g"] * 3
    for a in axes[3:]:
        n = a["noise"]["N"]
        assert n["unit"] == "m/s/sqrt(h)" and np.isfinite(n["value"]) and n["value"] > 0


@pytest.mark.parametrize("axis", "xyz")
def test_imu_utils_published_accelerometer_curve_gives_its_acc_n(axis: str) -> None:
    """imu_utils' own fitted accelerometer model curve (16448 IMU, ``data_16448_sim_acc_*``)
    refitted here gives N in m/s^2/sqrt(Hz) close to the ``acc_n`` imu_utils printed.

    Measured: 1.736e-3 / 1.887e-3 (x), 2.063e-3 / 2.313e-3 (y), 1.638e-3 / 1.758e-3 (z), i.e.
    8 to 11 % low.  imu_utils defines its parameters its own way (the data README says so)
    and the curve has no EDF (a flat 100 is used), so agreement is asked to 15 %: what the
    test guards is the unit, where a slip would be a factor 60 (per hour against per second)
    or 9.81 (g against m/s^2).
    """
    from types import SimpleNamespace

    from tests.conftest import shared_path

    folder = shared_path("allan_curves", "imu_utils")
    tau = np.loadtxt(folder / "data_16448_acc_t.txt")
    dev = np.loadtxt(folder / f"data_16448_sim_acc_{axis}.txt")
    published = yaml.safe_load(
        (folder / "16448_imu_param.yaml").read_text().split("---", 1)[1])["Acc"]
    curve = SimpleNamespace(kind="oadev", units="m/s^2", axis=axis, tau_s=tau, dev=dev,
                            edf=np.full(tau.size, 100.0))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        model = fogts.fit_noise(curve, terms="N,B,K")
    assert model.quantity == "accel"
    n_si = model.in_units("N", "si")
    assert n_si["unit"] == "m/s^2/sqrt(Hz)"
    assert n_si["value"] == pytest.approx(published[f"{axis}-axis"]["acc_n"], rel=0.15)
