"""The fast path for delimited text files: pandas' parallel C reader or pyarrow's.

Clean numeric text (comma, semicolon or tab separated, a header or none, ``#`` comment
lines, a UTF-8 byte-order mark, CRLF line ends, plain or gzip-compressed) is parsed straight
from the file, every column as float64, and checked with vectorised passes (no empty cell,
every value finite and within :data:`~fogts.io.table.MAX_ABS_VALUE`).  A plain file whose
data hold no comment line goes to :func:`pandas.read_csv` when pandas splits a local file
among threads itself (pandas 3.1 and later); the rest (a ``.gz`` stream, comment lines
among the data, a byte-order mark, an older pandas) to :func:`pyarrow.csv.read_csv`.
Anything else returns None, and the caller takes the checked path of :mod:`fogts.io.text`,
which knows each row's file line and words every error.  Numbers are parsed to the nearest
float64 by both readers and on the checked path (all three round correctly), so the paths
give the same values bit for bit.

The input limits of :mod:`fogts.io.limits` hold here too, without reading the file into
memory: a plain file is checked for over-long lines through a memory map (a few pages per
MiB), and a ``.gz`` stream is decompressed in chunks that are counted and checked as
pyarrow consumes them, so the text is never held whole.
"""

from __future__ import annotations

import dataclasses
import io
import mmap
import re
import warnings
import zlib
from pathlib import Path
from typing import Any

import numpy as np
import pandas as pd

from fogts.errors import DataError
from fogts.io.limits import CHUNK_BYTES, first_long_line, max_input_bytes, too_big
from fogts.io.sniff import BOM, PROBE_BYTES, Layout, comment_lines, layout, split
from fogts.io.table import Table, finite_and_bounded

__all__ = ["fast_text_table"]

#: Bytes read to find the layout; a file whose first data line lies further in takes the
#: checked path.
SNIFF_BYTES = 1 << 16

#: pandas reads a local file with its own thread pool, and rounds every number correctly,
#: from 3.1 on (``pandas.io.parsers.readers``: byte-range chunks cut at line ends).
PANDAS_SPLITS_FILES = tuple(int(v) for v in re.findall(r"\d+", pd.__version__)[:2]) >= (3, 1)


class _Fallback(Exception):
    """The text is not clean numeric data of the sniffed layout: take the checked path."""


def fast_text_table(path: Path, *, compressed: bool) -> Table | None:
    """Parse a clean numeric text file with pyarrow; None when the checked path must read it.

    Raises
    ------
    DataError
        Only for a ``.gz`` stream that decompresses to more than the input limit (it is
        refused here, so that it is not decompressed twice).
    """
    try:
        return _gzip_table(path) if compressed else _plain_table(path)
    except _Fallback:
        return None


def _plain_table(path: Path) -> Table:
    size = path.stat().st_size
    if size == 0 or size > max_input_bytes():
        raise _Fallback
    with open(path, "rb") as fh, mmap.mmap(fh.fileno(), 0, access=mmap.ACCESS_READ) as mm:
        begin = len(BOM) if mm[:len(BOM)] == BOM else 0
        head = mm[begin:begin + SNIFF_BYTES]
        found = _layout(head, complete=begin + len(head) == size)
        if first_long_line(mm, 0)[0] >= 0:
            raise _Fallback  # the checked path names the line
        skipped = comment_lines(mm, begin, begin + found.start)
        if skipped is None or not _pandas_takes(mm, begin, found):
            return _pyarrow_table(path, mm, begin, found, skipped)
        rows = _rows_before_data(mm, found)
    # pandas parses after the map is closed: the scan for '#' touched every page of it,
    # which would otherwise count a second time in the resident set beside pandas' own map
    frame = _pandas_frame(path, found, rows)
    return Table(frame, str(path), None, tuple(skipped), None, None, found.header, checked=True)


def _pyarrow_table(path: Path, mm: mmap.mmap, begin: int, found: Layout,
                   skipped: list[str] | None) -> Table:
    """Parse a plain file with pyarrow from its first data line on; ``mm`` maps the file,
    ``skipped``: the comment lines before the data."""
    import pyarrow as pa

    with pa.OSFile(str(path)) as stream:
        stream.seek(begin + found.start)
        frame, n_comments = _parse(stream, found)
    # Comment lines after the first data line were skipped by the parser; their text is
    # read here, in file order (each ``#`` is one of them: the parse failed on any other).
    comments = comment_lines(mm, begin) if n_comments else skipped
    if comments is None:
        raise _Fallback
    return Table(frame, str(path), None, tuple(comments), None, None, found.header,
                 checked=True)


def _layout(head: bytes, *, complete: bool) -> Layout:
    """The layout, when ``head`` holds enough of the text to tell it and pyarrow can read
    it (not whitespace-separated, distinct column names)."""
    if b"\x00" in head:
        raise _Fallback
    found = layout(head)
    if found is None or len(set(found.names)) != len(found.names):
        raise _Fallback
    if found.sep == r"\s+":
        if len(found.names) > 1:
            raise _Fallback  # runs of blanks as one separator: pandas' reader does that
        # One column: any line with a second cell fails to parse as a number.
        found = dataclasses.replace(found, sep="\t")
    if not complete and len(head) < found.start + PROBE_BYTES:
        raise _Fallback
    return found


def _pandas_takes(mm: mmap.mmap, begin: int, found: Layout) -> bool:
    """Whether pandas' reader takes the file.

    It does when pandas splits files itself, there is no byte-order mark, no ``#`` among
    the data (a comment line there is pyarrow's to skip), no quote in the lines before the
    header (pandas' tokenizer opens a quoted field in a line it skips, ``# gyro,"FOG 200``,
    and closes it lines later: the first data row would be lost), and the first data row
    has one cell per column (pandas would take an extra cell in the first row for an index,
    and drop a trailing one).
    """
    if (not PANDAS_SPLITS_FILES or begin or mm.find(b"#", found.start) != -1
            or mm.find(b'"', 0, found.start) != -1):
        return False
    row = mm.find(b"\n", found.start) + 1 if found.header else found.start
    end = mm.find(b"\n", row)
    first = mm[row:len(mm) if end == -1 else end].rstrip(b"\r").decode("utf-8", "replace")
    return len(split(first, found.sep)) == len(found.names)


def _rows_before_data(mm: mmap.mmap, found: Layout) -> tuple[int | None, int | None]:
    """:func:`pandas.read_csv`'s ``header`` and ``skiprows`` (in that order) that pass over
    the lines before the first data row (comment lines, blank lines, the header).

    A header after comment lines alone is pandas' ``header=k`` (the lines before it are
    dropped as it parses); ``skiprows`` tests every line of the file against its count,
    which makes pandas' single-threaded parse a third slower, so it is used only for a
    preamble pandas would count differently (blank lines) or a headerless one.
    """
    lines = mm[:found.start].splitlines()
    if found.header and all(line.strip() for line in lines):
        return len(lines), None
    if not lines and not found.header:
        return None, None
    return None, len(lines) + int(found.header)


def _pandas_frame(path: Path, found: Layout, rows: tuple[int | None, int | None]
                  ) -> pd.DataFrame:
    """Parse the data rows with :func:`pandas.read_csv` (C engine; pandas splits a large
    file among its threads) into checked float64 columns; a parse error, a warning (a
    row of another length) or a column with an empty, non-finite or huge value
    (:func:`~fogts.io.table.finite_and_bounded`) raises :class:`_Fallback`."""
    try:
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            frame = pd.read_csv(path, sep=found.sep, names=found.names, index_col=False,
                                dtype=np.float64, decimal=found.decimal, engine="c",
                                encoding="utf-8", header=rows[0], skiprows=rows[1])
    except (ValueError, OverflowError, OSError):
        raise _Fallback from None
    if caught or len(frame) == 0:
        raise _Fallback
    out: dict[str, np.ndarray] = {}
    for name in found.names:
        values = np.ascontiguousarray(frame[name].to_numpy(), dtype=np.float64)
        if not finite_and_bounded(values):
            raise _Fallback
        out[name] = values
    return pd.DataFrame(out, copy=False)


def _parse(stream: Any, found: Layout) -> tuple[pd.DataFrame, int]:
    """Parse ``stream`` (positioned at the first data line) into float64 columns; the
    number of comment lines the parser skipped."""
    import pyarrow as pa
    import pyarrow.csv as pacsv

    skipped = [0]

    def comment_row(row: Any) -> str:
        if row.text.lstrip(" \t").startswith("#"):
            skipped[0] += 1
            return "skip"
        return "error"

    try:
        table = pacsv.read_csv(
            stream,
            read_options=pacsv.ReadOptions(column_names=found.names,
                                           skip_rows=1 if found.header else 0),
            parse_options=pacsv.ParseOptions(delimiter=found.sep,
                                             invalid_row_handler=comment_row),
            convert_options=pacsv.ConvertOptions(
                column_types={n: pa.float64() for n in found.names},
                decimal_point=found.decimal))
    except DataError:
        raise  # the input limit, from the gzip stream
    except (pa.ArrowException, ValueError, OSError, EOFError, zlib.error):
        raise _Fallback from None
    if table.num_rows == 0:
        raise _Fallback
    columns = dict(zip(found.names, table.columns, strict=True))
    del table  # each column's buffers go as soon as it is converted
    return _frame(columns), skipped[0]


def _frame(columns: dict[str, Any]) -> pd.DataFrame:
    """The parsed columns (emptied as they are converted) as float64 arrays in a frame, each
    checked: no empty cell, finite, within :data:`MAX_ABS_VALUE`.  A column's arrow buffers
    are released once it is converted, so at most one column is held twice."""
    import pyarrow as pa

    pool = pa.default_memory_pool()
    pool.release_unused()  # what the parser kept besides the columns
    out: dict[str, np.ndarray] = {}
    for name in list(columns):
        col = columns.pop(name)
        if col.null_count:
            raise _Fallback
        # One numpy allocation per column (numpy asks for huge pages: fewer page faults
        # than arrow's own concatenation).
        values = np.concatenate([c.to_numpy(zero_copy_only=True) for c in col.chunks])
        del col
        pool.release_unused()  # the column's arrow memory back to the system, not kept
        if not finite_and_bounded(values):
            raise _Fallback
        out[name] = values
    return pd.DataFrame(out, copy=False)


class _GzipFeed(io.RawIOBase):
    """A gzip stream as pyarrow reads it: decompressed in chunks, each counted against the
    input limit, checked for over-long lines and scanned for comment lines."""

    def __init__(self, path: Path) -> None:
        import pyarrow as pa

        super().__init__()
        # arrow's inflater: a fifth less CPU than the gzip module, and it releases the GIL
        self._gz = pa.CompressedInputStream(pa.OSFile(str(path)), "gzip")
        self._source = str(path)
        self._limit = max_input_bytes()
        self._total = self._carry = 0
        self._tail = b""  # the unfinished last line of the chunks consumed so far
        self._pending = b""
        self.begin = 0  # length of a byte-order mark in the first chunk
        self.comments: list[str] = []
        # Why a read ended the stream early (the input limit, a line for the checked path):
        # never raised inside pyarrow's reader, whose read-ahead thread, left running after
        # an exception from this file object, aborts the interpreter at exit.
        self.failure: Exception | None = None

    def readable(self) -> bool:
        return True

    def close(self) -> None:
        self._gz.close()
        super().close()

    def head(self, n: int) -> bytes:
        """The first ``n`` bytes (fewer: the whole text); :meth:`read` then starts over."""
        parts = [self._next(n)]
        while parts[-1] and sum(map(len, parts)) < n:
            parts.append(self._next(n - sum(map(len, parts))))
        self._pending = b"".join(parts)
        return self._pending

    def skip(self, n: int) -> None:
        """Drop the first ``n`` bytes of what :meth:`read` returns next."""
        self._pending = self._pending[n:]

    def read(self, size: int | None = -1) -> bytes:
        if self._pending:
            out, self._pending = self._pending, b""
            return out
        if self.failure is not None:
            return b""
        try:
            return self._next(CHUNK_BYTES if size is None or size < 0 else size)
        except (DataError, _Fallback) as exc:
            self.failure = exc  # the end of the stream for pyarrow; raised after it
            return b""

    def raise_failure(self) -> None:
        """Raise what ended the stream early, if anything did."""
        if self.failure is not None:
            raise self.failure

    def _next(self, size: int) -> bytes:
        chunk = self._gz.read(size)
        first = self._total == 0
        self._total += len(chunk)
        if self._total > self._limit:
            raise too_big(self._source, "the stream decompresses to", self._limit)
        bad, self._carry = first_long_line(chunk, self._carry)
        if bad >= 0:
            raise _Fallback  # the checked path names the line
        body = chunk
        if first and chunk.startswith(BOM):
            self.begin, body = len(BOM), chunk[len(BOM):]
        self._comments_in(body)
        return chunk

    def _comments_in(self, body: bytes) -> None:
        """Collect the comment lines that ``body`` completes (all that are left, at the end
        of the stream)."""
        if not body:
            lines, self._tail = self._tail, b""
        elif b"#" in body or b"#" in self._tail:
            data = self._tail + body
            cut = data.rfind(b"\n") + 1
            lines, self._tail = data[:cut], data[cut:]
        else:
            last = body.rfind(b"\n")
            self._tail = body[last + 1:] if last >= 0 else self._tail + body
            return
        found = comment_lines(lines)
        if found is None:
            raise _Fallback
        self.comments += found


def _gzip_table(path: Path) -> Table:
    import pyarrow as pa

    try:
        feed = _GzipFeed(path)
    except (OSError, pa.ArrowException):
        raise _Fallback from None
    try:
        head = feed.head(SNIFF_BYTES)
        found = _layout(head[feed.begin:], complete=len(head) < SNIFF_BYTES)
        feed.skip(feed.begin + found.start)
        try:
            frame, _ = _parse(feed, found)
        finally:
            feed.raise_failure()  # the stream's own reason before the parser's
        return Table(frame, str(path), None, tuple(feed.comments), None, None, found.header,
                     checked=True)
    except (OSError, EOFError, zlib.error, pa.ArrowException):
        raise _Fallback from None  # the checked path words a corrupt stream
    finally:
        feed.close()
