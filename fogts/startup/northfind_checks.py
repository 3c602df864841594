"""Can a four-position record support an azimuth?  The two checks of a north finding.

**Earth-rate check.**  The half-difference vector ``v = ((ω₀ - ω₁₈₀)/2, (ω₂₇₀ - ω₉₀)/2)``
has length ``A = Ω cos L`` for a gyro whose rate unit, latitude and scale factor are right
(module :mod:`~fogts.startup.northfind`).  Its standard uncertainty follows from the
per-position means: each component of ``v`` is half a difference of two means, each mean
with variance ``σ_m² + σ_b²`` (white noise and position-to-position bias variation), so
each component has variance ``(σ_m² + σ_b²)/2``; the gradient of ``|v|`` is the unit vector
along ``v``, so first-order propagation (JCGM 100:2008, the GUM, §5.1.2, eq. 10) gives

    u(A)² = (σ_m² + σ_b²)/2 + δ_r²,

where ``δ_r = cos ψ · e_x + sin ψ · e_y`` is the radial part of the error of ``v`` that a
linear bias drift causes (``e_x, e_y`` as in the azimuth's drift term; added in quadrature
as the azimuth budget adds its drift term; a slope fitted to white noise makes this share
conservative).  ``|v|`` of a noisy vector is Rice distributed
(Rice 1945, *Bell Syst. Tech. J.* 24:46, §3.10), close to normal with this standard
deviation when ``A ≫ u(A)``.  The ratio ``r = A / (Ω cos L)`` has ``u(r) = u(A) / (Ω cos L)``.

``r`` is called inconsistent with 1 when its ``±SCALE_SIGMAS·u(r)`` interval lies wholly
outside ``[1/SCALE_TOLERANCE, SCALE_TOLERANCE]``.  The tolerance, a factor √2 either way
(symmetric in log r), is far wider than any rate gyro's scale-factor error (ppm for a FOG,
about 1 % for a MEMS gyro) and than the several per cent a cold-start drift that is not
linear adds to ``A``; it is far narrower than every unit mix-up (deg/s vs deg/h: 3600;
rad vs deg: 57.3) and catches a latitude wrong by about 15° or more at mid latitudes
(cos 60° / cos 45° = 1/√2).  Three standard uncertainties keep a noisy record near the
edge of the band from being flagged by chance (a one-sided normal tail of 0.13 %).

**Azimuth determinacy.**  The azimuth is "not determined" when its 95 % interval
``ψ ± z₀.₉₇₅ σ_ψ`` spans a half circle or more (``σ_ψ ≥ 90°/1.96 = 45.9°``): the interval then
holds directions at right angles to the estimate, so the data do not even tell on which
side of the perpendicular the axis points; the first-order error budget that gives
``σ_ψ`` is itself not valid there (its linearisation needs ``σ_ψ ≪ 1 rad``).
"""

from __future__ import annotations

import math
from statistics import NormalDist

from fogts.units import EARTH_RATE_RAD_S, RATE_UNITS, to_deg_per_hour_factor

__all__ = ["AZIMUTH_Z95", "MAX_HALF_WIDTH_DEG", "SCALE_SIGMAS", "SCALE_TOLERANCE",
           "amplitude_stderr", "azimuth_usable", "no_azimuth_text", "scale_consistent",
           "scale_warning"]

#: Factor either way by which the Earth-rate ratio may leave 1 (gyro scale factor, drift).
SCALE_TOLERANCE = math.sqrt(2.0)
#: Standard uncertainties by which the ratio must clear that band to be flagged.
SCALE_SIGMAS = 3.0
#: Two-sided 95 % normal quantile of the azimuth interval.
AZIMUTH_Z95 = NormalDist().inv_cdf(0.975)
#: Largest half width (degrees) of a 95 % azimuth interval that still determines ψ.
MAX_HALF_WIDTH_DEG = 90.0

#: Factors between rate units that a mislabelled record shows as the Earth-rate ratio.
_UNIT_FACTORS: tuple[tuple[float, str], ...] = (
    (3600.0, "deg/s vs deg/h"),
    (180.0 / math.pi, "rad vs deg"),
    (3600.0 * 180.0 / math.pi, "rad/s vs deg/h"),
)


def amplitude_stderr(sigma_mean: float, sigma_bias: float, radial_drift: float) -> float:
    """``u(A) = sqrt((σ_m² + σ_b²)/2 + δ_r²)``, the standard uncertainty of the measured
    Earth-rate amplitude (module docstring), in the unit of its inputs.

    Examples
    --------
    >>> round(amplitude_stderr(0.1, 0.0, 0.0), 6)   # sigma_m / sqrt(2)
    0.070711
    """
    return math.sqrt(0.5 * (sigma_mean ** 2 + sigma_bias ** 2) + radial_drift ** 2)


def scale_consistent(ratio: float, stderr: float) -> bool:
    """False when ``ratio ± SCALE_SIGMAS·stderr`` lies wholly outside
    ``[1/SCALE_TOLERANCE, SCALE_TOLERANCE]`` (module docstring).

    Examples
    --------
    >>> scale_consistent(1.07, 0.003), scale_consistent(3600.5, 5.0), scale_consistent(2.0, 0.5)
    (True, False, True)
    """
    u = SCALE_SIGMAS * (stderr if math.isfinite(stderr) else 0.0)
    return not (ratio - u > SCALE_TOLERANCE or ratio + u < 1.0 / SCALE_TOLERANCE)


def _unit_cause(ratio: float, units: str) -> str | None:
    """The unit mix-up a ratio matches (within the tolerance), or None."""
    for factor, name in _UNIT_FACTORS:
        for expected in (factor, 1.0 / factor):
            if abs(math.log(ratio / expected)) > math.log(SCALE_TOLERANCE):
                continue
            declared = to_deg_per_hour_factor(units)
            alike = [u for u in RATE_UNITS
                     if math.isclose(declared / to_deg_per_hour_factor(u), expected, rel_tol=1e-9)]
            text = f"a ratio of about {expected:.4g} is {name}"
            if alike:
                return (f"{text}: the rates are probably in {' or '.join(alike)}, not {units} "
                        "(check units)")
            bigger = "larger" if expected < 1 else "smaller"
            return (f"{text}: the rates are probably in a unit {max(factor, 1 / factor):.4g} "
                    f"times {bigger} than {units} (convert them, or check units)")
    return None


def scale_warning(ratio: float, stderr: float, *, amplitude_deg_h: float, omega_h_deg_h: float,
                  latitude_deg: float, units: str) -> str | None:
    """The warning of an Earth-rate ratio inconsistent with 1, naming the likely cause
    (a unit mix-up, the latitude, or a scale factor); None for a consistent one.

    Examples
    --------
    >>> scale_warning(1.0, 0.01, amplitude_deg_h=10.6, omega_h_deg_h=10.6, latitude_deg=45,
    ...               units="deg/h") is None
    True
    >>> "deg/s vs deg/h" in scale_warning(3600.0, 1.0, amplitude_deg_h=38290.0,
    ...     omega_h_deg_h=10.64, latitude_deg=45, units="deg/s")
    True
    """
    if scale_consistent(ratio, stderr) or not math.isfinite(ratio) or ratio <= 0:
        return None
    head = (f"measured Earth-rate amplitude {amplitude_deg_h:.6g} °/h is {ratio:.4g} ± "
            f"{stderr:.2g} (1σ) times Ω cos L = {omega_h_deg_h:.4f} °/h at latitude "
            f"{latitude_deg:g}°, outside [{1 / SCALE_TOLERANCE:.3f}, {SCALE_TOLERANCE:.3f}] by "
            f"more than {SCALE_SIGMAS:g}σ")
    causes = [c for c in (_unit_cause(ratio, units), _latitude_cause(ratio, latitude_deg)) if c]
    if not causes:
        full = math.degrees(EARTH_RATE_RAD_S) * 3600.0
        causes = [f"it exceeds the full Earth rate Ω = {full:.4f} °/h, so no latitude "
                  "explains it: check units or the gyro's scale factor"]
    return (f"{head}: {'; or '.join(causes)}; the azimuth's error budget assumes the given "
            "unit and latitude")


def _latitude_cause(ratio: float, latitude_deg: float) -> str | None:
    """The latitude whose Ω cos L the measured amplitude matches, or None (near the pole
    a wrong latitude can imitate the rad-vs-deg factor, so both causes may be named)."""
    horizontal = ratio * math.cos(math.radians(latitude_deg))
    if horizontal > 1.0:
        return None
    return (f"it matches the horizontal Earth rate at latitude "
            f"±{math.degrees(math.acos(horizontal)):.1f}°: check latitude_deg (or units, or "
            "the gyro's scale factor)")


def azimuth_usable(sigma_deg: float) -> bool:
    """Whether the 95 % interval ``±AZIMUTH_Z95·σ`` is narrower than a half circle.

    Examples
    --------
    >>> azimuth_usable(1.3), azimuth_usable(45.0), azimuth_usable(46.0), azimuth_usable(math.nan)
    (True, True, False, False)
    """
    return bool(math.isfinite(sigma_deg) and AZIMUTH_Z95 * sigma_deg < MAX_HALF_WIDTH_DEG)


def no_azimuth_text(sigma_deg: float, budget_deg: dict[str, float]) -> str:
    """The line printed instead of an azimuth whose 95 % interval spans a half circle.

    Examples
    --------
    >>> no_azimuth_text(98.47, {"arw": 7.48, "bias": 0.0, "drift": 98.19})[:40]
    'no usable azimuth: 1σ = 98.5° (ARW 7.48°'
    """
    b = budget_deg
    return (f"no usable azimuth: 1σ = {sigma_deg:.3g}° (ARW {b['arw']:.3g}°, bias "
            f"{b['bias']:.3g}°, drift {b['drift']:.3g}°), so the 95 % interval "
            f"±{AZIMUTH_Z95 * sigma_deg:.3g}° spans a half circle or more: the data do not "
            "determine the azimuth")
