"""The real-sensor table: the Allan analysis (fogts.pipeline, default settings) of every real
recording in ``../shared/data/imu`` and the bundled example, with the fitted terms, the fit
range, the fit check and whether the curve lies within its intervals.

``python -m tests.real_sensors`` prints the Markdown table kept in ``tests/README.md``;
``tests/test_real_sensors.py`` checks it.  CH104 comes as a MATLAB file, read here with
:func:`scipy.io.loadmat` (fogts does not read ``.mat`` yet).
"""

from __future__ import annotations

import warnings
from collections.abc import Iterator
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from fogts.io.reader import read_run
from fogts.io.run import Run
from fogts.pipeline import AxisAllan, analyse_allan_axis
from tests.conftest import SHARED_DATA

ROOT = Path(__file__).resolve().parents[1]

#: (label, file under ../shared/data/imu or the repository, rate unit)
RECORDINGS: tuple[tuple[str, str, str], ...] = (
    *((f"ADIS16405 run {i}", f"imu/adis_16405_imu{i}_gyro.npz", "deg/s") for i in range(1, 7)),
    ("CH104", "imu/ch104.mat", "deg/s"),
    ("MPU6050", "imu/mpu6050_gyro_temp_converted.csv.gz", "deg/s"),
    ("XSens cont_imu1", "imu/cont_imu1_gyro_x.npz", "rad/s"),
    ("bundled example (simulated)", "data/example_fog_10hz_3h.csv", "deg/h"),
)


@dataclass(frozen=True)
class Row:
    label: str
    axis: str
    analysis: AxisAllan
    warned: tuple[str, ...]

    def cells(self) -> list[str]:
        model = self.analysis.model
        assert model is not None
        terms = []
        for name in ("N", "B", "K"):
            t = model[name]
            if t.is_limit:
                terms.append(f"< {model.upper_limit(name):.3g}")
            else:
                terms.append(f"{t.value:.4g} ± {t.stderr:.2g}")
        check = self.analysis.fit_check
        assert check is not None
        fit_range = f"{model.tau_s[0]:.3g}..{model.tau_s[-1]:.4g} s"
        verdict = ("within CIs" if check.ok else
                   "; ".join(_span(m.ratio_min, m.ratio_max, "x") + " at "
                             + _span(m.tau_from_s, m.tau_to_s, " s") for m in check.misses))
        return [self.label, self.axis, *terms, fit_range, verdict,
                "yes" if any("misses the curve" in w for w in self.warned) else "no"]


def _span(lo: float, hi: float, unit: str) -> str:
    return f"{lo:.3g}{unit}" if f"{lo:.3g}" == f"{hi:.3g}" else f"{lo:.3g}-{hi:.3g}{unit}"


def _run(path: Path, units: str) -> Run:
    if path.suffix == ".mat":
        from scipy.io import loadmat

        gyro = np.asarray(loadmat(path)["gyroReading"], dtype=np.float64)
        return read_run(gyro, fs_hz=100.0, units=units)
    return read_run(path, units=units)


def rows() -> Iterator[Row]:
    """One row per recording and axis (recordings that are absent are left out)."""
    for label, name, units in RECORDINGS:
        path = (ROOT / name) if name.startswith("data/") else SHARED_DATA / name
        if not path.exists():
            continue
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            run = _run(path, units)
        for i, axis in enumerate(run.axes):
            with warnings.catch_warnings(record=True) as caught:
                warnings.simplefilter("always")
                analysis = analyse_allan_axis(run, i)
            yield Row(label, axis, analysis, tuple(str(w.message) for w in caught))


HEADER = ["recording", "axis", "N", "B", "K", "fit range", "fit check", "warned"]


def markdown() -> str:
    lines = ["| " + " | ".join(HEADER) + " |", "|" + "---|" * len(HEADER)]
    lines += ["| " + " | ".join(r.cells()) + " |" for r in rows()]
    return "\n".join(lines)


if __name__ == "__main__":  # pragma: no cover - maintenance entry point
    print(markdown())
