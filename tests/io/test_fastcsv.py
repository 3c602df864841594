"""fogts.io.fastcsv: which text files the pyarrow path takes, and that it reads them exactly
as the line-by-line path does (values bit for bit, comments in order)."""

from __future__ import annotations

import gzip
import random
import warnings
import zlib
from pathlib import Path

import numpy as np
import pytest

from fogts.errors import DataError
from fogts.io.fastcsv import fast_text_table
from fogts.io.reader import read_run
from fogts.io.table import Table
from fogts.io.text import text_file_table
from tests.io.files import csv_text, write_file


def _checked(table: Table) -> Table:
    assert table.reparse is not None
    return table.reparse()


def _same_values(fast: Table, checked: Table) -> None:
    """Every column of ``fast`` equals the checked path's parse of the same text, bit for
    bit (the checked path keeps text; ``float`` is Python's correctly rounded parse)."""
    assert list(fast.frame.columns) == list(checked.frame.columns)
    for name in fast.frame.columns:
        text = checked.frame[name].str.strip().str.replace(",", ".")
        expected = np.array([float(v) for v in text], dtype=np.float64)
        got = fast.frame[name].to_numpy()
        assert got.dtype == np.float64
        np.testing.assert_array_equal(got.view(np.int64), expected.view(np.int64))


def _edge_numbers(n: int, seed: int) -> list[str]:
    """17- to 19-digit mantissas with exponents, signed zeros, subnormals, underflow to 0,
    integers beyond 2**53, and the forms ``1E5``, ``+1.5``, ``.5``, ``5.``."""
    rng = random.Random(seed)
    fixed = ["-0", "0", "-0.0", "1e-320", "4.9e-324", "2.2250738585072011e-308", "1e-400",
             "9007199254740993", "123456789012345678901234567890", "1E5", "+1.5", ".5", "5.",
             "0.30000000000000004", "1.7976931348623157e140"]
    out = []
    for i in range(n):
        digits = "".join(rng.choice("0123456789") for _ in range(rng.randint(17, 19)))
        drawn = f"{rng.choice('-+ ').strip()}{digits[0]}.{digits[1:]}e{rng.randint(-330, 140)}"
        out.append(fixed[i] if i < len(fixed) else drawn)
    return out


@pytest.mark.parametrize("gz", [False, True], ids=["plain", "gzip"])
def test_values_equal_the_line_by_line_parse(tmp_path: Path, gz: bool) -> None:
    a, b = _edge_numbers(3000, 1), _edge_numbers(3000, 2)
    text = "time,rate,T\n" + "".join(f"{i / 100!r},{x},{y}\n"
                                     for i, (x, y) in enumerate(zip(a, b, strict=True)))
    name = "edge.csv.gz" if gz else "edge.csv"
    path = write_file(tmp_path, name, gzip.compress(text.encode()) if gz else text)
    fast = fast_text_table(path, compressed=gz)
    assert fast is not None and fast.checked
    _same_values(fast, _checked(text_file_table(path)))


@pytest.mark.parametrize(("name", "text"), [
    ("semicolon.csv", "time;rate;T\n0,0;1,5;20,1\n0,1;-2,25;20,2\n0,2;3,0;20,3\n"),
    ("tab.tsv", csv_text(sep="\t")),
    ("bom_crlf.csv", "\ufeff" + csv_text().replace("\n", "\r\n")),
    ("quoted.csv", '"time","rate","T"\n' + csv_text().split("\n", 1)[1]),
    ("headerless.csv", csv_text().split("\n", 1)[1]),
    ("one_column.csv", "rate\n" + "".join(f"  {i % 7 - 3.5}\n" for i in range(40))),
])
def test_clean_layouts_take_the_fast_path(tmp_path: Path, name: str, text: str) -> None:
    path = write_file(tmp_path, name, text)
    fast = fast_text_table(path, compressed=False)
    assert fast is not None
    _same_values(fast, _checked(text_file_table(path)))


def _commented(n_rows: int) -> str:
    lines = csv_text(n=n_rows).splitlines()
    body = [lines[0], "# mid, with a comma", *lines[1:n_rows // 2], "  # indented\r",
            *lines[n_rows // 2:]]
    return "# logger v1\n\n" + "\n".join(body) + "\n# end"


@pytest.mark.parametrize("gz", [False, True], ids=["plain", "gzip"])
def test_comment_lines_anywhere_in_order(tmp_path: Path, gz: bool) -> None:
    # 60,000 rows: the comments fall in different blocks of the reader.
    text = _commented(60_000)
    path = write_file(tmp_path, "c.csv.gz" if gz else "c.csv",
                      gzip.compress(text.encode()) if gz else text)
    fast = fast_text_table(path, compressed=gz)
    assert fast is not None
    expected = ("# logger v1", "# mid, with a comma", "# indented", "# end")
    assert fast.comments == expected
    assert read_run(path).comments == expected
    assert _checked(text_file_table(path)).comments == expected


@pytest.mark.parametrize(("name", "text"), [
    ("whitespace.txt", csv_text(sep=" ")),
    ("empty_cell.csv", "time,rate\n0,1\n0.1,\n0.2,3\n"),
    ("nan.csv", "time,rate\n0,1\n0.1,NAN\n0.2,3\n"),
    ("inf.csv", "time,rate\n0,1\n0.1,Infinity\n0.2,3\n"),
    ("huge.csv", "time,rate\n0,1\n0.1,1e200\n0.2,3\n"),
    ("text.csv", "time,rate\n0,1\n0.1,abc\n0.2,3\n"),
    ("inline_comment.csv", "time,rate\n0,1 # first\n0.1,2\n0.2,3\n"),
    ("ragged.csv", "time,rate\n0,1\n0.1,2,7\n0.2,3\n"),
    ("duplicate_names.csv", "t,rate,rate\n0,1,2\n0.1,2,3\n0.2,3,4\n"),
    ("header_only.csv", "time,rate\n"),
    ("comments_only.csv", "# a\n# b\n"),
    ("binary.csv", "\x00\x01" * 50),
    ("long.csv", "time,rate\n0,1\n0.1,0." + "0" * (1 << 20) + "1\n0.2,3\n"),
])
def test_anything_else_is_left_to_the_checked_path(tmp_path: Path, name: str,
                                                   text: str) -> None:
    assert fast_text_table(write_file(tmp_path, name, text), compressed=False) is None


def test_corrupt_or_long_lined_gzip_is_left_to_the_checked_path(tmp_path: Path) -> None:
    corrupt = write_file(tmp_path, "bad.csv.gz", gzip.compress(csv_text().encode())[:60])
    assert fast_text_table(corrupt, compressed=True) is None
    long = b"time,rate\n0,1\n0.1,0." + b"0" * (1 << 20) + b"1\n0.2,3\n"
    assert fast_text_table(write_file(tmp_path, "long.csv.gz", gzip.compress(long)),
                           compressed=True) is None


def test_gzip_beyond_the_input_limit_is_refused_while_streaming(
        tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    path = write_file(tmp_path, "big.csv.gz", gzip.compress(csv_text(n=100_000).encode()))
    monkeypatch.setenv("FOGTS_MAX_INPUT_BYTES", "1M")
    with pytest.raises(DataError, match=r"'.*big.csv.gz': the stream decompresses to more "
                                        r"than the input limit of 1 MiB; oversized input is "
                                        "refused"):
        fast_text_table(path, compressed=True)


def test_errors_found_after_the_parse_name_the_line(tmp_path: Path) -> None:
    text = "time,rate\n0,1\n0.2,2\n0.1,3\n0.3,4\n"
    path = write_file(tmp_path, "decreasing.csv", text)
    assert fast_text_table(path, compressed=False) is not None
    with pytest.raises(DataError, match=r"'time' is decreasing at data row 2 \(line 4 of"):
        read_run(path)


def test_gzip_feed_never_raises_inside_the_parser(tmp_path: Path,
                                                   monkeypatch: pytest.MonkeyPatch) -> None:
    """Over the input limit, the gzip feed ends the stream (pyarrow sees EOF) and keeps the
    error, which ``read_run`` raises after the parser returns: an exception raised inside
    pyarrow's reader left its read-ahead thread running, and the interpreter aborted at exit
    ("terminate called without an active exception") about one run in ten."""
    from fogts.io.fastcsv import _GzipFeed

    path = tmp_path / "many.csv.gz"
    rows = b"".join(b"%d,%d\n" % (i, i % 7) for i in range(200_000))
    path.write_bytes(zlib.compress(b"time,rate\n" + rows, wbits=31))
    monkeypatch.setenv("FOGTS_MAX_INPUT_BYTES", "1M")
    feed = _GzipFeed(path)
    try:
        while feed.read(1 << 16):
            pass
        assert isinstance(feed.failure, DataError)
        assert feed.read(1 << 16) == b""  # stays at the end
        with pytest.raises(DataError, match="decompresses to more than the input limit"):
            feed.raise_failure()
    finally:
        feed.close()
    with pytest.raises(DataError, match="decompresses to more than the input limit of 1 MiB"):
        read_run(path)


def _reader_used(monkeypatch: pytest.MonkeyPatch) -> list[str]:
    """Record which fast reader parses: 'pandas' or 'pyarrow'."""
    import fogts.io.fastcsv as fastcsv

    used: list[str] = []
    pandas_frame, pyarrow_parse = fastcsv._pandas_frame, fastcsv._parse

    def via_pandas(*args: object) -> object:
        used.append("pandas")
        return pandas_frame(*args)  # type: ignore[arg-type]

    def via_pyarrow(*args: object) -> object:
        used.append("pyarrow")
        return pyarrow_parse(*args)  # type: ignore[arg-type]

    monkeypatch.setattr(fastcsv, "_pandas_frame", via_pandas)
    monkeypatch.setattr(fastcsv, "_parse", via_pyarrow)
    return used


@pytest.mark.skipif(not __import__("fogts.io.fastcsv").io.fastcsv.PANDAS_SPLITS_FILES,
                    reason="pandas < 3.1 does not split a file among threads: pyarrow reads")
def test_a_file_pandas_splits_among_threads_reads_bit_for_bit(
        tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    # Over 5 MiB of data (pandas' threshold for its threaded read), with blank and comment
    # lines before the header: the chunks pandas cuts hold edge numbers at every boundary.
    numbers = _edge_numbers(170_000, 3)
    text = "# logger\n\n# v2\ntime,rate\n" + "".join(
        f"{i / 100!r},{x}\n" for i, x in enumerate(numbers))
    assert len(text) > 5 * 1024 * 1024
    path = write_file(tmp_path, "big.csv", text)
    used = _reader_used(monkeypatch)
    fast = fast_text_table(path, compressed=False)
    assert used == ["pandas"] and fast is not None
    assert fast.comments == ("# logger", "# v2")
    expected = np.array([float(v) for v in numbers])
    np.testing.assert_array_equal(fast.frame["rate"].to_numpy().view(np.int64),
                                  expected.view(np.int64))
    np.testing.assert_array_equal(fast.frame["time"].to_numpy(),
                                  np.arange(len(numbers)) / 100)


@pytest.mark.parametrize(("name", "text", "reader"), [
    ("clean.csv", csv_text(), "pandas"),
    ("headerless.csv", csv_text().split("\n", 1)[1], "pandas"),
    ("trailing_comment.csv", csv_text() + "# end\n", "pyarrow"),
    ("bom.csv", "\ufeff" + csv_text(), "pyarrow"),
])
def test_pandas_reads_unless_comments_follow_or_a_bom_leads(
        tmp_path: Path, monkeypatch: pytest.MonkeyPatch, name: str, text: str,
        reader: str) -> None:
    import fogts.io.fastcsv as fastcsv

    path = write_file(tmp_path, name, text)
    used = _reader_used(monkeypatch)
    fast = fast_text_table(path, compressed=False)
    assert fast is not None
    assert used == [reader if fastcsv.PANDAS_SPLITS_FILES else "pyarrow"]
    _same_values(fast, _checked(text_file_table(path)))


def test_a_first_row_with_an_extra_cell_is_refused_not_cut(tmp_path: Path) -> None:
    # pandas would take the extra cell for an index, or drop it with a warning
    path = write_file(tmp_path, "extra.csv", "time,rate\n0,1,5\n0.1,2\n0.2,3\n")
    assert fast_text_table(path, compressed=False) is None
    with pytest.raises(DataError, match=r"'.*extra.csv': data row 1 \(line 2\) has 3 cells "
                                        r"\(0, 1, 5\) but the header names 2 columns "
                                        r"\(time, rate\); fogts never drops a value"):
        read_run(path)


def test_trailing_separators_are_read_as_without_them(tmp_path: Path) -> None:
    path = write_file(tmp_path, "trailing.csv", "time,rate\n0,1,\n0.1,2,\n0.2,3,\n0.3,4,\n")
    assert fast_text_table(path, compressed=False) is None  # the checked path reads it
    np.testing.assert_array_equal(read_run(path).rate, [1.0, 2.0, 3.0, 4.0])


@pytest.mark.parametrize("preamble", ["# logger\n# v2\n", "# logger\n\n# v2\n", ""],
                         ids=["comments", "blank line", "none"])
@pytest.mark.parametrize("header", [True, False], ids=["header", "headerless"])
def test_every_preamble_keeps_every_row(tmp_path: Path, preamble: str, header: bool) -> None:
    rows = "".join(f"{i / 10!r},{i % 7 - 3.25}\n" for i in range(50))
    path = write_file(tmp_path, "p.csv", preamble + ("time,rate\n" if header else "") + rows)
    fast = fast_text_table(path, compressed=False)
    assert fast is not None
    assert fast.comments == tuple(line for line in preamble.splitlines() if line)
    np.testing.assert_array_equal(fast.frame.iloc[:, 1].to_numpy(),
                                  [i % 7 - 3.25 for i in range(50)])


def test_a_quote_before_the_header_leaves_the_file_to_pyarrow(
        tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    # pandas would open a quoted field in the skipped comment and lose the first data row
    path = write_file(tmp_path, "q.csv", '# gyro,"FOG 200\n"time","rate"\n0,1\n0.1,2\n0.2,3\n')
    used = _reader_used(monkeypatch)
    fast = fast_text_table(path, compressed=False)
    assert used == ["pyarrow"] and fast is not None
    np.testing.assert_array_equal(fast.frame["rate"].to_numpy(), [1.0, 2.0, 3.0])
    np.testing.assert_array_equal(read_run(path).rate, [1.0, 2.0, 3.0])


def test_older_pandas_leaves_plain_files_to_pyarrow(
        tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    import fogts.io.fastcsv as fastcsv

    monkeypatch.setattr(fastcsv, "PANDAS_SPLITS_FILES", False)
    path = write_file(tmp_path, "clean.csv", csv_text())
    used = _reader_used(monkeypatch)
    fast = fast_text_table(path, compressed=False)
    assert used == ["pyarrow"] and fast is not None
    _same_values(fast, _checked(text_file_table(path)))


def test_the_reference_text_files_read_alike_through_pandas_and_pyarrow(
        monkeypatch: pytest.MonkeyPatch) -> None:
    """Every text file of ``../shared/data`` that a fast path takes gives the same columns,
    values (bit for bit), comments and header through pandas' reader as through pyarrow's."""
    import fogts.io.fastcsv as fastcsv
    from tests.conftest import shared_path

    root = shared_path()
    files = sorted(p for p in root.rglob("*") if p.is_file()
                   and p.suffix.lower() in {".csv", ".txt", ".tsv", ".dat"})
    assert files
    taken = 0
    for path in files:
        tables = []
        for pandas_reads in (True, False):
            monkeypatch.setattr(fastcsv, "PANDAS_SPLITS_FILES", pandas_reads)
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")
                tables.append(fast_text_table(path, compressed=False))
        a, b = tables
        assert (a is None) == (b is None), path
        if a is None or b is None:
            continue
        taken += 1
        assert (list(a.frame.columns), a.comments, a.header) == \
            (list(b.frame.columns), b.comments, b.header), path
        for name in a.frame.columns:
            np.testing.assert_array_equal(a.frame[name].to_numpy().view(np.int64),
                                          b.frame[name].to_numpy().view(np.int64),
                                          err_msg=f"{path}: {name}")
    assert taken >= 100  # the published Allan curves and the bench recordings
