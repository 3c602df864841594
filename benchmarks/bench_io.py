"""``read_run`` against the plain library read of the same data, in the same run.

The data are 10^7 rows of ``time,rate,temperature`` (100 Hz, a white-noise rate, a slow
temperature ramp) written as a bench logger writes them: time to 0.01 s, rate to 1e-6,
temperature to 1e-3, about 250 MB of CSV; the same rows as a gzip-compressed CSV and as
Parquet, and the rate alone as ``.npy``.  ``--quick`` uses 2x10^5 rows.  The page cache is
warmed before each timing, so the figures are parsing speed, not disk speed.

Figures (ratio = peer seconds / fogts seconds, > 1 means fogts is faster):

* CSV: ``read_run`` against ``pandas.read_csv`` (C engine; pandas 3.1 splits a local file
  among its threads) and against ``pyarrow.csv.read_csv`` (multi-threaded); the
  single-threaded siblings time all three on one thread (pandas ``mode.max_threads=1``,
  ``pyarrow.set_cpu_count(1)``; the pyarrow peer with ``use_threads=False``);
* the split of ``read_run``'s CSV work, timed within one call: the parse
  (``fogts.io.text.text_file_table``: pyarrow plus the per-column checks) and the rest
  (column roles, time base, gaps, jitter, sample rate), as the CPU share of the rest;
* ``.csv.gz``: ``read_run`` against ``pandas.read_csv`` and ``pyarrow.csv.read_csv`` on
  the same compressed file (every reader decompresses as it parses);
* Parquet: ``read_run`` against ``pandas.read_parquet`` (both read with pyarrow's thread
  pool), and the same with one arrow thread;
* ``.npy``: ``read_run(path, fs_hz=...)`` against ``numpy.load``.

``read_run`` does more than the peers: it detects columns and units, checks every value is
finite and the time base strictly increasing, and measures the sample rate, gaps and
jitter.

Run: ``python -m benchmarks.bench_io [--quick]``.
"""

from __future__ import annotations

import gc
import gzip
import shutil
import tempfile
import time
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from pathlib import Path
from typing import Any

import numpy as np

from benchmarks.cli import script_main
from benchmarks.metric import Metric, accuracy_metric
from benchmarks.timing import measure, speed_from

FULL_ROWS = 10_000_000
QUICK_ROWS = 200_000
FS_HZ = 100.0
RESULTS = Path(__file__).resolve().parent / "results" / "io.md"


def _table(start: int, n: int, rng: np.random.Generator):  # type: ignore[no-untyped-def]
    import pyarrow as pa

    t = np.arange(start, start + n, dtype=np.float64) / FS_HZ
    rate = rng.normal(0.0, 0.05, n) + 0.3
    temp = 25.0 + 10.0 * (1.0 - np.exp(-t / 3600.0)) + rng.normal(0.0, 0.01, n)
    return pa.table({"time": np.round(t, 2), "rate": np.round(rate, 6),
                     "temperature": np.round(temp, 3)})


def write_files(folder: Path, n: int, *, seed: int = 0) -> dict[str, Path]:
    """``bench.csv``, ``bench.csv.gz``, ``bench.parquet`` (the same ``n`` rows) and
    ``bench.npy`` (the rate)."""
    import pyarrow.csv as pacsv
    import pyarrow.parquet as pq

    rng = np.random.default_rng(seed)
    files = {k: folder / f"bench.{k}" for k in ("csv", "csv.gz", "parquet", "npy")}
    chunk = 2_000_000
    options = pacsv.WriteOptions(quoting_style="none")
    with pacsv.CSVWriter(files["csv"], _table(0, 1, rng).schema,
                         write_options=options) as writer:
        for start in range(0, n, chunk):
            writer.write_table(_table(start, min(chunk, n - start), rng))
    with files["csv"].open("rb") as src, gzip.open(files["csv.gz"], "wb", 6) as dst:
        shutil.copyfileobj(src, dst, 8 << 20)
    table = pacsv.read_csv(files["csv"])
    pq.write_table(table, files["parquet"])
    np.save(files["npy"], table.column("rate").to_numpy())
    return files


def _warm(path: Path) -> None:
    with path.open("rb") as fh:
        while fh.read(1 << 24):
            pass


def _timed(fn: Callable[[], Any]) -> Callable[[], None]:
    def go() -> None:
        out = fn()
        del out
        gc.collect()
    return go


class _Split:
    """``read_run``'s two stages timed within one call: the parse
    (:func:`fogts.io.text.text_file_table`: pandas' or pyarrow's reader plus the per-column
    checks) and the rest
    (column roles, time base, gaps, jitter, sample rate); the round with the shortest
    call is kept, so both parts come from the same call."""

    def __init__(self, path: Path) -> None:
        self.path = path
        self.best: tuple[float, float, float, float] | None = None  # wall, cpu of each

    def __call__(self) -> None:
        from fogts.io.reader import _table_to_run
        from fogts.io.text import text_file_table

        c0, w0 = time.process_time(), time.perf_counter()
        table = text_file_table(self.path)
        c1, w1 = time.process_time(), time.perf_counter()
        _table_to_run(table, rate_column=None, time_column=None, temperature_column=None,
                      fs_hz=None, units=None)
        c2, w2 = time.process_time(), time.perf_counter()
        parts = (w1 - w0, c1 - c0, w2 - w1, c2 - c1)
        if self.best is None or parts[0] + parts[2] < self.best[0] + self.best[2]:
            self.best = parts


@contextmanager
def _pandas_threads(count: int) -> Iterator[None]:
    """pandas' worker threads (``mode.max_threads``, pandas 3.1: its threaded read_csv)
    limited to ``count`` within the block; nothing to limit on an older pandas."""
    import pandas as pd

    try:
        old = pd.get_option("mode.max_threads")
    except (KeyError, pd.errors.OptionError):
        yield
        return
    pd.set_option("mode.max_threads", count)
    try:
        yield
    finally:
        pd.set_option("mode.max_threads", old)


def _csv_figures(files: dict[str, Path], n: int, repeat: int, quick: bool) -> list[Metric]:
    import pandas as pd
    import pyarrow as pa
    import pyarrow.csv as pacsv

    from fogts.io.reader import read_run

    csv = files["csv"]
    mb = csv.stat().st_size / 1e6
    tag, size = _tag(n), f"{mb:.0f} MB"
    _warm(csv)
    check = read_run(csv)
    assert check.n == n and check.temperature is not None, (check.n, n)
    del check
    min_s = 2.0 if quick else 0.0
    split = _Split(csv)
    t = measure({"fogts": _timed(lambda: read_run(csv)), "split": _timed(split),
                 "pandas": _timed(lambda: pd.read_csv(csv)),
                 "arrow": _timed(lambda: pacsv.read_csv(csv))},
                repeat=repeat, min_total_s=min_s)
    threads = pa.cpu_count()
    one = pacsv.ReadOptions(use_threads=False)
    pa.set_cpu_count(1)
    try:
        with _pandas_threads(1):
            t1 = measure({"fogts": _timed(lambda: read_run(csv)),
                          "pandas 1 thread": _timed(lambda: pd.read_csv(csv)),
                          "arrow 1 thread": _timed(lambda: pacsv.read_csv(csv,
                                                                          read_options=one))},
                         repeat=repeat, min_total_s=min_s)
    finally:
        pa.set_cpu_count(threads)
    assert split.best is not None
    parse_s, parse_cpu, rest_s, rest_cpu = split.best
    total = t.wall["fogts"]
    details = {"rows": n, "csv_mb": round(mb, 1), "fogts_mb_per_s": round(mb / total, 1),
               "parse_s": round(parse_s, 4), "checks_s": round(rest_s, 4),
               "parse_cpu_s": round(parse_cpu, 4), "checks_cpu_s": round(rest_cpu, 4)}
    return [
        speed_from(t, f"speed.read_run.csv.{tag}", f"read_run, {size} CSV of {n:,} rows "
                   f"({mb / total:.0f} MB/s), vs pandas.read_csv", peer_key="pandas",
                   peer="pandas.read_csv", parallel=True, details=details),
        speed_from(t, f"speed.read_run.csv_arrow.{tag}", f"read_run, {size} CSV, vs "
                   "pyarrow.csv.read_csv (multi-threaded)", peer_key="arrow",
                   peer="pyarrow.csv", parallel=True, details=details),
        # the single-threaded siblings of the two CSV figures above
        speed_from(t1, f"speed.read_run.csv_1thread_pandas.{tag}", f"read_run, {size} CSV, "
                   "one thread (pandas mode.max_threads=1, pyarrow.set_cpu_count(1)), vs "
                   "pandas.read_csv on one thread", peer_key="pandas 1 thread",
                   peer="pandas.read_csv 1 thread", details=details),
        speed_from(t1, f"speed.read_run.csv_1thread.{tag}", f"read_run, {size} CSV, one "
                   "thread (as above), vs pyarrow.csv.read_csv (use_threads=False)",
                   peer_key="arrow 1 thread", peer="pyarrow.csv 1 thread", details=details),
        accuracy_metric(f"share.read_run.csv_checks.{tag}", f"read_run, {size} CSV: CPU "
                        "share of the work after the parse (roles, time base, gaps, jitter, "
                        f"sample rate: {rest_cpu:.3g} s CPU; the parse, pandas' or pyarrow's "
                        f"reader plus the column checks: {parse_cpu:.3g} s CPU), in one call",
                        value=round(rest_cpu / (parse_cpu + rest_cpu), 3), better="lower",
                        abs_tolerance=0.05, details=details),
    ]


def _gzip_figures(files: dict[str, Path], n: int, repeat: int, quick: bool) -> list[Metric]:
    import pandas as pd
    import pyarrow.csv as pacsv

    from fogts.io.reader import read_run

    gz = files["csv.gz"]
    mb = gz.stat().st_size / 1e6
    _warm(gz)
    t = measure({"fogts": _timed(lambda: read_run(gz)),
                 "pandas": _timed(lambda: pd.read_csv(gz)),
                 "arrow": _timed(lambda: pacsv.read_csv(gz))},
                repeat=repeat, min_total_s=2.0 if quick else 0.0)
    details = {"rows": n, "gz_mb": round(mb, 1)}
    tag = _tag(n)
    return [
        speed_from(t, f"speed.read_run.csv_gz.{tag}", f"read_run, the same CSV gzip-"
                   f"compressed ({mb:.0f} MB), vs pandas.read_csv", peer_key="pandas",
                   peer="pandas.read_csv", parallel=True, details=details),
        speed_from(t, f"speed.read_run.csv_gz_arrow.{tag}", "read_run, the same .csv.gz, vs "
                   "pyarrow.csv.read_csv (multi-threaded)", peer_key="arrow",
                   peer="pyarrow.csv", parallel=True, details=details),
    ]


def _binary_figures(files: dict[str, Path], n: int, repeat: int, quick: bool) -> list[Metric]:
    import pandas as pd
    import pyarrow as pa

    from fogts.io.reader import read_run

    parquet, npy = files["parquet"], files["npy"]
    tag = _tag(n)
    mb_pq = parquet.stat().st_size / 1e6
    min_s = 1.0 if quick else 0.0
    _warm(parquet)
    pq_t = measure({"fogts": _timed(lambda: read_run(parquet)),
                    "pandas": _timed(lambda: pd.read_parquet(parquet))},
                   repeat=max(repeat, 5), min_total_s=min_s)
    threads = pa.cpu_count()
    pa.set_cpu_count(1)
    try:
        pq1_t = measure({"fogts": _timed(lambda: read_run(parquet)),
                         "pandas": _timed(lambda: pd.read_parquet(parquet))},
                        repeat=max(repeat, 5), min_total_s=min_s)
    finally:
        pa.set_cpu_count(threads)
    _warm(npy)
    npy_t = measure({"fogts": _timed(lambda: read_run(npy, fs_hz=FS_HZ)),
                     "numpy": _timed(lambda: np.load(npy))},
                    repeat=max(repeat, 5), min_total_s=1.0)
    details = {"rows": n, "parquet_mb": round(mb_pq, 1)}
    return [
        speed_from(pq_t, f"speed.read_run.parquet.{tag}", f"read_run, Parquet of the same "
                   f"{n:,} rows ({mb_pq / pq_t.wall['fogts']:.0f} MB/s of file), vs "
                   "pandas.read_parquet", peer_key="pandas", peer="pandas.read_parquet",
                   parallel=True, details=details),
        speed_from(pq1_t, f"speed.read_run.parquet_1thread.{tag}", "read_run, the same "
                   "Parquet with one arrow thread (pyarrow.set_cpu_count(1)), vs "
                   "pandas.read_parquet", peer_key="pandas", peer="pandas.read_parquet",
                   details=details),
        speed_from(npy_t, f"speed.read_run.npy.{tag}", f"read_run, .npy of the {n:,} rates "
                   "(fs_hz given), vs numpy.load", peer_key="numpy", peer="numpy.load",
                   details={"rows": n}),
    ]


def _tag(n: int) -> str:
    return f"{n:.0e}".replace("e+0", "e").replace("e+", "e") + "rows"


def metrics(quick: bool) -> list[Metric]:
    """Measure and return the figures (the runner's entry point)."""
    n = QUICK_ROWS if quick else FULL_ROWS
    repeat = 3
    folder = Path(tempfile.mkdtemp(prefix="fogts-bench-io-"))
    try:
        files = write_files(folder, n)
        return [*_csv_figures(files, n, repeat, quick), *_gzip_figures(files, n, repeat, quick),
                *_binary_figures(files, n, repeat, quick)]
    finally:
        shutil.rmtree(folder, ignore_errors=True)


def main(argv: list[str] | None = None) -> int:
    return script_main(__doc__, metrics, argv, quick_help="2x10^5 rows instead of 10^7",
                       default_out=RESULTS)


if __name__ == "__main__":
    raise SystemExit(main())
