"""fogts.io.sources: the precedence of unit sources (given > file metadata > names > ...)."""

from __future__ import annotations

from fogts.io.sources import first_stated


def test_first_stated_source_wins_and_later_ones_are_not_consulted() -> None:
    called: list[str] = []

    def names() -> str | None:
        called.append("names")
        return "rad/s"

    assert first_stated(("deg/s", "given"), (names, "column name"), default="deg/h") == (
        "deg/s", "given")
    assert called == []  # a function source runs only when the ones before it are silent
    assert first_stated((None, "given"), (names, "column name"), default="deg/h") == (
        "rad/s", "column name")
    assert called == ["names"]


def test_nothing_stated_is_the_default_marked_assumed() -> None:
    assert first_stated((None, "given"), (lambda: None, "column name"), default="m/s^2") == (
        "m/s^2", "assumed")
