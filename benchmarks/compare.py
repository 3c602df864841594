"""Comparing a result against a stored baseline (``--compare``), robust to timing noise.

A metric is flagged when its figure got worse than the baseline's by more than its
tolerance (10 % relative by default, and more than ``abs_tolerance`` absolute), and a
metric of the baseline is flagged when it is missing now.  The machine is shared, so which
figure of a speed metric is compared follows one rule (:func:`compared_values`):

* **single-threaded** figures (both sides run on one thread; the suites run with one BLAS
  thread) are compared on the **CPU-time ratio**.  A single-threaded call's CPU time does not
  grow while the process waits for a core, so the ratio stays steady under a load that
  moves the wall-time ratio a lot; a slower fogts function still shows fully.
* **parallel** figures (a side may use several threads: oadev with its default thread pool,
  pyarrow's readers) depend on free cores.  They are compared on the wall-time ratio only if
  other processes kept at most :data:`FREE_LOAD` cores busy while each of the two runs
  timed them; otherwise they are shown but not judged (``not judged (busy)``).  Their CPU
  time is no substitute: threads sharing one core spend less CPU time than threads running
  side by side.  Every parallel figure has a single-threaded sibling that is always judged
  on CPU time (``speed.oadev.1thread``, ``speed.read_run.csv_1thread``,
  ``speed.read_run.parquet_1thread``).
* A suite with a flagged speed figure is measured again (``--confirm`` times) and the
  measurement closest to the baseline is kept (:func:`merge_best`), so a slowdown must show
  in every measurement to be reported; accuracy figures are deterministic and are not
  re-measured.
"""

from __future__ import annotations

from typing import Any, TypeGuard

from benchmarks.metric import DEFAULT_TOLERANCE, Metric

#: A parallel figure is compared on wall time only if, in both runs, other processes kept
#: at most this many cores busy on average while it was timed (see :func:`compared_values`).
FREE_LOAD = 0.25

Row = dict[str, Any]


def is_number(v: Any) -> TypeGuard[int | float]:
    """True for a finite int or float (not a bool, not NaN, not infinite)."""
    return (isinstance(v, int | float) and not isinstance(v, bool) and v == v
            and v not in (float("inf"), float("-inf")))


def _worse_by(new: float, old: float, better: str) -> float:
    """Relative change in the bad direction (positive = worse)."""
    if old == 0:
        return float("inf") if (new > 0 if better == "lower" else new < 0) else 0.0
    change = (new - old) / abs(old)
    return -change if better == "higher" else change


def compared_values(new: Metric, old: Metric) -> tuple[float, float, str]:
    """The two figures ``--compare`` sets against each other, and the basis used.

    * accuracy figure: its ``value`` (``"value"``);
    * single-threaded speed figure: the CPU-time ratio ``cpu_value`` (``"cpu"``);
    * parallel speed figure: the wall-time ratio when other processes kept at most
      :data:`FREE_LOAD` cores busy in both runs (``"wall"``: the cores were free), else
      ``"busy"``: not judged.  (Its CPU time is no substitute: threads that share one core
      spend less CPU time than threads running side by side, so the CPU-time ratio moves
      with the load too.)  Every parallel figure has a single-threaded sibling.
    * a stored result without CPU times (older schema): the wall ratio (``"wall"``).
    """
    if new.get("kind") != "speed":
        return new["value"], old["value"], "value"
    if new.get("parallel") or old.get("parallel"):
        loads = (new.get("other_load"), old.get("other_load"))
        if all(is_number(x) and x <= FREE_LOAD for x in loads):
            return new["value"], old["value"], "wall"
        return new["value"], old["value"], "busy"
    cpu_new, cpu_old = new.get("cpu_value"), old.get("cpu_value")
    if is_number(cpu_new) and is_number(cpu_old):
        return float(cpu_new), float(cpu_old), "cpu"
    return new["value"], old["value"], "wall"


def compare_row(m: Metric, o: Metric | None) -> Row:
    """One comparison row for new metric ``m`` against old metric ``o`` (see :func:`compare`)."""
    row: Row = {"id": m["id"], "title": m["title"], "unit": m.get("unit", ""),
                "new": m["value"], "old": None if o is None else o["value"],
                "change": None, "basis": ""}
    if o is None:
        row["verdict"] = "new"
        return row
    new_v, old_v, basis = compared_values(m, o)
    row.update(new=new_v, old=old_v, basis=basis)
    if not is_number(new_v) or not is_number(old_v):
        row["verdict"] = "not comparable"
        return row
    worse = _worse_by(float(new_v), float(old_v), m["better"])
    row["change"] = worse
    if basis == "busy":
        row["verdict"] = "not judged (busy)"
        return row
    tol = float(m.get("tolerance", DEFAULT_TOLERANCE))
    abs_tol = float(m.get("abs_tolerance", 0.0))
    row["tolerance"] = tol
    if worse > tol and abs(float(new_v) - float(old_v)) > abs_tol:
        row["verdict"] = "REGRESSION"
    else:
        row["verdict"] = "better" if worse < -tol else "ok"
    return row


def compare(new: dict[str, Any], old: dict[str, Any]) -> list[Row]:
    """One row per metric of either document: ``{id, title, old, new, change, basis, verdict}``.

    ``old``/``new`` are the figures compared (:func:`compared_values`; ``basis`` says which).
    ``verdict`` is ``ok``, ``better``, ``REGRESSION``, ``MISSING`` (in old, not in new: the
    figure is no longer measured), ``new``, ``not measured`` (its suite did not run, or the
    runs differ in ``quick``), ``not comparable`` (a NaN value) or ``not judged (busy)`` (a
    parallel figure timed while other processes held a core).
    """
    old_by = {m["id"]: m for m in old.get("metrics", [])}
    new_by = {m["id"]: m for m in new.get("metrics", [])}
    rows = [compare_row(m, old_by.get(mid)) for mid, m in new_by.items()]
    quick = bool(new.get("quick"))
    ran = set(new.get("suites", {}))
    for mid, o in old_by.items():
        if mid not in new_by:
            # Only a figure that the same kind of run (quick or full) of the same suite
            # measured before can go missing; suites left out with --only are not measured.
            measured = bool(old.get("quick")) == quick and (not ran or o.get("suite") in ran)
            rows.append({"id": mid, "title": o["title"], "unit": o.get("unit", ""),
                         "old": o["value"], "new": None, "change": None, "basis": "",
                         "verdict": "MISSING" if measured else "not measured"})
    return rows


def regressed(rows: list[Row]) -> list[Row]:
    """The rows that fail a comparison: ``REGRESSION`` and ``MISSING``."""
    return [r for r in rows if r["verdict"] in ("REGRESSION", "MISSING")]


def merge_best(doc: dict[str, Any], again: list[Metric], old: dict[str, Any]) -> None:
    """Fold a re-measurement of speed figures into ``doc``, keeping the better measurement.

    "Better" is judged the way :func:`compare` judges against ``old`` (the same basis), so
    a re-measurement can clear a figure that timing noise flagged, but a slowdown that every
    measurement shows stays flagged.  A kept re-measurement is marked ``remeasured``.
    """
    old_by = {m["id"]: m for m in old.get("metrics", [])}
    by_id = {m["id"]: m for m in again}
    for i, m in enumerate(doc["metrics"]):
        n = by_id.get(m["id"])
        o = old_by.get(m["id"])
        if n is None or m["kind"] != "speed" or o is None:
            continue
        cur_row, cand_row = compare_row(m, o), compare_row(n, o)
        cur, cand = cur_row["change"], cand_row["change"]
        if cand_row["verdict"] == "not judged (busy)" and cur_row["verdict"] != cand_row["verdict"]:
            continue  # a busy re-measurement does not replace a judged one
        if cand is not None and (cur is None or cand < cur):
            doc["metrics"][i] = {**n, "details": {**n.get("details", {}), "remeasured": True}}
