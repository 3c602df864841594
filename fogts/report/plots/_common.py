"""Helpers shared by the figures: safe text, time units, thinning of long series and numbers
written for matplotlib's mathtext."""

from __future__ import annotations

from typing import Protocol

import numpy as np

from fogts._typing import FloatArray

__all__ = ["Sliced", "minmax_envelope", "mpl_text", "num_tex", "thin_step", "time_unit", "value_pm_tex"]


def mpl_text(text: str) -> str:
    """Escape ``$`` so untrusted names are never parsed as mathtext."""
    return str(text).replace("$", r"\$")


def time_unit(span_s: float) -> tuple[float, str]:
    """The time unit of an axis spanning ``span_s`` seconds: (seconds per unit, unit name);
    hours from 3 h on, minutes from 3 min on, else seconds."""
    if span_s >= 3 * 3600:
        return 3600.0, "h"
    if span_s >= 180:
        return 60.0, "min"
    return 1.0, "s"


def thin_step(n: int, max_points: int) -> int:
    """Stride that keeps at most ``max_points`` of ``n`` samples (every k-th one)."""
    return max(1, int(np.ceil(n / max_points)))


class Sliced(Protocol):
    """An ndarray, or anything whose slices are arrays (a time axis formed slice by slice)."""

    def __getitem__(self, sl: slice, /) -> FloatArray: ...


def minmax_envelope(t: Sliced, y: FloatArray, bins: int
              ) -> tuple[FloatArray, FloatArray, FloatArray, FloatArray]:
    """Min-max envelope of ``y`` in ``bins`` equal-count blocks.

    ``t`` is only sliced (two strided slices and the tail), so it need not be an array.

    Returns
    -------
    tc, lo, hi : ndarray
        Block centre time, minimum and maximum; a shorter last block is included.
    mean : ndarray
        Mean of each full block (one fewer entry than ``tc`` when there is a last block).
    """
    n = y.size
    size = int(np.ceil(n / bins))
    k = n // size
    head = y[: k * size].reshape(k, size)
    lo, hi = head.min(axis=1), head.max(axis=1)
    tc = t[: k * size : size] + 0.5 * (t[size - 1 : k * size : size] - t[: k * size : size])
    if n > k * size:
        lo = np.append(lo, y[k * size:].min())
        hi = np.append(hi, y[k * size:].max())
        tc = np.append(tc, t[k * size:].mean())
    return tc, lo, hi, head.mean(axis=1)


def num_tex(v: float) -> str:
    """A number with 3 significant digits, in scientific notation when far from 1."""
    if not np.isfinite(v):
        return "n/a"
    if v == 0 or 1e-3 <= abs(v) < 1e4:
        return f"{v:.3g}"
    mant, exp = f"{v:.2e}".split("e")
    return rf"{mant}$\times$10$^{{{int(exp)}}}$"


def value_pm_tex(value: float, stderr: float) -> str:
    """``value ± stderr`` rounded to the standard error's two significant digits.

    The two share one power of ten when the value is outside [0.01, 1e4), e.g.
    ``(2.0030 ± 0.0045)×10^-3`` instead of ``0.002 ± 4.45×10^-6``, so the reader sees how
    many digits of the value mean something.
    """
    if not (np.isfinite(stderr) and stderr > 0 and np.isfinite(value) and value != 0):
        return num_tex(value) + (rf" ± {num_tex(stderr)}" if np.isfinite(stderr) else "")
    exp = 0 if 1e-2 <= abs(value) < 1e4 else int(np.floor(np.log10(abs(value))))
    scale = 10.0 ** exp
    decimals = max(0, 1 - int(np.floor(np.log10(stderr / scale))))
    text = f"{value / scale:.{decimals}f} ± {stderr / scale:.{decimals}f}"
    return text if exp == 0 else rf"({text})$\times$10$^{{{exp}}}$"
