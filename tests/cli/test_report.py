"""`fogts report` names the options the user typed where the report's messages suggest a
library keyword (the data-quality findings, the reasons a part was left out), and leaves
the text that comes from the input as it is.  The Python side (``units=``,
``gaps='split'``, ``temperature_column=``) is tests/report/test_sections.py's
``test_input_section_names_the_keywords`` and tests/report/test_html.py's
``test_short_record_without_temperature_omits_davar_and_thermal``."""

from __future__ import annotations

import html
import re
from pathlib import Path

import numpy as np
import pandas as pd
from typer.testing import CliRunner

from fogts.cli import app
from tests.conftest import error_output
from tests.preprocess.test_hygiene import unnamed_gappy_frame

runner = CliRunner()


def test_report_names_the_options_and_keeps_the_input_text(tmp_path: Path) -> None:
    src = tmp_path / "bare.csv"
    src.write_text("# logged with units=deg/s\n" + unnamed_gappy_frame().to_csv(index=False))
    out = tmp_path / "r.html"
    res = runner.invoke(app, ["report", str(src), "-o", str(out)])
    assert res.exit_code == 0, res.stderr
    assert ("not included: Thermal model: the file has no temperature column (name it T or "
            "temperature, or pass --temperature-column)") in res.stdout.splitlines()
    text = html.unescape(out.read_text())
    for said in ("rate unit from</td><td>ASSUMED (no unit in the column names; see Data "
                 "quality)",
                 "assuming deg/h; pass --units (deg/h, deg/s, rad/s, arcsec/s)",
                 "(--gaps split analyses the longest regular segment, --gaps error refuses "
                 "the file)",
                 "kept in the analysis (--outliers K replaces samples beyond K robust sigmas)",
                 "or pass --temperature-column)"):
        assert said in re.sub(r">\s+<", "><", text), said
    # the file's own comment line is shown as written, not as an option
    assert "logged with units=deg/s" in text
    assert not re.search(r"\b(gaps|outliers|temperature_column)=", text)
    assert len(re.findall(r"\bunits=", text)) == 1


def test_a_bad_davar_window_is_named_as_typed(tmp_path: Path) -> None:
    # audit2: it said "davar_window_s must be a finite number > 0"
    src = tmp_path / "r.csv"
    pd.DataFrame({"time": np.arange(600) / 10.0,
                  "rate_deg_h": np.random.default_rng(1).normal(size=600)}).to_csv(src,
                                                                                  index=False)
    out = tmp_path / "r.html"
    res = runner.invoke(app, ["report", str(src), "-o", str(out), "--davar-window", "-1"])
    assert res.exit_code == 2, res.output
    assert error_output(res.stderr).splitlines() == [
        "error: --davar-window must be a finite number > 0, got -1.0"]
    assert not out.exists()
