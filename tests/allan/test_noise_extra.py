"""fogts.allan.noise_extra: the optional Markov (M) and sinusoid (S) terms of fit_noise and
the likelihood-ratio test of adding them.

Truth: records simulated with fogts.simulate_gyro's exact discretisation of the
interval-averaged Gauss-Markov process (q_c = 0.3 deg/h/sqrt(s), T_c = 5 s, sigma =
q_c sqrt(T_c/2) = 0.474 deg/h) under white noise N = 0.01 deg/sqrt(h), 3 h at 100 Hz, fixed
seeds.  Tolerance: 2 standard errors (a 95 % normal interval).  Over seeds 100-111 the
estimates fell within 2 SE in 11/12 (T_c), 11/12 (q_c) and 12/12 (sigma) runs, with
root-mean-square z of 1.27, 1.13 and 0.85: the T_c error is about 25 % larger than
stated (tests/README.md); seed 13, not used here, misses T_c by 3.5 SE.
"""

from __future__ import annotations

import json
import math
import warnings
from pathlib import Path
from typing import Any

import pytest
from typer.testing import CliRunner

import fogts
from fogts.allan.misfit import check_fit
from fogts.cli import app
from fogts.errors import InsufficientDataError
from tests.conftest import shared_path

EXAMPLE = Path(__file__).resolve().parents[2] / "data" / "example_fog_10hz_3h.csv"
Q_C, T_C = 0.3, 5.0


def _fit(res: Any, **kw: Any) -> Any:
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return fogts.fit_noise(res, **kw)


@pytest.mark.parametrize("seed", [11, 12])
def test_markov_recovered_within_its_errors(seed: int) -> None:
    run = fogts.simulate_gyro({"N": 0.01, "q_c": Q_C, "T_c": T_C}, fs_hz=100,
                              duration_s=3 * 3600, rng=seed)
    res = fogts.allan_deviation(run)
    model = _fit(res, terms="N,B,K,M")
    (m,) = model.extra_terms
    assert m.name == "M" and m.status == "fitted" and not m.at_edge
    assert abs(m.parameter - T_C) < 2 * m.parameter_stderr
    assert abs(m.amplitude - Q_C) < 2 * m.amplitude_stderr
    assert abs(m.sigma - Q_C * math.sqrt(T_C / 2)) < 2 * m.sigma_stderr
    assert abs(model["N"].value - 0.01) < 2 * model["N"].stderr
    assert m.significant and m.p_value < 1e-20 and m.df == 2
    assert m.verdict.startswith("adding M (first-order Markov (correlated) noise): chi2 drop")
    assert m.verdict.endswith(": significant at 5 %")
    # the five-term fit misses the Markov hump; with M the curve lies within its intervals
    assert not check_fit(res, _fit(res)).ok
    assert check_fit(res, model).ok
    block = model.to_dict()["extra_terms"]["M"]
    assert block["T_c_unit"] == "s" and block["q_c_unit"] == "deg/h/sqrt(s)"
    assert block["T_c"] == pytest.approx(m.parameter, rel=1e-12)


def test_no_markov_term_in_the_bundled_example() -> None:
    """The bundled example (white noise and flicker, no Markov term): adding M is not
    significant, and the default fit has no optional-term output at all."""
    res = fogts.allan_deviation(fogts.read_run(EXAMPLE))
    model = _fit(res, terms="N,B,K,M")
    (m,) = model.extra_terms
    assert not m.significant and m.p_value > 0.1
    assert "not significant at 5 %" in m.verdict and m.verdict in model.summary()
    plain = _fit(res)
    assert plain.extra_terms == () and "extra_terms" not in plain.to_dict()


@pytest.mark.parametrize("seed", [5, 6, 7, 8])
def test_sinusoid_recovered(seed: int) -> None:
    """A 0.02 Hz sinusoid of 2 deg/h under white noise (1 h at 50 Hz) on the decade grid:
    f_0 within 5 % and the amplitude within 0.1 deg/h (seeds 5-8 gave 0.02 Hz and
    1.986-2.010, by WLS and by GLS alike).  The covariance model gives a deterministic
    term no variance of its own, so f_0's standard error is too small
    (fogts.allan.noise_extra) and the tolerances are absolute.  On the dense grid (10 taus
    per decade) the WLS fit lands on the sub-harmonic 0.01 Hz in seeds 5, 6 and 8, GLS
    on 0.02 Hz (tests/README.md, known limitations)."""
    run = fogts.simulate_gyro({"N": 0.01, "Omega_0": 2.0, "f_0": 0.02}, fs_hz=50,
                              duration_s=3600, rng=seed)
    res = fogts.allan_deviation(run, taus="decade")
    model = _fit(res, terms="N,S")
    (s,) = model.extra_terms
    assert s.significant
    assert s.parameter == pytest.approx(0.02, rel=0.05)
    assert abs(s.amplitude - 2.0) < 0.1


def test_adis16405_x_markov_takes_the_short_tau_roll_off() -> None:
    """ADIS16405 run 1 X: the five-term fit is 0.949-0.975x the data at 0.08-2.56 s.  With
    M the ratio there is within 1 % of 1, but T_c sits at the lower edge of its search
    range (half the sample interval): M describes the roll-off at the shortest taus (a
    sampling filter), which is what bent the five-term fit.  From 0.08 s on, M finds a
    slow process instead (T_c about 160 s) that takes part of B."""
    run = fogts.read_run(shared_path("imu", "adis_16405_imu1_gyro.npz"), units="deg/s")
    res = fogts.allan_deviation(run, axis=0)
    mid = (res.tau_s >= 0.08) & (res.tau_s <= 2.56)
    five = check_fit(res, _fit(res))
    assert 0.94 < five.ratio[mid].min() < five.ratio[mid].max() < 0.98
    with_m = _fit(res, terms="Q,N,B,K,R,M")
    (m,) = with_m.extra_terms
    ratio = check_fit(res, with_m).ratio[mid]
    assert 0.99 < ratio.min() and ratio.max() < 1.01
    assert m.at_edge and m.parameter == pytest.approx(0.005, rel=1e-3)
    assert m.significant and "at the edge" in m.describe()
    ranged = _fit(res, terms="Q,N,B,K,R,M", tau_range=(0.08, None))
    (slow,) = ranged.extra_terms
    assert not slow.at_edge and 100 < slow.parameter < 250 and slow.significant


def test_the_cli_reports_the_term_and_its_test(tmp_path: Path) -> None:
    out = tmp_path / "m.json"
    result = CliRunner().invoke(app, ["allan", str(EXAMPLE), "--terms", "N,B,K,M",
                                      "--json", str(out)])
    assert result.exit_code == 0, result.output
    data = json.loads(out.read_text())
    block = data["noise_fit"]["extra_terms"]["M"]
    assert block["df"] == 2 and block["significant"] is False
    assert set(data["noise"]) == {"N", "B", "K"}  # the terms table keeps its five-term keys
    plain = CliRunner().invoke(app, ["allan", str(EXAMPLE), "--terms", "N,B,K,M"])
    assert "adding M (first-order Markov (correlated) noise): chi2 drop" in plain.output


def test_too_few_taus_for_the_extra_parameters() -> None:
    res = fogts.allan_deviation(fogts.read_run(EXAMPLE)).within(1.0, 8.0)
    with pytest.raises(InsufficientDataError,
                       match=r"3 usable taus \(1\.6, 3\.2, 6\.4 s\), fewer than the 5 parameters of the terms "
                             r"requested \(N, B, K, M\)"):
        fogts.fit_noise(res, terms="N,B,K,M")


def test_markov_and_sinusoid_terms_are_refused_on_an_accelerometer_curve() -> None:
    """The M and S closed forms and their units are those of a gyro's rate (deg/h)."""
    import numpy as np

    x = 1e-3 * np.random.default_rng(1).standard_normal(20_000)
    curve = fogts.allan_deviation(x, fs_hz=100.0, units="m/s^2")
    with pytest.raises(fogts.DataError, match=r"terms M .* gyro rate curves only; this curve "
                                              r"is in 'm/s\^2'"):
        fogts.fit_noise(curve, terms="N,B,K,M")
