"""``fogts.allan.curve_weights``: alpha from a curve's slope (NIST SP1065 Table 5's
mu = -alpha - 1) and the record length from a number-of-terms column."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from fogts.allan.curve_weights import record_length, slope_alpha
from fogts.io.curve_table import read_curve_table

TAU = 2.0 ** np.arange(0, 10)


@pytest.mark.parametrize(("slope", "kind", "alpha"), [
    (-1.0, "oadev", 2),     # quantization (white phase); alpha 1 and 2 look alike here
    (-0.5, "oadev", 0),     # angle random walk: white rate noise
    (0.0, "oadev", -1),     # bias instability: flicker
    (0.5, "oadev", -2),     # rate random walk
    (1.0, "oadev", -2),     # a ramp is not a power law: the lowest alpha
    (1.0, "ohdev", -3),     # the Hadamard variance reaches further down
    (-1.5, "mdev", 2),      # mdev tells white phase (mu = -3) from flicker phase
    (-1.0, "mdev", 1),
])
def test_slope_alpha_follows_the_power_law(slope: float, kind: str, alpha: int) -> None:
    got = slope_alpha(TAU, TAU**slope, kind)
    assert got.tolist() == [alpha] * TAU.size


def test_slope_alpha_of_one_point_is_white_rate() -> None:
    assert slope_alpha(np.array([1.0]), np.array([2.0]), "oadev").tolist() == [0]


def test_record_length_from_an_oadev_terms_column(tmp_path: Path) -> None:
    """SP1065 eq. 11 sums N - 2m + 1 terms, so N = n + 2m - 1 at every tau."""
    path = tmp_path / "c.csv"
    path.write_text("tau,n,dev\n0.1,999,1\n0.2,997,0.8\n")
    table = read_curve_table(path)
    rows, m = np.arange(2), np.array([1, 2])
    assert record_length(table, rows, "oadev", m, None) == (1000, "file (number of terms)")
    assert record_length(table, rows, "adev", m, None) == (None, "")
    assert record_length(table, rows, "oadev", m, 5000) == (5000, "given")
    path.write_text("tau,n,dev\n0.1,999,1\n0.2,990,0.8\n")   # inconsistent: not used
    assert record_length(read_curve_table(path), rows, "oadev", m, None) == (None, "")
