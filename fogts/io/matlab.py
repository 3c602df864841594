"""MATLAB ``.mat`` files: version 5 (scipy.io) and version 7.3 (HDF5, through h5py).

A recording saved from MATLAB is a set of named variables: matrices such as ``gyroReading``
(N x 3, one column per axis, as MATLAB's ``imuSensor`` and many loggers write them),
vectors such as ``t``, scalars such as ``fs``, and structs of those.  Every numeric vector
or matrix of the recording's length becomes columns (``gyroReading_0``, ``gyroReading_1``,
...; a struct field is ``struct.field``); a matrix stored with the samples along its
columns (3 x N) is turned round; a scalar named like a sample rate (:data:`FS_NAMES`)
gives the sample rate; shorter variables (calibration matrices, metadata) are listed in the
Table's comments and not read as data.  The column roles (rate, time, temperature) are
then recognised by name as for any other format.

Sources: the MAT-file header is 128 bytes of text starting ``MATLAB 5.0 MAT-file`` (MATLAB
"MAT-File Format", The MathWorks, R2023b); a v7.3 file is HDF5 with a 512-byte user block
holding the same header (``MATLAB 7.3 MAT-file``), and stores a MATLAB m x n matrix as an
n x m HDF5 dataset (column-major order).
"""

from __future__ import annotations

from collections.abc import Iterator, Mapping
from pathlib import Path
from typing import Any

import numpy as np

from fogts.errors import DataError
from fogts.io.arrays import named_arrays_frame
from fogts.io.limits import max_input_bytes
from fogts.io.table import Table

__all__ = ["FS_NAMES", "mat_table"]

#: Scalar variable names read as the sample rate in Hz (case-insensitive).
FS_NAMES = frozenset({"fs", "fs_hz", "fshz", "samplerate", "sample_rate", "samplingrate",
                      "sampling_rate", "samplingfrequency", "sampling_frequency"})
_HEADER = b"MATLAB "
_HDF5_SIGNATURE = b"\x89HDF\r\n\x1a\n"


def mat_table(path: Path) -> Table:
    """A MATLAB ``.mat`` file (v5 or v7.3) as a Table (see the module docstring)."""
    source = str(path)
    if path.stat().st_size > max_input_bytes():
        raise DataError(f"{source!r} is larger than the input limit; oversized input is "
                        "refused (set FOGTS_MAX_INPUT_BYTES to raise it)")
    variables = _load_v73(path) if _is_hdf5(path) else _load_v5(path)
    fs_hz, numeric = _split_variables(variables, source)
    length = max(v.shape[0] for v in numeric.values())
    kept = {k: v for k, v in numeric.items() if v.shape[0] == length}
    skipped = tuple(f"not read as data (length {v.shape[0]}, not {length}): {k} "
                    f"{'x'.join(str(d) for d in v.shape)}"
                    for k, v in numeric.items() if v.shape[0] != length)
    if sum(v.nbytes for v in kept.values()) > max_input_bytes():
        raise DataError(f"{source!r} holds more data than the input limit; oversized input "
                        "is refused (set FOGTS_MAX_INPUT_BYTES to raise it)")
    frame = named_arrays_frame({k: np.asarray(v, dtype=np.float64) for k, v in kept.items()})
    return Table(frame, source, None, skipped, fs_hz, None, True, unit_hint=next(iter(kept)))


def _is_hdf5(path: Path) -> bool:
    with path.open("rb") as fh:
        head = fh.read(520)
    if not head.startswith(_HEADER) and not head.startswith(_HDF5_SIGNATURE):
        raise DataError(f"{str(path)!r} is not a MATLAB .mat file (its header does not start "
                        "with 'MATLAB')")
    return head[512:520] == _HDF5_SIGNATURE or head.startswith(_HDF5_SIGNATURE)


def _load_v5(path: Path) -> dict[str, Any]:
    import scipy.io

    try:
        loaded = scipy.io.loadmat(path, simplify_cells=True)
    except (ValueError, TypeError, OSError, NotImplementedError) as exc:
        raise DataError(f"cannot read MATLAB file {str(path)!r}: {exc}") from None
    return {k: v for k, v in loaded.items() if not k.startswith("__")}


def _load_v73(path: Path) -> dict[str, Any]:
    try:
        import h5py
    except ImportError:  # pragma: no cover - h5py is a dependency
        raise DataError(f"{str(path)!r} is a MATLAB v7.3 (HDF5) file: install h5py, or save "
                        "it with save(..., '-v7')") from None
    try:
        with h5py.File(path, "r") as h5:
            return _hdf5_group(h5)
    except OSError as exc:
        raise DataError(f"cannot read MATLAB v7.3 file {str(path)!r}: {exc}") from None


def _hdf5_group(group: Any) -> dict[str, Any]:
    import h5py

    out: dict[str, Any] = {}
    for key, item in group.items():
        if key.startswith("#"):  # MATLAB's #refs# and #subsystem# groups
            continue
        if isinstance(item, h5py.Group):
            out[key] = _hdf5_group(item)
        elif item.dtype.kind in "fiu":
            out[key] = np.asarray(item[()]).T  # column-major: MATLAB m x n is stored n x m
    return out


def _split_variables(variables: Mapping[str, Any], source: str
                     ) -> tuple[float | None, dict[str, np.ndarray]]:
    """The sample rate (a scalar named in :data:`FS_NAMES`) and the numeric vectors and
    matrices, samples along the first axis."""
    fs_hz: float | None = None
    numeric: dict[str, np.ndarray] = {}
    for name, value in _flatten(variables):
        arr = np.asarray(value)
        if arr.dtype.kind not in "fiu" or arr.size == 0:
            continue
        if arr.size == 1:
            if name.rsplit(".", 1)[-1].lower() in FS_NAMES:
                fs_hz = float(arr.reshape(()))
            continue
        arr = np.squeeze(arr)
        if arr.ndim == 2 and arr.shape[0] < arr.shape[1]:
            arr = arr.T  # channels x samples: turn round
        if arr.ndim in (1, 2):
            numeric[name] = arr
    if not numeric:
        names = ", ".join(name for name, _ in _flatten(variables)) or "(none)"
        raise DataError(f"{source!r} holds no numeric vector or matrix; variables are: {names}")
    return fs_hz, numeric


def _flatten(variables: Mapping[str, Any], prefix: str = "") -> Iterator[tuple[str, Any]]:
    for key, value in variables.items():
        name = f"{prefix}{key}"
        if isinstance(value, Mapping):
            yield from _flatten(value, prefix=f"{name}.")
        else:
            yield name, value
