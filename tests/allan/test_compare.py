"""Tests for fogts.allan.compare and the `fogts filter --method iir|moving-average` CLI."""

from __future__ import annotations

import json
import warnings
from pathlib import Path

import numpy as np
import pandas as pd
import pytest
from typer.testing import CliRunner

import fogts
from fogts.allan.compare import compare_allan
from fogts.cli import app
from fogts.errors import DataError
from fogts.preprocess.filters import lowpass
from tests.conftest import error_output, shared_path

FS = 100.0
runner = CliRunner()


def _white_plus_rrw(n: int = 200_000, seed: int = 7) -> np.ndarray:
    rng = np.random.default_rng(seed)
    return rng.normal(size=n) + np.cumsum(rng.normal(scale=1e-3, size=n))


@pytest.fixture(scope="module")
def comparison():  # type: ignore[no-untyped-def]
    x = _white_plus_rrw()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return compare_allan(x, lowpass(x, fs_hz=FS, cutoff_hz=1.0).filtered, fs_hz=FS,
                             cutoff_hz=1.0)


def test_filter_lowers_short_tau_and_keeps_long_tau(comparison) -> None:  # type: ignore[no-untyped-def]
    before, after = comparison.before, comparison.after
    ratio = comparison.dev_ratio()
    # tau = 0.01 s: white noise of unit variance low-passed at 1 Hz keeps ~1 % of sigma
    assert ratio[0] < 0.05
    long = before.tau_s >= 10.0  # tau >> 1/cutoff = 1 s
    half_ci = (before.ci_high - before.ci_low)[long] / 2
    assert np.all(np.abs(after.dev[long] - before.dev[long]) < half_ci)
    assert np.allclose(ratio[before.tau_s >= 50.0], 1.0, atol=2e-3)


def test_terms_above_cutoff_unchanged(comparison) -> None:  # type: ignore[no-untyped-def]
    assert comparison.fit_min_tau_s == 3.0
    assert not any(c.significant for c in comparison.changes)
    k = next(c for c in comparison.changes if c.term == "K")
    assert abs(k.change_pct) < 1.0
    d = comparison.to_dict()
    assert set(d["terms"]) == {"Q", "N", "B", "K", "R"} and "1/cutoff" in d["caveat"]


def test_full_range_fit_shows_the_artefact() -> None:
    # Fitting the filtered curve at tau < 1/cutoff is what the caveat warns about: the
    # ARW term "drops" (as the Allan-variance review of optical gyros reads its IIR denoising
    # study) because the filter removed it, not the sensor.
    x = _white_plus_rrw(100_000, 3)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        cmp = compare_allan(x, lowpass(x, fs_hz=FS, cutoff_hz=1.0).filtered, fs_hz=FS,
                            cutoff_hz=1.0, fit_min_tau_s=0.0, terms=("N", "K"))
    n = next(c for c in cmp.changes if c.term == "N")
    assert n.significant and n.after < 0.5 * n.before


def test_compare_bad_input() -> None:
    with pytest.raises(DataError, match="equal length"):
        compare_allan(np.zeros(10), np.zeros(11), fs_hz=1.0)
    x = _white_plus_rrw(5000)
    with pytest.raises(DataError, match="fit_min_tau_s=1000 s leaves 0 taus"):
        compare_allan(x, x, fs_hz=FS, fit_min_tau_s=1000.0)


@pytest.fixture
def record(tmp_path: Path) -> Path:
    x = _white_plus_rrw(60_000, 11)
    f = tmp_path / "run.csv"
    pd.DataFrame({"time": np.arange(x.size) / FS, "rate": x}).to_csv(f, index=False)
    return f


def test_cli_iir_compare(record: Path, tmp_path: Path) -> None:
    out, js, png = tmp_path / "f.csv", tmp_path / "f.json", tmp_path / "cmp.png"
    res = runner.invoke(app, ["filter", str(record), "--method", "iir", "--cutoff", "2",
                              "-o", str(out), "--compare-allan", "--json", str(js),
                              "--plot", str(png)])
    assert res.exit_code == 0, res.output
    assert "unchanged (within 2 sigma)" in res.stdout and "1/cutoff" in res.stdout
    frame = pd.read_csv(out)
    assert list(frame.columns) == ["time", "observed", "filtered"] and len(frame) == 60_000
    payload = json.loads(js.read_text())
    assert payload["filter"]["cutoff_hz"] == 2.0 and "compare_allan" in payload
    assert png.stat().st_size > 10_000


def test_cli_moving_average(record: Path, tmp_path: Path) -> None:
    res = runner.invoke(app, ["filter", str(record), "--method", "moving-average", "--window",
                              "0.5", "-o", str(tmp_path / "m.csv")])
    assert res.exit_code == 0, res.output
    assert "moving-average" in res.stdout


@pytest.mark.parametrize(("args", "message"), [
    (["--method", "iir", "--cutoff", "50"], "--cutoff must be below the Nyquist frequency 50 Hz"),
    (["--method", "iir", "--cutoff", "80"], "--cutoff must be below the Nyquist frequency"),
    (["--method", "iir", "--cutoff", "2", "--order", "0"], "order must be >= 1, got 0"),
    (["--method", "iir", "--cutoff", "2", "--order", "-3"], "order must be >= 1, got -3"),
    (["--method", "iir"], "--method iir needs --cutoff HZ"),
    (["--method", "iir", "--cutoff", "2", "--design", "bessel"], "'bessel' is not one of 'butter'"),
    (["--method", "moving-average"], "needs --window SECONDS"),
    (["--method", "iir", "--cutoff", "2", "--plot", "x.png"], "add --compare-allan"),
    (["--method", "wiener"], "'wiener' is not one of 'kalman', 'iir', 'moving-average'"),
])
def test_cli_filter_errors(record: Path, tmp_path: Path, args: list[str], message: str) -> None:
    res = runner.invoke(app, ["filter", str(record), "-o", str(tmp_path / "o.csv"), *args])
    assert res.exit_code == 2
    lines = error_output(res.stderr).splitlines()
    assert len(lines) == 1 and lines[0].startswith("error: ") and message in lines[0]
    assert not (tmp_path / "o.csv").exists()  # nothing written on error


def test_summary_columns_and_verdicts_follow_the_numbers(comparison) -> None:  # type: ignore[no-untyped-def]
    """A label longer than the column (the CLI's "moving-average filtered") keeps a space
    before it; a term that is an upper limit on both sides is "not measured", not
    "unchanged" (ADIS16405 run 1 X: Q, K, R printed "0  0  +0.0%  unchanged")."""
    import dataclasses

    long = dataclasses.replace(comparison, labels=("raw", "moving-average filtered"))
    header = long.summary().splitlines()[0]
    assert "raw  moving-average filtered" in header
    rows = {line.split()[0]: line for line in long.summary().splitlines()[1:6]}
    for c in comparison.changes:
        measured = not (comparison.noise_before[c.term].is_limit
                        and comparison.noise_after[c.term].is_limit)
        assert rows[c.term].endswith("not measured (an upper limit before and after)") \
            is not measured
    # white noise plus a random walk: N is measured on both sides, Q (absent) on neither
    assert rows["N"].endswith("unchanged (within 2 sigma)")
    assert rows["Q"].endswith("not measured (an upper limit before and after)")


def test_a_limit_is_printed_as_a_bound_not_as_a_value() -> None:
    """audit3: `fogts filter` on the first 10 min of ADIS run 1 (X, deg/s) with --method iir
    --cutoff 1 --compare-allan printed `B deg/h 35.03 ± 10  35.42 ± 10  +1.1%  not
    measured (an upper limit before and after)`: a value and a change for a term its own
    verdict calls a bound.  The cells now give the 95 % upper limits, the change '–'."""
    run = fogts.read_run(shared_path("imu", "adis_16405_imu1_gyro.npz"), units="deg/s")
    x = np.asarray(run.rate[:60_000, 0])
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        cmp = compare_allan(x, lowpass(x, fs_hz=FS, cutoff_hz=1.0).filtered, fs_hz=FS,
                            units="deg/s", cutoff_hz=1.0)
    b = cmp.noise_before["B"]
    assert b.value > 0 and b.is_limit and cmp.noise_after["B"].is_limit
    rows = {line.split()[0]: line for line in cmp.summary().splitlines()[1:6]}
    limit = f"< {cmp.noise_before.upper_limit('B'):.3g}"
    assert limit in rows["B"] and "±" not in rows["B"] and "%" not in rows["B"]
    assert rows["B"].endswith("not measured (an upper limit before and after)")
    assert "±" in rows["N"] and "%" in rows["N"]  # N is measured: value and change stay
