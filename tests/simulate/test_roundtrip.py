"""Round trip: coefficients -> simulate_gyro -> allan_deviation -> fit_noise recovers them."""

from __future__ import annotations

import numpy as np
import pytest

from fogts.simulate.gyro import simulate_gyro

#: Three sensor grades (deg/h-based units).  Each is chosen so that N, B and K each dominate
#: the Allan curve over part of a 3 h record (N -> B crossover near 20-40 s, B -> K near
#: 100-120 s); a term that dominates nowhere cannot be identified, whatever the fit.
GRADES = {
    "navigation FOG": {"N": 0.0005, "B": 0.008, "K": 0.05},
    "tactical FOG": {"N": 0.01, "B": 0.15, "K": 1.0},
    "MEMS": {"N": 0.2, "B": 4.0, "K": 25.0},
}
#: 30 seeds per grade, different for each grade, so that the three grades are independent
#: samples (with shared seeds they are nearly the same draws, rescaled).
ROUND_TRIP_SEEDS = {grade: range(1000 + 100 * i, 1030 + 100 * i) for i, grade in enumerate(GRADES)}
#: The test runs 3 h at 5 Hz; B and K live at tau >= 20 s, where 5 Hz and 100 Hz records
#: are equivalent.  The 100 Hz study is benchmarks/accuracy/roundtrip.py.
ROUND_TRIP_FS = 5.0


@pytest.fixture(scope="module")
def round_trip() -> dict[str, dict[str, dict[str, np.ndarray]]]:
    """Per grade and term: relative errors of the WLS fit and of the slope read-off, and
    whether the fit's 68.3 % interval covers the truth, over 30 seeds."""
    import warnings

    from fogts.allan import allan_deviation
    from fogts.allan.noise import fit_noise

    out: dict[str, dict[str, dict[str, np.ndarray]]] = {}
    for grade, truth in GRADES.items():
        rows: dict[str, list[tuple[float, float, bool]]] = {t: [] for t in truth}
        for seed in ROUND_TRIP_SEEDS[grade]:
            run = simulate_gyro(truth, fs_hz=ROUND_TRIP_FS, duration_s="3h", rng=seed)
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")  # Q and R are (rightly) unidentifiable
                model = fit_noise(allan_deviation(run, taus="octave"))
            for t, value in truth.items():
                term = model[t]
                rows[t].append((abs(term.value / value - 1),
                                abs(getattr(model.readoff, t) / value - 1),
                                bool(term.ci_low <= value <= term.ci_high)))
        out[grade] = {t: {"fit": np.array([r[0] for r in v]),
                          "readoff": np.array([r[1] for r in v]),
                          "covered": np.array([r[2] for r in v])} for t, v in rows.items()}
    return out


@pytest.mark.parametrize("grade", list(GRADES))
def test_round_trip_median_error(round_trip: dict, grade: str) -> None:
    """Median relative error over 30 seeds: <= 5 % for N, <= 15 % for B and K."""
    res = round_trip[grade]
    assert np.median(res["N"]["fit"]) <= 0.05
    assert np.median(res["B"]["fit"]) <= 0.15
    assert np.median(res["K"]["fit"]) <= 0.15


@pytest.mark.parametrize("term", ["N", "B", "K"])
def test_round_trip_interval_coverage(round_trip: dict, term: str) -> None:
    """The 68.3 % intervals cover the truth as often as a 68.3 % interval should.

    Pooled over the 90 independent fits (3 grades x 30 seeds), the number of hits is
    Binomial(90, 0.683) for honest intervals; the test accepts the central 99.9 % of that
    distribution (46-75 hits).
    """
    from scipy.stats import binom

    covered = np.concatenate([round_trip[grade][term]["covered"] for grade in GRADES])
    lo, hi = binom.ppf(0.0005, covered.size, 0.683), binom.isf(0.0005, covered.size, 0.683)
    assert lo <= covered.sum() <= hi, (term, covered.mean(), lo, hi)
    # ... and no grade is wildly off on its own (99.9 % band of Binomial(30, 0.683)).
    for grade in GRADES:
        hits = round_trip[grade][term]["covered"].sum()
        assert binom.ppf(0.0005, 30, 0.683) <= hits <= binom.isf(0.0005, 30, 0.683), grade


@pytest.mark.parametrize("grade", list(GRADES))
def test_weighted_fit_beats_slope_readoff(round_trip: dict, grade: str) -> None:
    for term, res in round_trip[grade].items():
        assert np.median(res["fit"]) < np.median(res["readoff"]), term
