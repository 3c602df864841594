"""Reading input files within bounded time and memory.

The readers (:mod:`fogts.io.reader` and the format families it dispatches to) open every
input through these functions, so that no input can hang a command or exhaust the machine:

* only regular files are read: a character or block device (``/dev/zero``,
  ``/dev/urandom``), a FIFO, a socket or a directory is refused from :func:`os.stat`,
  before anything is opened (opening a FIFO would block);
* the bytes read may not exceed :func:`max_input_bytes` and no text line may be longer than
  :data:`MAX_LINE_BYTES`.  A plain file's size is checked before it is read whole; a ``.gz``
  stream is decompressed in chunks and checked chunk by chunk, so a decompression bomb (a
  small ``.gz`` that expands to gigabytes of one line) stops after about one chunk;
* ``.npy`` headers and ``.npz`` member sizes are checked against the same limit before
  any array is loaded.

The limit is ``min(4 GiB, half the memory available)`` unless the environment variable
``FOGTS_MAX_INPUT_BYTES`` sets it (bytes, or with a suffix: ``8G``, ``512M``).
"""

from __future__ import annotations

import gzip
import mmap
import os
import re
import stat
import zipfile
from pathlib import Path
from typing import Any, NamedTuple

from fogts.errors import DataError
from fogts.io.paths import file_kind

__all__ = ["MAX_LINE_BYTES", "NpyHeader", "check_regular_file", "first_long_line",
           "max_input_bytes", "read_capped", "too_big"]

#: Longest text line accepted (a gyro record's line is well under 1 KiB).
MAX_LINE_BYTES = 1 << 20
#: Bytes read (or decompressed) at a time.
CHUNK_BYTES = 8 << 20
#: Default upper bound of the input limit.
DEFAULT_MAX_BYTES = 4 << 30
ENV_VAR = "FOGTS_MAX_INPUT_BYTES"
_SUFFIX = {"": 1, "K": 1 << 10, "M": 1 << 20, "G": 1 << 30, "T": 1 << 40}


def _available_memory() -> int | None:
    try:
        return os.sysconf("SC_AVPHYS_PAGES") * os.sysconf("SC_PAGE_SIZE")
    except (ValueError, OSError, AttributeError):  # pragma: no cover - non-POSIX
        return None


def max_input_bytes() -> int:
    """The largest input (after decompression) fogts reads, in bytes.

    ``FOGTS_MAX_INPUT_BYTES`` if set, else ``min(4 GiB, half the available memory)``.

    Examples
    --------
    >>> max_input_bytes() > 0
    True
    """
    text = os.environ.get(ENV_VAR, "").strip()
    if text:
        m = re.fullmatch(r"(\d+(?:\.\d+)?)\s*([KMGT]?)i?B?", text, flags=re.IGNORECASE)
        if m is None:
            raise DataError(f"{ENV_VAR} must be a number of bytes such as 4000000000 or 8G; "
                            f"got {text!r}")
        return int(float(m.group(1)) * _SUFFIX[m.group(2).upper()])
    free = _available_memory()
    return DEFAULT_MAX_BYTES if free is None else max(1 << 20, min(DEFAULT_MAX_BYTES,
                                                                    free // 2))


def _human(n: int) -> str:
    for unit, size in (("GiB", 1 << 30), ("MiB", 1 << 20), ("KiB", 1 << 10)):
        if n >= size:
            return f"{n / size:.3g} {unit}"
    return f"{n} bytes"


def too_big(source: str, what: str, limit: int) -> DataError:
    """The error refusing ``source``: ``what`` (e.g. "the file has 5 GiB,") more than
    ``limit``."""
    return DataError(f"{source!r}: {what} more than the input limit of {_human(limit)}; "
                     f"oversized input is refused (set {ENV_VAR}, e.g. {ENV_VAR}=16G, to "
                     "raise the limit)")


def check_regular_file(path: Path, what: str = "") -> os.stat_result:
    """``os.stat`` of ``path``, refusing anything but a regular file (symlinks followed).

    Raises
    ------
    DataError
        Missing, unreadable, a directory, a device, a FIFO or a socket.

    Examples
    --------
    >>> check_regular_file(Path("/dev/zero"))
    Traceback (most recent call last):
    ...
    fogts.errors.DataError: '/dev/zero' is a character device, not a regular file; fogts reads regular files only
    """
    label = f"{what} " if what else ""
    try:
        st = os.stat(path)
    except FileNotFoundError:
        raise DataError(f"{label}file not found: {str(path)!r}") from None
    except PermissionError:
        raise DataError(f"cannot read {label}{str(path)!r}: permission denied") from None
    except OSError as exc:
        raise DataError(f"cannot read {label}{str(path)!r}: {exc.strerror}") from None
    if stat.S_ISDIR(st.st_mode):
        raise DataError(f"{label}{str(path)!r} is a directory, not a file")
    if not stat.S_ISREG(st.st_mode):
        raise DataError(f"{label}{str(path)!r} is {file_kind(st.st_mode)}, not a regular file; "
                        "fogts reads regular files only")
    return st


def first_long_line(chunk: bytes | mmap.mmap, carry: int) -> tuple[int, int]:
    """Scan ``chunk`` (bytes, or a memory map of a whole file) for a line longer than
    :data:`MAX_LINE_BYTES`.

    ``carry`` is the length of the unfinished line before the chunk.  Returns the offset in
    ``chunk`` where the offending line starts (0 when it started in an earlier chunk), or
    -1, and the length of the unfinished line at the chunk's end.  Only one ``rfind`` per
    MiB, so a normal file costs almost nothing to check."""
    first = chunk.find(b"\n")
    if first == -1:
        carry += len(chunk)
        return (0 if carry > MAX_LINE_BYTES else -1), carry
    if carry + first > MAX_LINE_BYTES:
        return 0, carry
    pos = first + 1
    while len(chunk) - pos > MAX_LINE_BYTES:
        nl = chunk.rfind(b"\n", pos, pos + MAX_LINE_BYTES + 1)
        if nl == -1:
            return pos, 0
        pos = nl + 1
    return -1, len(chunk) - (chunk.rfind(b"\n") + 1)


def _long_line_error(source: str, earlier: list[bytes], chunk: bytes, at: int) -> DataError:
    line = sum(c.count(b"\n") for c in earlier) + chunk.count(b"\n", 0, at) + 1
    return DataError(f"{source!r}: line {line} is longer than {_human(MAX_LINE_BYTES)}; not a "
                     "gyro record (a text line holds one sample)")


def read_capped(path: Path, *, compressed: bool) -> bytes:
    """All bytes of a text file (``compressed``: gunzipped), read in chunks within the
    input limit and the line-length limit.

    Raises
    ------
    DataError
        Not a regular file, larger than :func:`max_input_bytes` (after decompression),
        a line longer than :data:`MAX_LINE_BYTES`, or a corrupt gzip stream.
    """
    st = check_regular_file(path)
    limit = max_input_bytes()
    source = str(path)
    if st.st_size > limit:
        raise too_big(source, f"the file has {_human(st.st_size)},", limit)
    try:
        if not compressed:
            data = path.read_bytes()  # its size is within the limit (checked above)
            bad, _ = first_long_line(data, 0)
            if bad >= 0:
                raise _long_line_error(source, [], data, bad)
            return data
        with gzip.open(path, "rb") as stream:
            return _read_chunks(stream, source, limit)
    except (OSError, EOFError, zipfile.BadZipFile) as exc:
        if compressed:
            raise DataError(f"{source!r} is not a valid gzip file ({exc})") from None
        raise DataError(f"cannot read {source!r}: {exc}") from None


def _read_chunks(stream: gzip.GzipFile, source: str, limit: int) -> bytes:
    """Decompress in chunks, stopping at the input limit or at a line that is too long."""
    chunks: list[bytes] = []
    total = carry = 0
    while chunk := stream.read(CHUNK_BYTES):
        total += len(chunk)
        if total > limit:
            raise too_big(source, "the stream decompresses to", limit)
        bad, carry = first_long_line(chunk, carry)
        if bad >= 0:
            raise _long_line_error(source, chunks, chunk, bad)
        chunks.append(chunk)
    return b"".join(chunks)


class NpyHeader(NamedTuple):
    """What an ``.npy`` header declares: the shape, the memory order, the element type and
    where the data start."""

    shape: tuple[int, ...]
    fortran_order: bool
    dtype: Any
    offset: int


def check_npy(path: Path) -> NpyHeader:
    """Refuse an ``.npy`` whose header declares more than the input limit, or more data
    than the file holds (truncated), before loading it; its header otherwise."""
    import numpy as np

    st = check_regular_file(path)
    source = str(path)
    with open(path, "rb") as fh:
        try:
            version = np.lib.format.read_magic(fh)
            header = (np.lib.format.read_array_header_1_0(fh) if version == (1, 0)
                      else np.lib.format.read_array_header_2_0(fh))
        except ValueError as exc:
            raise DataError(f"{source!r} is not a valid .npy file ({exc})") from None
        found = NpyHeader(tuple(header[0]), bool(header[1]), header[2], fh.tell())
    if found.dtype.hasobject:
        return found  # np.load(allow_pickle=False) refuses it with its own message
    n_bytes = int(np.prod(found.shape, dtype=np.int64)) * found.dtype.itemsize
    limit = max_input_bytes()
    if n_bytes > limit:
        raise too_big(source, f"the array {found.shape} of {found.dtype} needs "
                      f"{_human(n_bytes)},", limit)
    if found.offset + n_bytes > st.st_size:
        raise DataError(f"{source!r} is truncated: its header declares {found.shape} "
                        f"{found.dtype} ({n_bytes} bytes) but the file holds "
                        f"{st.st_size - found.offset}")
    return found


def check_npz(path: Path) -> None:
    """Refuse an ``.npz`` whose members expand to more than the input limit."""
    check_regular_file(path)
    source = str(path)
    try:
        with zipfile.ZipFile(path) as zf:
            total = sum(info.file_size for info in zf.infolist())
    except (zipfile.BadZipFile, OSError) as exc:
        raise DataError(f"{source!r} is not a valid .npz file ({exc})") from None
    limit = max_input_bytes()
    if total > limit:
        raise too_big(source, f"its arrays expand to {_human(total)},", limit)
