"""The one table model (fogts.tables) and its renderers: text, rich, HTML."""

from __future__ import annotations

import math

import numpy as np
from rich.console import Console

from fogts.cli._common import rich_table as _rich
from fogts.report.blocks import table_block
from fogts.tables import MISSING, Column, Table, format_cell


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
