"""A long series minus its mean, not formed until something reads it.

:func:`fogts.preprocess.prepare.prepare` removes the mean of a long series by holding the
input and the mean (:class:`Demeaned`) instead of an 800 MB copy per 1e8 samples; the
ARMA selection reads the input and subtracts the mean block by block where it needs the
demeaned values, and ``Prepared.x`` (or ``Candidate.data``) forms the array on first access.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from fogts._typing import FloatArray

__all__ = ["UNFORMED_MIN_N", "Demeaned", "HeldSeries", "held", "holds_unformed"]

#: Above this many samples (8 MB of float64) a series minus its mean is held unformed; the
#: ARMA fits take series this long block by block (``fogts.arma.blockwise``, same limit).
UNFORMED_MIN_N = 1 << 20


def holds_unformed(x: FloatArray) -> bool:
    """Whether ``x`` minus its mean is held as a :class:`Demeaned` rather than formed: long
    (over :data:`UNFORMED_MIN_N` samples), float64 and C-contiguous (read block by block)."""
    return (x.shape[0] > UNFORMED_MIN_N and x.dtype == np.float64
            and bool(x.flags.c_contiguous))


class Demeaned:
    """Stand-in for the array ``raw - mean``: formed (one subtraction, the values of
    ``raw - mean``) on the first call of :meth:`array` and kept from then on, so that every
    holder of this stand-in shares one array.

    Examples
    --------
    >>> d = Demeaned(np.array([1.0, 2.0, 6.0]), 3.0)
    >>> d.size, d.array().tolist()
    (3, [-2.0, -1.0, 3.0])
    """

    __slots__ = ("_formed", "mean", "raw")

    def __init__(self, raw: FloatArray, mean: float) -> None:
        self.raw = raw
        self.mean = float(mean)
        self._formed: FloatArray | None = None

    @property
    def size(self) -> int:
        return int(self.raw.shape[0])

    def array(self) -> FloatArray:
        """``raw - mean`` (formed once)."""
        if self._formed is None:
            self._formed = self.raw - self.mean
        return self._formed

    def __reduce__(self) -> tuple[type[Demeaned], tuple[FloatArray, float]]:
        return Demeaned, (self.raw, self.mean)

    def __repr__(self) -> str:
        return f"Demeaned(n={self.size}, mean={self.mean!r})"


class HeldSeries:
    """Data descriptor of a dataclass field that may hold a :class:`Demeaned`: reading the
    field forms the array (cached in the instance).  Reading it on the class raises
    AttributeError, so that the dataclass sees a field without default and its signature
    is unchanged (installed with ``setattr`` after ``@dataclass``)."""

    def __init__(self, name: str) -> None:
        self.name = name

    def __get__(self, obj: Any, owner: Any = None) -> Any:
        if obj is None:
            raise AttributeError(self.name)
        value = obj.__dict__[self.name]
        if isinstance(value, Demeaned):
            value = value.array()
            obj.__dict__[self.name] = value
        return value

    def __set__(self, obj: Any, value: Any) -> None:
        obj.__dict__[self.name] = value


def held(obj: Any, name: str) -> Any:
    """What the :class:`HeldSeries` field ``name`` of ``obj`` holds, without forming it."""
    return obj.__dict__[name]
