"""Empty, NaN and infinite cells: the ``nan=`` policy of :func:`fogts.io.reader.read_run`.

``"error"`` names the first such cell; ``"drop"`` removes its row (time stamps are never
interpolated, so with a time column the dropped rows become gaps); ``"interpolate"`` fills
rate and temperature linearly in time.  What was done is a
:class:`~fogts.io.run.MissingReport`.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Sequence

import numpy as np

from fogts._typing import FloatArray, IntArray
from fogts.choices import NAN_POLICIES
from fogts.errors import DataError, InsufficientDataError
from fogts.io.columns import Roles
from fogts.io.run import MissingReport
from fogts.io.table import MIN_SAMPLES, Table, numeric_column, where
from fogts.io.timebase import is_numeric_time

__all__ = ["NAN_POLICIES", "apply_missing_drop", "interpolate_missing", "missing_report"]



def apply_missing_drop(table: Table, roles: Roles, policy: str
                       ) -> tuple[Table, MissingReport | None, IntArray | None]:
    """For ``nan="drop"``: remove every row with an empty/NaN/inf cell in a rate,
    temperature or time column (time stamps are never interpolated).

    For ``nan="interpolate"``: refuse an empty or NaN time stamp; the table is unchanged.
    Returns the table, the report (None: nothing dropped) and the rows kept."""
    names = [*roles.rate, *([roles.temperature] if roles.temperature else [])]
    if roles.time is not None and is_numeric_time(table, roles.time):
        names.append(roles.time)
    if policy == "interpolate":
        if roles.time is None or not is_numeric_time(table, roles.time):
            return table, None, None
        names = [roles.time]
    bad_by_col = {c: ~np.isfinite(numeric_column(table, c, missing_ok=True)) for c in names}
    if policy == "interpolate":
        bad = bad_by_col[roles.time]  # type: ignore[index]
        if bad.any():
            row = int(np.argmax(bad))
            raise DataError(f"time column {roles.time!r} has an empty or NaN time stamp at "
                            f"{where(table, row)}; time stamps are never interpolated: pass "
                            "nan='drop'")
        return table, None, None
    bad = np.logical_or.reduce(list(bad_by_col.values()))
    if not bad.any():
        return table, None, None
    rows = np.flatnonzero(bad)
    kept = np.flatnonzero(~bad)
    report = MissingReport(policy, int(rows.size),
                           {c: int(b.sum()) for c, b in bad_by_col.items()},
                           tuple(int(r) for r in rows[:20]))
    frame = table.frame.iloc[kept].reset_index(drop=True)
    lines = table.line_of_row[kept] if table.line_of_row is not None else None
    if frame.shape[0] < MIN_SAMPLES:
        raise InsufficientDataError(f"{table.source}: {frame.shape[0]} row(s) left after "
                                    f"dropping {rows.size} with missing cells; at least "
                                    f"{MIN_SAMPLES} are needed")
    index = table.from_index[kept] if table.from_index is not None else None
    return (dataclasses.replace(table, frame=frame, line_of_row=lines, from_index=index),
            report, kept)


def interpolate_missing(values: FloatArray, time: FloatArray, name: str
                        ) -> tuple[FloatArray, IntArray]:
    """Fill NaN linearly in time (np.interp: the ends take the nearest finite value)."""
    bad = np.isnan(values)
    if not bad.any():
        return values, np.empty(0, dtype=np.int64)
    if bad.all():
        raise DataError(f"column {name!r} has no finite value at all; nan='interpolate' has "
                        "nothing to interpolate from")
    out = values.copy()
    out[bad] = np.interp(time[bad], time[~bad], values[~bad])
    return out, np.flatnonzero(bad)


def missing_report(policy: str, rate_names: Sequence[str], rate_rows: list[IntArray],
                   temperature: FloatArray | None) -> MissingReport | None:
    """What ``nan="interpolate"`` filled: cells per column and the first rows (None: no
    cell was missing)."""
    by_col = {n: int(r.size) for n, r in zip(rate_names, rate_rows, strict=True)}
    all_rows = [*rate_rows]
    if temperature is not None:
        t_rows = np.flatnonzero(np.isnan(temperature))
        by_col["temperature"] = int(t_rows.size)
        all_rows.append(t_rows)
    rows = np.unique(np.concatenate(all_rows))
    if rows.size == 0:
        return None
    return MissingReport(policy, int(rows.size), by_col, tuple(int(r) for r in rows[:20]))
