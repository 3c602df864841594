"""Reading a published Allan curve: a table of tau against the deviation, not a recording.

:func:`read_curve_table` opens the file and finds its columns by name; what the numbers
mean (units, sample rate, weights) is decided by :mod:`fogts.allan.curve_input`.  Three
layouts are recognised:

* a delimited or whitespace text table with a header line (``#`` comment lines skipped):
  a tau column and a deviation (or variance) column, optionally a channel column, bounds,
  an ``edf`` or ``errors`` column, ``m``, ``n`` (number of terms) and ``alpha``;
* the SMAC-Group/avar ``*_av.csv`` export, the same with ``freq_hz=[...]`` and ``n=[...]``
  on its first comment line;
* Stable32 text output: the comment header (``Sigma Type``, ``Phase`` or ``Frequency Data
  Points``, ``Confidence Factor``) and the columns ``AF Tau # Alpha MinSigma Sigma
  MaxSigma`` (a 0 bound means none).
"""

from __future__ import annotations

import dataclasses
import os
import re
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from fogts._typing import FloatArray
from fogts.errors import DataError
from fogts.io.columns import _is_rate_name, _is_time_name, _norm, _unit_from_names
from fogts.io.limits import check_regular_file
from fogts.io.table import Table, numeric_column
from fogts.io.text import text_file_table

__all__ = ["STABLE32_KINDS", "CurveTable", "read_curve_table"]

#: Stable32's "Sigma Type" names of the estimators fogts computes.
STABLE32_KINDS: dict[str, str] = {
    "allan": "adev", "overlapping allan": "oadev", "modified allan": "mdev",
    "hadamard": "hdev", "overlapping hadamard": "ohdev", "total": "totdev"}
_STABLE32_HEADER = re.compile(r"^#\s*AF\s+Tau\s+#\s+Alpha\b", re.IGNORECASE)
_STABLE32_NAMES = ["af", "tau", "terms", "alpha", "min_sigma", "sigma", "max_sigma"]
_RECORDING_SUFFIXES = (".npy", ".npz", ".mat", ".bag")

_TAU_NAMES = ("tau", "tau_s", "tau_sec", "taus", "averaging_time", "averaging_time_s",
              "tau_seconds")
#: Deviation column names and the estimator they name (None: not said).
DEV_NAMES: dict[str, str | None] = {
    "adev": "adev", "oadev": "oadev", "mdev": "mdev", "hdev": "hdev", "ohdev": "ohdev",
    "totdev": "totdev", "dev": None, "sigma": None, "deviation": None,
    "allan_deviation": None, "allan_dev": None, "overlapping_allan_deviation": "oadev"}
VAR_NAMES: dict[str, str | None] = {
    "avar": None, "oavar": "oadev", "allan_variance": None, "variance": None,
    "allan_var": None, "overlapping_allan_variance": "oadev"}
#: The optional columns by role, and their names.
_OPTIONAL: tuple[tuple[str, tuple[str, ...]], ...] = (
    ("edf", ("edf",)), ("errors", ("errors", "error", "rel_error")),
    ("m", ("m", "af", "averaging_factor")), ("terms", ("n", "terms", "n_terms", "#")),
    ("alpha", ("alpha",)), ("channel", ("channel", "axis", "sensor_axis")),
    ("type", ("type",)))
_LOW_NAMES = ("lci", "ci_low", "lower", "low", "min_sigma", "lo")
_HIGH_NAMES = ("uci", "ci_high", "upper", "high", "max_sigma", "hi")


@dataclass(frozen=True)
class CurveTable:
    """The columns of a curve file, found by name (rows in file order).

    A ``"table"`` is any delimited text with a header; a ``"smac"`` file is SMAC-Group/avar's
    table, whose header comment gives the sample rate and record length and whose ``type``
    column the estimator; ``"stable32"`` is Stable32's text output with its fixed columns.  Nothing here decides what the numbers mean
    (unit, sample rate, weights): :mod:`fogts.allan.curve_input` does.

    Attributes
    ----------
    source : str
        The file.
    layout : {"table", "smac", "stable32"}
        Which of the three it is.
    tau : ndarray
        The ``tau_column``'s values (s).
    dev : ndarray or None
        The deviation column (None when only a variance was given).
    var : ndarray or None
        The variance column, if any.
    columns : dict of str to str
        Role (``tau``, ``dev``, ``var``, ``low``, ``high``, ``edf``, ``errors``, ``m``,
        ``terms``, ``alpha``, ``channel``, ``type``) -> the column's name in the file.
    numbers : dict of str to ndarray
        The optional numeric columns by role.
    channel : ndarray of str or None
        The channel (axis) of each row.
    kind : str or None
        The estimator the file names (column name, SMAC ``type``, Stable32 ``Sigma Type``).
    unit : str or None
        A rate unit in the deviation column's name (``adev_deg_h``).
    meta : dict
        From the header: ``fs_hz``, ``n_samples``, ``confidence``, ``sigma_type``.
    line_of_row : ndarray or None
        The file line of each row of a text file, for the errors (:meth:`where`).
    """

    source: str
    layout: str
    tau: FloatArray
    dev: FloatArray | None
    var: FloatArray | None
    columns: dict[str, str]
    numbers: dict[str, FloatArray] = field(default_factory=dict)
    channel: np.ndarray | None = None
    kind: str | None = None
    unit: str | None = None
    meta: dict[str, float | int | str] = field(default_factory=dict)
    line_of_row: np.ndarray | None = None

    def where(self, row: int) -> str:
        """``"line 9"`` of a text row, else ``"row 7"``."""
        if self.line_of_row is not None:
            return f"line {int(self.line_of_row[row])}"
        return f"row {row + 1}"


def read_curve_table(path: str | os.PathLike[str]) -> CurveTable:
    """Read an Allan curve file and find its columns (module docstring).

    Raises
    ------
    DataError
        Missing or unreadable file, a recording format, an empty file, no tau or no
        deviation column (a recording's columns are named as such), non-numeric or missing
        cells.

    Examples
    --------
    >>> import tempfile, pathlib
    >>> p = pathlib.Path(tempfile.mkdtemp()) / "c.csv"
    >>> _ = p.write_text("tau,adev_deg_h\\n1,0.1\\n2,0.07\\n")
    >>> t = read_curve_table(p)
    >>> t.tau.tolist(), t.unit, t.columns["dev"]
    ([1.0, 2.0], 'deg/h', 'adev_deg_h')
    """
    source = Path(path)
    if not source.exists():
        raise DataError(f"curve file not found: {str(source)!r}")
    if source.suffix.lower() in _RECORDING_SUFFIXES:
        raise DataError(f"{str(source)!r} is a recording format ({source.suffix}); a curve "
                        "file is a text table of tau and the deviation; run 'fogts allan' "
                        "on a recording")
    check_regular_file(source, "curve file")
    table = text_file_table(source)
    if table.reparse is not None:  # the line-by-line parse names file lines in errors
        table = table.reparse()
    if any(_STABLE32_HEADER.match(c) for c in table.comments):
        return _stable32(table)
    return _named_columns(table)


def _stable32(table: Table) -> CurveTable:
    names = list(table.frame.columns)
    if len(names) != len(_STABLE32_NAMES):
        raise DataError(f"{table.source!r}: a Stable32 table has 7 columns (AF Tau # Alpha "
                        f"MinSigma Sigma MaxSigma); this one has {len(names)}")
    table = dataclasses.replace(table, frame=table.frame.set_axis(_STABLE32_NAMES, axis=1))
    col = {n: numeric_column(table, n, missing_ok=True) for n in _STABLE32_NAMES}
    meta: dict[str, float | int | str] = {}
    for c in table.comments:
        if m := re.search(r"Sigma Type:\s*(.+)$", c):
            meta["sigma_type"] = m.group(1).strip()
        elif m := re.search(r"(Phase|Frequency) Data Points \d+ thru \d+ of (\d+)", c):
            count = int(m.group(2))  # phase points are one more than rate samples
            meta["n_samples"] = count - 1 if m.group(1) == "Phase" else count
        elif m := re.search(r"Confidence Factor\s*=\s*([0-9.]+)", c):
            meta["confidence"] = float(m.group(1))
    sigma_type = str(meta.get("sigma_type", ""))
    kind = STABLE32_KINDS.get(sigma_type.lower())
    if kind is None:
        raise DataError(f"{table.source!r}: Stable32 Sigma Type {sigma_type or '(none)'!r} "
                        f"is not an estimator fogts reads; allowed: "
                        f"{', '.join(STABLE32_KINDS)}")
    numbers = {"m": col["af"], "terms": col["terms"], "alpha": col["alpha"]}
    low, high = col["min_sigma"], col["max_sigma"]
    if np.any(low > 0):  # 0 means "no bound printed"
        numbers["low"] = np.where(low > 0, low, np.nan)
        numbers["high"] = np.where(high > 0, high, np.nan)
    roles = {"tau": "Tau", "dev": "Sigma", "m": "AF", "terms": "#", "alpha": "Alpha",
             "low": "MinSigma", "high": "MaxSigma"}
    return CurveTable(source=table.source, layout="stable32", tau=col["tau"],
                      dev=col["sigma"], var=None, columns=roles, numbers=numbers, kind=kind,
                      meta=meta, line_of_row=table.line_of_row)


def _find(names: dict[str, str], candidates: tuple[str, ...] | dict[str, str | None]
          ) -> str | None:
    """The first column whose normalised name is a candidate, or a candidate followed by
    a unit (``adev_deg_h``) or a bracketed unit (``tau (s)`` -> ``tau_s``)."""
    for cand in candidates:
        for norm, name in names.items():
            if norm == cand or (_unit_from_names([norm]) and norm.startswith(cand + "_")
                                and _unit_from_names([norm[len(cand):]])):
                return name
    return None


def _named_columns(table: Table) -> CurveTable:
    names = {_norm(str(c)): str(c) for c in table.frame.columns}
    listed = ", ".join(map(str, table.frame.columns))
    tau = _find(names, _TAU_NAMES)
    if tau is None:
        recording = [c for c in table.frame.columns if _is_time_name(str(c))
                     or _is_rate_name(str(c))]
        if recording or not table.header:
            raise DataError(f"{table.source!r} looks like a recording, not an Allan curve "
                            f"(columns: {listed}); run 'fogts allan' on it, or give a curve "
                            "with a tau column and a deviation column")
        raise DataError(f"{table.source!r} has no tau column; columns are: {listed}; name "
                        f"it one of {', '.join(_TAU_NAMES)}")
    dev = _find(names, DEV_NAMES)
    var = _find(names, VAR_NAMES)
    if dev is None and var is None:
        raise DataError(f"{table.source!r} has no deviation or variance column; columns "
                        f"are: {listed}; name the deviation one of {', '.join(DEV_NAMES)} "
                        f"or the variance one of {', '.join(VAR_NAMES)}")
    roles = {"tau": tau}
    stem = _norm(dev or var or "")
    for role, cands in (("low", _LOW_NAMES), ("high", _HIGH_NAMES)):
        found = _find(names, tuple(f"{stem}_{c}" for c in cands) + cands)
        if found is not None:
            roles[role] = found
    for role, names_of_role in _OPTIONAL:
        found = _find(names, names_of_role)
        if found is not None:
            roles[role] = found
    numbers = {r: numeric_column(table, c, missing_ok=True) for r, c in roles.items()
               if r not in ("tau", "channel", "type")}
    kind = (DEV_NAMES.get(_norm(dev)) if dev is not None else None) or (
        VAR_NAMES.get(_norm(var)) if var is not None else None)
    if "type" in roles:
        kinds = {str(v).strip().lower() for v in table.frame[roles["type"]]}
        avar_types = {"mo": "oadev", "to": "adev"}  # SMAC avar: maximal / tau overlap
        if len(kinds) == 1 and next(iter(kinds)) in avar_types:
            kind = avar_types[next(iter(kinds))]  # the estimator itself, over the name
    meta: dict[str, float | int | str] = {}
    first = table.comments[0] if table.comments else ""
    if (fs := re.search(r"freq_hz=\[([0-9.eE+-]+)\]", first)) is not None:
        meta["fs_hz"] = float(fs.group(1))
    if (n := re.search(r"\bn=\[([0-9]+)\]", first)) is not None:
        meta["n_samples"] = int(n.group(1))
    if dev is not None:
        roles["dev"] = dev
    if var is not None:
        roles["var"] = var
    channel = (table.frame[roles["channel"]].astype(str).str.strip().to_numpy()
               if "channel" in roles else None)
    return CurveTable(
        source=table.source, layout="smac" if "fs_hz" in meta and "errors" in roles
        else "table", tau=numeric_column(table, tau, missing_ok=True),
        dev=numeric_column(table, dev, missing_ok=True) if dev is not None else None,
        var=numeric_column(table, var, missing_ok=True) if var is not None else None, columns=roles,
        numbers={k: v for k, v in numbers.items() if k not in ("dev", "var")},
        channel=channel, kind=kind,
        unit=_unit_from_names([dev or var or ""]), meta=meta, line_of_row=table.line_of_row)
