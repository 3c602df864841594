"""The noise fit over a tau range (fit_noise(tau_range=...), fogts allan --fit-tau-min/max)."""

from __future__ import annotations

import json
from pathlib import Path

import pytest
from typer.testing import CliRunner

import fogts
from fogts.cli import app
from fogts.errors import DataError
from tests.conftest import error_output, shared_path

EXAMPLE = Path(__file__).resolve().parents[2] / "data" / "example_fog_10hz_3h.csv"


def test_adis16405_x_without_the_shortest_taus() -> None:
    """The issue's hand-made experiment (first three taus dropped: N = 2.401 +- 0.012,
    B = 29.3, K = 51) as an option; tolerance 1e-3 relative (published to 4 digits)."""
    run = fogts.read_run(shared_path("imu", "adis_16405_imu1_gyro.npz"), units="deg/s")
    res = fogts.allan_deviation(run, axis=0)
    with pytest.warns(fogts.errors.FogtsWarning):
        model = fogts.fit_noise(res, tau_range=(0.08, None))
    assert model.tau_s[0] == pytest.approx(0.08)
    assert model["N"].value == pytest.approx(2.401, rel=1e-3)
    assert model["N"].stderr == pytest.approx(0.012, rel=0.05)
    assert model["B"].value == pytest.approx(29.3, rel=2e-3)
    assert model["K"].value == pytest.approx(51.3, rel=2e-3)


def test_within_keeps_the_points_in_range() -> None:
    res = fogts.allan_deviation(fogts.read_run(EXAMPLE))
    part = res.within(1.0, 100.0)
    assert part.tau_s.min() >= 1.0 and part.tau_s.max() <= 100.0
    assert part.m.size == part.dev.size == part.edf.size == part.tau_s.size
    with pytest.raises(DataError, match="tau_min < tau_max, got tau_min = 5 s and tau_max = 1 s"):
        res.within(5.0, 1.0)


def test_a_range_with_too_few_points_is_refused() -> None:
    res = fogts.allan_deviation(fogts.read_run(EXAMPLE))
    with pytest.raises(DataError, match="holds 2 tau\\(s\\); 5 terms need at least 6"):
        fogts.fit_noise(res, tau_range=(1000.0, None))
    with pytest.raises(DataError, match="tau_min must be a finite number > 0"):
        fogts.fit_noise(res, tau_range=(-1.0, None))


def test_cli_fit_range_in_the_json(tmp_path: Path) -> None:
    out = tmp_path / "a.json"
    res = CliRunner().invoke(app, ["allan", str(EXAMPLE), "--fit-tau-min", "1", "--json",
                                   str(out)])
    assert res.exit_code == 0, res.stderr
    doc = json.loads(out.read_text())
    assert doc["fit_range"] == [1.0, None] and doc["fit_check"]["ok"] is True
    assert "taus 1.6..3277 s" in res.stdout  # the octave grid's first tau >= 1 s is 1.6 s


@pytest.mark.parametrize(("args", "message"), [
    (["--fit-tau-min", "100", "--fit-tau-max", "10"],
     "error: the tau range must have --fit-tau-min < --fit-tau-max, got --fit-tau-min = 100 s"),
    (["--fit-tau-min", "1000"], "error: the fit range --fit-tau-min = 1000 s"),
    (["--fit-tau-min", "-1"], "error: --fit-tau-min must be a finite number > 0, got -1.0"),
])
def test_cli_bad_fit_range_names_the_option(args: list[str], message: str) -> None:
    res = CliRunner().invoke(app, ["allan", str(EXAMPLE), *args])
    assert res.exit_code == 2
    assert error_output(res.stderr).startswith(message)
