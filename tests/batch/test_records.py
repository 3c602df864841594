"""The records of a batch: option checks and the read settings they give the pipeline."""

from __future__ import annotations

import pytest

from fogts.batch import BatchOptions
from fogts.errors import DataError
from fogts.pipeline import ReadSettings


def test_bad_options() -> None:
    with pytest.raises(DataError, match="kind must be one of .*; got 'xdev'"):
        BatchOptions(kind="xdev")
    with pytest.raises(DataError, match="criterion must be one of .*; got 'r2'"):
        BatchOptions(criterion="r2")
    with pytest.raises(DataError, match="taus must be one of .*; got 'weekly'"):
        BatchOptions(taus="weekly")
    with pytest.raises(DataError, match="detrend must be <= 10, got 11"):
        BatchOptions(detrend=11)
    with pytest.raises(DataError, match="decimate must be >= 1, got 0"):
        BatchOptions(decimate=0)
    with pytest.raises(DataError, match="output_units must be one of deg, si; got 'mrad'"):
        BatchOptions(output_units="mrad")


def test_read_settings_carry_every_input_option() -> None:
    options = BatchOptions(rate_column="x, y", time_column="t", temperature_column="T",
                           fs_hz=5.0, units="deg/s", nan="drop", gaps="split", kind="adev")
    assert options.read_settings == ReadSettings(
        rate_column="x, y", time_column="t", temperature_column="T", fs_hz=5.0,
        units="deg/s", nan="drop", gaps="split")
    assert BatchOptions().read_settings == ReadSettings()


def test_counts_stay_integers_beside_a_failed_run() -> None:
    """audit2: with one failed run in the batch, n_gaps and n_glitches were written 0.0."""
    import io

    from fogts.batch.records import SUMMARY_COLUMNS, rows_frame

    ok = {c: None for c in SUMMARY_COLUMNS} | {"file": "a.csv", "n": 10, "n_gaps": 0,
                                                "n_glitches": 2, "status": "ok"}
    failed = {"file": "b.csv", "status": "error", "error": "too short"}
    frame = rows_frame([ok, failed])
    assert [str(frame[c].dtype) for c in ("n", "n_gaps", "n_glitches")] == ["Int64"] * 3
    buffer = io.StringIO()
    frame.to_csv(buffer, index=False)
    lines = buffer.getvalue().splitlines()
    cells = dict(zip(lines[0].split(","), lines[1].split(","), strict=False))
    assert (cells["n"], cells["n_gaps"], cells["n_glitches"]) == ("10", "0", "2")
