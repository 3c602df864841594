"""Tests for fogts.allan.readout (curve read-outs: minimum, slopes, regions)."""

from __future__ import annotations

import numpy as np
import pytest

from fogts.allan.readoff import READOFF_SLOPE_TOLERANCE, readoff_supported, slope_readoff
from fogts.allan.readout import read_curve
from fogts.allan.terms import B_PLATEAU
from fogts.errors import DataError, InsufficientDataError
from tests.allan.noise_cases import avar, make_result, quiet_fit


def _theory(tau: np.ndarray, n: float = 0.1, b: float = 0.01, k: float = 1e-4) -> dict[str, np.ndarray]:
    # IEEE 952 Annex C terms: sigma_N = N/sqrt(tau), sigma_B = B*sqrt(2 ln2/pi),
    # sigma_K = K*sqrt(tau/3)
    return {"N": n / np.sqrt(tau), "B": np.full_like(tau, b * np.sqrt(2 * np.log(2) / np.pi)),
            "K": k * np.sqrt(tau / 3)}


def test_power_law_slopes_are_exact() -> None:
    tau = np.logspace(-2, 5, 29)
    terms = _theory(tau)
    total = np.sqrt(sum(v**2 for v in terms.values()))
    r = read_curve(tau, terms["N"])
    np.testing.assert_allclose(r.segment_slope, -0.5, atol=1e-12)
    r = read_curve(tau, terms["K"])
    np.testing.assert_allclose(r.segment_slope, 0.5, atol=1e-12)
    r = read_curve(tau, total, term_curves=terms)
    assert [d.term for d in r.dominant] == ["N", "B", "K"]
    # N and B cross where N^2/tau = B^2 * 2ln2/pi
    cross = 0.1**2 / (0.01**2 * 2 * np.log(2) / np.pi)
    n_range = r.dominant[0]
    assert n_range.tau_to_s <= cross <= r.dominant[1].tau_from_s
    assert n_range.slope == -0.5


def test_minimum_and_regions_with_ci() -> None:
    tau = np.logspace(-1, 5, 41)
    total = np.sqrt(sum(v**2 for v in _theory(tau).values()))
    lo, hi = total * 0.9, total * 1.1
    r = read_curve(tau, total, lo, hi)
    i = int(np.argmin(total))
    assert r.tau_min_s == tau[i] and r.dev_min == total[i]
    assert r.dev_min_ci == (lo[i], hi[i])
    assert r.bias_instability_floor == pytest.approx(total[i] / B_PLATEAU)
    b, c, d = r.regions["B"], r.regions["C"], r.regions["D"]
    assert b is not None and c is not None and d is not None
    assert b[0] == tau[0] and b[1] == c[0] and c[1] == d[0] and d[1] == tau[-1]
    assert c[0] <= r.tau_min_s <= c[1]
    in_c = total[(tau >= c[0]) & (tau <= c[1])]
    assert np.all(in_c <= hi[i]) and np.all(in_c >= lo[i])
    assert r.to_frame().shape == (40, 3)
    assert r.to_dict()["minimum"]["tau"] == tau[i]
    assert r.summary().splitlines()[2].startswith("minimum") and "floor/0.664" in r.summary()


def test_monotone_curve_has_no_region_d() -> None:
    tau = np.logspace(0, 2, 5)
    r = read_curve(tau, 1 / np.sqrt(tau))
    assert r.regions["D"] is None and r.tau_min_s == 100.0


def test_bad_input() -> None:
    with pytest.raises(DataError, match="equal length"):
        read_curve([1, 2, 3], [1, 2])
    with pytest.raises(InsufficientDataError, match="at least 2 finite positive points, got 1"):
        read_curve([1, 2], [1, np.nan])
    with pytest.raises(DataError, match="strictly increasing"):
        read_curve([1, 3, 2], [1, 2, 3])


@pytest.mark.parametrize("seed", [1, 2, 3])
def test_minimum_of_simulated_record_matches_theory(seed: int) -> None:
    # white + flicker + rate random walk, 6 h at 10 Hz; the measured minimum
    # (among points with edf >= 10) lies within one octave (the grid spacing) of the
    # closed-form curve's minimum (311.9 s for these coefficients).
    import warnings

    from fogts.allan import allan_deviation
    from fogts.simulate.gyro import NoiseSpec, simulate_gyro

    spec = NoiseSpec.from_any({"N": 0.01, "B": 0.02, "K": 0.2})
    fine = np.logspace(-1, 4, 5001)
    tau_theory = fine[np.argmin(spec.adev(fine))]
    assert tau_theory == pytest.approx(311.9, rel=1e-3)
    run = simulate_gyro(spec, fs_hz=10, duration_s=6 * 3600, rng=seed)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        res = allan_deviation(run, taus="octave")
    r = res.readout()
    assert abs(np.log2(r.tau_min_s / tau_theory)) <= 1.0


def test_minimum_ignores_low_edf_points() -> None:
    tau = np.array([1.0, 10.0, 100.0, 1000.0])
    dev = np.array([1.0, 0.5, 0.4, 0.1])  # a chance low point at the longest tau
    r = read_curve(tau, dev, edf=[1e4, 1e3, 50.0, 1.5])
    assert r.tau_min_s == 100.0
    assert read_curve(tau, dev).tau_min_s == 1000.0
    assert read_curve(tau, dev, edf=[1.0, 1.0, 1.0, 1.0]).tau_min_s == 1000.0


# --------------------------------------------------------------------------- slope read-offs


def test_slope_readoffs_follow_the_matlab_definition() -> None:
    tau = 2.0 ** np.arange(-6, 18)
    n_only = quiet_fit(make_result(tau, np.sqrt(avar(tau, N=0.02))))
    assert n_only.readoff.N == pytest.approx(0.02, rel=1e-12)
    assert n_only.readoff.slope_N == pytest.approx(-0.5)
    k_only = quiet_fit(make_result(tau, np.sqrt(avar(tau, K=0.4, N=1e-6))))
    assert k_only.readoff.K == pytest.approx(0.4, rel=1e-6)
    mixed = quiet_fit(make_result(tau, np.sqrt(avar(tau, N=0.02, B=0.1, K=0.05))))
    dev = np.sqrt(avar(tau, N=0.02, B=0.1, K=0.05))
    assert mixed.readoff.B == pytest.approx(dev.min() / B_PLATEAU)
    assert mixed.readoff.tau_B_s == tau[np.argmin(dev)]
    assert "comparison only" in mixed.to_dict()["readoff"]["method"]


def test_slope_readoffs_in_si_units() -> None:
    """The read-off sentence in SI: N = 0.02 deg/sqrt(h) is 0.02 (pi/180)/60 rad/s/sqrt(Hz)
    (1 deg/sqrt(h) = (pi/180) rad / sqrt(3600 s)), B in rad/s (pi/180/3600 per deg/h)."""
    tau = 2.0 ** np.arange(-6, 18)
    model = quiet_fit(make_result(tau, np.sqrt(avar(tau, N=0.02, B=0.1, K=0.05))))
    text = model.readoff.describe(lambda v: f"{v:.6e}", units="si")
    n_si = model.readoff.N * np.pi / 180.0 / 60.0
    b_si = model.readoff.B * np.pi / 180.0 / 3600.0
    assert f"N = {n_si:.6e} rad/s/sqrt(Hz)" in text
    assert f"B = {b_si:.6e} rad/s" in text and "rad/s^2/sqrt(Hz)" in text
    assert "deg" not in text


def test_slope_readoff_of_pure_lines() -> None:
    """N from the -1/2 line at 1 s (/ 60), K from the +1/2 line at 3 s (x 60), B from the
    minimum / B_PLATEAU, in deg/h after the unit factor."""
    tau = 2.0 ** np.arange(-4, 8)
    n_line = slope_readoff(tau, 0.6 / np.sqrt(tau), 1.0)
    assert n_line.N == pytest.approx(0.01, rel=1e-12)
    assert n_line.points[0] == ("N", 1.0, pytest.approx(0.6, rel=1e-12))
    k_line = slope_readoff(tau, 0.5 * np.sqrt(tau / 3.0), 2.0)
    assert k_line.K == pytest.approx(60.0, rel=1e-12) and k_line.slope_K == pytest.approx(0.5)
    assert k_line.B == pytest.approx(2.0 * 0.5 * np.sqrt(tau[0] / 3.0) / B_PLATEAU, rel=1e-12)
    assert k_line.to_dict()["K"]["read_at_tau"] == 3.0
    single = slope_readoff(tau[:1], np.array([0.3]), 1.0)
    assert single.tau_B_s == tau[0] and np.isnan(single.N)


def test_a_readoff_without_a_segment_of_its_slope_is_not_read() -> None:
    """White noise plus a flicker floor (no rate random walk): the segment nearest +1/2 is
    flat, so a +1/2 line through it reads no K (ADIS16405 run 1 X printed "K = 53.87
    deg/h^1.5 (+1/2 line at tau = 3 s)" from a segment of slope +0.11 while the fit gave
    K < 55.9)."""
    tau = 2.0 ** np.arange(-4, 12)
    dev = np.sqrt(avar(tau, N=0.02, B=0.1))
    # EDF 100 (68 % intervals of +-7 %): the last octaves, still 6 % apart without
    # intervals, are flat within them, so the floor (and B) is read
    r = slope_readoff(tau, dev, 1.0, np.full(tau.size, 100.0))
    assert readoff_supported(r, "N") and not readoff_supported(r, "K")
    assert readoff_supported(r, "B")
    assert abs(r.slope_K - 0.5) > READOFF_SLOPE_TOLERANCE  # the closest is the flat floor
    text = r.describe()
    assert "K not read (no segment of slope +1/2: the closest, " in text
    assert f"{r.slope_K:+.2f}, starts at tau = {r.tau_K_s:.4g} s)" in text
    assert "K = " not in text and "N = " in text and "B = " in text
    # the JSON keeps the number and the local slope it came from (the contract)
    assert r.to_dict()["K"]["local_slope"] == pytest.approx(r.slope_K)
    # a curve that does rise at +1/2 is read
    k_curve = slope_readoff(tau, np.sqrt(avar(tau, N=0.02, B=0.1, K=5.0)), 1.0)
    assert readoff_supported(k_curve, "K") and "K = " in k_curve.describe()


def test_the_readoff_tolerance_is_half_way_to_the_neighbouring_slopes() -> None:
    tau = 2.0 ** np.arange(-4, 8)
    for slope, read in ((-0.5 + 0.24, True), (-0.5 + 0.26, False), (-0.5 - 0.26, False)):
        r = slope_readoff(tau, tau**slope, 1.0)
        assert r.slope_N == pytest.approx(slope, abs=1e-12)
        assert readoff_supported(r, "N") is read


def test_region_labels_do_not_read_as_term_names() -> None:
    """The curve table printed "falling (B)" two rows above "B dominates", where B is the
    bias-instability term; the regions are labelled "region B" etc."""
    tau = np.logspace(-2, 5, 29)
    terms = _theory(tau)
    total = np.sqrt(sum(v**2 for v in terms.values()))
    text = read_curve(tau, total, term_curves=terms).table("deg/h", "x").to_text()
    assert "falling (region B)" in text and "floor (region C)" in text
    assert "rising (region D)" in text and "falling (B)" not in text


def test_a_term_reported_as_an_upper_limit_is_not_said_to_dominate() -> None:
    """"K dominates 3277 .. 3277 s" was printed for a K the fit gave as an upper limit
    (z = 0.62): the range is marked not measured, in the table and the dict."""
    tau = np.logspace(-2, 5, 29)
    terms = _theory(tau)
    total = np.sqrt(sum(v**2 for v in terms.values()))
    both = read_curve(tau, total, term_curves=terms)
    marked = read_curve(tau, total, term_curves=terms, limits={"K"})
    assert [(d.term, d.tau_from_s, d.tau_to_s) for d in marked.dominant] == \
        [(d.term, d.tau_from_s, d.tau_to_s) for d in both.dominant]   # the same ranges
    assert {d.term: d.measured for d in marked.dominant} == {"N": True, "B": True, "K": False}
    assert all(d.measured for d in both.dominant)
    text = marked.table("deg/h", "x").to_text()
    assert "K dominates" not in text and "N dominates" in text
    assert "K line largest" in text and "K is not measured (an upper limit)" in text
    assert [d["measured"] for d in marked.to_dict()["dominant"]] == [True, True, False]


def test_readouts_in_another_unit_scale_the_deviations_only() -> None:
    tau = np.logspace(-1, 3, 9)
    r = read_curve(tau, np.sqrt(1 / tau + tau / 100))
    si = r.in_unit("deg/h", "rad/s")
    factor = np.pi / 180.0 / 3600.0      # deg/h -> rad/s, by definition
    assert si.dev_min == pytest.approx(r.dev_min * factor, rel=1e-15)
    assert si.dev_min_ci == pytest.approx(tuple(v * factor for v in r.dev_min_ci), rel=1e-15)
    assert si.bias_instability_floor == pytest.approx(r.bias_instability_floor * factor,
                                                      rel=1e-15)
    assert si.tau_min_s == r.tau_min_s and si.regions == r.regions
    assert r.in_unit("deg/h", "deg/h") is r


# --------------------------------------------------------------------------- floor and EDF


def test_points_below_the_minimum_past_it_mean_no_floor() -> None:
    """A curve that keeps falling past its last trusted point: no region C, no floor/0.664,
    the lower low-EDF points named; B read-off not supported, with the same words."""
    tau = 2.0 ** np.arange(0, 10)
    dev = 1.0 / np.sqrt(tau)
    edf = 4000.0 / tau  # the last three points (EDF 15.6, 7.8, 3.9 ...) : 512 s has 7.8
    lo, hi = dev * 0.9, dev * 1.1
    r = read_curve(tau, dev, lo, hi, edf=edf)
    assert r.tau_min_s == 256.0 and r.regions["C"] is None and r.regions["D"] is None
    assert r.regions["B"] == (1.0, 512.0)
    assert np.isnan(r.bias_instability_floor) and not r.floor_found
    assert r.floor_note == ("no floor: the curve is still falling at its last trusted tau "
                            "(256 s); the points beyond it (512 .. 512 s) lie below the "
                            "minimum's interval")
    assert r.minimum_note == ("the lowest point with EDF >= 10 (lower points at 512 s have "
                              "EDF < 10)")
    d = r.to_dict()["minimum"]
    assert d["bias_instability_floor"] is None and d["floor"] == r.floor_note
    assert d["lower_points"] == [{"tau": 512.0, "dev": pytest.approx(dev[-1]),
                                  "edf": pytest.approx(edf[-1])}]
    assert "floor/" not in r.summary() and r.floor_note in r.summary()
    ro = slope_readoff(tau, dev, 1.0, edf)
    assert not readoff_supported(ro, "B")
    assert f"B not read ({r.floor_note.split(';')[0]}" in ro.describe()


def test_low_points_that_come_back_leave_the_floor() -> None:
    """A low low-EDF point followed by one back inside the minimum's interval is scatter
    on the floor: the floor stays (without the low point), no region D (nothing rises)."""
    tau = 2.0 ** np.arange(0, 8)
    dev = np.array([1.0, 0.7, 0.5, 0.31, 0.3, 0.3, 0.2, 0.29])
    edf = np.array([1e4, 1e4, 1e3, 500, 200, 50, 5, 2])
    r = read_curve(tau, dev, dev * 0.9, dev * 1.1, edf=edf)
    assert r.tau_min_s == 16.0 and r.floor_found
    assert r.regions["C"] == (8.0, 32.0) and r.regions["D"] is None
    assert [p[0] for p in r.lower_points] == [64.0, 128.0]


def test_a_curve_that_ends_below_the_minimums_interval_has_no_floor() -> None:
    """The audit's 5 s ADIS16405 record (N1): the point after the minimum lies inside its
    interval, the last one below it: the curve is still falling, so no region C and no
    floor/0.664 (it read 'floor (region C) 0.32 .. 0.64 s' and B = 476 deg/h)."""
    tau = 0.01 * 2.0 ** np.arange(8)
    dev = np.array([0.32855, 0.26475, 0.18949, 0.14681, 0.11823, 0.087803, 0.084663, 0.061789])
    lo = np.array([0.31739, 0.25405, 0.1795, 0.13657, 0.10721, 0.076813, 0.070503, 0.047982])
    hi = np.array([0.34097, 0.27693, 0.20136, 0.15976, 0.13354, 0.10543, 0.11326, 0.10501])
    edf = np.array([390.7, 269.8, 152.3, 82.07, 42.18, 20.63, 9.563, 3.885])
    r = read_curve(tau, dev, lo, hi, edf=edf)
    assert r.tau_min_s == pytest.approx(0.32) and not r.floor_found
    assert r.regions["C"] is None and r.regions["D"] is None
    assert r.regions["B"] == (pytest.approx(0.01), pytest.approx(1.28))
    assert np.isnan(r.bias_instability_floor)
    assert r.floor_note == ("no floor: the curve is still falling at its last trusted tau "
                            "(0.32 s); the curve ends below the minimum's interval (point at "
                            "1.28 s)")
    assert not readoff_supported(slope_readoff(tau, dev, 1.0, edf, ci=(lo, hi)), "B")


def test_a_curve_that_rose_past_its_minimum_keeps_its_floor_despite_a_low_last_point() -> None:
    """The bundled FOG example's shape: the curve rises above the minimum's interval (region
    D) before its last point (EDF 1.6) dips below it: that point is scatter after a rise, not
    a continued fall, so the floor stays."""
    tau = np.array([102.4, 204.8, 409.6, 819.2, 1638.4, 3276.8])
    dev = np.array([0.014593, 0.012678, 0.013612, 0.014521, 0.014263, 0.011170])
    edf = np.array([122.0, 47.3, 29.1, 10.7, 4.6, 1.63])
    r = read_curve(tau, dev, dev * 0.91, dev * 1.12, edf=edf)
    assert r.tau_min_s == pytest.approx(204.8) and r.floor_found
    assert r.regions["C"] == (pytest.approx(204.8), pytest.approx(409.6))
    assert r.regions["D"] == (pytest.approx(409.6), pytest.approx(3276.8))


def test_no_trusted_point_is_said() -> None:
    r = read_curve([1.0, 2.0, 4.0], [1.0, 0.5, 0.7], edf=[2.0, 2.0, 2.0])
    assert r.minimum_note == "no point has EDF >= 10: the minimum is the lowest of all points"
    assert r.tau_min_s == 2.0 and r.floor_found


def test_a_kind_without_a_plateau_factor_does_not_convert_the_floor() -> None:
    tau = np.array([1.0, 2.0, 4.0])
    r = read_curve(tau, [1.0, 0.5, 0.7], kind="tdev")
    assert np.isnan(r.bias_instability_floor)
    assert r.floor_text() == ("the floor is not converted to B: no flicker-FM plateau factor "
                              "is established for tdev")
    assert r.to_dict()["minimum"]["plateau_factor"] is None
    ro = slope_readoff(tau, np.array([1.0, 0.5, 0.7]), 1.0, kind="tdev")
    assert "B not read (no flicker-FM plateau factor is established for tdev)" in ro.describe()


def test_lower_points_follow_the_unit() -> None:
    tau = np.array([1.0, 2.0, 4.0])
    r = read_curve(tau, [1.0, 0.5, 0.2], edf=[100.0, 100.0, 2.0])
    si = r.in_unit("deg/h", "rad/s")
    assert si.lower_points[0][1] == pytest.approx(0.2 * np.pi / 180 / 3600, rel=1e-12)


def test_a_readoff_segment_needs_trusted_points_and_a_decided_slope() -> None:
    """The +1/2 segment's points need EDF >= 10, and its slope's standard error (from
    var(ln sigma) = 1/(2 edf) per point) must keep it nearer +1/2 than 0 or +1."""
    tau = 2.0 ** np.arange(0, 8)
    dev = np.sqrt(avar(tau, N=1e-6, K=5.0))  # +1/2 throughout
    assert readoff_supported(slope_readoff(tau, dev, 1.0, np.full(8, 1e4)), "K")
    weak = slope_readoff(tau, dev, 1.0, np.full(8, 8.0))
    assert not readoff_supported(weak, "K")
    assert "rests on points with EDF 8 and 8, fewer than the 10" in weak.describe()
    # EDF 20: se = sqrt(1/40 + 1/40) / ln 2 = 0.32, and |+0.5 - 0.5| + 0.32 < 0.5: read;
    # EDF 12: se = 0.42, still read on an exact line, but not 0.15 off it
    assert readoff_supported(slope_readoff(tau, dev, 1.0, np.full(8, 20.0)), "K")
    tilted = slope_readoff(tau, dev * tau**0.15, 1.0, np.full(8, 12.0))
    # (N = 1e-6 bends the line by under 1e-6 in slope)
    assert abs(tilted.slope_K - 0.65) < 1e-5 and not readoff_supported(tilted, "K")
    assert "does not exclude the neighbouring slopes +0 and +1" in tilted.describe()


def test_a_readoff_outside_a_measured_interval_is_flagged() -> None:
    from fogts.allan.readoff import FitBound, fit_check

    tau = 2.0 ** np.arange(0, 8)
    r = slope_readoff(tau, np.sqrt(avar(tau, N=1e-6, K=5.0)), 1.0)
    inside = FitBound(4.0, 6.0, "68.3 % interval", False)
    below = FitBound(5.5, 6.0, "68.3 % interval", False)
    assert fit_check(r, "K", inside) == ""
    assert fit_check(r, "K", below) == ("it lies outside the fit's 68.3 % interval 5.5 .. 6 "
                                        "deg/h^1.5: the read-off and the fit disagree")
    text = r.describe(fit={"K": below, "N": below})
    assert "K = 5 deg/h^1.5 (+1/2 line at tau = 3 s; it lies outside" in text
    assert "N not read" in text and "B = " in text  # N (no -1/2 segment) is not checked
    assert r.to_dict({"K": below})["K"]["fit_check"] == fit_check(r, "K", below)
