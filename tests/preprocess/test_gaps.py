"""fogts.preprocess.gaps: gaps in a time base and the regular segments between them."""

from __future__ import annotations

import numpy as np
import pytest

from fogts.preprocess.gaps import find_gaps


def test_find_gaps_lists_gaps_and_segments() -> None:
    t = np.r_[np.arange(100), np.arange(150, 200), np.arange(205, 400)] / 10.0
    rep = find_gaps(t, fs_hz=10.0)
    assert rep.n_gaps == 2
    assert [(g.row, g.time_s) for g in rep.gaps] == [(99, 9.9), (149, 19.9)]
    assert rep.gaps[0].length_s == pytest.approx(5.1)
    assert rep.missing_s == pytest.approx(5.0 + 0.5)  # 51 - 1 and 6 - 1 steps of 0.1 s
    assert rep.segments == ((0, 100), (100, 150), (150, 345))
    assert rep.longest_segment() == (150, 345)
    assert "2 gap(s) in the time base (5.5 s missing; first at t = 9.9 s" in rep.summary()
