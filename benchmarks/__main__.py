"""``python -m benchmarks``: run every benchmark suite (see :mod:`benchmarks._runner`)."""

from benchmarks._runner import main

raise SystemExit(main())
