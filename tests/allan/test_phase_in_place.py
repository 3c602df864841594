"""The phase formed in the rate's own buffer (fogts.allan.kernels.phase_in_place): only for a
rate given up whose buffer has the spare point in front, the same phase bit for bit, and a
user's array is never touched.

Equality is asserted exactly where both sides run the same floating-point operations in
the same order (the same chunks, only the output memory differs)."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest
from typer.testing import CliRunner

from fogts import allan_deviation
from fogts._validate import finite_sum, known_sums
from fogts.allan import kernels
from fogts.allan.kernels import given_up_buffer, phase_from_rate, phase_in_place
from fogts.cli import app
from fogts.io.reader import read_run
from fogts.pipeline import AllanSettings

N = 5_003


def _rate(n: int = N, seed: int = 3) -> np.ndarray:
    rng = np.random.default_rng(seed)
    return rng.normal(size=n) + 4.0 + np.cumsum(rng.normal(scale=0.01, size=n))


@pytest.mark.parametrize("halves", [False, True])
def test_in_place_phase_equals_the_fresh_one(monkeypatch: pytest.MonkeyPatch,
                                             halves: bool) -> None:
    monkeypatch.setattr(kernels, "CHUNK", 64)
    monkeypatch.setattr(kernels, "HALVES_FROM", 1_000 if halves else N + 1)
    y = _rate()
    fresh = phase_from_rate(y)
    buf = np.empty(N + 1)
    buf[1:] = y
    got = phase_from_rate(buf[1:], out=buf)
    assert got is buf
    assert np.array_equal(got, fresh)


@pytest.mark.parametrize("make", [
    lambda y: y,                                      # owns its memory
    lambda y: np.r_[0.0, 0.0, y][2:],                 # two points in front, not one
    lambda y: np.r_[0.0, y, 0.0][1:-1],               # one point after as well
    lambda y: np.r_[0.0, y].astype(np.float32)[1:],   # not float64
    lambda y: np.r_[0.0, y][1:][::-1],                # not C-contiguous
])
def test_user_arrays_are_never_overwritten(make) -> None:  # type: ignore[no-untyped-def]
    y = make(_rate())
    before = y.copy()
    with phase_in_place(y) as spare:
        assert not spare
        allan_deviation(y, fs_hz=10.0, taus="octave")
    assert np.array_equal(y, before)


def test_a_read_only_buffer_is_not_written() -> None:
    buf = np.r_[0.0, _rate()]
    buf.flags.writeable = False
    with phase_in_place(buf[1:]) as spare:
        assert not spare
        allan_deviation(buf[1:], fs_hz=10.0)
    assert np.array_equal(buf[1:], _rate())


def test_given_up_buffer_is_handed_out_once_and_only_within_the_context() -> None:
    buf = np.r_[0.0, _rate()]
    assert given_up_buffer(buf[1:]) is None
    with phase_in_place(buf[1:]) as spare:
        assert spare
        assert given_up_buffer(np.r_[0.0, _rate()][1:]) is None  # other memory
        assert given_up_buffer(buf[1:]) is buf
        assert given_up_buffer(buf[1:]) is None
    with phase_in_place(buf[1:]):
        pass
    assert given_up_buffer(buf[1:]) is None


def _npy(tmp_path: Path) -> Path:
    path = tmp_path / "r.npy"
    np.save(path, _rate(40_000))
    return path


def test_a_read_rate_given_up_gives_the_same_curve(tmp_path: Path) -> None:
    path = _npy(tmp_path)
    plain_run = read_run(path, fs_hz=50.0)
    plain = allan_deviation(plain_run, taus="octave")
    assert np.array_equal(plain_run.rate, np.load(path))  # not given up: unchanged
    with known_sums():
        run = read_run(path, fs_hz=50.0)
        with phase_in_place(run.rate) as spare:
            assert spare  # the reader leaves the point in front
            spent = allan_deviation(run, taus="octave")
        # the rate now holds its phase, and its recorded sum is forgotten with it
        assert finite_sum(run.rate) == float(np.sum(run.rate))
    assert not np.array_equal(run.rate, np.load(path))
    for field in ("dev", "ci_low", "ci_high", "edf", "alpha", "n"):
        assert np.array_equal(getattr(spent, field), getattr(plain, field)), field


@pytest.mark.parametrize(("settings", "reads"), [
    (AllanSettings(), False),
    (AllanSettings(method="gmwm"), False),
    (AllanSettings(method="wls", compare_methods=("ml",)), True),
    (AllanSettings(method="ml"), True),
    (AllanSettings(check_allantools=True), True),
    (AllanSettings(decimate=4), True),
    (AllanSettings(outliers=5.0), True),
])
def test_which_settings_read_the_rate_after_the_curve(settings: AllanSettings,
                                                      reads: bool) -> None:
    assert settings.reads_rate_after_curve is reads


def test_cli_json_equals_the_library_curve(tmp_path: Path) -> None:
    path = _npy(tmp_path)
    out = tmp_path / "a.json"
    res = CliRunner().invoke(app, ["allan", str(path), "--fs", "50", "--units", "deg/h",
                                   "--json", str(out)])
    assert res.exit_code == 0, res.output
    points = json.loads(out.read_text())["axes"][0]["points"]
    ref = allan_deviation(np.load(path), fs_hz=50.0, units="deg/h", taus="octave")
    assert np.array_equal([p["dev"] for p in points], ref.dev)
    assert np.array_equal([p["ci_low"] for p in points], ref.ci_low)

