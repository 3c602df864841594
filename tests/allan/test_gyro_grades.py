"""Tests for fogts.allan.gyro_grades: the table of gyro grades and its envelope.

Reference figures are datasheet values, quoted beside each case.
"""

from __future__ import annotations

import math

import pytest

from fogts.allan.gyro_grades import B_ENVELOPE, GYRO_GRADES, N_ENVELOPE, grade_table, grades_of
from fogts.allan.plausibility import check_plausibility


def test_grade_table_and_envelope() -> None:
    assert [g.key for g in GYRO_GRADES] == ["strategic", "navigation", "tactical",
                                           "industrial", "consumer"]
    assert N_ENVELOPE == (3e-5, 10.0)
    assert B_ENVELOPE == (1e-4, 1000.0)
    table = grade_table()
    assert list(table.index) == [g.key for g in GYRO_GRADES]
    assert (table["N_low"] < table["N_high"]).all() and (table["B_low"] < table["B_high"]).all()
    for g in GYRO_GRADES:
        mid_n = math.sqrt(g.n_range[0] * g.n_range[1])
        mid_b = math.sqrt(g.b_range[0] * g.b_range[1])
        assert g.distance(mid_n, mid_b) == pytest.approx(0.0, abs=1e-12)
        assert g.distance(g.n_range[1], g.b_range[0]) == pytest.approx(1.0)
        assert g.key in check_plausibility(mid_n, mid_b, units="deg/h").grades


@pytest.mark.parametrize(("n", "b", "grade"), [
    (0.002, 0.003, "navigation"),    # Honeywell HG9900: N <= 0.002, B <= 0.003
    (0.0035, 0.0035, "navigation"),  # Honeywell GG1320AN
    (0.012, 0.05, "tactical"),       # KVH DSP-1750: N <= 0.012, B typ. 0.05
    (0.2, 5.0, "tactical"),          # Honeywell HG1700: N 0.125..0.3, B 1..10
    (0.26, 5.1, "industrial"),       # ADIS16488
    (0.66, 14.5, "industrial"),      # ADIS16448
    (0.3, 20.0, "consumer"),         # MPU-6050: 0.005 deg/s/sqrt(Hz)
])
def test_datasheet_gyros_fall_in_their_grade(n: float, b: float, grade: str) -> None:
    r = check_plausibility(n, b, units="deg/h")
    assert r.verdict == "plausible"
    assert grade in r.grades


def test_grades_of_orders_by_distance_to_the_middle() -> None:
    grades, distance = grades_of(0.3, 20.0)
    assert grades == ("consumer", "industrial", "tactical")   # all three hold N 0.3, B 20
    first = next(g for g in GYRO_GRADES if g.key == grades[0])
    assert distance == pytest.approx(first.distance(0.3, 20.0))
    assert all(first.distance(0.3, 20.0) <= g.distance(0.3, 20.0)
               for g in GYRO_GRADES if g.key in grades)
    none, nan = grades_of(1e-9, None)
    assert none == () and math.isnan(nan)


def test_the_table_is_importable_from_the_plausibility_module() -> None:
    from fogts.allan import plausibility

    assert plausibility.GYRO_GRADES is GYRO_GRADES and plausibility.grade_table is grade_table
    assert (plausibility.N_ENVELOPE, plausibility.B_ENVELOPE) == (N_ENVELOPE, B_ENVELOPE)
