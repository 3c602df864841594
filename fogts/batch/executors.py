"""Where the runs of a batch are analysed: in this process, on a local process pool, or on
an existing Dask distributed cluster.

Each executor is a generator of :class:`~fogts.batch.records.RunOutcome` in the order the
runs finish.  A run whose analysis raises gives an error outcome that is kept (``persist``);
a run lost by the infrastructure (a worker that died, a task that could not be sent) gives
one that is not, so that a resumed batch retries it.
"""

from __future__ import annotations

import os
import uuid
from collections.abc import Iterator

from fogts.batch.documents import error_outcome
from fogts.batch.files import run_key
from fogts.batch.records import Analysis, BatchOptions, RunOutcome
from fogts.errors import DataError
from fogts.report.text import error_message

__all__ = ["dask_cluster", "open_executor", "process_pool", "safe_call", "serial"]

#: Modules the forkserver imports once, before it forks the workers.
_WORKER_PRELOAD = ["fogts.batch", "fogts.io.reader", "fogts.preprocess.prepare", "fogts.allan",
                   "fogts.arma"]


def open_executor(jobs: list[str], analysis: Analysis, options: BatchOptions, *,
                  workers: int | None, scheduler: str | None, connect_timeout_s: float
                  ) -> tuple[str, Iterator[RunOutcome]]:
    """The backend name (``dask``, ``serial`` or ``process-pool``) and its outcome stream.

    Nothing starts before the stream is first iterated.
    """
    if scheduler:
        return "dask", dask_cluster(jobs, analysis, options, scheduler, connect_timeout_s)
    local = workers or os.cpu_count() or 1
    if local == 1 or len(jobs) <= 1:
        return "serial", serial(jobs, analysis, options)
    return "process-pool", process_pool(jobs, analysis, options, min(local, len(jobs)))


def safe_call(analysis: Analysis, file: str, options: BatchOptions) -> RunOutcome:
    """Run ``analysis``; an exception escaping it becomes an error outcome."""
    try:
        return analysis(file, options)
    except Exception as exc:
        return error_outcome(file, error_message(exc), persist=True)


def serial(jobs: list[str], analysis: Analysis, options: BatchOptions
           ) -> Iterator[RunOutcome]:
    """Analyse the runs one after the other in this process."""
    for file in jobs:
        yield safe_call(analysis, file, options)


def process_pool(jobs: list[str], analysis: Analysis, options: BatchOptions, workers: int
                 ) -> Iterator[RunOutcome]:
    """Analyse the runs on ``workers`` local processes."""
    import multiprocessing as mp
    from concurrent.futures import FIRST_COMPLETED, Future, ProcessPoolExecutor, wait

    # forkserver: workers fork from a clean server that has the heavy imports preloaded
    # (fork from a process with threads, e.g. a progress bar, is unsafe).
    ctx = mp.get_context("forkserver")
    ctx.set_forkserver_preload(_WORKER_PRELOAD)
    pool = ProcessPoolExecutor(max_workers=workers, mp_context=ctx)
    pending: dict[Future[RunOutcome], str] = {}
    try:
        for file in jobs:
            pending[pool.submit(safe_call, analysis, file, options)] = file
        while pending:
            done, _ = wait(pending, return_when=FIRST_COMPLETED)
            for fut in done:
                file = pending.pop(fut)
                try:
                    yield fut.result()
                except Exception as exc:  # the worker died (BrokenProcessPool) or unpicklable
                    yield _lost(file, exc)
    finally:
        pool.shutdown(wait=True, cancel_futures=True)


def dask_cluster(jobs: list[str], analysis: Analysis, options: BatchOptions, scheduler: str,
                 timeout_s: float) -> Iterator[RunOutcome]:
    """Analyse the runs on the Dask distributed cluster whose scheduler is at ``scheduler``.

    Raises
    ------
    DataError
        If Dask distributed is not installed or the scheduler cannot be reached in
        ``timeout_s`` seconds.
    """
    try:
        from distributed import Client, as_completed
    except ImportError:
        raise DataError("scheduler requires Dask distributed: pip install 'fogts[dask]'"
                        ) from None
    try:
        client = Client(scheduler, timeout=timeout_s, set_as_default=False)
    except (OSError, TimeoutError, ValueError) as exc:
        raise DataError(f"cannot connect to the Dask scheduler at {scheduler!r}: "
                        f"{error_message(exc)}") from None
    try:
        token = uuid.uuid4().hex[:12]  # keys unique to this batch on a shared cluster
        futures = {client.submit(safe_call, analysis, f, options, pure=False,
                                 key=f"fogts-batch-{token}-{i}-{run_key(f)}"): f
                   for i, f in enumerate(jobs)}
        for fut in as_completed(list(futures), loop=client.loop):
            file = futures[fut]
            try:
                yield fut.result()
            except Exception as exc:  # a worker was lost, or the task could not be sent
                yield _lost(file, exc)
            finally:
                fut.release()
    finally:
        client.close()


def _lost(file: str, exc: Exception) -> RunOutcome:
    """The outcome of a run the infrastructure lost (not kept: a resumed batch retries it)."""
    return error_outcome(file, f"worker failed: {error_message(exc)}", persist=False)
