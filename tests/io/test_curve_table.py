"""``fogts.io.curve_table``: the layouts of an Allan curve file, its columns by name, and
every refusal."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from fogts.errors import DataError
from fogts.io.curve_table import read_curve_table
from tests.allan.references import stable32_table
from tests.conftest import shared_path


def _write(tmp_path: Path, text: str, name: str = "c.csv") -> Path:
    path = tmp_path / name
    path.write_text(text)
    return path


@pytest.mark.parametrize(("header", "tau", "dev", "unit"), [
    ("tau,adev", "tau", "adev", None),
    ("Tau (s),ADEV_deg_h", "Tau (s)", "ADEV_deg_h", "deg/h"),
    ("averaging_time\tsigma", "averaging_time", "sigma", None),
    ("tau_s oadev_rad_s", "tau_s", "oadev_rad_s", "rad/s"),
    ("tau;allan_deviation", "tau", "allan_deviation", None),
])
def test_columns_are_found_by_name_case_insensitively(tmp_path: Path, header: str, tau: str,
                                                      dev: str, unit: str | None) -> None:
    sep = next((c for c in "\t;," if c in header), " ")
    t = read_curve_table(_write(tmp_path, f"# comment\n{header}\n1{sep}0.5\n2{sep}0.4\n"))
    assert t.columns["tau"] == tau and t.columns["dev"] == dev and t.unit == unit
    assert t.tau.tolist() == [1.0, 2.0] and t.dev is not None and t.dev.tolist() == [0.5, 0.4]
    assert t.layout == "table" and t.where(0) == "line 3"


def test_the_estimator_follows_the_column_name(tmp_path: Path) -> None:
    assert read_curve_table(_write(tmp_path, "tau,totdev\n1,2\n")).kind == "totdev"
    assert read_curve_table(_write(tmp_path, "tau,dev\n1,2\n")).kind is None
    assert read_curve_table(_write(tmp_path, "tau,oavar\n1,4\n")).kind == "oadev"


def test_optional_columns_bounds_and_fogts_csv_names(tmp_path: Path) -> None:
    t = read_curve_table(_write(tmp_path, "tau,m,n,dev,ci_low,ci_high,edf,alpha,fit\n"
                                          "0.1,1,999,0.5,0.45,0.55,900,0,0.5\n"))
    assert {"m", "terms", "low", "high", "edf", "alpha"} <= set(t.numbers)
    assert t.numbers["terms"].tolist() == [999.0]


def test_smac_header_gives_fs_n_and_the_estimator() -> None:
    t = read_curve_table(shared_path("allan_curves", "smac_avar", "ln200_av.csv"))
    assert t.layout == "smac" and t.kind == "oadev"   # type 'mo': maximal overlap
    assert t.meta == {"fs_hz": 400.0, "n_samples": 8640000}
    assert t.columns["low"] == "adev_lci" and t.columns["errors"] == "errors"
    assert t.var is not None and t.channel is not None and t.channel[0] == "Gyro. X"


def test_stable32_file_as_written() -> None:
    """PHASE.DAT octave oadev: taus, sigmas, alphas and bounds as in the file; 1001 phase
    points are 1000 rate samples."""
    t = read_curve_table(shared_path("stable32", "phasedat", "phase_dat_oadev_octave.txt"))
    ref = stable32_table("phasedat", "phase_dat_oadev_octave.txt")
    assert t.layout == "stable32" and t.kind == "oadev"
    assert t.meta["n_samples"] == 1000 and t.meta["confidence"] == 0.683
    np.testing.assert_array_equal(t.tau, ref[:, 1])
    assert t.dev is not None
    np.testing.assert_array_equal(t.dev, ref[:, 5])
    np.testing.assert_array_equal(t.numbers["alpha"], ref[:, 3])
    np.testing.assert_array_equal(t.numbers["low"], ref[:, 4])


def test_stable32_zero_bounds_mean_none() -> None:
    t = read_curve_table(shared_path("stable32", "ocxo", "stable32_adev_alltau.txt"))
    assert t.kind == "adev" and "low" not in t.numbers
    assert t.meta["n_samples"] == 19982   # frequency data: one rate sample per point


@pytest.mark.parametrize(("text", "match"), [
    ("time,gyro_x\n0,1\n0.01,2\n", r"looks like a recording, not an Allan curve \(columns: "
                                  r"time, gyro_x\); run 'fogts allan' on it"),
    ("0 1\n1 2\n", "looks like a recording"),
    ("period,adev\n1,2\n", r"has no tau column; columns are: period, adev; name it one of tau,"),
    ("tau,value\n1,2\n", r"has no deviation or variance column; columns are: tau, value; "
                         r"name the deviation one of adev, oadev"),
    ("", r"is empty"),
    ("tau,adev\n1,abc\n", r"column 'adev' has non-numeric value 'abc' at data row 0 \(line 2"),
])
def test_refusals_name_the_file_and_what_is_allowed(tmp_path: Path, text: str,
                                                    match: str) -> None:
    with pytest.raises(DataError, match=match):
        read_curve_table(_write(tmp_path, text))


def test_missing_file_directory_and_recording_formats(tmp_path: Path) -> None:
    with pytest.raises(DataError, match=r"curve file not found: '.*nope.csv'"):
        read_curve_table(tmp_path / "nope.csv")
    with pytest.raises(DataError, match="is a directory"):
        read_curve_table(tmp_path)
    np.save(tmp_path / "r.npy", np.zeros(3))
    with pytest.raises(DataError, match=r"is a recording format \(\.npy\); a curve file is a "
                                        r"text table of tau and the deviation"):
        read_curve_table(tmp_path / "r.npy")


def test_stable32_refusals(tmp_path: Path) -> None:
    head = "# Sigma Type: {}\n#  AF        Tau        #    Alpha  Min Sigma  Sigma  Max Sigma\n"
    row = "1 1.0 999 0 0.28 0.29 0.30\n"
    with pytest.raises(DataError, match=r"Stable32 Sigma Type 'MTIE' is not an estimator "
                                        r"fogts reads; allowed: allan, overlapping allan"):
        read_curve_table(_write(tmp_path, head.format("MTIE") + row, "s.txt"))
    with pytest.raises(DataError, match="a Stable32 table has 7 columns .* this one has 6"):
        read_curve_table(_write(tmp_path, head.format("Allan") + "1 1.0 999 0 0.28 0.29\n",
                                "s.txt"))
