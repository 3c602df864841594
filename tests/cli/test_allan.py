"""``fogts allan``: tables, the DESIGN.md JSON contract, CSV, plot, allantools check, errors."""

from __future__ import annotations

import json
import re
import subprocess
import sys
from pathlib import Path

import numpy as np
import pandas as pd
import pytest
from typer.testing import CliRunner

from fogts.cli import app
from tests.cli.conftest import FS, K_TRUE, N_TRUE
from tests.conftest import error_output, shared_path

runner = CliRunner()

def _run(args: list[str]) -> tuple[int, str, str]:
    res = runner.invoke(app, ["allan", *[str(a) for a in args]])
    return res.exit_code, res.stdout, res.stderr


def test_tables_json_csv_plot(gyro_npy: Path, tmp_path: Path) -> None:
    out_json, out_csv, out_png = tmp_path / "a.json", tmp_path / "a.csv", tmp_path / "a.png"
    code, out, err = _run([gyro_npy, "--fs", FS, "--json", out_json, "--csv", out_csv,
                           "--plot", out_png])
    assert code == 0, err
    assert "oadev of rate (deg/h), 68.3 % CI" in out
    assert "IEEE-952 noise terms of rate (WLS fit of oadev" in out
    assert "deg/sqrt(h)" in out and "slope read-offs (comparison only" in out
    assert "warning: gyro.npy: rate: noise term" in err  # Q, B, R are not in these data
    assert out.startswith("Summary: noise terms per file and axis")
    top = json.loads(out_json.read_text())
    # DESIGN.md contract: one block per axis; the top-level copy of axis 0 is deprecated
    assert [b["axis"] for b in top["axes"]] == ["rate"]
    assert set(top["deprecated"]["fields"]) >= {"points", "noise", "kind", "units"}
    assert all(top[k] == top["axes"][0][k] for k in top["deprecated"]["fields"])
    doc = {**top["axes"][0], "input": top["input"]}
    assert set(doc) >= {"input", "kind", "units", "points", "noise"}
    assert doc["kind"] == "oadev" and doc["units"] == "deg/h"
    assert doc["input"]["n"] == 240_000 and doc["input"]["fs_hz"] == FS
    assert doc["input"]["source"].endswith("gyro.npy") and doc["input"]["axis"] == "rate"
    for p in doc["points"]:
        assert set(p) >= {"tau", "m", "n", "dev", "ci_low", "ci_high", "edf"}
        assert p["ci_low"] < p["dev"] < p["ci_high"]
    assert set(doc["noise"]) == {"Q", "N", "B", "K", "R"}
    for term in doc["noise"].values():
        assert set(term) >= {"value", "stderr", "unit"}
    assert doc["noise"]["N"]["unit"] == "deg/sqrt(h)"
    assert doc["noise"]["N"]["value"] == pytest.approx(N_TRUE, rel=0.03)
    assert doc["noise"]["K"]["value"] == pytest.approx(K_TRUE, rel=0.3)
    assert doc["noise_fit"]["method"] == "wls" and doc["preprocessing"] is None
    table = pd.read_csv(out_csv)
    assert list(table.columns) == ["tau", "m", "n", "dev", "ci_low", "ci_high", "edf", "alpha",
                                   "fit"]
    np.testing.assert_allclose(table["dev"], [p["dev"] for p in doc["points"]], rtol=1e-15)
    assert out_png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


def test_json_stdout_is_pure_and_deterministic(gyro_npy: Path) -> None:
    code, out, _ = _run([gyro_npy, "--fs", FS, "--json", "-", "--taus", "decade"])
    assert code == 0
    doc = json.loads(out)  # the tables went to stderr
    assert [p["tau"] for p in doc["points"]][:4] == pytest.approx([0.01, 0.02, 0.04, 0.1])
    code2, out2, _ = _run([gyro_npy, "--fs", FS, "--json", "-", "--taus", "decade"])
    assert code2 == 0 and out2 == out


def test_check_allantools_and_options(gyro_npy: Path) -> None:
    code, out, err = _run([gyro_npy, "--fs", FS, "--check-allantools", "--terms", "N,K",
                           "--method", "gls", "--confidence", "0.95", "--taus", "0.1,1,10,100"])
    assert code == 0, err
    line = next(ln for ln in out.splitlines() if ln.startswith("allantools check"))
    worst = float(line.split("largest relative difference ")[1].split()[0])
    assert worst < 1e-9
    assert "GLS fit" in out and "95.0 % interval" in out
    code, out, _ = _run([gyro_npy, "--fs", FS, "--json", "-", "--terms", "N,K",
                         "--check-allantools", "--detrend", "1"])
    doc = json.loads(out)
    assert set(doc["noise"]) == {"N", "K"}
    assert doc["allantools_check"]["max_rel_diff"] < 1e-9
    assert doc["allantools_check"]["n_terms_equal"] is True
    assert doc["preprocessing"]["detrend"]["order"] == 1


def test_totdev_bias_correction_and_its_allantools_check(gyro_npy: Path) -> None:
    code, out, err = _run([gyro_npy, "--fs", FS, "--kind", "totdev", "--bias-correction",
                           "--check-allantools", "--terms", "N,K", "--json", "-"])
    assert code == 0, err
    doc = json.loads(out)
    assert doc["bias_corrected"] is True
    assert "totdev_bias" in doc["allantools_check"]["peer"]
    assert doc["allantools_check"]["max_rel_diff"] < 1e-9
    code, plain, err = _run([gyro_npy, "--fs", FS, "--kind", "totdev", "--json", "-",
                             "--terms", "N,K"])
    assert code == 0, err
    devs = [p["dev"] for p in doc["points"]]
    raw = [p["dev"] for p in json.loads(plain)["points"]]
    assert json.loads(plain)["bias_corrected"] is False
    assert all(a >= b for a, b in zip(devs, raw, strict=True)) and devs[-1] > raw[-1]
    code, out, err = _run([gyro_npy, "--fs", FS, "--kind", "totdev", "--bias-correction",
                           "--terms", "N,K"])
    assert code == 0, err
    assert "totdev of rate (deg/h), 68.3 % CI, bias-corrected (Howe 1999)" in out


def test_bias_correction_with_another_kind_is_a_usage_error(gyro_npy: Path) -> None:
    code, _out, err = _run([gyro_npy, "--fs", FS, "--bias-correction"])
    assert code == 2
    assert error_output(err).splitlines() == [
        "error: bias_correction applies to --kind totdev only (the other estimators are "
        "unbiased for every power-law noise), got --kind oadev"]


def test_mdev_is_computed_but_not_fitted(gyro_npy: Path) -> None:
    code, out, err = _run([gyro_npy, "--fs", FS, "--kind", "mdev", "--json", "-"])
    assert code == 0
    doc = json.loads(out)
    assert doc["kind"] == "mdev" and doc["noise"] == {}
    assert "not mdev" in doc["noise_fit"]["skipped"]
    assert "warning: gyro.npy: rate: noise terms are fitted to adev, oadev or totdev curves " \
        "only" in err


def test_multi_axis_real_imu(tmp_path: Path) -> None:
    """ADIS16405 run 1 (3 axes, deg/s, 100 Hz): one block per axis, the (deprecated) top
    level = axis 0."""
    path = shared_path("imu", "adis_16405_imu1_gyro.npz")
    out_csv, out_png = tmp_path / "axes.csv", tmp_path / "axes.svg"
    code, out, err = _run([path, "--json", "-", "--csv", out_csv, "--plot", out_png])
    assert code == 0, err
    doc = json.loads(out)
    names = [a["axis"] for a in doc["axes"]]
    assert len(names) == 3 and doc["input"]["axes"] == names
    assert doc["axis"] == names[0] and doc["points"] == doc["axes"][0]["points"]
    assert doc["units"] == "deg/s"
    for block in doc["axes"]:
        assert set(block) >= {"points", "noise", "kind", "units"}
    # ADIS16405 datasheet: angle random walk 2.0 deg/sqrt(h), in-run bias stability
    # 0.007 deg/s = 25 deg/h (typical); the X axis' fit lands at 2.3 and 34
    x_noise = doc["axes"][0]["noise"]
    assert 1.5 < x_noise["N"]["value"] < 3.0 and x_noise["N"]["unit"] == "deg/sqrt(h)"
    assert 15.0 < x_noise["B"]["value"] < 50.0 and x_noise["B"]["unit"] == "deg/h"
    table = pd.read_csv(out_csv)
    assert table.columns[0] == "axis" and sorted(set(table["axis"])) == sorted(names)
    assert out_png.read_text().lstrip().startswith("<?xml")
    code, out, _ = _run([path, "--json", "-", "--axis", names[1]])
    single = json.loads(out)
    assert [b["axis"] for b in single["axes"]] == [names[1]] and single["axis"] == names[1]
    assert single["points"] == doc["axes"][1]["points"]
    code, out, _ = _run([path, "--json", "-", "--axis", "2"])
    assert json.loads(out)["axis"] == names[2]


@pytest.mark.parametrize(("args", "match"), [
    (["--taus", "weekly"], "--taus must be octave, decade, dense, all or taus in seconds"),
    (["--terms", "N,X"], r"terms must be drawn from Q, N, B, K, R; got 'X' \(M and S may be added\)"),
    (["--terms", ""], "terms must name at least one of Q, N, B, K, R"),
    (["--kind", "xdev"], "Invalid value for '--kind': 'xdev' is not one of"),
    (["--method", "lsq"], "'lsq' is not one of 'wls', 'gls', 'ols'"),
    (["--confidence", "2"], r"confidence must be in \(0, 1\)"),
    (["--axis", "z"], "axis 'z' not found; axes are: rate"),
    (["--axis", "3"], r"--axis must be an axis name or an index in -1..0, got 3; axes are: rate"),
    (["--plot", "fig.jpg"], "--plot must end in .png, .svg or .pdf"),
    (["--csv", "points.xlsx"], "--csv must end in .csv, .csv.gz, .tsv, .txt or .parquet"),
    (["--decimate", "1000000"], "decimate=1000000 leaves 0 samples"),
])
def test_errors_are_one_line_exit_2(gyro_npy: Path, tmp_path: Path, args: list[str],
                                    match: str) -> None:
    args = [str(tmp_path / a) if a.endswith((".jpg", ".xlsx")) else a for a in args]
    code, out, err = _run([gyro_npy, "--fs", FS, *args])
    assert code == 2, (out, err)
    lines = [ln for ln in err.splitlines() if ln.startswith("error: ")]
    assert len(lines) == 1 and "Traceback" not in err
    assert pytest.importorskip("re").search(match, lines[0]), lines[0]


def test_missing_file_and_too_short(tmp_path: Path) -> None:
    code, _, err = _run([tmp_path / "nope.csv"])
    assert code == 2 and error_output(err).startswith("error: ")
    short = tmp_path / "short.npy"
    np.save(short, np.random.default_rng(0).normal(size=6))
    code, _, err = _run([short, "--fs", "10"])
    assert code == 2 and error_output(err).startswith("error: ") and "Traceback" not in err


def test_unsupported_terms_are_dropped_unless_kept(gyro_npy: Path) -> None:
    """White + RRW data: Q and R are not in the data; by default the fit drops what it
    cannot support, --keep-all-terms keeps all five (the pre-selection behaviour)."""
    code, out, _ = _run([gyro_npy, "--fs", FS, "--json", "-"])
    assert code == 0
    fit = json.loads(out)["noise_fit"]["fit"]
    assert fit["significance"] == 0.05 and "Q" in fit["dropped"]
    code, out, _ = _run([gyro_npy, "--fs", FS, "--keep-all-terms", "--json", "-"])
    assert code == 0
    payload = json.loads(out)
    assert payload["noise_fit"]["fit"]["significance"] is None
    assert payload["noise_fit"]["fit"]["dropped"] == []
    assert {t["status"] for t in payload["noise"].values()} <= {"fitted", "at_bound"}
    assert payload["noise"]["N"]["value"] == pytest.approx(N_TRUE, rel=0.03)


# ------------------------------------------------------------------ SI units and exports
def test_si_tables_and_a_kalibr_export_that_reads_back(tmp_path: Path) -> None:
    import yaml

    from fogts.units import TERM_SI_FACTOR

    adis = shared_path("imu", "adis_16405_imu1_gyro.npz")
    out, js = tmp_path / "imu.yaml", tmp_path / "a.json"
    code, stdout, _ = _run([adis, "--output-units", "si", "--export", "kalibr", out,
                            "--json", js])
    assert code == 0
    assert "rad/s^2/sqrt(Hz)" in stdout and "of Gyro. X (rad/s)" in stdout
    doc = json.loads(js.read_text())
    exported = yaml.safe_load(out.read_text())
    n_axes, k_axes = [], []
    for block in doc["axes"]:
        noise, si = block["noise"], block["noise_si"]
        for name in ("N", "K"):
            assert si[name]["value"] == pytest.approx(
                noise[name]["value"] * TERM_SI_FACTOR[name], rel=1e-12, abs=0.0)
        n_axes.append(si["N"]["value"])
        k = si["K"]
        k_axes.append(k["upper_limit_95"] if noise["K"]["upper_limit_95"] is not None
                      else k["value"])
    assert exported["gyroscope_noise_density"] == pytest.approx(max(n_axes), rel=1e-12)
    assert exported["gyroscope_random_walk"] == pytest.approx(max(k_axes), rel=1e-12)
    assert exported["update_rate"] == pytest.approx(100.0, rel=1e-15)


@pytest.mark.parametrize(("args", "message"), [
    (["--export", "ros", "OUT"], "--export FORMAT must be one of kalibr, imu_utils, json; "
                                 "got 'ros'"),
    (["--export", "kalibr", "OUT", "SECOND"], "--export describes one sensor: give one input "
                                              "file, not 2"),
    (["--export", "kalibr", "OUT", "--kind", "mdev"], "the export needs the noise terms, and "
                                                      "rate has none (fitted to --kind adev, "
                                                      "oadev or totdev only)"),
    (["--export", "kalibr", "OUT", "--terms", "N,B"], "K was not fitted (--terms must include "
                                                      "N and K)"),
    (["--export", "kalibr", "INPUT"], "fogts never replaces an input"),
    (["--output-units", "rad"], "Invalid value for '--output-units'"),
])
def test_export_and_unit_errors_are_one_line(gyro_npy: Path, tmp_path: Path,
                                             args: list[str], message: str) -> None:
    second = tmp_path / "second.npy"
    second.write_bytes(gyro_npy.read_bytes())
    swap = {"OUT": str(tmp_path / "imu.yaml"), "SECOND": str(second), "INPUT": str(gyro_npy)}
    code, _, err = _run([gyro_npy, "--fs", "100", *[swap.get(a, a) for a in args]])
    assert code == 2
    line = error_output(err)
    assert message in line and line.startswith("error:") and "\n" not in line
    assert not (tmp_path / "imu.yaml").exists()


def test_several_files_open_with_the_summary_and_the_spec(gyro_npy: Path,
                                                         tmp_path: Path) -> None:
    """Two files: the summary table first (one row each), PASS/FAIL against the spec with
    exit code 1 on a FAIL, and each file's warnings printed for that file (the same finding
    on the second file is not swallowed as a repeat)."""
    import shutil

    second = tmp_path / "gyro_b.npy"
    shutil.copy(gyro_npy, second)
    spec = tmp_path / "datasheet.yaml"
    # the truth is N = 0.05 deg/sqrt(h), K = 10 deg/h^1.5: N within, K beyond its limit
    spec.write_text(f"units: deg\nN: {2 * N_TRUE}\nK: {K_TRUE / 2}\n")
    code, out, err = _run([gyro_npy, second, "--fs", FS, "--spec", spec,
                           "--json", tmp_path / "s.json"])
    assert code == 1, err
    assert out.startswith("Summary: noise terms per file and axis")
    lines = [ln for ln in out.splitlines() if "gyro" in ln and "│" in ln]
    assert len(lines) == 2 and "gyro_b.npy" in lines[1]
    assert all("PASS" in ln and "FAIL" in ln for ln in lines)
    for name in ("gyro.npy", "gyro_b.npy"):
        assert f"warning: {name}: rate: noise term B (bias instability" in err
    doc = json.loads((tmp_path / "s.json").read_text())
    assert [(r["file"], r["N_spec"], r["K_spec"]) for r in doc["summary"]] == [
        ("gyro.npy", "PASS", "FAIL"), ("gyro_b.npy", "PASS", "FAIL")]
    assert doc["summary"][0]["N"] == pytest.approx(doc["inputs"][0]["axes"][0]["noise"]["N"]
                                                   ["value"], rel=1e-12)
    assert doc["spec"]["limits"]["K"] == {"value": K_TRUE / 2, "unit": "deg/h^1.5"}
    spec.write_text(f"N: {2 * N_TRUE}\nK: {2 * K_TRUE}\n")
    code, out, err = _run([gyro_npy, "--fs", FS, "--spec", spec, "--output-units", "si"])
    assert code == 0, err
    rows = [ln for ln in out.splitlines() if "gyro" in ln and "│" in ln]
    assert "N (rad/s/sqrt(Hz))" in out and rows and not any("FAIL" in ln for ln in rows)


def test_a_north_seeking_record_is_not_taken_as_static(tmp_path: Path) -> None:
    """audit: a four-position file with a position_deg column ran as a static record and
    reported K as measured; allan warns first, naming the column and fogts northfind,
    which reads the same file without that warning."""
    rng = np.random.default_rng(8)
    pos = np.repeat([0, 90, 180, 270], 300)
    path = tmp_path / "cs.csv"
    pd.DataFrame({"time": np.arange(pos.size, dtype=float), "position_deg": pos,
                  "rate_deg_h": 10 * np.cos(np.radians(pos + 30)) +
                  rng.standard_normal(pos.size)}).to_csv(path, index=False)
    code, _, err = _run([path])
    assert code == 0, err
    assert err.splitlines()[0].startswith("warning: cs.csv: column 'position_deg' holds "
                                          "turn-table positions: the record is not static")
    assert "use fogts northfind" in err.splitlines()[0]
    res = runner.invoke(app, ["northfind", str(path), "--latitude", "45", "--rate-column",
                              "rate_deg_h"])
    assert "turn-table" not in res.stderr, res.stderr


def test_a_spec_without_units_warns_first(gyro_npy: Path, tmp_path: Path) -> None:
    """A --spec without 'units:' is read in degree units: one warning line, at once (before
    the summary), naming the file, the units assumed and how to set them."""
    spec = tmp_path / "datasheet.yaml"
    spec.write_text("N: 1e-5\n")
    code, out, err = _run([gyro_npy, "--fs", FS, "--spec", spec])
    assert code == 1, err
    warned = [ln for ln in err.splitlines() if "datasheet.yaml" in ln]
    assert warned == ["warning: datasheet.yaml: no units in the spec; assuming deg (N in "
                      "deg/sqrt(h)); give 'units: deg' or 'units: si' (N in rad/s/sqrt(Hz))"]
    assert err.splitlines()[0] == warned[0] and "N ≤ 1e-05 deg/sqrt(h)" in " ".join(out.split())
    spec.write_text("units: si\nN: 1e-5\n")
    _, _, err = _run([gyro_npy, "--fs", FS, "--spec", spec])
    assert "no units" not in err


@pytest.mark.parametrize(("text", "message"), [
    ("- 0.15\n- 10\n", "error: datasheet.yaml must be a mapping of noise terms to limits"),
    ("N: [0.1\n", "error: --spec file '.*datasheet.yaml' is not valid YAML: "),
    ("N: 0.1\nARW: 2\n", r"error: datasheet.yaml: unknown key\(s\) 'ARW'; allowed are N, B, "
                         "K and units"),
    ("N: -1\n", "error: datasheet.yaml: the limit of N must be finite and > 0, got -1"),
    ("units: mdeg\nN: 1\n", "error: datasheet.yaml: units must be one of deg, si; got 'mdeg'"),
])
def test_a_bad_spec_is_a_one_line_error(gyro_npy: Path, tmp_path: Path, text: str,
                                        message: str) -> None:
    spec = tmp_path / "datasheet.yaml"
    spec.write_text(text)
    code, out, err = _run([gyro_npy, "--fs", FS, "--spec", spec])
    assert code == 2 and out == ""
    lines = error_output(err).splitlines()
    assert len(lines) == 1 and re.match(message, lines[0]), lines


def test_a_missing_spec_is_named(gyro_npy: Path, tmp_path: Path) -> None:
    code, _, err = _run([gyro_npy, "--fs", FS, "--spec", tmp_path / "none.yaml"])
    assert code == 2
    assert error_output(err).startswith("error: --spec file not found: '")


def test_method_ml_fits_the_record(gyro_npy: Path, tmp_path: Path) -> None:
    """--method ml: fit_noise_ml on the series (Q left out with a warning), the ML block in
    the JSON and its account of the fit in the text."""
    out = tmp_path / "ml.json"
    code, stdout, stderr = _run([gyro_npy, "--fs", FS, "--units", "deg/h", "--method", "ml",
                                 "--terms", "Q,N,K", "--json", out])
    assert code == 0, stderr
    assert "does not model Q" in stderr
    axis = json.loads(out.read_text())["axes"][0]
    assert axis["noise_fit"]["method"] == "ml" and axis["noise_fit"]["ml"]["model"] == "N + K"
    assert axis["noise"]["N"]["value"] == pytest.approx(N_TRUE, rel=0.01)
    assert "ML model: N + K" in stdout


def test_the_command_leaves_slow_imports_out(gyro_npy: Path, tmp_path: Path) -> None:
    """``fogts allan`` loads neither scipy.stats nor scipy.signal (about a second of
    start-up together), nor matplotlib or statsmodels, when it plots and tests nothing."""
    code = ("import sys; from fogts.cli import main\n"
            "try:\n    main(sys.argv[1:])\nexcept SystemExit:\n    pass\n"
            "print(sorted(m for m in ('scipy.stats', 'scipy.signal', 'matplotlib', "
            "'statsmodels') if m in sys.modules))")
    args = ["allan", str(gyro_npy), "--fs", str(FS), "--json", str(tmp_path / "a.json")]
    done = subprocess.run([sys.executable, "-c", code, *args], capture_output=True,
                          text=True, check=True, cwd=Path(__file__).resolve().parents[2])
    assert done.stdout.strip().splitlines()[-1] == "[]"
    assert json.loads((tmp_path / "a.json").read_text())["axes"][0]["points"]


def test_curve_readouts_follow_output_units_si(gyro_npy: Path) -> None:
    """--output-units si prints the points in rad/s; the read-out table below them (the
    minimum, its interval and the flicker floor) must be in rad/s too, not deg/h
    (1 deg/h = pi/180/3600 rad/s; the same numbers, so 1e-3 relative covers the printed
    4 significant digits)."""
    minimum = re.compile(r"│ minimum\s+│ [^│]+│ ([0-9.e+-]+) \[([0-9.e+-]+), ([0-9.e+-]+)\] "
                         r"(\S+); floor/0\.664 = ([0-9.e+-]+) (\S+)")
    code, deg, err = _run([gyro_npy, "--fs", FS, "-q"])
    assert code == 0, err
    code, si, err = _run([gyro_npy, "--fs", FS, "-q", "--output-units", "si"])
    assert code == 0, err
    d, s = minimum.search(deg), minimum.search(si)
    assert d is not None and s is not None
    assert d.group(4) == d.group(6) == "deg/h" and s.group(4) == s.group(6) == "rad/s"
    factor = np.pi / 180.0 / 3600.0
    for i in (1, 2, 3, 5):
        assert float(s.group(i)) == pytest.approx(float(d.group(i)) * factor, rel=1e-3)


def test_glitch_warning_says_replaced_under_outliers(tmp_path: Path) -> None:
    """With --outliers K the glitch warning must not say the glitches are "kept in the
    analysis" (ADIS16405 run 4 said so while the same run replaced 14 samples)."""
    rng = np.random.default_rng(8)
    rate = rng.standard_normal(20_000)
    rate[[5_000, 12_000]] += 60.0  # two 60-sigma spikes
    path = tmp_path / "spiky.npy"
    np.save(path, rate)
    code, _, err = _run([path, "--fs", "10", "--units", "deg/h", "-q"])
    assert code in (0, 1) and "2 glitches" in err and "kept in the analysis" in err
    code, _, err = _run([path, "--fs", "10", "--units", "deg/h", "-q", "--outliers", "7"])
    assert code in (0, 1), err
    assert "2 glitches" in err and "kept in the analysis" not in err
    assert ("--outliers 7: samples beyond 7 robust sigmas are replaced before the analysis"
            in err)
    out_json = tmp_path / "a.json"          # the JSON's quality record says the same
    code, _, err = _run([path, "--fs", "10", "--units", "deg/h", "-q", "--outliers", "7",
                         "--json", out_json])
    assert code in (0, 1), err
    said = json.loads(out_json.read_text())["data_quality"]["warnings"]
    assert any("are replaced before the analysis" in w for w in said)
    assert not any("kept in the analysis" in w for w in said)


def test_the_curve_notes_reach_the_terminal(gyro_npy: Path) -> None:
    """An explicit tau off the sample grid is rounded to whole samples; the note saying so
    was in the JSON and in AllanResult.summary() but not on the terminal (0.015 s at
    100 Hz is computed at 0.01 s: a 0.005 s change)."""
    code, out, err = _run([gyro_npy, "--fs", FS, "-q", "--taus", "0.015,0.1,1,10,100,300",
                           "--terms", "N,K"])
    assert code == 0, err
    assert ("note: 1 explicit tau(s) rounded to the nearest whole number of samples "
            "(largest change 0.005 s)") in out
    assert "note: prepared" not in out  # the preparation steps are printed once, above


def test_allan_runs_with_the_cycle_collector_paused_and_restores_it(
        gyro_npy: Path, tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    import gc

    import fogts.pipeline

    seen: list[bool] = []
    analyse = fogts.pipeline.analyse_allan_axis

    def spy(*args, **kwargs):  # type: ignore[no-untyped-def]
        seen.append(gc.isenabled())
        return analyse(*args, **kwargs)

    monkeypatch.setattr(fogts.pipeline, "analyse_allan_axis", spy)
    path = gyro_npy
    assert gc.isenabled()
    ok = runner.invoke(app, ["allan", str(path), "--fs", "50"])
    assert ok.exit_code == 0, ok.output
    assert seen == [False]
    assert gc.isenabled()
    bad = runner.invoke(app, ["allan", str(tmp_path / "missing.npy"), "--fs", "50"])
    assert bad.exit_code == 2
    assert gc.isenabled()  # restored on the error path too
    gc.disable()
    try:  # a collector the caller had off stays off
        runner.invoke(app, ["allan", str(path), "--fs", "50"])
        assert not gc.isenabled()
    finally:
        gc.enable()



def test_gaps_nan_header_says_how_many_samples_are_missing(tmp_path: Path) -> None:
    """--gaps nan analyses the regular grid: the count it prints includes the NaN points,
    and says how many they are (the JSON's input.n is the grid's, as before)."""
    t = np.r_[np.arange(3000), np.arange(3050, 6000)] / 10.0
    path = tmp_path / "gappy.csv"
    pd.DataFrame({"time": t, "rate_deg_h": np.random.default_rng(3).standard_normal(t.size)}
                 ).to_csv(path, index=False)
    code, out, _ = _run([path, "--gaps", "nan", "--taus", "decade"])
    assert code in (0, 1)
    assert ("gappy.csv: 6000 samples at 10 Hz (600 s; 50 of them missing (NaN) in the time "
            "stamps' gaps), rate in deg/h") in out
    code, out, _ = _run([path, "--taus", "decade"])
    assert "gappy.csv: 5950 samples at 10 Hz (595 s), rate in deg/h" in out

def test_gaps_nan_refuses_burst_logged_stamps(tmp_path: Path) -> None:
    """The MPU6050 record is stamped in bursts (median step 2 ms, mean 10 ms): on the
    k/fs grid its samples would merge, and the pauses would read as 13,397 gaps."""
    out = tmp_path / "a.json"
    code, _, err = _run([shared_path("imu", "mpu6050_gyro_temp_converted.csv.gz"),
                         "--gaps", "nan", "--json", out])
    assert code == 2 and "Traceback" not in err
    assert error_output(err).startswith("error: ") and "would land on the point of the " \
        "sample before (time stamps logged in bursts" in err
    assert not out.exists()


def test_burst_logged_stamps_count_no_missing_time_and_refuse_split(tmp_path: Path) -> None:
    """The MPU6050 stamps come in bursts: its 13,397 long steps are not read as 399 s of
    missing time, and the read's warning and the data-quality line, one wording
    (:func:`fogts.io.timebase.burst_logging_text`), are printed once; the JSON keeps the
    count and the longest step (0.4969 s, as ``fogts info``); --gaps split, whose longest
    'regular' stretch is 18 samples, is refused instead of analysing 0.18 s."""
    from fogts.io.timebase import burst_logging_text

    path = shared_path("imu", "mpu6050_gyro_temp_converted.csv.gz")
    out = tmp_path / "b.json"
    code, _, err = _run([path, "--axis", "0", "--json", out])
    assert code == 0, err
    lines = [ln for ln in err.splitlines() if "bursts" in ln]
    assert lines == [f"warning: mpu6050_gyro_temp_converted.csv.gz: "
                     f"{burst_logging_text(99.31713767)}"]
    assert "not gaps, so no time is counted as missing" in lines[0]
    assert "missing;" not in lines[0] and "--gaps split" not in lines[0]
    gaps = json.loads(out.read_text())["data_quality"]["gaps"]
    assert gaps["burst_logged"] and gaps["n_gaps"] == 13397
    assert gaps["largest_s"] == pytest.approx(0.4969, abs=1e-4)
    out = tmp_path / "a.json"
    code, _, err = _run([path, "--axis", "0", "--gaps", "split", "--json", out])
    assert code == 2 and not out.exists()
    assert error_output(err).endswith(
        "--gaps split needs regular stretches between gaps, and these "
        "time stamps are logged in bursts: the longest stretch is 18 of 65,067 samples; use "
        "--gaps warn (the record at its mean rate)")


def test_a_method_error_names_the_option(tmp_path: Path) -> None:
    """Too few taus for GMWM's parameters: the error names --method, not method=."""
    path = tmp_path / "short.csv"
    pd.DataFrame({"rate_deg_s": np.random.default_rng(6).standard_normal(20)}).to_csv(
        path, index=False)
    code, _, err = _run([path, "--fs", "100", "--method", "gmwm"])
    assert code == 2 and "Traceback" not in err
    assert "--method gmwm needs at least" in err and "method=" not in err


def test_export_format_is_checked_before_the_existing_file(gyro_npy: Path,
                                                           tmp_path: Path) -> None:
    """audit2 N15: ``--export foo k.yaml`` with k.yaml present said k.yaml exists before
    that foo is no export format; the format comes first, the file is left alone, and a
    good format still meets the existing-file check."""
    target = tmp_path / "k.yaml"
    target.write_text("mine\n")
    code, _, err = _run([gyro_npy, "--fs", FS, "--export", "foo", target])
    assert code == 2
    assert error_output(err) == ("error: --export FORMAT must be one of kalibr, imu_utils, "
                                 "json; got 'foo'")
    code, _, err = _run([gyro_npy, "--fs", FS, "--export", "json", target])
    assert code == 2 and error_output(err).startswith(f"error: --export '{target}' already "
                                                      "exists")
    assert target.read_text() == "mine\n"
