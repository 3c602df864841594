"""Candidate orders: the default set and the parser of AR(p), MA(q), ARMA(p,q) names."""

from __future__ import annotations

import pytest

from fogts.arma import DEFAULT_FIVE, parse_candidates
from fogts.errors import (
    DataError,
)


def test_parse_candidates() -> None:
    assert parse_candidates(None) == DEFAULT_FIVE
    assert parse_candidates("AR(1), arma(2, 1),MA(2)") == ((1, 0), (2, 1), (0, 2))
    assert parse_candidates([(1, 0), "ARMA(1,1)"]) == ((1, 0), (1, 1))


@pytest.mark.parametrize(("spec", "match"), [
    ("ARMA(1)", r"'ARMA\(1\)' needs two orders"),
    ("AR(1,1)", r"'AR\(1,1\)' takes one order"),
    ("ARIMA(1,1)", r"cannot read 'ARIMA\(1,1\)'"),
    ("AR(0)", r"p \+ q = 0"),
    ("AR(11)", r"has an order above 10"),
    ("AR(1),AR(1)", r"lists AR\(1\) twice"),
    ("", r"must name at least one model"),
    ([(1, 2, 3)], r"each entry must be a name"),
    (5, r"candidates must be a string"),
])
def test_bad_candidates(spec: object, match: str) -> None:
    with pytest.raises(DataError, match=match):
        parse_candidates(spec)
