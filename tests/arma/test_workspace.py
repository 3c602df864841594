"""The shared innovations array: prefixes use its memory, and taking it discards what any
sharer held."""

from __future__ import annotations

import numpy as np

from fogts.arma.likelihood import ExactLikelihood
from fogts.arma.workspace import Workspace


def test_prefix_shares_memory_and_invalidates() -> None:
    whole = Workspace(100)
    part = whole.prefix(40)
    a = whole.take()
    b = part.take()
    assert b.shape == (40,) and np.shares_memory(a, b)
    assert whole.holder is None and part.holder is None


def test_prefix_model_rebuilds_the_whole_series_innovations() -> None:
    """A prefix model's evaluation overwrites the shared array; the whole-series model's
    innovations are then rebuilt, equal to before (to rounding)."""
    x = np.random.default_rng(4).standard_normal(3000)
    model = ExactLikelihood(x, 1, 1)
    ev = model.evaluate(np.array([0.5]), np.array([0.2]))
    before = model.innovations(ev).copy()
    prefix = ExactLikelihood(x[:1000], 1, 1, work=model.work.prefix(1000))
    prefix.evaluate(np.array([0.1]), np.array([-0.3]))
    np.testing.assert_allclose(model.innovations(ev), before, rtol=0, atol=1e-13)
