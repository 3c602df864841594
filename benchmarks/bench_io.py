"""``read_run`` throughput on a large CSV and on Parquet, against pandas in the same run.

The file holds ``time,rate,temperature`` (100 Hz, white-noise rate, a slow temperature
ramp), written by pyarrow.  The full run uses a 1 GB CSV (about 22 million rows) and the
same table as Parquet; ``--quick`` uses about 8 MB.  The page cache is warmed before each
timing, so the figures are parsing speed, not disk speed.

Figures (ratio = peer seconds / fogts seconds, > 1 means fogts is faster):

* ``read_run`` on CSV against ``pandas.read_csv`` (C engine, the usual way to load a bench
  file; it keeps about two cores busy here) and against ``pyarrow.csv.read_csv``
  (multi-threaded), and against ``pyarrow.csv.read_csv`` with one thread (``read_run``
  parses on one thread);
* ``read_run`` on Parquet against ``pandas.read_parquet`` (both read with pyarrow's thread
  pool), and the same with one arrow thread.

``read_run`` does more than the peers: it detects columns and units, checks every value is
finite and the time base is monotonic, and measures gaps and jitter.

Run: ``python -m benchmarks.bench_io [--quick]``.
"""

from __future__ import annotations

import gc
import shutil
import tempfile
from pathlib import Path

import numpy as np

from benchmarks.cli import script_main
from benchmarks.metric import Metric
from benchmarks.timing import measure, speed_from

FULL_CSV_BYTES = 1_000_000_000
QUICK_CSV_BYTES = 8_000_000
FS_HZ = 100.0


def _table(n: int, rng: np.random.Generator):  # type: ignore[no-untyped-def]
    import pyarrow as pa

    t = np.arange(n, dtype=np.float64) / FS_HZ
    rate = rng.normal(0.0, 0.05, n) + 0.3
    temp = 25.0 + 10.0 * (1.0 - np.exp(-t / 3600.0)) + rng.normal(0.0, 0.01, n)
    return pa.table({"time": t, "rate": rate, "temperature": temp})


def write_files(folder: Path, target_bytes: int, *, seed: int = 0) -> tuple[Path, Path, int]:
    """Write ``bench.csv`` of about ``target_bytes`` and ``bench.parquet`` with the same rows."""
    import pyarrow.csv as pacsv
    import pyarrow.parquet as pq

    rng = np.random.default_rng(seed)
    probe = folder / "probe.csv"
    pacsv.write_csv(_table(10_000, rng), probe)
    per_row = probe.stat().st_size / 10_000
    probe.unlink()
    n = int(target_bytes / per_row)
    csv, parquet = folder / "bench.csv", folder / "bench.parquet"
    chunk = 2_000_000
    with pacsv.CSVWriter(csv, _table(1, rng).schema) as writer:
        for start in range(0, n, chunk):
            tab = _table(min(chunk, n - start), rng)
            import pyarrow as pa
            import pyarrow.compute as pc

            tab = tab.set_column(0, "time", pc.add(tab["time"], pa.scalar(start / FS_HZ)))
            writer.write_table(tab)
    pq.write_table(pacsv.read_csv(csv), parquet)
    return csv, parquet, n


def _warm(path: Path) -> None:
    with path.open("rb") as fh:
        while fh.read(1 << 24):
            pass


def metrics(quick: bool) -> list[Metric]:
    """Measure and return the figures (the runner's entry point)."""
    import pandas as pd
    import pyarrow as pa
    import pyarrow.csv as pacsv

    from fogts.io.reader import read_run

    target = QUICK_CSV_BYTES if quick else FULL_CSV_BYTES
    repeat = 3 if quick else 2
    folder = Path(tempfile.mkdtemp(prefix="fogts-bench-io-"))
    try:
        csv, parquet, n = write_files(folder, target)
        mb = csv.stat().st_size / 1e6
        mb_pq = parquet.stat().st_size / 1e6
        size = f"{mb / 1000:.2g} GB" if mb >= 1000 else f"{mb:.0f} MB"
        tag = "1GB" if not quick else f"{mb:.0f}MB"

        def timed(fn):  # type: ignore[no-untyped-def]
            def go() -> None:
                out = fn()
                del out
                gc.collect()
            return go

        one = pacsv.ReadOptions(use_threads=False)
        _warm(csv)
        check = read_run(csv)
        assert check.n == n and check.temperature is not None, (check.n, n)
        del check
        csv_t = measure({"fogts": timed(lambda: read_run(csv)),
                         "pandas": timed(lambda: pd.read_csv(csv)),
                         "arrow": timed(lambda: pacsv.read_csv(csv)),
                         "arrow 1 thread": timed(lambda: pacsv.read_csv(csv, read_options=one))},
                        repeat=repeat, min_total_s=2.0 if quick else 0.0)
        t_fogts, t_pandas, t_arrow = csv_t.wall["fogts"], csv_t.wall["pandas"], csv_t.wall["arrow"]
        _warm(parquet)
        pq_t = measure({"fogts": timed(lambda: read_run(parquet)),
                        "pandas": timed(lambda: pd.read_parquet(parquet))},
                       repeat=max(repeat, 5), min_total_s=1.0 if quick else 0.0)
        t_fogts_pq = pq_t.wall["fogts"]
        # the same with one arrow thread: the single-threaded sibling of the figure above
        threads = pa.cpu_count()
        pa.set_cpu_count(1)
        try:
            pq1_t = measure({"fogts": timed(lambda: read_run(parquet)),
                             "pandas": timed(lambda: pd.read_parquet(parquet))},
                            repeat=max(repeat, 5), min_total_s=1.0 if quick else 0.0)
        finally:
            pa.set_cpu_count(threads)
    finally:
        shutil.rmtree(folder, ignore_errors=True)

    details = {"rows": n, "csv_mb": round(mb, 1), "fogts_mb_per_s": round(mb / t_fogts, 1),
               "pandas_mb_per_s": round(mb / t_pandas, 1)}
    return [
        speed_from(csv_t, f"speed.read_run.csv.{tag}", f"read_run, {size} CSV "
                   f"({mb / t_fogts:.0f} MB/s), vs pandas.read_csv", peer_key="pandas",
                   peer="pandas.read_csv", parallel=True, details=details),
        speed_from(csv_t, f"speed.read_run.csv_arrow.{tag}", f"read_run, {size} CSV, vs "
                   "pyarrow.csv.read_csv (multi-threaded)", peer_key="arrow",
                   peer="pyarrow.csv", parallel=True,
                   details={**details, "arrow_mb_per_s": round(mb / t_arrow, 1)}),
        # the single-threaded sibling of the two CSV figures above
        speed_from(csv_t, f"speed.read_run.csv_1thread.{tag}", f"read_run, {size} CSV, vs "
                   "pyarrow.csv.read_csv with one thread (use_threads=False)",
                   peer_key="arrow 1 thread", peer="pyarrow.csv 1 thread", details=details),
        # both read Parquet with pyarrow's thread pool
        speed_from(pq_t, f"speed.read_run.parquet.{tag}", f"read_run, Parquet of the same "
                   f"{n:,} rows ({mb_pq / t_fogts_pq:.0f} MB/s of file), vs "
                   "pandas.read_parquet", peer_key="pandas", peer="pandas.read_parquet",
                   parallel=True, details={"rows": n, "parquet_mb": round(mb_pq, 1)}),
        speed_from(pq1_t, f"speed.read_run.parquet_1thread.{tag}", "read_run, the same "
                   "Parquet with one arrow thread (pyarrow.set_cpu_count(1)), vs "
                   "pandas.read_parquet", peer_key="pandas", peer="pandas.read_parquet",
                   details={"rows": n, "parquet_mb": round(mb_pq, 1)}),
    ]


def main(argv: list[str] | None = None) -> int:
    return script_main(__doc__, metrics, argv, quick_help="about 8 MB instead of 1 GB")


if __name__ == "__main__":
    raise SystemExit(main())
