"""fogts.report.blocks: table cells, tables and embedded figures of the HTML report."""

from __future__ import annotations

import base64

import numpy as np
from matplotlib.figure import Figure

from fogts.report.blocks import _fixed, figure_block, fmt_num, fmt_pval, html_table, yes_no


def test_figure_block_is_deterministic_and_falls_back_to_png() -> None:
    def fig() -> Figure:
        f = Figure(figsize=(4, 3))
        f.add_subplot().plot(np.arange(10.0), np.arange(10.0) ** 2)
        return f

    a, b = figure_block(fig(), id="a", alt="a"), figure_block(fig(), id="a", alt="a")
    assert a.mime == "image/svg+xml" and a.data == b.data
    png = figure_block(fig(), id="p", alt="p", max_svg_bytes=100)
    assert png.mime == "image/png"
    assert base64.b64decode(png.data)[:4] == b"\x89PNG"


def test_cells() -> None:
    assert [fmt_num(None), fmt_num(np.bool_(True)), fmt_num(np.int64(7)), fmt_num(float("nan"))] == \
        ["–", "yes", "7", "–"]
    assert [fmt_num(0.0), fmt_num(12345.6), fmt_num(0.012345678), fmt_num(2.5e-7), fmt_num("x")] == \
        ["0", "12346", "0.01235", "2.500e-07", "x"]
    assert [fmt_pval(0.04321), fmt_pval(1e-9), fmt_pval(None), fmt_pval(float("inf"))] == \
        ["0.0432", "< 1e-4", "–", "–"]
    assert [_fixed(3.14159), _fixed("x"), _fixed(float("nan"))] == ["3.14", "–", "–"]
    assert [yes_no(None), yes_no(True), yes_no(False)] == ["–", "yes", "no"]


def test_table_formats_numbers_and_right_aligns_numeric_columns() -> None:
    t = html_table("c", ["name", "value"], [["a", 1.23456789], ["b", None]])
    assert t.kind == "table" and t.rows == (("a", "1.235"), ("b", "–"))
    assert t.numeric == (False, True)
    assert html_table("empty", ["x"], []).numeric == (False,)
