"""Read gyro recordings into a :class:`~fogts.io.run.Run`, and write outputs atomically.

This is the only module that opens input files (DESIGN.md).  Supported inputs:

* delimited text: comma, semicolon (with decimal commas), tab or whitespace separated, with
  ``#`` comment lines anywhere (real FOG loggers write a trailing one), a UTF-8 BOM, CRLF
  line ends, optionally gzip-compressed (``.gz``);
* Parquet (``.parquet``, ``.pq``);
* NumPy ``.npy`` (1-D rate, or 2-D with one column per axis) and ``.npz`` (loaded with
  ``allow_pickle=False``: reading never executes anything from the input);
* a pandas DataFrame or Series (a DatetimeIndex or TimedeltaIndex gives the time base),
  or a plain array with ``fs_hz``.

Nothing is dropped silently: a non-numeric cell, NaN or inf is an error that names the
column, the data row and the file line.
"""

from __future__ import annotations

import dataclasses
import io as _io
import os
import re
import tempfile
import warnings
import zipfile
from collections.abc import Callable, Iterator, Sequence
from contextlib import contextmanager
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
import pandas as pd

from fogts._typing import FloatArray, IntArray
from fogts._validate import check_positive
from fogts.errors import DataError, DataQualityWarning, InsufficientDataError
from fogts.io.limits import check_npy, check_npz, check_regular_file, max_input_bytes, read_capped
from fogts.io.run import MissingReport, Run, SamplingReport
from fogts.units import parse_rate_unit

__all__ = [
    "MIN_SAMPLES",
    "atomic_path",
    "read_json",
    "read_run",
    "sampling_report",
    "write_frame_atomic",
    "write_text_atomic",
]

#: Fewest samples a Run may have (two time steps are needed to measure the sample rate).
MIN_SAMPLES = 3
#: Gap threshold: a time step longer than this multiple of the median step is a gap.
GAP_FACTOR = 1.5
#: Magnitude above which a value is treated as corrupt (its square would overflow float64
#: in variance sums).
MAX_ABS_VALUE = 1e150

_TEXT_SUFFIXES = {".csv", ".txt", ".tsv", ".dat", ".log", ".tab", ""}
_PARQUET_SUFFIXES = {".parquet", ".pq"}

_TIME_NAMES = {"time", "t", "timestamp", "time_s", "times", "time_sec", "sec", "seconds",
               "datetime", "date_time", "elapsed", "elapsed_s", "timestamps", "ts"}
_TEMP_NAMES = {"temp", "temperature", "tmp", "temp_c", "temperature_c", "temp_degc",
               "temperature_degc", "t_degc"}
_RATE_NAMES = {"rate", "gyro", "fog", "omega", "w", "wx", "wy", "wz", "gx", "gy", "gz",
               "angular_rate", "rate_x", "rate_y", "rate_z", "gyr", "gyro_rate"}
_RATE_PREFIXES = ("gyro", "gyr_", "fog", "rate", "omega", "angular_rate", "w_", "gx_", "gy_",
                  "gz_")

# Unit hints in column names, e.g. ``gyro_x_deg_s`` or ``rate[dph]``.
_UNIT_HINTS: tuple[tuple[str, str], ...] = (
    ("deg_s", "deg/s"), ("deg/s", "deg/s"), ("dps", "deg/s"),
    ("deg_h", "deg/h"), ("deg/h", "deg/h"), ("dph", "deg/h"),
    ("rad_s", "rad/s"), ("rad/s", "rad/s"),
    ("arcsec_s", "arcsec/s"), ("arcsec/s", "arcsec/s"),
)


# --------------------------------------------------------------------------- public API


def read_run(
    source: str | os.PathLike[str] | pd.DataFrame | pd.Series | np.ndarray,
    *,
    rate_column: str | Sequence[str] | None = None,
    time_column: str | None = None,
    temperature_column: str | None = None,
    fs_hz: float | None = None,
    units: str | None = None,
    nan: str = "error",
) -> Run:
    """Read a static gyro recording.

    Parameters
    ----------
    source : path, DataFrame, Series or ndarray
        A file (text, ``.gz``, Parquet, ``.npy``/``.npz``), a frame, a Series or an array.
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
    unit = parse_rate_unit(units) if units is not None else None
    if nan not in NAN_POLICIES:
        raise DataError(f"nan must be one of {', '.join(NAN_POLICIES)}; got {nan!r}")
    table = _load_table(source)
    if isinstance(source, str | os.PathLike):
        table = dataclasses.replace(table, sidecar_unit=_sidecar_unit(Path(source)))
    options: dict[str, Any] = {"rate_column": rate_column, "time_column": time_column,
                               "temperature_column": temperature_column, "fs_hz": fs_hz,
                               "units": unit, "nan": nan}
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
    import json

    source = Path(path)
    if not source.exists():
        raise DataError(f"{what} not found: {str(source)!r}")
    if source.is_dir():
        raise DataError(f"{what} {str(source)!r} is a directory, not a file")
    check_regular_file(source, what)
    try:
        return json.loads(read_capped(source, compressed=False).decode("utf-8"))
    except (json.JSONDecodeError, UnicodeDecodeError) as exc:
        raise DataError(f"{what} {str(source)!r} is not valid JSON: {exc}") from None


@contextmanager
def atomic_path(path: str | os.PathLike[str]) -> Iterator[Path]:
    """Yield a temporary path beside ``path``; move it onto ``path`` only on success.

    A reader never sees a half-written file, and a failure leaves any previous file intact.

    Examples
    --------
    >>> import tempfile, pathlib
    >>> target = pathlib.Path(tempfile.mkdtemp()) / "out.txt"
    >>> with atomic_path(target) as tmp:
    ...     _ = tmp.write_text("done")
    >>> target.read_text()
    'done'
    """
    target = Path(path)
    parent = target.parent if str(target.parent) else Path(".")
    if not parent.is_dir():
        raise DataError(f"output directory does not exist: {str(parent)!r}")
    fd, tmp_name = tempfile.mkstemp(prefix=f".{target.name}.", suffix=".tmp" + target.suffix,
                                    dir=parent)
    os.close(fd)
    tmp = Path(tmp_name)
    try:
        yield tmp
        os.chmod(tmp, _default_file_mode())  # mkstemp makes 0600; use the umask like open()
        os.replace(tmp, target)
    finally:
        if tmp.exists():
            tmp.unlink()


def _default_file_mode() -> int:
    umask = os.umask(0)
    os.umask(umask)
    return 0o666 & ~umask


def write_text_atomic(path: str | os.PathLike[str], text: str) -> Path:
    """Write ``text`` (UTF-8) to ``path`` atomically and return the path."""
    with atomic_path(path) as tmp:
        tmp.write_text(text, encoding="utf-8")
    return Path(path)


def write_frame_atomic(path: str | os.PathLike[str], frame: pd.DataFrame) -> Path:
    """Write a DataFrame atomically as CSV (``.csv``, ``.csv.gz``, ``.txt``) or Parquet.

    Floats are written with full (round-trip) precision; the index is not written.
    """
    target = Path(path)
    name = target.name.lower()
    with atomic_path(target) as tmp:
        if name.endswith((".parquet", ".pq")):
            frame.to_parquet(tmp, index=False)
        elif name.endswith((".csv", ".txt", ".csv.gz", ".tsv")):
            sep = "\t" if name.endswith(".tsv") else ","
            frame.to_csv(tmp, index=False, sep=sep,
                         compression="gzip" if name.endswith(".gz") else None)
        else:
            raise DataError(f"output file must end in .csv, .csv.gz, .tsv, .txt or .parquet; "
                            f"got {target.name!r}")
    return target


# --------------------------------------------------------------------------- loading


@dataclass(frozen=True)
class _Table:
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
    # For text parsed by the fast path: re-parse line by line (for error messages that
    # name the file line).
    reparse: Callable[[], _Table] | None = None


def _load_table(source: Any) -> _Table:
    if isinstance(source, pd.Series):
        name = str(source.name) if source.name is not None else "rate"
        return _frame_table(source.to_frame(name=name), "<Series>")
    if isinstance(source, pd.DataFrame):
        return _frame_table(source, "<DataFrame>")
    if isinstance(source, np.ndarray):
        return _array_table(source, "<array>", fs_hz=None)
    if isinstance(source, str | os.PathLike):
        return _file_table(Path(source))
    raise DataError(f"source must be a file path, DataFrame, Series or ndarray; "
                    f"got {type(source).__name__}")


def _frame_table(frame: pd.DataFrame, source: str) -> _Table:
    if frame.shape[1] == 0:
        raise DataError(f"{source} has no columns")
    index = frame.index if isinstance(frame.index, pd.DatetimeIndex | pd.TimedeltaIndex) else None
    out = frame.reset_index(drop=True)
    out.columns = [str(c) for c in out.columns]
    return _Table(out, source, None, (), None, index, header=True)


def _array_table(arr: np.ndarray, source: str, fs_hz: float | None,
                 names: Sequence[str] | None = None) -> _Table:
    if arr.dtype == object:
        raise DataError(f"{source}: object arrays are not supported (pickled data is never "
                        "loaded); save the rate as a numeric array")
    if arr.ndim == 1:
        arr = arr[:, None]
    if arr.ndim != 2:
        raise DataError(f"{source}: array must be 1-D (rate) or 2-D (samples x axes), "
                        f"got shape {arr.shape}")
    if names is None or len(names) != arr.shape[1]:
        names = ["rate"] if arr.shape[1] == 1 else [f"rate_{i}" for i in range(arr.shape[1])]
    frame = pd.DataFrame({str(n): arr[:, i] for i, n in enumerate(names)})
    return _Table(frame, source, None, (), fs_hz, None, header=True)


def _file_table(path: Path) -> _Table:
    """Read a file by its suffix; only regular files, within the input limits
    (:mod:`fogts.io.limits`)."""
    st = check_regular_file(path)
    suffixes = [s.lower() for s in path.suffixes]
    last = suffixes[-1] if suffixes else ""
    try:
        if last in _PARQUET_SUFFIXES:
            if st.st_size > max_input_bytes():
                raise DataError(f"{str(path)!r} is larger than the input limit; oversized "
                                "input is refused (set FOGTS_MAX_INPUT_BYTES to raise it)")
            return _parquet_table(path)
        if last == ".npy":
            _check_magic(path, b"\x93NUMPY", ".npy")
            check_npy(path)
            return _npy_table(path)
        if last == ".npz":
            _check_magic(path, b"PK\x03\x04", ".npz")
            check_npz(path)
            return _npz_table(path)
        with open(path, "rb") as fh:
            gzipped = last == ".gz" or fh.read(2) == b"\x1f\x8b"
    except PermissionError:
        raise DataError(f"cannot read {str(path)!r}: permission denied") from None
    return _text_table(read_capped(path, compressed=gzipped), str(path))


def _parquet_table(path: Path) -> _Table:
    try:
        frame = pd.read_parquet(path)
    except Exception as exc:  # pyarrow raises several unrelated types
        raise DataError(f"cannot read Parquet file {str(path)!r}: {exc}") from None
    table = _frame_table(frame, str(path))
    return _Table(table.frame, str(path), None, (), None, table.from_index, True)


def _check_magic(path: Path, magic: bytes, kind: str) -> None:
    with path.open("rb") as fh:
        head = fh.read(len(magic))
    if head != magic:
        raise DataError(f"{str(path)!r} is not a valid {kind} file (wrong signature)")


def _npy_table(path: Path) -> _Table:
    _check_magic(path, b"\x93NUMPY", ".npy")
    try:
        arr = np.load(path, allow_pickle=False)
    except ValueError as exc:
        raise DataError(f"cannot read {str(path)!r}: {exc} (pickled object arrays are never "
                        "loaded)") from None
    except OSError as exc:
        raise DataError(f"{str(path)!r} is not a valid .npy file ({exc})") from None
    return _array_table(np.asarray(arr), str(path), fs_hz=None)


def _npz_table(path: Path) -> _Table:
    _check_magic(path, b"PK\x03\x04", ".npz")
    try:
        with np.load(path, allow_pickle=False) as npz:
            arrays = {k: npz[k] for k in npz.files}
    except ValueError as exc:
        raise DataError(f"cannot read {str(path)!r}: {exc} (pickled object arrays are never "
                        "loaded)") from None
    except (OSError, zipfile.BadZipFile) as exc:
        raise DataError(f"{str(path)!r} is not a valid .npz file ({exc})") from None
    fs = arrays.pop("fs_hz", None)
    fs_hz = float(fs) if fs is not None and np.ndim(fs) == 0 else None
    names_arr = arrays.pop("columns", None)
    numeric = {k: v for k, v in arrays.items() if v.dtype.kind in "fiu" and v.ndim in (1, 2)}
    if not numeric:
        raise DataError(f"{str(path)!r} holds no numeric 1-D or 2-D array; keys are: "
                        f"{', '.join(arrays) or '(none)'}")
    frame_cols: dict[str, np.ndarray] = {}
    length = {v.shape[0] for v in numeric.values()}
    if len(length) > 1:
        raise DataError(f"{str(path)!r}: arrays have different lengths "
                        f"{ {k: v.shape[0] for k, v in numeric.items()} }")
    for key, arr in numeric.items():
        if arr.ndim == 1:
            frame_cols[key] = arr
        else:
            labels = ([str(c) for c in names_arr] if names_arr is not None
                      and len(numeric) == 1 and len(names_arr) == arr.shape[1]
                      else [f"{key}_{i}" for i in range(arr.shape[1])])
            for i, label in enumerate(labels):
                frame_cols[label] = arr[:, i]
    frame = pd.DataFrame(frame_cols)
    return _Table(frame, str(path), None, (), fs_hz, None, True, unit_hint=next(iter(numeric)))


# --------------------------------------------------------------------------- text parsing

_NUMBER = re.compile(r"^[+-]?(\d+([.,]\d*)?|[.,]\d+)([eE][+-]?\d+)?$")


def _decode(raw: bytes, source: str) -> str:
    try:
        return raw.decode("utf-8-sig")
    except UnicodeDecodeError:
        try:
            return raw.decode("latin-1")
        except UnicodeDecodeError:  # pragma: no cover - latin-1 decodes any byte
            raise DataError(f"{source!r} is not a text file") from None


def _detect_separator(line: str) -> str:
    if "\t" in line:
        return "\t"
    if ";" in line:
        return ";"
    if "," in line:
        return ","
    return r"\s+"


def _split(line: str, sep: str) -> list[str]:
    if sep == r"\s+":
        return line.split()
    return [c.strip() for c in line.split(sep)]


_COMMENT_LINE = re.compile(rb"^[ \t]*#[^\r\n]*", re.MULTILINE)
_FIRST_DATA_LINE = re.compile(rb"^[ \t]*([^#\s][^\r\n]*)", re.MULTILINE)


def _text_table(raw: bytes, source: str) -> _Table:
    """Parse delimited text: a fast path (pandas' C reader straight on the bytes) for clean
    numeric files, and a line-by-line path that knows every row's file line, used for
    anything else and to word error messages."""
    _check_text_bytes(raw, source)
    body = raw[3:] if raw.startswith(b"\xef\xbb\xbf") else raw
    first_match = _FIRST_DATA_LINE.search(body)
    if first_match is None:
        raise DataError(f"{source!r} has no data lines (only comments or blank lines)")
    first_line = first_match.group(1).decode("utf-8", "replace").rstrip()
    sep = _detect_separator(first_line)
    first = _split(first_line, sep)
    header = not all(_NUMBER.match(tok) for tok in first if tok)
    names = [c.strip().strip('"').strip("'") or f"col{i}" for i, c in enumerate(first)] \
        if header else [f"col{i}" for i in range(len(first))]

    def checked() -> _Table:
        return _checked_text_table(_decode(raw, source), sep, header, names, source)

    fast = _fast_numeric_table(body, first_match.start(), sep, header, names, source)
    return checked() if fast is None else dataclasses.replace(fast, reparse=checked)


def _check_text_bytes(raw: bytes, source: str) -> None:
    if not raw.strip():
        raise DataError(f"{source!r} is empty")
    if b"\x00" in raw[:65536]:
        raise DataError(f"{source!r} looks like a binary file (NUL bytes); expected text, "
                        "Parquet, .npy or .npz")


def _fast_numeric_table(body: bytes, start: int, sep: str, header: bool, names: list[str],
                        source: str) -> _Table | None:
    """Parse with pandas' C reader; None when anything is not clean numeric data.

    The caller then re-parses line by line to report exactly what is wrong and where.
    """
    comments = tuple(m.group(0).strip().decode("utf-8", "replace")
                     for m in _COMMENT_LINE.finditer(body)) if b"#" in body else ()
    lines = body[start:start + 4096].splitlines()
    probe = (lines[1] if header and len(lines) > 1 else lines[0]).decode("utf-8", "replace")
    decimal = "," if sep != "," and re.search(r"(^|[\s;\t])[+-]?\d+,\d+", probe) else "."
    try:
        frame = pd.read_csv(_io.BytesIO(body), sep=sep, header=0 if header else None,
                            names=names, decimal=decimal, comment="#" if comments else None,
                            skip_blank_lines=True, engine="c", index_col=False,
                            skipinitialspace=True, encoding="utf-8")
    except (pd.errors.ParserError, ValueError):
        return None
    if frame.shape[0] == 0 or frame.shape[1] != len(names):
        return None
    for col in frame.columns:
        if frame[col].dtype.kind not in "fi" or not np.isfinite(
                frame[col].to_numpy(dtype=np.float64)).all():
            return None
    return _Table(frame, source, None, comments, None, None, header)


def _checked_text_table(text: str, sep: str, header: bool, names: list[str],
                        source: str) -> _Table:
    comments: list[str] = []
    kept: list[str] = []
    line_no: list[int] = []
    for i, line in enumerate(text.splitlines(), start=1):
        stripped = line.strip()
        if not stripped:
            continue
        if stripped.startswith("#"):
            comments.append(stripped)
            continue
        kept.append(line)
        line_no.append(i)
    data_lines = kept[1:] if header else kept
    data_line_no = np.asarray(line_no[1:] if header else line_no, dtype=np.int64)
    if not data_lines:
        raise InsufficientDataError(f"{source!r} has a header ({', '.join(names)}) but no "
                                    "data rows")
    sample = _split(data_lines[0], sep)
    decimal = "," if sep != "," and any(re.match(r"^[+-]?\d+,\d+", t) for t in sample) else "."
    try:
        frame = pd.read_csv(_io.StringIO("\n".join(data_lines)), sep=sep, header=None,
                            names=names, decimal=decimal, dtype=str, engine="c"
                            if sep != r"\s+" else "python", skipinitialspace=True,
                            keep_default_na=False, index_col=False)
    except pd.errors.ParserError as exc:
        raise DataError(f"{source!r}: rows have inconsistent numbers of fields ({exc}); "
                        f"expected {len(names)} columns: {', '.join(names)}") from None
    frame.columns = names
    return _Table(frame, source, data_line_no, tuple(comments), None, None, header)


# --------------------------------------------------------------------------- interpretation


def _norm(name: str) -> str:
    return re.sub(r"[\s.\-()\[\]/]+", "_", name.strip().lower()).strip("_")


def _is_time_name(name: str) -> bool:
    n = _norm(name)
    return (name != "T" and n in _TIME_NAMES) or n.startswith("time")


def _is_temp_name(name: str) -> bool:
    n = _norm(name)
    return name == "T" or n in _TEMP_NAMES or n.startswith(("temp", "temperature"))


def _is_rate_name(name: str) -> bool:
    n = _norm(name)
    if n in ("sample_rate", "rate_hz", "fs", "fs_hz"):
        return False
    return n in _RATE_NAMES or n.startswith(_RATE_PREFIXES)


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
class _Roles:
    time: str | None
    rate: tuple[str, ...]
    temperature: str | None


def _assign_roles(table: _Table, rate_column: str | Sequence[str] | None,
                  time_column: str | None, temperature_column: str | None) -> _Roles:
    cols = list(table.frame.columns)
    time = _resolve(cols, time_column, "time") if time_column else None
    temp = _resolve(cols, temperature_column, "temperature") if temperature_column else None
    if time is None and table.from_index is None and table.header:
        time = next((c for c in cols if _is_time_name(c)), None)
    if temp is None:
        temp = next((c for c in cols if _is_temp_name(c) and c != time), None)
    if rate_column is not None:
        names = [rate_column] if isinstance(rate_column, str) else list(rate_column)
        rate = tuple(_resolve(cols, n, "rate") for n in names)
    else:
        rate = _detect_rate(table, cols, time, temp)
    clash = {time, temp} & set(rate)
    if clash - {None}:
        raise DataError(f"column {sorted(c for c in clash if c)[0]!r} cannot be both a rate "
                        "and a time/temperature column")
    return _Roles(time, rate, temp)


def _detect_rate(table: _Table, cols: list[str], time: str | None,
                 temp: str | None) -> tuple[str, ...]:
    named = tuple(c for c in cols if c not in (time, temp) and _is_rate_name(c))
    if named:
        return named
    rest = [c for c in cols if c not in (time, temp)]
    if not table.header:
        # Headerless text: first column is time if it increases, the next is the rate.
        return (rest[0],) if len(rest) == 1 or time is not None else (rest[1],)
    if len(rest) == 1:
        return (rest[0],)
    raise DataError("cannot tell which column is the rate; columns are: "
                    f"{', '.join(cols)}; pass rate_column= (CLI --rate-column)")


#: What ``read_run(nan=...)`` may do with empty, NaN and infinite cells.
NAN_POLICIES = ("error", "drop", "interpolate")


def _numeric_column(table: _Table, name: str, *, missing_ok: bool = False) -> FloatArray:
    """One column as float64.  Non-numeric text is always an error; empty, NaN and inf
    cells are an error too unless ``missing_ok`` (then they are returned as NaN)."""
    col = table.frame[name]
    if col.dtype.kind in "fiub":
        values = col.to_numpy(dtype=np.float64)
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
        hint = ("; pass nan='drop' or nan='interpolate' (CLI --nan drop|interpolate)" if empty
                else "")
        raise DataError(f"column {name!r} has {shown} at {_where(table, row)}{hint}")
    nonfinite = ~np.isfinite(values)
    if missing_ok:
        values = np.where(nonfinite, np.nan, values) if nonfinite.any() else values
    elif nonfinite.any():
        row = int(np.argmax(nonfinite))
        raise DataError(f"column {name!r} has {float(values[row])!r} at {_where(table, row)}; fogts "
                        "never drops rows silently: pass nan='drop' or nan='interpolate' "
                        "(CLI --nan drop|interpolate)")
    huge = np.abs(values) > MAX_ABS_VALUE
    if huge.any():
        row = int(np.argmax(huge))
        raise DataError(f"column {name!r} has the value {values[row]:.6g} at {_where(table, row)};"
                        f" magnitudes above {MAX_ABS_VALUE:.0e} overflow variance sums")
    return values


def _uses_decimal_comma(text: pd.Series) -> bool:
    head = text.head(50)
    return bool(head.str.match(r"^[+-]?\d*,\d+([eE][+-]?\d+)?$").any())


def _where(table: _Table, row: int) -> str:
    if table.line_of_row is not None:
        return f"data row {row} (line {int(table.line_of_row[row])} of {table.source})"
    return f"row {row}"


def _time_seconds(table: _Table, name: str) -> tuple[FloatArray, str | None]:
    col = table.frame[name]
    if col.dtype.kind in "fiu":
        return _numeric_column(table, name), None
    if col.dtype.kind == "M" or isinstance(col.dtype, pd.DatetimeTZDtype):
        return _datetime_seconds(pd.DatetimeIndex(col))
    sample = str(col.iloc[0]).strip()
    if _NUMBER.match(sample) or sample.lower() in ("nan", "inf", "-inf"):
        return _numeric_column(table, name), None
    try:
        stamps = pd.to_datetime(col.astype(str).str.strip(), format="ISO8601")
    except (ValueError, TypeError) as exc:
        raise DataError(f"time column {name!r} is neither seconds nor ISO-8601 date-times "
                        f"(first value {sample!r}): {exc}") from None
    if stamps.isna().any():
        row = int(np.argmax(stamps.isna().to_numpy()))
        raise DataError(f"time column {name!r} has an empty or invalid time stamp at "
                        f"{_where(table, row)}")
    return _datetime_seconds(pd.DatetimeIndex(stamps))


def _datetime_seconds(index: pd.DatetimeIndex | pd.TimedeltaIndex) -> tuple[FloatArray, str | None]:
    if isinstance(index, pd.TimedeltaIndex):
        delta = index - index[0]
        return np.asarray(delta.total_seconds(), dtype=np.float64), None
    delta = index - index[0]
    seconds = np.asarray(pd.TimedeltaIndex(delta).total_seconds(), dtype=np.float64)
    return seconds, index[0].isoformat()


def _check_monotonic(time: FloatArray, name: str, table: _Table) -> FloatArray:
    dt = np.diff(time)
    bad = dt <= 0
    if bad.any():
        i = int(np.argmax(bad)) + 1
        kind = "duplicated" if dt[i - 1] == 0 else "decreasing"
        raise DataError(f"time column {name!r} is {kind} at {_where(table, i)}: "
                        f"t={time[i]:.9g} after t={time[i - 1]:.9g}; time stamps must be "
                        "strictly increasing")
    return dt


def sampling_report(dt: FloatArray | None, fs_hz: float, fs_source: str) -> SamplingReport:
    """Measure gaps (steps > 1.5 x the nominal step ``1/fs_hz``) and jitter of a time base."""
    nominal = 1.0 / fs_hz
    if dt is None:
        return SamplingReport(nominal, 0, nominal, (), 0.0, 0.0, True, False, nominal, fs_source)
    median = float(np.median(dt))
    gaps = dt > GAP_FACTOR * nominal
    normal = dt[~gaps]
    jitter = float(np.std(normal)) if normal.size > 1 else 0.0
    gap_rows = tuple(int(i) for i in np.flatnonzero(gaps)[:100])
    jitter_rel = jitter / nominal
    return SamplingReport(
        median_dt_s=median,
        n_gaps=int(gaps.sum()),
        max_gap_s=float(dt.max()),
        gap_rows=gap_rows,
        jitter_s=jitter,
        jitter_rel=jitter_rel,
        regular=bool(not gaps.any() and jitter_rel < 0.01),
        from_time_column=True,
        mean_dt_s=float(np.mean(dt)),
        fs_source=fs_source,
    )


def _round_rate(fs: float) -> float:
    """Round a rate measured from float time stamps to 10 significant digits.

    Stamps such as ``i / 10`` give 1/median step = 10.000000000000568 Hz; the noise in the
    last digits is float rounding of the stamps, not information.
    """
    return float(f"{fs:.10g}")


def _whole_multiples(ratio: FloatArray) -> bool:
    """True when most step ratios are close to whole numbers (dropped samples)."""
    return bool(np.median(np.abs(ratio - np.rint(ratio))) < 0.1)


def _sample_rate(dt: FloatArray | None, given: float | None, from_file: float | None,
                 source: str) -> tuple[float, str]:
    """Pick the sample rate: given > median time step > file metadata.

    Burst-logged stamps (samples buffered and stamped in clumps) make the median step far
    shorter than the true mean step.  When more than 5 % of the steps are longer than
    1.5 x the median (so the median does not describe the sampling; a few real gaps do not
    trigger this), the mean step is used and a warning is issued -- unless the long steps
    are whole multiples of the median step (median distance to the nearest multiple below
    0.1 step): that is a clock that dropped samples, so the median step is the rate and
    the long steps are gaps (:func:`sampling_report` lists them).
    """
    if given is not None:
        return given, "given"
    if dt is not None:
        median, mean = float(np.median(dt)), float(np.mean(dt))
        long = dt[dt > GAP_FACTOR * median]
        if long.size <= 0.05 * dt.size or _whole_multiples(long / median):
            return _round_rate(1.0 / median), "median step"
        warnings.warn(f"{source}: median time step {median:.6g} s differs from the mean step "
                      f"{mean:.6g} s by more than 10 % (burst-logged time stamps); using the "
                      f"mean rate {1.0 / mean:.6g} Hz", DataQualityWarning, stacklevel=4)
        return _round_rate(1.0 / mean), "mean step"
    if from_file is not None:
        return from_file, "file"
    raise DataError("no sample rate")


def _unit_from_names(names: Sequence[str]) -> str | None:
    for name in names:
        n = _norm(name)
        for hint, unit in _UNIT_HINTS:
            if n.endswith(hint.replace("/", "_")) or f"_{hint.replace('/', '_')}_" in n:
                return unit
    return None


#: Largest sidecar JSON read for its unit.
_SIDECAR_MAX_BYTES = 1 << 20


def _sidecar_unit(path: Path) -> str | None:
    """The rate unit recorded in ``<path>.json`` when fogts wrote it (``fogts simulate``
    records the unit of the file it writes there), else None.  Never raises: a sidecar
    that is absent, large, unreadable or not fogts' own is ignored."""
    import json

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


def _rate_unit(given: str | None, rate_names: Sequence[str], file_key: str,
               sidecar: str | None = None) -> tuple[str, str]:
    """The rate unit and where it came from (see :attr:`fogts.io.run.Run.units_source`)."""
    if given is not None:
        return given, "given"
    if sidecar is not None:
        return sidecar, "file metadata"
    from_columns = _unit_from_names(rate_names)
    if from_columns is not None:
        return from_columns, "column name"
    from_key = _unit_from_names([file_key]) if file_key else None
    if from_key is not None:
        return from_key, "file key"
    return "deg/h", "assumed"


def _table_to_run(table: _Table, *, rate_column: str | Sequence[str] | None,
                  time_column: str | None, temperature_column: str | None,
                  fs_hz: float | None, units: str | None, nan: str = "error") -> Run:
    roles = _assign_roles(table, rate_column, time_column, temperature_column)
    n = table.frame.shape[0]
    if n < MIN_SAMPLES:
        raise InsufficientDataError(f"{table.source} has {n} data row(s); at least "
                                    f"{MIN_SAMPLES} are needed")
    missing: MissingReport | None = None
    kept_rows: IntArray | None = None
    if nan != "error":
        table, missing, kept_rows = _apply_missing_drop(table, roles, nan)
    rate_cols = [_numeric_column(table, c, missing_ok=nan == "interpolate") for c in roles.rate]
    temperature = (_numeric_column(table, roles.temperature, missing_ok=nan == "interpolate")
                   if roles.temperature else None)
    time, start, dt = _time_base(table, roles.time)
    if fs_hz is None and dt is None and table.fs_hz is None:
        cols = ", ".join(table.frame.columns)
        raise DataError(f"no time column found (columns are: {cols}) and no sample rate "
                        "given; pass fs_hz= (CLI --fs) or add a time column")
    fs, fs_source = _sample_rate(dt, fs_hz, table.fs_hz, table.source)
    if time is None and kept_rows is not None and kept_rows.size < n:
        # Dropped rows of a record without time stamps stay visible as gaps.
        time = kept_rows / fs
        dt = np.diff(time)
    if time is None:
        time = np.arange(table.frame.shape[0], dtype=np.float64) / fs
    if nan == "interpolate":
        filled = [_interpolate_missing(c, time, name)
                  for c, name in zip(rate_cols, roles.rate, strict=True)]
        rate_cols = [c for c, _ in filled]
        missing = _missing_report(nan, roles.rate, [m for _, m in filled], temperature)
        if temperature is not None:
            temperature = _interpolate_missing(temperature, time, str(roles.temperature))[0]
    for name, col in zip(roles.rate, rate_cols, strict=True):
        if np.ptp(col) == 0:
            raise DataError(f"rate column {name!r} is constant (every value is {col[0]:g}); a "
                            "gyro record must vary: check the column or the logger")
    rate = rate_cols[0] if len(rate_cols) == 1 else np.column_stack(rate_cols)
    unit, unit_source = _rate_unit(units, roles.rate, table.unit_hint, table.sidecar_unit)
    return Run(
        rate=np.ascontiguousarray(rate, dtype=np.float64),
        time=time,
        fs_hz=float(fs),
        units=unit,
        axes=roles.rate,
        temperature=temperature,
        columns=tuple(table.frame.columns),
        source=table.source,
        sampling=sampling_report(dt, float(fs), fs_source),
        start_time=start,
        comments=table.comments,
        units_source=unit_source,
        missing=missing,
    )


def _apply_missing_drop(table: _Table, roles: _Roles, policy: str
                        ) -> tuple[_Table, MissingReport | None, IntArray | None]:
    """For ``nan="drop"``: remove every row with an empty/NaN/inf cell in a rate,
    temperature or time column (time stamps are never interpolated)."""
    names = [*roles.rate, *([roles.temperature] if roles.temperature else [])]
    if roles.time is not None and _is_numeric_time(table, roles.time):
        names.append(roles.time)
    if policy == "interpolate":
        if roles.time is None or not _is_numeric_time(table, roles.time):
            return table, None, None
        names = [roles.time]
    bad_by_col = {c: ~np.isfinite(_numeric_column(table, c, missing_ok=True)) for c in names}
    if policy == "interpolate":
        bad = bad_by_col[roles.time]  # type: ignore[index]
        if bad.any():
            row = int(np.argmax(bad))
            raise DataError(f"time column {roles.time!r} has an empty or NaN time stamp at "
                            f"{_where(table, row)}; time stamps are never interpolated: pass "
                            "nan='drop' (CLI --nan drop)")
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


def _is_numeric_time(table: _Table, name: str) -> bool:
    return table.frame[name].dtype.kind in "fiu" or bool(
        _NUMBER.match(str(table.frame[name].iloc[0]).strip()))


def _interpolate_missing(values: FloatArray, time: FloatArray, name: str
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


def _missing_report(policy: str, rate_names: Sequence[str], rate_rows: list[IntArray],
                    temperature: FloatArray | None) -> MissingReport | None:
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


def _time_base(table: _Table, time_name: str | None
               ) -> tuple[FloatArray | None, str | None, FloatArray | None]:
    if isinstance(table.from_index, pd.DatetimeIndex | pd.TimedeltaIndex):
        time, start = _datetime_seconds(table.from_index)
        name = "index"
    elif time_name is not None:
        time, start = _time_seconds(table, time_name)
        time = time - time[0]
        name = time_name
    else:
        return None, None, None
    dt = _check_monotonic(time, name, table)
    return time, start, dt
