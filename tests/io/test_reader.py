"""fogts.io.reader: real recordings end to end, the hostile-input corpus, read_json."""

from __future__ import annotations

import warnings
from pathlib import Path

import pytest

from fogts.errors import DataError, DataQualityWarning, InsufficientDataError
from fogts.io.reader import read_json, read_run
from tests.conftest import shared_path
from tests.io.files import csv_text, write_file

# --------------------------------------------------------------------------- real files


def test_fog_0917_with_leading_and_trailing_comment() -> None:
    run = read_run(shared_path("fog", "fog_0917.txt"))
    assert run.axes == ("fog",)
    assert run.temperature is not None
    assert run.n == 6110  # 6113 lines - 2 comment lines - 1 header: nothing dropped
    assert run.comments == ("#2023/09/17 00:54:04", "#2023/09/17 00:55:06")
    # stamps to 0.1 ms, steps of 9.0 to 11.0 ms whose median is 10.1 ms: the rate is
    # the elapsed time over the steps (1e-9: rounded to 10 digits), not 1/median 99.0099 Hz
    assert run.sampling is not None and run.sampling.fs_source == "mean of jittered steps"
    assert run.fs_hz == pytest.approx((run.n - 1) / (run.time[-1] - run.time[0]), rel=1e-9)
    assert run.rate[0] == pytest.approx(-0.18)
    assert run.temperature[-1] == pytest.approx(36.5)


def test_mpu6050_irregular_time_is_reported() -> None:
    with pytest.warns(DataQualityWarning, match="the time stamps are logged in bursts: "):
        run = read_run(shared_path("imu", "mpu6050_gyro_temp_converted.csv.gz"))
    assert run.n_axes == 3
    assert run.units == "deg/s"  # from the column names gyro_x_deg_s ...
    assert run.temperature is not None
    assert run.sampling is not None
    assert not run.sampling.regular
    assert run.sampling.n_gaps > 1000
    assert run.sampling.max_gap_s == pytest.approx(0.4969, abs=1e-3)
    assert run.fs_hz == pytest.approx(99.32, abs=0.05)  # nominal 100 Hz, 655 s
    assert run.duration_s == pytest.approx(655.1, abs=0.5)


def test_adis_npz_multi_axis_with_fs_key() -> None:
    run = read_run(shared_path("imu", "adis_16405_imu1_gyro.npz"))
    assert run.rate.shape == (1_000_000, 3)
    assert run.axes == ("Gyro. X", "Gyro. Y", "Gyro. Z")
    assert run.fs_hz == 100.0
    assert run.units == "deg/s"  # from the key gyro_deg_s
    assert run.sampling is not None and run.sampling.fs_source == "file"


# --------------------------------------------------------------------------- hostile corpus


HOSTILE: list[tuple[str, str | bytes, dict[str, object], type[Exception], str]] = [
    ("empty.csv", "", {}, DataError, "is empty"),
    ("blank.csv", "\n\n  \n", {}, DataError, "is empty"),
    ("header_only.csv", "time,rate\n", {}, InsufficientDataError, "has a header .* but no data"),
    ("comments_only.csv", "# a\n# b\n", {}, DataError, "no data lines"),
    ("binary.csv", b"\x00\x01\x02\xff\xfe" * 50, {}, DataError, "binary file"),
    ("text.csv", "time,rate\n0,1\n0.1,abc\n0.2,3\n", {}, DataError,
     r"column 'rate' has non-numeric value 'abc' at data row 1 \(line 3"),
    ("empty_cell.csv", "time,rate\n0,1\n0.1,\n0.2,3\n", {}, DataError, "has an empty cell"),
    ("nan.csv", "time,rate\n0,1\n0.1,nan\n0.2,3\n", {}, DataError, "has nan at data row 1"),
    ("inf.csv", "time,rate\n0,1\n0.1,inf\n0.2,3\n", {}, DataError, "has inf at data row 1"),
    ("huge.csv", "time,rate\n0,1\n0.1,1e300\n0.2,3\n", {}, DataError,
     "value 1e\\+300 at data row 1.*overflow"),
    ("constant.csv", "time,rate\n0,5\n0.1,5\n0.2,5\n", {}, DataError, "is constant"),
    ("short.csv", "time,rate\n0,5\n0.1,6\n", {}, InsufficientDataError, "at least 3"),
    ("decreasing.csv", "time,rate\n0,1\n0.2,2\n0.1,3\n0.3,4\n", {}, DataError,
     "'time' is decreasing at data row 2 \\(line 4"),
    ("duplicated.csv", "time,rate\n0,1\n0.1,2\n0.1,3\n0.3,4\n", {}, DataError,
     "'time' is duplicated at data row 2"),
    ("notime.csv", "rate\n1\n2\n3\n", {}, DataError,
     r"no time column found \(columns are: rate\) and no sample rate given; pass "
     r"fs_hz= or add a time column$"),
    ("unknown_col.csv", "time,fog,T\n0,1,2\n0.1,2,3\n0.2,1,3\n", {"rate_column": "rate"},
     DataError, "rate column 'rate' not found; columns are: time, fog, T"),
    ("unknown_time.csv", "time,fog,T\n0,1,2\n0.1,2,3\n0.2,1,3\n", {"time_column": "clock"},
     DataError, "time column 'clock' not found; columns are: time, fog, T"),
    ("ambiguous.csv", "time,a,b\n0,1,2\n0.1,2,3\n0.2,1,3\n", {}, DataError,
     "cannot tell which column is the rate; columns are: time, a, b"),
    ("neg_fs.csv", "rate\n1\n2\n3\n", {"fs_hz": -10.0}, DataError,
     r"fs_hz must be a finite number > 0, got -10.0"),
    ("zero_fs.csv", "rate\n1\n2\n3\n", {"fs_hz": 0}, DataError, "fs_hz must be a finite number > 0"),
    ("bad_unit.csv", "rate\n1\n2\n3\n", {"units": "furlongs/fortnight", "fs_hz": 1.0}, DataError,
     "units must be one of deg/h, deg/s, rad/s, arcsec/s, got 'furlongs/fortnight'"),
    ("ragged.csv", "time,rate\n0,1\n0.1,2,7,8\n0.2,3\n", {}, DataError, "inconsistent numbers"),
    ("badtime.csv", "time,rate\n0,1\nnoon,2\n0.2,3\n", {}, DataError,
     "neither seconds nor ISO-8601|non-numeric value 'noon'"),
    ("both.csv", "time,rate\n0,1\n0.1,2\n0.2,3\n", {"rate_column": "time"}, DataError,
     "cannot be both a rate and a time"),
    ("bad.gz", b"\x1f\x8bnot really gzip", {}, DataError, "not a valid gzip file"),
    ("bad.parquet", b"PAR1 garbage", {}, DataError, "cannot read Parquet file"),
    ("bad.npz", b"PK garbage", {}, DataError, "not a valid .npz file"),
    ("nan_policy.csv", "time,rate\n0,1\n0.1,2\n0.2,3\n", {"nan": "skip"}, DataError,
     "nan must be one of error, drop, interpolate; got 'skip'"),
    ("nan_hint.csv", "time,rate\n0,1\n0.1,nan\n0.2,3\n", {}, DataError,
     r"has nan at data row 1 .*pass nan='drop' or nan='interpolate'$"),
    ("nan_time.csv", "time,rate\n0,1\n,2\n0.2,3\n0.3,4\n", {"nan": "interpolate"},
     DataError, r"time column 'time' has an empty or NaN time stamp at data row 1 .*never "
                r"interpolated: pass nan='drop'"),
    ("all_nan.csv", "time,rate,T\n0,1,nan\n0.1,2,nan\n0.2,3,nan\n", {"nan": "interpolate"},
     DataError, "column 'T' has no finite value at all"),
    ("drop_all.csv", "time,rate\n0,1\n0.1,nan\n0.2,nan\n0.3,\n", {"nan": "drop"},
     InsufficientDataError, r"1 row\(s\) left after dropping 3 with missing cells"),
]


@pytest.mark.parametrize(("name", "content", "kwargs", "exc", "match"), HOSTILE,
                         ids=[h[0] for h in HOSTILE])
def test_hostile_input(tmp_path: Path, name: str, content: str | bytes,
                       kwargs: dict[str, object], exc: type[Exception], match: str) -> None:
    path = write_file(tmp_path, name, content)
    with pytest.raises(exc, match=match):
        read_run(path, **kwargs)  # type: ignore[arg-type]


def test_missing_file(tmp_path: Path) -> None:
    with pytest.raises(DataError, match="file not found: '.*nope.csv'"):
        read_run(tmp_path / "nope.csv")


def test_directory_instead_of_file(tmp_path: Path) -> None:
    with pytest.raises(DataError, match="is a directory, not a file"):
        read_run(tmp_path)


def test_bad_source_type() -> None:
    with pytest.raises(DataError, match="source must be a file path, DataFrame, Series or "
                                        "ndarray; got dict"):
        read_run({"rate": [1, 2, 3]})  # type: ignore[arg-type]


def test_no_warning_on_regular_file(tmp_path: Path) -> None:
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        read_run(write_file(tmp_path, "a.csv", csv_text()))


# --------------------------------------------------------------------------- JSON documents


def test_read_json_errors(tmp_path: Path) -> None:
    with pytest.raises(DataError, match="thermal model not found: '.*m.json'"):
        read_json(tmp_path / "m.json", "thermal model")
    with pytest.raises(DataError, match="is a directory, not a file"):
        read_json(tmp_path)
    (tmp_path / "bad.json").write_text("{not json")
    with pytest.raises(DataError, match="'.*bad.json' is not valid JSON"):
        read_json(tmp_path / "bad.json")


def test_read_yaml_reads_a_specification_and_names_its_errors(tmp_path: Path) -> None:
    from fogts.io.reader import read_yaml

    good = tmp_path / "spec.yaml"
    good.write_text("units: si  # datasheet in SI\nN: 1.2e-4\nB: 5e-5\n")
    assert read_yaml(good) == {"units": "si", "N": 1.2e-4, "B": "5e-5"}  # YAML 1.1: a string
    with pytest.raises(DataError, match="--spec file not found: '.*none.yaml'"):
        read_yaml(tmp_path / "none.yaml", "--spec file")
    with pytest.raises(DataError, match="is a directory, not a file"):
        read_yaml(tmp_path)
    (tmp_path / "bad.yaml").write_text("N: [0.15\nB: 10\n")
    with pytest.raises(DataError, match=r"'.*bad.yaml' is not valid YAML: .*line \d"):
        read_yaml(tmp_path / "bad.yaml")


def test_a_time_order_error_shows_the_stamps_as_the_file_has_them(tmp_path: Path) -> None:
    """The stamps are rebased to the first one internally; the error quotes the file's own
    values (the audit's FOG copy said t=0.999 after t=1.0094 for 2.1597 after 2.1701)."""
    path = tmp_path / "late.csv"
    path.write_text("time,rate\n1.1503,1\n2.1701,2\n2.1597,3\n3.2,4\n")
    with pytest.raises(DataError, match=r"'time' is decreasing at data row 2 \(line 4 of .*\): "
                                        r"t=2\.1597 after t=2\.1701; time stamps must be"):
        read_run(path)
