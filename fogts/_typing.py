"""Shared type aliases (a leaf module: imports nothing from fogts)."""

from __future__ import annotations

from typing import TypeAlias

import numpy as np
import numpy.typing as npt
import pandas as pd

FloatArray: TypeAlias = npt.NDArray[np.float64]
IntArray: TypeAlias = npt.NDArray[np.int64]
BoolArray: TypeAlias = npt.NDArray[np.bool_]
ArrayLike1D: TypeAlias = "npt.ArrayLike | pd.Series"
RngLike: TypeAlias = "np.random.Generator | int | None"

__all__ = ["ArrayLike1D", "BoolArray", "FloatArray", "IntArray", "RngLike"]
