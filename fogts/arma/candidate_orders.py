"""Candidate ARMA orders: the default set and the parser of names like ``"ARMA(2,1)"``."""

from __future__ import annotations

import re
from collections.abc import Sequence
from typing import Any

from fogts._validate import check_int
from fogts.arma.fit_result import model_name
from fogts.errors import DataError

__all__ = ["DEFAULT_FIVE", "MAX_ORDER", "parse_candidates"]

#: The admissible low-order candidates of the drift paper, as (p, q).
DEFAULT_FIVE: tuple[tuple[int, int], ...] = ((1, 0), (2, 0), (3, 0), (1, 1), (2, 1))
#: Largest AR or MA order a candidate may have.
MAX_ORDER = 10

_NAME_RE = re.compile(r"^\s*(ARMA|AR|MA)\s*\(\s*(\d+)\s*(?:,\s*(\d+)\s*)?\)\s*$", re.IGNORECASE)


def _parse_one(item: Any) -> tuple[int, int]:
    if isinstance(item, str):
        m = _NAME_RE.match(item)
        if m is None:
            raise DataError(f"candidates: cannot read {item!r}; write AR(p), MA(q) or ARMA(p,q), "
                            "e.g. AR(1),ARMA(2,1)")
        kind, a, b = m.group(1).upper(), int(m.group(2)), m.group(3)
        if kind == "ARMA":
            if b is None:
                raise DataError(f"candidates: {item!r} needs two orders, e.g. ARMA(1,1)")
            p, q = a, int(b)
        elif b is not None:
            raise DataError(f"candidates: {item!r} takes one order, e.g. {kind}(1)")
        else:
            p, q = (a, 0) if kind == "AR" else (0, a)
    elif isinstance(item, Sequence) and len(item) == 2:
        p = check_int("candidates (p)", item[0], minimum=0, maximum=MAX_ORDER)
        q = check_int("candidates (q)", item[1], minimum=0, maximum=MAX_ORDER)
    else:
        raise DataError(f"candidates: each entry must be a name like 'ARMA(1,1)' or a (p, q) "
                        f"pair, got {item!r}")
    if p + q == 0:
        raise DataError(f"candidates: {item!r} has p + q = 0; white noise is not a candidate")
    if p > MAX_ORDER or q > MAX_ORDER:
        raise DataError(f"candidates: {item!r} has an order above {MAX_ORDER}")
    return p, q


def parse_candidates(spec: Any = None) -> tuple[tuple[int, int], ...]:
    """Candidate orders from names or (p, q) pairs.

    Parameters
    ----------
    spec : str, sequence or None
        ``None`` gives :data:`DEFAULT_FIVE`; a string like ``"AR(1),ARMA(1,1),MA(2)"``
        (case-insensitive, commas inside parentheses allowed); or a sequence of such names
        or of (p, q) pairs.

    Returns
    -------
    tuple of (p, q)

    Examples
    --------
    >>> parse_candidates("AR(1), ARMA(2,1)")
    ((1, 0), (2, 1))
    """
    if spec is None:
        return DEFAULT_FIVE
    if isinstance(spec, str):
        items: list[Any] = [s for s in re.split(r",(?![^()]*\))", spec) if s.strip()]
    elif isinstance(spec, Sequence):
        items = list(spec)
    else:
        raise DataError(f"candidates must be a string like 'AR(1),ARMA(1,1)' or a sequence, "
                        f"got {spec!r}")
    if not items:
        raise DataError(f"candidates must name at least one model, got {spec!r}")
    orders = [_parse_one(it) for it in items]
    seen: set[tuple[int, int]] = set()
    for o in orders:
        if o in seen:
            raise DataError(f"candidates lists {model_name(*o)} twice")
        seen.add(o)
    return tuple(orders)
