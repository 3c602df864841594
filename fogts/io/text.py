"""Delimited text: comma, semicolon (with decimal commas), tab or whitespace separated.

``#`` comment lines may appear anywhere (FOG loggers write a trailing one); a UTF-8 BOM,
CRLF line ends and gzip compression (``.gz``, or the gzip signature) are accepted.  A file
goes first through the fast path (:mod:`fogts.io.fastcsv`: pandas' or pyarrow's threaded
reader on the file itself).  Whatever that path does not take (whitespace-separated text, inline
comments, empty or non-numeric cells, ...) is read whole and parsed by pandas' C reader,
and when that fails too, line by line; the line-by-line path knows each data row's file
line and words every error.  A table from either fast reader keeps the line-by-line parse
as ``Table.reparse``, for errors found later (a decreasing time stamp) to name the line.
"""

from __future__ import annotations

import dataclasses
import io as _io
import re
import warnings
from pathlib import Path

import numpy as np
import pandas as pd

from fogts.errors import DataError, InsufficientDataError
from fogts.io.fastcsv import fast_text_table
from fogts.io.limits import read_capped
from fogts.io.sniff import BOM, Layout, layout, split
from fogts.io.table import Table

__all__ = ["text_file_table", "text_table"]

#: The first two bytes of a gzip stream.
GZIP_MAGIC = b"\x1f\x8b"

_COMMENT_LINE = re.compile(rb"^[ \t]*#[^\r\n]*", re.MULTILINE)


def text_file_table(path: Path) -> Table:
    """Read a text file, gunzipping it when it ends in ``.gz`` or starts with the gzip
    signature, within the input limits (:func:`fogts.io.limits.read_capped`)."""
    suffixes = path.suffixes
    with open(path, "rb") as fh:
        gzipped = (bool(suffixes) and suffixes[-1].lower() == ".gz") or fh.read(2) == GZIP_MAGIC

    def checked() -> Table:
        return _checked_table(read_capped(path, compressed=gzipped), str(path))

    fast = fast_text_table(path, compressed=gzipped)
    if fast is not None:
        return dataclasses.replace(fast, reparse=checked)
    return text_table(read_capped(path, compressed=gzipped), str(path))


def text_table(raw: bytes, source: str) -> Table:
    """Parse delimited text: pandas' C reader straight on the bytes for clean numeric
    text, else the line-by-line path that knows every row's file line (used for anything
    else and to word error messages)."""
    _check_text_bytes(raw, source)
    found = _layout(raw, source)
    body = raw[len(BOM):] if raw.startswith(BOM) else raw
    fast = _fast_numeric_table(body, found, source)
    if fast is None:
        return _checked_text_table(_decode(raw, source), found, source)
    return dataclasses.replace(fast, reparse=lambda: _checked_table(raw, source))


def _checked_table(raw: bytes, source: str) -> Table:
    """The line-by-line parse of ``raw``."""
    _check_text_bytes(raw, source)
    return _checked_text_table(_decode(raw, source), _layout(raw, source), source)


def _layout(raw: bytes, source: str) -> Layout:
    found = layout(raw[len(BOM):] if raw.startswith(BOM) else raw)
    if found is None:
        raise DataError(f"{source!r} has no data lines (only comments or blank lines)")
    return found


def _decode(raw: bytes, source: str) -> str:
    try:
        return raw.decode("utf-8-sig")
    except UnicodeDecodeError:
        try:
            return raw.decode("latin-1")
        except UnicodeDecodeError:  # pragma: no cover - latin-1 decodes any byte
            raise DataError(f"{source!r} is not a text file") from None


def _check_text_bytes(raw: bytes, source: str) -> None:
    if not raw or raw.isspace():  # as ``not raw.strip()``, without a copy of the text
        raise DataError(f"{source!r} is empty")
    if b"\x00" in raw[:65536]:
        raise DataError(f"{source!r} looks like a binary file (NUL bytes); expected text, "
                        "Parquet, .npy or .npz")


def _fast_numeric_table(body: bytes, found: Layout, source: str) -> Table | None:
    """Parse with pandas' C reader; None when anything is not clean numeric data.

    The caller then re-parses line by line to report exactly what is wrong and where.
    """
    comments = tuple(m.group(0).strip().decode("utf-8", "replace")
                     for m in _COMMENT_LINE.finditer(body)) if b"#" in body else ()
    try:
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            frame = pd.read_csv(_io.BytesIO(body), sep=found.sep,
                                header=0 if found.header else None, names=found.names,
                                decimal=found.decimal, comment="#" if comments else None,
                                skip_blank_lines=True, engine="c", index_col=False,
                                skipinitialspace=True, encoding="utf-8")
    except (pd.errors.ParserError, ValueError):
        return None
    if caught:
        return None  # a row of another length (pandas cut it): the checked path words it
    if frame.shape[0] == 0 or frame.shape[1] != len(found.names):
        return None
    for col in frame.columns:
        if frame[col].dtype.kind not in "fi" or not np.isfinite(
                frame[col].to_numpy(dtype=np.float64)).all():
            return None
    return Table(frame, source, None, comments, None, None, found.header)


def _checked_text_table(text: str, found: Layout, source: str) -> Table:
    sep, header, names = found.sep, found.header, found.names
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
    sample = split(data_lines[0], sep)
    if any(sample[len(names):]):
        # pandas would take the extra cells for an index, or drop them with a warning
        raise DataError(f"{source!r}: data row 1 (line {data_line_no[0]}) has {len(sample)} "
                        f"cells ({', '.join(sample)}) but the header names {len(names)} "
                        f"columns ({', '.join(names)}); fogts never drops a value")
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
    return Table(frame, source, data_line_no, tuple(comments), None, None, header)
