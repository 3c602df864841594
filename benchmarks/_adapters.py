"""Adapters for benchmark scripts that print a table instead of returning metrics.

``benchmarks/bench_emd_kalman.py`` prints ``| task | fogts | peer | peer time / fogts time |``
rows.  :func:`emd_kalman` runs its ``main`` with ``--quick`` when asked, reads that table and
turns each row with a ratio into a speed metric (the seconds are taken from the first time
in the fogts and peer cells).  If the module grows a ``metrics(quick)`` function, that is used
instead.
"""

from __future__ import annotations

import contextlib
import importlib
import io
import re
import sys
from typing import Any

from benchmarks._runner import Metric, speed_metric

_TIME = re.compile(r"([0-9]*\.?[0-9]+(?:e[-+]?[0-9]+)?)\s*(ms|s)\b")
_RATIO = re.compile(r"^\s*([0-9]*\.?[0-9]+(?:e[-+]?[0-9]+)?)x\s*$")


def _seconds(cell: str) -> float | None:
    m = _TIME.search(cell)
    if not m:
        return None
    value = float(m.group(1))
    return value / 1000.0 if m.group(2) == "ms" else value


def _slug(text: str) -> str:
    return re.sub(r"[^a-z0-9]+", "_", text.lower()).strip("_")


def table_metrics(text: str, *, prefix: str, quick: bool) -> list[Metric]:
    """Speed metrics from a ``| task | fogts | peer | ratio |`` markdown table."""
    out: list[Metric] = []
    for line in text.splitlines():
        cells = [c.strip() for c in line.strip().strip("|").split("|")]
        if len(cells) != 4 or not _RATIO.match(cells[3]):
            continue
        task, ours, peer, ratio = cells
        t_ours, t_peer = _seconds(ours), _seconds(peer)
        peer_name = peer.split()[0] if peer else "peer"
        if t_ours is None or t_peer is None:
            continue
        m = speed_metric(f"speed.{prefix}.{_slug(task)}" + (".quick" if quick else ""),
                         f"{task} (fogts: {ours}; peer: {peer})", fogts_s=t_ours,
                         peer_s=t_peer, peer=peer_name)
        m["details"]["printed_ratio"] = float(_RATIO.match(ratio).group(1))  # type: ignore[union-attr]
        out.append(m)
    return out


def emd_kalman(quick: bool) -> list[Metric]:
    """EMD, Kalman filter and thermal-fit speed (``benchmarks/bench_emd_kalman.py``)."""
    mod: Any = importlib.import_module("benchmarks.bench_emd_kalman")
    if callable(getattr(mod, "metrics", None)):
        return mod.metrics(quick)  # type: ignore[no-any-return]
    buf = io.StringIO()
    argv = sys.argv
    sys.argv = ["bench_emd_kalman.py", *(["--quick"] if quick else [])]
    try:
        with contextlib.redirect_stdout(buf):
            mod.main()
    finally:
        sys.argv = argv
    metrics = table_metrics(buf.getvalue(), prefix="emd_kalman", quick=quick)
    if not metrics:
        raise RuntimeError("bench_emd_kalman printed no '| task | fogts | peer | ratio |' row "
                           "with a ratio:\n" + buf.getvalue()[-2000:])
    return metrics
