"""Fixtures of the batch tests: the recordings, and one batch over them on the local pool."""

from __future__ import annotations

from pathlib import Path

import pytest
from click.testing import Result
from typer.testing import CliRunner

from fogts.cli import app
from tests.batch.cases import make_files


@pytest.fixture(scope="package")
def files(tmp_path_factory: pytest.TempPathFactory) -> Path:
    folder = tmp_path_factory.mktemp("batch") / "in"
    make_files(folder)
    return folder


@pytest.fixture(scope="package")
def pool_run(files: Path, tmp_path_factory: pytest.TempPathFactory) -> tuple[Path, Result]:
    """``fogts batch`` on every file with two workers: (output folder, CLI result)."""
    out = tmp_path_factory.mktemp("pool")
    res = CliRunner().invoke(app, ["batch", str(files / "*.csv"), "-o",
                                   str(out / "summary.csv"), "--json-dir", str(out / "json"),
                                   "--workers", "2"])
    return out, res
