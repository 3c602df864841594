"""No output ever replaces an input, nor without --overwrite an existing data file: every
output option of every command is checked against the command's inputs and the files that
exist before any analysis runs, through one shared check
(:func:`fogts.io.paths.check_outputs`).  Each attempt exits 2 with one ``error:`` line naming
the output option and the file, and leaves the file byte-identical (by hash)."""

from __future__ import annotations

import hashlib
import inspect
import os
from pathlib import Path
from typing import Any

import numpy as np
import pytest
import typer.main
from typer.testing import CliRunner

from fogts.cli import _hoist_global_flags, app, main
from fogts.cli._outputs import NO_OUTPUTS, Outputs, writes_outputs
from fogts.errors import DataError
from fogts.io.paths import check_outputs
from tests.conftest import error_output

runner = CliRunner()


def _digest(path: Path) -> str:
    return hashlib.sha256(path.read_bytes()).hexdigest()


@pytest.fixture
def recording(tmp_path: Path) -> Path:
    """A small 100 Hz record with a named unit (no unit warning in these tests)."""
    rng = np.random.default_rng(20261124)
    t = np.arange(6000) / 100.0
    path = tmp_path / "X.csv"
    np.savetxt(path, np.c_[t, rng.standard_normal(t.size)], delimiter=",",
               header="time,rate_deg_h", comments="")
    return path


# The six overwrite attempts measured on main before the fix (each replaced the input).
SIX_ATTEMPTS = [
    (["allan", "{x}", "--csv", "{x}"], "--csv"),
    (["allan", "{x}", "--json", "{x}"], "--json"),
    (["select", "{x}", "--json", "{x}"], "--json"),
    (["select", "{x}", "--predict", "{x}"], "--predict"),
    (["filter", "{x}", "-o", "{x}", "--method", "moving-average", "--window", "1"],
     "--output"),
    (["report", "{x}", "-o", "{x}"], "--output"),
]


@pytest.mark.parametrize(("args", "option"), SIX_ATTEMPTS)
def test_output_never_replaces_the_input(recording: Path, args: list[str], option: str) -> None:
    before = _digest(recording)
    res = runner.invoke(app, [a.format(x=recording) for a in args])
    assert res.exit_code == 2
    lines = res.stderr.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith(f"error: {option} ")
    assert "is the input FILE" in lines[0] and "never replaces an input" in lines[0]
    assert "Traceback" not in res.output + res.stderr
    assert _digest(recording) == before


@pytest.mark.parametrize("alias", ["symlink", "hardlink", "dotdot"])
def test_aliases_of_the_input_are_seen_through(recording: Path, alias: str) -> None:
    before = _digest(recording)
    if alias == "symlink":
        out = recording.with_name("link.csv")
        out.symlink_to(recording)
    elif alias == "hardlink":
        out = recording.with_name("hard.csv")
        os.link(recording, out)
    else:
        (recording.parent / "sub").mkdir()
        out = recording.parent / "sub" / ".." / recording.name
    res = runner.invoke(app, ["allan", str(recording), "--csv", str(out)])
    assert res.exit_code == 2
    assert f"error: --csv {str(out)!r} is the input FILES {str(recording)!r}" in res.stderr
    assert _digest(recording) == before


def test_other_commands_protect_their_inputs(recording: Path, tmp_path: Path) -> None:
    before = _digest(recording)
    cases = [
        (["info", str(recording), "--json", str(recording)], "--json"),
        (["davar", str(recording), "--json", str(recording), "--window", "10s",
          "--step", "5s"], "--json"),
        (["compensate", str(recording), "--save-model", str(recording)], "--save-model"),
        (["batch", str(recording), "-o", str(recording)], "--output"),
    ]
    for args, option in cases:
        res = runner.invoke(app, args)
        assert res.exit_code == 2, args
        assert error_output(res.stderr).startswith(f"error: {option} "), res.stderr
        assert "never replaces an input" in res.stderr
    assert _digest(recording) == before


def test_simulate_sidecar_never_replaces_its_from_json_input(tmp_path: Path) -> None:
    out = tmp_path / "Y.csv"
    assert runner.invoke(app, ["simulate", "noise", "-o", str(out), "--N", "0.1",
                               "--duration", "10s"]).exit_code == 0
    sidecar = tmp_path / "Y.csv.json"
    before = _digest(sidecar)
    res = runner.invoke(app, ["simulate", "noise", "-o", str(out), "--from-json", str(sidecar),
                              "--duration", "10s", "--overwrite"])   # never over an input
    assert res.exit_code == 2
    assert "--output's sidecar" in res.stderr and "is the input --from-json" in res.stderr
    assert _digest(sidecar) == before


EXISTING = "already exists; fogts replaces an existing data file only with --overwrite"


def test_simulate_replaces_an_existing_file_only_with_overwrite(recording: Path,
                                                                 tmp_path: Path) -> None:
    """A simulated record looks like a recording: ``-o`` over an existing file (a recording,
    a file in the sidecar's name, or a simulation's own output) is refused and the file
    left byte-identical; with --overwrite its own output is replaced."""
    sim = ["simulate", "noise", "--N", "0.1", "--duration", "10s", "-o"]
    before = _digest(recording)
    res = runner.invoke(app, [*sim, str(recording)])
    assert res.exit_code == 2, res.output
    assert error_output(res.stderr) == f"error: --output '{recording}' {EXISTING}: choose " \
        "another output name, or pass --overwrite if that file is fogts' own output to be " \
        "replaced"
    assert _digest(recording) == before and not Path(f"{recording}.json").exists()

    user_json = tmp_path / "new.csv.json"                    # the sidecar name taken
    user_json.write_text('{"mine": true}\n')
    res = runner.invoke(app, [*sim, str(tmp_path / "new.csv")])
    assert res.exit_code == 2
    assert error_output(res.stderr).startswith(f"error: --output's sidecar '{user_json}' "
                                               f"{EXISTING}")
    assert user_json.read_text() == '{"mine": true}\n' and not (tmp_path / "new.csv").exists()

    out = tmp_path / "sim.csv"
    assert runner.invoke(app, [*sim, str(out)]).exit_code == 0
    first = _digest(out)
    res = runner.invoke(app, [*sim[:-1], "--seed", "5", "-o", str(out)])
    assert res.exit_code == 2 and EXISTING in res.stderr and _digest(out) == first
    res = runner.invoke(app, [*sim[:-1], "--seed", "5", "--overwrite", "-o", str(out)])
    assert res.exit_code == 0, res.output
    assert _digest(out) != first


@pytest.mark.parametrize(("args", "option"), [
    (["allan", "{x}", "--json", "{y}"], "--json"),
    (["allan", "{x}", "--csv", "{y}"], "--csv"),
    (["select", "{x}", "--predict", "{y}"], "--predict"),
    (["filter", "{x}", "-o", "{y}", "--method", "moving-average", "--window", "1"],
     "--output"),
    (["info", "{x}", "--json", "{y}"], "--json"),
])
def test_an_existing_data_file_is_replaced_only_with_overwrite(
        recording: Path, tmp_path: Path, args: list[str], option: str) -> None:
    """The audit's case: another recording named as an output was replaced; now it is
    refused unless --overwrite is given (then it is replaced, atomically)."""
    other = tmp_path / "Y.csv"
    other.write_bytes(recording.read_bytes())
    before = _digest(other)
    filled = [a.format(x=recording, y=other) for a in args]
    res = runner.invoke(app, filled)
    assert res.exit_code == 2
    assert error_output(res.stderr).startswith(f"error: {option} '{other}' {EXISTING}")
    assert _digest(other) == before
    res = runner.invoke(app, [*filled, "--overwrite"])
    assert res.exit_code == 0, res.output
    assert _digest(other) != before


def test_figures_and_reports_are_replaced_and_batch_resume_keeps_its_summary(
        recording: Path, tmp_path: Path) -> None:
    """A figure or an HTML page is never read as input, so it is replaced without
    --overwrite; ``batch --resume`` rewrites its own summary."""
    png, html = tmp_path / "a.png", tmp_path / "r.html"
    png.write_bytes(b"old"), html.write_text("old")
    assert runner.invoke(app, ["allan", str(recording), "--plot", str(png)]).exit_code == 0
    assert png.read_bytes()[:4] == b"\x89PNG"
    res = runner.invoke(app, ["report", str(recording), "-o", str(html)])
    assert res.exit_code == 0, res.output
    assert html.read_text().startswith("<!DOCTYPE html>")
    summary = tmp_path / "s.csv"
    batch = ["batch", str(recording), "-o", str(summary), "--no-select", "--workers", "1"]
    assert runner.invoke(app, batch).exit_code == 0
    res = runner.invoke(app, batch)
    assert res.exit_code == 2 and f"error: --output '{summary}' {EXISTING}" in res.stderr
    assert runner.invoke(app, [*batch, "--resume"]).exit_code == 0
    assert runner.invoke(app, [*batch, "--overwrite"]).exit_code == 0


def test_special_file_and_duplicate_outputs_are_refused(recording: Path, tmp_path: Path) -> None:
    res = runner.invoke(app, ["info", str(recording), "--json", "/dev/null"])
    assert res.exit_code == 2
    assert "error: --json '/dev/null' is a character device, not a regular file" in res.stderr
    assert "use '-' for standard output" in res.stderr
    res = runner.invoke(app, ["allan", str(recording), "--json", str(tmp_path / "a.csv"),
                              "--csv", str(tmp_path / "a.csv")])
    assert res.exit_code == 2 and "name the same file" in res.stderr
    res = runner.invoke(app, ["allan", str(recording), "--csv", str(tmp_path / "no" / "a.csv")])
    assert res.exit_code == 2 and "does not exist; create it first" in res.stderr
    res = runner.invoke(app, ["allan", str(recording), "--json", str(tmp_path)])
    assert res.exit_code == 2 and "is a directory, not a regular file" in res.stderr


def test_check_outputs_library_errors(tmp_path: Path) -> None:
    src = tmp_path / "in.csv"
    src.write_text("t,rate\n")
    with pytest.raises(DataError, match=r"--csv '.*in\.csv' is the input FILE '.*in\.csv'"):
        check_outputs({"--csv": src}, {"FILE": [src]})
    with pytest.raises(DataError, match=r"--x '.*o\.csv' and --y '.*o\.csv' name the same"):
        check_outputs({"--y": tmp_path / "o.csv", "--x": tmp_path / "o.csv"}, {})
    check_outputs({"--json": "-", "--csv": None}, {"FILE": [src]})  # nothing to check
    check_outputs({"--csv": tmp_path / "new.csv"}, {"FILE": [tmp_path / "absent.csv"]})
    with pytest.raises(DataError, match=r"--csv '.*in\.csv' already exists; fogts replaces"):
        check_outputs({"--csv": src}, {})
    check_outputs({"--csv": src}, {}, overwrite=True)
    check_outputs({"--plot": tmp_path / "in.csv.png"}, {})  # absent: nothing to check


def test_debug_and_version_after_the_command(recording: Path,
                                             capsys: pytest.CaptureFixture[str]) -> None:
    assert _hoist_global_flags(["info", "x", "--debug"]) == ["--debug", "info", "x"]
    # the value of an option that takes one is left alone
    assert _hoist_global_flags(["report", "x", "--title", "--debug"]) == \
        ["report", "x", "--title", "--debug"]
    assert _hoist_global_flags(["select", "x", "--", "--debug"]) == \
        ["select", "x", "--", "--debug"]
    with pytest.raises(SystemExit) as exc:
        main(["info", str(recording), "--version"])
    assert exc.value.code == 0 and capsys.readouterr().out.startswith("fogts ")
    with pytest.raises(DataError, match="file not found"):  # --debug: the exception itself
        main(["info", str(recording.with_name("absent.csv")), "--debug"])


@pytest.mark.parametrize("name", ["", "/"])
def test_simulate_output_without_a_file_name(name: str) -> None:
    res = runner.invoke(app, ["simulate", "noise", "-o", name, "--N", "0.1", "--duration", "10s"])
    assert res.exit_code == 2
    assert error_output(res.stderr).endswith("is a directory, not a regular file; outputs are "
                                             "written to new or regular files only")
    assert "Traceback" not in res.output + res.stderr


def test_main_turns_any_escaped_exception_into_one_line(
        monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]) -> None:
    import fogts.cli

    def broken(**_: object) -> None:
        raise ValueError("a bug outside every guard")

    monkeypatch.setattr(fogts.cli, "app", broken)
    monkeypatch.setattr(fogts.cli, "_hoist_global_flags", lambda argv: argv)
    # The app's callback, which sets --debug, never runs here: an earlier test's --debug
    # on the same worker must not leak in.
    monkeypatch.setitem(fogts.cli._common._STATE, "debug", False)
    with pytest.raises(SystemExit) as exc:
        main(["info", "x.csv"])
    assert exc.value.code == 2
    assert capsys.readouterr().err == "error: a bug outside every guard\n"


@pytest.mark.parametrize("args", [
    ["filter", "{rec}", "-o", "{tmp}/f.csv", "--model", "AR(1)", "--json", "{tmp}/o.json",
     "--plot", "{tmp}/fig.txt"],
    ["compensate", "{rec}", "--no-emd", "-o", "{tmp}/f.csv", "--json", "{tmp}/o.json",
     "--plot", "{tmp}/fig.txt"],
    ["davar", "{rec}", "--window", "60s", "--step", "30s", "--json", "{tmp}/o.json",
     "--plot", "{tmp}/fig.txt"],
    ["northfind", "--simulate", "2", "--latitude", "45", "--json", "{tmp}/o.json",
     "--plot", "{tmp}/fig.txt"],
])
def test_a_bad_plot_name_is_refused_before_any_output(tmp_path: Path, args: list[str]) -> None:
    """filter, compensate, davar and northfind wrote --json (and -o) and then refused the
    --plot name: the one-line error must leave no output behind."""
    import pandas as pd

    rng = np.random.default_rng(14)
    n = 3000
    rec = tmp_path / "rec.csv"
    pd.DataFrame({"time": np.arange(n) / 10.0, "rate_deg_h": rng.normal(size=n),
                  "T": 20.0 + np.linspace(0.0, 5.0, n)}).to_csv(rec, index=False)
    argv = [a.replace("{rec}", str(rec)).replace("{tmp}", str(tmp_path)) for a in args]
    res = CliRunner().invoke(app, argv)
    assert res.exit_code == 2
    assert error_output(res.stderr) == "error: --plot must end in .png, .svg or .pdf; got 'fig.txt'"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["rec.csv"]


def test_writes_outputs_hands_the_command_one_outputs_argument() -> None:
    """``writes_outputs`` shows typer ``json_out`` and ``overwrite`` in place of ``out`` and
    calls the command with their values as one :class:`Outputs`."""
    seen: list[Outputs] = []

    def command(file: str, out: Outputs = NO_OUTPUTS, last: int = 0) -> None:
        seen.append(out)

    wrapped = writes_outputs()(command)
    assert list(inspect.signature(wrapped).parameters) == ["file", "json_out", "overwrite", "last"]
    wrapped("x", json_out="-", overwrite=True, last=1)
    assert seen == [Outputs(json="-", overwrite=True)]
    no_json = writes_outputs(json=False)(command)
    assert list(inspect.signature(no_json).parameters) == ["file", "overwrite", "last"]
    no_json("x", overwrite=False)
    assert seen[-1] == Outputs(json=None, overwrite=False)


def test_every_command_takes_overwrite_and_the_json_writers_json() -> None:
    """The shared output options reach every command's command line."""
    group: Any = typer.main.get_command(app)
    names: dict[str, set[str]] = {}
    for name, cmd in group.commands.items():
        subs = cmd.commands.items() if hasattr(cmd, "commands") else [(None, cmd)]
        for sub, leaf in subs:
            names[f"{name} {sub}" if sub else name] = {o for p in leaf.params for o in p.opts}
    assert all("--overwrite" in opts for opts in names.values()), names
    with_json = {n for n, opts in names.items() if "--json" in opts}
    assert with_json == {"allan", "compensate", "curve", "davar", "filter", "info",
                         "northfind", "select"}
