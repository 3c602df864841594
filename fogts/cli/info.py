"""`fogts info`: what was read (columns, rate, units, gaps, jitter, glitches, statistics)."""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

from fogts.cli._common import (
    FileArg,
    FsOpt,
    JsonOpt,
    NanOpt,
    NanPolicy,
    RateColOpt,
    TempColOpt,
    TimeColOpt,
    UnitsOpt,
    _emit_json,
    _guard,
    _read,
    app,
    console,
)

if TYPE_CHECKING:
    from fogts.io.run import Run



def _info_payload(run: Run) -> dict[str, Any]:
    from fogts.report.text import run_info

    return run_info(run)


@app.command("info")
def info_cmd(
    file: FileArg,
    rate_column: RateColOpt = None,
    time_column: TimeColOpt = None,
    temperature_column: TempColOpt = None,
    fs: FsOpt = None,
    units: UnitsOpt = None,
    nan: NanOpt = NanPolicy.error,
    json_out: JsonOpt = None,
) -> None:
    """Show what was read: columns, sample rate, duration, gaps, jitter, glitches and
    statistics."""
    with _guard(outputs={"--json": json_out}, inputs={"FILE": [file]}):
        run, quality = _read(file, rate_column, time_column, temperature_column, fs, units,
                             nan=nan, gaps="ignore")
        payload = {**_info_payload(run), "data_quality": quality.to_dict()}
        _emit_json(payload, json_out)
        if json_out != "-":
            from fogts.report.text import info_text

            console.print(info_text(payload), markup=False, soft_wrap=True)
