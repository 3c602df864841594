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
