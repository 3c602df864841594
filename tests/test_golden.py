"""Golden outputs: every command's JSON and CSV on the bundled examples and a generated
record, compared with the fixtures in ``tests/golden/``.

They guard refactors (the layout redesign must not change a number) and the JSON
contracts.  Regenerate after an intended change with::

    OPENBLAS_NUM_THREADS=1 python -m tests.test_golden

Comparison: keys, strings, booleans and integers must be equal; floats within
``REL_TOL`` relative or ``ABS_TOL`` absolute.  The fixtures are written on one machine, and
floats cannot be compared bit for bit elsewhere, measured under other OpenBLAS kernels
(``OPENBLAS_CORETYPE=Prescott``, ``SkylakeX``):

* deviations, noise terms and ADF statistics move in the last 1-3 bits (summation order
  in BLAS; ADF's least squares is not even bit-reproducible across thread counts);
* standard errors from a finite-difference Hessian move by ~2e-6 relative (the
  optimum itself is found to a gradient tolerance, and the Hessian's difference step
  amplifies that), hence ``REL_TOL = 1e-5``;
* a Kalman measurement noise estimated at its lower bound (1.2e-9 against a rate variance
  of 0.1 (deg/h)^2) is zero to the optimiser and moves by 30 %, hence ``ABS_TOL = 1e-8``
  in the outputs' own units (deg/h-based; the smallest real quantity in the fixtures is
  ~1e-4).

Set ``FOGTS_GOLDEN_EXACT=1`` to require bit equality (with ``OPENBLAS_NUM_THREADS=1``, on
the machine that wrote the fixtures) while refactoring.
"""

from __future__ import annotations

import io
import json
import math
import os
import re
import sys
from collections.abc import Callable
from pathlib import Path
from typing import Any

import numpy as np
import pandas as pd
import pytest
from typer.testing import CliRunner

from fogts.cli import app

ROOT = Path(__file__).resolve().parents[1]
GOLDEN = Path(__file__).resolve().parent / "golden"
#: Floats agree to this relative tolerance across BLAS kernels (see the module docstring).
REL_TOL = 1e-5
#: ... or to this absolute tolerance, for estimates that are zero to the optimiser.
ABS_TOL = 1e-8
EXACT = os.environ.get("FOGTS_GOLDEN_EXACT") == "1"


def _gappy_record(tmp: Path) -> Path:
    """A 2 h, 10 Hz record with a named unit, a 3 s gap and one spike (fixed seed)."""
    rng = np.random.default_rng(20261124)
    n = 72_000
    t = np.arange(n) / 10.0
    t[40_000:] += 3.0
    rate = 0.3 * rng.standard_normal(n) + np.cumsum(0.002 * rng.standard_normal(n))
    rate[10_000] += 9.0
    path = tmp / "gappy.csv"
    pd.DataFrame({"time": t, "rate_deg_h": rate}).to_csv(path, index=False, float_format="%.10g")
    return path


def _curve_file(tmp: Path) -> Path:
    """A published-style Allan curve: the five-term sigma (N = 0.002 deg/sqrt(h), B = 0.01
    deg/h, K = 0.05 deg/h^1.5; DESIGN.md) at octave taus of a 10 Hz record, times a fixed
    wiggle of up to 2 %, with no unit, fs or record length in the file."""
    tau = 2.0 ** np.arange(0, 16) / 10.0
    var = ((0.002 * 60) ** 2 / tau + 2 * math.log(2) / math.pi * 0.01**2
           + (0.05 / 60) ** 2 * tau / 3)
    dev = np.sqrt(var) * (1 + 0.02 * np.sin(np.arange(tau.size)))
    path = tmp / "curve.csv"
    pd.DataFrame({"tau_s": tau, "oadev": dev}).to_csv(path, index=False, float_format="%.10g")
    return path


#: name -> (command line, output files to capture); ``{tmp}`` is the output folder,
#: ``{gappy}`` the generated record and ``{curve}`` the generated Allan curve.  Paths to the bundled data are relative to the root.
CASES: dict[str, tuple[list[str], list[str]]] = {
    "info": (["info", "data/example_fog_10hz_3h.csv", "--json", "{tmp}/out.json"],
             ["out.json"]),
    "allan": (["allan", "data/example_fog_10hz_3h.csv", "--json", "{tmp}/out.json",
               "--csv", "{tmp}/points.csv"], ["out.json", "points.csv"]),
    "allan_gappy": (["allan", "{gappy}", "--taus", "decade", "--json", "{tmp}/out.json"],
                    ["out.json"]),
    "select": (["select", "data/example_fog_10hz_3h.csv", "--json", "{tmp}/out.json",
                "--predict", "{tmp}/pred.csv"], ["out.json", "pred.csv"]),
    "select_gappy": (["select", "{gappy}", "--decimate", "10", "--json", "{tmp}/out.json"],
                     ["out.json"]),
    "curve": (["curve", "{curve}", "--units", "deg/h", "--fs", "10", "--n-samples", "108000",
               "--json", "{tmp}/out.json"], ["out.json"]),
    "davar": (["davar", "data/example_fog_10hz_3h.csv", "--window", "20min", "--step",
               "10min", "--json", "{tmp}/out.json"], ["out.json"]),
    "filter_kalman": (["filter", "data/startup_cold_1hz.csv", "-o", "{tmp}/f.csv",
                       "--json", "{tmp}/out.json"], ["out.json", "f.csv"]),
    "filter_ma": (["filter", "data/example_fog_10hz_3h.csv", "-o", "{tmp}/f.csv",
                   "--method", "moving-average", "--window", "10", "--compare-allan",
                   "--json", "{tmp}/out.json"], ["out.json", "f.csv"]),
    "compensate": (["compensate", "data/startup_cold_1hz.csv", "-o", "{tmp}/c.csv",
                    "--json", "{tmp}/out.json"], ["out.json", "c.csv"]),
    "northfind": (["northfind", "data/startup_northfind_1hz.csv", "--latitude", "40",
                   "--json", "{tmp}/out.json"], ["out.json"]),
    "simulate": (["simulate", "noise", "-o", "{tmp}/sim.csv", "--N", "0.01", "--B", "0.02",
                  "--K", "0.05", "--duration", "10min", "--fs", "10", "--seed", "11"],
                 ["sim.csv", "sim.csv.json"]),
}


def run_case(name: str, tmp: Path) -> dict[str, Any]:
    """Run one case with the working directory at the repository root; return its
    outputs (JSON as objects, CSV as lists of rows), with the output folder written
    ``<tmp>``; CSV outputs as :func:`_table_digest`."""
    args, outputs = CASES[name]
    gappy = _gappy_record(tmp) if any("{gappy}" in a for a in args) else None
    curve = _curve_file(tmp) if any("{curve}" in a for a in args) else None
    line = [a.format(tmp=tmp, gappy=gappy, curve=curve) for a in args]
    cwd = Path.cwd()
    os.chdir(ROOT)
    try:
        res = CliRunner().invoke(app, line)
    finally:
        os.chdir(cwd)
    assert res.exit_code in (0, 1), f"{name}: {res.stderr}"
    captured: dict[str, Any] = {"exit_code": res.exit_code}
    for out in outputs:
        text = (tmp / out).read_text().replace(str(tmp), "<tmp>")
        captured[out] = json.loads(text) if out.endswith(".json") else _table_digest(text)
    return captured


def _table_digest(text: str) -> dict[str, Any]:
    """A CSV output as its header, row count, about 200 evenly spaced rows (as text) and
    the column sums (every row counts, without storing megabytes of fixtures)."""
    rows = [row.split(",") for row in text.splitlines()]
    header, body = rows[0], rows[1:]
    frame = pd.read_csv(io.StringIO(text))
    sums = [float(frame[c].sum()) if frame[c].dtype.kind in "fi" else None for c in frame]
    return {"header": header, "n_rows": len(body),
            "sample": body[:: max(1, len(body) // 200)], "column_sums": sums}


def _close(expected: Any, actual: Any, where: str) -> None:
    if isinstance(expected, dict):
        assert isinstance(actual, dict) and list(expected) == list(actual), \
            f"{where}: keys differ: {list(expected)} != {list(actual)}"
        for k in expected:
            _close(expected[k], actual[k], f"{where}.{k}")
    elif isinstance(expected, list):
        assert isinstance(actual, list) and len(expected) == len(actual), \
            f"{where}: lengths differ"
        for i, (e, a) in enumerate(zip(expected, actual, strict=True)):
            _close(e, a, f"{where}[{i}]")
    elif isinstance(expected, float) or (isinstance(expected, str) and _is_float(expected)
                                         and _is_float(actual)):
        e, a = float(expected), float(actual)
        if EXACT or not (math.isfinite(e) and math.isfinite(a)):
            assert (e == a) or (math.isnan(e) and math.isnan(a)), f"{where}: {e!r} != {a!r}"
        else:
            assert math.isclose(e, a, rel_tol=REL_TOL, abs_tol=ABS_TOL), \
                f"{where}: {e!r} != {a!r}"
    elif isinstance(expected, str) and isinstance(actual, str) and not EXACT:
        _close_text(expected, actual, where)
    else:
        assert expected == actual, f"{where}: {expected!r} != {actual!r}"


_NUMBER = re.compile(r"[-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?")


def _close_text(expected: str, actual: str, where: str) -> None:
    """Messages that quote numbers: the words must be equal, each number within the
    tolerance or within one unit of its last printed digit."""
    words_e, words_a = _NUMBER.split(expected), _NUMBER.split(actual)
    nums_e, nums_a = _NUMBER.findall(expected), _NUMBER.findall(actual)
    assert words_e == words_a and len(nums_e) == len(nums_a), \
        f"{where}: {expected!r} != {actual!r}"
    for e, a in zip(nums_e, nums_a, strict=True):
        digits = len(re.sub(r"[^0-9]", "", e.split("e")[0].split("E")[0]).lstrip("0")) or 1
        rel = max(REL_TOL, 10.0 ** (1 - digits))
        assert math.isclose(float(e), float(a), rel_tol=rel, abs_tol=ABS_TOL), \
            f"{where}: {expected!r} != {actual!r}"


def _is_float(text: Any) -> bool:
    if not isinstance(text, str) or not any(c in text for c in ".eE"):
        return False
    try:
        float(text)
    except ValueError:
        return False
    return True


@pytest.mark.parametrize("name", sorted(CASES))
def test_outputs_match_the_golden_fixtures(name: str, tmp_path: Path) -> None:
    fixture = GOLDEN / f"{name}.json"
    if not fixture.exists():
        pytest.fail(f"no golden fixture {fixture.name}; run OPENBLAS_NUM_THREADS=1 python -m tests.test_golden")
    expected = json.loads(fixture.read_text())
    _close(expected, run_case(name, tmp_path), name)


def _regenerate(write: Callable[[str, dict[str, Any]], None]) -> None:
    import tempfile

    for name in sorted(CASES):
        with tempfile.TemporaryDirectory() as tmp:
            write(name, run_case(name, Path(tmp)))


if __name__ == "__main__":  # pragma: no cover - maintenance entry point
    GOLDEN.mkdir(exist_ok=True)

    def _write(name: str, doc: dict[str, Any]) -> None:
        (GOLDEN / f"{name}.json").write_text(json.dumps(doc, indent=1, sort_keys=False) + "\n")
        print(f"wrote {GOLDEN / name}.json", file=sys.stderr)

    _regenerate(_write)
