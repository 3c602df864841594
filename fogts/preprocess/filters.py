"""Zero-phase denoising filters: IIR low-pass (Butterworth, Chebyshev I, elliptic) and a
centred moving average.

A gyro signal is denoised with an IIR low-pass filter, and its Allan analysis compared
before and after.  Filtering is done forward and backward (``scipy.signal.sosfiltfilt``),
so it adds no phase lag; the price is that the magnitude response is squared.  For the
Butterworth design fogts pre-warps the single-pass cutoff so that the *zero-phase* response
is exactly -3 dB at ``cutoff_hz``:

    |H_ff(f)|^2 = |H(f)|^4 = (1 + (w/w_d)^(2n))^-2 = 1/2  at f = f_c,  w = tan(pi f/fs)
    =>  w_d = w_c / (sqrt(2) - 1)^(1/(2n))   (bilinear-transform frequency warping)

(for Chebyshev I and elliptic designs ``cutoff_hz`` is the passband edge of the single
pass; the zero-phase passband ripple is twice ``ripple_db``).

Filtering changes the noise seen at averaging times shorter than about ``1/cutoff_hz``:
noise coefficients from filtered data describe the filtered signal, not the sensor.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any

import numpy as np
import pandas as pd

from fogts._typing import ArrayLike1D, FloatArray
from fogts._validate import check_choice, check_int, check_positive, pandas_index, to_float_array
from fogts.choices import FILTER_DESIGNS, FilterDesign
from fogts.errors import DataError

__all__ = ["FILTER_DESIGNS", "FilterResult", "lowpass", "moving_average"]


_CAVEAT = ("filtering changes the noise seen at tau shorter than about 1/cutoff; noise "
           "coefficients from filtered data describe the filtered signal, not the sensor")


@dataclass(frozen=True)
class FilterResult:
    """A filtered series and the filter that made it.

    Attributes
    ----------
    method : str
        ``"iir"`` or ``"moving-average"``.
    params : dict
        Design parameters (cutoff_hz, order, design, ripple_db, stopband_db, window).
    fs_hz : float
        Sample rate.
    observed : ndarray
        The input.
    filtered : ndarray
        The zero-phase filtered output (same length).
    cutoff_hz : float
        The -3 dB frequency of the zero-phase response (the moving average's is computed
        numerically).
    sos : ndarray or None
        Second-order sections of the single-pass IIR filter.
    index : pandas.Index or None
        The input Series' index.
    caveat : str
        What filtering does to an Allan analysis.
    """

    method: str
    params: dict[str, Any]
    fs_hz: float
    observed: FloatArray
    filtered: FloatArray
    cutoff_hz: float
    sos: FloatArray | None = None
    index: pd.Index | None = field(default=None, repr=False)
    caveat: str = _CAVEAT

    def frequency_response(self, freq_hz: FloatArray) -> FloatArray:
        """Amplitude response of the zero-phase filter at ``freq_hz``.

        For the IIR filter this is ``|H(f)|^2`` (forward-backward); for the moving average
        it is the boxcar's ``|sin(pi f N/fs) / (N sin(pi f/fs))|``.  In dB:
        ``20 * log10(response)``.
        """
        f = np.asarray(freq_hz, dtype=np.float64)
        if self.sos is not None:
            from scipy import signal

            _, h = signal.sosfreqz(self.sos, worN=f, fs=self.fs_hz)
            return np.asarray(np.abs(h) ** 2, dtype=np.float64)
        window = int(self.params["window"])
        return np.asarray(np.abs(_moving_average_response(window, f / self.fs_hz)),
                          dtype=np.float64)

    def series(self) -> pd.Series:
        """The filtered output, with the input's index if it had one."""
        return pd.Series(self.filtered, index=self.index, name="filtered")

    def to_frame(self) -> pd.DataFrame:
        frame = pd.DataFrame({"observed": self.observed, "filtered": self.filtered})
        if self.index is not None:
            frame.index = self.index
        return frame

    def to_dict(self) -> dict[str, Any]:
        return {"method": self.method, "params": dict(self.params), "fs_hz": self.fs_hz,
                "cutoff_hz": self.cutoff_hz, "n": int(self.observed.size),
                "removed_rms": float(np.sqrt(np.mean((self.observed - self.filtered) ** 2))),
                "caveat": self.caveat}

    def summary(self) -> str:
        p = ", ".join(f"{k}={v}" for k, v in self.params.items())
        return (f"{self.method} low-pass ({p}); zero-phase -3 dB at {self.cutoff_hz:.6g} Hz\n"
                f"note: {self.caveat}")


def lowpass(
    x: ArrayLike1D,
    *,
    fs_hz: float,
    cutoff_hz: float,
    order: int = 4,
    design: FilterDesign = "butter",
    ripple_db: float = 0.5,
    stopband_db: float = 60.0,
) -> FilterResult:
    """Zero-phase IIR low-pass filter (``scipy.signal`` design + ``sosfiltfilt``).

    Filtered forward and backward: no phase lag, and the magnitude response of the single
    pass squared (module docstring).

    Parameters
    ----------
    x : array_like or Series
        Rate samples.
    fs_hz : float
        Sample rate.
    cutoff_hz : float
        Cutoff, ``0 < cutoff_hz < fs_hz / 2``.  For ``butter`` it is the -3 dB point of the
        zero-phase response (see the module docstring).
    order : int
        Filter order of the single pass (1..20).
    design : {"butter", "cheby1", "ellip"}
        Filter family.
    ripple_db, stopband_db : float
        Passband ripple (cheby1, ellip) and stopband attenuation (ellip) of the single pass.

    Returns
    -------
    FilterResult

    Examples
    --------
    >>> import numpy as np
    >>> r = lowpass(np.random.default_rng(0).normal(size=2000), fs_hz=100, cutoff_hz=5)
    >>> round(float(20 * np.log10(r.frequency_response([5.0])[0])), 2)
    -3.01
    """
    fs = check_positive("fs_hz", fs_hz)
    fc = check_positive("cutoff_hz", cutoff_hz)
    nyquist = fs / 2.0
    if fc >= nyquist:
        raise DataError(f"cutoff_hz must be below the Nyquist frequency {nyquist:g} Hz "
                        f"(half the sample rate), got {cutoff_hz!r}")
    n = check_int("order", order, minimum=1, maximum=20)
    kind = check_choice("design", design, FILTER_DESIGNS)
    ripple = check_positive("ripple_db", ripple_db)
    stop = check_positive("stopband_db", stopband_db)
    index = pandas_index(x)
    data = to_float_array(x, "x", min_length=2)
    from scipy import signal  # on first use: slow to import, and most commands never filter

    if kind == "butter":
        sos = signal.butter(n, _zero_phase_butter_design_hz(fc, fs, n), btype="low", fs=fs,
                            output="sos")
    elif kind == "cheby1":
        sos = signal.cheby1(n, ripple, fc, btype="low", fs=fs, output="sos")
    else:
        sos = signal.ellip(n, ripple, stop, fc, btype="low", fs=fs, output="sos")
    padlen = 3 * (2 * sos.shape[0] + 1)
    if data.size <= padlen:
        raise DataError(f"x needs more than {padlen} samples for an order-{n} zero-phase "
                        f"filter, got {data.size}")
    filtered = signal.sosfiltfilt(sos, data)
    result = FilterResult(
        method="iir",
        params={"design": kind, "order": n, "cutoff_hz": fc, "ripple_db": ripple,
                "stopband_db": stop},
        fs_hz=fs, observed=data, filtered=np.ascontiguousarray(filtered), cutoff_hz=fc,
        sos=sos, index=index)
    return _with_measured_cutoff(result) if kind != "butter" else result


def _zero_phase_butter_design_hz(cutoff_hz: float, fs_hz: float, order: int) -> float:
    """Single-pass Butterworth cutoff whose forward-backward response is -3 dB at cutoff.

    The digital Butterworth (bilinear transform) has
    ``|H(f)|^2 = 1 / (1 + (tan(pi f/fs) / tan(pi f_d/fs))^(2n))``; forward-backward squares
    the amplitude, so -3 dB at ``f_c`` needs ``|H(f_c)|^2 = 1/sqrt(2)``, i.e.
    ``tan(pi f_d/fs) = tan(pi f_c/fs) / (sqrt(2) - 1)^(1/(2n))``.
    """
    warped = math.tan(math.pi * cutoff_hz / fs_hz) / (math.sqrt(2.0) - 1.0) ** (1.0 / (2 * order))
    return fs_hz / math.pi * math.atan(warped)


def moving_average(x: ArrayLike1D, *, fs_hz: float, window_s: float) -> FilterResult:
    """Centred (zero-phase) moving average over ``window_s`` seconds.

    Edges use reflected data (``scipy.ndimage.uniform_filter1d``, mode ``"reflect"``), so
    the output has the input's length.  The window is rounded to an odd number of samples
    so it is centred.

    Examples
    --------
    >>> import numpy as np
    >>> moving_average(np.arange(10.0), fs_hz=1, window_s=3).filtered[1:4]
    array([1., 2., 3.])
    """
    fs = check_positive("fs_hz", fs_hz)
    w_s = check_positive("window_s", window_s)
    window = round(w_s * fs)
    window += 1 - window % 2  # odd
    if window < 3:
        raise DataError(f"window_s={w_s:g} s is shorter than 3 samples at {fs:g} Hz; use at "
                        f"least {3 / fs:g} s")
    index = pandas_index(x)
    data = to_float_array(x, "x", min_length=2)
    if window > data.size:
        raise DataError(f"window_s={w_s:g} s ({window} samples) is longer than the record "
                        f"({data.size} samples)")
    from scipy import ndimage

    filtered = ndimage.uniform_filter1d(data, size=window, mode="reflect")
    result = FilterResult(method="moving-average", params={"window": window,
                                                           "window_s": window / fs},
                          fs_hz=fs, observed=data, filtered=filtered, cutoff_hz=float("nan"),
                          index=index)
    return _with_measured_cutoff(result)


def _moving_average_response(window: int, f_norm: FloatArray) -> FloatArray:
    """Amplitude response of a length-``window`` boxcar at normalised frequency f/fs."""
    num = np.sin(np.pi * f_norm * window)
    den = window * np.sin(np.pi * f_norm)
    with np.errstate(invalid="ignore", divide="ignore"):
        out = np.where(np.abs(den) < 1e-300, 1.0, num / den)
    return np.asarray(out, dtype=np.float64)


def _with_measured_cutoff(result: FilterResult) -> FilterResult:
    """Fill ``cutoff_hz`` with the first frequency where the zero-phase response is -3 dB."""
    f = np.linspace(0.0, result.fs_hz / 2.0, 20001)
    h = result.frequency_response(f)
    half_power = math.sqrt(0.5)
    below = np.flatnonzero(h <= half_power)
    if below.size == 0:
        return result
    i = int(below[0])
    # linear interpolation between the bracketing grid points
    f0, f1, h0, h1 = f[i - 1], f[i], h[i - 1], h[i]
    fc = float(f0 + (half_power - h0) * (f1 - f0) / (h1 - h0)) if h1 != h0 else float(f1)
    return FilterResult(result.method, result.params, result.fs_hz, result.observed,
                        result.filtered, fc, result.sos, result.index, result.caveat)
