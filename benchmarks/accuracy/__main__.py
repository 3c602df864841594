"""``python -m benchmarks.accuracy``: the noise-fit round-trip study (see :mod:`.roundtrip`)."""

from benchmarks.accuracy.roundtrip import main

raise SystemExit(main())
