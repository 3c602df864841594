"""`fogts davar`: the window's minimum length, the same as the HTML report's."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pandas as pd
from typer.testing import CliRunner

from fogts.allan.dynamic import MIN_WINDOW_SAMPLES
from fogts.cli import app
from fogts.report.html import DAVAR_MIN_WINDOW_SAMPLES
from tests.conftest import error_output

runner = CliRunner()


def test_a_window_below_the_minimum_is_refused_naming_the_option(tmp_path: Path) -> None:
    """audit: davar accepted a 5-sample window (two octave taus) while the report asks for
    256 samples per window: one minimum for both, and the error names --window, the value
    and the minimum; a window of exactly the minimum runs."""
    assert MIN_WINDOW_SAMPLES == DAVAR_MIN_WINDOW_SAMPLES == 256
    path = tmp_path / "g.csv"
    rate = np.random.default_rng(4).standard_normal(3000)
    pd.DataFrame({"time": np.arange(rate.size, dtype=float), "rate_deg_h": rate}
                 ).to_csv(path, index=False)
    res = runner.invoke(app, ["davar", str(path), "--window", "5s", "--step", "5s"])
    assert res.exit_code == 2, res.output
    assert error_output(res.stderr) == ("error: --window 5 s is 5 sample(s) at 1 Hz; a window "
                                        "needs at least 256 samples (256 s at 1 Hz)")
    res = runner.invoke(app, ["davar", str(path), "--window", "256s", "--step", "100s"])
    assert res.exit_code == 0, res.output
