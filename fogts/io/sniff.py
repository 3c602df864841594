"""The layout of delimited text, read from its first lines: where the data start, the
separator, whether the first line is a header, the column names and the decimal mark; and
the ``#`` comment lines of a text, in order.

Both text readers use it: the fast path (:mod:`fogts.io.fastcsv`) on the first bytes of a
file, and the checked path (:mod:`fogts.io.text`) on the whole text.
"""

from __future__ import annotations

import mmap
import re
from dataclasses import dataclass

from fogts.io.table import NUMBER

__all__ = ["BOM", "Layout", "comment_lines", "detect_separator", "layout", "split"]

#: The UTF-8 byte-order mark.
BOM = b"\xef\xbb\xbf"
#: Bytes after the first data line that the decimal-mark probe looks at.
PROBE_BYTES = 4096

_FIRST_DATA_LINE = re.compile(rb"^[ \t]*([^#\s][^\r\n]*)", re.MULTILINE)
_DECIMAL_COMMA = re.compile(r"(^|[\s;\t])[+-]?\d+,\d+")


@dataclass(frozen=True)
class Layout:
    """Where and how the data of a text are written.

    Attributes
    ----------
    start : int
        Offset of the first line that is neither blank nor a comment (the header, if any),
        in the text without its byte-order mark.
    sep : str
        ``","``, ``";"``, ``"\\t"`` or ``r"\\s+"`` (whitespace).
    header : bool
        True when the first line holds names (a cell that is not a number).
    names : list of str
        Column names (``col0``, ``col1``, ... without a header).
    decimal : str
        ``","`` when the first data row is written with decimal commas, else ``"."``.
    """

    start: int
    sep: str
    header: bool
    names: list[str]
    decimal: str


def detect_separator(line: str) -> str:
    """The separator of a data line: tab, semicolon, comma, else whitespace."""
    if "\t" in line:
        return "\t"
    if ";" in line:
        return ";"
    if "," in line:
        return ","
    return r"\s+"


def split(line: str, sep: str) -> list[str]:
    """The cells of one line, stripped."""
    if sep == r"\s+":
        return line.split()
    return [c.strip() for c in line.split(sep)]


def layout(body: bytes) -> Layout | None:
    """The layout of ``body`` (text without its byte-order mark); None when it holds no
    line that is neither blank nor a comment.

    Examples
    --------
    >>> layout(b"# logger\\ntime;rate\\n0;1,5\\n")
    Layout(start=9, sep=';', header=True, names=['time', 'rate'], decimal=',')
    """
    first_match = _FIRST_DATA_LINE.search(body)
    if first_match is None:
        return None
    first_line = first_match.group(1).decode("utf-8", "replace").rstrip()
    sep = detect_separator(first_line)
    first = split(first_line, sep)
    header = not all(NUMBER.match(tok) for tok in first if tok)
    names = ([c.strip().strip('"').strip("'") or f"col{i}" for i, c in enumerate(first)]
             if header else [f"col{i}" for i in range(len(first))])
    start = first_match.start()
    lines = body[start:start + PROBE_BYTES].splitlines()
    probe = (lines[1] if header and len(lines) > 1 else lines[0]).decode("utf-8", "replace")
    decimal = "," if sep != "," and _DECIMAL_COMMA.search(probe) else "."
    return Layout(start, sep, header, names, decimal)


def comment_lines(data: bytes | mmap.mmap, begin: int = 0, end: int | None = None
                  ) -> list[str] | None:
    """The ``#`` comment lines of ``data[begin:end]`` in order, each stripped (a comment
    line is a line whose first character other than spaces and tabs is ``#``).

    ``data`` may be a memory map: only the lines holding a ``#`` are read.  Returns None
    when a ``#`` stands in a line that is not a comment (an inline comment, or a ``#``
    inside a value): such a text is no clean numeric table.

    Examples
    --------
    >>> comment_lines(b"# a\\n1,2\\n  # b\\r\\n3,4\\n")
    ['# a', '# b']
    >>> comment_lines(b"1,2 # note\\n") is None
    True
    """
    stop = len(data) if end is None else end
    found: list[str] = []
    at = data.find(b"#", begin, stop)
    while at != -1:
        line_start = max(data.rfind(b"\n", begin, at) + 1, begin)
        if data[line_start:at].strip(b" \t"):
            return None
        line_end = data.find(b"\n", at, stop)
        line = data[at:stop if line_end == -1 else line_end]
        found.append(line.split(b"\r", 1)[0].strip().decode("utf-8", "replace"))
        if line_end == -1:
            break
        at = data.find(b"#", line_end, stop)
    return found
