"""Tables on a narrow terminal (fogts.cli._rich_table): every number, interval, p value,
model name and unit whole on one line at widths 80 and 60 (a table that cannot fit runs
long and is printed uncropped); only free-text columns (notes) wrap, between words."""

from __future__ import annotations

import io
import json
from pathlib import Path

import numpy as np
import pandas as pd
import pytest
from rich.console import Console
from typer.testing import CliRunner

from fogts import select_arma
from fogts.cli import _common as common
from fogts.cli import app
from fogts.cli._rich_table import rich_table
from fogts.cli.batch import _failed_runs_table
from fogts.tables import Column, Table

WIDTHS = (80, 60)


def _render(table: Table, width: int) -> str:
    """The table as printed by the commands (:func:`common.print_out`: uncropped) on a
    console of ``width`` columns without colour, as in a pipe or a log file."""
    console = Console(width=width, file=io.StringIO(), color_system=None, highlight=False)
    console.print(rich_table(table), crop=False)
    return console.file.getvalue()  # type: ignore[attr-defined]


def _body(text: str) -> list[list[str]]:
    """The body lines of a rendered table split into their (stripped) column segments."""
    return [[c.strip() for c in line.split("│")[1:-1]] for line in text.splitlines()
            if line.startswith("│")]


def _header(text: str) -> list[list[str]]:
    return [[c.strip() for c in line.split("┃")[1:-1]] for line in text.splitlines()
            if line.startswith("┃")]


def assert_whole(table: Table, text: str) -> None:
    """Every cell of a column kept whole is on exactly one printed line, unchanged: the
    column's printed segments, read down the table, are exactly its cells (so no number is
    split, cut, folded or ellipsised); a free-text column's words are all there, whole and
    in order; the titles each stand on one header line."""
    body, cells = _body(text), table.cells()
    assert [[c.title for c in table.columns]] == _header(text)
    for j, column in enumerate(table.columns):
        printed = [line[j] for line in body if line[j]]
        if column.wrap:
            assert " ".join(printed).split() == " ".join(r[j] for r in cells).split()
        else:
            assert printed == [r[j] for r in cells if r[j]], column.title


@pytest.fixture(scope="module")
def huge_candidates() -> Table:
    """The real candidate-table definition (its columns) with the values of a large-n
    record: AICs near -1.8e8 (12-13 characters), a ΔAIC of 2.8e7, p values to 5e-171."""
    rng = np.random.default_rng(3)
    x = np.cumsum(rng.standard_normal(2000)) * 1e-3 + rng.standard_normal(2000)
    defined = select_arma(x, fs_hz=10.0).candidate_table()
    assert [c.title for c in defined.columns] == ["#", "model", "AIC", "ΔAIC", "σ_a²", "ρ_a,2",
                                                   "ρ_ax,3", "LB p(10)", "LB p(20)", "white",
                                                   "notes"]
    rows = [(1, "ARMA(1,1)", -176637423.92, 0.0, 1.00069e-12, 0.0011, 0.0002, 0.526, 0.425,
             True, "AR/MA roots nearly cancel"),
            (2, "ARMA(2,1)", -176637421.75, 2.17, 1.00071e-12, 0.0011, 0.0003, 0.423, 0.362,
             True, "AR/MA roots nearly cancel; ar.L2 not significant; did not converge"),
            (3, "AR(3)", -148155074.77, 28482349.15, 1.21e-12, -0.0712, -0.0000, 8.33e-57,
             2.36e-136, False, ""),
            (None, "ARMA(3,2)", None, None, None, None, None, None, None, "failed",
             "fit failed: the optimiser did not converge")]
    return Table.build(defined.title, defined.columns, rows, caption=defined.caption,
                       failed=[(2, 7), (2, 8), (3, 9)], highlight=[0])


@pytest.mark.parametrize("width", WIDTHS)
def test_candidate_table_numbers_stay_whole(huge_candidates: Table, width: int) -> None:
    text = _render(huge_candidates, width)
    assert_whole(huge_candidates, text)
    lines = text.splitlines()
    for number in ("-176637423.92", "+28482349.15", "2.36e-136", "ARMA(2,1)"):
        assert any(f" {number} " in line for line in lines), number
    # the notes wrap (more printed lines than rows), between words: the table then fits
    # as narrow as its whole columns allow, and those alone are wider than 60
    assert len(_body(text)) > len(huge_candidates.rows)
    widest = max(len(line) for line in lines)
    assert widest > width and widest == len(_render(huge_candidates, 20).splitlines()[1])


def _mixed(note: str = "the data only bound this term: treat it as an upper limit") -> Table:
    """A table with each kind of cell: an interval, a signed fixed number, a unit, a missing
    cell, a long file name, and a free-text note."""
    return Table.build(
        "IEEE-952 noise terms of /data/runs/2026-11-28/gyro_x_deg_s.csv",
        (Column("file", numeric=False), Column("term", numeric=False),
         Column("value", digits=6), Column("± stderr", digits=3), Column("68.3 % interval"),
         Column("unit", numeric=False), Column("z", fixed=True, signed=True, digits=2),
         Column("note", numeric=False, wrap=True)),
        [("/data/runs/2026-11-28/gyro_x_deg_s.csv", "N", 0.00200312, 4.45e-06,
          (0.001998, 0.002007), "deg/sqrt(h)", 3.25, ""),
         ("/data/runs/2026-11-28/gyro_x_deg_s.csv", "K", 0.0341, float("nan"),
          (0.0143, 0.04611), "deg/h^1.5", -1.21, note)],
        caption="C_n: the square root of the coefficient of tau^n in sigma^2(tau)")


@pytest.mark.parametrize("width", WIDTHS)
def test_every_kind_of_cell_stays_whole_and_the_note_wraps(width: int) -> None:
    table = _mixed()
    text = _render(table, width)
    assert_whole(table, text)
    assert "0.001998 … 0.002007" in text and "deg/sqrt(h)" in text
    assert len(_body(text)) > len(table.rows)  # the note wraps
    assert "IEEE-952 noise terms of" in text


def test_a_table_that_fits_is_not_widened_and_its_note_not_wrapped() -> None:
    table = _mixed(note="upper limit")
    wide = _render(table, 200).splitlines()
    assert len(_body("\n".join(wide))) == len(table.rows)
    assert max(len(line) for line in wide) < 200
    narrow = Table.build("t", (Column("tau (s)"), Column("dev", digits=5)),
                         [(0.1, 0.37919), (3276.8, 0.01117)])
    assert max(len(line) for line in _render(narrow, 60).splitlines()) < 60


def test_a_free_text_word_is_never_folded() -> None:
    """A note's longest word (a number in a note, a path) keeps the column at least that
    wide: words are never folded across lines."""
    word = "z(C²)=1.2345678901234567890"
    table = Table.build("t", (Column("x"), Column("note", numeric=False, wrap=True)),
                        [(1.5, f"limit {word} here")])
    text = _render(table, 20)
    assert any(word in line for line in text.splitlines())
    assert_whole(table, text)


@pytest.mark.parametrize("quiet_json", [None, "-"])
def test_print_out_does_not_crop_a_table_wider_than_the_terminal(
        huge_candidates: Table, monkeypatch: pytest.MonkeyPatch, quiet_json: str | None) -> None:
    """The commands print through print_out: a line longer than the console is kept whole
    (the console would otherwise cut it at its width), on stdout or, with --json -, stderr."""
    out = Console(width=60, file=io.StringIO(), color_system=None)
    monkeypatch.setattr(common, "console" if quiet_json is None else "err_console", out)
    common.print_out(rich_table(huge_candidates), quiet_json=quiet_json)
    text = out.file.getvalue()  # type: ignore[attr-defined]
    assert_whole(huge_candidates, text)
    assert all(line.endswith(("│", "┃", "┓", "┩", "┘")) for line in text.splitlines()
               if line.startswith(("│", "┃", "┏", "┡", "└")))


@pytest.mark.parametrize("width", WIDTHS)
def test_batch_failed_runs_keep_the_file_name_whole(width: int) -> None:
    path = "/data/fog/campaign_2026-11/site_B/gyro_x_deg_s_run_00042.csv.gz"
    table = _failed_runs_table([{"file": path, "axis": None,
                                 "error": f"'{path}' has a header (a, b) but no data rows"}])
    text = _render(table, width)
    assert_whole(table, text)
    assert any(f" {path} " in line for line in text.splitlines())


def test_select_on_a_60_column_pipe(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    """``fogts select`` end to end on a console 60 columns wide: each candidate's model,
    AIC and ΔAIC on one line each, as in its JSON (formatted as the table formats them)."""
    rng = np.random.default_rng(5)
    n = 4000
    x = 1e-9 * (np.cumsum(rng.standard_normal(n)) * 1e-2 + rng.standard_normal(n))
    path, out_json = tmp_path / "fog.csv", tmp_path / "s.json"
    pd.DataFrame({"time": np.arange(n) / 10.0, "rate_deg_h": x}).to_csv(path, index=False)
    monkeypatch.setattr(common, "console", Console(width=60, highlight=False,
                                                    color_system=None))
    res = CliRunner().invoke(app, ["select", str(path), "--json", str(out_json)])
    assert res.exit_code in (0, 1), res.output
    start = res.stdout.index("┏")
    printed = res.stdout[start:res.stdout.index("┘", start) + 1]
    candidates = json.loads(out_json.read_text())["candidates"]
    best = min(c["aic"] for c in candidates if c["white"]) if any(
        c["white"] for c in candidates) else candidates[0]["aic"]
    assert _header(printed)[0][:4] == ["#", "model", "AIC", "ΔAIC"]
    body = _body(printed)
    assert [r[1] for r in body if r[1]] == [c["model"] for c in candidates]
    assert [r[2] for r in body if r[2]] == [f"{c['aic']:.2f}" for c in candidates]
    assert [r[3] for r in body if r[3]] == [f"{c['aic'] - best:+.2f}" for c in candidates]
    assert all(len(r[2]) >= 10 for r in body if r[2])  # e.g. -153916.61: 10 characters
    assert max(len(line) for line in printed.splitlines()) > 60
