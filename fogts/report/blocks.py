"""Building blocks of the HTML report's sections: numbers as table cells, tables, and
matplotlib figures embedded as data URIs."""

from __future__ import annotations

import base64
import io
import math
import re
from collections.abc import Sequence
from typing import TYPE_CHECKING, Any

import numpy as np

from fogts.report.page import Block

if TYPE_CHECKING:
    from fogts.tables import Table as FogtsTable

__all__ = ["MAX_SVG_BYTES", "figure_block", "fmt_num", "fmt_pval", "html_table", "table_block",
           "yes_no"]

#: Figures larger than this as SVG are embedded as PNG instead.
MAX_SVG_BYTES = 1_500_000


def figure_block(fig: Any, *, id: str, alt: str, caption: str = "",
                 max_svg_bytes: int = MAX_SVG_BYTES) -> Block:
    """Embed a matplotlib Figure as an SVG data URI (PNG if the SVG would be too large).

    The SVG carries no date and uses a fixed id salt, so the same figure gives the same
    bytes.
    """
    import matplotlib

    width_in, height_in = fig.get_size_inches()
    buf = io.BytesIO()
    with matplotlib.rc_context({"svg.hashsalt": "fogts"}):  # stable ids: same bytes
        fig.savefig(buf, format="svg", metadata={"Date": None})
    data, mime = buf.getvalue(), "image/svg+xml"
    width, height = round(width_in * 96), round(height_in * 96)
    head = re.search(rb'<svg[^>]*\swidth="([0-9.]+)pt"[^>]*\sheight="([0-9.]+)pt"', data[:2000])
    if head:  # the tight bounding box: CSS px = pt * 96 / 72
        width, height = round(float(head[1]) * 4 / 3), round(float(head[2]) * 4 / 3)
    if len(data) > max_svg_bytes:
        dpi = 110
        buf = io.BytesIO()
        fig.savefig(buf, format="png", dpi=dpi, metadata={"Software": None})
        data, mime = buf.getvalue(), "image/png"
        png_w, png_h = int.from_bytes(data[16:20], "big"), int.from_bytes(data[20:24], "big")
        width, height = round(png_w * 96 / dpi), round(png_h * 96 / dpi)
    return Block(kind="figure", id=id, mime=mime, data=base64.b64encode(data).decode("ascii"),
                 alt=alt, caption=caption, width=width, height=height)


def fmt_num(v: Any, digits: int = 4) -> str:
    """A number for a table cell: ``digits`` significant digits, "–" for missing."""
    if v is None:
        return "–"
    if isinstance(v, bool | np.bool_):
        return "yes" if v else "no"
    if isinstance(v, int | np.integer):
        return str(int(v))
    try:
        f = float(v)
    except (TypeError, ValueError):
        return str(v)
    if not math.isfinite(f):
        return "–"
    if f == 0:
        return "0"
    if 10 ** digits <= abs(f) < 1e6:
        return f"{f:.0f}"
    if 1e-3 <= abs(f) < 1e6:
        return f"{f:.{digits}g}"
    return f"{f:.{max(digits - 1, 1)}e}"


def fmt_pval(p: Any) -> str:
    """A p-value: 3 significant digits, "< 1e-4" below that."""
    try:
        f = float(p)
    except (TypeError, ValueError):
        return "–"
    if not math.isfinite(f):
        return "–"
    return "< 1e-4" if f < 1e-4 else f"{f:.3g}"


def _fixed(v: Any, decimals: int = 2) -> str:
    """A number with fixed decimals (information criteria, log-likelihoods)."""
    try:
        f = float(v)
    except (TypeError, ValueError):
        return "–"
    return f"{f:.{decimals}f}" if math.isfinite(f) else "–"


def yes_no(v: Any) -> str:
    """A check's outcome: "yes", "no", or "–" when it was not made."""
    return "–" if v is None else ("yes" if v else "no")


def html_table(caption: str, columns: Sequence[str], rows: Sequence[Sequence[Any]], *,
           numeric: Sequence[bool] | None = None, highlight: Sequence[int] = ()) -> Block:
    """A table block; cells that are not strings are formatted with :func:`fmt_num`, and a
    column is right-aligned (``numeric``) by default when none of its cells is a string."""
    cells = tuple(tuple(c if isinstance(c, str) else fmt_num(c) for c in r) for r in rows)
    if numeric is None:
        numeric = [all(not isinstance(r[j], str) for r in rows) if rows else False
                   for j in range(len(columns))]
    return Block(kind="table", caption=caption, columns=tuple(columns), rows=cells,
                 numeric=tuple(numeric), highlight=tuple(highlight))


def table_block(table: FogtsTable) -> Block:
    """A :class:`fogts.tables.Table` as a report table (its caption as a paragraph after
    it is left to the caller: the block's caption is the table's title)."""
    return Block(kind="table", caption=table.title, columns=tuple(table.titles),
                 rows=tuple(tuple(r) for r in table.cells()),
                 numeric=tuple(c.numeric for c in table.columns),
                 highlight=tuple(table.highlight))
