"""Four-position north seeking with a single level gyro: the azimuth estimator and its result.

Convention (stated once, used everywhere):

* ψ is the azimuth of the gyro's input axis at position 0, measured clockwise from true
  north, in [0°, 360°);
* position k (k = 0, 1, 2, 3; 0°, 90°, 180°, 270°) is reached by turning the axis clockwise,
  seen from above, by k·90°;
* at position k the gyro senses  ω_k = Ω·cos(L)·cos(ψ + k·90°) + b,  with Ω the Earth rate
  (WGS-84, :data:`fogts.units.EARTH_RATE_RAD_S`), L the latitude and b the bias.

Then ω₀ - ω₁₈₀ = 2Ω_h cos ψ and ω₂₇₀ - ω₉₀ = 2Ω_h sin ψ, so

    ψ = atan2(ω₂₇₀ - ω₉₀, ω₀ - ω₁₈₀),     b = (ω₀ + ω₉₀ + ω₁₈₀ + ω₂₇₀) / 4,

independent of the bias and of the scale factor.  Ω_h = Ω cos L enters only the error
budget: with σ_m the standard error of each position's mean rate, the azimuth error is
σ_ψ = σ_m / (√2 Ω_h) rad (first-order propagation through atan2).  A bias that drifts
linearly at r (°/h per s) between positions measured at times t_k adds the deterministic
error  δψ = [-sin ψ · r (t₀ - t₂) + cos ψ · r (t₃ - t₁)] / (2 Ω_h).

Near the poles Ω_h → 0 and the azimuth is undefined: latitudes beyond ±89° are refused.
Whether a record supports an azimuth at all (its Earth-rate amplitude against Ω_h, and an
interval narrower than a half circle) is decided in :mod:`~fogts.startup.northfind_checks`.
Simulated cold-start north seeking is in :mod:`~fogts.startup.northfind_simulation`.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import Any

import numpy as np
import pandas as pd

from fogts._typing import FloatArray
from fogts._validate import check_positive, to_float_array
from fogts.errors import DataError
from fogts.startup.northfind_checks import (
    SCALE_TOLERANCE,
    amplitude_stderr,
    azimuth_usable,
    no_azimuth_text,
    scale_consistent,
    scale_warning,
)
from fogts.tables import Column, Table, TableView
from fogts.units import earth_rate_component, parse_rate_unit, to_deg_per_hour_factor

__all__ = ["POSITIONS_DEG", "NorthFinding", "angle_error_deg", "four_position",
           "positions_from_frame"]

#: The four positions, in measuring order.
POSITIONS_DEG: tuple[int, ...] = (0, 90, 180, 270)
#: Largest |latitude| accepted (Ω cos L must stay measurable).
MAX_LATITUDE_DEG = 89.0
#: Fewest samples per position.
MIN_POSITION_SAMPLES = 3


@dataclass(frozen=True, repr=False)
class NorthFinding(TableView):
    """Result of a four-position north finding.

    What :func:`four_position` returns; ``summary()`` prints it and ``to_dict()`` gives its
    JSON record.

    Attributes
    ----------
    azimuth_deg : float
        ψ, azimuth of the input axis at position 0, clockwise from true north, in [0, 360).
    sigma_deg : float
        1σ azimuth uncertainty from the error budget (``budget_deg`` added in quadrature).
    budget_deg : dict
        ``{"arw": ..., "bias": ..., "drift": ...}`` in degrees: white-noise (ARW) part from the
        within-position scatter, the position-to-position bias variation given as
        ``bias_sigma_deg_h``, and the magnitude of the error caused by the bias drift measured
        inside the positions.
    latitude_deg : float
    earth_rate_h_deg_h : float
        Ω cos L, the horizontal Earth rate, in °/h.
    bias_deg_h : float
        Residual bias estimate b (mean of the four means), °/h.
    amplitude_deg_h : float
        ½·|(ω₀ - ω₁₈₀, ω₂₇₀ - ω₉₀)|, which should equal ``earth_rate_h_deg_h``.
    drift_rate_deg_h_per_s : float
        Pooled within-position slope of the rate (bias drift), °/h per s.
    drift_error_deg : float
        Signed azimuth error that drift predicts (first order).
    sigma_mean_deg_h : float
        Standard error of one position mean used in the budget (°/h).
    mean_rates : dict
        Mean rate at each position (°/h), keyed by position in degrees.
    std_rates : dict
        Sample standard deviation at each position (°/h).
    n_samples : dict
        Samples at each position.
    position_time_s : dict
        Centre time of each position (s from the start of the first).
    amplitude_stderr_deg_h : float
        Standard uncertainty of ``amplitude_deg_h`` (°/h;
        :func:`~fogts.startup.northfind_checks.amplitude_stderr`).
    units : str
        Rate unit the samples were declared in (named by the Earth-rate warning).

    The verdict: :attr:`scale_consistent` (the amplitude agrees with Ω cos L),
    :attr:`azimuth_usable` (the 95 % interval is narrower than a half circle) and
    :attr:`exit_code`, 1 when either fails.
    """

    azimuth_deg: float
    sigma_deg: float
    budget_deg: dict[str, float]
    latitude_deg: float
    earth_rate_h_deg_h: float
    bias_deg_h: float
    amplitude_deg_h: float
    drift_rate_deg_h_per_s: float
    drift_error_deg: float
    sigma_mean_deg_h: float
    mean_rates: dict[int, float]
    std_rates: dict[int, float]
    n_samples: dict[int, int]
    position_time_s: dict[int, float] = field(default_factory=dict)
    amplitude_stderr_deg_h: float = math.nan
    units: str = "deg/h"

    @property
    def scale_check(self) -> float:
        """``amplitude / (Ω cos L)``: about 1 for a healthy gyro and the right latitude."""
        return self.amplitude_deg_h / self.earth_rate_h_deg_h

    @property
    def scale_check_stderr(self) -> float:
        """Standard uncertainty of :attr:`scale_check`."""
        return self.amplitude_stderr_deg_h / self.earth_rate_h_deg_h

    @property
    def scale_consistent(self) -> bool:
        """Whether :attr:`scale_check` agrees with 1 (within the scale tolerance and three
        standard uncertainties; :func:`~fogts.startup.northfind_checks.scale_consistent`)."""
        return scale_consistent(self.scale_check, self.scale_check_stderr)

    @property
    def scale_warning(self) -> str | None:
        """The Earth-rate warning naming the likely cause, or None when consistent."""
        return scale_warning(self.scale_check, self.scale_check_stderr,
                             amplitude_deg_h=self.amplitude_deg_h,
                             omega_h_deg_h=self.earth_rate_h_deg_h,
                             latitude_deg=self.latitude_deg, units=self.units)

    @property
    def azimuth_usable(self) -> bool:
        """Whether the 95 % azimuth interval is narrower than a half circle."""
        return azimuth_usable(self.sigma_deg)

    @property
    def exit_code(self) -> int:
        """0 for a usable azimuth from a consistent Earth rate, 1 otherwise (DESIGN.md)."""
        return 0 if self.scale_consistent and self.azimuth_usable else 1

    def to_dict(self) -> dict[str, Any]:
        return {
            "azimuth_deg": self.azimuth_deg,
            "sigma_deg": self.sigma_deg,
            "budget_deg": dict(self.budget_deg),
            "latitude_deg": self.latitude_deg,
            "earth_rate_h_deg_h": self.earth_rate_h_deg_h,
            "positions": [{"position_deg": p, "mean_rate": self.mean_rates[p],
                           "std": self.std_rates[p], "n": self.n_samples[p],
                           "time_s": self.position_time_s.get(p)} for p in POSITIONS_DEG],
            "mean_rates": {str(p): self.mean_rates[p] for p in POSITIONS_DEG},
            "bias_deg_h": self.bias_deg_h,
            "amplitude_deg_h": self.amplitude_deg_h,
            "scale_check": self.scale_check,
            "drift_rate_deg_h_per_s": self.drift_rate_deg_h_per_s,
            "drift_error_deg": self.drift_error_deg,
            "sigma_mean_deg_h": self.sigma_mean_deg_h,
            "unit": "deg/h",
            "convention": ("azimuth of the input axis at position 0, clockwise from true north; "
                           "position k = axis turned clockwise by k*90 deg; "
                           "rate_k = Omega cos(L) cos(psi + k*90) + bias"),
            "amplitude_stderr_deg_h": self.amplitude_stderr_deg_h,
            "scale_check_stderr": self.scale_check_stderr,
            "scale_check_limits": [1.0 / SCALE_TOLERANCE, SCALE_TOLERANCE],
            "scale_consistent": self.scale_consistent,
            "scale_warning": self.scale_warning,
            "azimuth_usable": self.azimuth_usable,
        }

    def to_frame(self) -> pd.DataFrame:
        return pd.DataFrame({"position_deg": list(POSITIONS_DEG),
                             "mean_rate": [self.mean_rates[p] for p in POSITIONS_DEG],
                             "std": [self.std_rates[p] for p in POSITIONS_DEG],
                             "n": [self.n_samples[p] for p in POSITIONS_DEG]})

    # -------------------------------------------------------------- notebook view
    def _view_table(self) -> Table:
        rows = [(p, self.mean_rates[p], self.std_rates[p], self.n_samples[p])
                for p in POSITIONS_DEG]
        return Table.build(
            f"Four-position north finding at latitude {self.latitude_deg:g}°",
            (Column("position (°)"), Column("mean rate (°/h)", digits=6),
             Column("std (°/h)"), Column("n")), rows,
            caption="; ".join([self._azimuth_line(), *filter(None, [self.scale_warning])]))

    def _view_headline(self) -> str:
        if not self.azimuth_usable:
            return (f"no usable azimuth (1σ {self.sigma_deg:.3g}°) at latitude "
                    f"{self.latitude_deg:g}°")
        return (f"azimuth {self.azimuth_deg:.4f}° ± {self.sigma_deg:.4f}° at latitude "
                f"{self.latitude_deg:g}°")

    def _azimuth_line(self) -> str:
        """ψ with its budget, or why there is no usable azimuth."""
        b = self.budget_deg
        if not self.azimuth_usable:
            return no_azimuth_text(self.sigma_deg, b)
        return (f"azimuth ψ = {self.azimuth_deg:.4f}° ± {self.sigma_deg:.4f}° (1σ: ARW "
                f"{b['arw']:.4f}°, bias {b['bias']:.4f}°, drift {b['drift']:.4f}°)")

    def _scale_line(self) -> str:
        """The Earth-rate check with the numbers it rests on."""
        lo, hi = 1.0 / SCALE_TOLERANCE, SCALE_TOLERANCE
        ratio = f"ratio {self.scale_check:.4g} ± {self.scale_check_stderr:.2g} (1σ)"
        if self.scale_consistent:
            return (f"Earth-rate check: {ratio} is consistent with 1 (tolerance [{lo:.3f}, "
                    f"{hi:.3f}] for scale factor and drift)")
        return (f"Earth-rate check failed: {ratio} lies outside [{lo:.3f}, {hi:.3f}] by more "
                "than 3σ: the rates do not match the Earth rate at this latitude (see the "
                "warning)")

    def summary(self) -> str:
        lines = [f"Four-position north finding at latitude {self.latitude_deg:g}° "
                 f"(Ω cos L = {self.earth_rate_h_deg_h:.4f} °/h)",
                 "  position   mean rate [°/h]    std [°/h]      n"]
        for p in POSITIONS_DEG:
            lines.append(f"  {p:>6d}°  {self.mean_rates[p]:16.5f}  {self.std_rates[p]:11.4f}  "
                         f"{self.n_samples[p]:5d}")
        lines.append(f"  {self._azimuth_line()}")
        lines.append(f"  residual bias {self.bias_deg_h:.4f} °/h; measured Earth-rate amplitude "
                     f"{self.amplitude_deg_h:.4f} °/h (ratio {self.scale_check:.3f})")
        lines.append(f"  {self._scale_line()}")
        return "\n".join(lines)


def check_latitude(latitude_deg: float) -> float:
    try:
        lat = float(latitude_deg)
    except (TypeError, ValueError):
        raise DataError(f"latitude_deg must be a number in degrees, got {latitude_deg!r}") from None
    if not math.isfinite(lat) or abs(lat) > 90.0:
        raise DataError(f"latitude_deg must be in [-{MAX_LATITUDE_DEG:g}, {MAX_LATITUDE_DEG:g}] "
                        f"(north finding needs the horizontal Earth rate), got "
                        f"{latitude_deg!r}")
    if abs(lat) > MAX_LATITUDE_DEG:
        raise DataError(f"latitude_deg={lat:g} is within {90 - MAX_LATITUDE_DEG:g}° of the pole: the "
                        "horizontal Earth rate Ω cos L is too small to find north "
                        f"(allowed |latitude| <= {MAX_LATITUDE_DEG:g}°)")
    return lat


def _normalise_positions(rates_by_position: Any) -> dict[int, FloatArray]:
    if isinstance(rates_by_position, pd.DataFrame):
        return {p: v for p, v in positions_from_frame(rates_by_position).items()}
    if not isinstance(rates_by_position, Mapping):
        raise DataError("rates_by_position must map each position (0, 90, 180, 270) to its rate "
                        f"samples, or be a DataFrame with position_deg and rate; got "
                        f"{type(rates_by_position).__name__}")
    out: dict[int, FloatArray] = {}
    for key, val in rates_by_position.items():
        try:
            p = round(float(key)) % 360
        except (TypeError, ValueError):
            raise DataError(f"position {key!r} is not a number of degrees; positions are "
                            "0, 90, 180, 270") from None
        if p not in POSITIONS_DEG or abs(float(key) % 360 - p) > 1e-6:
            raise DataError(f"position {key!r} is not one of 0, 90, 180, 270")
        out[p] = to_float_array(val, f"rate at position {p}", min_length=MIN_POSITION_SAMPLES)
    missing = [p for p in POSITIONS_DEG if p not in out]
    if missing:
        raise DataError(f"positions {', '.join(map(str, missing))} are missing; four-position "
                        "north finding needs 0, 90, 180 and 270 (got "
                        f"{', '.join(map(str, sorted(out))) or 'none'})")
    return out


def positions_from_frame(frame: pd.DataFrame, *, position_column: str = "position_deg",
                         rate_column: str = "rate") -> dict[int, FloatArray]:
    """Split a table with a position column (0/90/180/270) into rate arrays per position.

    Examples
    --------
    >>> df = pd.DataFrame({"position_deg": [0] * 3 + [90] * 3 + [180] * 3 + [270] * 3,
    ...                    "rate": np.arange(12.0)})
    >>> positions_from_frame(df)[180].tolist()
    [6.0, 7.0, 8.0]
    """
    for col in (position_column, rate_column):
        if col not in frame.columns:
            raise DataError(f"column {col!r} not found; columns are: "
                            f"{', '.join(map(str, frame.columns))}")
    pos = to_float_array(frame[position_column], position_column, min_length=1)
    rate = to_float_array(frame[rate_column], rate_column, min_length=1)
    keys = np.round(pos).astype(np.int64) % 360
    bad = ~np.isin(keys, POSITIONS_DEG) | (np.abs(pos % 360 - keys) > 1e-6)
    if bad.any():
        i = int(np.argmax(bad))
        raise DataError(f"{position_column} must be 0, 90, 180 or 270; row {i} has {float(pos[i])!r}")
    out = {int(p): rate[keys == p] for p in POSITIONS_DEG if np.any(keys == p)}
    return _normalise_positions(out)



def four_position(
    rates_by_position: Mapping[Any, Any] | pd.DataFrame,
    *,
    latitude_deg: float,
    fs_hz: float = 1.0,
    units: str = "deg/h",
    position_time_s: Mapping[int, float] | None = None,
    transition_s: float = 0.0,
    bias_sigma_deg_h: float = 0.0,
) -> NorthFinding:
    """Azimuth from the mean rates at four positions (convention in the module docstring).

    ψ = atan2(ω₂₇₀ - ω₉₀, ω₀ - ω₁₈₀), free of the bias and of the scale factor; its error
    budget needs the latitude (Ω cos L).

    Parameters
    ----------
    rates_by_position : mapping or DataFrame
        ``{0: rate, 90: rate, 180: rate, 270: rate}`` (arrays or Series of samples), or a
        DataFrame with columns ``position_deg`` and ``rate``.
    latitude_deg : float
        Latitude L in degrees, |L| <= 89.
    fs_hz : float
        Sample rate (for the drift slope and the position times).
    units : str
        Rate unit of the samples.
    position_time_s : mapping, optional
        Centre time of each position in seconds.  Default: positions measured back to back in
        the order 0, 90, 180, 270, separated by ``transition_s``.
    transition_s : float
        Time to turn between positions (used for the default position times).
    bias_sigma_deg_h : float
        1σ variation of the bias from one position to the next beyond white noise (for
        example the bias stability at the position duration); enters the budget.

    Returns
    -------
    NorthFinding
        Its ``scale_consistent`` and ``azimuth_usable`` say whether the data support the
        azimuth (:mod:`~fogts.startup.northfind_checks`).

    Raises
    ------
    DataError
        A position is missing or unknown, latitude beyond ±89°, bad option.
    InsufficientDataError
        Fewer than 3 samples at a position.

    Examples
    --------
    >>> import numpy as np
    >>> from fogts.units import earth_rate_component
    >>> om = earth_rate_component(32.05, axis="north")
    >>> rates = {k: np.full(60, om * np.cos(np.radians(30.0 + k)) + 0.5) for k in (0, 90, 180, 270)}
    >>> round(four_position(rates, latitude_deg=32.05).azimuth_deg, 9)
    30.0
    """
    lat = check_latitude(latitude_deg)
    fs = check_positive("fs_hz", fs_hz)
    unit = parse_rate_unit(units)
    check_positive("transition_s", transition_s, allow_zero=True)
    sig_b = check_positive("bias_sigma_deg_h", bias_sigma_deg_h, allow_zero=True)
    data = {p: v * to_deg_per_hour_factor(unit)
            for p, v in _normalise_positions(rates_by_position).items()}
    omega_h = earth_rate_component(lat, unit="deg/h", axis="north")
    means = {p: float(np.mean(data[p])) for p in POSITIONS_DEG}
    stds = {p: float(np.std(data[p], ddof=1)) for p in POSITIONS_DEG}
    counts = {p: int(data[p].size) for p in POSITIONS_DEG}
    psi, dx, dy = _azimuth_deg(means)
    slope, sigma_mean = _within_position_fit(data, counts, fs)
    times = _position_times(counts, fs, position_time_s, transition_s)
    budget, drift_err, radial = _error_budget(psi, slope, times, sigma_mean, sig_b, omega_h)
    sigma = math.sqrt(sum(v * v for v in budget.values()))
    return NorthFinding(azimuth_deg=psi, sigma_deg=sigma, budget_deg=budget, latitude_deg=lat,
                        earth_rate_h_deg_h=omega_h, mean_rates=means, std_rates=stds,
                        n_samples=counts, bias_deg_h=float(np.mean(list(means.values()))),
                        amplitude_deg_h=0.5 * math.hypot(dx, dy),
                        drift_rate_deg_h_per_s=slope, drift_error_deg=drift_err,
                        sigma_mean_deg_h=sigma_mean, position_time_s=times, units=unit,
                        amplitude_stderr_deg_h=amplitude_stderr(sigma_mean, sig_b, radial))


def _azimuth_deg(means: Mapping[int, float]) -> tuple[float, float, float]:
    """ψ in [0, 360) from the four mean rates, with ω₀ - ω₁₈₀ and ω₂₇₀ - ω₉₀."""
    dx = means[0] - means[180]
    dy = means[270] - means[90]
    psi = math.degrees(math.atan2(dy, dx)) % 360.0
    if psi >= 360.0:  # atan2 of -0.0 rounding
        psi = 0.0
    return psi, dx, dy


def _within_position_fit(data: Mapping[int, FloatArray], counts: Mapping[int, int],
                         fs: float) -> tuple[float, float]:
    """Pooled within-position linear fit: the slope (bias drift, °/h per s) and the standard
    error of one position mean from the residual (white) scatter."""
    sxx = syy = sxy = 0.0
    dof = 0
    for p in POSITIONS_DEG:
        v = data[p]
        t = np.arange(v.size) / fs
        tc = t - t.mean()
        vc = v - v.mean()
        sxx += float(tc @ tc)
        sxy += float(tc @ vc)
        syy += float(vc @ vc)
        dof += v.size - 2
    slope = sxy / sxx if sxx > 0 else 0.0
    resid_var = max(syy - slope * sxy, 0.0) / max(dof, 1)
    n_eff = float(np.mean(list(counts.values())))
    return slope, math.sqrt(resid_var / n_eff)


def _position_times(counts: Mapping[int, int], fs: float,
                    position_time_s: Mapping[int, float] | None,
                    transition_s: float) -> dict[int, float]:
    """Centre time of each position: as given, or back to back with ``transition_s`` turns."""
    times: dict[int, float] = {}
    if position_time_s is None:
        start = 0.0
        for p in POSITIONS_DEG:
            dur = counts[p] / fs
            times[p] = start + 0.5 * dur
            start += dur + float(transition_s)
        return times
    for p in POSITIONS_DEG:
        if p not in position_time_s:
            raise DataError(f"position_time_s lacks position {p}; give all of 0, 90, 180, 270")
        times[p] = float(position_time_s[p])
    return times


def _error_budget(psi: float, slope: float, times: Mapping[int, float], sigma_mean: float,
                  sig_b: float, omega_h: float) -> tuple[dict[str, float], float, float]:
    """The 1σ budget (ARW, bias, drift; degrees), the signed drift error (module doc) and
    the drift's error along the measured Earth-rate vector (°/h, for its amplitude)."""
    rad = math.radians(psi)
    ex = slope * (times[0] - times[180]) / 2.0
    ey = slope * (times[270] - times[90]) / 2.0
    drift_err = math.degrees((-math.sin(rad) * ex + math.cos(rad) * ey) / omega_h)
    radial = math.cos(rad) * ex + math.sin(rad) * ey
    arw_deg = math.degrees(sigma_mean / (math.sqrt(2.0) * omega_h))
    bias_deg = math.degrees(sig_b / (math.sqrt(2.0) * omega_h))
    return {"arw": arw_deg, "bias": bias_deg, "drift": abs(drift_err)}, drift_err, radial


def angle_error_deg(estimate_deg: Any, truth_deg: Any) -> FloatArray:
    """Signed circular difference ``estimate - truth`` wrapped to [-180, 180).

    Examples
    --------
    >>> float(angle_error_deg(359.5, 0.5))
    -1.0
    """
    d = (np.asarray(estimate_deg, dtype=float) - np.asarray(truth_deg, dtype=float) + 180.0) % 360.0
    return d - 180.0
