"""One table model for every tabular output.

A result defines each of its tables once, as a :class:`Table` (title, columns, rows, a
caption, the cells that fail a check, the rows to emphasise); the renderers turn that one
definition into plain text (:meth:`Table.to_text`, used by ``summary()``), a DataFrame
(:meth:`Table.to_frame`), a rich table on the terminal (:func:`fogts.cli._common._rich`)
and an HTML table in the report (:func:`fogts.report.blocks.table_block`).  A change of
wording or of a column therefore reaches all of them together.  (The JSON documents are
contracts of their own: DESIGN.md, "Contracts".)
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass, fields
from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:
    import pandas as pd

__all__ = ["Column", "Table", "TableView", "fields_dict", "format_cell"]

#: What an empty, NaN or infinite cell shows.
MISSING = "–"


@dataclass(frozen=True)
class Column:
    """A column: its ``title`` (shown), whether it holds numbers (right-aligned) and the
    ``digits`` (significant, or decimals with ``fixed``) numbers are shown with.

    ``wrap`` marks free text (a note, a read-out's explanation): the terminal may wrap it
    between words.  Every other column (numbers, intervals, p values, model names, units,
    file names) is kept whole on one line, however narrow the terminal
    (:func:`fogts.cli._rich_table.rich_table`).  ``pvalue`` shows a p value of exactly 0
    (a tail probability below float64's range, e.g. ``chi2.sf`` far out) as ``<1e-300``."""

    title: str
    numeric: bool = True
    digits: int = 4
    fixed: bool = False
    signed: bool = False
    wrap: bool = False
    pvalue: bool = False


def fields_dict(result: Any, **keys: str) -> dict[str, Any]:
    """The fields of a dataclass result as its ``to_dict`` mapping, in field order.

    ``keys`` renames fields: ``fields_dict(term, t_c="t_c_s")`` writes the field ``t_c``
    under ``"t_c_s"``.  The values are the fields themselves (no copy, no recursion).
    """
    return {keys.get(f.name, f.name): getattr(result, f.name) for f in fields(result)}


def format_cell(value: Any, column: Column) -> str:
    """A cell as text: strings as they are, booleans as yes/no, (low, high) pairs as an
    interval, numbers with the column's digits; None, NaN and inf as :data:`MISSING`."""
    if value is None:
        return MISSING
    if isinstance(value, str):
        return value
    if isinstance(value, bool):
        return "yes" if value else "no"
    if isinstance(value, tuple) and len(value) == 2:
        return f"{format_cell(value[0], column)} … {format_cell(value[1], column)}"
    if isinstance(value, int):
        return f"{value:+d}" if column.signed else str(value)
    v = float(value)
    if not math.isfinite(v):
        return MISSING
    if column.pvalue and v == 0.0:
        return "<1e-300"
    sign = "+" if column.signed else ""
    return f"{v:{sign}.{column.digits}f}" if column.fixed else f"{v:{sign}.{column.digits}g}"


@dataclass(frozen=True)
class Table:
    """A titled table.

    Attributes
    ----------
    title : str
    columns : tuple of Column
    rows : tuple of tuples
        The raw values (numbers stay numbers: each renderer formats them).
    caption : str
        How to read the table (thresholds, units), shown under it.
    failed : frozenset of (row, column)
        Cells whose value fails a check (shown in red / marked).
    highlight : tuple of int
        Rows to emphasise (the selected model, say).
    """

    title: str
    columns: tuple[Column, ...]
    rows: tuple[tuple[Any, ...], ...]
    caption: str = ""
    failed: frozenset[tuple[int, int]] = frozenset()
    highlight: tuple[int, ...] = ()

    @classmethod
    def build(cls, title: str, columns: Sequence[Column], rows: Sequence[Sequence[Any]], *,
              caption: str = "", failed: Sequence[tuple[int, int]] = (),
              highlight: Sequence[int] = ()) -> Table:
        """A Table from lists (converted to the frozen tuples)."""
        return cls(title=title, columns=tuple(columns), rows=tuple(tuple(r) for r in rows),
                   caption=caption, failed=frozenset(failed), highlight=tuple(highlight))

    @property
    def titles(self) -> list[str]:
        return [c.title for c in self.columns]

    def cells(self) -> list[list[str]]:
        """Every cell as text (:func:`format_cell`)."""
        return [[format_cell(v, c) for v, c in zip(row, self.columns, strict=True)]
                for row in self.rows]

    def to_text(self) -> str:
        """Aligned plain text: the title, the header, the rows and the caption."""
        cells = self.cells()
        widths = [max([len(c.title), *(len(r[j]) for r in cells)])
                  for j, c in enumerate(self.columns)]

        def line(values: Sequence[str]) -> str:
            return "  ".join(v.rjust(w) if c.numeric else v.ljust(w)
                             for v, w, c in zip(values, widths, self.columns, strict=True)
                             ).rstrip()

        out = [self.title, line(self.titles), *(line(r) for r in cells)]
        if self.caption:
            out.append(self.caption)
        return "\n".join(out)

    def to_html(self) -> str:
        """A compact HTML table (escaped text; numeric columns right-aligned), the title as
        its caption and the caption as a note under it: a result's notebook view."""
        from html import escape

        def cell(tag: str, text: str, numeric: bool) -> str:
            align = ' style="text-align:right"' if numeric else ""
            return f"<{tag}{align}>{escape(text)}</{tag}>"

        head = "".join(cell("th", c.title, c.numeric) for c in self.columns)
        body = "".join("<tr>" + "".join(cell("td", v, c.numeric)
                                        for v, c in zip(row, self.columns, strict=True))
                       + "</tr>" for row in self.cells())
        note = f"<p><small>{escape(self.caption)}</small></p>" if self.caption else ""
        return (f"<table><caption>{escape(self.title)}</caption><thead><tr>{head}</tr>"
                f"</thead><tbody>{body}</tbody></table>{note}")

    def to_frame(self) -> pd.DataFrame:
        """The raw values with the column titles as columns."""
        import pandas as pd

        return pd.DataFrame([list(r) for r in self.rows], columns=self.titles)


class TableView:
    """A result's short ``repr`` and its notebook view, both from its main table.

    A result class (a frozen dataclass declared with ``repr=False``) defines
    :meth:`_view_table` and :meth:`_view_headline`; the ``repr`` is one line
    ``<ClassName: headline>`` instead of every field, and Jupyter shows the table
    (``_repr_html_``).
    """

    def _view_table(self) -> Table:
        raise NotImplementedError

    def _view_headline(self) -> str:
        raise NotImplementedError

    def __repr__(self) -> str:
        return f"<{type(self).__name__}: {self._view_headline()}>"

    def _repr_html_(self) -> str:
        return self._view_table().to_html()
