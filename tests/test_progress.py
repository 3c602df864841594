"""The library's progress reports (fogts.progress): the loops that take time report their
steps to an installed callback, in order, and nothing happens without one."""

from __future__ import annotations

import numpy as np
import pytest

import fogts
from fogts import progress
from fogts.report.html import PARTS, build_report


class Recorder:
    """A ProgressCallback keeping every call."""

    def __init__(self) -> None:
        self.calls: list[tuple[str, int, int | None]] = []

    def __call__(self, stage: str, done: int, total: int | None) -> None:
        self.calls.append((stage, done, total))

    def stages(self, prefix: str) -> list[tuple[str, int, int | None]]:
        return [c for c in self.calls if c[0].startswith(prefix)]


def test_allan_reports_every_tau_of_every_axis() -> None:
    y = np.random.default_rng(0).normal(size=(20_000, 2))
    rec = Recorder()
    with progress.reporting(rec):
        res = fogts.allan_deviation(y, fs_hz=10.0, taus="octave")
    n_tau = res.curves[0].tau_s.size
    steps = rec.stages("oadev")
    assert [d for _, d, _ in steps] == list(range(n_tau + 1)) * 2  # 0..n per axis
    assert {t for _, _, t in steps} == {n_tau}


def test_threaded_estimator_reports_from_the_calling_thread() -> None:
    from fogts.allan.estimators import oadev

    rec = Recorder()
    with progress.reporting(rec):
        out = oadev(np.random.default_rng(1).normal(size=50_000), fs_hz=1.0,
                    m=2 ** np.arange(12), workers=2)
    assert [d for _, d, _ in rec.calls] == list(range(out.m.size + 1))


def test_select_reports_each_candidate() -> None:
    x = np.random.default_rng(2).normal(size=3000)
    rec = Recorder()
    with progress.reporting(rec):
        sel = fogts.select_arma(x, fs_hz=1.0)
    steps = rec.stages("ARMA")
    n = len(sel.candidates)
    assert steps == [(f"ARMA: {n} candidates", d, n) for d in range(n + 1)]


def test_davar_reports_each_tau_or_window() -> None:
    y = np.random.default_rng(3).normal(size=6000)
    rec = Recorder()
    with progress.reporting(rec):
        res = fogts.dynamic_allan(y, fs_hz=1.0, window_s=1000, step_s=500)
    assert [d for _, d, _ in rec.stages("dynamic oadev")] == list(range(res.tau_s.size + 1))
    rec = Recorder()
    with progress.reporting(rec):
        fogts.dynamic_allan(y, fs_hz=1.0, window_s=1000, step_s=500, method="kernel")
    windows = res.shape[0]
    assert rec.calls[0] == (f"dynamic oadev: {windows} windows", 0, windows)
    # one step per window; the windows' own estimator calls report nothing
    assert [d for _, d, _ in rec.stages("dynamic")] == list(range(windows + 1))
    assert rec.calls[:windows + 1] == rec.stages("dynamic")


def test_report_reports_each_part() -> None:
    run = fogts.read_run(np.random.default_rng(4).normal(size=2000), fs_hz=10.0,
                         units="deg/h")
    rec = Recorder()
    with progress.reporting(rec):
        build_report(run, parts=("input", "allan"))
    assert rec.stages("report") == [("report: 2 parts", d, 2) for d in (0, 0, 1, 2)]
    assert len(PARTS) >= 2


def test_nothing_is_reported_outside_the_block_and_nesting_restores() -> None:
    outer, inner = Recorder(), Recorder()
    y = np.random.default_rng(5).normal(size=5000)
    fogts.allan_deviation(y, fs_hz=1.0)  # no callback: nothing to check but no error
    with progress.reporting(outer):
        with progress.reporting(inner):
            fogts.allan_deviation(y, fs_hz=1.0)
        with progress.reporting(None):
            fogts.allan_deviation(y, fs_hz=1.0)
    assert inner.calls and not outer.calls
    assert progress.ticker("x", 1) is progress._ignore


@pytest.mark.parametrize("total", [None, 3])
def test_ticker_passes_the_total(total: int | None) -> None:
    rec = Recorder()
    with progress.reporting(rec):
        tick = progress.ticker("stage", total)
        tick(1)
    assert rec.calls == [("stage", 0, total), ("stage", 1, total)]
