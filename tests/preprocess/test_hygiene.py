"""fogts.preprocess.hygiene: the gap policies and the DataQuality record of assess_run."""

from __future__ import annotations

import numpy as np
import pandas as pd
import pytest

from fogts.errors import DataError
from fogts.io.reader import read_run
from fogts.preprocess.hygiene import assess_run


def _gappy_frame() -> pd.DataFrame:
    t = np.r_[np.arange(3000), np.arange(3100, 9000)] / 100.0
    rate = np.random.default_rng(11).standard_normal(t.size)
    return pd.DataFrame({"time": t, "rate_deg_h": rate})


def test_assess_run_gap_policies() -> None:
    run = read_run(_gappy_frame())
    kept, q = assess_run(run)
    assert kept is run and q.gaps.n_gaps == 1
    assert any("analysed as if the samples were regular" in w for w in q.warnings())
    split, q = assess_run(run, gaps="split")
    assert split.n == 5900 and q.segment == (3000, 8900)
    assert split.time[0] == 0.0 and split.sampling is not None and split.sampling.n_gaps == 0
    assert "gaps='split': analysing the longest regular segment, rows 3000..8899" in \
        q.warnings()[0]
    _, q = assess_run(run, gaps="ignore")
    assert q.warnings() == [] and q.to_dict()["gaps"]["n_gaps"] == 1
    with pytest.raises(DataError, match=r"1 gap\(s\) in the time base .*gaps='error' "
                                        r"refuses it: pass gaps='split'"):
        assess_run(run, gaps="error")
    with pytest.raises(DataError, match="gaps must be one of warn, error, split, ignore"):
        assess_run(run, gaps="skip")  # type: ignore[arg-type]


def test_assess_run_units_and_dict() -> None:
    run = read_run(np.random.default_rng(0).standard_normal(500), fs_hz=10.0)
    _, q = assess_run(run)
    assert q.units_source == "assumed"
    assert q.warnings()[0].startswith("no unit in the rate column(s) 'rate'; assuming deg/h")
    d = q.to_dict()
    assert d["units_source"] == "assumed" and d["glitches"][0]["n_events"] == 0
    assert q.glitch_count("rate") == 0 and q.glitch_count("absent") == 0
    run = read_run(np.random.default_rng(0).standard_normal(500), fs_hz=10.0, units="deg/s")
    _, q = assess_run(run)
    assert q.warnings() == [] and q.summary() == "no data-quality issue found"
    assert q.to_frame().empty


def test_accelerometer_axes_keep_their_unit_in_the_quality_record() -> None:
    """The "no unit in the rate column(s)" warning names the gyro columns only, and the
    glitch reports of accelerometer axes carry their unit (g), not the rate unit."""
    rng = np.random.default_rng(5)
    n = 3000
    frame = pd.DataFrame({"time": np.arange(n) / 100.0, "gyro_x": rng.normal(size=n),
                          "acc_x": 0.01 * rng.normal(size=n),
                          "acc_z": 1.0 + 0.01 * rng.normal(size=n)})
    _, q = assess_run(read_run(frame))
    assert q.warnings()[0].startswith("no unit in the rate column(s) 'gyro_x'; assuming deg/h")
    assert "acc_x" not in q.warnings()[0]
    units = {g.axis: g.units for g in q.glitches}
    assert units == {"gyro_x": "deg/h", "acc_x": "g", "acc_z": "g"}
    assert [g["units"] for g in q.to_dict()["glitches"]] == ["deg/h", "g", "g"]


def test_glitch_wording_with_and_without_replacement() -> None:
    from fogts.preprocess.hygiene import GLITCHES_KEPT, glitches_replaced

    assert GLITCHES_KEPT.startswith("kept in the analysis")
    assert glitches_replaced(5.5) == ("outliers=5.5: samples beyond 5.5 robust sigmas are "
                                      "replaced before the analysis (counted below)")


def unnamed_gappy_frame() -> pd.DataFrame:
    """10 min at 10 Hz in a column without a unit, 1 s missing after t = 300 s and one
    spike at t = 100 s: every finding of DataQuality.warnings() that suggests an argument.
    The command line's side is tests/cli/test_hygiene.py's
    ``test_quality_warnings_name_the_options``."""
    t = np.r_[np.arange(3000), np.arange(3010, 6010)] / 10.0
    rate = np.random.default_rng(8).standard_normal(t.size)
    rate[1000] += 40.0
    return pd.DataFrame({"time": t, "rate": rate})


#: Each warning's suggestion in Python: the keywords of read_run/assess_run/AllanSettings.
QUALITY_KEYWORDS = {
    "units": "; assuming deg/h; pass units= (deg/h, deg/s, rad/s, arcsec/s)",
    "warn": "; analysed as if the samples were regular (gaps='split' analyses the longest "
            "regular segment, gaps='error' refuses the file)",
    "nan": "; gaps='nan': the whole record on the regular grid, missing samples as NaN",
    "split": "; gaps='split': analysing the longest regular segment, rows 0..2999",
    "kept": "; kept in the analysis (outliers=K replaces samples beyond K robust sigmas)",
}


def test_quality_warnings_name_the_keywords() -> None:
    """In Python the data-quality findings name the keywords (``units=``, ``gaps='split'``,
    ``outliers=K``), in the warnings and in to_dict(), never an option (``--units``)."""
    frame = unnamed_gappy_frame()
    lines: list[str] = []
    for policy in ("warn", "nan", "split"):
        _, q = assess_run(read_run(frame), gaps=policy)  # type: ignore[arg-type]
        assert q.to_dict()["warnings"] == q.warnings()
        lines += q.warnings()
        assert any(QUALITY_KEYWORDS[policy] in w for w in q.warnings()), q.warnings()
    for finding in ("units", "kept"):
        assert any(QUALITY_KEYWORDS[finding] in w for w in lines), finding
    assert not any("--" in w for w in lines)


def test_grid_note_counts_the_samples_gaps_nan_adds() -> None:
    # 1 s missing at 10 Hz: the regular grid has 10 points more than the samples read
    frame = unnamed_gappy_frame()
    run, q = assess_run(read_run(frame), gaps="nan")
    assert run.n == q.n_input + 10 and int(np.isnan(run.axis(0)).sum()) == 10
    assert q.grid_note(run.n) == "; 10 of them missing (NaN) in the time stamps' gaps"
    for policy in ("warn", "split"):
        other, q2 = assess_run(read_run(frame), gaps=policy)  # type: ignore[arg-type]
        assert q2.grid_note(other.n) == ""


@pytest.mark.parametrize("name", ["position_deg", "Position", "position_degrees"])
def test_a_position_column_says_the_record_is_not_static(name: str) -> None:
    """A four-position north-seeking record (a position column beside the rate) was analysed
    as a static record and its K reported as measured: the record turns between positions,
    and the warning names the column and points to fogts northfind.  Read as an axis (as
    northfind reads it), no warning; a record without one, none."""
    rng = np.random.default_rng(5)
    pos = np.repeat([0, 90, 180, 270], 50)
    frame = pd.DataFrame({"time": np.arange(pos.size, dtype=float), name: pos,
                          "rate_deg_h": 10 * np.cos(np.radians(pos + 30)) +
                          rng.standard_normal(pos.size)})
    _, q = assess_run(read_run(frame))
    assert q.position_column == name
    said = [w for w in q.warnings() if "turn-table" in w]
    assert said == [f"column {name!r} holds turn-table positions: the record is not static "
                    "(it turns between positions), so its Allan curve and noise terms (K "
                    "above all) measure the steps between the positions' rates; for "
                    "north-finding use fogts northfind, or analyse one position's rows"]
    assert said[0] in q.to_dict()["warnings"]
    _, q = assess_run(read_run(frame, rate_column=["rate_deg_h", name]))
    assert q.position_column is None
    _, q = assess_run(read_run(frame.drop(columns=name)))
    assert q.position_column is None and not any("turn-table" in w for w in q.warnings())


def test_burst_logged_quality_line_is_the_read_warning() -> None:
    """One wording for burst-logged stamps: the data-quality line is the read's warning
    (:func:`fogts.io.timebase.burst_logging_text`), and gaps='error' says it too."""
    import warnings as _warnings

    from fogts.errors import DataQualityWarning
    from fogts.io.reader import read_run
    from fogts.io.timebase import burst_logging_text
    from fogts.preprocess.hygiene import assess_run
    from tests.conftest import shared_path

    with _warnings.catch_warnings(record=True) as caught:
        _warnings.simplefilter("always", DataQualityWarning)
        run = read_run(shared_path("imu", "mpu6050_gyro_temp_converted.csv.gz"))
    said = [str(w.message) for w in caught if "bursts" in str(w.message)]
    _, quality = assess_run(run, gaps="warn", glitches=False)
    line = burst_logging_text(run.fs_hz)
    assert said == [f"{run.source}: {line}"] and line in quality.warnings()
    with pytest.raises(DataError, match="the time stamps are logged in bursts: the sample "
                                        r"rate is the mean step's, .*13397 such step\(s\)"):
        assess_run(run, gaps="error", glitches=False)
