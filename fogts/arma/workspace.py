"""The series-length innovations array that exact-likelihood models share.

A fit of a long series evaluates its likelihood many times; each evaluation's innovations
(:meth:`fogts.arma.likelihood.ExactLikelihood.evaluate`) go into one preallocated array,
which the models of that series, and of its prefixes, share instead of allocating their own.
"""

from __future__ import annotations

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

    def __init__(self, n: int, root: Workspace | None = None) -> None:
        self.n = n
        self.array: FloatArray | None = None
        self.holder: Evaluation | None = None
        self.root = self if root is None else root
        self.sharing: list[Workspace] = [self]

    def prefix(self, m: int) -> Workspace:
        """A workspace of the first ``m`` samples in this one's memory: taking either one
        discards the innovations the other holds."""
        out = Workspace(m, self.root)
        self.root.sharing.append(out)
        return out

    def take(self) -> FloatArray:
        """The array, to be overwritten (it no longer holds anyone's innovations)."""
        root = self.root
        if root.array is None:
            root.array = np.empty(root.n)
        for w in root.sharing:
            w.holder = None
        self.array = root.array[:self.n]
        return self.array
