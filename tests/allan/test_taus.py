"""Tau grids: named grids, explicit taus, term counts and the dropped-tau record.

Reference numbers: allantools' own tau filtering (``tau_generator`` + ``remove_small_ns``),
which drops every tau with at most one term, and Stable32's ``#`` column for PHASE.DAT.
"""

from __future__ import annotations

import allantools
import numpy as np
import pytest

from fogts.allan.taus import (
    GRID_NAMES,
    KINDS,
    DroppedTau,
    TauGrid,
    max_m,
    n_terms,
    tau_grid,
)
from fogts.errors import DataError, InsufficientDataError


def test_octave_decade_dense_all_contents() -> None:
    assert tau_grid("octave", fs_hz=1.0, n_samples=1000).m.tolist() == [
        1, 2, 4, 8, 16, 32, 64, 128, 256]
    assert tau_grid("decade", fs_hz=1.0, n_samples=1000).m.tolist() == [
        1, 2, 4, 10, 20, 40, 100, 200, 400]
    dense = tau_grid("dense", fs_hz=1.0, n_samples=100_000, per_decade=20).m
    # 20 log-spaced points per decade, rounded to whole samples and made unique.
    assert dense[:12].tolist() == [1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 13]
    decade = dense[(dense >= 1000) & (dense < 10_000)]
    assert decade.size == 20
    np.testing.assert_allclose(np.diff(np.log10(decade)), 0.05, atol=2e-3)
    assert tau_grid("dense", fs_hz=1.0, n_samples=100_000, per_decade=5).m.tolist()[:8] == [
        1, 2, 3, 4, 6, 10, 16, 25]
    assert tau_grid("all", fs_hz=1.0, n_samples=20).m.tolist() == list(range(1, 10))


def test_tau_is_m_over_fs_and_grid_records_its_inputs() -> None:
    g = tau_grid("octave", fs_hz=200.0, n_samples=5000, kind="mdev")
    np.testing.assert_array_equal(g.tau_s, g.m / 200.0)
    assert g.m.dtype == np.int64 and g.tau_s.dtype == np.float64
    assert (g.spec, g.kind, g.fs_hz, g.n_samples, g.dropped) == ("octave", "mdev", 200.0,
                                                                 5000, ())
    assert len(g) == g.m.size
    d = g.to_dict()
    assert d["m"] == g.m.tolist() and d["dropped"] == [] and d["spec"] == "octave"


@pytest.mark.parametrize("kind", KINDS)
def test_named_grids_stop_at_the_largest_computable_m(kind: str) -> None:
    for n in (4, 5, 11, 100, 1001):
        top = max_m(kind, n)
        assert top >= 1
        assert tau_grid("all", fs_hz=1.0, n_samples=n, kind=kind).m[-1] == top
        assert n_terms(kind, top, n) >= 2
        if kind != "totdev":
            assert n_terms(kind, top + 1, n) < 2


@pytest.mark.parametrize("kind", ["adev", "oadev", "mdev", "hdev", "ohdev"])
@pytest.mark.parametrize("n", [4, 7, 10, 33, 250])
def test_max_m_equals_allantools_largest_kept_tau(kind: str, n: int) -> None:
    # allantools computes every m < N and drops those with ns <= 1; its last kept m is the
    # largest computable one (totdev differs by design: fogts stops at T/2, SP1065).
    y = np.random.default_rng(n).normal(size=n)
    taus, _, _, ns = getattr(allantools, kind)(y, rate=1.0, data_type="freq", taus="all")
    assert int(np.rint(taus[-1])) == max_m(kind, n)
    np.testing.assert_array_equal(n_terms(kind, np.rint(taus).astype(int), n),
                                  ns.astype(np.int64))


def test_n_terms_matches_stable32_counts_for_phase_dat() -> None:
    # Stable32 '#' column for the 1000 frequency points of PHASE.DAT (see the
    # phase_dat_*.txt headers): adev m=2 -> 499, m=3 -> 332; mdev m=2 -> 996;
    # hdev m=1 -> 998, m=2 -> 498; ohdev m=2 -> 995; totdev -> 999 at any m.
    assert n_terms("adev", [1, 2, 3, 4], 1000).tolist() == [999, 499, 332, 249]
    assert n_terms("oadev", [1, 2, 10], 1000).tolist() == [999, 997, 981]
    assert n_terms("mdev", [1, 2, 3, 4], 1000).tolist() == [999, 996, 993, 990]
    assert n_terms("hdev", [1, 2, 3, 4], 1000).tolist() == [998, 498, 331, 248]
    assert n_terms("ohdev", [1, 2, 3, 4], 1000).tolist() == [998, 995, 992, 989]
    assert n_terms("totdev", [1, 2, 499, 500, 501], 1000).tolist() == [999, 999, 999, 999, 0]


def test_explicit_taus_are_rounded_and_bad_ones_dropped_with_reasons() -> None:
    g = tau_grid([0.004, 0.1, 0.104, 0.25, 0.31, 1.0, 1e4], fs_hz=10.0, n_samples=1000)
    assert g.spec == "explicit"
    # 2.5 rounds half-to-even to 2 (as numpy and allantools), 3.1 to 3.
    assert g.m.tolist() == [1, 2, 3, 10]
    np.testing.assert_allclose(g.tau_s, [0.1, 0.2, 0.3, 1.0])
    by_tau = {d.tau_s: d for d in g.dropped}
    assert set(by_tau) == {0.004, 0.104, 1e4}
    assert "duplicate: rounds to the same m = 1 as tau = 0.1 s" in by_tau[0.104].reason
    assert by_tau[0.004].m == 0 and "below half a sample period" in by_tau[0.004].reason
    assert by_tau[1e4].m == 100_000
    assert "oadev has only 0 term(s)" in by_tau[1e4].reason
    assert "largest m is 499" in by_tau[1e4].reason
    assert len(g.notes) == 1 and "rounded to the nearest whole number" in g.notes[0]
    assert g.to_dict()["dropped"][0] == {"tau": 0.004, "m": 0, "reason": by_tau[0.004].reason}


def test_explicit_duplicates_after_rounding_are_reported() -> None:
    g = tau_grid([1.0, 1.04, 0.96, 2.0], fs_hz=1.0, n_samples=100)
    assert g.m.tolist() == [1, 2]
    dup = [d for d in g.dropped if "duplicate" in d.reason]
    assert sorted(d.tau_s for d in dup) == [1.0, 1.04]   # 0.96 came first in sorted order
    assert all(d.m == 1 for d in dup)


def test_explicit_exact_taus_carry_no_rounding_note() -> None:
    g = tau_grid(np.array([0.01, 0.02, 0.5]), fs_hz=100.0, n_samples=1000)
    assert g.m.tolist() == [1, 2, 50] and g.notes == () and g.dropped == ()


def test_explicit_scalar_tau_is_accepted() -> None:
    assert tau_grid(2.0, fs_hz=1.0, n_samples=100).m.tolist() == [2]


def test_totdev_drops_taus_beyond_half_the_record() -> None:
    g = tau_grid([1.0, 50.0, 51.0], fs_hz=1.0, n_samples=100, kind="totdev")
    assert g.m.tolist() == [1, 50]
    assert len(g.dropped) == 1 and "T/2" in g.dropped[0].reason


@pytest.mark.parametrize("kind", ["adev", "oadev", "mdev", "hdev", "ohdev"])
def test_explicit_dropping_agrees_with_allantools(kind: str) -> None:
    n = 200
    y = np.random.default_rng(3).normal(size=n)
    taus = np.array([0.3, 1.0, 7.0, 33.0, 49.0, 50.0, 66.0, 67.0, 99.0, 100.0, 150.0, 199.0])
    g = tau_grid(taus, fs_hz=1.0, n_samples=n, kind=kind)
    kept = getattr(allantools, kind)(y, rate=1.0, data_type="freq", taus=taus)[0]
    assert g.m.tolist() == np.rint(kept).astype(int).tolist()
    assert len(g.m) + len(g.dropped) == taus.size


def test_dropped_tau_and_grid_are_frozen() -> None:
    d = DroppedTau(1.0, 1, "x")
    with pytest.raises(AttributeError, match="cannot assign"):
        d.m = 2  # type: ignore[misc]
    g = tau_grid("octave", fs_hz=1.0, n_samples=100)
    assert isinstance(g, TauGrid)
    with pytest.raises(AttributeError, match="cannot assign"):
        g.spec = "all"  # type: ignore[misc]


def test_grid_names_constant() -> None:
    assert GRID_NAMES == ("octave", "decade", "dense", "all")
    assert KINDS == ("adev", "oadev", "mdev", "hdev", "ohdev", "totdev")


# ------------------------------------------------------------------------- bad input


def test_unknown_grid_name_raises() -> None:
    with pytest.raises(DataError, match=r"taus must be one of octave, decade, dense, all; "
                                        r"got 'weekly'"):
        tau_grid("weekly", fs_hz=1.0, n_samples=100)


def test_unknown_kind_raises() -> None:
    with pytest.raises(DataError, match=r"kind must be one of adev, oadev.*got 'tdev'"):
        tau_grid("octave", fs_hz=1.0, n_samples=100, kind="tdev")
    with pytest.raises(DataError, match="kind must be one of"):
        n_terms("avar", [1], 100)
    with pytest.raises(DataError, match="kind must be one of"):
        max_m("avar", 100)


def test_bad_fs_samples_per_decade_raise() -> None:
    with pytest.raises(DataError, match=r"fs_hz must be a finite number > 0, got -1"):
        tau_grid("octave", fs_hz=-1, n_samples=100)
    with pytest.raises(DataError, match=r"n_samples must be >= 1, got 0"):
        tau_grid("octave", fs_hz=1.0, n_samples=0)
    with pytest.raises(DataError, match=r"per_decade must be >= 1, got 0"):
        tau_grid("dense", fs_hz=1.0, n_samples=100, per_decade=0)


@pytest.mark.parametrize("bad, pos", [([1.0, -2.0], "-2.0"), ([np.nan], "nan"),
                                      ([0.0, 1.0], "0.0"), ([1.0, np.inf], "inf")])
def test_non_positive_or_non_finite_taus_raise(bad: list[float], pos: str) -> None:
    with pytest.raises(DataError, match=rf"taus must be finite and > 0 seconds, got {pos}"):
        tau_grid(bad, fs_hz=1.0, n_samples=100)


def test_malformed_tau_arrays_raise() -> None:
    with pytest.raises(DataError, match=r"non-empty 1-D array of taus in seconds, got shape "
                                        r"\(0,\)"):
        tau_grid([], fs_hz=1.0, n_samples=100)
    with pytest.raises(DataError, match=r"got shape \(2, 2\)"):
        tau_grid([[1.0, 2.0], [3.0, 4.0]], fs_hz=1.0, n_samples=100)
    with pytest.raises(DataError, match=r"taus must be one of octave, decade, dense, all or an "
                                        r"array of taus in seconds"):
        tau_grid([1.0, "x"], fs_hz=1.0, n_samples=100)


def test_no_computable_tau_raises() -> None:
    with pytest.raises(InsufficientDataError, match=r"none of the requested taus can be "
                                                    r"computed for oadev with 100 samples"):
        tau_grid([0.01, 1000.0], fs_hz=1.0, n_samples=100)
    with pytest.raises(InsufficientDataError, match=r"hdev needs more samples: 3 rate "
                                                    r"sample\(s\) give no averaging factor"):
        tau_grid("octave", fs_hz=1.0, n_samples=3, kind="hdev")
