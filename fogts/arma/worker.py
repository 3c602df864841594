"""A second thread for the series-length passes of a long fit: :class:`Worker`.

The passes of :mod:`fogts.arma.likelihood` and :mod:`fogts.arma.likelihood_passes` are
chains of ``scipy.signal.lfilter`` calls over ``CHUNK``-long blocks, each latency-bound
(about 5 ns a sample, one core); scipy and numpy release the GIL inside them.  Where a
block's work has a part that does not depend on the chain (another filter of the same
block, the block's series, dot products, copying the block into the workspace), that part
runs on one worker thread while the caller's thread runs the chain.

Bit for bit: the worker runs the jobs in the order they were submitted, each job does the
same floating-point operations as the single-threaded pass, and every sum is accumulated
in the same order, so the results equal those of one thread exactly.  The jobs run in a
copy of the caller's context, so ``np.errstate`` (a context variable) applies to them as
to the caller.  Short series (below :data:`THREAD_MIN` samples) run the same jobs inline:
a thread's start and hand-overs would cost more than they save.  So do all passes on a
machine busy with other work (:func:`idle_core`), where the two threads would take turns
on one core.  The measured gain and cost are in ``benchmarks/README.md``.

On a loaded machine the worker may not get a core when its job is due: the caller then
takes the jobs the worker has not started and runs them itself, still in order, instead
of waiting for the worker to be scheduled.
"""

from __future__ import annotations

import contextvars
import os
from collections import deque
from collections.abc import Callable
from concurrent.futures import Future, ThreadPoolExecutor
from types import TracebackType
from typing import Any, Generic, TypeVar

__all__ = ["DEPTH", "THREADS", "THREAD_MIN", "Worker", "idle_core"]

#: Passes over at least this many samples use the worker thread (8 blocks of 2^16).
THREAD_MIN = 1 << 19
#: True: passes of at least THREAD_MIN samples use the worker thread; False: every job
#: runs inline (the results are the same); None: the thread only while a core is idle.
THREADS: bool | None = None
#: At most this many jobs are pending: a job holds its block's arrays.
DEPTH = 4

T = TypeVar("T")


class _Job(Generic[T]):
    """A submitted job: the call, the future running it on the worker (None once settled
    or run by the caller) and its value."""

    __slots__ = ("args", "fn", "fut", "value")

    def __init__(self, fn: Callable[..., T], args: tuple[Any, ...]) -> None:
        self.fn = fn
        self.args = args
        self.fut: Future[T] | None = None
        self.value: T | None = None


class Worker:
    """One background thread running submitted jobs in the order submitted, or inline if
    ``n`` (the samples of the pass) is below :data:`THREAD_MIN`, or :data:`THREADS` is
    False, or None and no core is idle (:func:`idle_core`).

    :meth:`submit` returns a function that gives the job's value (raising its exception),
    waiting for the job - or running it, and any not started before it, in this thread if
    the worker has not started it.  At most :data:`DEPTH` jobs are pending.  Use as a
    context manager: leaving it completes the jobs still pending.
    """

    def __init__(self, n: int) -> None:
        use = n >= THREAD_MIN and (THREADS if THREADS is not None else idle_core())
        self._pool = (ThreadPoolExecutor(max_workers=1, thread_name_prefix="fogts-arma")
                      if use else None)
        self._ctx = contextvars.copy_context()
        self._pending: deque[_Job[Any]] = deque()

    @property
    def threaded(self) -> bool:
        """Whether the jobs run on a second thread."""
        return self._pool is not None

    def submit(self, fn: Callable[..., T], *args: Any) -> Callable[[], T]:
        """Queue ``fn(*args)``; returns a function that gives its value."""
        job: _Job[T] = _Job(fn, args)
        if self._pool is None:
            job.value = fn(*args)
        else:
            while self._pending and (len(self._pending) >= DEPTH
                                     or _done(self._pending[0])):
                self._finish(self._pending[0])
            self._start(job)
            self._pending.append(job)
        return lambda: self._finish(job)

    def _start(self, job: _Job[Any]) -> None:
        assert self._pool is not None
        job.fut = self._pool.submit(self._ctx.run, job.fn, *job.args)

    def _finish(self, job: _Job[T]) -> T:
        """Complete the pending jobs up to ``job``, in order, and return its value.

        The jobs after ``job`` that the worker has not started are withdrawn (newest
        first, so none of them starts meanwhile); if ``job`` itself was withdrawn, the
        ones before it are running or done: they are waited for and ``job`` runs here.
        The withdrawn later jobs are queued again, behind it."""
        if job not in self._pending:
            return job.value      # type: ignore[return-value]
        jobs = list(self._pending)
        i = jobs.index(job)
        withdrawn = []
        for later in reversed(jobs[i + 1:]):
            assert later.fut is not None
            if not later.fut.cancel():
                break
            withdrawn.append(later)
        assert job.fut is not None
        here = job.fut.cancel()
        for earlier in jobs[:i]:
            self._settle(earlier)
        if here:
            self._pending.popleft()
            job.fut = None
            job.value = job.fn(*job.args)
        else:
            self._settle(job)
        for later in reversed(withdrawn):
            self._start(later)
        return job.value      # type: ignore[return-value]

    def _settle(self, job: _Job[Any]) -> None:
        """Wait for the oldest pending job (``job``), started on the worker."""
        assert self._pending[0] is job and job.fut is not None
        self._pending.popleft()
        job.value = job.fut.result()
        job.fut = None

    def __enter__(self) -> Worker:
        return self

    def __exit__(self, exc_type: type[BaseException] | None, exc: BaseException | None,
                 tb: TracebackType | None) -> None:
        if self._pool is None:
            return
        try:
            if exc_type is None and self._pending:  # a job's exception is raised here
                self._finish(self._pending[-1])
        finally:
            self._pool.shutdown(wait=True, cancel_futures=True)


def _done(job: _Job[Any]) -> bool:
    return job.fut is not None and job.fut.done()


def idle_core() -> bool:
    """Whether a second thread would find a core: at least two cores available to this
    process, and a 1-minute load average below their number plus one.  The load counts
    this process's own threads (about 1.4 while it runs a fit with the worker), so the
    bound allows one other busy process on two cores, not two."""
    try:
        cores = len(os.sched_getaffinity(0))
    except AttributeError:        # not on Linux
        cores = os.cpu_count() or 1
    if cores < 2:
        return False
    try:
        return os.getloadavg()[0] < cores + 1.0
    except OSError:
        return True
