"""`fogts info`: what was read (columns, rate, units, gaps, jitter, glitches, statistics)."""

from __future__ import annotations

import dataclasses
from typing import TYPE_CHECKING, Any

from fogts.cli._common import (
    DEFAULT_READ,
    FileArg,
    JsonOpt,
    _emit_json,
    _guard,
    _read,
    app,
    console,
    reads_input,
)
from fogts.pipeline import ReadSettings

if TYPE_CHECKING:
    from fogts.io.run import Run



def _info_payload(run: Run) -> dict[str, Any]:
    from fogts.report.text import run_info

    return run_info(run)


@app.command("info")
@reads_input(gaps=False)
def info_cmd(
    file: FileArg,
    json_out: JsonOpt = None,
    read: ReadSettings = DEFAULT_READ,
) -> None:
    """Show what was read: columns, sample rate, duration, gaps, jitter, glitches and
    statistics."""
    with _guard(outputs={"--json": json_out}, inputs={"FILE": [file]}):
        run, quality = _read(file, dataclasses.replace(read, gaps="ignore"))
        payload = {**_info_payload(run), "data_quality": quality.to_dict()}
        _emit_json(payload, json_out)
        if json_out != "-":
            from fogts.report.text import info_text

            console.print(info_text(payload), markup=False, soft_wrap=True)
