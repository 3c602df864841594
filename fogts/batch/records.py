"""The records of a batch: its options, the outcome of one run, progress, and the result.

Every record is a frozen dataclass; :class:`BatchOptions` and :class:`RunOutcome` cross process
boundaries (they are picklable).
"""

from __future__ import annotations

from collections.abc import Callable, Iterable
from dataclasses import asdict, dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np
import pandas as pd

from fogts._validate import check_choice, check_int
from fogts.allan.taus import GRID_NAMES, KINDS
from fogts.arma.select import CRITERIA
from fogts.choices import OUTPUT_UNITS
from fogts.io.missing import NAN_POLICIES
from fogts.pipeline import InputColumns, ReadSettings
from fogts.preprocess.hygiene import GAP_POLICIES

if TYPE_CHECKING:
    from fogts.allan.datasheet import NoiseSpec
    from fogts.pipeline import ReadSettings

__all__ = ["SUMMARY_COLUMNS", "Analysis", "BatchOptions", "BatchProgress", "BatchResult", "RunOutcome",
           "rows_frame"]

#: Columns of the summary table, in order (one row per run and axis).
#: ``input_units`` is the rate unit of the input; each term's values (``N``, ``N_stderr``,
#: ``N_upper``: the 95 % upper limit of a term the data only bound) are in its ``N_unit``
#: (``output_units``); ``N_spec`` is PASS/FAIL against a datasheet spec; ``fit`` the misfit
#: verdict (:func:`fogts.report.summary.axis_row`).
SUMMARY_COLUMNS: tuple[str, ...] = (
    "file", "axis", "n", "fs_hz", "input_units", "units_source", "n_gaps", "n_glitches",
    *(f"{t}{suffix}" for t in ("N", "B", "K")
      for suffix in ("", "_stderr", "_upper", "_unit", "_spec")),
    "fit", "selected", "aic", "white", "status", "error", "json",
)

_INTEGER_COLUMNS = ("n", "n_gaps", "n_glitches")
_FLOAT_COLUMNS = ("fs_hz", "N", "N_stderr", "N_upper", "B", "B_stderr", "B_upper", "K",
                  "K_stderr", "K_upper", "aic")


@dataclass(frozen=True)
class BatchOptions(InputColumns):
    """What to read and how to analyse each file (picklable; sent to every worker).

    Attributes
    ----------
    rate_column, time_column, temperature_column, fs_hz, units
        Input options, as for :func:`fogts.io.reader.read_run` (``rate_column`` may hold several
        comma-separated names).
    kind : str
        Allan estimator (``oadev`` by default).
    taus : str
        Tau grid (``octave``, ``decade``, ``dense``, ``all``).
    detrend : int or None
        Polynomial order removed before the ARMA selection (None: mean removal only).
    decimate : int or None
        Block-averaging factor applied before the ARMA selection.
    criterion : str
        Ranking criterion of the ARMA selection.
    select : bool
        Run the ARMA selection (``False`` gives info and Allan only).
    nan : str
        Empty/NaN/inf cells: ``error``, ``drop`` or ``interpolate`` (see
        :func:`fogts.io.reader.read_run`).
    gaps : str
        Gaps in the time base: ``warn``, ``error``, ``split`` or ``ignore`` (see
        :func:`fogts.preprocess.hygiene.assess_run`).
    output_units : str
        Units of the noise terms in the summary: ``deg`` or ``si``.
    spec : NoiseSpec or None
        Datasheet limits: PASS/FAIL per term (:class:`fogts.allan.datasheet.NoiseSpec`).
    """

    kind: str = "oadev"
    taus: str = "octave"
    detrend: int | None = None
    decimate: int | None = None
    criterion: str = "aic"
    select: bool = True
    nan: str = "error"
    gaps: str = "warn"
    output_units: str = "deg"
    spec: NoiseSpec | None = None

    def __post_init__(self) -> None:
        check_choice("output_units", self.output_units, OUTPUT_UNITS)
        check_choice("kind", self.kind, KINDS)
        check_choice("taus", self.taus, GRID_NAMES)
        check_choice("criterion", self.criterion, CRITERIA)
        check_choice("nan", self.nan, NAN_POLICIES)
        check_choice("gaps", self.gaps, GAP_POLICIES)
        if self.detrend is not None:
            check_int("detrend", self.detrend, minimum=0, maximum=10)
        if self.decimate is not None:
            check_int("decimate", self.decimate, minimum=1)

    @property
    def read_settings(self) -> ReadSettings:
        """The input options as the pipeline's :class:`~fogts.pipeline.ReadSettings`."""
        from fogts.pipeline import ReadSettings

        return ReadSettings(rate_column=self.rate_column, time_column=self.time_column,
                            temperature_column=self.temperature_column, fs_hz=self.fs_hz,
                            units=self.units, nan=self.nan, gaps=self.gaps)

    def to_dict(self) -> dict[str, Any]:
        out = asdict(self)
        out["spec"] = self.spec.to_dict() if self.spec is not None else None
        return out


@dataclass(frozen=True)
class RunOutcome:
    """The result of analysing one file.

    A worker returns one per file; ``resume`` rebuilds it from the per-run JSON of a file
    already done (:func:`~fogts.batch.files.load_resumed`).  :meth:`to_dict` leaves out the
    ``document`` and ``persist``.

    Attributes
    ----------
    file : str
        The file as matched by the pattern.
    status : str
        ``"ok"`` if every axis was analysed, else ``"error"``.
    error : str
        The first error message ("" when ok).
    rows : tuple of dict
        Summary rows, one per axis (one row with an empty axis if the file could not be read).
    document : dict
        The per-run JSON document (JSON-safe).
    persist : bool
        Whether the outcome is a property of the file (written as per-run JSON, so that
        ``resume`` skips it) rather than of the infrastructure (a worker that died).
    """

    file: str
    status: str
    error: str
    rows: tuple[dict[str, Any], ...]
    document: dict[str, Any] = field(default_factory=dict)
    persist: bool = True

    def to_dict(self) -> dict[str, Any]:
        return {"file": self.file, "status": self.status, "error": self.error,
                "rows": [dict(r) for r in self.rows]}


@dataclass(frozen=True)
class BatchProgress:
    """Progress of a batch, passed to the ``progress`` callback after each finished run."""

    total: int
    done: int
    failed: int
    skipped: int
    last_file: str | None = None

    @property
    def remaining(self) -> int:
        return self.total - self.done


@dataclass(frozen=True)
class BatchResult:
    """What a batch did.

    Attributes
    ----------
    rows : tuple of dict
        The summary rows (columns :data:`SUMMARY_COLUMNS`), sorted by file and axis.
    files : tuple of str
        Every matched file, in order.
    summary_path : Path
    json_dir : Path
    n_skipped : int
        Runs read back from existing per-run JSON (``resume``).
    interrupted : bool
        True if the batch stopped before every run finished.
    seconds : float
        Wall-clock time.
    backend : str
        ``"serial"``, ``"process-pool"`` or ``"dask"``.
    """

    rows: tuple[dict[str, Any], ...]
    files: tuple[str, ...]
    summary_path: Path
    json_dir: Path
    n_skipped: int = 0
    interrupted: bool = False
    seconds: float = 0.0
    backend: str = "serial"

    @property
    def n_files(self) -> int:
        return len(self.files)

    @property
    def n_ok(self) -> int:
        """Runs (files) with every axis ok."""
        return len(self._status_by_file()) - self.n_error

    @property
    def n_error(self) -> int:
        """Runs (files) with at least one failed axis."""
        return sum(1 for s in self._status_by_file().values() if s == "error")

    def _status_by_file(self) -> dict[str, str]:
        status: dict[str, str] = {}
        for r in self.rows:
            if r["status"] == "error" or r["file"] not in status:
                status[r["file"]] = r["status"]
        return status

    def to_frame(self) -> pd.DataFrame:
        return rows_frame(self.rows)

    def to_dict(self) -> dict[str, Any]:
        return {"files": len(self.files), "ok": self.n_ok, "error": self.n_error,
                "skipped": self.n_skipped, "interrupted": self.interrupted,
                "backend": self.backend, "summary": str(self.summary_path),
                "json_dir": str(self.json_dir), "rows": [dict(r) for r in self.rows]}

    def summary(self) -> str:
        done = len(self._status_by_file())
        lines = [f"batch ({self.backend}): {done} of {self.n_files} run(s) done, "
                 f"{self.n_ok} ok, {self.n_error} failed, {self.n_skipped} resumed from JSON, "
                 f"{self.seconds:.1f} s",
                 f"summary  {self.summary_path}", f"per-run  {self.json_dir}"]
        if self.interrupted:
            lines.append("interrupted: rerun with --resume to finish")
        return "\n".join(lines)


#: The per-file analysis of a batch: ``analysis(file, options) -> RunOutcome`` (picklable).
Analysis = Callable[[str, BatchOptions], RunOutcome]


def rows_frame(rows: Iterable[dict[str, Any]]) -> pd.DataFrame:
    """Summary rows as a table with the columns :data:`SUMMARY_COLUMNS` and fixed dtypes."""
    frame = pd.DataFrame(list(rows), columns=list(SUMMARY_COLUMNS))
    for col in _INTEGER_COLUMNS:
        frame[col] = frame[col].astype("Int64")
    for col in _FLOAT_COLUMNS:
        frame[col] = pd.to_numeric(frame[col], errors="coerce").astype(np.float64)
    frame["white"] = frame["white"].astype("boolean")
    frame["error"] = frame["error"].fillna("")
    return frame
