"""Read gyro recordings into a :class:`~fogts.io.run.Run`.

Input files are opened only here and in the format families this module dispatches to.
Supported inputs:

* delimited text, optionally gzip-compressed (:mod:`fogts.io.text`);
* Parquet, NumPy ``.npy``/``.npz`` (:mod:`fogts.io.arrays`), MATLAB ``.mat``
  (:mod:`fogts.io.matlab`);
* a pandas DataFrame or Series (a DatetimeIndex or TimedeltaIndex gives the time base),
  or a plain array with ``fs_hz``.

A source is loaded into a :class:`~fogts.io.table.Table`, whose columns then get their roles
(:mod:`fogts.io.columns`), their missing cells the ``nan=`` policy (:mod:`fogts.io.missing`)
and the record its time base and sample rate (:mod:`fogts.io.timebase`).  Nothing is dropped
silently: a non-numeric cell, NaN or inf is an error that names the column, the data row
and the file line.
"""

from __future__ import annotations

import dataclasses
import json
import os
from collections.abc import Callable, Sequence
from pathlib import Path
from typing import Any

import numpy as np
import pandas as pd

from fogts._typing import FloatArray, IntArray
from fogts._validate import check_positive, note_sum
from fogts.errors import DataError, InsufficientDataError
from fogts.io.accel import accel_unit
from fogts.io.angle import ANGLE_UNIT_RATE, input_kind, rate_unit_of_angle, to_rate
from fogts.io.arrays import array_table, frame_table, npy_table, npz_table, parquet_table
from fogts.io.columns import assign_roles, rate_unit, sidecar_unit
from fogts.io.limits import check_regular_file, read_capped
from fogts.io.matlab import mat_table
from fogts.io.missing import NAN_POLICIES, apply_missing_drop, interpolate_missing, missing_report
from fogts.io.rosbag import is_ros2_bag, rosbag_table
from fogts.io.run import MissingReport, RegularTime, Run
from fogts.io.table import MIN_SAMPLES, Table, numeric_column
from fogts.io.text import text_file_table
from fogts.io.timebase import Steps, sample_rate, sampling_report, time_base
from fogts.units import parse_accel_unit, parse_rate_unit

__all__ = ["MIN_SAMPLES", "read_json", "read_run", "read_yaml"]

#: Readers of binary formats by (lower-case) last file suffix; any other file is read as
#: text.  Each takes the path of a regular file and returns a Table.  Further formats (a
#: ROS bag reader) plug in here the same way.
FILE_READERS: dict[str, Callable[[Path], Table]] = {
    ".parquet": parquet_table,
    ".pq": parquet_table,
    ".npy": npy_table,
    ".npz": npz_table,
    ".mat": mat_table,
}


# Long only by its numpydoc docstring (every option and format); the body validates the
# options, loads the table and hands it to _table_to_run.
def read_run(
    source: str | os.PathLike[str] | pd.DataFrame | pd.Series | np.ndarray,
    *,
    rate_column: str | Sequence[str] | None = None,
    time_column: str | None = None,
    temperature_column: str | None = None,
    fs_hz: float | None = None,
    units: str | None = None,
    nan: str = "error",
    topic: str | None = None,
    accel_column: str | Sequence[str] | None = None,
    accel_units: str | None = None,
    input: str | None = None,
) -> Run:
    """Read a static gyro recording.

    Parameters
    ----------
    source : path, DataFrame, Series or ndarray
        A file (text, ``.gz``, Parquet, ``.npy``/``.npz``, MATLAB ``.mat``, a ROS 1
        ``.bag``), a ROS 2 bag directory, a frame, a Series or an array.
    rate_column : str or sequence of str, optional
        Rate column(s).  Default: detected by name (``rate``, ``gyro*``, ``fog``, ``omega``,
        ``w``, ...).  Several rate columns give a multi-axis Run.
    time_column : str, optional
        Time column, in seconds or ISO-8601 date-times.  Default: detected by name
        (``time``, ``t``, ``timestamp``, ``time_s``, ...).
    temperature_column : str, optional
        Temperature column in degC.  Default: detected by name (``T``, ``temp*``, ...).
    fs_hz : float, optional
        Sample rate in Hz.  Overrides the median time step; required without a time base.
    units : str, optional
        Rate unit (``deg/h``, ``deg/s``, ``rad/s``, ``arcsec/s``).  Default: taken from a
        unit hint in the column name (``gyro_x_deg_s``), else ``deg/h`` (and
        ``Run.units_source`` is ``"assumed"``).
    nan : {"error", "drop", "interpolate"}
        Empty, NaN and infinite cells: an error naming the first one (default), rows
        dropped (with a time column they become gaps; without one the time base keeps the
        row numbers, so they are gaps too), or interpolated linearly in time.  What was
        done is recorded in ``Run.missing``.  Non-numeric text is always an error.
    topic : str, optional
        ROS bags: the ``sensor_msgs/Imu`` topic (needed when the bag has several).
    accel_column : str or sequence of str, optional
        Accelerometer column(s), analysed as further axes after the rate axes.  Default:
        detected by name (``acc*``, ``ax``, ``linear_acceleration_*``; see
        :mod:`fogts.io.accel`) when ``rate_column`` is not given; ``[]`` reads none.
    accel_units : str, optional
        Their unit (``m/s^2``, ``g``, ``mg``, ``ug``).  Default: from a hint in the names
        (``acc_x_mps2``, ``accel_g``), else from the length of the mean vector (gravity),
        else m/s^2 (``Run.accel_units_source`` says which).
    input : {"rate", "increment", "angle"}, optional
        What the rate columns hold (:mod:`fogts.io.angle`).  Default: from the names
        (``dtheta``, ``delta_angle``: increments; ``angle``, ``theta``: angle), else rate.
        For angles ``units`` may be an angle unit (``deg``, ``rad``, ``arcsec``).

    Returns
    -------
    Run

    Raises
    ------
    DataError
        Unreadable, non-numeric, non-finite or non-monotonic input, or an unknown column.
    InsufficientDataError
        Fewer than :data:`MIN_SAMPLES` samples.

    Examples
    --------
    >>> import numpy as np
    >>> run = read_run(np.zeros(10) + np.arange(10) % 3, fs_hz=10.0)
    >>> run.n, run.fs_hz, run.units
    (10, 10.0, 'deg/h')
    """
    if fs_hz is not None:
        fs_hz = check_positive("fs_hz", fs_hz)
    if units is not None:
        units = ANGLE_UNIT_RATE.get(str(units).strip().lower(), units)
    unit = parse_rate_unit(units) if units is not None else None
    acc_unit = parse_accel_unit(accel_units, "accel_units") if accel_units is not None else None
    if nan not in NAN_POLICIES:
        raise DataError(f"nan must be one of {', '.join(NAN_POLICIES)}; got {nan!r}")
    table = _load_table(source, topic)
    if isinstance(source, str | os.PathLike) and table.sidecar_unit is None:
        table = dataclasses.replace(table, sidecar_unit=sidecar_unit(Path(source)))
    options: dict[str, Any] = {"rate_column": rate_column, "time_column": time_column,
                               "temperature_column": temperature_column, "fs_hz": fs_hz,
                               "units": unit, "nan": nan, "accel_column": accel_column,
                               "accel_units": acc_unit, "input": input}
    try:
        return _table_to_run(table, **options)
    except DataError:
        if table.reparse is None:
            raise
        reparsed = dataclasses.replace(table.reparse(), sidecar_unit=table.sidecar_unit)
        return _table_to_run(reparsed, **options)  # raises again, naming the line


def read_json(path: str | os.PathLike[str], what: str = "JSON file") -> Any:
    """Load a JSON document (a saved model, a noise specification) with clear errors.

    Examples
    --------
    >>> import tempfile, pathlib
    >>> p = pathlib.Path(tempfile.mkdtemp()) / "m.json"
    >>> _ = p.write_text('{"a": 1}')
    >>> read_json(p)
    {'a': 1}
    """
    source = _document_path(path, what)
    try:
        return json.loads(read_capped(source, compressed=False).decode("utf-8"))
    except (json.JSONDecodeError, UnicodeDecodeError) as exc:
        raise DataError(f"{what} {str(source)!r} is not valid JSON: {exc}") from None


def read_yaml(path: str | os.PathLike[str], what: str = "YAML file") -> Any:
    """Load a YAML document (a datasheet specification) with PyYAML's safe loader and clear
    errors (JSON is YAML too).

    Examples
    --------
    >>> import tempfile, pathlib
    >>> p = pathlib.Path(tempfile.mkdtemp()) / "spec.yaml"
    >>> _ = p.write_text("N: 0.15  # deg/sqrt(h)" + chr(10) + "B: 10" + chr(10))
    >>> read_yaml(p)
    {'N': 0.15, 'B': 10}
    """
    import yaml

    source = _document_path(path, what)
    try:
        return yaml.safe_load(read_capped(source, compressed=False).decode("utf-8"))
    except (yaml.YAMLError, UnicodeDecodeError) as exc:
        reason = " ".join(str(exc).split())
        raise DataError(f"{what} {str(source)!r} is not valid YAML: {reason}") from None


def _document_path(path: str | os.PathLike[str], what: str) -> Path:
    """``path`` checked as a readable regular file (a small document)."""
    source = Path(path)
    if not source.exists():
        raise DataError(f"{what} not found: {str(source)!r}")
    if source.is_dir():
        raise DataError(f"{what} {str(source)!r} is a directory, not a file")
    check_regular_file(source, what)
    return source


def _load_table(source: Any, topic: str | None = None) -> Table:
    if isinstance(source, pd.Series):
        name = str(source.name) if source.name is not None else "rate"
        return frame_table(source.to_frame(name=name), "<Series>")
    if isinstance(source, pd.DataFrame):
        return frame_table(source, "<DataFrame>")
    if isinstance(source, np.ndarray):
        return array_table(source, "<array>", fs_hz=None)
    if isinstance(source, str | os.PathLike):
        return _file_table(Path(source), topic)
    raise DataError(f"source must be a file path, DataFrame, Series or ndarray; "
                    f"got {type(source).__name__}")


def _file_table(path: Path, topic: str | None = None) -> Table:
    """Read a file by its last suffix (:data:`FILE_READERS`, else text), or a ROS bag
    (:mod:`fogts.io.rosbag`); only regular files (and ROS 2 bag directories), within the
    input limits (:mod:`fogts.io.limits`)."""
    if is_ros2_bag(path) or path.suffix.lower() == ".bag":
        if not path.is_dir():
            check_regular_file(path)
        return rosbag_table(path, topic)
    if topic is not None:
        raise DataError(f"topic is for ROS bags; {str(path)!r} is not one")
    check_regular_file(path)
    suffixes = [s.lower() for s in path.suffixes]
    read = FILE_READERS.get(suffixes[-1] if suffixes else "", text_file_table)
    try:
        return read(path)
    except PermissionError:
        raise DataError(f"cannot read {str(path)!r}: permission denied") from None


def _table_to_run(table: Table, *, rate_column: str | Sequence[str] | None,
                  time_column: str | None, temperature_column: str | None,
                  fs_hz: float | None, units: str | None, nan: str = "error",
                  accel_column: str | Sequence[str] | None = None,
                  accel_units: str | None = None, input: str | None = None) -> Run:
    roles = assign_roles(table, rate_column, time_column, temperature_column, accel_column)
    kind = input_kind(input, roles.gyro)
    if kind != "rate" and roles.accel:
        raise DataError(f"input={kind!r} applies to angle columns; the accelerometer columns "
                        f"{', '.join(roles.accel)} cannot be read with them: pass "
                        "accel_column=[] (or read them separately)")
    n = table.frame.shape[0]
    if n < MIN_SAMPLES:
        raise InsufficientDataError(f"{table.source} has {n} data row(s); at least "
                                    f"{MIN_SAMPLES} are needed")
    missing: MissingReport | None = None
    kept_rows: IntArray | None = None
    if nan != "error":
        table, missing, kept_rows = apply_missing_drop(table, roles, nan)
    rate_cols = [numeric_column(table, c, missing_ok=nan == "interpolate") for c in roles.rate]
    temperature = (numeric_column(table, roles.temperature, missing_ok=nan == "interpolate")
                   if roles.temperature else None)
    time, start, steps = time_base(table, roles.time)
    if fs_hz is None and steps is None and table.fs_hz is None:
        cols = ", ".join(table.frame.columns)
        raise DataError(f"no time column found (columns are: {cols}) and no sample rate "
                        "given; pass fs_hz= or add a time column")
    if steps is not None:  # one median for both uses
        fs, fs_source = steps.sample_rate(fs_hz, table.fs_hz, table.source)
    else:
        fs, fs_source = sample_rate(None, fs_hz, table.fs_hz, table.source)
    if time is None and kept_rows is not None and kept_rows.size < n:
        # Dropped rows of a record without time stamps stay visible as gaps.
        time = kept_rows / fs
        steps = Steps(np.diff(time))
    # Without stamps the time base is k / fs: formed on first use of Run.time, not here.
    rows = table.frame.shape[0]
    if nan == "interpolate":
        at = time if time is not None else RegularTime(rows, fs).array()
        rate_cols, temperature, missing = _interpolate_columns(rate_cols, temperature, at,
                                                               roles)
        del at
    rate_cols, angle = to_rate(kind, rate_cols, float(fs))
    if kind == "angle":  # n angles give n - 1 rates, each timed at the start of its step
        rows -= 1
        time, steps = (time[:-1] if time is not None else None,
                       Steps(steps.array()[:-1]) if steps is not None else None)
        temperature = temperature[:-1] if temperature is not None else None
    _check_not_constant(roles.rate, rate_cols)
    rate = rate_cols[0] if len(rate_cols) == 1 else np.column_stack(rate_cols)
    angle_unit = rate_unit_of_angle(None, roles.gyro) if kind != "rate" and not units else None
    unit, unit_source = ((angle_unit, "column name") if angle_unit is not None else
                         rate_unit(units, roles.gyro, table.unit_hint, table.sidecar_unit,
                                   table.source))
    axis_units, acc_source = _axis_units(roles, unit, rate_cols, accel_units, table.accel_unit)
    if not roles.gyro:
        unit, unit_source = axis_units[0], acc_source
    run = Run(
        rate=np.ascontiguousarray(rate, dtype=np.float64),
        time=time if time is not None else RegularTime(rows, fs),  # type: ignore[arg-type]
        fs_hz=float(fs),
        units=unit,
        axes=roles.rate,
        temperature=temperature,
        columns=tuple(table.frame.columns),
        source=table.source,
        sampling=(steps.report(float(fs), fs_source) if steps is not None
                  else sampling_report(None, float(fs), fs_source)),
        start_time=start,
        comments=table.comments,
        units_source=unit_source,
        missing=missing,
        axis_units=axis_units,
        accel_units_source=acc_source,
        input_kind=kind,
        angle=angle,
    )
    if nan == "error" and kind == "rate":
        _pass_on_sum(table, roles.rate, run.rate)
    return run


def _pass_on_sum(table: Table, rate_columns: Sequence[str], rate: FloatArray) -> None:
    """Record the reader's sum of a single rate column for ``rate``, that column unchanged
    (:func:`fogts._validate.note_sum`), so the analysis need not sum it again."""
    if table.sums is not None and len(rate_columns) == 1:
        total = table.sums.get(rate_columns[0])
        if total is not None:
            note_sum(rate, total)


def _interpolate_columns(rate_cols: list[FloatArray], temperature: FloatArray | None,
                         at: FloatArray, roles: Any
                         ) -> tuple[list[FloatArray], FloatArray | None, MissingReport | None]:
    """The rate and temperature columns with their missing cells interpolated linearly in
    time ``at``, and the report of what was filled (``nan="interpolate"``)."""
    filled = [interpolate_missing(c, at, name)
              for c, name in zip(rate_cols, roles.rate, strict=True)]
    missing = missing_report("interpolate", roles.rate, [m for _, m in filled], temperature)
    if temperature is not None:
        temperature = interpolate_missing(temperature, at, str(roles.temperature))[0]
    return [c for c, _ in filled], temperature, missing


def _check_not_constant(names: Sequence[str], columns: list[FloatArray]) -> None:
    """Refuse a rate column whose every value is the same (a stuck logger or wrong column)."""
    for name, col in zip(names, columns, strict=True):
        if np.ptp(col[:1024]) == 0 and np.ptp(col) == 0:  # a varying head settles it
            raise DataError(f"rate column {name!r} is constant (every value is {col[0]:g}); a "
                            "gyro record must vary: check the column or the logger")


def _axis_units(roles: Any, gyro_unit: str, columns: list[Any], given: str | None,
                recorded: str | None) -> tuple[tuple[str, ...], str]:
    """Per-axis units (empty without accelerometer columns) and the accelerometer unit's
    source."""
    if not roles.accel:
        return (), ""
    acc = [c for c, name in zip(columns, roles.rate, strict=True) if name in roles.accel]
    unit, source = accel_unit(given, roles.accel, acc, recorded)
    return tuple(unit if name in roles.accel else gyro_unit for name in roles.rate), source
