"""Filter-ready noise parameters: Kalibr's ``imu.yaml``, imu_utils' parameter file, JSON.

A visual-inertial or INS filter wants, per gyro, the white rate noise density and the rate
random walk in SI units.  These are fogts' IEEE-952 terms N and K converted by
:data:`fogts.units.TERM_SI_FACTOR`:

* ``gyroscope_noise_density`` (Kalibr) = ``gyr_n`` (imu_utils) = N in rad/s/sqrt(Hz);
* ``gyroscope_random_walk`` (Kalibr) = ``gyr_w`` (imu_utils) = K in rad/s^2/sqrt(Hz).

These are the definitions of the Kalibr wiki ("IMU Noise Model": sigma^2(tau) =
sigma_g^2 / tau for the white noise and sigma_bg^2 tau / 3 for the random walk, which are
IEEE 952's N^2/tau and K^2 tau/3).  imu_utils itself writes the Allan minimum (a bias
instability) as ``gyr_w``; the file written here carries K there, as the filters that read
the file expect, and says so in a comment.

Accelerometer axes (:mod:`fogts.io.accel`) give the accelerometer pair the same way, from
their N and K in SI (:data:`fogts.units.ACCEL_TERM_SI_FACTOR`):
``accelerometer_noise_density`` = ``acc_n`` = N in m/s^2/sqrt(Hz) and
``accelerometer_random_walk`` = ``acc_w`` = K in m/s^3/sqrt(Hz).

A term that the data do not measure (at zero, dropped, or z < 2) is exported as its
one-sided 95 % upper limit and marked as such in a comment: a filter then gets a
conservative value, never a zero.  Kalibr wants one value per sensor: the largest axis is
written (conservative), every axis in a comment.  A record without accelerometer axes
leaves the accelerometer pair out, and a comment says so.
"""

from __future__ import annotations

import json
import math
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any

import yaml

from fogts._version import __version__
from fogts.choices import EXPORT_FORMATS, ExportFormat
from fogts.errors import DataError
from fogts.pipeline import AllanAnalysis, AxisAllan
from fogts.units import term_unit

if TYPE_CHECKING:
    from fogts.allan.curve_input import CurveProvenance

__all__ = ["ExportSource", "ExportedTerm", "export_noise", "exported_terms",
           "noise_export_text"]

#: The terms a filter needs, in the order written.
_FILTER_TERMS = ("N", "K")


@dataclass(frozen=True)
class ExportedTerm:
    """One term of one axis as exported: its SI value and whether it is only a limit.

    :func:`exported_terms` gives one for each term a filter needs (N and K); the Kalibr and
    imu_utils files note its :attr:`comment` in a comment, the JSON export ``is_limit`` as
    ``"upper_limit"``.

    Attributes
    ----------
    axis : str
        Axis name.
    term : str
        ``"N"`` or ``"K"``.
    quantity : str
        ``"rate"`` (a gyro axis) or ``"accel"`` (an accelerometer axis).
    value_si : float
        The fitted value, or for a term that is only a limit its 95 % upper limit, in SI.
    is_limit : bool
        True when ``value_si`` is the 95 % upper limit.
    unit : str
        SI unit (:data:`fogts.units.TERM_SI_UNIT`, :data:`fogts.units.ACCEL_TERM_SI_UNIT`).
    """

    axis: str
    term: str
    value_si: float
    is_limit: bool
    unit: str
    quantity: str = "rate"

    @property
    def comment(self) -> str:
        """``fitted`` or ``95 % upper limit, not measured``."""
        return "95 % upper limit, not measured" if self.is_limit else "fitted"


@dataclass(frozen=True)
class ExportSource:
    """The analysed axes of one sensor and what the export says about where they came from.

    Attributes
    ----------
    source : str
        The file analysed (a recording, or a published Allan curve).
    update_rate_hz : float
        The IMU's sample rate, written as Kalibr's ``update_rate``.
    rate_note : str
        Where ``update_rate_hz`` came from, said beside it when it is not the recording's
        own (empty for a recording).
    detail : str
        The second header line: what was analysed.
    axes : tuple of AxisAllan
        The analysed axes (gyro and accelerometer).
    """

    source: str
    update_rate_hz: float
    rate_note: str
    detail: str
    axes: tuple[AxisAllan, ...]

    @classmethod
    def of_recording(cls, analysis: AllanAnalysis) -> ExportSource:
        """The axes of ``fogts allan``'s analysis of a recording."""
        run = analysis.run
        return cls(source=run.source, update_rate_hz=float(run.fs_hz), rate_note="",
                   detail=f"{run.n} samples at {run.fs_hz:g} Hz; rate read in {run.units}",
                   axes=analysis.axes)

    @classmethod
    def of_curve(cls, provenance: CurveProvenance, axes: tuple[AxisAllan, ...]
                 ) -> ExportSource:
        """The axes fitted to a published Allan curve (``fogts curve``): the sample rate
        and the record length are the curve's, as :class:`CurveProvenance` states them."""
        p = provenance
        note = "" if p.fs_source != "inferred" else \
            "inferred as 1 / the curve's shortest tau: check it is the IMU's sample rate"
        return cls(source=p.source, update_rate_hz=float(p.fs_hz), rate_note=note,
                   detail=f"a published {p.kind} curve in {p.units} ({p.units_source}); "
                          f"{p.fs_hz:g} Hz ({p.fs_source}), {p.n_samples} samples "
                          f"({p.n_source})",
                   axes=axes)


def exported_terms(axis: AxisAllan) -> dict[str, ExportedTerm]:
    """N and K of one analysed axis, in SI, each the fitted value or its upper limit."""
    model, name = axis.model, axis.result.axis
    if model is None:
        raise DataError(f"the export needs the noise terms, and {name} has none (fitted to "
                        "kind= adev, oadev or totdev only)")
    out = {}
    for term in _FILTER_TERMS:
        if term not in model.names:
            raise DataError(f"the export needs N and K; {term} was not fitted (terms= "
                            "must include N and K)")
        shown = model.in_units(term, "si")
        limit = model[term].is_limit
        value = shown["upper_limit_95"] if limit else shown["value"]
        if not math.isfinite(value):
            raise DataError(f"{name}: {term} has no finite value or upper limit to export")
        out[term] = ExportedTerm(name, term, float(value), limit,
                                 term_unit(term, "si", model.quantity), model.quantity)
    return out


def noise_export_text(analysis: AllanAnalysis | ExportSource, fmt: ExportFormat) -> str:
    """The text of the export in format ``fmt`` (``kalibr``, ``imu_utils`` or ``json``)
    of a recording's analysis or an :class:`ExportSource`."""
    if fmt not in EXPORT_FORMATS:
        raise DataError(f"export format must be one of {', '.join(EXPORT_FORMATS)}; got "
                        f"{fmt!r}")
    src = analysis if isinstance(analysis, ExportSource) else \
        ExportSource.of_recording(analysis)
    terms = {ax.result.axis: exported_terms(ax) for ax in src.axes}
    return _WRITERS[fmt](src, terms)


def export_noise(analysis: AllanAnalysis | ExportSource, fmt: ExportFormat,
                 path: str | Path) -> Path:
    """Write the export atomically to ``path`` and return it."""
    from fogts.io.writer import write_text_atomic

    return write_text_atomic(Path(path), noise_export_text(analysis, fmt))


# ------------------------------------------------------------------ the formats
def _header(src: ExportSource, what: str) -> list[str]:
    return [f"# {what}, written by fogts {__version__} from {Path(src.source).name}",
            f"# ({src.detail})"]


def _axis_comments(terms: dict[str, dict[str, ExportedTerm]]) -> list[str]:
    return [f"#   {axis}: " + "; ".join(f"{t.term} = {t.value_si:.6e} {t.unit} ({t.comment})"
                                        for t in by_term.values())
            for axis, by_term in terms.items()]


def _of(terms: dict[str, dict[str, ExportedTerm]], quantity: str
        ) -> dict[str, dict[str, ExportedTerm]]:
    """The axes of one quantity (``"rate"`` or ``"accel"``)."""
    return {axis: by_term for axis, by_term in terms.items()
            if by_term["N"].quantity == quantity}


def _worst(terms: dict[str, dict[str, ExportedTerm]]) -> dict[str, ExportedTerm]:
    return {term: max((by_term[term] for by_term in terms.values()), key=lambda t: t.value_si)
            for term in _FILTER_TERMS}


_KALIBR_KEYS = {"rate": ("gyroscope_noise_density", "gyroscope_random_walk"),
                "accel": ("accelerometer_noise_density", "accelerometer_random_walk")}


def _kalibr(src: ExportSource, terms: dict[str, dict[str, ExportedTerm]]) -> str:
    body: dict[str, Any] = {"rostopic": "/imu0", "update_rate": src.update_rate_hz}
    marks: dict[str, ExportedTerm] = {}
    lines = _header(src, "Kalibr IMU noise model (imu.yaml)")
    for quantity, (density, walk) in _KALIBR_KEYS.items():
        group = _of(terms, quantity)
        if not group:
            continue
        worst = _worst(group)
        body[density], body[walk] = worst["N"].value_si, worst["K"].value_si
        marks[density], marks[walk] = worst["N"], worst["K"]
        lines += [f"# {density}: N in {worst['N'].unit}; {walk}: K in {worst['K'].unit}; "
                  "the largest axis of:"]
        lines += _axis_comments(group)
    if not _of(terms, "accel"):
        lines += ["# accelerometer_noise_density and accelerometer_random_walk are not "
                  "written: the record has no accelerometer axes; add them from the "
                  "accelerometer's analysis."]
    if not _of(terms, "rate"):
        lines += ["# gyroscope_noise_density and gyroscope_random_walk are not written: the "
                  "record has no gyro axes."]
    for line in yaml.safe_dump(body, sort_keys=False).splitlines():
        key = line.split(":", 1)[0]
        mark = marks.get(key)
        note = f"  # {src.rate_note}" if key == "update_rate" and src.rate_note else ""
        lines.append(line + (f"  # {mark.axis}, {mark.comment}" if mark is not None else note))
    return "\n".join(lines) + "\n"


def _imu_utils_block(terms: dict[str, dict[str, ExportedTerm]], prefix: str, unit: str
                     ) -> tuple[dict[str, Any], list[str]]:
    """One imu_utils sensor block (``Gyr`` or ``Acc``) and the comments naming its axes."""
    axes = list(terms)
    keys = ([f"{c}-axis" for c in "xyz"] if len(axes) == 3
            else [f"{a}-axis" for a in axes])
    mean = {term: sum(terms[a][term].value_si for a in axes) / len(axes)
            for term in _FILTER_TERMS}
    block: dict[str, Any] = {"unit": unit,
                             "avg-axis": {f"{prefix}_n": mean["N"], f"{prefix}_w": mean["K"]}}
    for key, axis in zip(keys, axes, strict=True):
        block[key] = {f"{prefix}_n": terms[axis]["N"].value_si,
                      f"{prefix}_w": terms[axis]["K"].value_si}
    label = "" if prefix == "gyr" else "Acc "
    return block, [f"# {label}{key} is {axis}" for key, axis in zip(keys, axes, strict=True)]


def _imu_utils(src: ExportSource, terms: dict[str, dict[str, ExportedTerm]]) -> str:
    body: dict[str, Any] = {"type": "IMU", "name": Path(src.source).stem}
    lines = ["%YAML:1.0", "---"]
    lines += _header(src, "imu_utils IMU parameters (OpenCV YAML)")
    naming: list[str] = []
    if _of(terms, "rate"):
        body["Gyr"], names = _imu_utils_block(_of(terms, "rate"), "gyr", " rad/s")
        naming += names
        lines += ["# gyr_n: N in rad/s/sqrt(Hz); gyr_w: K (rate random walk) in "
                  "rad/s^2/sqrt(Hz), where imu_utils writes the Allan minimum; avg-axis: the "
                  "mean of the axes"]
    if _of(terms, "accel"):
        body["Acc"], names = _imu_utils_block(_of(terms, "accel"), "acc", " m/s^2")
        naming += names
        lines += ["# acc_n: N in m/s^2/sqrt(Hz); acc_w: K (acceleration random walk) in "
                  "m/s^3/sqrt(Hz), where imu_utils writes the Allan minimum"]
    lines += naming
    lines += _axis_comments(terms)
    lines += yaml.safe_dump(body, sort_keys=False, indent=3).splitlines()
    return "\n".join(lines) + "\n"


def _json(src: ExportSource, terms: dict[str, dict[str, ExportedTerm]]) -> str:
    doc = {"format": "fogts-imu-noise", "version": 1, "fogts_version": __version__,
           "source": src.source, "update_rate_hz": src.update_rate_hz,
           **({"update_rate_note": src.rate_note} if src.rate_note else {}),
           "axes": {axis: {t.term: {"value": t.value_si, "unit": t.unit,
                                    "upper_limit": t.is_limit}
                           for t in by_term.values()}
                    for axis, by_term in terms.items()}}
    return json.dumps(doc, indent=2) + "\n"


_WRITERS: dict[str, Callable[[ExportSource, dict[str, dict[str, ExportedTerm]]], str]] = {
    "kalibr": _kalibr, "imu_utils": _imu_utils, "json": _json}
