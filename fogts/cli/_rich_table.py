"""A :class:`fogts.tables.Table` on the terminal, every number whole on one line.

Rich fits a table to the console width by narrowing its columns: a column that may wrap
folds its cells at the column edge (``-176637423.92`` printed as ``-176637423.9`` and, on
the next line, ``2``), and when even the narrowest wrapping does not fit, it narrows every
column evenly, cropping the ``no_wrap`` ones too (``Table._calculate_column_widths``, its
"last resort").  A reader of a log then reads a wrong number.

Here a column is either kept whole or free text (:attr:`fogts.tables.Column.wrap`):

* a whole column (numbers, intervals, p values, model names, units, file names) is
  ``no_wrap`` and never narrower than its widest cell (``min_width``, which rich honours
  after every narrowing: ``Table._measure_column`` clamps to it);
* a free-text column wraps between words and is never narrower than its longest word;
* a table that cannot fit the console even so is drawn at its least width, wider than the
  console (:class:`WholeCellsTable`), and :func:`fogts.cli._common.print_out` prints it
  uncropped: a line runs long, a number is never split or cut.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from rich.cells import cell_len
from rich.markup import escape
from rich.table import Table
from rich.text import Text

if TYPE_CHECKING:
    from collections.abc import Iterable

    from rich.console import Console, ConsoleOptions, RenderResult

    from fogts.tables import Table as FogtsTable

__all__ = ["WholeCellsTable", "rich_table"]

#: Wider than any table: the width at which a table's least width is measured.
_UNBOUNDED = 1 << 20


def _longest(texts: Iterable[str], *, words: bool) -> int:
    """The widest text (in terminal cells), or with ``words`` the widest word in them."""
    pieces = (w for t in texts for w in (t.split() if words else t.splitlines() or [t]))
    return max((cell_len(p) for p in pieces), default=0)


class WholeCellsTable(Table):
    """A rich table that, when the console is narrower than its least width (every whole
    column at its widest cell, every free-text column at its longest word, the title and
    caption's longest word), is drawn at that least width instead of narrowing a column
    below it.  Print it with ``crop=False`` (:func:`fogts.cli._common.print_out`), else the
    console cuts the long lines at its width."""

    def __rich_console__(self, console: Console, options: ConsoleOptions) -> RenderResult:
        least = self.__rich_measure__(console, options.update_width(_UNBOUNDED)).minimum
        if options.max_width < least:
            options = options.update_width(least)
        yield from super().__rich_console__(console, options)


def rich_table(table: FogtsTable) -> WholeCellsTable:
    """A :class:`fogts.tables.Table` on the terminal: failed checks in red, emphasised rows
    in bold, the caption under it; numbers and labels whole on one line, free-text columns
    wrapped between words (module docstring)."""
    cells = table.cells()
    words = [table.title, table.caption]
    out = WholeCellsTable(title=escape(table.title), title_justify="left",
                          caption=escape(table.caption) or None, caption_justify="left",
                          min_width=_longest(words, words=True) or None)
    for j, c in enumerate(table.columns):
        column = [c.title, *(r[j] for r in cells)]
        # ellipsis: never reached (the column is as wide as its widest cell); were it ever,
        # a marked cut is read as one, where a crop or a fold reads as another number
        out.add_column(escape(c.title), justify="right" if c.numeric else "left",
                       no_wrap=not c.wrap, overflow="fold" if c.wrap else "ellipsis",
                       min_width=_longest(column, words=c.wrap) or None)
    for i, row in enumerate(cells):
        style = "bold" if i in table.highlight else ""
        out.add_row(*[Text(v, "red" if (i, j) in table.failed else style)
                      for j, v in enumerate(row)])
    return out
