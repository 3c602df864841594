"""GMWM: a Gauss-Markov component whose correlation time is below
:data:`~fogts.allan.gmwm_result.GM_MIN_TC_SAMPLES` sample periods is white noise at the
data taus, not bias instability; it stays in the fit but not in the flicker-equivalent B,
and with no other component B is an upper limit that says why (fogts.allan.gmwm, "Which
components count toward B").  And the summary's fit cell of a GMWM fit carries its J test.
"""

from __future__ import annotations

import json
import math
import warnings
from pathlib import Path
from types import SimpleNamespace

import numpy as np
import pytest
from typer.testing import CliRunner

import fogts
from fogts.allan import allan_deviation
from fogts.allan.gmwm import counted_in_b, fit_gmwm
from fogts.allan.gmwm_core import Composite
from fogts.allan.gmwm_result import GM_MIN_TC_SAMPLES
from fogts.allan.noise import NoiseModel
from fogts.allan.noise_selection import identify_terms
from fogts.cli import app
from fogts.report.summary import J_REJECTS, axis_row, summary_table
from fogts.simulate.gyro import simulate_gyro
from tests.conftest import shared_path

FS_HZ = 10.0


def _gmwm(curve: object) -> NoiseModel:
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return fit_gmwm(curve)


def test_counted_in_b_is_the_correlation_time_against_the_sample_period() -> None:
    model = Composite((-1,), 2)
    dt = 0.1
    theta = np.array([0.0, 0.0, math.log(dt), 0.0, math.log(GM_MIN_TC_SAMPLES * dt)])
    assert counted_in_b(theta, model, dt) == (False, True)


def test_a_gm_at_the_sample_period_is_not_bias_instability() -> None:
    """White + a GM with T_c = one sample period (filtered white noise) + RW, 2 h at 10 Hz:
    GMWM draws the GM (T_c = dt) and, before the rule, reported B = 0.24 deg/h measured
    from it; the WLS fit finds no B.  Now B is an upper limit and its reason names T_c."""
    run = simulate_gyro({"N": 0.01, "K": 1.0, "q_c": 3.0, "T_c": 1.0 / FS_HZ},
                        fs_hz=FS_HZ, duration_s=7200, rng=12)
    m = _gmwm(allan_deviation(run, taus="octave"))
    assert m.gmwm is not None and m.gmwm.gauss_markov
    assert all(g.t_c < GM_MIN_TC_SAMPLES / FS_HZ and not g.in_b for g in m.gmwm.gauss_markov)
    b = m["B"]
    assert b.is_limit and b.value == 0 and b.status == "at_bound"
    assert "below 4 sample periods" in b.limit_reason and b.short_gm
    assert b.to_dict()["measured"] is False and "white noise" in b.to_dict()["limit_reason"]
    assert 0 < m.upper_limit("B") < 0.2
    assert "not counted in B" in m.gmwm.describe()
    assert m.gmwm.to_dict()["gauss_markov"][0]["in_b"] is False


def test_a_gm_bias_instability_stays_measured() -> None:
    """White + RW + a GM with T_c = 30 s (300 sample periods): B measured as before."""
    run = simulate_gyro({"N": 0.01, "K": 1.0, "q_c": 0.3 / math.sqrt(15.0), "T_c": 30.0},
                        fs_hz=FS_HZ, duration_s=7200, rng=12)
    m = _gmwm(allan_deviation(run, taus="octave"))
    assert m.gmwm is not None and all(g.in_b for g in m.gmwm.gauss_markov)
    assert not m["B"].is_limit and m["B"].short_gm == ""
    assert m["B"].value == pytest.approx(0.2135, rel=0.02)


def _adis(run: int) -> fogts.NoiseModel:
    path = shared_path("imu", f"adis_16405_imu{run}_gyro.npz")
    res = fogts.allan_deviation(fogts.read_run(path, units="deg/s"), axis="Gyro. X")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return fogts.fit_noise(res, method="gmwm")


def test_adis_run1_b_leaves_out_the_gm_at_the_sample_period() -> None:
    """ADIS16405 run 1, X (100 Hz): N + 2 GM, GM 1 at T_c = 0.01 s.  Before: B = 91.4 +-
    4.6 deg/h from both GMs, beside WLS 33.7 +- 2.8 and the read-off 33.3; now B comes
    from GM 2 (T_c = 184 s) alone and agrees with them."""
    m = _adis(1)
    assert m.gmwm is not None
    assert [g.in_b for g in m.gmwm.gauss_markov] == [False, True]
    b = m["B"]
    assert not b.is_limit and 25 < b.value < 40


def test_adis_run5_b_is_a_limit_when_the_only_gm_is_at_the_sample_period() -> None:
    """ADIS16405 run 5, X: N + K + 1 GM at T_c = 0.01 s.  Before: B = 262 deg/h measured;
    now an upper limit whose reason says the GM is white noise at the data taus."""
    m = _adis(5)
    b = m["B"]
    assert b.is_limit and b.short_gm and "0.01 s" in b.limit_reason
    assert m.upper_limit("B") < 100


# --------------------------------------------------------------------------- summary


def _axis(consistent: bool | None, ok: bool) -> SimpleNamespace:
    gmwm = None if consistent is None else SimpleNamespace(consistent=consistent)
    model = SimpleNamespace(gmwm=gmwm, quantity="rate", names=())
    return SimpleNamespace(fit_check=SimpleNamespace(ok=ok), model=model,
                           result=SimpleNamespace(units="deg/h", axis="x"))


@pytest.mark.parametrize(("consistent", "ok", "cell"), [
    (None, True, "ok"), (None, False, "misses"), (True, True, "ok"),
    (False, True, J_REJECTS), (False, False, f"misses, {J_REJECTS}")])
def test_summary_fit_cell_carries_the_gmwm_j_test(consistent: bool | None, ok: bool,
                                                  cell: str) -> None:
    row = axis_row("f", _axis(consistent, ok))  # type: ignore[arg-type]
    assert row["fit"] == cell
    table = summary_table([row])
    assert (J_REJECTS in table.caption) == (consistent is False)
    assert bool(table.failed) == (cell != "ok")


def test_mpu6050_summary_says_the_j_test_rejects(tmp_path: Path) -> None:
    """mpu6050 gyro_x: GMWM J = 24.4 on 13 dof, p = 0.028, rejected, yet the summary's fit
    cell said 'ok' (the model within the points' intervals)."""
    path = shared_path("imu", "mpu6050_gyro_temp_converted.csv.gz")
    out = tmp_path / "mpu.json"
    res = CliRunner().invoke(app, ["allan", str(path), "--method", "gmwm", "--json", str(out)])
    assert res.exit_code == 0, res.stderr
    assert "J rejects': a GMWM fit whose J test rejects" in " ".join(res.stdout.split())
    d = json.loads(out.read_text())
    rows = {r["axis"]: r for r in d["summary"]}
    assert rows["gyro_x_deg_s"]["fit"] == J_REJECTS
    gmwm = next(a for a in d["axes"] if a["axis"] == "gyro_x_deg_s")["noise_fit"]["gmwm"]
    assert gmwm["consistent"] is False


def test_shares_are_taken_of_the_curve_with_the_uncounted_gm() -> None:
    """identify_terms' ``extra_avar`` (the GMs left out of B) enters the total: a part 1e6
    times the curve leaves every term below 25 % at every tau."""
    m = _gmwm(allan_deviation(simulate_gyro({"N": 0.01, "K": 1.0}, fs_hz=FS_HZ,
                                            duration_s=3600, rng=5), taus="octave"))
    alone, _ = identify_terms(m, m.tau_s)
    assert alone[m.names.index("N")].n_covered > 0
    drowned, _ = identify_terms(m, m.tau_s, lambda t: 1e6 * m.curve(t) ** 2)
    assert all(t.n_covered == 0 for t in drowned)


def test_adis_run5_z_shares_count_the_white_gm() -> None:
    """ADIS16405 run 5, Z: Q + K + 1 GM at T_c = 0.01 s.  Without the GM in the total, Q
    would make up 25 % of it at 9 taus and K at 11 (the white GM is most of the curve);
    with it, Q at most at one and K only beyond 100 s."""
    path = shared_path("imu", "adis_16405_imu5_gyro.npz")
    res = fogts.allan_deviation(fogts.read_run(path, units="deg/s"), axis="Gyro. Z")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        m = fogts.fit_noise(res, method="gmwm")
    assert m["Q"].n_covered <= 1
    assert m["K"].region_tau_s[0] > 50 and m["K"].n_covered <= 6
