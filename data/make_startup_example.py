"""Regenerate the bundled cold-start examples of the seed-004 workflow with ``fogts simulate
--startup`` (issue 6).

No public FOG start-up record with temperature exists, so the files are simulated
(:func:`fogts.startup.simulator.simulate_startup`, through the command line below):

* ``startup_cold_1hz.csv`` — one hour after switch-on at 1 Hz (3600 rows), columns
  ``time,rate,temperature`` (rate in deg/h, temperature in degC, 0.01 degC resolution).
  Temperature rises 20 -> 45.8 degC with a peak rate of 0.05 degC/s (two-lag warm-up,
  time constants 400 s and 40 s); the drift follows the seed-004 model with the default
  coefficients (a..f = 0.4, 0.0015, -0.12, 120, 25, 2); AR(1) drift noise (phi = 0.9,
  sigma_a = 0.05 deg/h) and white noise (0.3 deg/h).  Seed 4004.
* ``startup_cold_15c_1hz.csv``, ``startup_cold_25c_1hz.csv`` — the same cold start at
  ambient 15 and 25 degC (seeds 4014, 4024): calibration runs for ``--calibration``.
* ``startup_northfind_1hz.csv`` — a four-position north finding right after a cold start
  (ambient 18 degC) at latitude 32.05 deg: 60 s at each of 0, 90, 180, 270 deg with 10 s
  turns in between (turn samples left out), columns ``time,position_deg,rate,temperature``.
  True azimuth of the input axis at position 0: 37.5 deg.  Seed 4005.

The true parameters are written beside each file (``.json``).  Run from the repository root::

    python data/make_startup_example.py

which runs these commands (rates rounded to 5 decimals)::

    fogts simulate startup --seed 4004 --decimals 5 -o data/startup_cold_1hz.csv
    fogts simulate startup --ambient-c 15 --seed 4014 --decimals 5 -o data/startup_cold_15c_1hz.csv
    fogts simulate startup --ambient-c 25 --seed 4024 --decimals 5 -o data/startup_cold_25c_1hz.csv
    fogts simulate startup --positions --latitude 32.05 --azimuth 37.5 --ambient-c 18 \
        --seed 4005 --decimals 5 -o data/startup_northfind_1hz.csv

and try::

    fogts compensate data/startup_cold_1hz.csv --calibration data/startup_cold_15c_1hz.csv \
        --calibration data/startup_cold_25c_1hz.csv --save-model m.json -o comp.csv \
        --plot comp.png
    fogts filter data/startup_cold_1hz.csv -o filtered.csv
    fogts northfind data/startup_northfind_1hz.csv --latitude 32.05
    fogts northfind data/startup_northfind_1hz.csv --latitude 32.05 --thermal-model m.json
"""

from __future__ import annotations

from pathlib import Path

from fogts.cli import main

HERE = Path(__file__).resolve().parent
LATITUDE_DEG = 32.05
AZIMUTH_DEG = 37.5

#: (output name, extra options, seed) of each bundled file.
RUNS: list[tuple[str, list[str], int]] = [
    ("startup_cold_1hz.csv", [], 4004),
    ("startup_cold_15c_1hz.csv", ["--ambient-c", "15"], 4014),
    ("startup_cold_25c_1hz.csv", ["--ambient-c", "25"], 4024),
    ("startup_northfind_1hz.csv", ["--positions", "--latitude", str(LATITUDE_DEG),
                                   "--azimuth", str(AZIMUTH_DEG), "--ambient-c", "18"], 4005),
]


def arguments(directory: Path = HERE) -> list[list[str]]:
    """The ``fogts`` command lines that write the bundled files into ``directory``."""
    return [["simulate", "startup", *extra, "--seed", str(seed), "--decimals", "5",
             "-o", str(directory / name)] for name, extra, seed in RUNS]


if __name__ == "__main__":
    for argv in arguments():
        try:
            main(argv)
        except SystemExit as exc:
            if exc.code:
                raise
