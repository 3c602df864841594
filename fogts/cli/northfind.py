"""`fogts northfind`: four-position north seeking."""

from __future__ import annotations

import dataclasses
from pathlib import Path
from typing import TYPE_CHECKING, Annotated

import typer

from fogts.cli import _common as common
from fogts.pipeline import ReadSettings

#: Library argument names of ``fogts northfind`` and their options.
_NORTHFIND_OPTIONS = {"latitude_deg": "--latitude", "transition_s": "--transition",
                      "bias_sigma_deg_h": "--bias-sigma", "n_trials": "--simulate"}
#: Argument names the Earth-rate warning asks the user to check, as options.
_CHECK_OPTIONS = {"latitude_deg": "--latitude", "units": "--units"}

if TYPE_CHECKING:
    from fogts._typing import FloatArray
    from fogts.startup.thermal_model import ThermalModel



def _position_rates(files: list[Path], *, position_column: str, read: ReadSettings,
                    thermal: ThermalModel | None
                    ) -> tuple[dict[int, FloatArray], dict[int, float] | None, float, str]:
    import numpy as np

    from fogts.errors import DataError
    from fogts.startup.compensation import compensate
    from fogts.startup.northfind import POSITIONS_DEG, positions_from_frame

    if len(files) == 1:
        both = f"{read.rate_column or 'rate'},{position_column}"
        try:
            run, _ = common.read_input(files[0], dataclasses.replace(read, rate_column=both),
                                       glitches=False)
        except DataError as exc:  # the position column is read as a second rate column
            said = f"rate column {position_column!r} not found"
            if not str(exc).startswith(said):
                raise
            raise DataError(f"position column {position_column!r} (--position-column) not "
                            f"found{str(exc)[len(said):]}; give one file with the positions "
                            "in degrees, or four files (0, 90, 180, 270 degrees in that "
                            "order)") from None
        if thermal is not None:
            run = compensate(run, thermal, axis=0)
        import pandas as pd

        frame = pd.DataFrame({"position_deg": run.rate[:, 1], "rate": run.rate[:, 0],
                              "time": run.time})
        rates = positions_from_frame(frame)
        keys = np.round(frame["position_deg"].to_numpy()) % 360
        times = {p: float(frame["time"].to_numpy()[keys == p].mean()) for p in POSITIONS_DEG}
        return rates, times, run.fs_hz, run.units
    if len(files) != 4:
        raise DataError(f"give one file with a {position_column!r} column, or four files (0, 90, "
                        f"180, 270 degrees in that order); got {len(files)} files")
    from fogts.units import convert_rate

    rates = {}
    fs_hz, unit = 0.0, "deg/h"
    for p, path in zip(POSITIONS_DEG, files, strict=True):
        run, _ = common.read_input(path, read, glitches=False)
        if thermal is not None:
            run = compensate(run, thermal, axis=0)
        if p == POSITIONS_DEG[0]:
            fs_hz, unit = run.fs_hz, run.units
        elif abs(run.fs_hz - fs_hz) > 1e-6 * fs_hz:
            raise DataError(f"{path.name} (position {p}) is sampled at {run.fs_hz:g} Hz, "
                            f"{files[0].name} (position 0) at {fs_hz:g} Hz; the four "
                            "position files must share one sample rate")
        # each file in its own unit (a column named rate_deg_s beside plain deg/h files):
        # the positions are compared in the first file's
        rates[p] = np.asarray(convert_rate(run.axis(0), run.units, unit), dtype=np.float64)
    return rates, None, fs_hz, unit


def _check_mode_options(simulating: bool, *, plot: bool, given: dict[str, bool]) -> None:
    """Refuse, before any work or output, the options the chosen mode does not use:
    --plot outside --simulate, and the measured-positions options (``given``: option ->
    set away from its default) with --simulate."""
    from fogts.errors import DataError

    if plot and not simulating:
        raise DataError("--plot is available in --simulate mode only")
    stray = [o for o, on in given.items() if on]
    if simulating and stray:
        raise DataError(f"--simulate does not use {', '.join(stray)} (options of measured "
                        "positions files); drop it or give the files instead of --simulate")


@common.app.command("northfind")
@common.writes_outputs()
@common.reads_input(nan=False, gaps=False)
def northfind_cmd(
    files: Annotated[list[Path] | None, typer.Argument(help="One CSV with position_deg and rate columns, or four files for 0/90/180/270 degrees (omit with --simulate).")] = None,
    latitude: Annotated[float, typer.Option("--latitude", help="Latitude in degrees (|L| <= 89).")] = ...,  # type: ignore[assignment]
    thermal_model: Annotated[Path | None, typer.Option("--thermal-model", help="Compensate the rates with a saved thermal model (JSON from 'fogts compensate --save-model').")] = None,
    position_column: Annotated[str, typer.Option("--position-column", help="Column holding the position in degrees (0/90/180/270).")] = "position_deg",
    transition: Annotated[float, typer.Option("--transition", help="Seconds spent turning between positions (four-file input).")] = 0.0,
    bias_sigma: Annotated[float, typer.Option("--bias-sigma", help="1-sigma position-to-position bias variation in deg/h for the error budget.")] = 0.0,
    simulate: Annotated[int | None, typer.Option("--simulate", help="Simulation mode: repeat cold-start north seeking N times, with and without thermal compensation.")] = None,
    seed: Annotated[int, typer.Option("--seed", help="Random seed of the simulation mode.")] = 4,
    plot: Annotated[Path | None, typer.Option("--plot", help="Simulation mode: azimuth error per trial (.png, .svg, .pdf).")] = None,
    out: common.Outputs = common.NO_OUTPUTS,
    read: ReadSettings = common.DEFAULT_READ,
) -> None:
    """Four-position north seeking: azimuth of the input axis at position 0,
    clockwise from true north, with its error budget; or, with --simulate N, the cold-start
    error with and without thermal compensation.

    Exits 1 when the measured Earth-rate amplitude does not match Omega cos(latitude)
    (a wrong --units, --latitude or scale factor; a warning names the likely cause) or when
    the azimuth's 95 % interval spans a half circle ("no usable azimuth")."""
    from fogts.errors import DataError
    from fogts.startup import four_position, simulate_north_seeking

    with common.guard(_NORTHFIND_OPTIONS, overwrite=out.overwrite, outputs={"--json": out.json, "--plot": plot},
                inputs={"FILES": files or [],
                        "--thermal-model": [thermal_model] if thermal_model else []}):
        common.check_output_names(plot=plot)  # before any output is written
        _check_mode_options(simulate is not None, plot=plot is not None, given={
            "--bias-sigma": bias_sigma != 0.0, "--transition": transition != 0.0,
            "--position-column": position_column != "position_deg"})
        thermal = common.load_thermal_model(thermal_model) if thermal_model is not None else None
        if thermal is not None:
            from fogts.startup.thermal_identification import reuse_warning

            common.warn(reuse_warning(thermal))
        if simulate is not None:
            if files:
                raise DataError("--simulate takes no input files")
            notes = []
            if thermal is None:
                from fogts.startup.northfind_simulation import simulated_calibration

                thermal = simulated_calibration((15.0, 20.0, 25.0), rng=seed + 1_000_003)
                notes.append("thermal model fitted on three separate simulated calibration cold "
                             "starts (ambient 15, 20, 25 degC)")
            study = simulate_north_seeking(simulate, latitude_deg=latitude, model=thermal,
                                           rng=seed)
            payload = {"mode": "simulate", "seed": seed, **study.to_dict(), "notes": notes}
            common.emit_json(payload, out.json)
            if plot is not None:
                from fogts.report.plots import plot_north_seeking

                common.save_figure(plot_north_seeking(study), plot)
            common.say([study.summary(), *notes], out.json)
            return
        if not files:
            raise DataError("give one positions file or four files, or --simulate N")
        rates, times, fs_hz, unit = _position_rates(
            files, position_column=position_column,
            read=dataclasses.replace(read, gaps="ignore"), thermal=thermal)
        result = four_position(rates, latitude_deg=latitude, fs_hz=fs_hz, units=unit,
                               position_time_s=times, transition_s=transition,
                               bias_sigma_deg_h=bias_sigma)
        payload = {"input": [str(f) for f in files],
                   "thermal_model": None if thermal_model is None else str(thermal_model),
                   **result.to_dict()}
        common.emit_json(payload, out.json)
        common.say([result.summary()], out.json)
        if result.scale_warning is not None:
            common.warn(common.option_names(result.scale_warning, _CHECK_OPTIONS))
    if result.exit_code:  # the Earth-rate check failed or the azimuth is not determined
        raise typer.Exit(common.ExitCode.NEGATIVE)
