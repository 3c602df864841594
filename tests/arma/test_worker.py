"""The second thread of the long passes: the same bits as one thread, and its failures
reach the caller."""

from __future__ import annotations

import threading

import numpy as np
import pytest
from scipy.signal import lfilter

from fogts.arma import worker
from fogts.arma.likelihood import ExactLikelihood
from fogts.arma.worker import THREAD_MIN, Worker


@pytest.fixture(autouse=True)
def _threads(monkeypatch: pytest.MonkeyPatch) -> None:
    """The worker thread whatever the machine's load (the automatic choice is tested
    below)."""
    monkeypatch.setattr(worker, "THREADS", True)


def _passes(x: np.ndarray, p: int, q: int, mean: bool) -> list[bytes]:
    """S, D, f, the innovations and the derivatives (with the Hessian) at two points."""
    model = ExactLikelihood(x, p, q, mean=mean, scale=1.3, offsets=(0.01,))
    out = []
    for phi, theta in ((np.array([0.9, -0.2][:p]), np.array([0.3][:q])),
                       (np.array([0.5, 0.1][:p]), np.array([-0.6][:q]))):
        ev = model.evaluate(phi, theta)
        out.append(np.array([ev.S, ev.D, ev.f]).tobytes())
        out.append(model.innovations(ev).tobytes())
        out += [np.asarray(d).tobytes() for d in model.derivatives(ev, hessian=True)]
    return out


@pytest.mark.parametrize(("p", "q", "mean"), [(1, 1, True), (2, 1, False), (2, 0, True)])
def test_threaded_passes_equal_one_thread_bit_for_bit(monkeypatch: pytest.MonkeyPatch,
                                                      p: int, q: int, mean: bool) -> None:
    """The worker's share of evaluate, the adjoint and the Hessian pass changes no bit
    (a series long enough for the thread: 2 x THREAD_MIN + an odd tail)."""
    e = np.random.default_rng(11).standard_normal(2 * THREAD_MIN + 12_345)
    x = lfilter([1.0, 0.4], [1.0, -1.2, 0.5], e)
    x = (x - x.mean()) / x.std()
    monkeypatch.setattr(worker, "THREADS", False)
    one = _passes(x, p, q, mean)
    monkeypatch.setattr(worker, "THREADS", True)
    assert _passes(x, p, q, mean) == one


def test_job_failure_reaches_the_caller() -> None:
    with Worker(THREAD_MIN) as w:
        assert w.threaded
        value = w.submit(lambda: 1 / 0)
        with pytest.raises(ZeroDivisionError):
            value()
    with pytest.raises(ZeroDivisionError), Worker(THREAD_MIN) as w:
        w.submit(lambda: 1 / 0)       # not waited for: raised on leaving the block


def test_jobs_run_in_order_whoever_runs_them() -> None:
    """Jobs the caller takes over (the worker busy or not started) still run in order."""
    seen: list[int] = []
    gate = threading.Event()
    with Worker(THREAD_MIN) as w:
        w.submit(gate.wait)                     # holds the worker until released
        values = [w.submit(lambda i=i: seen.append(i) or i * i) for i in range(3)]
        # the caller wants the second: the first waits for the worker's job, which waits
        # for the gate, so release it from another thread
        threading.Timer(0.05, gate.set).start()
        assert values[1]() == 1
        for i in range(3, 50):
            w.submit(seen.append, i)
        assert values[0]() == 0 and values[2]() == 4
    assert seen == list(range(50))


def test_unstarted_jobs_are_taken_over_in_order() -> None:
    seen: list[int] = []
    with Worker(THREAD_MIN) as w:
        got = [w.submit(lambda i=i: seen.append(i) or -i) for i in range(10)]
        assert [value() for value in reversed(got)] == [-i for i in reversed(range(10))]
    assert seen == list(range(10))


def test_jobs_see_the_callers_errstate() -> None:
    big = np.array([1e308])
    with np.errstate(over="raise"), Worker(THREAD_MIN) as w:
        value = w.submit(lambda: big * 10.0)
        with pytest.raises(FloatingPointError):
            value()


def test_automatic_choice_follows_the_load(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(worker, "THREADS", None)
    monkeypatch.setattr(worker.os, "sched_getaffinity", lambda pid: {0, 1}, raising=False)
    monkeypatch.setattr(worker.os, "getloadavg", lambda: (2.6, 1.0, 1.0))
    assert worker.idle_core()
    with Worker(THREAD_MIN) as w:
        assert w.threaded
    monkeypatch.setattr(worker.os, "getloadavg", lambda: (3.1, 2.0, 1.0))
    assert not worker.idle_core()
    with Worker(THREAD_MIN) as w:
        assert not w.threaded
    monkeypatch.setattr(worker.os, "sched_getaffinity", lambda pid: {0}, raising=False)
    monkeypatch.setattr(worker.os, "getloadavg", lambda: (0.0, 0.0, 0.0))
    assert not worker.idle_core()


def test_short_passes_run_inline() -> None:
    with Worker(THREAD_MIN - 1) as w:
        assert not w.threaded
        assert w.submit(lambda: 3)() == 3
