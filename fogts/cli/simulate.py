"""`fogts simulate noise` (gyro noise from IEEE-952 coefficients) and `fogts simulate startup`
(a cold start with thermal drift, optionally a four-position north seeking)."""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING, Annotated, Any

import typer

from fogts import choices
from fogts.cli import _common as common

if TYPE_CHECKING:
    import pandas as pd

    from fogts.simulate import NoiseSpec

#: Library argument names of ``fogts simulate`` (both modes) and their options.
_SIMULATE_OPTIONS = {
    "fs_hz": "--fs", "duration_s": "--duration", "latitude_deg": "--latitude",
    "azimuth_deg": "--azimuth", "position_s": "--position-time", "turn_s": "--turn-time",
    "start_delay_s": "--start-after", "start_s": "--start-after",
    "ambient_degC": "--ambient-c", "peak_rate_degC_s": "--peak-heating-c-s",
    "tau_s": "--time-constants", "white_sigma_deg_h": "--white-deg-h",
    "temperature_resolution_degC": "--temperature-resolution-c", "n_axes": "--axes",
}


_SIM_SUFFIXES = (".csv", ".csv.gz", ".tsv", ".txt", ".parquet", ".pq")


def _pair(text: str | None, option: str, names: str) -> tuple[float, float] | None:
    """Parse ``"a,b"`` into two floats (for --markov and --sine)."""
    import math

    from fogts.errors import DataError

    if text is None:
        return None
    parts = [p.strip() for p in text.split(",")]
    try:
        a, b = (float(p) for p in parts) if len(parts) == 2 else (math.nan, math.nan)
    except ValueError:
        a = b = math.nan
    if not (math.isfinite(a) and math.isfinite(b)):
        raise DataError(f"{option} must be two numbers '{names}', got {text!r}")
    return a, b


def _coefficients(text: str | None, option: str) -> dict[str, float] | None:
    """Parse ``"T=0.02,dT=30,1=0.5"`` into a dict."""
    from fogts.errors import DataError

    if text is None:
        return None
    out: dict[str, float] = {}
    for part in text.split(","):
        key, sep, value = part.partition("=")
        try:
            out[key.strip()] = float(value)
        except ValueError:
            sep = ""
        if not sep:
            raise DataError(f"{option} must look like 'T=0.02,dT=30,1=0.5', got {text!r}")
    return out


simulate_app = typer.Typer(
    help="Simulate a static gyro record: 'noise' from IEEE-952 coefficients, 'startup' a cold "
         "start with thermal drift (optionally a four-position north seeking).",
    no_args_is_help=True, rich_markup_mode="markdown")
common.app.add_typer(simulate_app, name="simulate")

OutputOpt = Annotated[Path, typer.Option("--output", "-o", help="Output file: .csv, .csv.gz, .tsv, .txt or .parquet. The true parameters go to OUTPUT.json beside it. Existing files are replaced only with --overwrite.")]
SampleRateOpt = Annotated[float, typer.Option("--fs", help="Sample rate in Hz.")]
DurationOpt = Annotated[str | None, typer.Option("--duration", help="Record length: 3h, 90min, 600s, 1d, 1h30min or seconds (default 1h).")]
BiasOpt = Annotated[float, typer.Option("--bias", help="Constant rate offset in deg/h.")]
ThermalOpt = Annotated[str | None, typer.Option("--thermal", help="Temperature-driven drift D = a T dT + b T^2 + c T + d dT^2 + e dT + f, as `T*dT=a,T2=b,T=c,dT2=d,dT=e,1=f` (deg/h; dT in degC/s); with 'noise' it needs --temperature-profile; 'startup' default: `T*dT=0.4,T2=0.0015,T=-0.12,dT2=120,dT=25,1=2`.")]
SeedOpt = Annotated[int | None, typer.Option("--seed", help="Random seed (default: a fresh one, recorded in the sidecar JSON).")]
OutUnitsOpt = Annotated[str, typer.Option("--units", help="Unit of the output rate: deg/h, deg/s, rad/s, arcsec/s (coefficients stay in deg/h-based units).")]
DecimalsOpt = Annotated[int | None, typer.Option("--decimals", help="Round the rate and temperature to this many decimals (smaller files).")]


# Over 80 lines by its 20 option declarations and the sidecar record written beside the output.
@simulate_app.command("noise")
@common.writes_outputs(json=False)
def simulate_noise_cmd(
    output: OutputOpt,
    fs: SampleRateOpt = 100.0,
    duration: DurationOpt = None,
    q_term: Annotated[float, typer.Option("--Q", help="Angle quantization Q in arcsec.")] = 0.0,
    n_term: Annotated[float, typer.Option("--N", help="Angle random walk N in deg/sqrt(h).")] = 0.0,
    b_term: Annotated[float, typer.Option("--B", help="Bias instability B in deg/h (Allan plateau 0.664 B).")] = 0.0,
    k_term: Annotated[float, typer.Option("--K", help="Rate random walk K in deg/h^1.5.")] = 0.0,
    r_term: Annotated[float, typer.Option("--R", help="Rate ramp R in deg/h^2.")] = 0.0,
    markov: Annotated[str | None, typer.Option("--markov", help="First-order Markov term 'q_c,T_c': q_c in deg/h/sqrt(s), T_c in s.")] = None,
    sine: Annotated[str | None, typer.Option("--sine", help="Sinusoid 'amplitude,frequency': deg/h and Hz.")] = None,
    bias: BiasOpt = 0.0,
    arma: Annotated[str | None, typer.Option("--arma", help="ARMA drift added to the rate, e.g. 'ar=0.9,-0.2;ma=0.3;sigma2=1e-4' (statsmodels signs; deg/h).")] = None,
    noise_json: Annotated[Path | None, typer.Option("--from-json", help="Take the noise terms from a JSON file: 'fogts allan --json' output, a NoiseModel dict or a simulate sidecar; --Q/--N/... override single terms.")] = None,
    axes: Annotated[int, typer.Option("--axes", help="Number of independent axes (rate_x, rate_y, rate_z).")] = 1,
    temperature_profile: Annotated[str | None, typer.Option("--temperature-profile", help="Temperature column: 'constant:T', 'warmup:START,END,TAU' (degC; TAU like 20min) or 'ramp:START,END'.")] = None,
    thermal: ThermalOpt = None,
    flicker: Annotated[choices.FlickerMethod, typer.Option("--flicker", help="Flicker (B) synthesis: markov (sum of Markov processes, chunked) or kasdin (Kasdin-Walter, in memory).")] = "markov",
    seed: SeedOpt = None,
    units: OutUnitsOpt = "deg/h",
    decimals: DecimalsOpt = None,
    out: common.Outputs = common.NO_OUTPUTS,
) -> None:
    """Simulate a static gyro record from IEEE-952 noise coefficients (IEEE Std 952-1997,
    Annex C, Table C.1).

    Writes time, rate (rate_x, rate_y, rate_z with --axes 3) and temperature (with a
    profile), and a sidecar JSON OUTPUT.json with the true parameters and the closed-form
    Allan deviation.
    """
    import numpy as np

    from fogts._version import __version__ as version
    from fogts.errors import DataError
    from fogts.io.writer import write_frame_atomic, write_text_atomic
    from fogts.report.text import json_dumps
    from fogts.simulate import ArmaSpec, TemperatureProfile, simulate_gyro
    from fogts.units import parse_duration

    sidecar_path = Path(f"{output}.json")  # never raises, whatever the user typed
    with common.guard(_SIMULATE_OPTIONS, overwrite=out.overwrite, outputs={"--output": output,
                                            "--output's sidecar": sidecar_path},
                inputs={"--from-json": [noise_json] if noise_json else []}):
        _check_simulation_output(output)
        duration_s = parse_duration("1h" if duration is None else duration, "--duration")
        spec = _noise_spec(noise_json, {"Q": q_term, "N": n_term, "B": b_term, "K": k_term,
                                         "R": r_term, "bias": bias}, markov=markov, sine=sine)
        arma_spec = ArmaSpec.parse(arma) if arma is not None else None
        profile = TemperatureProfile.parse(temperature_profile) \
            if temperature_profile is not None else None
        coefs = _coefficients(thermal, "--thermal")
        if decimals is not None and not 0 <= decimals <= 15:
            raise DataError(f"--decimals must be in 0..15, got {decimals}")
        if seed is None:
            seed = int(np.random.SeedSequence().generate_state(1, np.uint64)[0] >> np.uint64(1))
        run = simulate_gyro(spec, fs_hz=fs, duration_s=duration_s, rng=seed, units=units,
                            n_axes=axes, arma=arma_spec, temperature=profile,
                            thermal_coefficients=coefs,
                            flicker=flicker)
        frame = _rounded(run.to_frame(), decimals)
        m = 2 ** np.arange(int(np.log2(max(run.n // 4, 1))) + 1)
        sidecar = {
            "generator": f"fogts {version} simulate noise", "output": output.name, "seed": seed,
            "fs_hz": run.fs_hz, "duration_s": run.duration_s, "n": run.n, "units": run.units,
            "columns": list(frame.columns), "axes": list(run.axes), "flicker": flicker,
            "decimals": decimals, "noise": spec.to_dict(),
            "arma": arma_spec.to_dict() if arma_spec is not None else None,
            "temperature_profile": profile.to_dict() if profile is not None else None,
            "thermal_coefficients": coefs,
            "closed_form": {"kind": "oadev", "units": run.units, "tau": (m / run.fs_hz).tolist(),
                            "dev": spec.adev(m / run.fs_hz, units=run.units).tolist(),
                            "note": "IEEE 952 Table C.1 closed form of the noise terms "
                                    "(without ARMA and thermal drift)"},
        }
        write_frame_atomic(output, frame)
        side = output.with_name(output.name + ".json")
        write_text_atomic(side, json_dumps(sidecar) + "\n")
        common.console.print(f"wrote {output}: {run.n:,} samples x {run.n_axes} axis(es) at "
                      f"{run.fs_hz:g} Hz ({run.duration_s:g} s), rate in {run.units}, seed "
                      f"{seed}; true parameters in {side}", markup=False, soft_wrap=True)
        common.console.print(spec.summary(), markup=False, soft_wrap=True)


def _noise_spec(noise_json: Path | None, given: dict[str, float], *, markov: str | None,
                sine: str | None) -> NoiseSpec:
    """The noise terms: those of ``--from-json`` (if given), overridden by the non-zero
    ``--Q/--N/--B/--K/--R/--bias``, plus ``--markov`` and ``--sine``."""
    import dataclasses

    from fogts.simulate import NoiseSpec

    values: dict[str, float] = {}
    if noise_json is not None:
        from fogts.io.reader import read_json

        loaded = read_json(noise_json, "--from-json file")
        values.update(dataclasses.asdict(_from_json_terms(loaded, given)))
    values.update({k: v for k, v in given.items() if v != 0.0 or k not in values})
    pm = _pair(markov, "--markov", "q_c,T_c")
    if pm is not None:
        values["q_c"], values["T_c"] = pm
    ps = _pair(sine, "--sine", "amplitude,frequency")
    if ps is not None:
        values["Omega_0"], values["f_0"] = ps
    return NoiseSpec(**values)


def _from_json_terms(loaded: Any, given: dict[str, float]) -> NoiseSpec:
    """``--from-json``'s terms; the warning that a term was not measured is left out for a
    term the command line sets itself (``--K 0.3``)."""
    import warnings

    from fogts.simulate import NoiseSpec
    from fogts.simulate.noise_spec import NOT_MEASURED_PREFIX

    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        spec = NoiseSpec.from_any(loaded)
    set_here = tuple(f"{NOT_MEASURED_PREFIX}{k} = " for k, v in given.items() if v != 0.0)
    for w in caught:
        if not str(w.message).startswith(set_here):
            warnings.warn_explicit(w.message, w.category, w.filename, w.lineno)
    return spec


def _rounded(frame: pd.DataFrame, decimals: int | None) -> pd.DataFrame:
    """Time to the nanosecond and, with ``--decimals``, the other columns to that many
    decimals (smaller files)."""
    import numpy as np

    frame["time"] = np.round(frame["time"].to_numpy(), 9)
    if decimals is not None:
        for col in frame.columns[1:]:
            frame[col] = np.round(frame[col].to_numpy(), decimals)
    return frame


def _duration_or_zero(text: str | None, option: str, default: float) -> float:
    """A duration option that may also be 0 (``"0"``, ``"0s"``)."""
    from fogts.units import parse_duration

    if text is None:
        return default
    if text.strip().rstrip("s").strip() in ("0", "0.0"):
        return 0.0
    return parse_duration(text, option)


@simulate_app.command("startup")
@common.writes_outputs(json=False)
def simulate_startup_cmd(
    output: OutputOpt,
    duration: DurationOpt = None,
    fs: SampleRateOpt = 1.0,
    bias: BiasOpt = 0.0,
    arma: Annotated[str | None, typer.Option("--arma", help="ARMA drift of the rate (statsmodels signs; deg/h) (default 'ar=0.9;sigma2=0.0025').")] = None,
    thermal: ThermalOpt = None,
    seed: SeedOpt = None,
    units: OutUnitsOpt = "deg/h",
    decimals: DecimalsOpt = None,
    ambient_c: Annotated[float, typer.Option("--ambient-c", help="Ambient (switch-on) temperature in degC.")] = 20.0,
    peak_heating_c_s: Annotated[float | None, typer.Option("--peak-heating-c-s", help="Peak warm-up rate dT/dt in degC/s (default 0.05, as in the published FOG cold-start record the simulator follows).")] = None,
    time_constants: Annotated[str | None, typer.Option("--time-constants", help="Slow and fast warm-up lags 'SLOW,FAST' (default '400s,40s').")] = None,
    white_deg_h: Annotated[float | None, typer.Option("--white-deg-h", help="1-sigma white rate noise per sample in deg/h (default 0.3; = 60 N sqrt(fs) with N in deg/sqrt(h)).")] = None,
    temperature_resolution_c: Annotated[float | None, typer.Option("--temperature-resolution-c", help="Temperature sensor resolution in degC, 0 = exact (default 0.01).")] = None,
    start_after: Annotated[str | None, typer.Option("--start-after", help="Time from switch-on to the first sample, e.g. 10min (default 0).")] = None,
    positions: Annotated[bool, typer.Option("--positions", help="Four-position north seeking during the cold start: writes time,position_deg,rate,temperature for 'fogts northfind'; needs --latitude and --azimuth.", rich_help_panel="Four-position north seeking")] = False,
    latitude: Annotated[float | None, typer.Option("--latitude", help="Latitude in degrees (|L| <= 89) for --positions.", rich_help_panel="Four-position north seeking")] = None,
    azimuth: Annotated[float | None, typer.Option("--azimuth", help="True azimuth of the input axis at position 0 in degrees, clockwise from north, for --positions.", rich_help_panel="Four-position north seeking")] = None,
    position_time: Annotated[str | None, typer.Option("--position-time", help="Time measured at each position (default 60s).", rich_help_panel="Four-position north seeking")] = None,
    turn_time: Annotated[str | None, typer.Option("--turn-time", help="Time spent turning between positions, left out of the file (default 10s).", rich_help_panel="Four-position north seeking")] = None,
    out: common.Outputs = common.NO_OUTPUTS,
) -> None:
    """Simulate a cold start: warm-up temperature, thermal drift
    (--thermal), ARMA drift and white noise; writes time, rate, temperature for
    'fogts compensate', 'filter' and (with --positions) 'northfind'.

    The sidecar JSON OUTPUT.json holds the true thermal coefficients and warm-up
    parameters.
    """
    sidecar_path = Path(f"{output}.json")  # never raises, whatever the user typed
    with common.guard(_SIMULATE_OPTIONS, overwrite=out.overwrite, outputs={"--output": output,
                                            "--output's sidecar": sidecar_path}):
        _check_simulation_output(output)
        cold = {"--ambient-c": ambient_c, "--peak-heating-c-s": peak_heating_c_s,
                "--time-constants": time_constants, "--white-deg-h": white_deg_h,
                "--temperature-resolution-c": temperature_resolution_c,
                "--start-after": start_after, "--positions": positions or None,
                "--latitude": latitude, "--azimuth": azimuth,
                "--position-time": position_time, "--turn-time": turn_time}
        _simulate_startup(output, fs=fs, duration=duration, seed=seed, units=units,
                          decimals=decimals, bias=bias, arma=arma, thermal=thermal, cold=cold)


def _check_simulation_output(output: Path) -> None:
    """Refuse an output name of another type (an existing file is refused by the guard
    without --overwrite: a simulated record looks like a recording)."""
    from fogts.errors import DataError

    if not output.name.lower().endswith(_SIM_SUFFIXES):
        raise DataError(f"--output must end in {', '.join(_SIM_SUFFIXES)}; got "
                        f"{output.name!r}")


def _startup_kwargs(cold: dict[str, Any], *, bias: float, arma: str | None,
                    thermal: str | None) -> dict[str, Any]:
    """The cold-start options as keyword arguments of the start-up simulator."""
    import math

    from fogts._validate import check_positive
    from fogts.arma.spec import ArmaSpec
    from fogts.errors import DataError
    from fogts.startup.simulator import DEFAULT_STARTUP_COEFFICIENTS
    from fogts.units import parse_duration

    kwargs: dict[str, Any] = {"ambient_degC": cold["--ambient-c"], "earth_rate_deg_h": bias}
    for name, key, zero in (("--peak-heating-c-s", "peak_rate_degC_s", False),
                            ("--white-deg-h", "white_sigma_deg_h", True),
                            ("--temperature-resolution-c", "temperature_resolution_degC", True)):
        if cold[name] is not None:
            kwargs[key] = check_positive(name, cold[name], allow_zero=zero)
    if cold["--time-constants"] is not None:
        parts = cold["--time-constants"].split(",")
        taus = tuple(parse_duration(p, "--time-constants") for p in parts)
        if len(taus) != 2 or not taus[0] > taus[1]:
            raise DataError("--time-constants must be two durations 'SLOW,FAST' with SLOW > "
                            f"FAST, such as '400s,40s'; got {cold['--time-constants']!r}")
        kwargs["tau_s"] = taus
    kwargs["start_s"] = _duration_or_zero(cold["--start-after"], "--start-after", 0.0)
    if arma is not None:
        spec = ArmaSpec.parse(arma)
        kwargs.update(ar=spec.ar, ma=spec.ma, arma_sigma_deg_h=math.sqrt(spec.sigma2),
                      earth_rate_deg_h=bias + spec.const)
    kwargs["coefficients"] = _coefficients(thermal, "--thermal") or DEFAULT_STARTUP_COEFFICIENTS
    return kwargs


def _simulate_startup(output: Path, *, fs: float, duration: str | None,
                      seed: int | None, units: str, decimals: int | None, bias: float,
                      arma: str | None, thermal: str | None, cold: dict[str, Any]) -> None:
    """A cold start (or four-position record) to a file that ``fogts compensate``,
    ``filter`` and ``northfind`` read directly."""

    import numpy as np

    from fogts._version import __version__ as version
    from fogts.errors import DataError
    from fogts.io.writer import write_frame_atomic, write_text_atomic
    from fogts.report.text import json_dumps
    from fogts.startup.northfind_simulation import simulate_startup_positions
    from fogts.startup.simulator import simulate_startup
    from fogts.units import convert_rate, parse_duration, parse_rate_unit

    if decimals is not None and not 0 <= decimals <= 15:
        raise DataError(f"--decimals must be in 0..15, got {decimals}")
    unit = parse_rate_unit(units, "--units")
    kwargs = _startup_kwargs(cold, bias=bias, arma=arma, thermal=thermal)
    fs_hz = fs
    if seed is None:
        seed = int(np.random.SeedSequence().generate_state(1, np.uint64)[0] >> np.uint64(1))
    if cold["--positions"]:
        if duration is not None:
            raise DataError("--duration does not apply with --positions: the record lasts 4 x "
                            "--position-time + 3 x --turn-time (+ --start-after before it)")
        for name in ("--latitude", "--azimuth"):
            if cold[name] is None:
                raise DataError(f"--positions needs {name} (degrees)")
        rec = simulate_startup_positions(
            latitude_deg=cold["--latitude"], azimuth_deg=cold["--azimuth"],
            position_s=parse_duration(cold["--position-time"] or "60s", "--position-time"),
            turn_s=_duration_or_zero(cold["--turn-time"], "--turn-time", 10.0),
            fs_hz=fs_hz, rng=seed, **kwargs)
        frame, run, truth, summary = (rec.to_frame(), rec.run, rec.to_dict(), rec.summary())
    else:
        for name in ("--latitude", "--azimuth", "--position-time", "--turn-time"):
            if cold[name] is not None:
                raise DataError(f"{name} needs --positions (a four-position north-seeking "
                                "record)")
        sim = simulate_startup(duration_s=parse_duration(duration or "1h", "--duration"),
                               fs_hz=fs_hz, rng=seed, **kwargs)
        run, truth, summary = sim.run, sim.to_dict(), sim.summary()
        frame = run.to_frame().rename(columns={"gyro": "rate"})
    frame["time"] = np.round(frame["time"].to_numpy(), 9)
    frame["rate"] = convert_rate(frame["rate"].to_numpy(), "deg/h", unit)
    if decimals is not None:
        frame["rate"] = np.round(frame["rate"].to_numpy(), decimals)
    # a quantised temperature is written at its resolution (20.01, not 20.010000000000002)
    res = truth["temperature_resolution_degC"]
    digits = [d for d in range(16) if round(res, d) == res][:1] if res > 0 else []
    if digits or decimals is not None:
        nd = min(digits + ([] if decimals is None else [decimals]))
        frame["temperature"] = np.round(frame["temperature"].to_numpy(), nd)
    sidecar = {"generator": f"fogts {version} simulate startup", "output": output.name,
               "seed": seed, "mode": "startup-positions" if cold["--positions"] else "startup",
               "n": len(frame), "units": unit, "columns": list(frame.columns),
               "decimals": decimals, **truth,
               "note": "drift D = a T dT + b T^2 + c T + d dT^2 + e dT + f in deg/h (T in degC, "
                       "dT in degC/s), coefficients keyed by term; rate = drift + ARMA + white "
                       "noise + earth_rate_deg_h (+ the Earth rate at each position)"}
    write_frame_atomic(output, frame)
    side = output.with_name(output.name + ".json")
    write_text_atomic(side, json_dumps(sidecar) + "\n")
    common.console.print(f"wrote {output}: {len(frame):,} samples at {run.fs_hz:g} Hz, rate in {unit}, "
                  f"seed {seed}; true parameters in {side}", markup=False, soft_wrap=True)
    common.console.print(summary, markup=False, soft_wrap=True)
