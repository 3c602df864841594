"""Results as JSON-safe dicts and JSON text, one-line messages, and the ``fogts info`` text.

JSON conventions: keys are stable; NaN and inf become ``null``; numpy scalars and arrays
become Python numbers and lists; floats are written with ``repr`` precision so that the same
input gives byte-identical JSON.
"""

from __future__ import annotations

import dataclasses
import json
import math
import warnings
from collections.abc import Callable, Iterable, Mapping
from typing import Any

import numpy as np

from fogts.io.run import Run, held_time
from fogts.io.timebase import REGULAR_JITTER
from fogts.units import quantity_of

__all__ = ["axes_rows", "duration_line", "duration_text", "error_message", "fit_sentences",
           "gaps_phrase", "info_text", "json_dumps", "run_info", "time_base_verdict", "time_span_s",
           "to_jsonable", "warning_texts"]


def to_jsonable(obj: Any) -> Any:
    """Recursively convert ``obj`` to JSON-safe Python types (NaN/inf -> None)."""
    if obj is None or isinstance(obj, bool | str):
        return obj
    if isinstance(obj, np.bool_):
        return bool(obj)
    if isinstance(obj, int | np.integer):
        return int(obj)
    if isinstance(obj, float | np.floating):
        v = float(obj)
        return v if math.isfinite(v) else None
    if isinstance(obj, complex | np.complexfloating):
        return {"real": to_jsonable(obj.real), "imag": to_jsonable(obj.imag)}
    if isinstance(obj, np.ndarray):
        return [to_jsonable(v) for v in obj.tolist()]
    if hasattr(obj, "to_dict") and callable(obj.to_dict) and not isinstance(obj, Mapping):
        return to_jsonable(obj.to_dict())
    if dataclasses.is_dataclass(obj) and not isinstance(obj, type):
        return {f.name: to_jsonable(getattr(obj, f.name)) for f in dataclasses.fields(obj)}
    if isinstance(obj, Mapping):
        return {str(k): to_jsonable(v) for k, v in obj.items()}
    if isinstance(obj, list | tuple | set | frozenset):
        return [to_jsonable(v) for v in obj]
    return str(obj)


def json_dumps(obj: Any, *, indent: int | None = 2) -> str:
    """Deterministic JSON text of ``obj`` (see module docstring)."""
    return json.dumps(to_jsonable(obj), indent=indent, allow_nan=False, ensure_ascii=False)


# --------------------------------------------------------------------------- messages


def error_message(exc: BaseException) -> str:
    """One line for an exception, as the CLI prints it after ``error:``.

    fogts' own errors (and ``ValueError``/``OSError``) keep their message; anything else is
    labelled as an internal error with its type.
    """
    from fogts.errors import FogtsError

    text = str(exc).strip()
    msg = text.splitlines()[0] if text else type(exc).__name__
    if not isinstance(exc, FogtsError | ValueError | OSError):
        msg = f"internal error ({type(exc).__name__}): {msg}"
    return msg


def warning_texts(caught: Iterable[warnings.WarningMessage]) -> list[str]:
    """The first line of each distinct warning, in order."""
    seen: list[str] = []
    for w in caught:
        text = str(w.message).strip().splitlines()[0] if str(w.message).strip() else ""
        if text and text not in seen:
            seen.append(text)
    return seen


# --------------------------------------------------------------------------- run info


def fit_sentences(model: Any) -> list[str]:
    """The noise fit's own account under its term table, as ``fogts allan`` prints it and
    the report shows it: the ML or GMWM description, else the least-squares
    ``fit: chi2 ...`` line (:func:`fogts.allan.noise_lsq.chi2_sentence`) with the
    standard errors' method; then one sentence per extra term (Markov, sinusoid)."""
    if model.ml is not None:
        lines = [model.ml.describe()]
    elif model.gmwm is not None:
        lines = [model.gmwm.describe()]
    else:
        from fogts.allan.noise_lsq import chi2_sentence

        chi2 = chi2_sentence(model.chi2, model.dof, model.model_error, model.model_error_lr,
                             model.significance)
        lines = [f"fit: {chi2}; "
                 f"standard errors: {model.stderr_method}"]
    return lines + [e.describe() for e in model.extra_terms]


def _stats(x: np.ndarray) -> dict[str, float]:
    return {"mean": float(np.mean(x)), "std": float(np.std(x, ddof=1)) if x.size > 1 else 0.0,
            "min": float(np.min(x)), "max": float(np.max(x))}


def run_info(run: Run) -> dict[str, Any]:
    """The ``fogts info`` JSON payload (its keys are stable).

    Keys: ``source, n, fs_hz, duration_s, columns, units, axes, axis_units, gaps, jitter,
    stats`` (plus ``span_s``, ``input``, ``start_time``, ``temperature``, ``fs_source`` and
    ``comments``); ``axis_units`` gives each axis' own unit (an accelerometer axis' is not
    ``units``); ``input`` what the rate columns held (``rate``, ``increment`` or ``angle``:
    the axes and ``stats`` are the rate formed from them).  ``duration_s`` is the samples' time, ``n / fs_hz``; ``span_s`` the time
    the stamps cover (first to last stamp, plus one step), longer by the gaps.
    ``gaps.burst_logged``: the stamps are logged in bursts (the rate is the mean step's),
    so the ``gaps.count`` long steps are the bursts' pattern, not gaps
    (:func:`fogts.io.timebase.burst_logging_text`).
    """
    sampling = run.sampling
    assert sampling is not None
    stats = {name: _stats(run.axis(i)) for i, name in enumerate(run.axes)}
    if run.temperature is not None:
        stats["temperature"] = _stats(run.temperature)
    return {
        "source": run.source,
        "n": run.n,
        "fs_hz": run.fs_hz,
        "duration_s": run.duration_s,
        "span_s": time_span_s(run),
        "columns": list(run.columns),
        "units": run.units,
        "axes": list(run.axes),
        "axis_units": [run.unit_of(i) for i in range(len(run.axes))],
        "input": run.input_kind,
        "gaps": {"count": sampling.n_gaps, "max_s": sampling.max_gap_s,
                 "threshold_s": 1.5 / run.fs_hz, "after_rows": list(sampling.gap_rows),
                 "burst_logged": sampling.fs_source == "mean step"},
        "jitter": {"std_s": sampling.jitter_s, "relative": sampling.jitter_rel,
                   "median_dt_s": sampling.median_dt_s, "mean_dt_s": sampling.mean_dt_s,
                   "regular": sampling.regular},
        "stats": stats,
        "fs_source": sampling.fs_source,
        "time_from_column": sampling.from_time_column,
        "start_time": run.start_time,
        "temperature": run.temperature is not None,
        "comments": list(run.comments),
    }


def time_span_s(run: Run) -> float:
    """The time the stamps cover: first to last stamp plus one step (``n / fs_hz`` for a
    time base built from the sample rate); longer than ``run.duration_s`` by the gaps."""
    stamps = held_time(run)
    if stamps is None or stamps.size == 0:
        return run.duration_s
    return float(stamps[-1] - stamps[0]) + 1.0 / run.fs_hz


def duration_text(seconds: float) -> str:
    """A record's length as every text and figure says it: hours from 1 h, minutes from
    1 min, with the seconds after them.

    Examples
    --------
    >>> duration_text(10000.0), duration_text(595.0), duration_text(5.0)
    ('2.78 h (10000 s)', '9.92 min (595 s)', '5 s')
    """
    if seconds >= 3600:
        return f"{seconds / 3600:.3g} h ({seconds:.6g} s)"
    if seconds >= 60:
        return f"{seconds / 60:.3g} min ({seconds:.6g} s)"
    return f"{seconds:.6g} s"


def axes_rows(info: Mapping[str, Any], accel_source: str = "") -> list[tuple[str, str]]:
    """The sensor axes of :func:`run_info`'s payload grouped by unit (``axis_units``):
    ``("rate axes", "x, y, z  [deg/s]")`` and, for an IMU file, ``("accel axes", "ax, ay,
    az  [g] (unit from gravity magnitude)")`` (``accel_source``: where the accelerometer
    unit came from, :attr:`Run.accel_units_source`); an accelerometer axis is never listed
    as a rate axis in the rate unit."""
    groups: dict[str, list[str]] = {}
    for name, unit in zip(info["axes"], info["axis_units"], strict=True):
        groups.setdefault(unit, []).append(name)
    rows = []
    for unit, names in groups.items():
        if quantity_of(unit) == "accel":
            rows.append(("accel axes", f"{', '.join(names)}  [{unit}] (unit from "
                                       f"{accel_source or 'the file'})"))
        else:
            rows.append(("rate axes", f"{', '.join(names)}  [{unit}]"
                                      f"{_FORMED_FROM.get(info.get('input', 'rate'), '')}"))
    return rows


#: What the rate axes of a record read as angle increments or angles are (the statistics
#: too are the rate's).
_FORMED_FROM = {
    "increment": " (the columns hold angle increments: rate = increment x fs)",
    "angle": " (the columns hold an angle: rate = its difference x fs)",
}


def time_base_verdict(info: Mapping[str, Any]) -> str:
    """"regular", or "IRREGULAR" with the reason the numbers beside it give (gaps, or a
    jitter of at least 1 % of the step), for :func:`run_info`'s payload."""
    if info["jitter"]["regular"]:
        return "regular"
    why = []
    if info["gaps"].get("burst_logged"):
        why.append("time stamps logged in bursts")
    elif info["gaps"]["count"]:
        why.append("gaps")
    if info["jitter"]["relative"] >= REGULAR_JITTER:
        why.append(f"jitter >= {100 * REGULAR_JITTER:g} % of the step")
    return "IRREGULAR" + (f" ({', '.join(why)})" if why else "")


def gaps_phrase(info: Mapping[str, Any], fmt: Callable[[float], str]) -> str:
    """The long steps of :func:`run_info`'s payload: "3 gap(s) longer than 0.015 s
    (longest 0.5 s)", or for burst-logged stamps that they are the bursts' pattern, not
    gaps, as the data-quality warning says (:func:`fogts.io.timebase.burst_logging_text`).
    ``fmt`` formats a number (the terminal's or the report's)."""
    gaps = info["gaps"]
    longest = f"longest {fmt(gaps['max_s'])} s"
    if gaps.get("burst_logged"):
        return (f"{gaps['count']} step(s) longer than {fmt(gaps['threshold_s'])} s ({longest}), "
                "the bursts' pattern, not gaps: no time is counted as missing")
    return f"{gaps['count']} gap(s) longer than {fmt(gaps['threshold_s'])} s ({longest})"


def duration_line(info: Mapping[str, Any]) -> str:
    """The duration of :func:`run_info`'s payload, and the stamps' span after it when gaps
    make the span longer by over one step ("2.83 h (10200 s) of samples; the time stamps
    span 3 h (10800 s)")."""
    text = duration_text(info["duration_s"])
    span = info.get("span_s")
    if span is None or span - info["duration_s"] <= 1.0 / info["fs_hz"]:
        return text
    return f"{text} of samples; the time stamps span {duration_text(span)}"


def info_text(info: Mapping[str, Any], accel_source: str = "") -> str:
    """Plain-text rendering of :func:`run_info` for the terminal (``accel_source``: see
    :func:`axes_rows`)."""
    jitter = info["jitter"]
    shown = axes_rows(info, accel_source)
    lines = [
        f"source      {info['source']}",
        f"samples     {info['n']}",
        f"sample rate {info['fs_hz']:.6g} Hz (from {info['fs_source']})",
        f"duration    {duration_line(info)}",
        f"columns     {', '.join(info['columns'])}",
        *(f"{label:<11} {text}" for label, text in shown),
    ]
    if info["start_time"]:
        lines.append(f"start time  {info['start_time']}")
    if info["time_from_column"]:
        regular = time_base_verdict(info)
        lines.append(f"time base   {regular}: {gaps_phrase(info, lambda v: f'{v:.4g}')}; "
                     f"jitter {jitter['std_s']:.3g} s "
                     f"({100 * jitter['relative']:.2g} % of the step); median step "
                     f"{jitter['median_dt_s']:.6g} s, mean step {jitter['mean_dt_s']:.6g} s")
    else:
        lines.append("time base   none in the file: built from the sample rate")
    lines.append("")
    lines.append(f"{'column':<24}{'mean':>14}{'std':>14}{'min':>14}{'max':>14}")
    for name, st in info["stats"].items():
        lines.append(f"{name:<24}{st['mean']:>14.6g}{st['std']:>14.6g}{st['min']:>14.6g}"
                     f"{st['max']:>14.6g}")
    for c in info["comments"][:5]:
        lines.append(f"comment     {c}")
    if len(info["comments"]) > 5:
        lines.append(f"            ... {len(info['comments']) - 5} more comment line(s)")
    return "\n".join(lines)
