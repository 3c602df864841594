"""fogts.io.text: separators, decimal commas, BOM and CRLF, gzip, comment lines."""

from __future__ import annotations

import gzip
from pathlib import Path

import numpy as np
import pytest

from fogts.io.reader import read_run
from tests.io.files import csv_text, write_file


@pytest.mark.parametrize("sep", [",", ";", "\t", " "])
def test_separators(tmp_path: Path, sep: str) -> None:
    run = read_run(write_file(tmp_path, "a.txt", csv_text(sep=sep)))
    assert run.n == 50 and run.fs_hz == pytest.approx(10.0)
    assert run.axes == ("rate",)
    assert run.temperature is not None


def test_semicolon_with_decimal_commas(tmp_path: Path) -> None:
    text = "time;rate;temp\n0,0;1,5;20,1\n0,1;-2,25;20,2\n0,2;3,0;20,3\n0,3;0,5;20,4\n"
    run = read_run(write_file(tmp_path, "dc.csv", text))
    np.testing.assert_allclose(run.rate, [1.5, -2.25, 3.0, 0.5])
    assert run.fs_hz == pytest.approx(10.0)


def test_utf8_bom_and_crlf(tmp_path: Path) -> None:
    text = csv_text().replace("\n", "\r\n").encode("utf-8")
    run = read_run(write_file(tmp_path, "bom.csv", b"\xef\xbb\xbf" + text))
    assert run.columns == ("time", "rate", "T")
    assert run.n == 50


def test_gzip(tmp_path: Path) -> None:
    run = read_run(write_file(tmp_path, "a.csv.gz", gzip.compress(csv_text().encode())))
    assert run.n == 50


def test_comment_lines_anywhere(tmp_path: Path) -> None:
    lines = csv_text().splitlines()
    text = "# logger v1\n" + lines[0] + "\n# mid\n" + "\n".join(lines[1:]) + "\n# end\n"
    run = read_run(write_file(tmp_path, "c.csv", text))
    assert run.n == 50
    assert run.comments == ("# logger v1", "# mid", "# end")


def test_huge_but_valid_values_are_read(tmp_path: Path) -> None:
    run = read_run(write_file(tmp_path, "h.csv", "time,rate\n0,1e100\n1,-1e100\n2,3e99\n"))
    assert run.rate[0] == 1e100
