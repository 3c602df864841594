"""Output paths that can never destroy an input.

A gyro recording is often the only copy of a day on a rate table, so every command checks
its output names against its inputs *before* any analysis runs, with one shared function,
:func:`check_outputs`.  Two names are the same file when :func:`os.stat` gives the same
device and inode: that sees through symbolic links, ``..`` and hard links.

An output that already exists must be a regular file (it is replaced atomically by
:func:`fogts.io.writer.atomic_path`); a device, FIFO, socket or directory is refused, so that
``--json /dev/sda`` can never be replaced by a text file.  And an existing file that could
hold data (anything but a figure or an HTML page, :data:`REPLACEABLE_SUFFIXES`) is
replaced only when the user says so (``overwrite=True``, the CLI's ``--overwrite``): a
mistyped output name must not turn another recording, or a sidecar that states its unit,
into fogts' output.
"""

from __future__ import annotations

import os
import stat
from collections.abc import Iterable, Mapping
from pathlib import Path

from fogts.errors import DataError

__all__ = ["REPLACEABLE_SUFFIXES", "check_outputs", "file_kind"]

#: Outputs that replace an existing file without ``overwrite``: figures and HTML pages,
#: which fogts never reads as input.
REPLACEABLE_SUFFIXES = (".png", ".svg", ".pdf", ".html", ".htm")

PathLike = str | os.PathLike[str]

_KINDS = (
    (stat.S_ISDIR, "a directory"),
    (stat.S_ISCHR, "a character device"),
    (stat.S_ISBLK, "a block device"),
    (stat.S_ISFIFO, "a FIFO (named pipe)"),
    (stat.S_ISSOCK, "a socket"),
)


def file_kind(mode: int) -> str:
    """Describe a file type from an ``st_mode``: ``"a regular file"``, ``"a directory"``, ...

    Examples
    --------
    >>> import os
    >>> file_kind(os.stat("/dev/null").st_mode)
    'a character device'
    """
    for test, kind in _KINDS:
        if test(mode):
            return kind
    return "a regular file" if stat.S_ISREG(mode) else "a special file"


def _identity(path: Path) -> tuple[int, int, int] | None:
    """``(st_dev, st_ino, st_mode)`` of what ``path`` points to, or None if it is absent."""
    try:
        st = os.stat(path)
    except (FileNotFoundError, NotADirectoryError):
        return None
    except OSError as exc:  # permission denied on a parent, a loop of symlinks, ...
        raise DataError(f"cannot check {str(path)!r}: {exc.strerror}") from None
    return st.st_dev, st.st_ino, st.st_mode


def check_outputs(outputs: Mapping[str, PathLike | None],
                  inputs: Mapping[str, Iterable[PathLike]], *, overwrite: bool = False) -> None:
    """Refuse any output that is one of the inputs, that names the same file as another
    output, that exists and is not a regular file, or (without ``overwrite``) that exists
    and is not a figure or an HTML page.

    Parameters
    ----------
    outputs : mapping of option name -> path or None
        The command's output options as the user typed them (``{"--csv": "x.csv"}``).
        None (option not given) and ``"-"`` (standard output) are skipped.
    inputs : mapping of argument name -> paths
        The files the command reads (``{"FILE": ["x.csv"]}``).  Inputs that do not exist
        are skipped: reading them will fail with its own message.
    overwrite : bool
        Allow replacing existing regular files that are not inputs.

    Raises
    ------
    DataError
        Naming both options and both paths, and saying what to do instead.

    Examples
    --------
    >>> import tempfile, pathlib
    >>> d = pathlib.Path(tempfile.mkdtemp())
    >>> _ = (d / "run.csv").write_text("t,rate\\n0,1\\n")
    >>> check_outputs({"--json": d / "out.json"}, {"FILE": [d / "run.csv"]})
    >>> check_outputs({"--csv": d / "run.csv"}, {"FILE": [d / "run.csv"]})  # doctest: +ELLIPSIS
    Traceback (most recent call last):
    ...
    fogts.errors.DataError: --csv '...run.csv' is the input FILE '...run.csv'; fogts never replaces an input: choose another output name
    """
    readers: dict[tuple[int, int], tuple[str, str]] = {}
    for name, paths in inputs.items():
        for p in paths:
            ident = _identity(Path(p))
            if ident is not None:
                readers.setdefault(ident[:2], (name, str(p)))
    written: dict[tuple[int, int] | str, tuple[str, str]] = {}
    for option, value in outputs.items():
        if value is None or str(value) == "-":
            continue
        path = Path(value)
        ident = _identity(path)
        if ident is not None:
            if not stat.S_ISREG(ident[2]):
                raise DataError(f"{option} {str(path)!r} is {file_kind(ident[2])}, not a regular "
                                "file; outputs are written to new or regular files only"
                                + (" (use '-' for standard output)" if option == "--json"
                                   else ""))
            if ident[:2] in readers:
                name, source = readers[ident[:2]]
                raise DataError(f"{option} {str(path)!r} is the input {name} {source!r}; fogts "
                                "never replaces an input: choose another output name")
            if not overwrite and not path.name.lower().endswith(REPLACEABLE_SUFFIXES):
                raise DataError(f"{option} {str(path)!r} already exists; fogts replaces an "
                                "existing data file only with --overwrite: choose another "
                                "output name, or pass --overwrite if that file is fogts' own "
                                "output to be replaced")
        elif not path.parent.is_dir():
            raise DataError(f"{option} {str(path)!r}: the folder {str(path.parent)!r} does not "
                            "exist; create it first or choose another output name")
        key: tuple[int, int] | str = ident[:2] if ident is not None else os.path.realpath(path)
        if key in written:
            other, first = written[key]
            raise DataError(f"{option} {str(path)!r} and {other} {first!r} name the same file; "
                            "give each output its own name")
        written[key] = (option, str(path))
