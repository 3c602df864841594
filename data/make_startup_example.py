"""Regenerate the bundled cold-start examples of the seed-004 workflow (issue 6).

Two files, both simulated by :func:`fogts.simulate_startup.simulate_startup` (no public FOG
start-up record with temperature exists):

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

and try::

    fogts compensate data/startup_cold_1hz.csv --calibration data/startup_cold_15c_1hz.csv \
        --calibration data/startup_cold_25c_1hz.csv --save-model m.json -o comp.csv \
        --plot comp.png
    fogts filter data/startup_cold_1hz.csv -o filtered.csv
    fogts northfind data/startup_northfind_1hz.csv --latitude 32.05
    fogts northfind data/startup_northfind_1hz.csv --latitude 32.05 --thermal-model m.json
"""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pandas as pd

from fogts import __version__
from fogts.simulate_startup import simulate_startup
from fogts.units import earth_rate_component

HERE = Path(__file__).resolve().parent
LATITUDE_DEG = 32.05
AZIMUTH_DEG = 37.5


def main() -> None:
    for name, ambient, seed in (("startup_cold_1hz.csv", 20.0, 4004),
                                ("startup_cold_15c_1hz.csv", 15.0, 4014),
                                ("startup_cold_25c_1hz.csv", 25.0, 4024)):
        cal = simulate_startup(duration_s=3600.0, ambient_degC=ambient, rng=seed)
        frame = pd.DataFrame({"time": cal.run.time, "rate": np.round(cal.run.rate, 5),
                              "temperature": np.round(cal.run.temperature, 2)})
        frame.to_csv(HERE / name, index=False)
        meta = {"generator": f"fogts {__version__} simulate_startup", "seed": seed,
                **cal.to_dict()}
        (HERE / f"{name}.json").write_text(json.dumps(meta, indent=2) + "\n")

    pos_s, turn_s = 60, 10
    total = 4 * pos_s + 3 * turn_s
    sim = simulate_startup(duration_s=float(total), ambient_degC=18.0, rng=4005)
    omega_h = earth_rate_component(LATITUDE_DEG, axis="north")
    parts = []
    for k, p in enumerate((0, 90, 180, 270)):
        sl = slice(k * (pos_s + turn_s), k * (pos_s + turn_s) + pos_s)
        earth = omega_h * math.cos(math.radians(AZIMUTH_DEG + p))
        parts.append(pd.DataFrame({"time": sim.run.time[sl], "position_deg": p,
                                   "rate": np.round(sim.run.rate[sl] + earth, 5),
                                   "temperature": np.round(sim.run.temperature[sl], 2)}))
    pd.concat(parts).to_csv(HERE / "startup_northfind_1hz.csv", index=False)
    meta = {"generator": f"fogts {__version__} simulate_startup", "seed": 4005,
            "latitude_deg": LATITUDE_DEG, "azimuth_deg": AZIMUTH_DEG, "position_s": pos_s,
            "turn_s": turn_s, "earth_rate_h_deg_h": omega_h, **sim.to_dict()}
    (HERE / "startup_northfind_1hz.csv.json").write_text(json.dumps(meta, indent=2) + "\n")


if __name__ == "__main__":
    main()
