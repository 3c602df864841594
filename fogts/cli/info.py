"""`fogts info`: what was read (columns, rate, units, gaps, jitter, glitches, statistics)."""

from __future__ import annotations

import dataclasses
from typing import TYPE_CHECKING, Any

from fogts.cli import _common as common
from fogts.pipeline import ReadSettings

if TYPE_CHECKING:
    from fogts.io.run import Run



def _info_payload(run: Run) -> dict[str, Any]:
    from fogts.report.text import run_info

    return run_info(run)


@common.app.command("info")
@common.writes_outputs()
@common.reads_input(gaps=False)
def info_cmd(
    file: common.FileArg,
    out: common.Outputs = common.NO_OUTPUTS,
    read: ReadSettings = common.DEFAULT_READ,
) -> None:
    """Show what was read: columns, sample rate, duration, gaps, jitter, glitches and
    statistics."""
    with common.guard(overwrite=out.overwrite, outputs={"--json": out.json}, inputs={"FILE": [file]}):
        run, quality = common.read_input(file, dataclasses.replace(read, gaps="ignore"))
        payload = {**_info_payload(run), "data_quality": quality.to_dict()}
        common.emit_json(payload, out.json)
        if out.json != "-":
            from fogts.report.text import info_text

            common.console.print(info_text(payload, run.accel_units_source), markup=False,
                                 soft_wrap=True)
