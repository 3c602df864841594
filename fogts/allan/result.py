"""Result records of the Allan analysis: one curve (:class:`AllanResult`) or one per axis.

Both are frozen dataclasses with ``to_frame()``, ``to_dict()`` (JSON-safe, stable keys) and
``summary()``.  The arrays are stored read-only.
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Iterator
from dataclasses import dataclass
from typing import Any, Generic, Protocol, TypeVar

import numpy as np
import pandas as pd

from fogts._typing import FloatArray, IntArray
from fogts._validate import finite_or_none
from fogts.allan.taus import DroppedTau
from fogts.errors import DataError
from fogts.tables import Column, Table, TableView
from fogts.units import convert_sensor, parse_sensor_unit

__all__ = ["KIND_LABELS", "AllanResult", "AllanResultSet", "AxisIndexed"]

#: Long names used in summaries and plot labels.
KIND_LABELS: dict[str, str] = {
    "adev": "Allan deviation (non-overlapping)",
    "oadev": "overlapping Allan deviation",
    "mdev": "modified Allan deviation",
    "hdev": "Hadamard deviation (non-overlapping)",
    "ohdev": "overlapping Hadamard deviation",
    "totdev": "total deviation",
}

_FLOAT_FIELDS = ("tau_s", "dev", "ci_low", "ci_high", "edf")
_INT_FIELDS = ("m", "n", "alpha")


def _frozen(a: Any, dtype: type) -> np.ndarray:
    arr: np.ndarray = np.array(a, dtype=dtype, copy=True).reshape(-1)
    arr.setflags(write=False)
    return arr


@dataclass(frozen=True, repr=False)
class AllanResult(TableView):
    """One Allan-family curve with per-point uncertainty.

    Attributes
    ----------
    kind : str
        Estimator: ``adev``, ``oadev``, ``mdev``, ``hdev``, ``ohdev`` or ``totdev``.
    units : str
        Unit of the rate, hence of ``dev``, ``ci_low`` and ``ci_high``.
    axis : str
        Name of the axis (rate column) analysed.
    fs_hz : float
        Sample rate of the analysed series.
    n_samples : int
        Number of rate samples analysed.
    confidence : float
        Level of the confidence intervals (NaN when none were computed).
    tau_s : ndarray of float64
        Averaging times, ``m / fs_hz``.
    m : ndarray of int64
        Averaging factors.
    n : ndarray of int64
        Number of terms at each tau (Stable32's ``#``).
    dev : ndarray of float64
        The deviation.
    ci_low, ci_high : ndarray of float64
        Chi-squared confidence limits of ``dev`` (NaN when not computed).
    edf : ndarray of float64
        Equivalent degrees of freedom (NaN when not computed).
    alpha : ndarray of int64
        Power-law noise exponent used for each point's EDF: identified there, or taken
        from the nearest identified tau where ``alpha_method`` is ``"none"``.  Reported
        as missing (``None``/``<NA>``) where no interval was computed.
    bias_corrected : bool
        True for a ``totdev`` curve divided by its noise-type bias
        (:func:`fogts.allan.confidence.totdev_bias`), as Stable32 reports it.
    dropped : tuple of DroppedTau
        Requested taus that could not be computed.
    alpha_method : tuple of str
        How each alpha was found: ``"acf"``, ``"b1"``, ``"rn"`` or ``"none"``.
    notes : tuple of str
        Anything else done to the request or the data (tau rounding, preparation steps,
        why no confidence intervals are given).
    """

    kind: str
    units: str
    axis: str
    fs_hz: float
    n_samples: int
    confidence: float
    tau_s: FloatArray
    m: IntArray
    n: IntArray
    dev: FloatArray
    ci_low: FloatArray
    ci_high: FloatArray
    edf: FloatArray
    alpha: IntArray
    bias_corrected: bool = False
    dropped: tuple[DroppedTau, ...] = ()
    alpha_method: tuple[str, ...] = ()
    notes: tuple[str, ...] = ()

    def __post_init__(self) -> None:
        for name in _FLOAT_FIELDS:
            object.__setattr__(self, name, _frozen(getattr(self, name), np.float64))
        for name in _INT_FIELDS:
            object.__setattr__(self, name, _frozen(getattr(self, name), np.int64))
        size = self.dev.size
        for name in (*_FLOAT_FIELDS, *_INT_FIELDS):
            if getattr(self, name).size != size:
                raise DataError(f"AllanResult.{name} has {getattr(self, name).size} values; "
                                f"dev has {size}")
        methods = tuple(self.alpha_method) or ("none",) * size
        if len(methods) != size:
            raise DataError(f"AllanResult.alpha_method has {len(methods)} values; dev has "
                            f"{size}")
        object.__setattr__(self, "alpha_method", methods)
        object.__setattr__(self, "dropped", tuple(self.dropped))
        object.__setattr__(self, "notes", tuple(self.notes))

    def __len__(self) -> int:
        return int(self.dev.size)

    @property
    def avar(self) -> FloatArray:
        """The variance, ``dev ** 2``."""
        return self.dev**2

    @property
    def has_ci(self) -> bool:
        """True when confidence intervals were computed for at least one point."""
        return bool(np.isfinite(self.ci_low).any())

    def within(self, tau_min_s: float | None = None, tau_max_s: float | None = None
               ) -> AllanResult:
        """The points with ``tau_min_s <= tau <= tau_max_s`` (None: no bound), e.g. the range
        a noise model is fitted over."""
        lo = -np.inf if tau_min_s is None else float(tau_min_s)
        hi = np.inf if tau_max_s is None else float(tau_max_s)
        if not lo < hi:
            raise DataError(f"the tau range must have tau_min < tau_max, got tau_min = {lo:g} s "
                            f"and tau_max = {hi:g} s")
        keep = (self.tau_s >= lo * (1 - 1e-9)) & (self.tau_s <= hi * (1 + 1e-9))
        n = self.tau_s.size
        per_tau = {f.name: getattr(self, f.name) for f in dataclasses.fields(self)
                   if isinstance(getattr(self, f.name), np.ndarray | tuple)
                   and len(getattr(self, f.name)) == n and f.name != "dropped"}
        sliced: dict[str, Any] = {
            k: (v[keep] if isinstance(v, np.ndarray)
                else tuple(x for x, k2 in zip(v, keep, strict=True) if k2))
            for k, v in per_tau.items()}
        return dataclasses.replace(self, **sliced)

    def readout(self, noise: Any = None) -> Any:
        """Curve read-outs: minimum with its CI, regions A-D, segment slopes and, given the
        fitted :class:`~fogts.allan.noise.NoiseModel`, where each term dominates.

        Returns a :class:`fogts.allan.readout.CurveReadout` (see :func:`read_curve`); the
        dominant ranges that leave the taus ``noise`` was fitted over (a ``tau_range`` fit)
        are marked extrapolated.
        """
        from fogts.allan.readout import read_curve

        lines = noise.lines(self.tau_s) if noise is not None else None
        limits = [t.name for t in noise.terms if t.is_limit] if noise is not None else ()
        fitted = (float(noise.tau_s[0]), float(noise.tau_s[-1])) \
            if noise is not None and len(noise.tau_s) else None
        return read_curve(self.tau_s, self.dev, self.ci_low, self.ci_high,
                          confidence=self.confidence, edf=self.edf, term_curves=lines,
                          limits=limits, kind=self.kind, fit_tau_s=fitted)

    def _alpha_or_none(self) -> list[int | None]:
        # The alpha behind each point's EDF; None where no interval was computed.
        return [int(a) if math.isfinite(e) else None
                for a, e in zip(self.alpha, self.edf, strict=True)]

    def to_frame(self) -> pd.DataFrame:
        """One row per tau: ``tau, m, n, dev, ci_low, ci_high, edf, alpha``.

        ``alpha`` is a nullable integer column (missing where no interval was computed).
        """
        return pd.DataFrame({
            "tau": self.tau_s, "m": self.m, "n": self.n, "dev": self.dev,
            "ci_low": self.ci_low, "ci_high": self.ci_high, "edf": self.edf,
            "alpha": pd.array(self._alpha_or_none(), dtype="Int64"),
        })

    def to_dict(self) -> dict[str, Any]:
        """JSON-safe dict with stable keys; NaN becomes None."""
        alphas = self._alpha_or_none()
        points = [
            {"tau": float(self.tau_s[i]), "m": int(self.m[i]), "n": int(self.n[i]),
             "dev": finite_or_none(self.dev[i]), "ci_low": finite_or_none(self.ci_low[i]),
             "ci_high": finite_or_none(self.ci_high[i]), "edf": finite_or_none(self.edf[i]), "alpha": alphas[i],
             "alpha_method": self.alpha_method[i]}
            for i in range(len(self))
        ]
        return {"kind": self.kind, "units": self.units, "axis": self.axis,
                "fs_hz": float(self.fs_hz), "n_samples": int(self.n_samples),
                "confidence": finite_or_none(self.confidence), "bias_corrected": self.bias_corrected,
                "points": points,
                "dropped": [d.to_dict() for d in self.dropped], "notes": list(self.notes)}

    def points_table(self, rate_units: str | None = None) -> Table:
        """The points: tau, averaging factor, number of terms, deviation, interval, EDF;
        the deviations in ``rate_units`` (default: the input's unit)."""
        pct = f"{100 * self.confidence:.1f} % CI" if math.isfinite(self.confidence) \
            else "no CI"
        corrected = ", bias-corrected (Howe 1999)" if self.bias_corrected else ""
        unit = self.units if rate_units is None else parse_sensor_unit(rate_units, "rate_units")
        scale = float(convert_sensor(1.0, self.units, unit)) if unit != self.units else 1.0
        rows = list(zip(self.tau_s.tolist(), self.m.tolist(), self.n.tolist(),
                        (self.dev * scale).tolist(), (self.ci_low * scale).tolist(),
                        (self.ci_high * scale).tolist(), self.edf.tolist(), strict=True))
        return Table.build(
            f"{self.kind} of {self.axis} ({unit}), {pct}{corrected}",
            (Column("tau (s)", digits=6), Column("m"), Column("terms"), Column("dev", digits=5),
             Column("ci_low", digits=5), Column("ci_high", digits=5), Column("edf")), rows)

    # -------------------------------------------------------------- notebook view
    def _view_table(self) -> Table:
        return self.points_table()

    def _view_headline(self) -> str:
        return (f"{self.kind} of {self.axis!r}, {self.tau_s.size} taus "
                f"{self.tau_s[0]:.3g}..{self.tau_s[-1]:.3g} s, {self.units}")

    def summary(self) -> str:
        """Plain-text table of the curve, the dropped taus and the notes."""
        label = KIND_LABELS.get(self.kind, self.kind)
        lines = [f"{label} ({self.kind}) of axis {self.axis!r}: {self.n_samples} samples at "
                 f"{self.fs_hz:g} Hz ({self.n_samples / self.fs_hz:.6g} s), unit {self.units}"]
        if self.has_ci:
            lines.append(f"confidence intervals at {100 * self.confidence:.1f} % "
                         "(chi-squared, EDF per point)")
        head = f"{'tau [s]':>12} {'m':>9} {'n':>10} {'dev':>12} {'ci_low':>12} {'ci_high':>12}"
        head += f" {'edf':>9} {'alpha':>5}"
        lines.append(head)
        for i, a in enumerate(self._alpha_or_none()):
            lines.append(f"{self.tau_s[i]:12.6g} {self.m[i]:9d} {self.n[i]:10d} "
                         f"{self.dev[i]:12.6g} {self.ci_low[i]:12.6g} {self.ci_high[i]:12.6g} "
                         f"{self.edf[i]:9.4g} {'-' if a is None else a:>5}")
        if self.dropped:
            lines.append(f"dropped {len(self.dropped)} tau(s):")
            lines += [f"  tau={d.tau_s:g} s (m={d.m}): {d.reason}" for d in self.dropped]
        lines += [f"note: {note}" for note in self.notes]
        return "\n".join(lines)


CurveT = TypeVar("CurveT", bound="_HasAxis")


class _HasAxis(Protocol):
    @property
    def axis(self) -> str: ...

    def to_frame(self) -> pd.DataFrame: ...


class AxisIndexed(Generic[CurveT]):
    """Mixin for frozen dataclasses holding ``curves: tuple[CurveT, ...]``, one per axis.

    Gives ``axes``, ``len()``, iteration, indexing by axis name or position and the long
    frame of all curves; call :meth:`_check_curves` from ``__post_init__``.  Shared by
    :class:`AllanResultSet` and the dynamic Allan result set.
    """

    curves: tuple[CurveT, ...]

    def _check_curves(self) -> None:
        curves = tuple(self.curves)
        name = type(self).__name__
        if not curves:
            raise DataError(f"{name} needs at least one curve")
        names = [c.axis for c in curves]
        if len(set(names)) != len(names):
            raise DataError(f"{name} axis names must be unique, got {names}")
        object.__setattr__(self, "curves", curves)

    def _long_frame(self) -> pd.DataFrame:
        """Every curve's ``to_frame()`` stacked, after an ``axis`` column."""
        frames = [c.to_frame().assign(axis=c.axis) for c in self.curves]
        out = pd.concat(frames, ignore_index=True)
        return out[["axis", *[c for c in out.columns if c != "axis"]]]

    @property
    def axes(self) -> tuple[str, ...]:
        """Axis names, in order."""
        return tuple(c.axis for c in self.curves)

    def __len__(self) -> int:
        return len(self.curves)

    def __iter__(self) -> Iterator[CurveT]:
        return iter(self.curves)

    def __getitem__(self, key: str | int) -> CurveT:
        if isinstance(key, str):
            if key not in self.axes:
                raise DataError(f"axis {key!r} not found; axes are: {', '.join(self.axes)}")
            return self.curves[self.axes.index(key)]
        if isinstance(key, bool) or not isinstance(key, int | np.integer):
            raise DataError(f"index {type(self).__name__} by axis name or position, got "
                            f"{key!r}")
        if not -len(self) <= int(key) < len(self):
            raise DataError(f"axis index must be in [0, {len(self) - 1}], got {key}")
        return self.curves[int(key)]


@dataclass(frozen=True)
class AllanResultSet(AxisIndexed[AllanResult]):
    """One :class:`AllanResult` per axis of a multi-axis recording.

    Index it by axis name or position: ``results["gyro_x"]``, ``results[0]``.
    """

    curves: tuple[AllanResult, ...]

    def __post_init__(self) -> None:
        self._check_curves()

    @property
    def kind(self) -> str:
        return self.curves[0].kind

    @property
    def units(self) -> str:
        return self.curves[0].units

    def to_frame(self) -> pd.DataFrame:
        """Long format: an ``axis`` column, then the columns of :meth:`AllanResult.to_frame`."""
        return self._long_frame()

    def to_dict(self) -> dict[str, Any]:
        return {"axes": list(self.axes), "curves": [c.to_dict() for c in self.curves]}

    def summary(self) -> str:
        return "\n\n".join(c.summary() for c in self.curves)
