"""``--axis``, declared once: :data:`AxisOpt` for the one-axis commands (``select``,
``compensate``, ``filter``: a name, an index or ``all``, default the first axis) and
:data:`EveryAxisOpt` for those that analyse every axis by default (``allan``, ``davar``); for
the one-axis commands, the line that says which axis was used, and the per-axis names of the
figures and models written when several axes are analysed.

Tables (``--output``, ``--predict``) stay one file: with several axes they gain an ``axis``
column first, as ``fogts allan --csv`` does.
"""

from __future__ import annotations

import re
from pathlib import Path
from typing import TYPE_CHECKING, Annotated

import typer

from fogts.cli import _common as common

if TYPE_CHECKING:
    import pandas as pd

    from fogts.io.run import Run

#: The help text of ``--axis`` on the one-axis commands.
AXIS_HELP = ("Axis to analyse: a name, an index (negative from the end) or 'all' (each axis "
             "in turn; figures and saved models get the axis name in their file names, "
             "tables an 'axis' column). Default: the first axis, named in the output.")
AxisOpt = Annotated[str | None, typer.Option("--axis", help=AXIS_HELP)]
EveryAxisOpt = Annotated[str | None, typer.Option("--axis", help="Analyse one axis (name or index) (default: every axis).")]


def axis_picks(run: Run, axis: str | None) -> list[int]:
    """The axes ``--axis`` selects: every axis for ``all``, the first for None."""
    if axis is not None and axis.strip().lower() == "all":
        return list(range(run.n_axes))
    return [0 if axis is None else common.axis_index(run, axis)]


def axis_lines(run: Run, picks: list[int], axis: str | None) -> list[str]:
    """Which axis (or axes) the command analyses and how the default was chosen; nothing
    for a file with one axis."""
    if run.n_axes == 1:
        return []
    if len(picks) > 1:
        return [f"axes      all {len(picks)}: {', '.join(run.axes[i] for i in picks)}"]
    name = run.axes[picks[0]]
    if axis is not None:
        return [f"axis      {name!r} (--axis {axis})"]
    return [f"axis      {name!r} (default: the first of {run.n_axes}: "
            f"{', '.join(run.axes)}; choose with --axis NAME, INDEX or all)"]


def axis_path(path: Path, run: Run, i: int, many: bool) -> Path:
    """``path`` for axis ``i``: unchanged for one axis; with several, the axis name (its
    letters, digits, '-' and '_') appended to the stem, with the axis number if two names
    would collide (``plot.png`` -> ``plot_Gyro_X.png``)."""
    if not many:
        return path
    safe = [re.sub(r"[^\w-]+", "_", a).strip("_") or str(k + 1) for k, a in enumerate(run.axes)]
    tag = safe[i] if safe.count(safe[i]) == 1 else f"{i + 1}_{safe[i]}"
    suffixes = "".join(path.suffixes[-2:]) if path.name.lower().endswith(".csv.gz") \
        else path.suffix
    return path.with_name(f"{path.name[: len(path.name) - len(suffixes)]}_{tag}{suffixes}")


def with_axis_column(frames: list[pd.DataFrame], names: list[str], *, many: bool
                     ) -> pd.DataFrame:
    """One table of per-axis tables: as it is for one axis, with ``axis`` first when
    several were analysed."""
    import pandas as pd

    if not many:
        return frames[0]
    return pd.concat([f.assign(axis=n)[["axis", *f.columns]] for f, n in zip(frames, names,
                                                                            strict=True)],
                     ignore_index=True)
