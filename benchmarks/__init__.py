"""fogts regression benchmarks.

One entry point runs every suite::

    python -m benchmarks [--quick] [--out results.json] [--md results.md] [--compare old.json]

Each suite measures fogts against a peer in the same run (speed figures are ratios: peer
seconds / fogts seconds) or measures an accuracy figure on simulated data with known truth.
``--compare`` flags any figure that got worse by more than its tolerance (10 % by default)
and exits 1.

Modules:

* :mod:`benchmarks.metric`: the speed and accuracy figures a suite returns;
* :mod:`benchmarks.timing`: timing fogts and its peer in rotating rounds (wall and CPU time,
  the load of other processes);
* :mod:`benchmarks.compare`: the noise-robust comparison against a baseline;
* :mod:`benchmarks.render`: the markdown tables;
* :mod:`benchmarks.environment`: machine, library versions and commit of a result;
* :mod:`benchmarks.suites`: the suite list and the result document;
* :mod:`benchmarks.cli`: ``python -m benchmarks`` and the single-suite command line.

The suite modules (``bench_*.py``, ``accuracy/``) also run on their own:
``python -m benchmarks.bench_allan --quick``.
"""
