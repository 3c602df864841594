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


def test_fill_gaps_nan_refuses_stamps_that_would_share_a_grid_point() -> None:
    from fogts.errors import DataError
    from fogts.io.run import Run
    from fogts.preprocess.gaps import fill_gaps_nan

    # two samples stamped 0.02 s apart in a 10 Hz record: both round to the grid point 0.1 s
    t = np.r_[0.0, 0.09, 0.11, 0.2, 0.6, 0.7]
    run = Run(rate=np.arange(6.0), time=t, fs_hz=10.0, units="deg/h", axes=("rate",),
              source="clumps.csv")
    with pytest.raises(DataError, match=r"^clumps\.csv: gaps='nan' puts each "
                       r"sample at its nearest grid point k/fs \(10 Hz\), and 1 sample\(s\) "
                       r"would land on the point of the sample before"):
        fill_gaps_nan(run)
    ok = Run(rate=np.arange(5.0), time=np.r_[0.0, 0.1, 0.2, 0.5, 0.6], fs_hz=10.0,
             units="deg/h", axes=("rate",))
    assert np.isnan(fill_gaps_nan(ok).rate).sum() == 2   # the grid with its two holes


def test_the_longest_gap_is_found_beyond_the_listed_ones() -> None:
    """60 gaps of 0.2 s, the 55th 0.9 s long: only MAX_LISTED (50) are listed, but the
    summary and ``longest`` name the 0.9 s one."""
    from fogts.preprocess.gaps import MAX_LISTED

    steps = np.full(600, 0.1)
    steps[9::10] = 0.3                  # a 0.2 s hole after every tenth sample
    steps[549] = 1.0                    # the 55th gap: 0.9 s missing
    t = np.r_[0.0, np.cumsum(steps)]
    rep = find_gaps(t, fs_hz=10.0)
    assert rep.n_gaps == 60 and len(rep.gaps) == MAX_LISTED
    assert rep.longest is not None and rep.longest.row == 549
    assert rep.longest.length_s == pytest.approx(1.0, rel=1e-12)
    assert rep.largest_s == rep.longest.length_s
    assert f"longest 1 s at t = {t[549]:.6g} s" in rep.summary()
