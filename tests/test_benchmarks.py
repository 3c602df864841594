"""The benchmark runner: timing, the comparison against a baseline, rendering, the CLI.

The rule under test (:mod:`benchmarks.compare`): accuracy figures compare their value;
single-threaded speed figures compare the CPU-time ratio; parallel speed figures compare the
wall-time ratio only when both runs had free cores, and are not judged otherwise; a flagged
speed figure is re-measured and the measurement closest to the baseline is kept.  No test
here asserts a wall-clock time: documents are built by hand, and the one measured test
compares a 3x larger amount of work (a CPU-time ratio) against a 10 % tolerance.
"""

from __future__ import annotations

import json
from typing import Any

import numpy as np
import pytest

from benchmarks.cli import main
from benchmarks.compare import compare, merge_best
from benchmarks.metric import accuracy_metric, speed_metric
from benchmarks.render import render_comparison, render_markdown
from benchmarks.suites import SUITES, merge_results, suite_named
from benchmarks.timing import Timing, measure, speed_from


def _speed(value: float, cpu: float | None, *, parallel: bool = False,
           load: float | None = 0.0, id: str = "speed.x.n=1e6") -> dict[str, Any]:
    # fogts 1 s; the peer's times make the wanted ratios
    return speed_metric(id, "x against the peer", fogts_s=1.0, peer_s=value, peer="peer",
                               fogts_cpu_s=None if cpu is None else 1.0, peer_cpu_s=cpu,
                               parallel=parallel, other_load=load, suite="s")


def _doc(*metrics: dict[str, Any], quick: bool = False) -> dict[str, Any]:
    return {"quick": quick, "suites": {"s": {"status": "ok", "seconds": 1.0, "error": ""}},
            "metrics": list(metrics)}


def _verdict(new: dict[str, Any], old: dict[str, Any]) -> dict[str, Any]:
    rows = compare(_doc(new), _doc(old))
    assert len(rows) == 1
    return rows[0]


def test_speed_metric_records_wall_and_cpu_ratios() -> None:
    m = speed_metric("speed.a", "a", fogts_s=2.0, peer_s=6.0, peer="p", fogts_cpu_s=1.5,
                            peer_cpu_s=6.0, other_load=0.123456, suite="s")
    assert m["value"] == pytest.approx(3.0)
    assert m["cpu_value"] == pytest.approx(4.0)
    assert m["cpu_seconds"] == {"fogts": 1.5, "p": 6.0}
    assert m["other_load"] == 0.123
    assert m["parallel"] is False
    no_cpu = speed_metric("speed.b", "b", fogts_s=1.0, peer_s=2.0, peer="p")
    assert no_cpu["cpu_value"] is None and no_cpu["cpu_seconds"] == {}


def test_accuracy_metric_rejects_unknown_direction() -> None:
    with pytest.raises(ValueError, match="better must be 'lower' or 'higher', got 'up'"):
        accuracy_metric("a", "a", value=1.0, better="up")


def test_single_threaded_speed_is_compared_on_cpu_time() -> None:
    # the wall ratio lost 40 % to machine load, the CPU-time ratio held: no regression
    row = _verdict(_speed(2.4, 3.9), _speed(4.0, 4.0))
    assert row["basis"] == "cpu" and row["verdict"] == "ok"
    assert row["change"] == pytest.approx(0.025)
    # a genuine slowdown shows in CPU time too
    row = _verdict(_speed(3.0, 3.0), _speed(4.0, 4.0))
    assert row["basis"] == "cpu" and row["verdict"] == "REGRESSION"
    assert row["change"] == pytest.approx(0.25)
    # within the tolerance
    assert _verdict(_speed(4.0, 3.7), _speed(4.0, 4.0))["verdict"] == "ok"
    assert _verdict(_speed(4.0, 5.0), _speed(4.0, 4.0))["verdict"] == "better"


def test_parallel_speed_is_judged_on_wall_time_only_with_free_cores() -> None:
    old = _speed(4.0, 3.3, parallel=True, load=0.05)
    # both runs had the second core free: the wall ratio is the figure
    row = _verdict(_speed(3.0, 3.3, parallel=True, load=0.1), old)
    assert row["basis"] == "wall" and row["verdict"] == "REGRESSION"
    assert _verdict(_speed(3.8, 2.0, parallel=True, load=0.2), old)["verdict"] == "ok"
    # the new run was busy: shown, not judged (neither its wall nor its CPU ratio is steady)
    row = _verdict(_speed(2.2, 3.2, parallel=True, load=1.1), old)
    assert row["basis"] == "busy" and row["verdict"] == "not judged (busy)"
    assert row["change"] == pytest.approx(0.45)
    # a baseline measured busy leaves every later run unjudged too
    busy_old = _speed(2.5, 3.3, parallel=True, load=0.9)
    assert _verdict(_speed(1.0, 1.0, parallel=True, load=0.0), busy_old)["basis"] == "busy"
    # no load reading (not Linux): never assume the cores were free
    assert _verdict(_speed(4.0, 3.3, parallel=True, load=None), old)["basis"] == "busy"


def test_baseline_without_cpu_times_falls_back_to_wall_ratio() -> None:
    legacy = _speed(4.0, None)
    row = _verdict(_speed(3.0, 4.0), legacy)
    assert row["basis"] == "wall" and row["verdict"] == "REGRESSION"


def test_accuracy_tolerances_relative_and_absolute() -> None:
    def acc(v: float, better: str = "lower", abs_tol: float = 0.0) -> dict[str, Any]:
        return accuracy_metric("acc.a", "a", value=v, better=better,
                                      abs_tolerance=abs_tol, suite="s")

    assert _verdict(acc(1.12), acc(1.0))["verdict"] == "REGRESSION"
    assert _verdict(acc(1.08), acc(1.0))["verdict"] == "ok"
    assert _verdict(acc(0.85, "higher"), acc(1.0, "higher"))["verdict"] == "REGRESSION"
    # worse by 50 % but within the absolute tolerance: not a regression
    assert _verdict(acc(0.03, abs_tol=0.02), acc(0.02, abs_tol=0.02))["verdict"] == "ok"
    row = _verdict(acc(float("nan")), acc(1.0))
    assert row["verdict"] == "not comparable"


def test_missing_and_not_measured_figures() -> None:
    old = _doc(_speed(4.0, 4.0, id="speed.gone"), _speed(4.0, 4.0, id="speed.kept"))
    new = _doc(_speed(4.0, 4.0, id="speed.kept"))
    verdicts = {r["id"]: r["verdict"] for r in compare(new, old)}
    assert verdicts == {"speed.kept": "ok", "speed.gone": "MISSING"}
    # a quick run never reports a full run's figure as missing
    quick = _doc(_speed(4.0, 4.0, id="speed.kept"), quick=True)
    verdicts = {r["id"]: r["verdict"] for r in compare(quick, old)}
    assert verdicts["speed.gone"] == "not measured"


def test_merge_best_keeps_the_measurement_closest_to_the_baseline() -> None:
    old = _doc(_speed(4.0, 4.0))
    doc = _doc(_speed(3.0, 3.0))                      # flagged (noise, say)
    merge_best(doc, [_speed(3.2, 3.9)], old)   # the re-measurement clears it
    m = doc["metrics"][0]
    assert m["cpu_value"] == pytest.approx(3.9) and m["details"]["remeasured"] is True
    assert compare(doc, old)[0]["verdict"] == "ok"
    # a worse re-measurement does not replace a better one
    merge_best(doc, [_speed(2.0, 2.0)], old)
    assert doc["metrics"][0]["cpu_value"] == pytest.approx(3.9)
    # a genuine regression stays flagged whatever the re-measurements say
    doc = _doc(_speed(3.0, 3.0))
    for again in (_speed(3.1, 3.1), _speed(2.9, 2.95)):
        merge_best(doc, [again], old)
    assert compare(doc, old)[0]["verdict"] == "REGRESSION"
    # a busy (unjudged) re-measurement of a parallel figure does not replace a judged one
    par_old = _doc(_speed(4.0, 4.0, parallel=True, load=0.0))
    doc = _doc(_speed(3.0, 4.0, parallel=True, load=0.1))
    merge_best(doc, [_speed(4.5, 4.0, parallel=True, load=1.0)], par_old)
    assert compare(doc, par_old)[0]["verdict"] == "REGRESSION"
    # accuracy figures are never replaced
    acc = accuracy_metric("acc.a", "a", value=1.0, better="lower", suite="s")
    doc = _doc(acc)
    merge_best(doc, [{**acc, "value": 0.5}], _doc(acc))
    assert doc["metrics"][0]["value"] == 1.0


def test_measure_rotates_and_repeats() -> None:
    calls: list[str] = []
    t = measure({"a": lambda: calls.append("a"), "b": lambda: calls.append("b"),
                        "c": lambda: calls.append("c")}, repeat=3)
    assert calls == ["a", "b", "c", "b", "c", "a", "c", "a", "b"]
    assert t.rounds == 3 and set(t.wall) == set(t.cpu) == {"a", "b", "c"}
    assert all(len(v) == 3 for v in t.rounds_s.values())
    assert set(t.noise("a", "b")) == {"rounds", "spread_wall", "spread_cpu"}
    # min_total_s asks for more rounds, up to max_repeat
    calls.clear()
    measure({"a": lambda: calls.append("a")}, repeat=1, min_total_s=1e9, max_repeat=7)
    assert len(calls) == 7


def test_speed_from_uses_the_named_contenders() -> None:
    t = Timing(wall={"ours": 2.0, "p": 8.0}, cpu={"ours": 1.0, "p": 6.0},
                      rounds_s={"ours": [(2.0, 1.0), (2.5, 1.0)], "p": [(8.0, 6.0), (9.0, 6.6)]},
                      other_load=0.5)
    m = speed_from(t, "speed.z", "z", peer="P", peer_key="p", ours="ours",
                          parallel=True)
    assert m["value"] == pytest.approx(4.0) and m["cpu_value"] == pytest.approx(6.0)
    assert m["parallel"] is True and m["other_load"] == 0.5
    assert m["noise"]["rounds"] == 2
    assert m["noise"]["spread_wall"] == pytest.approx(4.0 / 3.6 - 1, abs=1e-4)
    assert m["noise"]["spread_cpu"] == pytest.approx(6.6 / 6.0 - 1, abs=1e-4)


def test_a_slower_function_is_caught_on_cpu_time() -> None:
    """Measured: the same peer against fogts-like work made 3x larger is a regression.

    The work is a sort of 200k floats (single-threaded numpy); the ratio falls to about a
    third, far beyond the 10 % tolerance, whatever the machine load.
    """
    x = np.random.default_rng(0).standard_normal(200_000)

    def work() -> object:
        return np.sort(x)

    def slow() -> object:
        for _ in range(3):
            np.sort(x)
        return None

    def figure(fn: Any) -> dict[str, Any]:
        t = measure({"fogts": fn, "peer": work}, repeat=5)
        return speed_from(t, "speed.sort", "sort", peer="numpy", suite="s")

    row = _verdict(figure(slow), figure(work))
    assert row["basis"] == "cpu"
    assert row["verdict"] == "REGRESSION"


def test_cli_compare_against_exits_1_and_names_the_figure(tmp_path: Any,
                                                          capsys: Any) -> None:
    old, new = tmp_path / "old.json", tmp_path / "new.json"
    old.write_text(json.dumps(_doc(_speed(4.0, 4.0, id="speed.oadev.1thread.n=1e7"))))
    new.write_text(json.dumps(_doc(_speed(2.5, 3.0, id="speed.oadev.1thread.n=1e7"))))
    assert main(["--compare", str(old), "--against", str(new)]) == 1
    err = capsys.readouterr().err
    assert "REGRESSION speed.oadev.1thread.n=1e7 (x against the peer): cpu 4 -> 3, worse by " \
           "25.0 % (tolerance 10 %)" in err
    assert main(["--compare", str(old), "--against", str(old)]) == 0


def test_cli_usage_errors(tmp_path: Any, capsys: Any) -> None:
    assert main(["--only", "nope"]) == 2
    assert "unknown suite(s) nope" in capsys.readouterr().err
    doc = tmp_path / "d.json"
    doc.write_text(json.dumps(_doc(_speed(4.0, 4.0))))
    assert main(["--against", str(doc)]) == 2
    assert "--against needs --compare" in capsys.readouterr().err


def test_render_shows_both_ratios_and_the_basis() -> None:
    text = render_markdown(_doc(_speed(2.5, 3.0, parallel=True)))
    assert "| ratio | CPU-time ratio |" in text
    assert "(parallel)" in text and "**2.5x** | 3x |" in text
    table = render_comparison(compare(_doc(_speed(3.0, 3.0)),
                                                    _doc(_speed(4.0, 4.0))))
    assert "| cpu | 4 | 3 | +25.0 % | REGRESSION |" in table


def test_merge_results_refuses_quick_with_full() -> None:
    with pytest.raises(ValueError, match="cannot merge a quick run with a full run"):
        merge_results(_doc(quick=True), _doc(quick=False))


def test_every_suite_loads_as_a_module_of_the_package() -> None:
    for suite in SUITES:
        assert suite.module_path().is_file(), suite.name
        assert callable(suite.load()), suite.name
        assert suite_named(suite.name) is suite
    with pytest.raises(KeyError):
        suite_named("nope")


def test_cli_render_writes_the_tables(tmp_path: Any) -> None:
    doc, md = tmp_path / "d.json", tmp_path / "out" / "d.md"
    doc.write_text(json.dumps(_doc(_speed(2.5, 3.0))))
    assert main(["--render", str(doc), "--md", str(md)]) == 0
    assert md.read_text() == render_markdown(_doc(_speed(2.5, 3.0)))


def test_run_child_reports_the_childs_own_peak_memory() -> None:
    """A command started while this process holds 400 MB reports its own peak (a bare
    interpreter: under 100 MB), not this process's: Linux carries a forked child's
    ``ru_maxrss`` across ``execve``, which made `fogts select` at 1e8 read 7x its input."""
    import sys

    from benchmarks.timing import run_child

    held = np.ones(50_000_000)  # 400 MB resident in this process
    bare = run_child([sys.executable, "-c", "pass"])
    assert held[-1] == 1.0 and bare.exit_code == 0
    assert bare.max_rss_bytes < 100e6
    touched = run_child([sys.executable, "-c",
                         "import numpy as np; a = np.ones(25_000_000); a += 1"])
    assert touched.max_rss_bytes > 200e6  # its own 200 MB array is seen
    assert run_child([sys.executable, "-c", "raise SystemExit(3)"]).exit_code == 3
