"""The figures a suite returns: one dict per speed or accuracy metric.

Fields of a metric (``--out`` stores them as they are)::

    {"id", "suite", "title", "kind": "speed"|"accuracy", "value", "unit",
     "better": "higher"|"lower", "tolerance", "abs_tolerance",
     "seconds": {name: s}, "details": {...},
     # speed figures only:
     "cpu_value", "cpu_seconds": {name: s}, "parallel": bool,
     "other_load": cores, "noise": {"rounds", "spread_wall", "spread_cpu"}}

* A **speed** metric's value is a ratio measured in one run: peer seconds / fogts seconds
  (higher is better), from the best wall time of each side.  ``cpu_value`` is the same
  ratio from the best CPU times (process time of the calls).  Absolute seconds are stored
  and shown, never compared.  ``other_load`` is how many cores other processes kept busy
  while the figure was timed (``/proc/stat``); ``noise`` the spread of the ratio over the
  timed rounds (information only: it does not widen the tolerance).
* An **accuracy** metric is an error (lower is better) or a rate (higher is better) measured
  on simulated data with fixed seeds (the same value on every run of the same code), or a
  memory multiple, or a CPU time without a peer.
* Metric ids carry the problem size (``speed.oadev.n=1e7``), so a ``--quick`` run and a full
  run never compare figures of different sizes.
"""

from __future__ import annotations

from typing import Any

#: A figure is flagged when it got worse than the baseline by more than this share.
DEFAULT_TOLERANCE = 0.10

Metric = dict[str, Any]


def speed_metric(id: str, title: str, *, fogts_s: float, peer_s: float, peer: str,
                 suite: str = "", tolerance: float = DEFAULT_TOLERANCE,
                 fogts_cpu_s: float | None = None, peer_cpu_s: float | None = None,
                 parallel: bool = False, other_load: float | None = None,
                 noise: dict[str, Any] | None = None,
                 details: dict[str, Any] | None = None) -> Metric:
    """A speed figure: ``peer_s / fogts_s`` ("x faster than the peer"; higher is better).

    ``fogts_cpu_s`` / ``peer_cpu_s`` are the CPU times of the same calls (process time, all
    threads); their ratio is ``cpu_value``.  ``parallel`` says that a contender may use more
    than one thread; ``other_load`` is the number of cores other processes kept busy while
    the figure was timed; ``noise`` holds the spread of the ratio over the timed rounds.
    """
    cpu_value = (peer_cpu_s / fogts_cpu_s if fogts_cpu_s is not None and peer_cpu_s is not None
                 and fogts_cpu_s > 0 else None)
    return {"id": id, "suite": suite, "title": title, "kind": "speed",
            "value": peer_s / fogts_s if fogts_s > 0 else float("nan"),
            "cpu_value": cpu_value, "parallel": bool(parallel),
            "other_load": None if other_load is None else round(float(other_load), 3),
            "unit": f"x vs {peer}", "better": "higher", "tolerance": tolerance,
            "abs_tolerance": 0.0, "seconds": {"fogts": fogts_s, peer: peer_s},
            "cpu_seconds": ({} if cpu_value is None else {"fogts": fogts_cpu_s, peer: peer_cpu_s}),
            "noise": noise or {}, "details": details or {}}


def accuracy_metric(id: str, title: str, *, value: float, better: str, unit: str = "",
                    suite: str = "", tolerance: float = DEFAULT_TOLERANCE,
                    abs_tolerance: float = 0.0, details: dict[str, Any] | None = None) -> Metric:
    """An accuracy figure (an error: ``better="lower"``; a rate: ``better="higher"``)."""
    if better not in ("lower", "higher"):
        raise ValueError(f"better must be 'lower' or 'higher', got {better!r}")
    return {"id": id, "suite": suite, "title": title, "kind": "accuracy", "value": value,
            "unit": unit, "better": better, "tolerance": tolerance,
            "abs_tolerance": abs_tolerance, "seconds": {}, "details": details or {}}
