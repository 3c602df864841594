"""The one table model (fogts.tables) and its renderers: text, rich, HTML."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest
from rich.console import Console

from fogts.cli._common import rich_table as _rich
from fogts.report.blocks import table_block
from fogts.tables import MISSING, Column, Table, TableView, format_cell

EXAMPLE = Path(__file__).resolve().parents[1] / "data" / "example_fog_10hz_3h.csv"


def _example() -> Table:
    return Table.build("t", [Column("name", numeric=False), Column("x", digits=3),
                             Column("d", fixed=True, digits=2, signed=True),
                             Column("ci")],
                       [["a", 1234.5678, 0.5, (1.0, 2.0)], ["b", math.nan, -1.25, None]],
                       caption="how to read", failed=[(1, 2)], highlight=[0])


def test_cells_are_formatted_once_by_the_column() -> None:
    assert _example().cells() == [["a", "1.23e+03", "+0.50", "1 … 2"],
                                  ["b", MISSING, "-1.25", MISSING]]
    assert format_cell(True, Column("w")) == "yes"
    assert format_cell(3, Column("n", signed=True)) == "+3"
    assert format_cell(np.float64(0.1234567), Column("v")) == "0.1235"


def test_text_rendering_aligns_numbers_right() -> None:
    lines = _example().to_text().splitlines()
    assert lines[0] == "t" and lines[-1] == "how to read"
    assert lines[1:4] == ["name         x      d     ci",
                          "a     1.23e+03  +0.50  1 … 2",
                          "b            –  -1.25      –"]


def test_frame_keeps_the_raw_values() -> None:
    frame = _example().to_frame()
    assert list(frame.columns) == ["name", "x", "d", "ci"]
    assert frame["x"].iloc[0] == 1234.5678


def test_rich_and_html_show_the_same_cells_as_the_text() -> None:
    table = _example()
    console = Console(width=200, record=True)
    console.print(_rich(table))
    shown = console.export_text()
    for row in table.cells():
        for cell in row:
            assert cell in shown
    assert "how to read" in shown
    block = table_block(table)
    assert block.rows == tuple(tuple(r) for r in table.cells())
    assert block.columns == ("name", "x", "d", "ci") and block.highlight == (0,)
    assert block.numeric == (False, True, True, True)


def test_failed_cells_are_red_and_emphasised_rows_bold() -> None:
    rich_table = _rich(_example())
    cells = [list(col.cells) for col in rich_table.columns]
    assert str(cells[2][1].style) == "red"
    assert str(cells[0][0].style) == "bold"


# --------------------------------------------------------------------------- notebook views


def test_html_is_escaped_and_aligned() -> None:
    table = Table.build("a <b> & c", [Column("name", numeric=False), Column("x")],
                        [("<script>", 1.5)], caption="x < 2")
    html = table.to_html()
    assert "<script>" not in html and "&lt;script&gt;" in html
    assert '<td style="text-align:right">1.5</td>' in html
    assert "<caption>a &lt;b&gt; &amp; c</caption>" in html and "x &lt; 2" in html


@pytest.fixture(scope="module")
def results() -> dict[str, object]:
    """One of each main result, from the bundled example, a simulated cold start and a
    noiseless four-position run (fixed seeds)."""
    import warnings

    import fogts
    from fogts.startup.northfind import four_position

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        run = fogts.read_run(EXAMPLE)
        adev = fogts.allan_deviation(run)
        selection = fogts.select_arma(fogts.prepare(run, decimate=10))
        sim = fogts.simulate_startup(duration_s=1800.0, rng=3)
        compensation = fogts.startup_compensation(sim.run, emd=False)
        dynamic = fogts.dynamic_allan(run.rate[:20000], fs_hz=10.0, window_s=200.0,
                                      step_s=100.0)
    omega = 15.041 * math.cos(math.radians(32.05))  # deg/h, azimuth 37.5 deg
    rates = {p: np.full(60, omega * math.cos(math.radians(37.5 + p)) + 0.3)
             for p in (0, 90, 180, 270)}
    best = selection.selected
    assert best is not None and best.fit is not None
    return {"AllanResult": adev, "NoiseModel": fogts.fit_noise(adev, terms="N,B,K"),
            "Selection": selection, "ArmaFit": best.fit, "DynamicAllanResult": dynamic,
            "ThermalModel": compensation.model, "StartupCompensation": compensation,
            "NorthFinding": four_position(rates, latitude_deg=32.05)}


@pytest.mark.parametrize("name", ["AllanResult", "NoiseModel", "Selection", "ArmaFit",
                                  "DynamicAllanResult", "ThermalModel",
                                  "StartupCompensation", "NorthFinding"])
def test_main_results_have_a_short_repr_and_an_html_table(results: dict[str, object],
                                                          name: str) -> None:
    """The repr is one short line (not every field: a NoiseModel's was 4,431 characters)
    and the notebook view is the result's main table with its values."""
    from html import escape

    obj = results[name]
    assert type(obj).__name__ == name and isinstance(obj, TableView)
    text = repr(obj)
    assert text.startswith(f"<{name}: ") and text.endswith(">") and len(text) < 200, text
    html = obj._repr_html_()
    assert html.startswith("<table>") and len(html) < 50_000
    for row in obj._view_table().cells():
        for cell in row:
            assert escape(cell) in html


def test_the_views_show_the_results_own_numbers(results: dict[str, object]) -> None:
    """Spot checks against the results' fields, formatted independently of the tables."""
    import fogts
    from fogts.startup.northfind import NorthFinding

    model = results["NoiseModel"]
    assert isinstance(model, fogts.NoiseModel)
    assert f"{model['N'].value:.4g}" in model._repr_html_()
    assert f"N = {model['N'].value:.4g} ± {model['N'].stderr:.2g}" in repr(model)
    north = results["NorthFinding"]
    assert isinstance(north, NorthFinding)
    assert north.azimuth_deg == pytest.approx(37.5, abs=1e-9)
    assert "37.5000°" in repr(north) and "37.5000°" in north._repr_html_()
    adev = results["AllanResult"]
    assert isinstance(adev, fogts.AllanResult)
    assert f"{adev.dev[0]:.5g}" in adev._repr_html_()


def test_a_p_value_that_underflowed_is_shown_as_a_bound() -> None:
    """``chi2.sf`` far in the tail returns 0 (below float64): a p-value column shows
    ``<1e-300`` there, not ``0``; other columns and other p values are unchanged."""
    from scipy.stats import chi2

    p = float(chi2.sf(5000.0, 20))
    assert p == 0.0
    assert format_cell(p, Column("LB p(20)", digits=3, pvalue=True)) == "<1e-300"
    assert format_cell(8.6e-20, Column("LB p(20)", digits=3, pvalue=True)) == "8.6e-20"
    assert format_cell(0.0, Column("x", digits=3)) == "0"
