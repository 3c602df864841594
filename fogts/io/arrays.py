"""Array sources: Parquet, NumPy ``.npy``/``.npz`` files and in-memory frames and arrays.

``.npy`` holds a 1-D rate, or a 2-D array with one column per axis; ``.npz`` holds named
arrays (an ``fs_hz`` key gives the sample rate, a ``columns`` key the axis names).  Both are
loaded with ``allow_pickle=False``: reading never executes anything from the input.  A
pandas DataFrame or Series keeps a DatetimeIndex or TimedeltaIndex as its time base.
"""

from __future__ import annotations

import dataclasses
import io
import zipfile
from collections.abc import Callable, Sequence
from pathlib import Path

import numpy as np
import pandas as pd

from fogts._validate import sums_known
from fogts.errors import DataError
from fogts.io.limits import NpyHeader, check_npy, check_npz, max_input_bytes
from fogts.io.table import Table, finite_and_bounded
from fogts.io.timesteps import pairwise_fold_halves

__all__ = ["array_table", "frame_table", "named_arrays_frame", "npy_table", "npz_table",
           "parquet_table"]


def frame_table(frame: pd.DataFrame, source: str) -> Table:
    """A DataFrame as a Table; a DatetimeIndex or TimedeltaIndex becomes the time base, and
    any other named index (``df.set_index("time")``) a column of that name."""
    if frame.shape[1] == 0:
        raise DataError(f"{source} has no columns")
    index = frame.index if isinstance(frame.index, pd.DatetimeIndex | pd.TimedeltaIndex) else None
    names = [n for n in frame.index.names if n is not None]
    named = (index is None and len(names) == frame.index.nlevels
             and not set(map(str, names)) & set(map(str, frame.columns)))
    out = frame.reset_index(drop=not named)
    out.columns = [str(c) for c in out.columns]
    return Table(out, source, None, (), None, index, header=True)


def array_table(arr: np.ndarray, source: str, fs_hz: float | None,
                names: Sequence[str] | None = None, *, copy: bool = True) -> Table:
    """A 1-D (rate) or 2-D (samples x axes) numeric array as a Table (``copy=False``: the
    table's columns are views of ``arr``, for an array the reader loaded itself)."""
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
    frame = pd.DataFrame({str(n): arr[:, i] for i, n in enumerate(names)}, copy=copy)
    return Table(frame, source, None, (), fs_hz, None, header=True)


def parquet_table(path: Path) -> Table:
    """A Parquet file no larger than :func:`fogts.io.limits.max_input_bytes`."""
    if path.stat().st_size > max_input_bytes():
        raise DataError(f"{str(path)!r} is larger than the input limit; oversized "
                        "input is refused (set FOGTS_MAX_INPUT_BYTES to raise it)")
    try:
        # One block per column (no consolidating copy), and each column's arrow memory
        # released as it is converted.
        frame = pd.read_parquet(path, engine="pyarrow",
                                to_pandas_kwargs={"split_blocks": True, "self_destruct": True})
    except Exception as exc:  # pyarrow raises several unrelated types
        raise DataError(f"cannot read Parquet file {str(path)!r}: {exc}") from None
    table = frame_table(frame, str(path))
    return Table(table.frame, str(path), None, (), None, table.from_index, True)


def _check_signature(path: Path, magic: bytes, kind: str) -> None:
    with path.open("rb") as fh:
        head = fh.read(len(magic))
    if head != magic:
        raise DataError(f"{str(path)!r} is not a valid {kind} file (wrong signature)")


def npy_table(path: Path) -> Table:
    """An ``.npy`` file, its signature and declared size checked before it is loaded."""
    _check_signature(path, b"\x93NUMPY", ".npy")
    header = check_npy(path)
    if header.dtype == np.dtype(np.float64) and not header.fortran_order:
        arr, clean, total = _read_checked_float64(path, header)
        table = array_table(arr, str(path), fs_hz=None, copy=False)
        sums = {str(table.frame.columns[0]): total} if total is not None else None
        return dataclasses.replace(table, checked=clean, sums=sums)
    try:
        arr = np.load(path, allow_pickle=False)
    except ValueError as exc:
        raise DataError(f"cannot read {str(path)!r}: {exc} (pickled object arrays are never "
                        "loaded)") from None
    except OSError as exc:
        raise DataError(f"{str(path)!r} is not a valid .npy file ({exc})") from None
    return array_table(np.asarray(arr), str(path), fs_hz=None, copy=False)


def _read_checked_float64(path: Path, header: NpyHeader
                          ) -> tuple[np.ndarray, bool, float | None]:
    """The native float64 C-order array of an ``.npy``, whether every value is finite
    and within :data:`~fogts.io.table.MAX_ABS_VALUE`, and, for a 1-D array read within
    :func:`fogts._validate.known_sums`, ``numpy.sum`` of it (else None).

    The array is read in blocks of at most 2^16 values (512 KiB), each checked (and summed)
    while it is in the cache: the check costs a few per cent of the read instead of two
    passes over memory.  The blocks are the nodes of numpy's pairwise summation
    (:func:`~fogts.io.timesteps.pairwise_fold_halves`, the two halves read on two threads
    for a large file, each with its own file handle), so their sums add up to
    ``numpy.sum`` bit for bit.  The values are those of ``np.load``, bit for bit.

    A 1-D array is read into the tail ``buf[1:]`` of a buffer one point longer, so that an
    owner that reads the rate no more can form its phase (``n + 1`` points) in the same
    memory instead of a second array (:func:`fogts.allan.kernels.phase_in_place`)."""
    if len(header.shape) == 1:
        arr = np.empty(header.shape[0] + 1, dtype=np.float64)[1:]
    else:
        arr = np.empty(header.shape, dtype=np.float64)
    flat = arr.reshape(-1)
    raw = flat.data.cast("B")
    summing = arr.ndim == 1 and sums_known()
    handles: list[io.FileIO] = []  # one per thread, each positioned by its blocks
    try:
        def make_block() -> Callable[[int, int], tuple[bool, float]]:
            fh = open(path, "rb", buffering=0)  # closed below
            handles.append(fh)

            def block(start: int, stop: int) -> tuple[bool, float]:
                fh.seek(header.offset + start * 8)
                _read_exactly(fh, raw[start * 8:stop * 8], path)
                ok = finite_and_bounded(flat[start:stop])
                return ok, float(np.sum(flat[start:stop])) if summing and ok else 0.0
            return block

        clean, total = pairwise_fold_halves(0, flat.size, make_block,
                                            lambda a, b: (a[0] and b[0], a[1] + b[1]))
    finally:
        for fh in handles:
            fh.close()
    return arr, clean, total if summing and clean else None


def _read_exactly(fh: io.FileIO, into: memoryview, path: Path) -> None:
    got = 0
    while got < len(into):
        n = fh.readinto(into[got:])
        if not n:
            raise DataError(f"{str(path)!r} is truncated: it ended while its data were read")
        got += n


def npz_table(path: Path) -> Table:
    """An ``.npz`` file: every numeric 1-D or 2-D array becomes columns (a 2-D array's
    columns are named by a ``columns`` key when it is the only one); ``fs_hz`` is the
    sample rate; the first array's key is a unit hint (``gyro_deg_s``)."""
    _check_signature(path, b"PK\x03\x04", ".npz")
    check_npz(path)
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
    length = {v.shape[0] for v in numeric.values()}
    if len(length) > 1:
        raise DataError(f"{str(path)!r}: arrays have different lengths "
                        f"{ {k: v.shape[0] for k, v in numeric.items()} }")
    labels = ([str(c) for c in names_arr] if names_arr is not None and len(numeric) == 1
              else None)
    frame = named_arrays_frame(numeric, labels)
    return Table(frame, str(path), None, (), fs_hz, None, True, unit_hint=next(iter(numeric)))


def named_arrays_frame(arrays: dict[str, np.ndarray],
                       labels: Sequence[str] | None = None) -> pd.DataFrame:
    """Named 1-D and 2-D (samples x channels) arrays of one length as frame columns: a 1-D
    array keeps its name, a 2-D one gives ``name_0``, ``name_1``, ... (or ``labels``, for
    a single 2-D array with as many columns)."""
    columns: dict[str, np.ndarray] = {}
    for key, arr in arrays.items():
        if arr.ndim == 1:
            columns[key] = arr
            continue
        names = (list(labels) if labels is not None and len(labels) == arr.shape[1]
                 else [f"{key}_{i}" for i in range(arr.shape[1])])
        for i, name in enumerate(names):
            columns[name] = arr[:, i]
    return pd.DataFrame(columns)
