"""The command lines: ``python -m benchmarks`` (every suite, one JSON result, a markdown
table, ``--compare``) and the one every ``python -m benchmarks.<suite>`` script shares."""

from __future__ import annotations

import argparse
import json
import sys
from collections.abc import Callable
from pathlib import Path
from typing import Any

from benchmarks.compare import Row, compare, merge_best
from benchmarks.metric import Metric
from benchmarks.render import (
    measured_markdown,
    render_comparison,
    render_markdown,
    report_regressions,
    write_atomic,
    write_table,
)
from benchmarks.suites import (
    SUITES,
    Suite,
    merge_results,
    run_in_this_process,
    run_suite,
    run_suites,
    suite_named,
)

Log = Callable[[str], None]


def _parser() -> argparse.ArgumentParser:
    p = argparse.ArgumentParser(prog="python -m benchmarks",
                                description="Run the fogts benchmark suites; compare the "
                                            "result with a baseline.")
    p.add_argument("--quick", action="store_true", help="small problems (a CI smoke run)")
    p.add_argument("--out", type=Path, help="write the JSON result here")
    p.add_argument("--md", type=Path, help="write the markdown table here")
    p.add_argument("--compare", type=Path, metavar="OLD_JSON",
                   help="flag figures worse than OLD_JSON's by more than their tolerance; "
                        "exit 1 if any")
    p.add_argument("--confirm", type=int, default=2,
                   help="re-measure a suite with a flagged speed figure up to N times")
    p.add_argument("--only", help="comma-separated suite names (default: all): "
                   + ", ".join(s.name for s in SUITES))
    p.add_argument("--update", type=Path, metavar="JSON",
                   help="start from this result and replace only the suites run now (with "
                        "--only: re-measure one suite of a full result)")
    p.add_argument("--against", type=Path, metavar="NEW_JSON",
                   help="with --compare: compare this stored result instead of running")
    p.add_argument("--render", type=Path, metavar="JSON",
                   help="do not run anything: render JSON as markdown (to --md or stdout)")
    p.add_argument("--timeout", type=float, default=None,
                   help="seconds allowed per suite (default: none; 600 with --quick)")
    p.add_argument("--jobs", type=int, default=1,
                   help="run N suites at once (faster smoke runs; noisier ratios)")
    p.add_argument("--list", action="store_true", help="list the suites and exit")
    p.add_argument("--child", help=argparse.SUPPRESS)
    p.add_argument("--child-out", help=argparse.SUPPRESS)
    return p


def _log(msg: str) -> None:
    print(msg, file=sys.stderr, flush=True)


def _list_suites() -> int:
    for s in SUITES:
        state = "" if s.module_path().exists() else "  (module missing)"
        print(f"{s.name:<18} {s.description}{state}")
    return 0


def _render(source: Path, md: Path | None) -> int:
    text = render_markdown(json.loads(source.read_text()))
    if md:
        write_atomic(md, text)
    else:
        sys.stdout.write(text)
    return 0


def _selected(only: str | None) -> list[Suite] | None:
    """The suites ``--only`` names (all without it); None, after a message, if one is unknown."""
    if not only:
        return list(SUITES)
    names = [n.strip() for n in only.split(",") if n.strip()]
    unknown = [n for n in names if n not in {s.name for s in SUITES}]
    if unknown:
        _log(f"error: unknown suite(s) {', '.join(unknown)}; suites are: "
             f"{', '.join(s.name for s in SUITES)}")
        return None
    return [s for s in SUITES if s.name in names]


def _confirmed_rows(doc: dict[str, Any], old: dict[str, Any], *, quick: bool, confirm: int,
                    timeout: float | None) -> list[Row]:
    """Compare ``doc`` with ``old``, re-measuring suites with a flagged speed figure.

    Up to ``confirm`` times, every suite with a speed figure flagged as a regression runs
    again and :func:`~benchmarks.compare.merge_best` keeps the measurement closest to ``old``.
    """
    rows = compare(doc, old)
    for attempt in range(max(0, confirm)):
        flagged = {r["id"] for r in rows if r["verdict"] == "REGRESSION"}
        again = sorted({m["suite"] for m in doc["metrics"]
                        if m["id"] in flagged and m["kind"] == "speed"})
        if not again:
            break
        _log(f"== re-measuring {', '.join(again)} (speed regression flagged; attempt "
             f"{attempt + 1} of {confirm})")
        for name in again:
            status, metrics = run_suite(suite_named(name), quick, timeout)
            if status["status"] == "ok":
                merge_best(doc, metrics, old)
        rows = compare(doc, old)
    return rows


def _report(doc: dict[str, Any], args: argparse.Namespace, rows: list[Row] | None) -> int:
    """Print and write the result; return the exit code (1 if a suite failed or regressed)."""
    text = render_markdown(doc)
    print(text)
    if args.out:
        write_atomic(args.out, json.dumps(doc, indent=2, allow_nan=True) + "\n")
    if args.md:
        write_atomic(args.md, text)
    failed = [n for n, s in doc["suites"].items() if s["status"] == "failed"]
    code = 0
    if failed:
        _log(f"FAILED suite(s): {', '.join(failed)}")
        code = 1
    if rows is not None:
        print(render_comparison(rows))
        if report_regressions(rows, _log):
            code = 1
        else:
            _log(f"no regression against {args.compare}")
    return code


def main(argv: list[str] | None = None) -> int:
    """Entry point; returns the exit code (0 ok, 1 regression or failed suite, 2 usage)."""
    args = _parser().parse_args(argv)
    if args.child:
        return run_in_this_process(args.child, args.quick, args.child_out)
    if args.list:
        return _list_suites()
    if args.render:
        return _render(args.render, args.md)
    suites = _selected(args.only)
    if suites is None:
        return 2
    old = json.loads(args.compare.read_text()) if args.compare else None
    timeout = args.timeout if args.timeout is not None else (600.0 if args.quick else None)
    if args.against is not None:
        if old is None:
            _log("error: --against needs --compare OLD_JSON")
            return 2
        rows = compare(json.loads(args.against.read_text()), old)
        print(render_comparison(rows))
        return 1 if report_regressions(rows, _log) else 0
    doc = run_suites(suites, quick=args.quick, timeout_s=timeout, log=_log,
                     jobs=max(1, args.jobs))
    if args.update is not None:
        doc = merge_results(json.loads(args.update.read_text()), doc)
    confirmed = None if old is None else _confirmed_rows(doc, old, quick=args.quick,
                                                         confirm=args.confirm, timeout=timeout)
    return _report(doc, args, confirmed)


def script_main(doc: str | None, metrics: Callable[[bool], list[Metric]],
                argv: list[str] | None = None, *, quick_help: str = "smaller problems",
                default_out: Path | None = None) -> int:
    """The command line every single-suite benchmark script shares.

    ``--quick`` passes ``quick=True`` to ``metrics``; the markdown table is printed and
    written to ``--out`` (or, for a full run, ``default_out``).
    """
    p = argparse.ArgumentParser(description=(doc or "").split("\n")[0])
    p.add_argument("--quick", action="store_true", help=quick_help)
    hint = f" (default {default_out} for a full run)" if default_out is not None else ""
    p.add_argument("--out", type=Path, default=None,
                   help=f"also write the markdown table to this file{hint}")
    args = p.parse_args(argv)
    text = measured_markdown(lambda: metrics(args.quick), quick=args.quick)
    print(text)
    write_table(text, args.out if args.out is not None else (None if args.quick else default_out))
    return 0
