"""Tests for fogts.io.reader: formats, column detection, time base, and the hostile-input corpus."""

from __future__ import annotations

import gzip
import warnings
from pathlib import Path

import numpy as np
import pandas as pd
import pytest

from fogts.errors import DataError, DataQualityWarning, InsufficientDataError
from fogts.io.reader import atomic_path, read_run, write_frame_atomic, write_text_atomic
from tests.conftest import shared_path


def _write(tmp_path: Path, name: str, text: str | bytes) -> Path:
    p = tmp_path / name
    if isinstance(text, bytes):
        p.write_bytes(text)
    else:
        p.write_text(text, encoding="utf-8", newline="")
    return p


def _csv(n: int = 50, fs: float = 10.0, sep: str = ",", header: str = "time,rate,T") -> str:
    rng = np.random.default_rng(1)
    rows = [header.replace(",", sep)]
    for i in range(n):
        rows.append(sep.join([f"{i / fs:.4f}", f"{rng.normal():.6f}", f"{25 + i * 0.01:.3f}"]))
    return "\n".join(rows) + "\n"


# --------------------------------------------------------------------------- real files


def test_fog_0917_with_leading_and_trailing_comment() -> None:
    run = read_run(shared_path("fog", "fog_0917.txt"))
    assert run.axes == ("fog",)
    assert run.temperature is not None
    assert run.n == 6110  # 6113 lines - 2 comment lines - 1 header: nothing dropped
    assert run.comments == ("#2023/09/17 00:54:04", "#2023/09/17 00:55:06")
    assert run.fs_hz == pytest.approx(99.0099, rel=1e-4)
    assert run.rate[0] == pytest.approx(-0.18)
    assert run.temperature[-1] == pytest.approx(36.5)


def test_mpu6050_irregular_time_is_reported() -> None:
    with pytest.warns(DataQualityWarning, match="burst-logged"):
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


# --------------------------------------------------------------------------- formats


@pytest.mark.parametrize("sep", [",", ";", "\t", " "])
def test_separators(tmp_path: Path, sep: str) -> None:
    run = read_run(_write(tmp_path, "a.txt", _csv(sep=sep)))
    assert run.n == 50 and run.fs_hz == pytest.approx(10.0)
    assert run.axes == ("rate",)
    assert run.temperature is not None


def test_semicolon_with_decimal_commas(tmp_path: Path) -> None:
    text = "time;rate;temp\n0,0;1,5;20,1\n0,1;-2,25;20,2\n0,2;3,0;20,3\n0,3;0,5;20,4\n"
    run = read_run(_write(tmp_path, "dc.csv", text))
    np.testing.assert_allclose(run.rate, [1.5, -2.25, 3.0, 0.5])
    assert run.fs_hz == pytest.approx(10.0)


def test_utf8_bom_and_crlf(tmp_path: Path) -> None:
    text = _csv().replace("\n", "\r\n").encode("utf-8")
    run = read_run(_write(tmp_path, "bom.csv", b"\xef\xbb\xbf" + text))
    assert run.columns == ("time", "rate", "T")
    assert run.n == 50


def test_gzip(tmp_path: Path) -> None:
    run = read_run(_write(tmp_path, "a.csv.gz", gzip.compress(_csv().encode())))
    assert run.n == 50


def test_comment_lines_anywhere(tmp_path: Path) -> None:
    lines = _csv().splitlines()
    text = "# logger v1\n" + lines[0] + "\n# mid\n" + "\n".join(lines[1:]) + "\n# end\n"
    run = read_run(_write(tmp_path, "c.csv", text))
    assert run.n == 50
    assert run.comments == ("# logger v1", "# mid", "# end")


def test_parquet_npy_npz(tmp_path: Path) -> None:
    x = np.random.default_rng(0).normal(size=100)
    df = pd.DataFrame({"time": np.arange(100) / 20.0, "gyro": x})
    df.to_parquet(tmp_path / "a.parquet")
    np.save(tmp_path / "a.npy", x)
    np.savez(tmp_path / "a.npz", rate=x, fs_hz=np.float64(20.0))
    for name, kwargs in [("a.parquet", {}), ("a.npy", {"fs_hz": 20.0}), ("a.npz", {})]:
        run = read_run(tmp_path / name, **kwargs)
        np.testing.assert_array_equal(run.rate, x)
        assert run.fs_hz == pytest.approx(20.0)


def test_dataframe_with_datetime_index() -> None:
    idx = pd.date_range("2026-01-01", periods=40, freq="100ms")
    df = pd.DataFrame({"rate": np.arange(40.0) % 7, "temperature": 20.0 + np.arange(40)}, index=idx)
    run = read_run(df)
    assert run.fs_hz == pytest.approx(10.0)
    assert run.start_time == "2026-01-01T00:00:00"
    assert run.time[-1] == pytest.approx(3.9)


def test_series_with_timedelta_index() -> None:
    s = pd.Series(np.arange(30.0) % 5, index=pd.timedelta_range(0, periods=30, freq="20ms"),
                  name="omega")
    run = read_run(s)
    assert run.axes == ("omega",) and run.fs_hz == pytest.approx(50.0)


def test_iso8601_time_column(tmp_path: Path) -> None:
    t = pd.date_range("2026-03-01T10:00:00", periods=20, freq="500ms")
    text = "timestamp,rate\n" + "\n".join(f"{ts.isoformat()},{i % 3}" for i, ts in enumerate(t))
    run = read_run(_write(tmp_path, "iso.csv", text))
    assert run.fs_hz == pytest.approx(2.0)
    assert run.start_time is not None and run.start_time.startswith("2026-03-01T10:00:00")


def test_three_axis_file(tmp_path: Path) -> None:
    rng = np.random.default_rng(3)
    rows = ["t,gyro_x,gyro_y,gyro_z,temp"] + [
        f"{i / 100},{rng.normal()},{rng.normal()},{rng.normal()},30" for i in range(20)]
    run = read_run(_write(tmp_path, "xyz.csv", "\n".join(rows)))
    assert run.axes == ("gyro_x", "gyro_y", "gyro_z")
    assert run.rate.shape == (20, 3)
    assert run.fs_hz == pytest.approx(100.0)


def test_explicit_columns_and_fs_override(tmp_path: Path) -> None:
    run = read_run(_write(tmp_path, "a.csv", _csv()), rate_column="T", time_column="time",
                   fs_hz=12.5, temperature_column="rate")
    assert run.axes == ("T",) and run.fs_hz == 12.5
    assert run.sampling is not None and run.sampling.fs_source == "given"


def test_irregular_time_is_read_and_reported(tmp_path: Path) -> None:
    t = np.arange(100) / 10.0
    t[50:] += 2.0  # one 2.1 s gap after row 49
    text = "time,rate\n" + "\n".join(f"{a},{i % 4}" for i, a in enumerate(t))
    run = read_run(_write(tmp_path, "gap.csv", text))
    assert run.n == 100  # nothing dropped
    assert run.sampling is not None
    assert run.sampling.n_gaps == 1 and run.sampling.gap_rows == (49,)
    assert run.sampling.max_gap_s == pytest.approx(2.1)
    assert not run.sampling.regular


def test_rate_from_float_stamps_is_rounded() -> None:
    df = pd.DataFrame({"time": np.arange(1000) / 10.0, "rate": np.arange(1000) % 7})
    assert read_run(df).fs_hz == 10.0  # 1/median(diff) is 10.000000000000568


def test_huge_but_valid_values_are_read(tmp_path: Path) -> None:
    run = read_run(_write(tmp_path, "h.csv", "time,rate\n0,1e100\n1,-1e100\n2,3e99\n"))
    assert run.rate[0] == 1e100


def test_units_option_and_default() -> None:
    assert read_run(np.arange(5.0), fs_hz=1).units == "deg/h"
    assert read_run(np.arange(5.0), fs_hz=1, units="DPS").units == "deg/s"


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
     r"no time column found \(columns are: rate\).*--fs"),
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
     r"has nan at data row 1 .*pass nan='drop' or nan='interpolate' \(CLI --nan"),
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
    path = _write(tmp_path, name, content)
    with pytest.raises(exc, match=match):
        read_run(path, **kwargs)  # type: ignore[arg-type]


def test_missing_file(tmp_path: Path) -> None:
    with pytest.raises(DataError, match="file not found: '.*nope.csv'"):
        read_run(tmp_path / "nope.csv")


def test_directory_instead_of_file(tmp_path: Path) -> None:
    with pytest.raises(DataError, match="is a directory, not a file"):
        read_run(tmp_path)


def test_pickled_object_array_is_refused(tmp_path: Path) -> None:
    np.save(tmp_path / "obj.npy", np.array([{"a": 1}, 2], dtype=object), allow_pickle=True)
    with pytest.raises(DataError, match="pickled object arrays are never loaded"):
        read_run(tmp_path / "obj.npy", fs_hz=1.0)


def test_npz_without_numeric_arrays(tmp_path: Path) -> None:
    np.savez(tmp_path / "s.npz", names=np.array(["a", "b"]))
    with pytest.raises(DataError, match="holds no numeric 1-D or 2-D array; keys are: names"):
        read_run(tmp_path / "s.npz", fs_hz=1.0)


def test_bad_source_type() -> None:
    with pytest.raises(DataError, match="source must be a file path, DataFrame, Series or "
                                        "ndarray; got dict"):
        read_run({"rate": [1, 2, 3]})  # type: ignore[arg-type]


def test_3d_array_refused() -> None:
    with pytest.raises(DataError, match=r"array must be 1-D \(rate\) or 2-D"):
        read_run(np.zeros((3, 3, 3)), fs_hz=1.0)


def test_bad_iso_stamp(tmp_path: Path) -> None:
    text = "timestamp,rate\n2026-01-01T00:00:00,1\n2026-13-45T99:00:00,2\n2026-01-01T00:00:02,3\n"
    with pytest.raises(DataError, match="neither seconds nor ISO-8601"):
        read_run(_write(tmp_path, "iso.csv", text))


def test_no_warning_on_regular_file(tmp_path: Path) -> None:
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        read_run(_write(tmp_path, "a.csv", _csv()))


# --------------------------------------------------------------------------- atomic writes


def test_atomic_write_keeps_old_file_on_failure(tmp_path: Path) -> None:
    target = tmp_path / "out.txt"
    write_text_atomic(target, "old")
    with pytest.raises(RuntimeError), atomic_path(target) as tmp:
        tmp.write_text("half")
        raise RuntimeError("boom")
    assert target.read_text() == "old"
    assert [p.name for p in tmp_path.iterdir()] == ["out.txt"]  # no temp file left


def test_atomic_write_uses_normal_permissions(tmp_path: Path) -> None:
    import os
    import stat

    umask = os.umask(0o022)
    try:
        write_text_atomic(tmp_path / "p.txt", "x")
    finally:
        os.umask(umask)
    assert stat.S_IMODE((tmp_path / "p.txt").stat().st_mode) == 0o644


def test_write_frame_atomic_roundtrip(tmp_path: Path) -> None:
    df = pd.DataFrame({"time": [0.0, 0.1], "rate": [1.0 / 3.0, 2.0]})
    for name in ("a.csv", "a.parquet", "a.csv.gz"):
        write_frame_atomic(tmp_path / name, df)
        back = pd.read_parquet(tmp_path / name) if name.endswith("parquet") else pd.read_csv(
            tmp_path / name)
        pd.testing.assert_frame_equal(back, df)


def test_write_errors(tmp_path: Path) -> None:
    with pytest.raises(DataError, match="output file must end in .csv"):
        write_frame_atomic(tmp_path / "a.xlsx", pd.DataFrame({"a": [1]}))
    with pytest.raises(DataError, match="output directory does not exist"):
        write_text_atomic(tmp_path / "missing" / "a.txt", "x")


def test_bad_npy_signature(tmp_path: Path) -> None:
    with pytest.raises(DataError, match=r"not a valid .npy file \(wrong signature\)"):
        read_run(_write(tmp_path, "x.npy", b"garbage"), fs_hz=1.0)


def test_read_json_errors(tmp_path: Path) -> None:
    from fogts.io.reader import read_json

    with pytest.raises(DataError, match="thermal model not found: '.*m.json'"):
        read_json(tmp_path / "m.json", "thermal model")
    with pytest.raises(DataError, match="is a directory, not a file"):
        read_json(tmp_path)
    (tmp_path / "bad.json").write_text("{not json")
    with pytest.raises(DataError, match="'.*bad.json' is not valid JSON"):
        read_json(tmp_path / "bad.json")
