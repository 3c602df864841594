"""fogts.report.text: JSON-safe conversion, deterministic JSON and the ``fogts info`` text."""

from __future__ import annotations

import numpy as np

from fogts.io.reader import read_run
from fogts.report.text import info_text, json_dumps, run_info, to_jsonable


def test_json_helpers_and_info_text() -> None:
    assert to_jsonable({"a": np.float64("nan"), "b": np.arange(2)}) == {"a": None, "b": [0, 1]}
    assert json_dumps({"x": 1.5}, indent=None) == '{"x": 1.5}'
    run = read_run(np.random.default_rng(0).normal(size=100), fs_hz=10.0)
    info = run_info(run)
    assert info["n"] == 100 and "samples     100" in info_text(info)
