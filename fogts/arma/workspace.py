"""The series-length innovations array that exact-likelihood models share.

A fit of a long series evaluates its likelihood many times; each evaluation's innovations
(:meth:`fogts.arma.likelihood.ExactLikelihood.evaluate`) go into one preallocated array,
which the models of that series, and of its prefixes, share instead of allocating their own.
"""

from __future__ import annotations

import weakref
from typing import TYPE_CHECKING

import numpy as np

from fogts._typing import FloatArray

if TYPE_CHECKING:
    from fogts.arma.likelihood import Evaluation

__all__ = ["Workspace"]


class Workspace:
    """One series-length float64 array, allocated on first use, that likelihood models of the
    same length may share (one at a time), and the evaluation whose innovations it holds.
    Models of a prefix of the series may use its first samples (:meth:`prefix`)."""

    def __init__(self, n: int) -> None:
        self.n = n
        self.array: FloatArray | None = None
        self.holder: Evaluation | None = None
        self._root: Workspace | None = None     # the workspace whose memory a prefix uses
        # a prefix's holder is cleared when the root is taken (weakly: no reference cycle,
        # so a dropped workspace's memory is freed at once)
        self._prefixes: weakref.WeakSet[Workspace] = weakref.WeakSet()

    def prefix(self, m: int) -> Workspace:
        """A workspace of the first ``m`` samples in this one's memory: taking either one
        discards the innovations the other holds."""
        root = self if self._root is None else self._root
        out = Workspace(m)
        out._root = root
        root._prefixes.add(out)
        return out

    def take(self) -> FloatArray:
        """The array, to be overwritten (it no longer holds anyone's innovations)."""
        root = self if self._root is None else self._root
        if root.array is None:
            root.array = np.empty(root.n)
        root.holder = None
        for w in root._prefixes:
            w.holder = None
        out = root.array if self._root is None else root.array[:self.n]
        self.array = out
        return out
