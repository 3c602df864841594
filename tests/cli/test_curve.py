"""``fogts curve``: the noise terms of published Allan curves (SMAC-Group/avar, Stable32, a
``fogts allan --csv`` table), against the reference helper, the recording behind a curve
and a round trip; the JSON keys, notes, warnings and every refusal."""

from __future__ import annotations

import json
import math
import re
import warnings
from pathlib import Path

import numpy as np
import pytest
from typer.testing import CliRunner

from fogts.cli import app
from tests.allan.noise_cases import quiet_fit, smac_result
from tests.cli.conftest import FS
from tests.conftest import error_output, shared_path

runner = CliRunner()
TERMS = ("Q", "N", "B", "K", "R")


def _run(args: list[object], command: str = "curve") -> tuple[int, str, str]:
    res = runner.invoke(app, [command, *[str(a) for a in args]])
    return res.exit_code, res.stdout, res.stderr


def _json(args: list[object], tmp_path: Path) -> dict:
    out = tmp_path / f"c{len(list(tmp_path.glob('c*.json')))}.json"
    code, _, err = _run([*args, "--json", out])
    assert code == 0, err
    return json.loads(out.read_text())


def _smac(sensor: str) -> Path:
    return shared_path("allan_curves", "smac_avar", f"{sensor}_av.csv")


@pytest.mark.parametrize(("sensor", "units"), [("kvh1750", "deg/s"), ("ln200", "rad/s"),
                                               ("imar", "rad/s")])
def test_smac_fog_curves_equal_the_reference_fit(sensor: str, units: str,
                                                 tmp_path: Path) -> None:
    """Gyro X of the three FOGs: the terms through the command equal fit_noise on
    ``smac_result`` (same inputs; 1e-12 relative; ``test_noise.test_published_fog_curves``
    checks those fits against the sensors' published values)."""
    doc = _json([_smac(sensor), "--units", units, "--channel", "Gyro. X"], tmp_path)
    ref = quiet_fit(smac_result(sensor, units, "Gyro. X"))
    for t in TERMS:
        assert doc["noise"][t]["value"] == pytest.approx(ref[t].value, rel=1e-12, abs=0)
        if math.isfinite(ref[t].stderr):
            assert doc["noise"][t]["stderr"] == pytest.approx(ref[t].stderr, rel=1e-12)
    assert doc["input"]["fs_source"] == "file" and doc["input"]["n_samples_source"] == "file"
    assert doc["input"]["weights"].startswith("the errors column")


def test_json_keys_are_an_allan_axis_block_plus_the_input(tmp_path: Path) -> None:
    doc = _json([_smac("ln200"), "--units", "rad/s", "--channel", "Gyro. Y"], tmp_path)
    assert {"input", "axes", "kind", "units", "points", "noise", "noise_si", "curve",
            "noise_fit", "fit_check", "plausibility"} <= set(doc)
    assert doc["axes"][0]["axis"] == "Gyro. Y" and len(doc["axes"]) == 1
    assert set(doc["input"]) >= {"source", "format", "channels", "kind", "units",
                                 "units_source", "fs_hz", "fs_source", "n_samples",
                                 "n_samples_source", "weights", "confidence", "notes"}
    assert set(doc["points"][0]) >= {"tau", "m", "n", "dev", "ci_low", "ci_high", "edf"}
    every = _json([_smac("ln200"), "--units", "rad/s"], tmp_path)
    assert [b["axis"] for b in every["axes"]] == ["Gyro. X", "Gyro. Y", "Gyro. Z"]
    assert "noise" not in every   # several channels: the blocks are under "axes" only
    assert any("left out the channels Accel. X" in n for n in every["input"]["notes"])


def test_adis_curve_agrees_with_its_recording(tmp_path: Path) -> None:
    """ADIS16405 run 1: SMAC's curve and ``fogts allan`` on the recording at the curve's
    taus agree to ~6e-6 (data README), so N and B differ only through the weights (the
    errors column's IEEE 952 N/m - 1 against Greenhall's EDF with the identified alpha):
    within a quarter of a standard error (found: N 0.02, B 0.12 SE).  On fogts' own octave
    grid (with tau = 0.01 s) N moves by about one SE, B by 0.3: still within two combined
    SEs, as two fits of the same record must be."""
    taus = ",".join(repr(2.0**j / 100) for j in range(1, 19))
    rec_json = tmp_path / "rec.json"
    code, _, err = _run([shared_path("imu", "adis_16405_imu1_gyro.npz"), "--axis", "0",
                         "--taus", taus, "--json", rec_json], command="allan")
    assert code == 0, err
    rec = json.loads(rec_json.read_text())["axes"][0]
    curve = _json([_smac("adis"), "--units", "deg/s", "--channel", "Gyro. X"], tmp_path)
    np.testing.assert_allclose([p["dev"] for p in curve["points"]],
                               [p["dev"] for p in rec["points"]], rtol=1e-5)
    for t in ("N", "B"):
        a, b = rec["noise"][t], curve["noise"][t]
        assert abs(a["value"] - b["value"]) < 0.25 * max(a["stderr"], b["stderr"]), t


def test_fogts_allan_csv_round_trip(gyro_npy: Path, tmp_path: Path) -> None:
    """``fogts allan --csv`` written, read back: fs from m/tau, N from the number of terms,
    the EDF column: the same terms as ``fogts allan`` (1e-9: the same points and weights,
    through a text file that may round a last digit)."""
    out_csv, out_json = tmp_path / "a.csv", tmp_path / "a.json"
    code, _, err = _run([gyro_npy, "--fs", FS, "--units", "deg/h", "--csv", out_csv,
                         "--json", out_json], command="allan")
    assert code == 0, err
    rec = json.loads(out_json.read_text())["axes"][0]
    doc = _json([out_csv, "--units", "deg/h"], tmp_path)
    assert doc["input"]["fs_hz"] == pytest.approx(FS, rel=1e-12)
    assert doc["input"]["n_samples"] == rec["points"][0]["n"] + 2 * rec["points"][0]["m"] - 1
    assert doc["input"]["weights"] == "the edf column"
    for t in ("N", "K"):
        assert doc["noise"][t]["value"] == pytest.approx(rec["noise"][t]["value"], rel=1e-9)


def test_stable32_file(tmp_path: Path) -> None:
    path = shared_path("stable32", "phasedat", "phase_dat_oadev_octave.txt")
    code, out, err = _run([path, "--units", "deg/h"])
    assert code == 0, err
    assert "fs = 1 Hz (file), n = 1,000 samples (file); weights: Greenhall-Riley EDF of " \
           "oadev from the file's alpha" in out
    assert "oadev of phase_dat_oadev_octave (deg/h), 68.3 % CI" in out


def test_inferred_fs_is_printed_and_gmwm_ml_refused(tmp_path: Path) -> None:
    path = tmp_path / "d.csv"
    rows = "".join(f"{t!r},{0.1 / math.sqrt(t)!r},{2e5 / t!r}\n"
                   for t in (0.1 * 2.0**np.arange(12)).tolist())
    path.write_text("tau,adev_deg_h,edf\n" + rows)
    code, out, err = _run([path, "--terms", "N,B,K"])
    assert code == 0, err
    assert "note: the sample rate is not stated: the shortest tau, 0.1 s, taken as the " \
           "sample interval (fs = 10 Hz); give --fs if the record was sampled faster" in out
    assert "(inferred)" in out and "(estimated)" in out
    for method, match in (("ml", "error: method 'ml' fits the recording itself"),
                          ("wls,gmwm", "error: method 'gmwm' needs the record length")):
        code, _, err = _run([path, "--method", method])
        assert code == 2 and error_output(err).startswith(match)
    code, out, err = _run([path, "--method", "wls,gmwm", "--n-samples", 2_000_000,
                           "--fs", 10])
    assert code == 0, err


def test_rad_s_curve_read_as_deg_h_warns(tmp_path: Path) -> None:
    """The common mistake (``test_plausibility``): LN-200's rad/s curve taken as deg/h."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        code, _, err = _run([_smac("ln200"), "--channel", "Gyro. X"])
    assert code == 0
    assert "no unit in the deviation column 'adev'; assuming deg/h" in err
    assert "warning: ln200_av.csv: Gyro. X:" in err and "rad/s" in err


def test_plot_and_output_checks(tmp_path: Path) -> None:
    png = tmp_path / "c.png"
    code, _, err = _run([_smac("imar"), "--units", "rad/s", "--plot", png])
    assert code == 0, err
    assert png.stat().st_size > 0
    code, _, err = _run([_smac("imar"), "--units", "rad/s", "--json", _smac("imar")])
    assert code == 2
    assert "is the input FILE" in error_output(err) and "never replaces an input" in err


@pytest.mark.parametrize(("args", "match"), [
    (["--fs", "-3"], r"error: --fs must be a finite number > 0, got -3.0"),
    (["--n-samples", "1"], r"error: --n-samples must be .*>= 2"),
    (["--channel", "Gyro. Q"], r"error: channel 'Gyro. Q' not found in .*; channels are: "),
])
def test_errors_are_one_line_with_exit_2(args: list[str], match: str) -> None:
    code, _, err = _run([_smac("imar"), "--units", "rad/s", *args])
    assert code == 2
    line = error_output(err)
    assert "\n" not in line
    assert re.match(match, line), line


def test_missing_file_is_one_line(tmp_path: Path) -> None:
    code, _, err = _run([tmp_path / "none.csv"])
    assert code == 2 and error_output(err).startswith("error: curve file not found")


def test_export_of_a_published_curve_is_its_fitted_si_terms(tmp_path: Path) -> None:
    """``--export json`` from the KVH1750 curve: N and K of each axis are the command's own
    ``noise_si`` block (1e-12 relative: the same numbers through JSON), the update rate the
    file's, with no note (the SMAC header states it)."""
    out = tmp_path / "imu.json"
    doc = _json([_smac("kvh1750"), "--units", "deg/s", "--channel", "all",
                 "--export", "json", out], tmp_path)
    exported = json.loads(out.read_text())
    assert exported["update_rate_hz"] == pytest.approx(doc["input"]["fs_hz"], rel=1e-12)
    assert "update_rate_note" not in exported
    assert set(exported["axes"]) == {ax["axis"] for ax in doc["axes"]}
    for ax in doc["axes"]:
        for t in ("N", "K"):
            si = ax["noise_si"][t]
            got = exported["axes"][ax["axis"]][t]
            want = si["upper_limit_95"] if got["upper_limit"] else si["value"]
            assert got["value"] == pytest.approx(want, rel=1e-12)


def test_export_says_when_the_update_rate_was_inferred(tmp_path: Path) -> None:
    """A curve without a sample rate: Kalibr's update_rate is 1 / the shortest tau, and the
    line says so; ``--fs`` removes the note."""
    path = tmp_path / "d.csv"
    rows = "".join(f"{t!r},{0.1 / math.sqrt(t) + 1e-3 * math.sqrt(t)!r},{2e5 / t!r}\n"
                   for t in (0.1 * 2.0**np.arange(12)).tolist())
    path.write_text("tau,adev_deg_h,edf\n" + rows)
    yaml_path = tmp_path / "imu.yaml"
    code, _, err = _run([path, "--export", "kalibr", yaml_path])
    assert code == 0, err
    text = yaml_path.read_text()
    assert "update_rate: 10.0  # inferred as 1 / the curve's shortest tau: check it is the " \
           "IMU's sample rate" in text
    assert "(a published oadev curve in deg/h (column name); 10 Hz (inferred)" in text
    code, _, err = _run([path, "--fs", 200, "--export", "kalibr", yaml_path, "--overwrite"])
    assert code == 0, err
    assert "update_rate: 200.0\n" in yaml_path.read_text()


def test_export_errors_write_nothing(tmp_path: Path) -> None:
    out = tmp_path / "imu.yaml"
    code, _, err = _run([_smac("imar"), "--units", "rad/s", "--export", "yaml", out])
    assert code == 2
    assert error_output(err) == "error: --export FORMAT must be one of kalibr, imu_utils, " \
                                "json; got 'yaml'"
    code, _, err = _run([_smac("imar"), "--units", "rad/s", "--terms", "N,B",
                         "--export", "kalibr", out])
    assert code == 2 and "the export needs N and K" in error_output(err)
    assert not out.exists()
    code, _, err = _run([_smac("imar"), "--units", "rad/s", "--export", "json", _smac("imar")])
    assert code == 2 and "is the input FILE" in error_output(err)


def test_inference_notes_name_the_options(tmp_path: Path) -> None:
    """The notes and the unit warning of tests/allan/test_curve_input.py's
    ``test_inference_notes_and_the_unit_warning_name_the_keywords``, as the command line
    prints them and writes them into its JSON: the options (``--units``, ``--kind``,
    ``--fs``, ``--n-samples N``, ``--channel NAME``), never the keywords."""
    from tests.allan.test_curve_input import CURVE_NOTE_KEYWORDS, _bare_channels_csv

    out = tmp_path / "bare.json"
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        code, printed, err = _run([_bare_channels_csv(tmp_path), "--terms", "N,K",
                                   "--json", out])
    assert code == 0, err
    assert ("warning: bare.csv: no unit in the deviation column 'dev'; assuming deg/h; pass "
            "--units (deg/h, deg/s, rad/s, arcsec/s)") in err.splitlines()
    options = {"give kind=": "give --kind",
               "pick one with channel=NAME and its units=": "pick one with --channel NAME "
                                                            "and its --units",
               "give fs_hz= if the record was sampled faster": "give --fs if the record was "
                                                              "sampled faster",
               "give n_samples=N": "give --n-samples N"}
    doc = json.loads(out.read_text())
    for start, keyword in CURVE_NOTE_KEYWORDS.items():
        line = next(ln for ln in printed.splitlines() if ln.startswith(f"note: {start}"))
        assert line.endswith(options[keyword]), line
        for notes in (doc["notes"], doc["input"]["notes"], doc["axes"][0]["notes"]):
            (note,) = [n for n in notes if n.startswith(start)]
            assert note == line[len("note: "):]
    texts = [*doc["notes"], *doc["input"]["notes"], err, printed]
    assert not any(re.search(r"\b(units|kind|fs_hz|n_samples|channel)=", t) for t in texts)


def test_export_format_is_checked_before_the_existing_file(tmp_path: Path) -> None:
    """audit2 N15: the --export format is checked before the output's existence."""
    out = tmp_path / "imu.yaml"
    out.write_text("mine\n")
    code, _, err = _run([_smac("imar"), "--units", "rad/s", "--export", "yaml", out])
    assert code == 2 and out.read_text() == "mine\n"
    assert error_output(err) == "error: --export FORMAT must be one of kalibr, imu_utils, " \
                                "json; got 'yaml'"
