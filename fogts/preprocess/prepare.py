"""Prepare one gyro axis for modelling: outliers, trend, mean, decimation, stationarity.

Before time-series (ARMA) modelling of the drift, the trend is removed by a least-squares
polynomial and the mean is subtracted; outliers are replaced with a MAD-based sigma factor,
as Stable32 does.  Every step taken is listed on the :class:`Prepared` result, and nothing
is dropped without being recorded.
"""

from __future__ import annotations

import warnings
from dataclasses import dataclass, field
from typing import Any

import numpy as np
import pandas as pd

from fogts._typing import ArrayLike1D, FloatArray, IntArray
from fogts._validate import check_int, check_positive
from fogts.errors import DataError, InsufficientDataError
from fogts.io.run import RegularTime, Run, _TimeField, held_time
from fogts.preprocess.demeaned import Demeaned, HeldSeries, held, holds_unformed
from fogts.preprocess.glitches import MAD_TO_SIGMA
from fogts.preprocess.inputs import ensure_series

__all__ = ["OutlierReport", "Prepared", "StationarityReport", "prepare"]

#: Stationarity tests run on block means of at most this many points (the low-frequency
#: structure ADF and KPSS probe survives block averaging).
STATIONARITY_MAX_POINTS = 20_000
#: Cap on the ADF lag search (Schwert's 12 (n/100)^(1/4) would be 45 at 20,000 points).
ADF_MAX_LAG = 24
#: Fewest samples :func:`prepare` accepts.
MIN_PREPARE_SAMPLES = 10


@dataclass(frozen=True)
class OutlierReport:
    """Samples replaced as outliers (Stable32-style MAD sigma factor).

    ``Prepared.outliers`` when :func:`prepare` is given an ``outliers`` sigma factor.

    Attributes
    ----------
    sigma_factor : float
        Threshold in robust sigmas (``MAD * 1.4826``) from the median.
    threshold : float
        Absolute deviation from the median above which a sample is an outlier.
    indices : ndarray of int64
        Positions (in the input series) of the replaced samples.
    values : ndarray of float64
        Their original values.
    """

    sigma_factor: float
    threshold: float
    indices: IntArray
    values: FloatArray

    @property
    def count(self) -> int:
        return int(self.indices.size)

    def to_dict(self) -> dict[str, Any]:
        return {"sigma_factor": self.sigma_factor, "threshold": self.threshold,
                "count": self.count, "indices": self.indices[:1000].tolist(),
                "values": self.values[:1000].tolist()}


@dataclass(frozen=True)
class StationarityReport:
    """ADF (H0: unit root) and KPSS (H0: level-stationary) results from statsmodels.

    ``verdict`` combines them at the 5 % level: ``"stationary"`` (ADF rejects, KPSS does
    not), ``"non-stationary"`` (KPSS rejects, ADF does not), ``"inconclusive"`` otherwise.

    Both test the level of the series (a unit root, a drifting mean), not its noise level:
    a record whose noise halves mid-run with a constant mean passes them (the dynamic Allan
    deviation, :mod:`fogts.allan.dynamic`, tests the noise level).  :meth:`summary` says so
    (D. Kwiatkowski et al., J. Econometrics 54, 1992, eq. 1: KPSS's null is a constant
    level plus stationary error).
    """

    adf_stat: float
    adf_pvalue: float
    adf_lags: int
    kpss_stat: float
    kpss_pvalue: float
    kpss_lags: int
    n_tested: int
    block: int
    verdict: str
    notes: tuple[str, ...] = ()

    def to_dict(self) -> dict[str, Any]:
        return {"adf": {"stat": self.adf_stat, "pvalue": self.adf_pvalue, "lags": self.adf_lags},
                "kpss": {"stat": self.kpss_stat, "pvalue": self.kpss_pvalue,
                         "lags": self.kpss_lags},
                "n_tested": self.n_tested, "block": self.block, "verdict": self.verdict,
                "notes": list(self.notes), "summary": self.summary()}

    def summary(self) -> str:
        """The verdict with both p-values, naming what the tests test (the preparation step
        ``fogts select`` and the report print).

        A p-value beyond its table is shown as the bound it is: KPSS's look-up table
        (Kwiatkowski et al. 1992, table 1) spans 0.01-0.1, and statsmodels returns the end
        it passed (``p<0.01``, ``p>0.1``, said by the KPSS note); MacKinnon's (1994, 2010)
        approximation returns 0 for an ADF statistic below its range (``p<0.0001``, as for
        any p-value under 1e-4).
        """
        return (f"level: {self.verdict} (ADF {_p_text(self.adf_pvalue)}, KPSS "
                f"{_p_text(self.kpss_pvalue, self._kpss_beyond_table())}; tests the mean, "
                "not the noise level)")

    def _kpss_beyond_table(self) -> str:
        """``"<"`` or ``">"`` when statsmodels said the KPSS p-value lies beyond its table
        (the InterpolationWarning kept in :attr:`notes`), else ``""``."""
        for note in self.notes:
            if note.startswith("KPSS:") and "p-value is smaller" in note:
                return "<"
            if note.startswith("KPSS:") and "p-value is greater" in note:
                return ">"
        return ""


def _p_text(p: float, beyond: str = "") -> str:
    """``p=0.0123``; ``p<0.01`` for a p-value that is an upper bound (``beyond="<"``),
    ``p>0.1`` for a lower bound; ``p<0.0001`` below 1e-4."""
    if beyond:
        return f"p{beyond}{p:.3g}"
    if p < 1e-4:
        return "p<0.0001"
    return f"p={p:.3g}"


@dataclass(frozen=True)
class Prepared:
    """One axis, ready for Allan or ARMA analysis.

    Attributes
    ----------
    x : ndarray of float64
        The prepared series (a long input minus its mean is formed on first access;
        :attr:`lazy_x` does not form it).
    fs_hz : float
        Sample rate after decimation.
    units : str
        Rate unit.
    axis : str
        Name of the axis.
    time : ndarray of float64
        Time of each prepared sample in seconds (block start after decimation); a regular
        time base is formed on first access (:attr:`lazy_time` does not form it).
    index : pandas.Index or None
        The input Series' index (decimated alongside), to re-wrap outputs.
    steps : tuple of str
        Human-readable list of what was done, in order.
    n_input : int
        Samples before decimation.
    outliers : OutlierReport or None
    trend_order : int or None
        Polynomial order removed (0 = mean only), or None.
    trend_coefficients : tuple of float
        Coefficients of the removed polynomial in powers of time in seconds (lowest first).
    removed_mean : float or None
        The mean removed when only the mean was (``demean``); None otherwise.
    decimate : int
        Block-averaging factor (1 = none).
    dropped_tail : int
        Samples at the end that did not fill a last decimation block.
    stationarity : StationarityReport or None
    run : Run or None
        The Run this came from.
    """

    x: FloatArray
    fs_hz: float
    units: str
    axis: str
    time: FloatArray
    index: pd.Index | None = None
    steps: tuple[str, ...] = ()
    n_input: int = 0
    outliers: OutlierReport | None = None
    trend_order: int | None = None
    trend_coefficients: tuple[float, ...] = ()
    removed_mean: float | None = None
    decimate: int = 1
    dropped_tail: int = 0
    stationarity: StationarityReport | None = None
    run: Run | None = field(default=None, repr=False)

    @property
    def lazy_time(self) -> FloatArray | RegularTime:
        """``time`` without forming it: a :class:`~fogts.io.run.RegularTime` for a regular
        time base not formed yet (a 1e8-sample record's would be 800 MB), else the array."""
        return self.__dict__["time"]  # type: ignore[no-any-return]

    @property
    def lazy_x(self) -> FloatArray | Demeaned:
        """``x`` without forming it: a :class:`~fogts.preprocess.demeaned.Demeaned` for a
        long input minus its mean not formed yet, else the array."""
        return held(self, "x")  # type: ignore[no-any-return]

    @property
    def n(self) -> int:
        return int(self.lazy_x.size)

    def removed_level(self) -> FloatArray | float:
        """What the preparation subtracted from each sample: the removed polynomial at
        :attr:`time`, the removed mean, or 0.0.  Added to the prepared series (or to a
        prediction of it) it gives values on the input's scale.

        Examples
        --------
        >>> p = prepare(np.array([1.0, 2.0, 6.0, 3.0] * 25), fs_hz=1.0, stationarity=False)
        >>> p.removed_level(), float(p.x[2] + p.removed_level())
        (3.0, 6.0)
        """
        if self.trend_order is not None:
            return np.asarray(np.polynomial.Polynomial(self.trend_coefficients)(self.time),
                              dtype=np.float64)
        return 0.0 if self.removed_mean is None else self.removed_mean

    def series(self) -> pd.Series:
        """The prepared data as a Series (with the input's index if it had one)."""
        index = self.index if self.index is not None else pd.Index(self.time, name="time_s")
        return pd.Series(self.x, index=index, name=self.axis)

    def to_frame(self) -> pd.DataFrame:
        return pd.DataFrame({"time": self.time, self.axis: self.x})

    def to_dict(self) -> dict[str, Any]:
        return {
            "axis": self.axis,
            "units": self.units,
            "n_input": self.n_input,
            "n": self.n,
            "fs_hz": self.fs_hz,
            "steps": list(self.steps),
            "outliers": self.outliers.to_dict() if self.outliers else None,
            "detrend": None if self.trend_order is None else {
                "order": self.trend_order, "coefficients": list(self.trend_coefficients)},
            "decimate": self.decimate,
            "dropped_tail": self.dropped_tail,
            "stationarity": self.stationarity.to_dict() if self.stationarity else None,
        }

    def summary(self) -> str:
        lines = [f"Prepared {self.axis!r}: {self.n} samples at {self.fs_hz:g} Hz ({self.units})"]
        lines += [f"  - {s}" for s in self.steps] or ["  - no preprocessing"]
        return "\n".join(lines)


# Long by its docstring (every step and option); the body is one step after another.
def prepare(
    data: ArrayLike1D | Run,
    *,
    fs_hz: float | None = None,
    units: str | None = None,
    axis: int | str = 0,
    outliers: float | None = None,
    detrend: int | None = None,
    demean: bool = True,
    decimate: int | None = None,
    stationarity: bool = True,
) -> Prepared:
    """Prepare one axis of a recording for modelling.

    Steps, in this order, each recorded on the result:

    1. outliers: samples farther than ``outliers`` robust sigmas (MAD x 1.4826) from the
       median are replaced by linear interpolation between their good neighbours
       (replaced, not dropped, so the time base stays regular);
    2. decimation by block averaging over ``decimate`` samples (a partial last block is
       dropped and recorded);
    3. polynomial trend removal of order ``detrend`` (least squares in time); order 0 is
       mean removal;
    4. mean removal if ``demean`` and no trend was removed (of a long input, held as the
       input and its mean until ``Prepared.x`` is read);
    5. ADF and KPSS stationarity tests (statsmodels) on the result.

    Parameters
    ----------
    data : Run, ndarray or Series
        The recording; a Run carries its own sample rate and units.
    fs_hz : float, optional
        Sample rate; required for ndarray input (a Series with a DatetimeIndex or
        TimedeltaIndex supplies it).
    units : str, optional
        Rate unit of array/Series input (default deg/h); a Run carries its own.
    axis : int or str
        Which axis of a multi-axis Run.
    outliers : float, optional
        Sigma factor for outlier replacement (Stable32 uses e.g. 5); None skips.
    detrend : int, optional
        Polynomial order to remove (0..10); None skips.
    demean : bool
        Remove the mean (implied by any ``detrend``).
    decimate : int, optional
        Block-averaging factor (>= 2); None or 1 skips.
    stationarity : bool
        Run ADF and KPSS.

    Returns
    -------
    Prepared

    Examples
    --------
    >>> import numpy as np
    >>> x = np.arange(500.0) + np.random.default_rng(0).normal(size=500)
    >>> p = prepare(x, fs_hz=10, detrend=1)
    >>> p.steps
    ('removed a polynomial trend of order 1', 'level: stationary (ADF p<0.0001, KPSS p>0.1; tests the mean, not the noise level)')
    """
    inp = ensure_series(data, "data", fs_hz=fs_hz, units=units, axis=axis,
                        min_length=MIN_PREPARE_SAMPLES, accept_prepared=False, require_fs=True)
    x, fs, name, index, run = inp.values, inp.fs_hz, inp.axes[0], inp.index, inp.run
    assert fs is not None  # require_fs
    units = inp.units or "deg/h"
    if np.ptp(x) == 0:
        raise InsufficientDataError(f"{name!r} is constant (every value is {x[0]:g}); nothing "
                                    "to model")
    base = _time_base(run, x.size, fs)
    steps: list[str] = []
    n_input = x.size

    report = None
    if outliers is not None:
        x, report = _replace_outliers(x, check_positive("outliers", outliers))
        steps.append(f"replaced {report.count} outlier(s) beyond {report.sigma_factor:g} robust "
                     f"sigma (|x - median| > {report.threshold:.6g}) by linear interpolation")

    k, dropped_tail = 1, 0
    # no decimation: the full time axis (a regular one formed on first access of .time)
    time: FloatArray | RegularTime = base
    if decimate is not None and decimate != 1:
        k = check_int("decimate", decimate, minimum=1)  # 1 (no decimation) is allowed
        if x.size // k < MIN_PREPARE_SAMPLES:
            raise InsufficientDataError(f"decimate={k} leaves {x.size // k} samples; at least "
                                        f"{MIN_PREPARE_SAMPLES} are needed")
        x, time, index, dropped_tail = _block_average(x, base, index, k)
        fs = fs / k
        steps.append(f"decimated by block averaging over {k} samples -> {fs:g} Hz"
                     + (f" (dropped {dropped_tail} tail samples)" if dropped_tail else ""))

    order: int | None = None
    coefs: tuple[float, ...] = ()
    mean: float | None = None
    out: FloatArray | Demeaned = x
    if detrend is not None:
        order = check_int("detrend", detrend, minimum=0, maximum=10)
        out, coefs = _remove_polynomial(
            x, time.array() if isinstance(time, RegularTime) else time, order)
        steps.append(f"removed a polynomial trend of order {order}" if order else
                     "removed the mean (trend order 0)")
    elif demean:
        mean = float(np.mean(x))
        # a long input is held with its mean, not copied (the ARMA selection reads it so);
        # any other array is a copy the preparation made already
        out = Demeaned(x, mean) if x is inp.values and holds_unformed(x) else x - mean
        steps.append(f"removed the mean ({mean:.6g} {units})")

    stat = _stationarity(out) if stationarity else None
    if stat is not None:
        steps.append(stat.summary())
    return Prepared(x=out if isinstance(out, Demeaned)  # type: ignore[arg-type]  # HeldSeries
                    else np.ascontiguousarray(out), fs_hz=fs, units=units, axis=name,
                    time=time,  # type: ignore[arg-type]  # formed by _TimeField on access
                    index=index, steps=tuple(steps), n_input=n_input, outliers=report,
                    trend_order=order, trend_coefficients=coefs, removed_mean=mean,
                    decimate=k, dropped_tail=dropped_tail, stationarity=stat, run=run)


def _replace_outliers(x: FloatArray, sigma_factor: float) -> tuple[FloatArray, OutlierReport]:
    """Replace samples beyond ``sigma_factor`` robust sigmas by linear interpolation."""
    median = float(np.median(x))
    mad = float(np.median(np.abs(x - median)))
    if mad == 0.0:
        # Quantized data can have MAD = 0; fall back to the standard deviation.
        mad = float(np.std(x)) / MAD_TO_SIGMA
    threshold = sigma_factor * MAD_TO_SIGMA * mad
    bad = np.abs(x - median) > threshold
    idx = np.flatnonzero(bad)
    if idx.size == x.size:
        raise DataError(f"outliers={sigma_factor:g} marks every sample as an outlier; use a "
                        "larger sigma factor")
    out = x.copy()
    if idx.size:
        good = np.flatnonzero(~bad)
        out[idx] = np.interp(idx, good, x[good])
    return out, OutlierReport(sigma_factor, threshold, idx.astype(np.int64), x[idx].copy())


def _time_base(run: Run | None, n: int, fs: float) -> FloatArray | RegularTime:
    """The time of ``n`` samples: the run's when it has as many, else ``k / fs``; a regular
    base is left unformed (:class:`~fogts.io.run.RegularTime`: block averaging needs every
    ``k``-th time only)."""
    if run is not None:
        held = held_time(run)
        if held is None and run.n == n:
            return RegularTime(n, run.fs_hz)
        if held is not None and held.size == n:
            return held
        if held is None and run.time.size == n:  # a RegularTime of another length than rate
            return run.time
    return RegularTime(n, fs)


def _block_average(x: FloatArray, time: FloatArray | RegularTime, index: pd.Index | None,
                   k: int) -> tuple[FloatArray, FloatArray, pd.Index | None, int]:
    m = x.size // k
    tail = x.size - m * k
    xd = x[: m * k].reshape(m, k).mean(axis=1)
    if isinstance(time, RegularTime):  # every k-th of arange(n) / fs, the same values
        td = np.arange(0, m * k, k, dtype=np.float64) / time.fs_hz
    else:
        td = time[: m * k : k].copy()
    idx = index[: m * k : k] if index is not None else None
    return xd, td, idx, tail


def _remove_polynomial(x: FloatArray, time: FloatArray, order: int
                       ) -> tuple[FloatArray, tuple[float, ...]]:
    """Least-squares polynomial in time (scaled domain for conditioning)."""
    if x.size <= order + 1:
        raise InsufficientDataError(f"detrend={order} needs more than {order + 1} samples, "
                                    f"got {x.size}")
    poly = np.polynomial.Polynomial.fit(time, x, order)
    residual = np.asarray(x - poly(time), dtype=np.float64)
    return residual, tuple(float(c) for c in poly.convert().coef)


def _stationarity(x: FloatArray | Demeaned) -> StationarityReport:
    """ADF and KPSS on ``x`` or its block means; of a :class:`Demeaned` series the block
    means of the input minus the mean (equal to those of the demeaned array to rounding)."""
    from statsmodels.tools.sm_exceptions import InterpolationWarning
    from statsmodels.tsa.stattools import adfuller, kpss

    block = max(1, int(np.ceil(x.size / STATIONARITY_MAX_POINTS)))
    if isinstance(x, Demeaned):
        raw = x.raw
        y = raw[: x.size // block * block].reshape(-1, block).mean(axis=1) - x.mean
    else:
        y = x if block == 1 else x[: x.size // block * block].reshape(-1, block).mean(axis=1)
    notes: list[str] = []
    if block > 1:
        notes.append(f"tested on block means of {block} samples ({y.size} points)")
    if y.size < 20 or np.ptp(y) == 0:
        nan = float("nan")
        return StationarityReport(nan, nan, 0, nan, nan, 0, int(y.size), block, "not tested",
                                  ("too few points for ADF/KPSS",))
    maxlag = min(ADF_MAX_LAG, int(12 * (y.size / 100.0) ** 0.25))
    adf = adfuller(y, maxlag=maxlag, autolag="AIC", regression="c", result_object=True)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always", InterpolationWarning)
        kp = kpss(y, regression="c", nlags="auto", result_object=True)
    for w in caught:
        notes.append(f"KPSS: {str(w.message).splitlines()[0]}")
    adf_p, kpss_p = float(adf.pvalue), float(kp.pvalue)
    if adf_p < 0.05 <= kpss_p:
        verdict = "stationary"
    elif kpss_p < 0.05 <= adf_p:
        verdict = "non-stationary"
    else:
        verdict = "inconclusive"
    return StationarityReport(float(adf.statistic), adf_p, int(adf.lags), float(kp.statistic),
                              kpss_p, int(kp.lags), int(y.size), block, verdict, tuple(notes))


setattr(Prepared, "time", _TimeField())  # noqa: B010  (formed on first access)
setattr(Prepared, "x", HeldSeries("x"))  # noqa: B010  (formed on first access)
