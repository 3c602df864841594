"""fogts.report.blocks: table cells, tables and embedded figures of the HTML report."""

from __future__ import annotations

import base64

import numpy as np
from matplotlib.figure import Figure

from fogts.report.blocks import _fixed, _num, _pval, _table, _yes_no, figure_block


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
    assert [_num(None), _num(np.bool_(True)), _num(np.int64(7)), _num(float("nan"))] == \
        ["–", "yes", "7", "–"]
    assert [_num(0.0), _num(12345.6), _num(0.012345678), _num(2.5e-7), _num("x")] == \
        ["0", "12346", "0.01235", "2.500e-07", "x"]
    assert [_pval(0.04321), _pval(1e-9), _pval(None), _pval(float("inf"))] == \
        ["0.0432", "< 1e-4", "–", "–"]
    assert [_fixed(3.14159), _fixed("x"), _fixed(float("nan"))] == ["3.14", "–", "–"]
    assert [_yes_no(None), _yes_no(True), _yes_no(False)] == ["–", "yes", "no"]


def test_table_formats_numbers_and_right_aligns_numeric_columns() -> None:
    t = _table("c", ["name", "value"], [["a", 1.23456789], ["b", None]])
    assert t.kind == "table" and t.rows == (("a", "1.235"), ("b", "–"))
    assert t.numeric == (False, True)
    assert _table("empty", ["x"], []).numeric == (False,)
