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
    with pytest.raises(DataError, match=r"^clumps\.csv: gaps='nan' \(CLI --gaps nan\) puts each "
                       r"sample at its nearest grid point k/fs \(10 Hz\), and 1 sample\(s\) "
                       r"would land on the point of the sample before"):
        fill_gaps_nan(run)
    ok = Run(rate=np.arange(5.0), time=np.r_[0.0, 0.1, 0.2, 0.5, 0.6], fs_hz=10.0,
             units="deg/h", axes=("rate",))
    assert np.isnan(fill_gaps_nan(ok).rate).sum() == 2   # the grid with its two holes
