"""Where a unit was stated: the first of several sources in order of precedence."""

from __future__ import annotations

from collections.abc import Callable

__all__ = ["UnitSource", "first_stated"]

#: A unit, or a function that finds one (None: not stated there).
UnitSource = str | None | Callable[[], str | None]


def first_stated(*sources: tuple[UnitSource, str], default: str) -> tuple[str, str]:
    """The first unit stated, in order of precedence, with the name of its source;
    ``(default, "assumed")`` when none is.  A source may be a function, called only when
    the sources before it stated nothing.

    Examples
    --------
    >>> first_stated((None, "given"), (lambda: "deg/s", "column name"), default="deg/h")
    ('deg/s', 'column name')
    >>> first_stated((None, "given"), default="deg/h")
    ('deg/h', 'assumed')
    """
    for found, where in sources:
        unit = found() if callable(found) else found
        if unit is not None:
            return unit, where
    return default, "assumed"
