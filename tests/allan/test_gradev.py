"""The gap-robust overlapping ADEV against allantools.gradev (Sesia & Tavella 2008) and
against the plain overlapping ADEV of the same data without gaps."""

from __future__ import annotations

import allantools
import numpy as np
import pytest

from fogts.allan.estimators import oadev
from fogts.allan.gradev import gradev
from fogts.errors import DataError, InsufficientDataError

FS = 10.0
M = np.array([1, 2, 4, 8, 16, 32, 64, 128, 256])


def _rate(seed: int = 3, n: int = 20_000) -> np.ndarray:
    rng = np.random.default_rng(seed)
    return rng.normal(size=n) + np.cumsum(rng.normal(scale=0.01, size=n))


def test_angle_with_missing_points_matches_allantools_gradev() -> None:
    """Same terms, same formula: the only difference is the order of float64 additions
    (numpy's pairwise sum against our dot product), ~1e-15 relative; 1e-10 leaves room for
    other BLAS kernels without hiding a wrong term (a term more or less moves the result
    by ~1/n ~ 1e-4)."""
    angle = np.r_[0.0, np.cumsum(_rate())] / FS
    angle[3000:3500] = np.nan
    angle[9000] = np.nan
    angle[15000:15010] = np.nan
    ours = gradev(angle, fs_hz=FS, m=M, input="angle")
    taus, dev, _, ns = allantools.gradev(angle, rate=FS, data_type="phase", taus=M / FS)
    np.testing.assert_allclose(taus, M / FS, rtol=1e-12)
    np.testing.assert_array_equal(ours.n, ns.astype(np.int64))
    np.testing.assert_allclose(ours.dev, dev, rtol=1e-10, atol=0)


def test_rate_without_gaps_is_the_overlapping_adev() -> None:
    y = _rate()
    np.testing.assert_allclose(gradev(y, fs_hz=FS, m=M).dev, oadev(y, fs_hz=FS, m=M).dev,
                               rtol=1e-10, atol=0)


def test_rate_gap_removes_exactly_the_terms_that_touch_it() -> None:
    """With samples 5000..5999 missing, the valid terms are those of the two segments: the
    sum of squares is the two segments' oadev sums added (each segment's own phase)."""
    y = _rate()
    gapped = y.copy()
    gapped[5000:6000] = np.nan
    out = gradev(gapped, fs_hz=FS, m=M)
    mean = float(np.mean(np.r_[y[:5000], y[6000:]]))
    total, count = np.zeros(M.size), np.zeros(M.size)
    for seg in (y[:5000] - mean, y[6000:] - mean):
        x = np.r_[0.0, np.cumsum(seg)]
        for i, mi in enumerate(M):
            d = x[2 * mi:] - 2 * x[mi:-mi] + x[:-2 * mi]
            total[i] += float(np.sum(d * d))
            count[i] += d.size
    np.testing.assert_array_equal(out.n, count.astype(np.int64))
    np.testing.assert_allclose(out.dev, np.sqrt(total / (2 * count)) / M, rtol=1e-10)


def test_gradev_errors() -> None:
    with pytest.raises(DataError, match="data must be finite or NaN"):
        gradev(np.r_[1.0, np.inf, 2.0, 3.0], fs_hz=1.0, m=[1])
    with pytest.raises(DataError, match="input must be one of rate, angle; got 'x'"):
        gradev(np.ones(10), fs_hz=1.0, m=[1], input="x")
    with pytest.raises(DataError, match="m must be a non-empty 1-D array"):
        gradev(np.ones(10), fs_hz=1.0, m=[0])
    with pytest.raises(InsufficientDataError, match="m = 8 needs more than 16 phase points"):
        gradev(np.ones(10), fs_hz=1.0, m=[8])


def test_gaps_nan_analyses_the_whole_record(tmp_path) -> None:  # type: ignore[no-untyped-def]
    """``--gaps nan``: a record with two dropped stretches is analysed whole on its grid;
    the curve is :func:`gradev` of the NaN-filled record, and N (white noise 0.1 deg/h at
    10 Hz, i.e. N = 0.1/sqrt(10)/60 deg/sqrt(h)) lies within its 95 % interval."""
    import json

    import pandas as pd
    from typer.testing import CliRunner

    from fogts.cli import app

    rng = np.random.default_rng(8)
    n = 60_000
    y = rng.normal(scale=0.1, size=n)
    keep = np.ones(n, dtype=bool)
    keep[10_000:12_000] = False
    keep[40_000:40_500] = False
    path = tmp_path / "gappy.csv"
    pd.DataFrame({"time": np.arange(n)[keep] / FS, "rate_deg_h": y[keep]}).to_csv(
        path, index=False, float_format="%.17g")
    result = CliRunner().invoke(app, ["allan", str(path), "--gaps", "nan", "--confidence",
                                      "0.95", "--terms", "N,B,K", "--json", "-"])
    assert result.exit_code == 0, result.output
    doc = json.loads(result.stdout)
    filled = np.where(keep, y, np.nan)
    m = np.array([p["m"] for p in doc["points"]])
    expected = gradev(filled, fs_hz=FS, m=m)
    np.testing.assert_allclose([p["dev"] for p in doc["points"]], expected.dev, rtol=1e-9)
    assert [p["n"] for p in doc["points"]] == expected.n.tolist()
    term = doc["noise"]["N"]
    assert term["ci_low"] <= 0.1 / np.sqrt(FS) / 60 <= term["ci_high"]
    assert "--gaps nan" in result.output or doc["data_quality"]["gap_policy"] == "nan"


def test_gaps_nan_refuses_other_kinds(tmp_path) -> None:  # type: ignore[no-untyped-def]
    import fogts
    from fogts.io.run import Run
    from fogts.preprocess.gaps import fill_gaps_nan

    t = np.r_[np.arange(500), np.arange(600, 1000)] / FS
    run = fill_gaps_nan(Run(rate=_rate(n=t.size), time=t, fs_hz=FS, units="deg/h",
                            axes=("rate",)))
    with pytest.raises(DataError, match="only kind='oadev' has a gap-robust estimator, got "
                                        "kind='mdev'"):
        fogts.allan_deviation(run, kind="mdev")
