"""Data hygiene at the command line (issue 13): every measurement of the issue as a
regression test: assumed units warn and the plausibility check names rad/s for the
XSens record, a gap shows in `fogts allan`'s text and JSON, ADIS16405 run 4's glitch is
named with its time, --nan drop|interpolate report counts, --outliers reports its effect
on N, and a DatetimeIndex with dropped samples is gaps, not burst logging."""

from __future__ import annotations

import json
import re
import warnings
from pathlib import Path

import numpy as np
import pandas as pd
import pytest
from typer.testing import CliRunner

from fogts.cli import app
from fogts.errors import DataQualityWarning
from fogts.io.reader import read_run
from tests.conftest import error_output, shared_path

runner = CliRunner()


def _warnings(stderr: str) -> list[str]:
    return [ln for ln in stderr.splitlines() if ln.startswith("warning: ")]


def test_cont_imu1_without_units_warns_and_names_rad_s(tmp_path: Path) -> None:
    src = shared_path("imu", "cont_imu1_gyro_x.npz")
    out = tmp_path / "a.json"
    res = runner.invoke(app, ["allan", str(src), "--json", str(out)])
    assert res.exit_code == 0, res.stderr
    lines = _warnings(res.stderr)
    # printed first, before any analysis output (rich prints stderr unbuffered)
    assert lines[0] == ("warning: cont_imu1_gyro_x.npz: no unit in the rate column(s) "
                        "'gyro_x'; assuming deg/h; pass --units (deg/h, deg/s, rad/s, "
                        "arcsec/s)")
    implausible = next(ln for ln in lines if "gyro_x: N = 1.09e-05 deg/sqrt(h)" in ln)
    assert "rad/s" in implausible and "N = 2.25 deg/sqrt(h)" in implausible  # x 206265
    # the option, not read_run's units= (tests/allan/test_plausibility.py)
    assert implausible.endswith("; set the rate unit explicitly (--units)")
    doc = json.loads(out.read_text())
    assert doc["plausibility"]["message"].endswith("; set the rate unit explicitly (--units)")
    assert doc["data_quality"]["warnings"][0].endswith("; pass --units (deg/h, deg/s, rad/s, "
                                                       "arcsec/s)")
    assert doc["input"]["units_source"] == "assumed"
    assert doc["plausibility"]["verdict"] == "implausible"
    assert "rad/s" in [a["units"] for a in doc["plausibility"]["alternatives"]]
    # told the unit, the same record is a plausible MEMS and nothing is assumed
    res = runner.invoke(app, ["allan", str(src), "--units", "rad/s", "--json", str(out),
                              "--overwrite"])
    assert res.exit_code == 0
    assert not [ln for ln in _warnings(res.stderr) if "unit" in ln or "N = " in ln]
    doc = json.loads(out.read_text())
    assert doc["input"]["units_source"] == "given"
    assert doc["plausibility"]["verdict"] == "plausible"
    assert doc["noise"]["N"]["value"] == pytest.approx(2.25, rel=0.05)


def test_fog_file_units_are_said_to_be_assumed() -> None:
    res = runner.invoke(app, ["info", str(shared_path("fog", "fog_0917.txt")), "--json", "-"])
    assert res.exit_code == 0
    assert "no unit in the rate column(s) 'fog'; assuming deg/h" in res.stderr
    assert json.loads(res.stdout)["data_quality"]["units_source"] == "assumed"


@pytest.fixture
def gappy_csv(tmp_path: Path) -> Path:
    """120 s at 100 Hz with the samples of 1 s missing after t = 59.99 s."""
    t = np.r_[np.arange(6000), np.arange(6100, 12100)] / 100.0
    rate = np.random.default_rng(42).standard_normal(t.size)
    path = tmp_path / "gap.csv"
    pd.DataFrame({"time": t, "rate_deg_h": rate}).to_csv(path, index=False)
    return path


def test_a_gap_appears_in_allan_text_and_json(gappy_csv: Path, tmp_path: Path) -> None:
    out = tmp_path / "a.json"
    res = runner.invoke(app, ["allan", str(gappy_csv), "--json", str(out)])
    assert res.exit_code == 0, res.stderr
    gap_line = next(ln for ln in _warnings(res.stderr) if "gap" in ln)
    assert gap_line.startswith("warning: gap.csv: 1 gap(s) in the time base (1 s missing; "
                               "first at t = 59.99 s")
    assert "analysed as if the samples were regular" in gap_line
    doc = json.loads(out.read_text())
    quality = doc["data_quality"]
    assert quality["gaps"]["n_gaps"] == 1 and quality["gap_policy"] == "warn"
    assert quality["gaps"]["gaps"][0]["time_s"] == pytest.approx(59.99)
    assert any("gap" in w for w in quality["warnings"])


def test_gaps_split_and_error(gappy_csv: Path, tmp_path: Path) -> None:
    out = tmp_path / "a.json"
    res = runner.invoke(app, ["allan", str(gappy_csv), "--gaps", "split", "--json", str(out)])
    assert res.exit_code == 0
    assert "--gaps split: analysing the longest regular segment, rows 0..5999 (6,000 of " \
           "12,000 samples" in res.stderr
    doc = json.loads(out.read_text())
    assert doc["input"]["n"] == 6000 and doc["data_quality"]["segment"]["n"] == 6000
    res = runner.invoke(app, ["select", str(gappy_csv), "--gaps", "error"])
    assert res.exit_code == 2
    assert error_output(res.stderr).startswith("error: ")
    assert "; --gaps error refuses it: pass --gaps split to analyse" in res.stderr
    res = runner.invoke(app, ["davar", str(gappy_csv), "--gaps", "sometimes"])
    assert res.exit_code == 2 and error_output(res.stderr) == (
        "error: Invalid value for '--gaps': 'sometimes' is not one of 'warn', 'error', "
        "'split', 'ignore', 'nan'. (see 'fogts davar --help')")


def test_select_and_davar_report_gaps_in_json(gappy_csv: Path, tmp_path: Path) -> None:
    for args in (["select", str(gappy_csv)],
                 ["davar", str(gappy_csv), "--window", "20s", "--step", "10s"]):
        out = tmp_path / f"{args[0]}.json"
        res = runner.invoke(app, [*args, "--json", str(out)])
        assert res.exit_code in (0, 1), res.stderr
        assert any("1 gap(s) in the time base" in ln for ln in _warnings(res.stderr))
        assert json.loads(out.read_text())["data_quality"]["gaps"]["n_gaps"] == 1


def test_adis_run4_glitch_is_listed_by_allan(tmp_path: Path) -> None:
    out = tmp_path / "a.json"
    res = runner.invoke(app, ["allan", str(shared_path("imu", "adis_16405_imu4_gyro.npz")),
                              "--axis", "0", "--json", str(out)])
    assert res.exit_code == 0, res.stderr
    line = next(ln for ln in _warnings(res.stderr) if "glitch" in ln)
    assert "axis 'Gyro. X': 6 glitches" in line
    assert "t = 4046.07 s: -17 deg/s (-47 sigma" in line
    glitches = json.loads(out.read_text())["data_quality"]["glitches"]
    x_axis = next(g for g in glitches if g["axis"] == "Gyro. X")
    assert any(abs(e["time_s"] - 4046.07) < 0.01 for e in x_axis["events"])


@pytest.fixture
def holey_csv(tmp_path: Path) -> Path:
    t = np.arange(2000) / 10.0
    rate = np.random.default_rng(7).standard_normal(t.size)
    text = ["time,rate_deg_h"] + [f"{a:.17g},{b:.17g}" for a, b in zip(t, rate, strict=True)]
    text[101] = f"{t[100]:.17g},"    # an empty cell (data row 100)
    text[501] = f"{t[500]:.17g},nan"   # a NaN (data row 500)
    path = tmp_path / "holes.csv"
    path.write_text("\n".join(text) + "\n")
    return path


def test_nan_default_is_an_error_naming_the_row_and_option(holey_csv: Path) -> None:
    res = runner.invoke(app, ["allan", str(holey_csv)])
    assert res.exit_code == 2
    assert error_output(res.stderr) == (
        f"error: column 'rate_deg_h' has an empty cell at data row 100 (line 102 of "
        f"{holey_csv}); pass --nan drop or --nan interpolate")


def test_nan_drop_and_interpolate_report_counts(holey_csv: Path, tmp_path: Path) -> None:
    out = tmp_path / "a.json"
    res = runner.invoke(app, ["allan", str(holey_csv), "--nan", "drop", "--json", str(out)])
    assert res.exit_code == 0, res.stderr
    assert "2 row(s) with empty/NaN/inf cells dropped (rate_deg_h: 2; first at data row " \
           "100)" in res.stderr
    doc = json.loads(out.read_text())
    assert doc["input"]["n"] == 1998
    assert doc["data_quality"]["missing"] == {"policy": "drop", "n_rows": 2, "by_column": {
        "rate_deg_h": 2, "time": 0}, "first_rows": [100, 500]}
    assert doc["data_quality"]["gaps"]["n_gaps"] == 2  # the dropped rows are gaps
    res = runner.invoke(app, ["info", str(holey_csv), "--nan", "interpolate", "--json", "-"])
    assert res.exit_code == 0
    info = json.loads(res.stdout)
    assert info["n"] == 2000
    assert info["data_quality"]["missing"]["by_column"] == {"rate_deg_h": 2}
    assert "interpolated linearly in time" in res.stderr
    res = runner.invoke(app, ["info", str(holey_csv), "--nan", "guess"])
    assert res.exit_code == 2
    assert "Invalid value for '--nan': 'guess' is not one of 'error', 'drop', " \
           "'interpolate'" in res.stderr


def test_outliers_prints_count_and_effect_on_n() -> None:
    res = runner.invoke(app, ["allan", str(shared_path("imu", "cont_imu1_gyro_x.npz")),
                              "--units", "rad/s", "--outliers", "8"])
    assert res.exit_code == 0
    line = next(ln for ln in res.stdout.splitlines() if "--outliers 8:" in ln)
    assert "replaced 8,187 of 500,000 samples (1.64 %)" in line
    assert "without the replacement (-15" in line  # the issue measured N -16 %


def test_datetime_index_with_dropped_samples_is_gaps_not_bursts() -> None:
    rng = np.random.default_rng(5)
    index = pd.date_range("2026-01-01", periods=20_000, freq="10ms")
    keep = rng.random(index.size) > 0.1  # 10 % of the samples lost
    series = pd.Series(rng.standard_normal(index.size), index=index)[keep]
    with warnings.catch_warnings():
        warnings.simplefilter("error", DataQualityWarning)  # no burst-logging warning
        run = read_run(series)
    assert run.fs_hz == pytest.approx(100.0)
    assert run.sampling is not None and run.sampling.fs_source == "median step"
    assert run.sampling.n_gaps > 1000


def test_batch_names_the_files_with_gaps(gappy_csv: Path, tmp_path: Path) -> None:
    out = tmp_path / "summary.csv"
    res = runner.invoke(app, ["batch", str(gappy_csv), "-o", str(out), "--no-select",
                              "--workers", "1"])
    assert res.exit_code == 0, res.stderr
    assert "warning: gaps in the time base in 1 file(s): gap.csv" in res.stderr
    row = pd.read_csv(out).iloc[0]
    assert (row["units_source"], row["n_gaps"], row["n_glitches"]) == ("column name", 1, 0)


def test_units_from_a_fogts_sidecar(tmp_path: Path) -> None:
    src = tmp_path / "sim.csv"
    res = runner.invoke(app, ["simulate", "noise", "-o", str(src), "--N", "0.01", "--duration", "60s",
                              "--units", "deg/s", "--seed", "3"])
    assert res.exit_code == 0
    run = read_run(src)
    assert (run.units, run.units_source) == ("deg/s", "file metadata")
    # a JSON beside the file that fogts did not write is not trusted
    (tmp_path / "sim.csv.json").write_text('{"generator": "other", "units": "rad/s"}')
    assert read_run(src).units_source == "assumed"
    assert read_run(src, units="rad/s").units_source == "given"


def test_axis_minus_one_means_the_last_axis_everywhere(tmp_path: Path) -> None:
    """One --axis parser: a name or an index, negative from the end, for every command."""
    rng = np.random.default_rng(3)
    t = np.arange(3000) / 10.0
    src = tmp_path / "xyz.csv"
    pd.DataFrame({"time": t, "rate_x_deg_h": rng.standard_normal(t.size),
                  "rate_y_deg_h": rng.standard_normal(t.size),
                  "rate_z_deg_h": rng.standard_normal(t.size)}).to_csv(src, index=False)
    for args in (["allan"], ["select"], ["davar", "--window", "60s", "--step", "30s"]):
        out = tmp_path / f"{args[0]}.json"
        res = runner.invoke(app, [args[0], str(src), *args[1:], "--axis", "-1",
                                  "--json", str(out)])
        assert res.exit_code in (0, 1), res.stderr
        doc = json.loads(out.read_text())
        axis = doc["input"]["axis"] if args[0] == "select" else doc["axis"]
        assert axis == "rate_z_deg_h"
    res = runner.invoke(app, ["select", str(src), "--axis", "-4"])
    assert res.exit_code == 2
    assert "--axis must be an axis name or an index in -3..2, got -4; axes are: " \
           "rate_x_deg_h, rate_y_deg_h, rate_z_deg_h" in res.stderr


def test_quality_warnings_name_the_options(tmp_path: Path) -> None:
    """The findings of tests/preprocess/test_hygiene.py's
    ``test_quality_warnings_name_the_keywords`` as the command line prints them and writes
    them into its JSON: ``--units``, ``--gaps split``, ``--outliers K``, not the keywords;
    with ``--outliers 8`` the glitch line and the effect on N say ``--outliers 8``."""
    from tests.preprocess.test_hygiene import unnamed_gappy_frame

    path = tmp_path / "bare.csv"
    unnamed_gappy_frame().to_csv(path, index=False)
    options = {
        "units": "; assuming deg/h; pass --units (deg/h, deg/s, rad/s, arcsec/s)",
        "warn": "; analysed as if the samples were regular (--gaps split analyses the longest "
                "regular segment, --gaps error refuses the file)",
        "nan": "; --gaps nan: the whole record on the regular grid, missing samples as NaN",
        "split": "; --gaps split: analysing the longest regular segment, rows 0..2999",
        "kept": "; kept in the analysis (--outliers K replaces samples beyond K robust sigmas)",
        "replaced": "; --outliers 8: samples beyond 8 robust sigmas are replaced before the "
                    "analysis (counted below)",
    }
    runs = {"warn": ["units", "warn", "kept"], "nan": ["nan"], "split": ["split"]}
    for policy, findings in runs.items():
        out = tmp_path / f"{policy}.json"
        res = runner.invoke(app, ["allan", str(path), "--gaps", policy, "--json", str(out)])
        assert res.exit_code == 0, res.stderr
        printed = [ln.removeprefix("warning: bare.csv: ") for ln in _warnings(res.stderr)]
        written = json.loads(out.read_text())["data_quality"]["warnings"]
        assert written == printed[:len(written)]
        for finding in findings:
            assert any(options[finding] in w for w in written), (finding, written)
        assert not any(re.search(r"\b(units|gaps|outliers)=", w) for w in printed)
    out = tmp_path / "replaced.json"
    res = runner.invoke(app, ["allan", str(path), "--outliers", "8", "--json", str(out)])
    assert res.exit_code == 0, res.stderr
    doc = json.loads(out.read_text())
    assert any(options["replaced"] in w for w in doc["data_quality"]["warnings"])
    assert doc["outliers_effect"]["text"].startswith("--outliers 8: replaced 1 of 6,000 samples")
    assert any(ln.startswith("rate: --outliers 8: replaced 1 of 6,000") for ln in
               res.stdout.splitlines())
