"""Argument validation shared by every entry point (a leaf module).

Each check raises :class:`fogts.errors.DataError` with a message that names the argument,
echoes the bad value and says what is allowed (DESIGN.md, convention 4).
"""

from __future__ import annotations

import math
from collections.abc import Collection, Iterator
from contextlib import contextmanager
from contextvars import ContextVar
from typing import Any, NoReturn

import numpy as np
import pandas as pd

from fogts._typing import FloatArray
from fogts.errors import DataError, InsufficientDataError

__all__ = ["all_finite", "as_rng", "check_choice", "check_fraction", "check_int", "check_positive",
           "checked_sum", "finite_or_none", "finite_sum", "forget_sum", "is_pandas", "known_sums", "note_sum",
           "pandas_index", "sums_known", "to_float_array"]

#: Within :func:`known_sums`: id of an array -> the array and its :func:`finite_sum`.
_KNOWN_SUMS: ContextVar[dict[int, tuple[np.ndarray, float]] | None] = \
    ContextVar("fogts_known_sums", default=None)


def check_positive(name: str, value: Any, *, allow_zero: bool = False) -> float:
    """Return ``value`` as a float if it is finite and > 0 (>= 0 with ``allow_zero``)."""
    try:
        v = float(value)
    except (TypeError, ValueError):
        raise DataError(f"{name} must be a number, got {value!r}") from None
    if not math.isfinite(v) or v < 0 or (v == 0 and not allow_zero):
        op = ">= 0" if allow_zero else "> 0"
        raise DataError(f"{name} must be a finite number {op}, got {value!r}")
    return v


def check_int(name: str, value: Any, *, minimum: int | None = None,
              maximum: int | None = None) -> int:
    """Return ``value`` as an int within ``[minimum, maximum]``."""
    if isinstance(value, bool) or not isinstance(value, int | np.integer):
        if isinstance(value, float | np.floating) and float(value).is_integer():
            value = int(value)
        else:
            raise DataError(f"{name} must be an integer, got {value!r}")
    v = int(value)
    if minimum is not None and v < minimum:
        raise DataError(f"{name} must be >= {minimum}, got {v}")
    if maximum is not None and v > maximum:
        raise DataError(f"{name} must be <= {maximum}, got {v}")
    return v


def check_fraction(name: str, value: Any) -> float:
    """Return ``value`` as a float strictly between 0 and 1."""
    try:
        v = float(value)
    except (TypeError, ValueError):
        raise DataError(f"{name} must be a number in (0, 1), got {value!r}") from None
    if not 0.0 < v < 1.0:
        raise DataError(f"{name} must be in (0, 1), got {value!r}")
    return v


def check_choice(name: str, value: Any, allowed: Collection[str]) -> str:
    """Return ``value`` if it is one of ``allowed``."""
    if not isinstance(value, str) or value not in allowed:
        raise DataError(f"{name} must be one of {', '.join(map(str, allowed))}; got {value!r}")
    return value


def is_pandas(x: object) -> bool:
    """True for a pandas Series or DataFrame."""
    return isinstance(x, pd.Series | pd.DataFrame)


def pandas_index(x: object) -> pd.Index | None:
    """The index of a pandas object, else None (kept to re-wrap outputs)."""
    return x.index if isinstance(x, pd.Series | pd.DataFrame) else None


def all_finite(arr: np.ndarray) -> bool:
    """Whether every value of the float array ``arr`` is finite.

    One summing pass that allocates nothing: NaN and inf propagate through a sum, so a
    finite sum settles it; a non-finite sum (a NaN or inf, or finite values that overflow)
    is settled value by value.

    Examples
    --------
    >>> all_finite(np.array([1.0, 2.0])), all_finite(np.array([1.0, np.nan]))
    (True, False)
    >>> all_finite(np.array([1e308, 1e308]))   # the sum overflows, the values do not
    True
    """
    return finite_sum(arr) is not None


@contextmanager
def known_sums() -> Iterator[None]:
    """Within this context :func:`finite_sum` of an array recorded by :func:`note_sum` (a
    reader's sum, taken while it checked the values in the cache) is that sum, not another
    pass.  The recorded arrays must stay unchanged meanwhile: a command's own input from
    reading to its output, which each check along the way would otherwise sum again (two
    passes over 800 MB at 10^8 samples).  Each is held while the context lasts, so its id
    cannot be reused by another array.

    Examples
    --------
    >>> x = np.array([1.0, 2.0])
    >>> with known_sums():
    ...     note_sum(x, 3.0)
    ...     finite_sum(x)
    3.0
    """
    token = _KNOWN_SUMS.set({})
    try:
        yield
    finally:
        _KNOWN_SUMS.reset(token)


def sums_known() -> bool:
    """Whether a :func:`known_sums` context is open (a reader then records its sums)."""
    return _KNOWN_SUMS.get() is not None


def note_sum(arr: np.ndarray, total: float) -> None:
    """Record ``total`` as ``numpy.sum(arr)`` (bit for bit) of the finite float array
    ``arr`` within :func:`known_sums`; nothing outside it."""
    known = _KNOWN_SUMS.get()
    if known is not None:
        known[id(arr)] = (arr, total)


def forget_sum(arr: np.ndarray) -> None:
    """Forget the sum :func:`note_sum` recorded for ``arr``, whose values are about to
    change (:func:`fogts.allan.kernels.phase_in_place`); nothing if none was.

    Examples
    --------
    >>> x = np.array([1.0, 2.0])
    >>> with known_sums():
    ...     note_sum(x, 0.5)  # a recorded sum is taken as it is ...
    ...     recorded = finite_sum(x)
    ...     forget_sum(x)     # ... until it is forgotten: then the values are summed
    ...     recorded, finite_sum(x)
    (0.5, 3.0)
    """
    known = _KNOWN_SUMS.get()
    if known is not None and known.get(id(arr), (None,))[0] is arr:
        del known[id(arr)]


def finite_sum(arr: np.ndarray) -> float | None:
    """``numpy.sum(arr)`` when every value of the float array ``arr`` is finite, else None:
    the pass of :func:`all_finite`, whose sum is the one ``numpy.mean`` divides by the
    count (the same pairwise reduction, so ``finite_sum(a) / a.size == numpy.mean(a)``
    bit for bit).  Within :func:`known_sums` it is taken once per array.

    Examples
    --------
    >>> finite_sum(np.array([1.0, 2.5])), finite_sum(np.array([1.0, np.inf]))
    (3.5, None)
    """
    known = _KNOWN_SUMS.get()
    held = known.get(id(arr)) if known is not None else None
    if held is not None and held[0] is arr:
        return held[1]
    with np.errstate(over="ignore", invalid="ignore"):
        total = float(np.sum(arr))
    if math.isfinite(total) or np.isfinite(arr).all():
        return total
    return None


def checked_sum(arr: np.ndarray, name: str = "x") -> float:
    """:func:`finite_sum` of ``arr``; a non-finite value raises :class:`DataError` naming its
    position, as :func:`to_float_array` does."""
    total = finite_sum(arr)
    if total is None:
        _refuse_nonfinite(arr, name)
    return total


def _refuse_nonfinite(arr: np.ndarray, name: str) -> NoReturn:
    bad = ~np.isfinite(arr)
    pos = int(np.argwhere(bad)[0][0])
    raise DataError(f"{name} contains a non-finite value ({float(arr.flat[np.argmax(bad)])!r}) "
                    f"at position {pos}; remove or interpolate it first")


def to_float_array(x: Any, name: str = "x", *, min_length: int = 2,
                   allow_nonfinite: bool = False, ndim: int = 1) -> FloatArray:
    """Convert ``x`` to a contiguous float64 array and check it.

    Parameters
    ----------
    x : array_like or pandas.Series
        The data.
    name : str
        Argument name used in error messages.
    min_length : int
        Fewer samples raise :class:`InsufficientDataError`.
    allow_nonfinite : bool
        If False, NaN or inf raise :class:`DataError` naming the first bad position.
    ndim : int
        1 for a single series; 2 accepts ``(n,)`` or ``(n, axes)``.
    """
    if isinstance(x, pd.Series | pd.DataFrame):
        x = x.to_numpy()
    try:
        arr = np.ascontiguousarray(np.asarray(x, dtype=np.float64))
    except (TypeError, ValueError) as exc:
        raise DataError(f"{name} must be numeric, could not convert to float64: {exc}") from None
    if arr.ndim == 0 or arr.ndim > ndim:
        allowed = "a 1-D array" if ndim == 1 else "a 1-D or 2-D array"
        raise DataError(f"{name} must be {allowed}, got shape {arr.shape}")
    if arr.shape[0] < min_length:
        raise InsufficientDataError(
            f"{name} needs at least {min_length} samples, got {arr.shape[0]}")
    if not allow_nonfinite and not all_finite(arr):
        _refuse_nonfinite(arr, name)
    return arr


def as_rng(rng: Any) -> np.random.Generator:
    """Turn ``rng`` (Generator, int seed or None) into a Generator; no global state is used."""
    if isinstance(rng, np.random.Generator):
        return rng
    if rng is None or isinstance(rng, int | np.integer):
        return np.random.default_rng(rng)
    raise DataError(f"rng must be a numpy Generator, an int seed or None, got {rng!r}")


def finite_or_none(v: Any) -> float | None:
    """``v`` as a float, or None if it is not a finite number (a JSON- and CSV-safe cell).

    Examples
    --------
    >>> finite_or_none(2), finite_or_none(float("nan")), finite_or_none(None)
    (2.0, None, None)
    """
    try:
        f = float(v)
    except (TypeError, ValueError):
        return None
    return f if math.isfinite(f) else None
