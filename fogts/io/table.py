"""A loaded source before its columns are interpreted, and its cells as numbers.

Every format family (:mod:`fogts.io.text`, :mod:`fogts.io.arrays`) loads its input into a
:class:`Table`; :func:`numeric_column` turns one column into float64, naming the column,
the data row and (for text) the file line of the first cell it refuses.
"""

from __future__ import annotations

import re
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
import pandas as pd

from fogts._typing import FloatArray
from fogts.errors import DataError

__all__ = ["MAX_ABS_VALUE", "MIN_SAMPLES", "NUMBER", "Table", "finite_and_bounded", "numeric_column",
           "where"]

#: Fewest samples a Run may have (two time steps are needed to measure the sample rate).
MIN_SAMPLES = 3
#: Magnitude above which a value is treated as corrupt (its square would overflow float64
#: in variance sums).
MAX_ABS_VALUE = 1e150
#: A number as written in a text cell (decimal point or decimal comma, optional exponent).
NUMBER = re.compile(r"^[+-]?(\d+([.,]\d*)?|[.,]\d+)([eE][+-]?\d+)?$")


@dataclass(frozen=True)
class Table:
    """A loaded source before column interpretation."""

    frame: pd.DataFrame
    source: str
    line_of_row: np.ndarray | None  # 1-based file line of each data row (text files)
    comments: tuple[str, ...]
    fs_hz: float | None  # from an .npz ``fs_hz`` key
    from_index: pd.Index | None  # DatetimeIndex/TimedeltaIndex time base
    header: bool
    unit_hint: str = ""  # e.g. an .npz key such as ``gyro_deg_s``
    sidecar_unit: str | None = None  # from a ``<file>.json`` written by fogts simulate
    accel_unit: str | None = None  # fixed by the format (a ROS Imu message: m/s^2)
    # For text parsed by the fast path: re-parse line by line (for error messages that
    # name the file line).
    reparse: Callable[[], Table] | None = None
    # Every column is float64, finite and within MAX_ABS_VALUE (the fast text path checked
    # it while parsing), so numeric_column has nothing left to refuse.
    checked: bool = False
    # ``numpy.sum`` of some columns, taken while they were checked (for
    # fogts._validate.note_sum); None: none taken.
    sums: dict[str, float] | None = None


def where(table: Table, row: int) -> str:
    """``"data row 7 (line 9 of run.csv)"`` for text, ``"row 7"`` otherwise."""
    if table.line_of_row is not None:
        return f"data row {row} (line {int(table.line_of_row[row])} of {table.source})"
    return f"row {row}"


def numeric_column(table: Table, name: str, *, missing_ok: bool = False) -> FloatArray:
    """One column as float64.  Non-numeric text is always an error; empty, NaN and inf
    cells are an error too unless ``missing_ok`` (then they are returned as NaN)."""
    col = table.frame[name]
    if col.dtype.kind in "fiub":
        values = col.to_numpy(dtype=np.float64)
        if table.checked or finite_and_bounded(values):
            return values
        bad_text = np.zeros(values.shape, dtype=bool)
    else:
        text = col.astype(str).str.strip()
        if table.line_of_row is not None and _uses_decimal_comma(text):
            text = text.str.replace(",", ".", regex=False)
        values = pd.to_numeric(text, errors="coerce").to_numpy(dtype=np.float64)
        lowered = text.str.lower()
        allowed = ["nan", "+nan", "-nan"] + (["", "na", "n/a", "null", "none"] if missing_ok
                                             else [])
        bad_text = np.isnan(values) & ~lowered.isin(allowed).to_numpy()
    if bad_text.any():
        row = int(np.argmax(bad_text))
        cell = table.frame[name].iloc[row]
        empty = str(cell).strip() == ""
        shown = "an empty cell" if empty else f"non-numeric value {cell!r}"
        hint = ("; pass nan='drop' or nan='interpolate'" if empty
                else "")
        raise DataError(f"column {name!r} has {shown} at {where(table, row)}{hint}")
    nonfinite = ~np.isfinite(values)
    if missing_ok:
        values = np.where(nonfinite, np.nan, values) if nonfinite.any() else values
    elif nonfinite.any():
        row = int(np.argmax(nonfinite))
        raise DataError(f"column {name!r} has {float(values[row])!r} at {where(table, row)}; fogts "
                        "never drops rows silently: pass nan='drop' or nan='interpolate'")
    huge = np.abs(values) > MAX_ABS_VALUE
    if huge.any():
        row = int(np.argmax(huge))
        raise DataError(f"column {name!r} has the value {values[row]:.6g} at {where(table, row)};"
                        f" magnitudes above {MAX_ABS_VALUE:.0e} overflow variance sums")
    return values


def finite_and_bounded(values: FloatArray) -> bool:
    """True when every value is finite and within :data:`MAX_ABS_VALUE` (two passes that
    allocate nothing: NaN propagates through min and max, and inf shows at an end)."""
    if values.size == 0:
        return False
    lo, hi = values.min(), values.max()
    return bool(np.isfinite(lo) and np.isfinite(hi) and max(-lo, hi) <= MAX_ABS_VALUE)


def _uses_decimal_comma(text: pd.Series) -> bool:
    head = text.head(50)
    return bool(head.str.match(r"^[+-]?\d*,\d+([eE][+-]?\d+)?$").any())
