"""fogts.pipeline: the one analysis chain behind allan, select, batch and the report."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pandas as pd
import pytest
from typer.testing import CliRunner

from fogts.cli import app
from fogts.pipeline import (
    AllanSettings,
    ReadSettings,
    SelectSettings,
    analyse_allan,
    analyse_allan_axis,
    analyse_selection,
    load,
)
from fogts.report.text import json_dumps

EXAMPLE = Path(__file__).resolve().parents[1] / "data" / "example_fog_10hz_3h.csv"


@pytest.mark.parametrize(("text", "expected"), [
    (None, None), ("", None), ("gyro_x", "gyro_x"), ("a, b,c", ["a", "b", "c"]), ("a,", "a")])
def test_rate_columns_are_split_at_commas(text: str | None, expected: object) -> None:
    assert ReadSettings(rate_column=text).rate_columns == expected


def test_allan_analysis_is_what_fogts_allan_writes(tmp_path: Path) -> None:
    """The CLI's JSON is the pipeline's to_dict() and its summary rows, number for number."""
    from fogts.report.summary import summary_rows

    out = tmp_path / "a.json"
    res = CliRunner().invoke(app, ["allan", str(EXAMPLE), "--json", str(out)])
    assert res.exit_code == 0, res.stderr
    run, quality = load(EXAMPLE)
    analysis = analyse_allan(run, quality)
    mine = json.loads(json_dumps({**analysis.to_dict(), "summary": summary_rows([analysis])}))
    assert mine == json.loads(out.read_text())


def test_selection_is_what_fogts_select_writes(tmp_path: Path) -> None:
    out = tmp_path / "s.json"
    res = CliRunner().invoke(app, ["select", str(EXAMPLE), "--decimate", "10", "--json",
                                   str(out)])
    assert res.exit_code in (0, 1), res.stderr
    run, quality = load(EXAMPLE)
    mine = analyse_selection(run, quality, 0, SelectSettings(decimate=10), file=str(EXAMPLE))
    assert json.loads(json_dumps(mine.to_dict())) == json.loads(out.read_text())


def test_preparation_is_applied_and_reported() -> None:
    rng = np.random.default_rng(5)
    x = rng.normal(size=20_000)
    x[100] = 80.0
    frame = pd.DataFrame({"time": np.arange(x.size) / 10.0, "rate_deg_h": x})
    from fogts.io.reader import read_run

    run = read_run(frame)
    axis = analyse_allan_axis(run, 0, AllanSettings(outliers=8.0))
    assert axis.prepared is not None and axis.prepared.outliers is not None
    assert axis.prepared.outliers.count == 1
    assert axis.outliers_effect is not None and axis.outliers_effect["replaced"] == 1
    assert any("replaced 1 of 20,000" in note for note in axis.notes)
    # AllanSettings' keyword; the command line's --outliers 8: tests/cli/test_hygiene.py
    assert axis.outliers_effect["text"].startswith("outliers=8: replaced 1 of 20,000 samples")
    block = axis.to_dict()
    assert block["preprocessing"] is not None and "outliers_effect" in block


def test_a_non_fittable_estimator_has_no_model_and_says_why() -> None:
    run, _ = load(EXAMPLE)
    with pytest.warns(UserWarning, match="fitted to adev, oadev or totdev curves only"):
        axis = analyse_allan_axis(run, 0, AllanSettings(kind="mdev"))
    assert axis.model is None and axis.plausibility is None
    assert axis.to_dict()["noise_fit"]["skipped"].endswith("not mdev")
