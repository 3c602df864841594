"""`fogts batch` on the command line: what its terminal tables say."""

from __future__ import annotations

from pathlib import Path

import pytest
from typer.testing import CliRunner

from fogts.cli import app

runner = CliRunner()


def test_a_failed_run_names_the_option_to_pass(tmp_path: Path,
                                               monkeypatch: pytest.MonkeyPatch) -> None:
    """audit2: the failed-runs table said "pass rate_column=" (the library's keyword); the
    command line's is --rate-column."""
    path = tmp_path / "two.csv"
    path.write_text("a,b\n" + "".join(f"{i},{i % 3}\n" for i in range(50)))
    monkeypatch.chdir(tmp_path)  # short names: the table holds the message on one line
    res = runner.invoke(app, ["batch", path.name, "-o", "s.csv", "-q", "--workers", "1",
                              "--no-select"])
    assert res.exit_code == 1, res.output
    text = " ".join(res.stdout.split())  # the table wraps long messages
    assert "cannot tell which column is the rate; columns are: a, b; pass --rate-column" in text
    assert "rate_column=" not in text
