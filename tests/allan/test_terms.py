"""Tests for fogts.allan.terms: the IEEE-952 term table, C_n conversions, term names."""

from __future__ import annotations

import math

import pytest

from fogts.allan.terms import c_from_terms, parse_terms, terms_from_c
from fogts.errors import DataError

SEED_C = {-2: 1.1754e-5, -1: 1.0228e-2, 0: 3.835e-3, 1: 1.196e-3, 2: 1.827e-4}


SEED_TERMS = {"N": 1.704e-4, "B": 5.776e-3, "K": 0.1243, "R": 0.9303, "Q": 6.786e-6}


# --------------------------------------------------------------------------- conversions


def test_seed_paper_conversions() -> None:
    """DESIGN.md: the seed paper's C_n give its N, B, K, R, Q.

    With the DESIGN.md factors, B, K and Q agree with the published values at their
    quoted 4 significant digits.  R = 3600 sqrt(2) * 1.827e-4 = 0.93016 -> '0.9302' vs the
    quoted 0.9303: C_2 is quoted to 4 digits only, and the quoted R maps back onto it
    (0.9303 -> C_2 = 1.8273e-4 -> '1.827e-04').  N = 1.0228e-2 / 60 = 1.70467e-4 -> '1.705e-04'
    vs the quoted 1.704e-4: no consistent factor reproduces it (the quoted N maps back to
    C_-1 = 1.0224e-2, not 1.0228e-2), so the paper's N carries a 4e-4 relative slip; we
    check it at that tolerance.
    """
    t = terms_from_c(SEED_C)
    for name in ("B", "K", "Q"):
        assert f"{t[name]:.4g}" == f"{SEED_TERMS[name]:.4g}", name
    assert t["R"] == pytest.approx(SEED_TERMS["R"], rel=2e-4)
    assert f"{c_from_terms({'R': SEED_TERMS['R']})[2]:.4g}" == f"{SEED_C[2]:.4g}"
    assert t["N"] == pytest.approx(SEED_TERMS["N"], rel=5e-4)
    assert c_from_terms({"N": SEED_TERMS["N"]})[-1] == pytest.approx(1.0224e-2, rel=1e-12)
    # every other quoted term maps back onto its quoted C_n
    back = c_from_terms({k: v for k, v in SEED_TERMS.items() if k != "N"})
    for power in (-2, 0, 1, 2):
        assert f"{back[power]:.4g}" == f"{SEED_C[power]:.4g}"


def test_conversion_round_trip_and_names() -> None:
    t = terms_from_c({"N": 0.6, "K": 0.01})
    assert t == pytest.approx({"N": 0.01, "K": 0.6 * math.sqrt(3) * 0.01 / 0.6 * 60})
    assert c_from_terms(terms_from_c(SEED_C)) == pytest.approx(SEED_C, rel=1e-14)


@pytest.mark.parametrize(("func", "arg", "match"), [
    (terms_from_c, {3: 1.0}, "coefficient key must be a term name"),
    (terms_from_c, {"X": 1.0}, "coefficient key must be a term name"),
    (terms_from_c, {True: 1.0}, "coefficient key must be a term name"),
    (terms_from_c, {-1: -1.0}, r"C coefficient -1 must be a finite number >= 0, got -1.0"),
    (terms_from_c, {"N": float("nan")}, "must be a finite number >= 0"),
    (c_from_terms, {"K": -2.0}, r"term 'K' must be a finite number >= 0, got -2.0"),
])
def test_conversion_errors(func: object, arg: dict, match: str) -> None:
    with pytest.raises(DataError, match=match):
        func(arg)  # type: ignore[operator]


# --------------------------------------------------------------------------- names


def test_parse_terms() -> None:
    assert parse_terms(" r, q ,N") == ("Q", "N", "R")
    assert parse_terms(("K",)) == ("K",)
