"""fogts regression benchmarks.

One entry point runs every suite::

    python -m benchmarks [--quick] [--out results.json] [--md results.md] [--compare old.json]

Each suite measures fogts against a peer in the same run (speed figures are ratios: peer
seconds / fogts seconds) or measures an accuracy figure on simulated data with known truth.
``--compare`` flags any figure that got worse by more than its tolerance (10 % by default)
and exits 1.  See :mod:`benchmarks._runner` for the result format.

The per-topic modules (``bench_*.py``, ``accuracy/``) also run on their own as scripts.
"""
