"""Reading input files within bounded time and memory.

:mod:`fogts.io` opens every input through these functions, so that no input can hang a
command or exhaust the machine:

* only regular files are read: a character or block device (``/dev/zero``,
  ``/dev/urandom``), a FIFO, a socket or a directory is refused from :func:`os.stat`,
  before anything is opened (opening a FIFO would block);
* text is read, and ``.gz`` decompressed, in chunks; the bytes read may not exceed
  :func:`max_input_bytes` and no line may be longer than :data:`MAX_LINE_BYTES`, checked
  chunk by chunk, so a decompression bomb (a small ``.gz`` that expands to gigabytes of
  one line) stops after about one chunk;
* ``.npy`` headers and ``.npz`` member sizes are checked against the same limit before
  any array is loaded.

The limit is ``min(4 GiB, half the memory available)`` unless the environment variable
``FOGTS_MAX_INPUT_BYTES`` sets it (bytes, or with a suffix: ``8G``, ``512M``).
"""

from __future__ import annotations

import gzip
import os
import re
import stat
import zipfile
from pathlib import Path
from typing import BinaryIO

from fogts.errors import DataError
from fogts.paths import file_kind

__all__ = ["MAX_LINE_BYTES", "check_regular_file", "max_input_bytes", "read_capped"]

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


def _too_big(source: str, what: str, limit: int) -> DataError:
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


class _LineGuard:
    """Counts lines across chunks and fails on the first line over the limit."""

    def __init__(self, source: str) -> None:
        self.source = source
        self.carry = 0      # bytes of the current, unfinished line
        self.line = 1       # number of that line

    def feed(self, chunk: bytes) -> None:
        first = chunk.find(b"\n")
        if first == -1:
            self._grow(len(chunk))
            return
        self._grow(first)
        pos = first + 1
        self.line += 1
        # interior lines: a window of MAX_LINE_BYTES + 1 bytes without a newline
        while len(chunk) - pos > MAX_LINE_BYTES:
            nl = chunk.rfind(b"\n", pos, pos + MAX_LINE_BYTES + 1)
            if nl == -1:
                self.carry = 0
                self._grow(MAX_LINE_BYTES + 1)
            self.line += chunk.count(b"\n", pos, nl + 1)
            pos = nl + 1
        self.line += chunk.count(b"\n", pos)
        last = chunk.rfind(b"\n")
        self.carry = 0
        self._grow(len(chunk) - max(last + 1, pos))

    def _grow(self, n: int) -> None:
        self.carry += n
        if self.carry > MAX_LINE_BYTES:
            raise DataError(f"{self.source!r}: line {self.line} is longer than "
                            f"{_human(MAX_LINE_BYTES)}; not a gyro record (a text line holds "
                            "one sample)")


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
        raise _too_big(source, f"the file has {_human(st.st_size)},", limit)
    try:
        with open(path, "rb") as raw:
            stream: BinaryIO = gzip.GzipFile(fileobj=raw) if compressed else raw  # type: ignore[assignment]
            return _read_chunks(stream, source, limit, compressed)
    except (OSError, EOFError, zipfile.BadZipFile) as exc:
        if compressed:
            raise DataError(f"{source!r} is not a valid gzip file ({exc})") from None
        raise DataError(f"cannot read {source!r}: {exc}") from None


def _read_chunks(stream: BinaryIO, source: str, limit: int, compressed: bool) -> bytes:
    guard = _LineGuard(source)
    chunks: list[bytes] = []
    total = 0
    while chunk := stream.read(CHUNK_BYTES):
        total += len(chunk)
        if total > limit:
            what = "decompresses to" if compressed else "holds"
            raise _too_big(source, f"the stream {what}", limit)
        guard.feed(chunk)
        chunks.append(chunk)
    return b"".join(chunks)


def check_npy(path: Path) -> None:
    """Refuse an ``.npy`` whose header declares more than the input limit, or more data
    than the file holds (truncated), before loading it."""
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
        offset = fh.tell()
    shape, _, dtype = header
    if dtype.hasobject:
        return  # np.load(allow_pickle=False) refuses it with its own message
    n_bytes = int(np.prod(shape, dtype=np.int64)) * dtype.itemsize
    limit = max_input_bytes()
    if n_bytes > limit:
        raise _too_big(source, f"the array {tuple(shape)} of {dtype} needs {_human(n_bytes)},",
                       limit)
    if offset + n_bytes > st.st_size:
        raise DataError(f"{source!r} is truncated: its header declares {tuple(shape)} {dtype} "
                        f"({n_bytes} bytes) but the file holds {st.st_size - offset}")


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
        raise _too_big(source, f"its arrays expand to {_human(total)},", limit)
