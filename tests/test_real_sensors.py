"""The real-sensor table (tests/real_sensors.py, printed into tests/README.md): every curve
the five-term fit misses beyond its intervals carries a warning; ADIS16405 run 1 X and
CH104 X are among them; the bundled example and MPU6050 X lie within their intervals."""

from __future__ import annotations

import pytest

from tests.conftest import shared_path
from tests.real_sensors import rows


@pytest.fixture(scope="module")
def table() -> dict[tuple[str, str], object]:
    shared_path("imu", "adis_16405_imu1_gyro.npz")  # skip without the reference data
    return {(r.label, r.axis): r for r in rows()}


def test_every_miss_carries_a_warning(table: dict) -> None:
    for row in table.values():
        check = row.analysis.fit_check
        warned = any("misses the curve" in w for w in row.warned)
        assert warned == (not check.ok), (row.label, row.axis)


def test_the_known_misfits_are_flagged(table: dict) -> None:
    assert not table[("ADIS16405 run 1", "Gyro. X")].analysis.fit_check.ok
    assert not table[("CH104", "rate_0")].analysis.fit_check.ok
    assert table[("bundled example (simulated)", "rate")].analysis.fit_check.ok
    assert table[("MPU6050", "gyro_x_deg_s")].analysis.fit_check.ok


def test_the_table_covers_every_recording(table: dict) -> None:
    labels = {label for label, _ in table}
    assert {f"ADIS16405 run {i}" for i in range(1, 7)} <= labels
    assert {"CH104", "MPU6050", "XSens cont_imu1", "bundled example (simulated)"} <= labels
    assert len(table) == 6 * 3 + 3 + 3 + 1 + 1
    for row in table.values():
        assert len(row.cells()) == 8
