"""The per-run JSON document and its rows."""

from __future__ import annotations

from fogts.batch import RUN_JSON_VERSION, SUMMARY_COLUMNS
from fogts.batch.documents import blank_row, error_outcome


def test_blank_row_has_every_column() -> None:
    row = blank_row("a.csv", "x")
    assert list(row) == list(SUMMARY_COLUMNS)
    assert (row["file"], row["axis"], row["status"], row["error"]) == ("a.csv", "x", "ok", "")


def test_error_outcome_is_one_error_row_in_its_document() -> None:
    got = error_outcome("a.csv", "boom", persist=False)
    assert (got.status, got.error, got.persist) == ("error", "boom", False)
    assert got.rows[0]["status"] == "error" and got.rows[0]["axis"] == ""
    assert got.document["version"] == RUN_JSON_VERSION
    assert got.document["rows"] == [got.rows[0]] and got.document["error"] == "boom"
