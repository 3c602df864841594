"""A published Allan curve as an :class:`~fogts.allan.result.AllanResult`: fit the IEEE-952
terms when only the curve is at hand (a datasheet curve digitised to CSV, another tool's
output, Stable32 text).

:func:`read_curve_file` reads the file (:func:`fogts.io.curve_table.read_curve_table`) and
decides what its numbers mean, saying where each came from
(:class:`CurveProvenance`):

* **unit** of the deviation: ``units``, else a unit in the column name (``adev_deg_h``),
  else deg/h *assumed*, with a warning (the recordings' policy, DESIGN.md);
* **estimator**: ``kind``, else the file (column name, SMAC ``type``, Stable32 ``Sigma
  Type``), else ``oadev``, said in a note;
* **sample rate**: ``fs_hz``, else the file (SMAC header, Stable32 ``AF``/``Tau``, an ``m``
  column), else the shortest tau taken as the sample interval, said in a note;
  ``m = round(tau fs)`` must be whole (relative 1e-4, Stable32's five printed digits);
* **record length**: ``n_samples``, else the file (SMAC header, Stable32 data points, an
  oadev ``n`` column: ``N = n + 2m - 1``), else IEEE Std 952-1997 C.3 inverted at the
  shortest tau from the point's EDF (``N = m (edf + 1)``), said in a note;
* **weights** (each point's equivalent degrees of freedom, which the fit needs), in this
  order: an ``edf`` column; SMAC's ``errors`` (IEEE 952 C.3's relative error
  ``1/sqrt(2 (N/m - 1))``, so ``edf = 1/(2 errors^2)``); Stable32's ``Alpha`` (or an
  ``alpha`` column) with the record length, through :func:`fogts.allan.edf.edf_for`
  (Greenhall & Riley 2003; NIST SP1065 sec. 5.3); the record length alone, with alpha
  identified from the curve's local slope (:func:`slope_alpha`).  Without any of these:
  a DataError naming what to give.  Weights are never invented.
"""

from __future__ import annotations

import os
import warnings
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from fogts._typing import FloatArray
from fogts._validate import check_choice, check_fraction, check_int, check_positive
from fogts.allan.confidence import chi2_interval
from fogts.allan.curve_weights import curve_weights, record_length
from fogts.allan.result import AllanResult, AllanResultSet
from fogts.allan.taus import KINDS, n_terms
from fogts.errors import DataError, DataQualityWarning
from fogts.io.accel import is_accel_name
from fogts.io.curve_table import CurveTable, read_curve_table
from fogts.units import parse_sensor_unit, quantity_of

__all__ = ["CURVE_METHODS", "CurveInput", "CurveProvenance", "read_curve_file", "read_curves"]

#: Noise-fit methods that work on a curve alone ("ml" needs the record; "gmwm" the record
#: length, which must then be stated, not estimated).
CURVE_METHODS: tuple[str, ...] = ("wls", "gls", "ols", "gmwm")
#: Largest relative departure of tau * fs from a whole number of samples.
M_TOLERANCE = 1e-4
#: Largest relative difference between a file's deviation and the root of its variance.
VAR_DEV_TOLERANCE = 1e-3


@dataclass(frozen=True)
class CurveProvenance:
    """Where each number behind the curves came from (``*_source``: ``"given"``, ``"file"``,
    ``"column name"``, ``"assumed"``, ``"inferred"``, ``"estimated"``)."""

    source: str
    layout: str
    channels: tuple[str, ...]
    kind: str
    kind_source: str
    units: str
    units_source: str
    fs_hz: float
    fs_source: str
    n_samples: int
    n_source: str
    weights: str
    confidence: float
    confidence_source: str
    columns: dict[str, str] = field(default_factory=dict)
    notes: tuple[str, ...] = ()

    @property
    def units_assumed(self) -> bool:
        """True when no unit was given or found (deg/h assumed)."""
        return self.units_source == "assumed"

    def to_dict(self) -> dict[str, Any]:
        """JSON-safe, stable keys."""
        return {"source": self.source, "format": self.layout, "channels": list(self.channels),
                "kind": self.kind, "kind_source": self.kind_source, "units": self.units,
                "units_source": self.units_source, "fs_hz": self.fs_hz,
                "fs_source": self.fs_source, "n_samples": self.n_samples,
                "n_samples_source": self.n_source, "weights": self.weights,
                "confidence": self.confidence, "confidence_source": self.confidence_source,
                "columns": dict(self.columns), "notes": list(self.notes)}

    def describe(self) -> list[str]:
        """The lines a command prints about what was read."""
        return [f"read      {self.source}: {self.kind} ({self.kind_source}) of "
                f"{', '.join(repr(c) for c in self.channels)}, deviation in {self.units} "
                f"({self.units_source})",
                f"          fs = {self.fs_hz:.6g} Hz ({self.fs_source}), n = "
                f"{self.n_samples:,} samples ({self.n_source}); weights: {self.weights}"]


@dataclass(frozen=True)
class CurveInput:
    """The curves of a file (one per channel read) and where their numbers came from."""

    curves: tuple[AllanResult, ...]
    provenance: CurveProvenance

    @property
    def result(self) -> AllanResult | AllanResultSet:
        """One curve as an AllanResult, several as an AllanResultSet."""
        return self.curves[0] if len(self.curves) == 1 else AllanResultSet(self.curves)


def read_curve_file(path: str | os.PathLike[str], *, units: str | None = None,
                    fs_hz: float | None = None, n_samples: int | None = None,
                    kind: str | None = None, channel: str | None = None,
                    confidence: float | None = None
                    ) -> AllanResult | AllanResultSet:
    """Read a published Allan curve (module docstring) for :func:`fogts.fit_noise`.

    Parameters
    ----------
    path : str or PathLike
        CSV/TSV/whitespace text with a header (SMAC-Group/avar ``*_av.csv`` included) or
        Stable32 text output.
    units : str, optional
        Rate (or specific-force) unit of the deviation; default: from the column name,
        else deg/h with a warning.
    fs_hz : float, optional
        Sample rate of the record the curve was computed from.
    n_samples : int, optional
        Number of rate samples of that record.
    kind : {"adev", "oadev", "mdev", "hdev", "ohdev", "totdev"}, optional
        The estimator (default: from the file, else oadev).
    channel : str, optional
        With a ``channel`` column: one channel's name, or ``"all"``.  Default: every
        channel of the unit's quantity (a gyro unit leaves accelerometer channels out,
        in a note).
    confidence : float, optional
        Level of the file's bounds (default: the file's, 0.954 for SMAC's 2-sigma bounds,
        else 0.683); without bounds, chi-squared intervals at this level are computed.

    Returns
    -------
    AllanResult or AllanResultSet
        One per channel read; ``notes`` say what was inferred.

    Raises
    ------
    DataError
        Anything the file or the arguments do not allow (the message says what is).

    Examples
    --------
    >>> import tempfile, pathlib
    >>> p = pathlib.Path(tempfile.mkdtemp()) / "c.csv"
    >>> _ = p.write_text("tau,oadev,edf\\n0.1,0.5,900\\n0.2,0.36,450\\n0.4,0.25,220\\n")
    >>> r = read_curve_file(p, units="deg/h", fs_hz=10)
    >>> r.kind, r.m.tolist(), r.edf.tolist()
    ('oadev', [1, 2, 4], [900.0, 450.0, 220.0])
    """
    return read_curves(path, units=units, fs_hz=fs_hz, n_samples=n_samples, kind=kind,
                       channel=channel, confidence=confidence).result


def read_curves(path: str | os.PathLike[str], *, units: str | None = None,
                fs_hz: float | None = None, n_samples: int | None = None,
                kind: str | None = None, channel: str | None = None,
                confidence: float | None = None) -> CurveInput:
    """:func:`read_curve_file` with the provenance of every number (:class:`CurveInput`)."""
    fs_given = check_positive("fs_hz", fs_hz) if fs_hz is not None else None
    n_given = check_int("n_samples", n_samples, minimum=2) if n_samples is not None else None
    level = check_fraction("confidence", confidence) if confidence is not None else None
    table = read_curve_table(path)
    name = Path(table.source).name
    notes: list[str] = []
    kind, kind_source = _kind(table, kind, notes)
    unit, unit_source = _unit(table, units, name)
    dev = _deviation(table, notes)
    picks = _channels(table, channel, unit, notes)
    first = picks[0][1]
    fs, fs_source = _sample_rate(table, first, fs_given, notes)
    # Stable32 divides TOTVAR by its bias where it identified FM noise (Howe 1999)
    corrected = table.layout == "stable32" and kind == "totdev" and "alpha" in table.numbers
    if corrected:
        notes.append("Stable32's totdev: bias-corrected where it identified FM noise (Howe "
                     "1999), fitted as printed")
    built = []
    n_info: tuple[int, str] | None = None
    weights = ""
    for label, rows in picks:
        tau = _checked_tau(table, rows)
        d = _checked_dev(table, rows, dev)
        m = _whole_m(table, rows, tau, fs)
        n_rec, n_source = record_length(table, rows, kind, m, n_given)
        w = curve_weights(table, rows, kind, tau, d, m, n_rec)
        if n_rec is None:
            n_rec, n_source = w.n_estimate, "estimated"
        if n_info is None:
            n_info, weights = (n_rec, n_source), w.description
            if n_source == "estimated":
                notes.append(f"the record length is not stated: estimated as m (edf + 1) "
                             f"= {n_rec:,} samples at the shortest tau (IEEE Std 952-1997 "
                             "C.3); it shapes the model covariance behind the standard "
                             "errors and gls; give n_samples=N")
        low, high, lvl, lvl_source = _bounds(table, rows, d, w.edf, level)
        terms = (table.numbers["terms"][rows] if "terms" in table.numbers
                 and np.all(np.isfinite(table.numbers["terms"][rows]))
                 else n_terms(kind, m, n_rec))
        built.append(AllanResult(
            kind=kind, units=unit, axis=label, fs_hz=fs, n_samples=n_rec,
            confidence=lvl, tau_s=tau, m=m, n=terms, dev=d, ci_low=low, ci_high=high,
            edf=w.edf, alpha=w.alpha, alpha_method=w.alpha_method, bias_corrected=corrected,
            notes=tuple(notes) + ((f"bounds: {lvl_source}",) if lvl_source else ())))
    assert n_info is not None
    prov = CurveProvenance(
        source=table.source, layout=table.layout, channels=tuple(c for c, _ in picks),
        kind=kind, kind_source=kind_source, units=unit, units_source=unit_source, fs_hz=fs,
        fs_source=fs_source, n_samples=n_info[0], n_source=n_info[1], weights=weights,
        confidence=built[0].confidence, confidence_source=lvl_source or "file",
        columns=dict(table.columns), notes=tuple(notes))
    return CurveInput(curves=tuple(built), provenance=prov)


def check_curve_methods(methods: list[str] | tuple[str, ...], provenance: CurveProvenance
                        ) -> None:
    """Refuse the noise-fit methods a curve cannot support: ``ml`` (exact likelihood of the
    record, which a curve does not hold) and ``gmwm`` when the record length was estimated
    (its moment covariance needs the true N)."""
    for method in methods:
        if method == "ml":
            raise DataError("method 'ml' fits the recording itself (exact Gaussian "
                            "likelihood), which a curve file does not hold; run 'fogts allan "
                            "RECORDING --method ml', or fit the curve with wls, gls or ols")
        if method == "gmwm" and provenance.n_source == "estimated":
            raise DataError("method 'gmwm' needs the record length for its moment "
                            "covariance; this curve does not state it: give n_samples=N, or "
                            "fit with wls, gls or ols")
        if method not in CURVE_METHODS:
            raise DataError(f"method must be one of {', '.join(CURVE_METHODS)} for a curve; "
                            f"got {method!r}")


def _kind(table: CurveTable, kind: str | None, notes: list[str]) -> tuple[str, str]:
    if kind is not None:
        return check_choice("kind", kind, KINDS), "given"
    if table.kind is not None:
        return table.kind, "file"
    notes.append("the estimator is not stated: taken as oadev (overlapping Allan "
                 "deviation); give kind=")
    return "oadev", "assumed"


def _unit(table: CurveTable, units: str | None, name: str) -> tuple[str, str]:
    if units is not None:
        return parse_sensor_unit(units, "units"), "given"
    if table.unit is not None:
        return table.unit, "column name"
    column = table.columns.get("dev", table.columns.get("var", ""))
    warnings.warn(f"{name}: no unit in the deviation column {column!r}; assuming deg/h; "
                  "pass units= (deg/h, deg/s, rad/s, arcsec/s)", DataQualityWarning,
                  stacklevel=3)
    return "deg/h", "assumed"


def _deviation(table: CurveTable, notes: list[str]) -> FloatArray:
    """The deviation column, or the root of the variance (checked against each other when
    both are given)."""
    var = table.var
    if var is not None:
        bad = np.flatnonzero(var < 0)
        if bad.size:
            raise DataError(f"{table.source}: column {table.columns['var']!r} has the "
                            f"negative variance {var[bad[0]]:.6g} at {table.where(bad[0])}; "
                            "a variance must be >= 0")
    if table.dev is None:
        assert var is not None
        notes.append(f"deviation = sqrt of the variance column {table.columns['var']!r}")
        return np.sqrt(var)
    if var is not None:
        root = np.sqrt(np.abs(var))
        off = np.abs(root - table.dev) > VAR_DEV_TOLERANCE * np.maximum(np.abs(table.dev),
                                                                        1e-300)
        off &= np.isfinite(root) & np.isfinite(table.dev)
        if off.any():
            i = int(np.flatnonzero(off)[0])
            raise DataError(f"{table.source}: the deviation {table.columns['dev']!r} = "
                            f"{table.dev[i]:.6g} and the root of the variance "
                            f"{table.columns['var']!r} = {root[i]:.6g} disagree at "
                            f"{table.where(i)} (by more than {VAR_DEV_TOLERANCE:g} relative); "
                            "give one of them")
    return table.dev


def _channels(table: CurveTable, channel: str | None, unit: str, notes: list[str]
              ) -> list[tuple[str, np.ndarray]]:
    """(name, row indices) of each channel read."""
    if table.channel is None:
        if channel not in (None, "all"):
            raise DataError(f"channel {channel!r}: {table.source} has no channel column "
                            "(one curve); leave out channel=")
        return [(Path(table.source).name.split(".")[0], np.arange(table.tau.size))]
    names = list(dict.fromkeys(table.channel.tolist()))
    if channel is None:
        accel = quantity_of(unit) == "accel"
        chosen = [c for c in names if is_accel_name(c) == accel]
        left = [c for c in names if c not in chosen]
        if not chosen:
            chosen, left = names, []
        if left:
            notes.append(f"left out the channels {', '.join(left)} (another quantity than "
                         f"{unit}); pick one with channel=NAME and its units=")
    elif channel == "all":
        chosen = names
    else:
        lowered = {c.lower(): c for c in names}
        if channel.lower() not in lowered:
            raise DataError(f"channel {channel!r} not found in {table.source}; channels are: "
                            f"{', '.join(names)} (or 'all')")
        chosen = [lowered[channel.lower()]]
    return [(c, np.flatnonzero(table.channel == c)) for c in chosen]


def _checked_tau(table: CurveTable, rows: np.ndarray) -> FloatArray:
    tau = table.tau[rows]
    col = table.columns["tau"]
    bad = np.flatnonzero(~np.isfinite(tau) | (tau <= 0))
    if bad.size:
        raise DataError(f"{table.source}: column {col!r} has {float(tau[bad[0]])!r} at "
                        f"{table.where(rows[bad[0]])}; every tau must be a finite number > 0 s")
    step = np.flatnonzero(np.diff(tau) <= 0)
    if step.size:
        i = step[0]
        raise DataError(f"{table.source}: column {col!r} does not increase at "
                        f"{table.where(rows[i + 1])} ({tau[i]:g} s, then {tau[i + 1]:g} s); "
                        "the taus of a curve must be strictly increasing")
    return tau


def _checked_dev(table: CurveTable, rows: np.ndarray, dev: FloatArray) -> FloatArray:
    d = dev[rows]
    col = table.columns.get("dev", table.columns.get("var", ""))
    bad = np.flatnonzero(~np.isfinite(d) | (d < 0))
    if bad.size:
        raise DataError(f"{table.source}: column {col!r} has {float(d[bad[0]])!r} at "
                        f"{table.where(rows[bad[0]])}; a deviation must be a finite "
                        "number >= 0")
    return d


def _sample_rate(table: CurveTable, rows: np.ndarray, fs: float | None, notes: list[str]
                 ) -> tuple[float, str]:
    if fs is not None:
        return fs, "given"
    if "fs_hz" in table.meta:
        return float(table.meta["fs_hz"]), "file"
    tau = table.tau[rows]
    if "m" in table.numbers and np.all(np.isfinite(table.numbers["m"][rows])):
        rates = table.numbers["m"][rows] / tau
        if np.all(np.abs(rates / rates[0] - 1.0) <= M_TOLERANCE):
            return float(np.median(rates)), "file"
    notes.append(f"the sample rate is not stated: the shortest tau, {tau[0]:g} s, taken as "
                 f"the sample interval (fs = {1.0 / tau[0]:.6g} Hz); give fs_hz= if the "
                 "record was sampled faster")
    return 1.0 / float(tau[0]), "inferred"


def _whole_m(table: CurveTable, rows: np.ndarray, tau: FloatArray, fs: float) -> np.ndarray:
    """``round(tau fs)``, refusing taus that are not whole multiples of ``1/fs``."""
    exact = tau * fs
    m = np.rint(exact)
    off = (m < 1) | (np.abs(exact - m) > M_TOLERANCE * np.maximum(m, 1.0))
    if off.any():
        i = int(np.flatnonzero(off)[0])
        raise DataError(f"{table.source}: tau = {tau[i]:.6g} s at {table.where(rows[i])} is "
                        f"not a whole number of samples at fs = {fs:.6g} Hz (tau fs = "
                        f"{exact[i]:.6g}); taus must be m / fs with m = 1, 2, ...: give the "
                        "record's fs_hz=, or round a digitised curve's taus to whole samples")
    stated = table.numbers.get("m")
    if stated is not None:
        differ = np.isfinite(stated[rows]) & (stated[rows] != m)
        if differ.any():
            i = int(np.flatnonzero(differ)[0])
            raise DataError(f"{table.source}: column {table.columns['m']!r} says m = "
                            f"{stated[rows][i]:g} at {table.where(rows[i])}, but tau fs = "
                            f"{exact[i]:.6g} at fs = {fs:.6g} Hz; give the record's fs_hz= "
                            f"({stated[rows][i] / tau[i]:.6g} Hz by the file)")
    return m.astype(np.int64)


def _bounds(table: CurveTable, rows: np.ndarray, dev: FloatArray, edf: FloatArray,
            level: float | None) -> tuple[FloatArray, FloatArray, float, str]:
    """The file's bounds and their level, or chi-squared intervals (NIST SP1065 sec. 5.3)
    from the EDF; the last item says which, if not the file's."""
    if "low" in table.numbers and "high" in table.numbers:
        low, high = table.numbers["low"][rows], table.numbers["high"][rows]
        if level is not None:
            return low, high, level, "level given"
        if "confidence" in table.meta:
            return low, high, float(table.meta["confidence"]), ""
        if table.layout == "smac":  # adev (1 -/+ 2 errors): about a 95.4 % interval
            return low, high, 0.954, "SMAC's adev (1 -/+ 2 errors), a 95.4 % level"
        return low, high, 0.683, "the file's, level not stated (taken as 68.3 %)"
    c = level if level is not None else 0.683
    lo, hi = chi2_interval(dev, edf, c)
    return (np.asarray(lo, dtype=np.float64), np.asarray(hi, dtype=np.float64), c,
            f"chi-squared at {100 * c:.1f} % from the EDF (NIST SP1065 sec. 5.3)")
