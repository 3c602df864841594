"""Public entry point of the Allan analysis: :func:`allan_deviation`.

It takes a rate series in any of the forms fogts knows (ndarray, Series, DataFrame,
:class:`~fogts.io.run.Run`, :class:`~fogts.preprocess.prepare.Prepared`), builds the tau grid
(:mod:`fogts.allan.taus`), runs the phase-based estimator (:mod:`fogts.allan.estimators`)
and attaches noise identification, EDF and chi-squared intervals
(:mod:`fogts.allan.confidence`) to every point.
"""

from __future__ import annotations

import dataclasses
from typing import Any, Literal

import numpy as np
import numpy.typing as npt
import pandas as pd

from fogts._typing import ArrayLike1D, FloatArray, IntArray
from fogts._validate import all_finite, check_choice, check_fraction
from fogts.allan.bias import totdev_bias
from fogts.allan.confidence import confidence_table, curve_table
from fogts.allan.decimated import DecimatedSums
from fogts.allan.estimators import (
    ESTIMATORS,
    EstimatorOutput,
    estimate_from_angle,
    estimate_with_sums,
)
from fogts.allan.gradev import gradev
from fogts.allan.noise_identification import acf_orders
from fogts.allan.result import AllanResult, AllanResultSet
from fogts.allan.taus import KINDS, DroppedTau, Kind, TauGrid, tau_grid
from fogts.choices import INPUT_KINDS, InputKind
from fogts.errors import DataError
from fogts.io.run import Run
from fogts.preprocess.inputs import InputData, ensure_axes
from fogts.preprocess.prepare import Prepared
from fogts.units import parse_sensor_unit

__all__ = ["allan_deviation"]

TauSpec = Literal["octave", "decade", "dense", "all"] | npt.ArrayLike


# Long only by its docstring: the public entry point documents every option.
def allan_deviation(
    x: ArrayLike1D | pd.DataFrame | Run | Prepared,
    *,
    fs_hz: float | None = None,
    kind: Kind = "oadev",
    taus: TauSpec = "octave",
    confidence: float | None = 0.683,
    axis: int | str | None = None,
    units: str | None = None,
    per_decade: int = 20,
    workers: int | None = None,
    bias_correction: bool = False,
    input: InputKind = "rate",
) -> AllanResult | AllanResultSet:
    """Allan-family deviation of gyro rate data, with confidence intervals.

    The rate is integrated once to angle (phase) and differenced (NIST SP1065 eqs. 7, 11,
    14, 18, 20, 25 for adev, oadev, mdev, hdev, ohdev, totdev).  Each
    point carries the number of terms, the identified power-law noise type, its equivalent
    degrees of freedom and a chi-squared confidence interval (see
    :mod:`fogts.allan.confidence`).

    Parameters
    ----------
    x : ndarray, Series, DataFrame, Run or Prepared
        Rate data.  A 2-D array ``(n, k)``, a DataFrame (every column an axis) or a
        multi-axis Run gives one curve per axis unless ``axis`` picks one.  A Series or
        DataFrame is read as a Run (:func:`fogts.preprocess.inputs.run_from_pandas`).
    fs_hz : float, optional
        Sample rate.  Required for ndarray input; a Series/DataFrame with a
        DatetimeIndex/TimedeltaIndex, a Run or a Prepared carry their own (``fs_hz``
        overrides it).
    kind : {"oadev", "adev", "mdev", "hdev", "ohdev", "totdev"}
        Estimator; the overlapping Allan deviation is the default.
    taus : {"octave", "decade", "dense", "all"} or array_like of float
        Tau grid (see :func:`fogts.allan.taus.tau_grid`); an array gives taus in seconds.
        Taus that cannot be computed are listed in ``result.dropped``.
    confidence : float or None
        Confidence level of the intervals (default 0.683, i.e. 1 sigma); None skips the
        noise identification and intervals (``ci_low``, ``ci_high``, ``edf`` are NaN).
    axis : int or str, optional
        Analyse this axis only (name or position).
    units : str, optional
        Rate unit of array/Series/DataFrame input (default ``deg/h``); a Run or Prepared
        carries its own.
    per_decade : int
        Points per decade of the ``"dense"`` grid.
    workers : int, optional
        Threads for the estimator (default: all cores for large inputs).
    bias_correction : bool
        ``kind="totdev"`` only: divide TOTVAR by its bias ratio ``B = 1 - a tau/T`` at the
        points identified as flicker FM (``a = 1/(3 ln 2)``) or random-walk FM
        (``a = 3/4``), as Stable32 does (Howe 1999; :func:`fogts.allan.confidence.
        totdev_bias`).  Uncorrected TOTDEV of a rate random walk is ``sqrt(1 - 0.75 tau/T)``
        low at long tau, which biases K fitted from it.  The correction is only as good as
        the noise type identified at each tau, which is uncertain at the last few taus.
        The default (False) is the plain estimator that allantools also computes.
    input : {"rate", "increment", "angle"}
        What array/Series/DataFrame input holds: rate, angle increments per sample (the
        rate is ``x fs``) or integrated angle (``n + 1`` angles for ``n`` rates).  Angle
        and increments are used as the phase of the estimators directly (NIST SP1065
        sec. 5.2), never differenced and integrated back
        (:func:`fogts.allan.estimators.estimate_from_angle`); the deviations are in the
        rate unit (``units`` of an angle in deg is ``deg/s``).  A Run read from such a file
        carries its angle (:attr:`fogts.io.run.Run.angle`) and is used the same way.

    Returns
    -------
    AllanResult or AllanResultSet
        An :class:`AllanResultSet` for multi-axis input without ``axis``.

    Raises
    ------
    DataError
        Bad argument, non-finite data, unknown axis, missing sample rate;
        ``bias_correction`` with another kind or without ``confidence`` (the correction
        needs the per-point noise type).
    InsufficientDataError
        Too few samples for any tau.

    Examples
    --------
    >>> import numpy as np
    >>> y = np.random.default_rng(1).normal(scale=0.1, size=10_000)   # deg/h at 10 Hz
    >>> res = allan_deviation(y, fs_hz=10.0, taus="decade")
    >>> res.tau_s[:4].tolist()
    [0.1, 0.2, 0.4, 1.0]
    >>> bool(abs(res.dev[0] - 0.1) < 0.005), res.n[0].item()
    (True, 9999)
    """
    kind = check_choice("kind", kind, KINDS)  # type: ignore[assignment]
    if confidence is not None:
        confidence = check_fraction("confidence", confidence)
    _check_bias_correction(bias_correction, kind, confidence)
    if units is not None:
        units = parse_sensor_unit(units)
    input = check_choice("input", input, INPUT_KINDS)  # type: ignore[assignment]
    inp = ensure_axes(x, fs_hz=fs_hz, axis=axis, units=units, input=input, allow_nan=True)
    fs, unit, notes = analysis_context(inp)
    curves = [_one_curve(y, name, fs_hz=fs, units=unit, kind=kind, taus=taus,
                         confidence=confidence, per_decade=per_decade, workers=workers,
                         notes=notes, bias_correction=bias_correction, angle=inp.angle(i),
                         missing=inp.missing)
              for i, (name, y) in enumerate(inp.columns())]
    if len(curves) == 1 and (axis is not None or not inp.multi_axis_form):
        return curves[0]
    return AllanResultSet(curves=tuple(curves))


def analysis_context(inp: InputData) -> tuple[float, str, tuple[str, ...]]:
    """Sample rate, rate unit (deg/h unless stated) and the notes (a Prepared's steps) of
    an Allan analysis of ``inp``."""
    assert inp.fs_hz is not None  # ensure_axes requires it
    steps = inp.prepared.steps if inp.prepared is not None else ()
    return inp.fs_hz, inp.units or "deg/h", tuple(f"prepared: {step}" for step in steps)


def _check_bias_correction(bias_correction: Any, kind: str, confidence: float | None) -> None:
    if not isinstance(bias_correction, bool | np.bool_):
        raise DataError(f"bias_correction must be True or False, got {bias_correction!r}")
    if not bias_correction:
        return
    if kind != "totdev":
        raise DataError(f"bias_correction applies to kind='totdev' only (the other estimators "
                        f"are unbiased for every power-law noise), got kind={kind!r}")
    if confidence is None:
        raise DataError("bias_correction needs the per-tau noise identification; pass a "
                        "confidence level, not confidence=None")


def _with_gaps(y: FloatArray, name: str, kind: str) -> bool:
    """Whether a Run's axis holds NaN for missing samples (``gaps="nan"``); inf is refused."""
    if all_finite(y):
        return False
    if np.isinf(y).any():
        raise DataError(f"axis {name!r} holds inf; rate data must be finite")
    if kind != "oadev":
        raise DataError(f"axis {name!r} has missing samples (NaN, gaps='nan'); only "
                        f"kind='oadev' has a gap-robust estimator, got kind={kind!r}")
    return True


def _gap_robust(y: FloatArray, fs_hz: float, grid: TauGrid) -> tuple[TauGrid, EstimatorOutput]:
    """:func:`gradev` on the grid, without the taus left with fewer than two terms free of
    missing samples (listed in ``dropped``)."""
    est = gradev(y, fs_hz=fs_hz, m=grid.m)
    keep = est.n >= 2
    if keep.all():
        return grid, est
    lost = tuple(DroppedTau(float(t), int(m), "fewer than 2 terms free of missing samples")
                 for t, m in zip(grid.tau_s[~keep], grid.m[~keep], strict=True))
    grid = dataclasses.replace(grid, m=grid.m[keep], tau_s=grid.tau_s[keep],
                               dropped=(*grid.dropped, *lost))
    return grid, dataclasses.replace(est, m=est.m[keep], tau_s=est.tau_s[keep],
                                     dev=est.dev[keep], n=est.n[keep])


def _one_curve(y: FloatArray, name: str, *, fs_hz: float, units: str, kind: str, taus: Any,
               confidence: float | None, per_decade: int, workers: int | None,
               notes: tuple[str, ...], bias_correction: bool = False,
               angle: FloatArray | None = None, missing: bool = True) -> AllanResult:
    """One axis' curve; ``missing`` False says ``y`` was checked finite (no NaN to look
    for: :attr:`fogts.preprocess.inputs.InputData.missing`)."""
    grid = tau_grid(taus, fs_hz=fs_hz, n_samples=y.size, kind=kind, per_decade=per_decade)
    phase: FloatArray | None = None
    sums: tuple[DecimatedSums | None, ...] | None = None
    if missing and _with_gaps(y, name, kind):  # Sesia & Tavella (2008): the terms free of missing samples
        grid, est = _gap_robust(y, fs_hz, grid)
        notes = (*notes, f"{int(np.count_nonzero(np.isnan(y)))} missing samples (NaN): "
                 "gap-robust overlapping ADEV (Sesia & Tavella 2008); noise type and EDF "
                 "from the samples present")
        y = y[np.isfinite(y)]
    elif angle is not None:
        est = estimate_from_angle(kind, angle, fs_hz=fs_hz, m=grid.m, workers=workers)
    elif confidence is not None:  # the noise identification's sums from the same pass
        phased = estimate_with_sums(kind, y, fs_hz=fs_hz, m=grid.m, workers=workers,
                                    d_max=acf_orders(kind))
        est, phase, sums = phased.output, phased.phase, phased.sums
    else:
        est = ESTIMATORS[kind](y, fs_hz=fs_hz, m=grid.m, workers=workers)
    size = grid.m.size
    nan = np.full(size, np.nan)
    ci_low, ci_high, edf = nan, nan, nan
    alpha: IntArray = np.zeros(size, dtype=np.int64)
    methods: tuple[str, ...] = ("none",) * size
    level = float("nan")
    if confidence is not None:
        table = (confidence_table(y, fs_hz=fs_hz, kind=kind, m=grid.m, dev=est.dev,
                                  confidence=confidence) if phase is None
                 else curve_table(y, fs_hz=fs_hz, kind=kind, m=est.m, dev=est.dev,
                                  confidence=confidence, phase=phase, sums=sums))
        ci_low, ci_high = table.ci_low, table.ci_high
        edf, alpha = table.edf, table.alpha
        methods = tuple(str(v) for v in table.alpha_method)
        level = float(table.confidence)
    dev = est.dev
    if bias_correction:
        root_b = np.sqrt(totdev_bias(alpha, grid.m, y.size + 1))
        dev, ci_low, ci_high = dev / root_b, ci_low / root_b, ci_high / root_b
        notes = (*notes, "totdev divided by sqrt(B), B = 1 - a tau/T with a = 0.481 at "
                 "flicker-FM and 0.75 at random-walk-FM points (Howe 1999), as Stable32 "
                 f"reports it; {int(np.count_nonzero(root_b < 1))} of {root_b.size} points "
                 "corrected")
    return AllanResult(kind=kind, units=units, axis=name, fs_hz=fs_hz, n_samples=y.size,
                       confidence=level, tau_s=grid.tau_s, m=grid.m, n=est.n, dev=dev,
                       ci_low=ci_low, ci_high=ci_high, edf=edf, alpha=alpha,
                       dropped=grid.dropped, alpha_method=methods,
                       notes=(*grid.notes, *notes), bias_corrected=bias_correction)
