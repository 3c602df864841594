"""``python -m benchmarks``: run every benchmark suite (see :mod:`benchmarks.cli`)."""

from benchmarks.cli import main

raise SystemExit(main())
