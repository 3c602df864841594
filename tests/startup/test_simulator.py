"""The cold-start simulator: bad inputs (its outputs are checked by the tests of the fit,
the compensation and north seeking, which use it as their truth)."""

from __future__ import annotations

import numpy as np
import pytest

from fogts.errors import DataError, InsufficientDataError
from fogts.startup.simulator import simulate_startup, warmup_temperature


def test_bad_input() -> None:
    with pytest.raises(DataError, match="tau_s must be"):
        warmup_temperature(np.arange(10.0), tau_s=(10.0, 100.0))
    with pytest.raises(DataError, match="not stationary"):
        simulate_startup(ar=(1.1,))
    with pytest.raises(DataError, match="unknown thermal term"):
        simulate_startup(coefficients={"T3": 1.0})
    with pytest.raises(InsufficientDataError, match="at least 10 needed"):
        simulate_startup(duration_s=5)
