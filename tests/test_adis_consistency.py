"""The six-run ADIS16405 consistency study (``benchmarks/accuracy/adis_consistency.py``,
issue 15): the chi-square machinery on hand-checkable cases, and a small rerun on the real
data (axis X, WLS and GMWM, all six runs; the full table, with ML and the other axes, is in
tests/README.md).
"""

from __future__ import annotations

import math

import pytest
from scipy.special import erfc

from benchmarks.accuracy.adis_consistency import (
    RUNS,
    adis_path,
    consistency,
    markdown,
    study,
    summarise,
)
from tests.conftest import shared_path


def test_three_unit_weight_estimates_by_hand() -> None:
    """x = 1, 2, 3 with s = 1: mean 2, its se 1/sqrt(3), chi2 = 1 + 0 + 1 = 2 on 2 dof,
    p = exp(-chi2 / 2) = exp(-1) (the chi2_2 tail).  Tolerance 1e-12: a few roundings."""
    c = consistency([1.0, 2.0, 3.0], [1.0, 1.0, 1.0])
    assert (c.k, c.dof) == (3, 2)
    assert c.mean == pytest.approx(2.0, rel=1e-12)
    assert c.mean_se == pytest.approx(1.0 / math.sqrt(3.0), rel=1e-12)
    assert c.chi2 == pytest.approx(2.0, rel=1e-12)
    assert c.p_value == pytest.approx(math.exp(-1.0), rel=1e-12)
    assert c.birge == pytest.approx(1.0, rel=1e-12)


def test_two_unequal_estimates_by_hand() -> None:
    """x = 0, 3 with s = 1, 2: weights 1, 1/4, mean 0.75 / 1.25 = 0.6, and for two
    estimates chi2 = (x1 - x2)^2 / (s1^2 + s2^2) = 9 / 5; on 1 dof
    p = erfc(sqrt(chi2 / 2)).  Tolerance 1e-12: a few roundings."""
    c = consistency([0.0, 3.0], [1.0, 2.0])
    assert c.mean == pytest.approx(0.6, rel=1e-12)
    assert c.mean_se == pytest.approx(1.0 / math.sqrt(1.25), rel=1e-12)
    assert c.chi2 == pytest.approx(1.8, rel=1e-12)
    assert c.p_value == pytest.approx(erfc(math.sqrt(0.9)), rel=1e-10)


def test_estimates_without_a_usable_stderr_are_left_out() -> None:
    c = consistency([1.0, 5.0, 7.0], [1.0, math.nan, 0.0])
    assert (c.k, c.dof) == (1, 0) and c.mean == pytest.approx(1.0, rel=1e-12)
    assert math.isnan(c.p_value) and math.isnan(c.birge)
    assert consistency([], []).k == 0


def _row(run: int, value: float, stderr: float, limit: bool = False) -> dict[str, object]:
    return {"run": run, "axis": "X", "method": "wls", "term": "K", "value": value,
            "stderr": stderr, "limit": limit, "upper": 9.0 if limit else math.nan,
            "seconds": 0.1, "model": "N + B"}


def test_upper_limits_are_listed_and_left_out_of_the_chi2() -> None:
    """Runs 1-3 measure K (1, 2, 3 ± 1), runs 4-6 only bound it: chi2 = 2 on 2 dof, the
    limits shown as '< 9' in the per-run table and not counted in k."""
    rows = [_row(1, 1.0, 1.0), _row(2, 2.0, 1.0), _row(3, 3.0, 1.0),
            *(_row(r, 0.0, math.nan, limit=True) for r in (4, 5, 6))]
    c = summarise(rows)[("X", "K", "wls")]
    assert (c.k, c.dof) == (3, 2) and c.chi2 == pytest.approx(2.0, rel=1e-12)
    text = markdown(rows)
    assert "| X | K | 2 ± 0.58 (3) | 2 (2) / 0.37 | 1 |" in text
    assert "| X | K | WLS | 1 ± 1 | 2 ± 1 | 3 ± 1 | < 9 | < 9 | < 9 |" in text


def test_all_limits_give_no_chi2() -> None:
    rows = [_row(r, 0.0, math.nan, limit=True) for r in RUNS]
    assert summarise(rows)[("X", "K", "wls")].k == 0
    assert "| X | K | all limits | – | – |" in markdown(rows)


@pytest.fixture(scope="module")
def x_rows() -> list[dict[str, object]]:
    for r in RUNS:
        shared_path("imu", adis_path(r).name)  # skips, with the reason, without the data
    return study(RUNS, axes=("X",), methods=("wls", "gmwm"))


def test_the_study_runs_on_the_six_recordings(x_rows: list[dict[str, object]]) -> None:
    """Axis X of the six runs, WLS and GMWM: one row per run, method and term; WLS's N is
    the real-sensor table's (tests/README.md, printed to 4 digits: rel. 1e-3), and the
    chi2 is the hand formula over the runs that measure the term."""
    assert len(x_rows) == 6 * 2 * 3
    wls_n = {r["run"]: r for r in x_rows if (r["method"], r["term"]) == ("wls", "N")}
    published = {1: (2.306, 0.046), 2: (2.282, 0.046), 3: (2.343, 0.052),
                 4: (2.35, 0.052), 5: (2.453, 0.075), 6: (2.327, 0.045)}
    for run, (value, stderr) in published.items():
        assert not wls_n[run]["limit"]
        assert wls_n[run]["value"] == pytest.approx(value, rel=1e-3)
        assert wls_n[run]["stderr"] == pytest.approx(stderr, rel=2e-2)  # 2 digits printed
    summary = summarise(x_rows)
    for key, c in summary.items():
        sel = [r for r in x_rows if (r["axis"], r["term"], r["method"]) == key
               and not r["limit"]]
        assert c.k == len(sel)
        if c.k < 2:
            continue
        w = [1.0 / float(r["stderr"]) ** 2 for r in sel]  # type: ignore[arg-type]
        x = [float(r["value"]) for r in sel]  # type: ignore[arg-type]
        mean = sum(wi * xi for wi, xi in zip(w, x, strict=True)) / sum(w)
        chi2 = sum(wi * (xi - mean) ** 2 for wi, xi in zip(w, x, strict=True))
        assert c.chi2 == pytest.approx(chi2, rel=1e-9)  # summation order only
        assert 0.0 <= c.p_value <= 1.0
    text = markdown(x_rows)
    assert "| X | N | WLS | 2.306 ± 0.046 |" in text and "GMWM χ² (dof) / p" in text


def test_a_measured_value_without_a_usable_stderr_is_shown_as_left_out() -> None:
    """A fit that reports a measured term with standard error 0 (seen: ML, ADIS16405 run 4
    Z, B) cannot enter the chi2; the per-run table says so."""
    rows = [_row(1, 1.0, 1.0), _row(2, 2.0, 0.0), _row(3, 3.0, 1.0)]
    assert summarise(rows)[("X", "K", "wls")].k == 2
    assert "| 2 ± 0 (left out) |" in markdown(rows)
