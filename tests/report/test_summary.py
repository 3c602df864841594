"""The one-page summary (fogts.report.summary): rows per file and axis in the chosen units,
limits shown as '< x', the fit verdict and PASS/FAIL against a spec."""

from __future__ import annotations

import warnings
from pathlib import Path

import pytest

from fogts.allan.datasheet import NoiseSpec
from fogts.pipeline import AllanAnalysis, analyse_allan, load
from fogts.report.summary import SUMMARY_TERMS, summary_rows, summary_table
from fogts.units import TERM_SI_FACTOR

EXAMPLE = Path(__file__).resolve().parents[2] / "data" / "example_fog_10hz_3h.csv"


@pytest.fixture(scope="module")
def analysis() -> AllanAnalysis:
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return analyse_allan(*load(EXAMPLE))


def test_rows_carry_the_model_in_the_chosen_units(analysis: AllanAnalysis) -> None:
    model = analysis.axes[0].model
    assert model is not None
    deg, si = summary_rows([analysis])[0], summary_rows([analysis], "si")[0]
    assert deg["file"] == EXAMPLE.name and deg["axis"] == analysis.axes[0].result.axis
    for t in SUMMARY_TERMS:
        assert deg[f"{t}_unit"] == model[t].unit
        assert si[t] == pytest.approx(model[t].value * TERM_SI_FACTOR[t], rel=1e-12)
    assert si["N_unit"] == "rad/s/sqrt(Hz)" and si["K_unit"] == "rad/s^2/sqrt(Hz)"
    # K is only bounded in this record: its upper limit, and no spec verdict without a spec
    assert deg["K_upper"] == pytest.approx(model.upper_limit("K"), rel=1e-12)
    assert deg["N_upper"] is None and deg["N_spec"] is None
    assert deg["fit"] == ("ok" if analysis.axes[0].fit_check.ok else "misses")  # type: ignore[union-attr]


def test_table_shows_values_limits_and_spec(analysis: AllanAnalysis) -> None:
    model = analysis.axes[0].model
    assert model is not None
    spec = NoiseSpec.from_mapping({"N": model["N"].value * 0.5, "K": 1e3}, source="ds.yaml")
    rows = summary_rows([analysis, analysis], spec=spec)
    table = summary_table(rows, spec)
    assert table.titles == ["file", "axis", "N (deg/sqrt(h))", "B (deg/h)", "K (deg/h^1.5)",
                            "fit", "N spec", "K spec"]
    cells = table.cells()
    assert len(cells) == 2
    n, se = model["N"].value, model["N"].stderr  # below 0.01: exponent form, 4 and 2 digits
    assert n < 0.01 and cells[0][2] == f"{n:.3e} ± {se:.1e}"
    assert cells[0][4] == f"< {model.upper_limit('K'):.3g}"
    assert cells[0][6:] == ["FAIL", "PASS"] and (0, 6) in table.failed
    assert "ds.yaml: N ≤ " in table.caption and "only as an upper limit passes only" in \
        table.caption


def test_mixed_units_go_into_the_cells() -> None:
    """Rows whose terms have different units (files analysed apart) name the unit per cell."""
    base = {"file": "a", "axis": "x", "fit": None}
    for t in SUMMARY_TERMS:
        base |= {t: 1.0, f"{t}_stderr": 0.1, f"{t}_upper": None, f"{t}_unit": "deg/h",
                 f"{t}_spec": None}
    other = {**base, "file": "b", "N_unit": "rad/s", "N": 0.0, "N_upper": 2e-6}
    table = summary_table([base, other])
    assert table.titles[2] == "N" and table.titles[3] == "B (deg/h)"
    assert [r[2] for r in table.cells()] == ["1 ± 0.1 deg/h", "< 2.00e-06 rad/s"]
    assert table.cells()[0][5] == "not checked"


def _imu_csv(path: Path) -> Path:
    """10 Hz, 40 min: a gyro axis in deg/h and an accelerometer triad in g (|mean| = 1)."""
    import numpy as np
    import pandas as pd

    rng = np.random.default_rng(12)
    n = 24_000
    pd.DataFrame({"time": np.arange(n) / 10.0, "gyro_x_deg_h": rng.normal(0, 1.0, n),
                  "acc_x": rng.normal(0, 1e-3, n), "acc_y": rng.normal(0, 1e-3, n),
                  "acc_z": 1.0 + rng.normal(0, 1e-3, n)}).to_csv(path, index=False)
    return path


def test_accelerometer_rows_carry_accelerometer_units(tmp_path: Path) -> None:
    """The summary labelled an accelerometer axis' N, B, K in deg/sqrt(h), deg/h and
    deg/h^1.5 (CH104's accReading axes, in `fogts allan` and in the batch CSV) while the
    values were in m/s/sqrt(h), ug and m/s/h^1.5, as the term table says."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        analysis = analyse_allan(*load(_imu_csv(tmp_path / "imu.csv")))
    rows = summary_rows([analysis])
    units = {r["axis"]: (r["N_unit"], r["B_unit"], r["K_unit"]) for r in rows}
    assert units["gyro_x_deg_h"] == ("deg/sqrt(h)", "deg/h", "deg/h^1.5")
    for acc in ("acc_x", "acc_y", "acc_z"):
        assert units[acc] == ("m/s/sqrt(h)", "ug", "m/s/h^1.5")
    acc_z = next(ax for ax in analysis.axes if ax.result.axis == "acc_z")
    assert acc_z.model is not None
    row = next(r for r in rows if r["axis"] == "acc_z")
    assert row["N_unit"] == acc_z.model.in_units("N", "deg")["unit"]
    assert next(r for r in summary_rows([analysis], "si")
                if r["axis"] == "acc_z")["N_unit"] == "m/s^2/sqrt(Hz)"
    text = summary_table(rows).to_text()
    assert "m/s/sqrt(h)" in text and "deg/sqrt(h)" in text  # mixed: the unit in each cell
    assert "(accelerometer axes: N velocity random walk" in text
    gyro_only = [r for r in rows if r["axis"] == "gyro_x_deg_h"]
    assert "accelerometer axes" not in summary_table(gyro_only).to_text()
