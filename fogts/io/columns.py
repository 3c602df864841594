"""Column roles and the rate unit: which column is time, rate or temperature, by name or
as given, and the unit from the argument, a ``<file>.json`` sidecar, a unit hint in a column
name (``gyro_x_deg_s``, ``rate[dph]``) or an ``.npz`` key.
"""

from __future__ import annotations

import json
import re
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from pathlib import Path

from fogts.errors import DataError
from fogts.io.accel import is_accel_name
from fogts.io.angle import is_angle_name
from fogts.io.sources import first_stated
from fogts.io.table import Table
from fogts.units import parse_rate_unit

__all__ = ["Roles", "assign_roles", "rate_unit", "sidecar_unit"]

_TIME_NAMES = {"time", "t", "timestamp", "time_s", "times", "time_sec", "sec", "seconds",
               "datetime", "date_time", "elapsed", "elapsed_s", "timestamps", "ts"}
_TEMP_NAMES = {"temp", "temperature", "tmp", "temp_c", "temperature_c", "temp_degc",
               "temperature_degc", "t_degc"}
_RATE_NAMES = {"rate", "gyro", "fog", "omega", "w", "wx", "wy", "wz", "gx", "gy", "gz",
               "angular_rate", "rate_x", "rate_y", "rate_z", "gyr", "gyro_rate", "x", "y", "z"}
_RATE_PREFIXES = ("gyro", "gyr_", "fog", "rate", "omega", "angular_rate", "angular_velocity",
                  "w_", "gx_", "gy_", "gz_")

# Unit hints in column names, e.g. ``gyro_x_deg_s`` or ``rate[dph]``.
_UNIT_HINTS: tuple[tuple[str, str], ...] = (
    ("deg_s", "deg/s"), ("deg/s", "deg/s"), ("dps", "deg/s"),
    ("deg_h", "deg/h"), ("deg/h", "deg/h"), ("dph", "deg/h"),
    ("rad_s", "rad/s"), ("rad/s", "rad/s"),
    ("arcsec_s", "arcsec/s"), ("arcsec/s", "arcsec/s"),
)

#: Largest sidecar JSON read for its unit.
_SIDECAR_MAX_BYTES = 1 << 20


def _norm(name: str) -> str:
    return re.sub(r"[\s.\-()\[\]/]+", "_", name.strip().lower()).strip("_")


def _struct_field(test: Callable[[str], bool]) -> Callable[[str], bool]:
    """``test`` applied to the name, and for a struct path such as ``imu.gyro`` (a MATLAB
    struct field) also to its last part."""
    def judged(name: str) -> bool:
        return test(name) or ("." in name and test(name.rsplit(".", 1)[-1]))
    judged.__doc__ = test.__doc__
    return judged


@_struct_field
def _is_time_name(name: str) -> bool:
    n = _norm(name)
    return (name != "T" and n in _TIME_NAMES) or n.startswith("time")


@_struct_field
def _is_temp_name(name: str) -> bool:
    n = _norm(name)
    return name == "T" or n in _TEMP_NAMES or n.startswith(("temp", "temperature"))


@_struct_field
def _is_rate_name(name: str) -> bool:
    n = _norm(name)
    if n in ("sample_rate", "rate_hz", "fs", "fs_hz"):
        return False
    return n in _RATE_NAMES or n.startswith(_RATE_PREFIXES) or is_angle_name(name)


def _resolve(columns: list[str], name: str, role: str) -> str:
    if name in columns:
        return name
    lowered = {c.lower(): c for c in columns}
    if name.lower() in lowered:
        return lowered[name.lower()]
    if re.fullmatch(r"\d+", name) and int(name) < len(columns):
        return columns[int(name)]
    raise DataError(f"{role} column {name!r} not found; columns are: {', '.join(columns)}")


@dataclass(frozen=True)
class Roles:
    """The time column (None: no time base in the columns), the sensor columns (one per
    axis: the rate columns, then the accelerometer columns), the temperature column (None:
    none) and which of the sensor columns are accelerometers."""

    time: str | None
    rate: tuple[str, ...]
    temperature: str | None
    accel: tuple[str, ...] = ()

    @property
    def gyro(self) -> tuple[str, ...]:
        """The sensor columns that are not accelerometers."""
        return tuple(c for c in self.rate if c not in self.accel)


def assign_roles(table: Table, rate_column: str | Sequence[str] | None,
                 time_column: str | None, temperature_column: str | None,
                 accel_column: str | Sequence[str] | None = None) -> Roles:
    """Given columns (by name, case-insensitive name or position) first, then detection by
    name; a column cannot be both a rate and the time or temperature.  Accelerometer
    columns (:func:`fogts.io.accel.is_accel_name`) are detected only when no rate column
    is given; ``accel_column`` names them (an empty list: none)."""
    cols = list(table.frame.columns)
    time = _resolve(cols, time_column, "time") if time_column else None
    temp = _resolve(cols, temperature_column, "temperature") if temperature_column else None
    if time is None and table.from_index is None and table.header:
        time = next((c for c in cols if _is_time_name(c)), None)
    if temp is None:
        temp = next((c for c in cols if _is_temp_name(c) and c != time), None)
    accel = _accel_columns(cols, accel_column, rate_column, time, temp)
    if rate_column is not None:
        names = [rate_column] if isinstance(rate_column, str) else list(rate_column)
        rate = tuple(_resolve(cols, n, "rate") for n in names)
    else:
        rate = _detect_rate(table, [c for c in cols if c not in accel], time, temp,
                            bool(accel))
    both = set(rate) & set(accel)
    if both:
        raise DataError(f"column {sorted(both)[0]!r} cannot be both a rate and an "
                        "accelerometer column")
    rate = (*rate, *accel)
    clash = {time, temp} & set(rate)
    if clash - {None}:
        raise DataError(f"column {sorted(c for c in clash if c)[0]!r} cannot be both a rate "
                        "and a time/temperature column")
    return Roles(time, rate, temp, accel)


def _accel_columns(cols: list[str], accel_column: str | Sequence[str] | None,
                   rate_column: str | Sequence[str] | None, time: str | None,
                   temp: str | None) -> tuple[str, ...]:
    if accel_column is not None:
        names = [accel_column] if isinstance(accel_column, str) else list(accel_column)
        return tuple(_resolve(cols, n, "accelerometer") for n in names)
    if rate_column is not None:
        return ()
    return tuple(c for c in cols if c not in (time, temp) and is_accel_name(c))


def _detect_rate(table: Table, cols: list[str], time: str | None,
                 temp: str | None, have_accel: bool = False) -> tuple[str, ...]:
    named = tuple(c for c in cols if c not in (time, temp) and _is_rate_name(c))
    if named or have_accel:
        return named
    rest = [c for c in cols if c not in (time, temp)]
    if not table.header:
        # Headerless text: first column is time if it increases, the next is the rate.
        return (rest[0],) if len(rest) == 1 or time is not None else (rest[1],)
    if len(rest) == 1:
        return (rest[0],)
    raise DataError("cannot tell which column is the rate; columns are: "
                    f"{', '.join(cols)}; pass rate_column=")


def _unit_from_names(names: Sequence[str]) -> str | None:
    named = _named_unit(names)
    return None if named is None else named[0]


def _named_unit(names: Sequence[str]) -> tuple[str, str] | None:
    """The unit hinted by the first name that hints one, and that name."""
    for name in names:
        n = _norm(name)
        for hint, unit in _UNIT_HINTS:
            if n.endswith(hint.replace("/", "_")) or f"_{hint.replace('/', '_')}_" in n:
                return unit, name
    return None


def sidecar_unit(path: Path) -> str | None:
    """The rate unit recorded in ``<path>.json`` when fogts wrote it (``fogts simulate``
    records the unit of the file it writes there), else None.  Never raises: a sidecar
    that is absent, large, unreadable or not fogts' own is ignored."""
    side = path.with_name(path.name + ".json")
    try:
        if not side.is_file() or side.stat().st_size > _SIDECAR_MAX_BYTES:
            return None
        doc = json.loads(side.read_text(encoding="utf-8"))
        if not (isinstance(doc, dict) and str(doc.get("generator", "")).startswith("fogts")):
            return None
        return parse_rate_unit(str(doc["units"]))
    except (OSError, ValueError, KeyError, DataError):
        return None


def rate_unit(given: str | None, rate_names: Sequence[str], file_key: str,
              sidecar: str | None = None, source: str = "") -> tuple[str, str]:
    """The rate unit and where it came from (see :attr:`fogts.io.run.Run.units_source`).

    A given unit wins; when the file states another one (its sidecar, a column name or
    an ``.npz`` key), a :class:`~fogts.errors.DataQualityWarning` shows both: a unit
    typed by habit over a file that says otherwise scales every term by up to 3600x.
    """
    if given is not None:
        _check_given_unit(given, _stated_unit(rate_names, file_key, sidecar), source)
    return first_stated((given, "given"), (sidecar, "file metadata"),
                        (lambda: _unit_from_names(rate_names), "column name"),
                        (lambda: _unit_from_names([file_key]) if file_key else None,
                         "file key"),
                        default="deg/h")


def _stated_unit(rate_names: Sequence[str], file_key: str, sidecar: str | None
                 ) -> tuple[str, str] | None:
    """The unit the file itself states and where, in the reader's order of precedence."""
    if sidecar is not None:
        return sidecar, "fogts sidecar"
    for names, what in ((rate_names, "column name"), ([file_key] if file_key else [], "key")):
        named = _named_unit(names)
        if named is not None:
            return named[0], f"{what} {named[1]!r}"
    return None


def _check_given_unit(given: str, stated: tuple[str, str] | None, source: str) -> None:
    if stated is None or stated[0] == given:
        return
    import warnings

    from fogts.errors import DataQualityWarning

    where = f"{source}: " if source else ""
    warnings.warn(f"{where}units = {given} (given) overrides the unit the file states, "
                  f"{stated[0]} (from the {stated[1]}); the given unit is used",
                  DataQualityWarning, stacklevel=4)

