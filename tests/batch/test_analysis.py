"""The default per-file analysis: a batch row is the analysis of that one file, and the
per-run JSON holds the documents ``fogts allan --json`` and ``fogts select --json`` write."""

from __future__ import annotations

import json
from pathlib import Path

import pandas as pd
import pytest
from click.testing import Result
from typer.testing import CliRunner

from fogts.batch import BatchOptions, analyze_file, run_key
from fogts.cli import app
from tests.batch.cases import N_SAMPLES


def test_row_equals_single_file_analysis(pool_run: tuple[Path, Result], files: Path) -> None:
    """The batch row is exactly what the analysis of that one file gives, in this process."""
    out, _ = pool_run
    frame = pd.read_csv(out / "summary.csv")
    target = files / "run_03.csv"
    row = frame[frame["file"].map(lambda f: Path(f).name) == "run_03.csv"].iloc[0]
    single = analyze_file(str(target), BatchOptions())
    assert single.status == "ok"
    for col in ("N", "N_stderr", "B", "K", "aic"):
        a, b = single.rows[0][col], row[col]
        assert (a is None and pd.isna(b)) or a == pytest.approx(float(b), rel=1e-12), col
    assert single.rows[0]["selected"] == row["selected"]
    doc = json.loads((out / "json" / run_key(str(target))).read_text())
    assert doc["info"]["n"] == N_SAMPLES and doc["select"][0]["candidates"]


def test_run_json_has_the_shape_of_the_allan_and_select_json(pool_run: tuple[Path, Result],
                                                             files: Path) -> None:
    """The per-run JSON holds, under "allan" and "select", documents of the same shape as
    ``fogts allan --json`` and ``fogts select --json`` on that file."""
    out, _ = pool_run
    target = files / "run_03.csv"
    doc = json.loads((out / "json" / run_key(str(target))).read_text())
    cli = {}
    for command in ("allan", "select"):
        path = out / f"{command}.json"
        res = CliRunner().invoke(app, [command, str(target), "--json", str(path)])
        assert res.exit_code in (0, 1), res.stderr
        cli[command] = json.loads(path.read_text())

    def shape(d: object) -> object:
        if isinstance(d, dict):
            return {k: shape(v) for k, v in d.items() if k not in ("stationarity",)}
        if isinstance(d, list):
            return [shape(v) for v in d[:1]]
        return type(d).__name__ if d is not None else None

    cli["allan"].pop("summary")  # the CLI's table across files: the batch has its rows
    assert shape(doc["allan"]) == shape(cli["allan"])
    # the batch skips the stationarity tests (None): the rest of the preparation is alike
    assert set(doc["select"][0]) == set(cli["select"])
    assert doc["select"][0]["candidates"] == cli["select"]["candidates"]


def test_unreadable_file_is_one_error_row(files: Path) -> None:
    """A file that cannot be read: one row with an empty axis, the message, and a document
    that still records the options."""
    got = analyze_file(str(files / "bad_text.csv"), BatchOptions(select=False))
    assert got.status == "error" and "non-numeric" in got.error and got.persist
    assert len(got.rows) == 1 and got.rows[0]["axis"] == "" and got.rows[0]["error"] == got.error
    assert got.document["rows"] == [got.rows[0]]
    assert got.document["options"]["select"] is False


def test_an_axis_whose_every_candidate_fails_is_an_error_row_with_the_reasons(
        files: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    """Not "internal error (AttributeError)": the row names why the fits failed."""
    import fogts.arma.select as select_module
    from fogts.errors import ModelFitError

    def failing_fit(*args: object, **kwargs: object) -> None:
        raise ModelFitError("optimiser diverged (simulated)")

    monkeypatch.setattr(select_module, "fit_arma", failing_fit)
    outcome = analyze_file(str(files / "run_03.csv"), BatchOptions())
    row = outcome.rows[0]
    assert outcome.status == "error" and row["status"] == "error"
    assert "AttributeError" not in row["error"] and "optimiser diverged" in row["error"]


def test_terms_at_zero_carry_their_upper_limit_in_the_row(files: Path) -> None:
    """White-noise runs: B and K fit to zero, so the row has B_upper and K_upper, and N
    (fitted) has none."""
    row = analyze_file(str(files / "run_03.csv"), BatchOptions(select=False)).rows[0]
    assert row["N_upper"] is None and row["N"] > 0
    zero = [t for t in ("B", "K") if row[t] == 0.0]
    assert zero and all(row[f"{t}_upper"] > 0 for t in zero)


def test_rows_name_each_terms_unit_and_its_spec_verdict(files: Path, tmp_path: Path) -> None:
    """The unit columns name the terms' units (not the input's rate unit, which is
    input_units), in the chosen output units; --spec adds PASS/FAIL per term, and the CLI's
    summary CSV carries them.  B is not measured on this record, so a B limit below its
    95 % upper limit is INCONCLUSIVE, not FAIL (exit 0)."""
    from fogts.allan.datasheet import NoiseSpec
    from fogts.units import TERM_SI_FACTOR

    target = str(files / "run_03.csv")
    deg = analyze_file(target, BatchOptions(select=False)).rows[0]
    spec = NoiseSpec.from_mapping({"N": deg["N"] * 2, "B": 1e-9})
    si = analyze_file(target, BatchOptions(select=False, output_units="si", spec=spec)).rows[0]
    assert deg["input_units"] == si["input_units"] == "deg/h" and "units" not in deg
    assert (deg["N_unit"], deg["B_unit"], deg["K_unit"]) == ("deg/sqrt(h)", "deg/h",
                                                             "deg/h^1.5")
    assert (si["N_unit"], si["B_unit"], si["K_unit"]) == ("rad/s/sqrt(Hz)", "rad/s",
                                                          "rad/s^2/sqrt(Hz)")
    assert si["N"] == pytest.approx(deg["N"] * TERM_SI_FACTOR["N"], rel=1e-12)
    assert (si["N_spec"], si["B_spec"], si["K_spec"]) == ("PASS", "INCONCLUSIVE", None)
    assert deg["N_spec"] is None and deg["fit"] in ("ok", "misses")
    spec_file = tmp_path / "spec.yaml"
    spec_file.write_text(f"N: {deg['N'] * 2}\nB: 1e-9\n")
    out = tmp_path / "summary.csv"
    res = CliRunner().invoke(app, ["batch", target, "-o", str(out), "--no-select",
                                   "--workers", "1", "--spec", str(spec_file),
                                   "--output-units", "si"])
    assert res.exit_code == 0, res.output
    row = pd.read_csv(out).iloc[0]
    assert (row["N_unit"], row["B_spec"], row["N_spec"]) == ("rad/s/sqrt(Hz)", "INCONCLUSIVE",
                                                             "PASS")
    assert row["N"] == pytest.approx(si["N"], rel=1e-12)


def test_accelerometer_rows_name_their_own_input_unit(tmp_path: Path) -> None:
    """A batch row of an accelerometer axis gave the gyro's input unit (CH104 read with
    --units deg/s: accReading rows said deg/s and N in deg/sqrt(h))."""
    import numpy as np

    rng = np.random.default_rng(13)
    n = 12_000
    path = tmp_path / "imu.csv"
    pd.DataFrame({"time": np.arange(n) / 10.0, "gyro_x_deg_s": rng.normal(0, 0.01, n),
                  "acc_z": 1.0 + rng.normal(0, 1e-3, n)}).to_csv(path, index=False)
    out = analyze_file(str(path), BatchOptions(select=False))
    assert out.status == "ok"
    rows = {r["axis"]: r for r in out.rows}
    assert (rows["gyro_x_deg_s"]["input_units"], rows["gyro_x_deg_s"]["units_source"]) == \
        ("deg/s", "column name")
    assert (rows["acc_z"]["input_units"], rows["acc_z"]["units_source"]) == \
        ("g", "gravity magnitude")
    assert rows["acc_z"]["N_unit"] == "m/s/sqrt(h)" and rows["acc_z"]["B_unit"] == "ug"
