"""Filter-ready exports (Kalibr, imu_utils, JSON) and SI output units.

Truth comes from simulation in SI: white rate noise of density N_si (rad/s/sqrt(Hz)) sampled
at fs has a per-sample standard deviation N_si sqrt(fs), and a rate random walk of K_si
(rad/s^2/sqrt(Hz)) has increments of standard deviation K_si / sqrt(fs) (IEEE Std 952-1997
Annex C; Kalibr wiki "IMU Noise Model").  The fit runs on rad/s input and reports deg-based
terms, so agreement with the SI truth checks the conversion factors end to end.
"""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pytest
import yaml

from fogts.errors import DataError
from fogts.io.run import Run
from fogts.pipeline import AllanAnalysis, AllanSettings, analyse_allan
from fogts.preprocess.hygiene import assess_run
from fogts.report.export import export_noise, exported_terms, noise_export_text
from fogts.units import TERM_SI_FACTOR

# The simulated records do not identify Q, B and R: their warnings are expected here.
pytestmark = pytest.mark.filterwarnings("ignore::fogts.errors.UnidentifiableTermWarning")

FS = 100.0
N_SI = (3e-4, 4e-4, 5e-4)     # rad/s/sqrt(Hz), one per axis
K_SI = (2e-5, 3e-5, 4e-5)     # rad/s^2/sqrt(Hz)


def _imu_run(n: int = 400_000, seed: int = 20261124) -> Run:
    rng = np.random.default_rng(seed)
    cols = [n_si * math.sqrt(FS) * rng.standard_normal(n)
            + np.cumsum(k_si / math.sqrt(FS) * rng.standard_normal(n))
            for n_si, k_si in zip(N_SI, K_SI, strict=True)]
    return Run(rate=np.column_stack(cols), time=np.arange(n) / FS, fs_hz=FS, units="rad/s",
               axes=("gx", "gy", "gz"), columns=("time", "gx", "gy", "gz"), source="imu.csv")


@pytest.fixture(scope="module")
def analysis() -> AllanAnalysis:
    run, quality = assess_run(_imu_run())
    return analyse_allan(run, quality, AllanSettings())


def test_si_terms_recover_the_si_truth_within_their_intervals(analysis: AllanAnalysis) -> None:
    # 400,000 samples: N is measured to ~1 %, K to ~15-30 %; allow 3 standard errors.
    for ax, n_si, k_si in zip(analysis.axes, N_SI, K_SI, strict=True):
        model = ax.model
        assert model is not None
        for name, truth in (("N", n_si), ("K", k_si)):
            si = model.in_units(name, "si")
            assert not model[name].is_limit
            assert abs(si["value"] - truth) < 3 * si["stderr"], (ax.result.axis, name, si)


def test_si_values_are_the_degree_values_times_the_documented_factors(
        analysis: AllanAnalysis) -> None:
    model = analysis.axes[0].model
    assert model is not None
    frame_deg, frame_si = model.to_frame(), model.to_frame(units="si")
    for name in model.names:
        for col in ("value", "stderr", "ci_low", "ci_high"):
            assert frame_si.loc[name, col] == pytest.approx(
                frame_deg.loc[name, col] * TERM_SI_FACTOR[name], rel=1e-12, abs=0.0, nan_ok=True)
    assert frame_si.loc["N", "unit"] == "rad/s/sqrt(Hz)"
    assert frame_si.loc["K", "unit"] == "rad/s^2/sqrt(Hz)"
    assert model.to_dict(units="si")["output_units"] == "si"
    assert "rad/s^2/sqrt(Hz)" in model.term_table("si").to_text()


def test_kalibr_yaml_reads_back_as_the_largest_axis(analysis: AllanAnalysis,
                                                    tmp_path: Path) -> None:
    path = export_noise(analysis, "kalibr", tmp_path / "imu.yaml")
    doc = yaml.safe_load(path.read_text())
    per_axis = [exported_terms(ax) for ax in analysis.axes]
    assert doc["update_rate"] == pytest.approx(FS, rel=1e-15)
    assert doc["gyroscope_noise_density"] == pytest.approx(
        max(t["N"].value_si for t in per_axis), rel=1e-12)
    assert doc["gyroscope_random_walk"] == pytest.approx(
        max(t["K"].value_si for t in per_axis), rel=1e-12)
    assert "accelerometer_noise_density" not in doc
    assert "# accelerometer_noise_density and accelerometer_random_walk are not written" \
        in path.read_text()


def test_imu_utils_file_has_every_axis_and_their_mean(analysis: AllanAnalysis) -> None:
    text = noise_export_text(analysis, "imu_utils")
    assert text.startswith("%YAML:1.0\n---\n")   # OpenCV FileStorage's header
    doc = yaml.safe_load(text.split("\n", 1)[1])  # PyYAML does not read OpenCV's directive
    gyr = doc["Gyr"]
    values = [exported_terms(ax) for ax in analysis.axes]
    for key, terms in zip(("x-axis", "y-axis", "z-axis"), values, strict=True):
        assert gyr[key]["gyr_n"] == pytest.approx(terms["N"].value_si, rel=1e-12)
        assert gyr[key]["gyr_w"] == pytest.approx(terms["K"].value_si, rel=1e-12)
    assert gyr["avg-axis"]["gyr_n"] == pytest.approx(
        np.mean([t["N"].value_si for t in values]), rel=1e-12)


def test_json_export_marks_limits(analysis: AllanAnalysis) -> None:
    doc = json.loads(noise_export_text(analysis, "json"))
    assert doc["format"] == "fogts-imu-noise"
    assert set(doc["axes"]) == {"gx", "gy", "gz"}
    assert doc["axes"]["gx"]["N"]["unit"] == "rad/s/sqrt(Hz)"
    assert doc["axes"]["gx"]["N"]["upper_limit"] is False


def test_a_term_at_zero_is_exported_as_its_upper_limit_and_marked() -> None:
    rng = np.random.default_rng(5)
    x = 4e-4 * math.sqrt(FS) * rng.standard_normal(200_000)   # white only: K not measured
    run = Run(rate=x, time=np.arange(x.size) / FS, fs_hz=FS, units="rad/s", axes=("gx",),
              columns=("time", "gx"), source="white.csv")
    run, quality = assess_run(run)
    analysis = analyse_allan(run, quality, AllanSettings())
    model = analysis.axes[0].model
    assert model is not None and model["K"].is_limit
    k = exported_terms(analysis.axes[0])["K"]
    assert k.is_limit
    assert k.value_si == pytest.approx(model.upper_limit("K") * TERM_SI_FACTOR["K"], rel=1e-12)
    assert k.value_si > 0
    text = noise_export_text(analysis, "kalibr")
    line = next(li for li in text.splitlines() if li.startswith("gyroscope_random_walk"))
    assert line.endswith("# gx, 95 % upper limit, not measured")


def test_export_errors_name_what_is_missing(analysis: AllanAnalysis) -> None:
    with pytest.raises(DataError, match="export format must be one of kalibr, imu_utils, "
                                        "json; got 'ros'"):
        noise_export_text(analysis, "ros")  # type: ignore[arg-type]
    run, quality = analysis.run, analysis.quality
    no_k = analyse_allan(run, quality, AllanSettings(terms=("Q", "N", "B")), axes=[0])
    with pytest.raises(DataError, match=r"K was not fitted \(terms= must include N and K\)$"):
        noise_export_text(no_k, "kalibr")
    mdev = analyse_allan(run, quality, AllanSettings(kind="mdev"), axes=[0])
    with pytest.raises(DataError, match=r"the export needs the noise terms, and gx has none "
                                        r"\(fitted to kind= adev, oadev or totdev only\)$"):
        noise_export_text(mdev, "kalibr")
