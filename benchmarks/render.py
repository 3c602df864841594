"""Markdown of a result: the tables of ``benchmarks/README.md`` and ``benchmarks/results/``,
the comparison table of ``--compare``, and the lines that name each regression."""

from __future__ import annotations

import os
import tempfile
import time
from collections.abc import Callable
from pathlib import Path
from typing import Any

from benchmarks.compare import Row, regressed
from benchmarks.environment import library_versions, load_average, machine_info
from benchmarks.metric import DEFAULT_TOLERANCE, Metric


def fmt(v: Any, digits: int = 3) -> str:
    """A table cell: ``digits`` significant digits, no trailing zeros, ``-`` for None."""
    if v is None:
        return "-"
    if isinstance(v, bool):
        return str(v)
    if isinstance(v, int):
        return str(v)
    if isinstance(v, float):
        if v != v:
            return "nan"
        if v == 0:
            return "0"
        if abs(v) >= 1e4 or abs(v) < 1e-3:
            return f"{v:.{digits}g}"
        return f"{v:.{digits}g}" if abs(v) < 1 else f"{v:.{max(digits - 1, 1)}f}".rstrip(
            "0").rstrip(".")
    return str(v)


def _md_escape(text: str) -> str:
    return str(text).replace("|", "\\|").replace("\n", " ")


def _header(doc: dict[str, Any]) -> list[str]:
    """The line naming the machine, the versions and the date (and quick mode)."""
    m = doc.get("machine", {})
    libs = ", ".join(f"{k} {val}" for k, val in doc.get("versions", {}).items() if val)
    if m:
        return [f"Measured {doc.get('date', '?')} on {m.get('cpu', '?')} "
                f"({m.get('cores', '?')} cores, {m.get('memory_gib', '?')} GiB, load average "
                f"{fmt((m.get('loadavg_at_start') or [None])[0])} at start), Python "
                f"{m.get('python', '?')}; {libs}."
                + (" Quick mode (smaller problems)." if doc.get("quick") else ""), ""]
    return ["Quick mode (smaller problems).", ""] if doc.get("quick") else []


def _speed_table(speed: list[Metric]) -> list[str]:
    lines = ["| speed | fogts (s) | peer (s) | ratio | CPU-time ratio |",
             "|---|---:|---:|---:|---:|"]
    for x in speed:
        secs = x.get("seconds", {})
        peer = next((k for k in secs if k != "fogts"), "peer")
        cpu = x.get("cpu_value")
        cpu_cell = "-" if cpu is None else f"{fmt(cpu)}x"
        title = x["title"] + (" (parallel)" if x.get("parallel") else "")
        lines.append(f"| {_md_escape(title)} | {fmt(secs.get('fogts'))} | "
                     f"{fmt(secs.get(peer))} ({_md_escape(peer)}) | "
                     f"**{fmt(x['value'])}x** | {cpu_cell} |")
    return [*lines, ""]


def _accuracy_table(acc: list[Metric]) -> list[str]:
    lines = ["| accuracy | value | better |", "|---|---:|---|"]
    for x in acc:
        unit = f" {x['unit']}" if x.get("unit") else ""
        lines.append(f"| {_md_escape(x['title'])} | {fmt(x['value'])}{_md_escape(unit)} "
                     f"| {x['better']} |")
    return [*lines, ""]


def render_markdown(doc: dict[str, Any]) -> str:
    """The result as markdown: a header line (machine, versions, date) and one table per kind."""
    lines = _header(doc)
    speed = [x for x in doc.get("metrics", []) if x["kind"] == "speed"]
    acc = [x for x in doc.get("metrics", []) if x["kind"] == "accuracy"]
    if speed:
        lines += _speed_table(speed)
    if acc:
        lines += _accuracy_table(acc)
    bad = {k: s for k, s in doc.get("suites", {}).items() if s["status"] != "ok"}
    for name, s in bad.items():
        first = s["error"].splitlines()[0] if s.get("error") else ""
        lines.append(f"- suite `{name}`: {s['status']} {_md_escape(first)}")
    return "\n".join(lines).rstrip() + "\n"


def render_comparison(rows: list[Row]) -> str:
    """The ``--compare`` table: one line per figure with its basis, both values and verdict."""
    lines = ["| figure | compared | old | new | worse by | verdict |",
             "|---|---|---:|---:|---:|---|"]
    for r in rows:
        change = "-" if r["change"] is None else f"{100 * r['change']:+.1f} %"
        lines.append(f"| {_md_escape(r['title'])} | {r.get('basis', '')} | {fmt(r['old'])} | "
                     f"{fmt(r['new'])} | {change} | {r['verdict']} |")
    return "\n".join(lines) + "\n"


def report_regressions(rows: list[Row], log: Callable[[str], None]) -> int:
    """Log one line per regressed or missing figure; return how many there are."""
    bad = regressed(rows)
    for r in bad:
        if r["verdict"] == "MISSING":
            log(f"MISSING {r['id']} ({r['title']}): measured before, not now")
        else:
            log(f"REGRESSION {r['id']} ({r['title']}): {r['basis']} {fmt(r['old'])} -> "
                f"{fmt(r['new'])}, worse by {100 * r['change']:.1f} % (tolerance "
                f"{100 * r.get('tolerance', DEFAULT_TOLERANCE):.0f} %)")
    if bad:
        log(f"{len(bad)} figure(s) got worse by more than their tolerance or went missing")
    return len(bad)


def measured_markdown(run: Callable[[], list[Metric]], *, quick: bool,
                      how: str = "ratios are paired, best of the rounds") -> str:
    """Run ``run()`` and render its figures with the machine, versions, date and the load
    average at start and end (a single-suite script's table)."""
    start = machine_info()
    figures = run()
    load_end = load_average()
    text = render_markdown({
        "metrics": figures, "quick": quick, "machine": start, "versions": library_versions(),
        "date": time.strftime("%Y-%m-%dT%H:%M:%SZ", time.gmtime())})
    return text + (f"\nLoad average at start {start.get('loadavg_at_start')}, at end "
                   f"{load_end} (the machine is shared; {how}).\n")


def write_atomic(path: Path, text: str) -> None:
    """Write ``text`` to ``path`` through a temporary file, so a reader never sees half of it."""
    path.parent.mkdir(parents=True, exist_ok=True)
    fd, tmp = tempfile.mkstemp(prefix=f".{path.name}.", suffix=".tmp", dir=path.parent)
    with os.fdopen(fd, "w", encoding="utf-8") as fh:
        fh.write(text)
    umask = os.umask(0)
    os.umask(umask)
    os.chmod(tmp, 0o666 & ~umask)  # mkstemp makes 0600; a result file is for everyone
    os.replace(tmp, path)


def write_table(text: str, target: Path | None) -> None:
    """Write a markdown table to ``target`` with a final newline (nothing when None)."""
    if target is not None:
        write_atomic(target, text if text.endswith("\n") else text + "\n")
