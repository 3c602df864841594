"""Gyro noise from coefficients, and ARMA series from a model.

:func:`simulate_gyro` turns IEEE-952 noise coefficients (the units :mod:`fogts.allan.noise`
reports, DESIGN.md "Definitions") into a rate record whose Allan variance follows the
closed forms of seed 000, Table 1 / IEEE Std 952-1997 Annex C, Table C.1.  With the rate
``y`` in deg/h and tau in s, and every sample being the *average* rate over its sample
interval (which is what an integrating gyro's output is, and what the phase-based Allan
estimators assume):

==========================  ===================================  ==========================
term (unit)                 synthesis                            sigma^2(tau)
==========================  ===================================  ==========================
Q, angle quantisation       white angle noise, differenced       3 Q^2 / tau^2
(arcsec = (deg/h) s)
N, angle random walk        white rate noise                     N'^2 / tau
(deg/sqrt(h))
B, bias instability         flicker: sum of Markov processes     (2 ln 2 / pi) B^2
(deg/h)                     (default) or Kasdin-Walter
K, rate random walk         continuous random walk, interval     K'^2 tau / 3
(deg/h^1.5)                 averages (exact)
R, rate ramp (deg/h^2)      deterministic ramp                   R'^2 tau^2 / 2
Markov (q_c, T_c)           exact discretisation of the          (q_c T_c)^2/tau [1 - T_c/(2 tau)
                            interval-averaged Gauss-Markov        (3 - 4 e^{-tau/T_c} + e^{-2tau/T_c})]
sinusoid (Omega_0, f_0)     exact interval averages              Omega_0^2 sin^4(pi f_0 tau)/(pi f_0 tau)^2
==========================  ===================================  ==========================

where N' = 60 N (deg/h sqrt(s)), K' = K / 60 (deg/h / sqrt(s)) and R' = R / 3600 (deg/h/s)
are the coefficients in deg/h and seconds.  Every synthesis except Kasdin-Walter flicker is
*exact* in discrete time (its expected Allan variance is the closed form at every
tau = m / fs), and every one except Kasdin-Walter runs in chunks, so a 10^8-sample record
needs little more memory than its output array.  :meth:`NoiseSpec.avar` returns the
closed form.

Flicker (B) has no finite-dimensional exact synthesis.  The default is a sum of
first-order Markov processes with correlation times spaced three per decade from
``dt/100`` to ``10 x duration`` and weights ``q_i^2 = 2 Delta B^2 / (pi T_i)`` (Delta =
ln(10)/3), whose summed Lorentzian spectra approximate ``S(f) = B^2 / (2 pi f)`` (the
two-sided PSD of IEEE 952 Table C.1) within a ripple that puts the Allan plateau within
0.5 % of 0.664 B for every tau from ``1/fs`` to half the record (Keshner, "1/f noise",
Proc. IEEE 70(3), 1982, for the superposition idea).  ``flicker="kasdin"`` uses
Kasdin & Walter's fractional integration instead (N. J. Kasdin, "Discrete simulation of
colored noise and stochastic processes and 1/f^alpha power law noise generation",
Proc. IEEE 83(5), 1995, eq. 116: h_0 = 1, h_k = h_{k-1} (k - 1 + alpha/2)/k, alpha = 1,
applied by FFT convolution in O(n log n)).  It is sampled rather than interval-averaged
flicker, so its deviation exceeds 0.664 B by 20 %, 7.4 %, 2.5 % and 0.8 % at
m = 1, 2, 4 and 8 samples (the discrete-time integral of its spectrum), and it needs the
whole record in memory.

Random streams are split per axis and per term with ``numpy.random.Generator.spawn``, so
adding or removing one term leaves every other term's realisation unchanged, and the
output does not depend on the chunk size (beyond the rounding of running sums).
"""

from __future__ import annotations

import math
import warnings
from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass, fields
from typing import Any, Literal, get_args

import numpy as np
import scipy.fft
import scipy.signal

from fogts._typing import FloatArray, RngLike
from fogts._validate import as_rng, check_choice, check_int, check_positive
from fogts.allan.terms import TERM_DESCRIPTION, TERM_UNIT, TO_SECONDS
from fogts.errors import DataError, FogtsWarning
from fogts.io.run import Run, SamplingReport
from fogts.startup.thermal_model import THERMAL_TERMS, design_matrix, temperature_rate
from fogts.units import parse_duration, parse_rate_unit, to_deg_per_hour_factor

__all__ = [
    "ArmaSpec",
    "FlickerMethod",
    "NoiseSpec",
    "TemperatureProfile",
    "simulate_arma",
    "simulate_gyro",
    "thermal_drift",
]

FlickerMethod = Literal["markov", "kasdin"]
FLICKER_METHODS: tuple[str, ...] = get_args(FlickerMethod)


#: Default number of samples generated per chunk.
DEFAULT_CHUNK = 1 << 20

# Conversion of each coefficient to deg/h-and-seconds units (DESIGN.md "Definitions").
_TO_INTERNAL = TO_SECONDS
_UNITS = {**TERM_UNIT, "q_c": "deg/h/sqrt(s)", "T_c": "s", "Omega_0": "deg/h", "f_0": "Hz",
          "bias": "deg/h"}
_NAMES = {**TERM_DESCRIPTION, "q_c": "Markov driving noise",
          "T_c": "Markov correlation time", "Omega_0": "sinusoid amplitude",
          "f_0": "sinusoid frequency", "bias": "constant bias"}
_ALIASES = {"markov_q": "q_c", "qc": "q_c", "markov_t": "T_c", "tc": "T_c",
            "omega0": "Omega_0", "omega_0": "Omega_0", "sine_amplitude": "Omega_0",
            "f0": "f_0", "sine_freq_hz": "f_0", "sine_frequency": "f_0"}
# One independent random stream per term (fixed order: never reorder, only append).
_STREAMS = ("Q", "N", "B", "K", "markov", "sine", "arma")
_FLICKER_PPD = 3           # Markov poles per decade of correlation time
_FLICKER_LO_DECADES = 2    # poles start at dt / 10**2
_FLICKER_HI_FACTOR = 10.0  # ... and end at >= 10 x the record length
_TWO_LN2_OVER_PI = 2.0 * math.log(2.0) / math.pi


# --------------------------------------------------------------------------- NoiseSpec
@dataclass(frozen=True)
class NoiseSpec:
    """Noise coefficients of a gyro, in the units :func:`fogts.allan.noise.fit_noise` reports.

    Attributes
    ----------
    Q : float
        Angle quantisation noise in arcsec (= (deg/h) s).
    N : float
        Angle random walk in deg/sqrt(h).
    B : float
        Bias instability in deg/h (the Allan plateau is 0.664 B).
    K : float
        Rate random walk in deg/h^1.5.
    R : float
        Rate ramp in deg/h^2 (may be negative: the sign of the deterministic ramp).
    q_c : float
        First-order Markov driving-noise amplitude in deg/h/sqrt(s); the process has the
        two-sided PSD (q_c T_c)^2 / (1 + (2 pi f T_c)^2) and the stationary standard
        deviation ``q_c sqrt(T_c / 2)`` (IEEE 952 Table C.1).
    T_c : float
        Markov correlation time in s (required when ``q_c > 0``).
    Omega_0 : float
        Sinusoid amplitude in deg/h.
    f_0 : float
        Sinusoid frequency in Hz (required when ``Omega_0 > 0``).
    bias : float
        Constant rate offset in deg/h (invisible to the Allan variance; e.g. Earth rate
        plus turn-on bias).

    Examples
    --------
    >>> spec = NoiseSpec(N=0.002, B=0.01, K=0.02)
    >>> spec.terms
    ('N', 'B', 'K')
    >>> round(float(spec.adev([1.0])[0]), 4)   # deg/h at tau = 1 s, dominated by 60 N
    0.1202
    """

    Q: float = 0.0
    N: float = 0.0
    B: float = 0.0
    K: float = 0.0
    R: float = 0.0
    q_c: float = 0.0
    T_c: float = 0.0
    Omega_0: float = 0.0
    f_0: float = 0.0
    bias: float = 0.0

    def __post_init__(self) -> None:
        for f in fields(self):
            value = getattr(self, f.name)
            try:
                v = float(value)
            except (TypeError, ValueError):
                raise DataError(f"noise term {f.name} must be a number, got {value!r}") from None
            if not math.isfinite(v):
                raise DataError(f"noise term {f.name} must be finite, got {value!r}")
            if v < 0 and f.name not in ("R", "bias"):
                raise DataError(f"noise term {f.name} ({_NAMES[f.name]}) must be >= 0, "
                                f"got {value!r}")
            object.__setattr__(self, f.name, v)
        if self.q_c > 0 and self.T_c <= 0:
            raise DataError(f"a Markov term needs T_c > 0 (correlation time in s), got "
                            f"q_c={self.q_c!r}, T_c={self.T_c!r}")
        if self.Omega_0 > 0 and self.f_0 <= 0:
            raise DataError(f"a sinusoid needs f_0 > 0 (Hz), got Omega_0={self.Omega_0!r}, "
                            f"f_0={self.f_0!r}")

    # ---- construction
    @classmethod
    def from_any(cls, noise: Any) -> NoiseSpec:
        """Build a spec from a NoiseSpec, a mapping or a fitted noise model.

        Accepted: a :class:`NoiseSpec`; a mapping from term names (``Q N B K R q_c T_c
        Omega_0 f_0 bias``) to numbers, to ``{"value": ...}`` dicts (the ``noise`` block of
        ``fogts allan --json``) or to objects with a ``.value``; or any object (such as
        :class:`fogts.allan.noise.NoiseModel`) whose ``to_dict()`` gives such a mapping,
        possibly under a ``"terms"`` key, or that has the term names as attributes.
        A term whose value is None or NaN (not identified by a fit) is left out.
        """
        if isinstance(noise, NoiseSpec):
            return noise
        mapping = _term_mapping(noise)
        values: dict[str, float] = {}
        allowed = [f.name for f in fields(cls)]
        for key, raw in mapping.items():
            name = _canonical_term(str(key), allowed)
            value = _term_value(raw)
            if value is None:
                continue
            values[name] = value
        return cls(**values)

    # ---- derived quantities
    @property
    def terms(self) -> tuple[str, ...]:
        """Names of the terms present (non-zero): a subset of Q N B K R markov sine bias."""
        out = [t for t in ("Q", "N", "B", "K", "R") if getattr(self, t) != 0.0]
        if self.q_c > 0:
            out.append("markov")
        if self.Omega_0 > 0:
            out.append("sine")
        if self.bias != 0.0:
            out.append("bias")
        return tuple(out)

    def internal(self, name: str) -> float:
        """Coefficient ``name`` (Q N B K R) converted to deg/h and seconds."""
        return float(getattr(self, name)) * _TO_INTERNAL[name]

    def avar(self, tau_s: Any, *, units: str = "deg/h") -> FloatArray:
        """Closed-form Allan variance at ``tau_s`` (seed 000 Table 1; IEEE 952 Table C.1).

        sigma^2 = 3Q^2/tau^2 + N'^2/tau + (2 ln2/pi) B^2 + K'^2 tau/3 + R'^2 tau^2/2
        + Markov + sinusoid (see the module docstring); in ``units``^2.  The flicker term is
        the IEEE asymptote (2 ln 2 / pi) B^2.
        """
        tau = np.asarray(tau_s, dtype=np.float64)
        if tau.size and (not np.all(np.isfinite(tau)) or np.any(tau <= 0)):
            raise DataError(f"tau_s must be finite and > 0, got {tau_s!r}")
        q, n_, b = self.internal("Q"), self.internal("N"), self.internal("B")
        k, r = self.internal("K"), self.internal("R")
        av = (3.0 * q * q / tau**2 + n_ * n_ / tau + _TWO_LN2_OVER_PI * b * b
              + k * k * tau / 3.0 + r * r * tau**2 / 2.0)
        if self.q_c > 0:
            av = av + markov_avar(self.q_c, self.T_c, tau)
        if self.Omega_0 > 0:
            x = math.pi * self.f_0 * tau
            av = av + self.Omega_0**2 * np.sin(x) ** 4 / x**2
        scale = 1.0 / to_deg_per_hour_factor(parse_rate_unit(units))
        return np.asarray(av * scale * scale, dtype=np.float64)

    def adev(self, tau_s: Any, *, units: str = "deg/h") -> FloatArray:
        """Closed-form Allan deviation, ``sqrt(avar)``."""
        return np.sqrt(self.avar(tau_s, units=units))

    # ---- output
    def to_dict(self) -> dict[str, Any]:
        """``{name: {"value", "unit", "description"}}`` for every field (stable keys)."""
        return {f.name: {"value": getattr(self, f.name), "unit": _UNITS[f.name],
                         "description": _NAMES[f.name]} for f in fields(self)}

    def to_frame(self) -> Any:
        """One row per coefficient: term, value, unit, description."""
        import pandas as pd

        return pd.DataFrame([{"term": k, **v} for k, v in self.to_dict().items()])

    def summary(self) -> str:
        lines = ["Noise specification (IEEE Std 952-1997 units)"]
        for name, d in self.to_dict().items():
            if d["value"] != 0.0:
                lines.append(f"  {name:<8}{d['value']:>14.6g}  {d['unit']:<14}{d['description']}")
        if len(lines) == 1:
            lines.append("  (no noise terms: a noiseless record)")
        return "\n".join(lines)


def _term_mapping(noise: Any) -> Mapping[str, Any]:
    if isinstance(noise, Mapping):
        inner = noise.get("terms") if "terms" in noise else noise.get("noise")
        return inner if isinstance(inner, Mapping) else noise
    terms = getattr(noise, "terms", None)
    if isinstance(terms, Mapping):
        return terms
    to_dict = getattr(noise, "to_dict", None)
    if callable(to_dict):
        d = to_dict()
        if isinstance(d, Mapping):
            return _term_mapping(d)
    names = [f.name for f in fields(NoiseSpec)]
    found = {n: getattr(noise, n) for n in names if hasattr(noise, n)}
    if found:
        return found
    raise DataError(f"noise must be a NoiseSpec, a mapping of term names (Q, N, B, K, R, q_c, "
                    f"T_c, Omega_0, f_0, bias) to values, or a fitted NoiseModel; got "
                    f"{type(noise).__name__}")


def _canonical_term(key: str, allowed: Sequence[str]) -> str:
    if key in allowed:
        return key
    alias = _ALIASES.get(key.lower())
    if alias is not None:
        return alias
    upper = key.upper()
    if upper in ("Q", "N", "B", "K", "R"):
        return upper
    raise DataError(f"unknown noise term {key!r}; terms are: {', '.join(allowed)}")


def _term_value(raw: Any) -> float | None:
    if isinstance(raw, Mapping):
        raw = raw.get("value")
    elif hasattr(raw, "value") and not isinstance(raw, int | float | np.number):
        raw = raw.value
    if raw is None:
        return None
    try:
        v = float(raw)
    except (TypeError, ValueError):
        raise DataError(f"noise term values must be numbers, got {raw!r}") from None
    return None if math.isnan(v) else v


def markov_avar(q_c: float, T_c: float, tau_s: Any) -> FloatArray:
    """Allan variance of the interval-averaged first-order Markov process (IEEE 952 Table C.1).

    sigma^2(tau) = (q_c T_c)^2 / tau [1 - T_c/(2 tau) (3 - 4 e^{-tau/T_c} + e^{-2 tau/T_c})],
    evaluated with a Taylor series for tau < 0.01 T_c (where the bracket cancels).

    Examples
    --------
    >>> round(float(markov_avar(1.0, 10.0, 1e4)[0]) * 1e4, 3)   # tau >> T_c: (q_c T_c)^2/tau
    99.85
    """
    tau = np.atleast_1d(np.asarray(tau_s, dtype=np.float64))
    h = tau / T_c
    num = np.empty_like(h)
    small = h < 1e-2
    hs = h[small]
    num[small] = 2 * hs**3 / 3 - hs**4 / 2 + 7 * hs**5 / 30 - hs**6 / 12
    hl = h[~small]
    num[~small] = 2 * hl - 3 + 4 * np.exp(-hl) - np.exp(-2 * hl)
    return np.asarray((q_c * T_c) ** 2 / tau * num / (2 * h), dtype=np.float64)


# --------------------------------------------------------------------------- ARMA spec
@dataclass(frozen=True)
class ArmaSpec:
    """An ARMA(p, q) model in statsmodels' sign convention (DESIGN.md).

    x_t - const = phi_1 (x_{t-1} - const) + ... + a_t + theta_1 a_{t-1} + ...,
    with a_t white, variance ``sigma2``.

    Examples
    --------
    >>> ArmaSpec.parse("ar=0.9,-0.2;ma=0.3;sigma2=1e-4").order
    (2, 1)
    """

    ar: tuple[float, ...] = ()
    ma: tuple[float, ...] = ()
    sigma2: float = 1.0
    const: float = 0.0

    def __post_init__(self) -> None:
        ar = tuple(float(v) for v in np.atleast_1d(np.asarray(self.ar, dtype=np.float64)))
        ma = tuple(float(v) for v in np.atleast_1d(np.asarray(self.ma, dtype=np.float64)))
        object.__setattr__(self, "ar", ar)
        object.__setattr__(self, "ma", ma)
        if not all(math.isfinite(v) for v in (*ar, *ma)):
            raise DataError(f"ARMA coefficients must be finite, got ar={ar}, ma={ma}")
        object.__setattr__(self, "sigma2", check_positive("sigma2", self.sigma2))
        c = float(self.const)
        if not math.isfinite(c):
            raise DataError(f"const must be finite, got {self.const!r}")
        object.__setattr__(self, "const", c)
        if ar and self.ar_radius >= 1.0:
            raise DataError(f"the AR part is not stationary (largest inverse root modulus "
                            f"{self.ar_radius:.6g} >= 1); ar={list(ar)}")

    @property
    def order(self) -> tuple[int, int]:
        return (len(self.ar), len(self.ma))

    @property
    def ar_radius(self) -> float:
        """Largest modulus of the AR poles (inverse roots); < 1 means stationary."""
        if not self.ar:
            return 0.0
        return float(np.max(np.abs(np.roots(np.r_[1.0, -np.asarray(self.ar)]))))

    def burn_in(self, tol: float = 1e-12, cap: int = 1_000_000) -> int:
        """Samples to discard so the start-up transient decays below ``tol``."""
        rho = self.ar_radius
        n = len(self.ma) + len(self.ar)
        if rho > 0:
            n = max(n, math.ceil(math.log(tol) / math.log(rho)))
        return int(min(max(n, 10 * (len(self.ar) + len(self.ma))), cap))

    @classmethod
    def parse(cls, text: str) -> ArmaSpec:
        """Parse ``"ar=0.9,-0.2;ma=0.3;sigma2=1e-4[;const=0]"`` (any part may be omitted)."""
        values: dict[str, Any] = {}
        for part in str(text).split(";"):
            if not part.strip():
                continue
            if "=" not in part:
                raise DataError(f"arma must look like 'ar=0.9,-0.2;ma=0.3;sigma2=1e-4'; got "
                                f"{text!r}")
            key, _, val = part.partition("=")
            key = key.strip().lower()
            if key not in ("ar", "ma", "sigma2", "const"):
                raise DataError(f"arma key must be one of ar, ma, sigma2, const; got {key!r}")
            try:
                nums = [float(v) for v in val.split(",") if v.strip()]
            except ValueError:
                raise DataError(f"arma {key} must be numbers separated by commas, got "
                                f"{val.strip()!r}") from None
            if key in ("ar", "ma"):
                values[key] = tuple(nums)
            else:
                if len(nums) != 1:
                    raise DataError(f"arma {key} must be one number, got {val.strip()!r}")
                values[key] = nums[0]
        if "sigma2" not in values:
            raise DataError(f"arma needs sigma2 (the innovation variance); got {text!r}")
        return cls(**values)

    @classmethod
    def from_any(cls, model: Any) -> ArmaSpec:
        """From an ArmaSpec, a fitted model (``.ar``, ``.ma``, ``.params["sigma2"]``), a
        selection (``.best``), a ``{"ar", "ma", "sigma2"}`` mapping, a mapping of
        statsmodels parameter names (``ar.L1``, ``ma.L1``, ``sigma2``, ``const``; e.g. a
        ``fogts select`` candidate's ``params``) or a string for :meth:`parse`."""
        if isinstance(model, ArmaSpec):
            return model
        if isinstance(model, str):
            return cls.parse(model)
        if hasattr(model, "best") and not isinstance(model, Mapping):
            if model.best is None:
                raise DataError("the selection has no selected model (every candidate "
                                "failed); pick a candidate explicitly")
            model = model.best
        if isinstance(model, Mapping):
            if "params" in model and isinstance(model["params"], Mapping):
                return cls._from_param_names(model["params"])
            if any(str(k).startswith(("ar.L", "ma.L")) for k in model):
                return cls._from_param_names(model)
            unknown = set(model) - {"ar", "ma", "sigma2", "const"}
            if unknown:
                raise DataError(f"ARMA mapping keys must be ar, ma, sigma2, const; got "
                                f"{sorted(map(str, unknown))}")
            if "sigma2" not in model:
                raise DataError("an ARMA mapping needs 'sigma2' (the innovation variance)")
            return cls(ar=tuple(model.get("ar", ())), ma=tuple(model.get("ma", ())),
                       sigma2=model["sigma2"], const=model.get("const", 0.0))
        if hasattr(model, "ar") and hasattr(model, "ma"):
            params = getattr(model, "params", None)
            sigma2 = getattr(model, "sigma2", None)
            if sigma2 is None and params is not None:
                try:
                    sigma2 = params["sigma2"]
                except (KeyError, IndexError, TypeError):
                    sigma2 = None
            if sigma2 is None:
                raise DataError(f"{type(model).__name__} has no sigma2 (innovation variance)")
            const = 0.0
            if params is not None:
                try:
                    const = float(params["const"])
                except (KeyError, IndexError, TypeError, ValueError):
                    const = 0.0
            return cls(ar=tuple(np.asarray(model.ar, dtype=np.float64).ravel()),
                       ma=tuple(np.asarray(model.ma, dtype=np.float64).ravel()),
                       sigma2=float(sigma2), const=const)
        raise DataError(f"model must be an ARMA fit, a selection, a mapping with ar/ma/sigma2 "
                        f"or a string like 'ar=0.9;sigma2=1'; got {type(model).__name__}")

    @classmethod
    def _from_param_names(cls, params: Mapping[str, Any]) -> ArmaSpec:
        def lagged(prefix: str) -> tuple[float, ...]:
            lags = sorted(int(k[len(prefix):]) for k in params if str(k).startswith(prefix))
            out = [0.0] * (max(lags) if lags else 0)
            for lag in lags:
                out[lag - 1] = float(params[f"{prefix}{lag}"])
            return tuple(out)

        if "sigma2" not in params:
            raise DataError("ARMA params need 'sigma2' (the innovation variance)")
        return cls(ar=lagged("ar.L"), ma=lagged("ma.L"), sigma2=float(params["sigma2"]),
                   const=float(params.get("const", 0.0)))

    def to_dict(self) -> dict[str, Any]:
        return {"ar": list(self.ar), "ma": list(self.ma), "sigma2": self.sigma2,
                "const": self.const, "order": list(self.order)}


class _ArmaStream:
    """Stateful chunked ARMA generator (scipy.signal.lfilter with carried state)."""

    def __init__(self, spec: ArmaSpec, rng: np.random.Generator, burn_in: int | None) -> None:
        self.spec = spec
        self.rng = rng
        self.b = np.r_[1.0, np.asarray(spec.ma, dtype=np.float64)]
        self.a = np.r_[1.0, -np.asarray(spec.ar, dtype=np.float64)]
        self.sd = math.sqrt(spec.sigma2)
        self.zi = np.zeros(max(len(self.a), len(self.b)) - 1)
        burn = spec.burn_in() if burn_in is None else check_int("burn_in", burn_in, minimum=0)
        if burn_in is None and burn >= 1_000_000 and spec.ar_radius > 0:
            warnings.warn(f"AR pole modulus {spec.ar_radius:.8g} is close to 1: the burn-in is "
                          f"capped at {burn} samples, so the start may not be stationary",
                          FogtsWarning, stacklevel=3)
        self.burn_in = burn
        done = 0
        while done < burn:
            c = min(DEFAULT_CHUNK, burn - done)
            self.next(c)
            done += c

    def next(self, count: int) -> FloatArray:
        e = self.rng.standard_normal(count) * self.sd
        if self.zi.size == 0:
            return e + self.spec.const
        y, self.zi = scipy.signal.lfilter(self.b, self.a, e, zi=self.zi)
        return np.asarray(y, dtype=np.float64) + self.spec.const


def simulate_arma(model_or_params: Any, n: int, *, rng: RngLike = None,
                  burn_in: int | None = None) -> FloatArray:
    """Simulate ``n`` samples of an ARMA(p, q) process.

    Parameters
    ----------
    model_or_params : ArmaFit, Selection, mapping, str or ArmaSpec
        A fitted model (``.ar``, ``.ma``, ``.params["sigma2"]``, e.g. ``Selection.best``),
        ``{"ar": [...], "ma": [...], "sigma2": ...}``, statsmodels parameter names
        (``ar.L1``, ``ma.L1``, ``sigma2``, ``const``) or ``"ar=...;ma=...;sigma2=..."``.
        Sign convention of statsmodels: x_t = phi_1 x_{t-1} + ... + a_t + theta_1 a_{t-1}.
    n : int
        Number of samples.
    rng : Generator, int or None
        Random source.
    burn_in : int, optional
        Start-up samples discarded; default: enough for the slowest AR pole to decay by
        1e-12 (at least 10 (p + q), at most 10^6).

    Returns
    -------
    ndarray of float64, shape (n,)

    Notes
    -----
    The filter is ``scipy.signal.lfilter([1, theta...], [1, -phi...], a)`` with the state
    carried across chunks and through the burn-in (Box, Jenkins & Reinsel, *Time Series
    Analysis*, ch. 3).

    Examples
    --------
    >>> x = simulate_arma({"ar": [0.9], "sigma2": 1.0}, 200_000, rng=0)
    >>> round(float(np.var(x)), 1)   # 1 / (1 - 0.81) = 5.26
    5.3
    """
    spec = ArmaSpec.from_any(model_or_params)
    n = check_int("n", n, minimum=1)
    stream = _ArmaStream(spec, as_rng(rng), burn_in)
    out = np.empty(n, dtype=np.float64)
    for i0 in range(0, n, DEFAULT_CHUNK):
        i1 = min(n, i0 + DEFAULT_CHUNK)
        out[i0:i1] = stream.next(i1 - i0)
    return out


# --------------------------------------------------------------------------- temperature
@dataclass(frozen=True)
class TemperatureProfile:
    """A smooth temperature history in degC.

    Kinds:

    * ``constant``: T = ``start_c``;
    * ``warmup``: first-order approach to a steady state (a powered-up FOG heating its
      enclosure), T = end - (end - start) exp(-t / tau); the rate of change peaks at t = 0
      with (end - start) / tau degC/s;
    * ``ramp``: linear from ``start_c`` to ``end_c`` over the record.

    Examples
    --------
    >>> p = TemperatureProfile.parse("warmup:20,30,20min")
    >>> round(float(p.evaluate(np.array([0.0, 1200.0]), duration_s=3600)[1]), 3)
    26.321
    """

    kind: Literal["constant", "warmup", "ramp"]
    start_c: float
    end_c: float = float("nan")
    time_constant_s: float = float("nan")

    def __post_init__(self) -> None:
        check_choice("temperature profile kind", self.kind, ("constant", "warmup", "ramp"))
        for name in ("start_c",) + (("end_c",) if self.kind != "constant" else ()):
            v = float(getattr(self, name))
            if not math.isfinite(v) or not -273.15 < v < 1000:
                raise DataError(f"temperature {name} must be a temperature in degC, got "
                                f"{getattr(self, name)!r}")
        if self.kind == "warmup":
            check_positive("temperature time constant", self.time_constant_s)

    @classmethod
    def parse(cls, text: str) -> TemperatureProfile:
        """``"constant:25"``, ``"warmup:START,END,TAU"`` (TAU a duration such as ``20min``)
        or ``"ramp:START,END"``."""
        kind, _, rest = str(text).partition(":")
        kind = kind.strip().lower()
        args = [a.strip() for a in rest.split(",") if a.strip()]
        usage = ("temperature profile must be 'constant:T', 'warmup:START,END,TAU' or "
                 f"'ramp:START,END' (degC; TAU like 20min); got {text!r}")
        expected = {"constant": 1, "const": 1, "warmup": 3, "ramp": 2}
        if kind not in expected or len(args) != expected[kind]:
            raise DataError(usage)
        try:
            nums = [float(a) for a in args[:2]]
        except ValueError:
            raise DataError(usage) from None
        if kind in ("constant", "const"):
            return cls("constant", nums[0])
        if kind == "ramp":
            return cls("ramp", nums[0], nums[1])
        return cls("warmup", nums[0], nums[1],
                   parse_duration(args[2], "temperature time constant"))

    def evaluate(self, time_s: FloatArray, *, duration_s: float) -> FloatArray:
        t = np.asarray(time_s, dtype=np.float64)
        if self.kind == "constant":
            return np.full(t.shape, self.start_c)
        if self.kind == "ramp":
            return self.start_c + (self.end_c - self.start_c) * t / duration_s
        return self.end_c - (self.end_c - self.start_c) * np.exp(-t / self.time_constant_s)

    def to_dict(self) -> dict[str, Any]:
        return {"kind": self.kind, "start_c": self.start_c, "end_c": self.end_c,
                "time_constant_s": self.time_constant_s}


def thermal_drift(temperature: Any, coefficients: Mapping[str, float], *,
                  fs_hz: float) -> FloatArray:
    """Temperature-driven drift D = a T dT + b T^2 + c T + d dT^2 + e dT + f (seed 004).

    The regressors are those of :func:`fogts.startup.thermal_model.design_matrix`; dT is the temperature
    rate of change in degC/s from ``numpy.gradient`` of the noiseless profile
    (:func:`fogts.startup.thermal_model.temperature_rate` with ``smoothing_s=None``).

    Parameters
    ----------
    temperature : array_like
        Temperature in degC, one value per sample (at least 5).
    coefficients : mapping
        Any of ``"T*dT"`` (a), ``"T2"`` (b), ``"T"`` (c), ``"dT2"`` (d), ``"dT"`` (e) and
        ``"1"`` (f), in deg/h per unit of the regressor.
    fs_hz : float
        Sample rate.

    Returns
    -------
    ndarray of float64
        Drift in deg/h.

    Examples
    --------
    >>> d = thermal_drift(np.linspace(20, 21, 11), {"T": 0.1, "dT": 10.0}, fs_hz=1.0)
    >>> round(float(d[0]), 6)   # 0.1 * 20 + 10 * 0.1
    3.0
    """
    unknown = set(coefficients) - set(THERMAL_TERMS)
    if unknown:
        raise DataError(f"thermal coefficient names must be among {', '.join(THERMAL_TERMS)}; "
                        f"got {sorted(unknown)}")
    names = list(coefficients)
    values = np.array([float(coefficients[k]) for k in names], dtype=np.float64)
    if not np.all(np.isfinite(values)):
        bad = names[int(np.argmax(~np.isfinite(values)))]
        raise DataError(f"thermal coefficient {bad!r} must be finite, got "
                        f"{coefficients[bad]!r}")
    dtemp = temperature_rate(temperature, fs_hz=fs_hz, smoothing_s=None)
    temp = np.asarray(temperature, dtype=np.float64)
    return np.asarray(design_matrix(temp, dtemp, names) @ values, dtype=np.float64)


# --------------------------------------------------------------------------- term streams
class _Stream:
    """One noise term of one axis, generated chunk by chunk (state carried across chunks)."""

    def next(self, i0: int, count: int) -> FloatArray:  # pragma: no cover - interface
        raise NotImplementedError


class _White(_Stream):
    def __init__(self, sd: float, g: np.random.Generator) -> None:
        self.sd, self.g = sd, g

    def next(self, i0: int, count: int) -> FloatArray:
        return self.g.standard_normal(count) * self.sd


class _AngleWhite(_Stream):
    """Rate = (theta_{k+1} - theta_k) fs, theta white with sd ``q`` (deg/h s)."""

    def __init__(self, q: float, fs: float, g: np.random.Generator) -> None:
        self.q, self.fs, self.g = q, fs, g
        self.last = float(g.standard_normal()) * q

    def next(self, i0: int, count: int) -> FloatArray:
        theta = np.empty(count + 1)
        theta[0] = self.last
        theta[1:] = self.g.standard_normal(count) * self.q
        self.last = float(theta[-1])
        return np.diff(theta) * self.fs


class _RandomWalk(_Stream):
    """Interval averages of a continuous random walk W with diffusion k^2 (exact):
    y_k = (W_k + W_{k+1}) / 2 + sqrt(k^2 dt / 12) z'_k (the Brownian-bridge mean)."""

    def __init__(self, k: float, fs: float, g: np.random.Generator) -> None:
        dt = 1.0 / fs
        self.step_sd, self.bridge_sd, self.g = k * math.sqrt(dt), k * math.sqrt(dt / 12), g
        self.w = 0.0

    def next(self, i0: int, count: int) -> FloatArray:
        z = self.g.standard_normal(2 * count)
        w = np.empty(count + 1)
        w[0] = self.w
        np.cumsum(z[0::2] * self.step_sd, out=w[1:])
        w[1:] += self.w
        self.w = float(w[-1])
        return 0.5 * (w[:-1] + w[1:]) + z[1::2] * self.bridge_sd


class _Markov(_Stream):
    """Exact discretisation of interval averages of the Gauss-Markov process
    dx = -x/T dt + q dW (one or several, summed).

    With a = exp(-dt/T): x_{k+1} = a x_k + u_k and y_k = (T (1 - a) x_k + v_k) / dt, where
    (u_k, v_k) are jointly Gaussian with var u = q^2 T/2 (1 - a^2),
    var v = q^2 T^3 [h - 2(1 - e^{-h}) + (1 - e^{-2h})/2] (h = dt/T) and
    cov(u, v) = q^2 T^2 (1 - a)^2 / 2; x_0 is drawn from the stationary N(0, q^2 T / 2).

    Writing u = l11 z1 and v = l21 z1 + l22 z2 (Cholesky), each pole's output is one IIR
    filter of z1, y = [c1 + (g l11 - a c1) z^-1] / (1 - a z^-1) z1 with c1 = l21/dt and
    g = T(1 - a)/dt, plus the white part (l22/dt) z2.  The white parts of all poles are
    independent, so their sum is drawn as one white sequence of variance sum (l22/dt)^2:
    P + 1 normal draws per sample for P poles.
    """

    def __init__(self, q: Sequence[float] | FloatArray, T: Sequence[float] | FloatArray,
                 fs: float, g: np.random.Generator) -> None:
        dt = 1.0 / fs
        q_arr, t_arr = np.asarray(q, dtype=np.float64), np.asarray(T, dtype=np.float64)
        h = dt / t_arr
        one_minus_a = -np.expm1(-h)
        a = 1.0 - one_minus_a
        one_minus_a2 = -np.expm1(-2 * h)
        var_u = q_arr**2 * t_arr / 2 * one_minus_a2
        f = np.where(h < 1e-2, h**3 / 3 - h**4 / 4 + 7 * h**5 / 60 - h**6 / 24,
                     h - 2 * one_minus_a + one_minus_a2 / 2)
        var_v = q_arr**2 * t_arr**3 * f
        cov = q_arr**2 * t_arr**2 * one_minus_a**2 / 2
        l11 = np.sqrt(var_u)
        l21 = np.divide(cov, l11, out=np.zeros_like(cov), where=l11 > 0)
        l22 = np.sqrt(np.maximum(var_v - l21**2, 0.0))
        gain = t_arr * one_minus_a / dt
        c1 = l21 / dt
        self.a = a
        self.b = np.stack([c1, gain * l11 - a * c1], axis=1)
        self.white_sd = float(np.sqrt(np.sum((l22 / dt) ** 2)))
        # one stream per pole (+ one for the white parts), so that the output does not
        # depend on the chunk size
        gens = g.spawn(q_arr.size + 1)
        self.gens, self.white_gen = gens[:-1], gens[-1]
        x0 = np.array([gj.standard_normal() for gj in self.gens]) * q_arr * np.sqrt(t_arr / 2)
        self.zi = gain * x0  # lfilter state: y_0 = c1 z1_0 + gain x_0

    def next(self, i0: int, count: int) -> FloatArray:
        out = self.white_gen.standard_normal(count) * self.white_sd
        for j in range(self.a.size):
            z1 = self.gens[j].standard_normal(count)
            y, zf = scipy.signal.lfilter(self.b[j], [1.0, -self.a[j]], z1,
                                         zi=self.zi[j:j + 1])
            self.zi[j] = zf[0]
            out += y
        return out


class _Sine(_Stream):
    """Interval averages of Omega sin(2 pi f t + phi): Omega sinc(f dt) sin(2 pi f (t + dt/2) + phi)."""

    def __init__(self, amp: float, f0: float, fs: float, g: np.random.Generator) -> None:
        self.amp = amp * float(np.sinc(f0 / fs))
        self.w, self.fs = 2 * math.pi * f0, fs
        self.phase = float(g.uniform(0.0, 2 * math.pi))

    def next(self, i0: int, count: int) -> FloatArray:
        t = (np.arange(i0, i0 + count, dtype=np.float64) + 0.5) / self.fs
        return self.amp * np.sin(self.w * t + self.phase)


class _Precomputed(_Stream):
    def __init__(self, values: FloatArray) -> None:
        self.values = values

    def next(self, i0: int, count: int) -> FloatArray:
        return self.values[i0:i0 + count]


def flicker_poles(fs_hz: float, duration_s: float) -> tuple[FloatArray, FloatArray]:
    """Correlation times T_i (s) and driving amplitudes q_i (per unit B, deg/h/sqrt(s) per
    deg/h) of the Markov sum that approximates flicker noise over a record.

    Three poles per decade from ``dt/100`` (on a grid aligned with dt) to at least
    ``10 x duration``, with q_i^2 = 2 Delta B^2 / (pi T_i) and Delta = ln(10)/3, so that
    sum_i (q_i T_i)^2 / (1 + (2 pi f T_i)^2) ~ B^2 / (2 pi f).
    """
    dt = 1.0 / fs_hz
    k_lo = -_FLICKER_LO_DECADES * _FLICKER_PPD
    k_hi = math.ceil(_FLICKER_PPD * math.log10(_FLICKER_HI_FACTOR * duration_s / dt))
    T = dt * 10.0 ** (np.arange(k_lo, k_hi + 1) / _FLICKER_PPD)
    delta = math.log(10.0) / _FLICKER_PPD
    q = np.sqrt(2.0 * delta / (math.pi * T))
    return T, q


def _kasdin_flicker(n: int, b: float, g: np.random.Generator) -> FloatArray:
    """Kasdin-Walter 1/f (alpha = 1) noise of ``n`` samples, two-sided PSD ~ b^2/(2 pi f).

    h_0 = 1, h_k = h_{k-1} (k - 0.5) / k (Kasdin 1995, eq. 116) convolved with white noise
    of variance b^2 by a zero-padded FFT (linear, not circular, convolution).
    """
    k = np.arange(1, n, dtype=np.float64)
    h = np.empty(n)
    h[0] = 1.0
    h[1:] = np.cumprod((k - 0.5) / k)
    w = g.standard_normal(n) * b
    size = scipy.fft.next_fast_len(2 * n, real=True)
    y = scipy.fft.irfft(scipy.fft.rfft(w, size) * scipy.fft.rfft(h, size), size)[:n]
    return np.ascontiguousarray(y, dtype=np.float64)


def _axis_streams(spec: NoiseSpec, arma: ArmaSpec | None, *, fs: float, n: int,
                  duration: float, flicker: str, rng: np.random.Generator) -> list[_Stream]:
    gens = dict(zip(_STREAMS, rng.spawn(len(_STREAMS)), strict=True))
    streams: list[_Stream] = []
    if spec.Q > 0:
        streams.append(_AngleWhite(spec.internal("Q"), fs, gens["Q"]))
    if spec.N > 0:
        streams.append(_White(spec.internal("N") * math.sqrt(fs), gens["N"]))
    if spec.B > 0:
        if flicker == "kasdin":
            streams.append(_Precomputed(_kasdin_flicker(n, spec.B, gens["B"])))
        else:
            T, q = flicker_poles(fs, duration)
            streams.append(_Markov(q * spec.B, T, fs, gens["B"]))
    if spec.K > 0:
        streams.append(_RandomWalk(spec.internal("K"), fs, gens["K"]))
    if spec.q_c > 0:
        streams.append(_Markov([spec.q_c], [spec.T_c], fs, gens["markov"]))
    if spec.Omega_0 > 0:
        streams.append(_Sine(spec.Omega_0, spec.f_0, fs, gens["sine"]))
    if arma is not None:
        stream = _ArmaStream(arma, gens["arma"], None)
        streams.append(_FromArma(stream))
    return streams


class _FromArma(_Stream):
    def __init__(self, stream: _ArmaStream) -> None:
        self.stream = stream

    def next(self, i0: int, count: int) -> FloatArray:
        return self.stream.next(count)


# --------------------------------------------------------------------------- simulate_gyro
def simulate_gyro(
    noise: Any,
    *,
    fs_hz: float,
    duration_s: float | str,
    rng: RngLike = None,
    units: str = "deg/h",
    n_axes: int | None = None,
    arma: Any = None,
    temperature: Any = None,
    thermal_coefficients: Mapping[str, float] | None = None,
    flicker: FlickerMethod = "markov",
    chunk_size: int = DEFAULT_CHUNK,
) -> Run:
    """Simulate a static gyro record from IEEE-952 noise coefficients.

    Parameters
    ----------
    noise : NoiseSpec, mapping, NoiseModel, or a sequence of these (one per axis)
        Coefficients in the units ``fit_noise`` reports (see :class:`NoiseSpec`).
    fs_hz : float
        Sample rate in Hz.
    duration_s : float or str
        Record length in seconds, or a duration string (``"3h"``, ``"90min"``).
    rng : Generator, int or None
        Random source (fixed seed -> byte-identical output).
    units : str
        Unit of the output rate (deg/h, deg/s, rad/s, arcsec/s); coefficients stay in
        deg/h-based units.
    n_axes : int, optional
        Number of independent axes with the same coefficients (default 1, or the length
        of a sequence ``noise``).  Axes are named ``rate`` (one axis) or ``rate_x``,
        ``rate_y``, ``rate_z`` (``rate_1``... beyond three).
    arma : optional
        An ARMA model (anything :meth:`ArmaSpec.from_any` accepts, e.g. ``Selection.best``)
        whose output, in deg/h at ``fs_hz``, is added to every axis.
    temperature : TemperatureProfile, str, array_like or callable, optional
        Temperature in degC: a profile (or its string form, e.g. ``"warmup:20,30,20min"``),
        an array of one value per sample, or ``f(time_s) -> array``.  It is stored on the
        Run; with ``thermal_coefficients`` it also drives a drift.
    thermal_coefficients : mapping, optional
        Coefficients of D = a T dT + b T^2 + c T + d dT^2 + e dT + f (keys
        :data:`fogts.startup.thermal_model.THERMAL_TERMS`, deg/h per unit of the regressor); see
        :func:`thermal_drift`.
    flicker : {"markov", "kasdin"}
        Flicker (B) synthesis: a sum of Markov processes (exact, chunked) or Kasdin-Walter
        fractional integration (needs the whole record in memory); see the module notes.
    chunk_size : int
        Samples generated at a time (changes the output only by rounding: the random draws
        are the same).

    Returns
    -------
    Run
        ``rate`` of shape (n,) or (n, n_axes), ``time = arange(n) / fs_hz``, and
        ``temperature`` if one was given.  ``comments`` records the coefficients.

    Notes
    -----
    Synthesis and closed forms: seed 000 Table 1, IEEE Std 952-1997 Annex C (see the
    module docstring).  Each term has its own random stream, so terms are independent and
    toggling one leaves the others' realisations unchanged.

    Examples
    --------
    >>> run = simulate_gyro({"N": 0.01, "B": 0.02}, fs_hz=10, duration_s="10min", rng=1)
    >>> run.n, run.axes, run.units
    (6000, ('rate',), 'deg/h')
    """
    fs = check_positive("fs_hz", fs_hz)
    duration = parse_duration(duration_s, "duration_s")
    n = round(duration * fs)
    if n < 2:
        raise DataError(f"duration_s * fs_hz must give at least 2 samples, got {n} "
                        f"(duration {duration:g} s at {fs:g} Hz)")
    unit = parse_rate_unit(units)
    flicker = check_choice("flicker", flicker, FLICKER_METHODS)  # type: ignore[assignment]
    chunk = check_int("chunk_size", chunk_size, minimum=1)
    specs = _specs(noise, n_axes)
    for spec in specs:
        if spec.Omega_0 > 0 and spec.f_0 >= fs / 2:
            raise DataError(f"sinusoid frequency f_0={spec.f_0:g} Hz must be below the Nyquist "
                            f"frequency {fs / 2:g} Hz")
    arma_spec = ArmaSpec.from_any(arma) if arma is not None else None
    time = np.arange(n, dtype=np.float64) / fs
    temp = _temperature(temperature, time, duration)
    drift = None
    if thermal_coefficients is not None:
        if not isinstance(thermal_coefficients, Mapping):
            raise DataError(f"thermal_coefficients must be a mapping such as {{'T': 0.01}}, "
                            f"got {thermal_coefficients!r}")
        if temp is None:
            raise DataError("thermal_coefficients need a temperature profile (temperature=...)")
        drift = thermal_drift(temp, thermal_coefficients, fs_hz=fs)

    k = len(specs)
    root = as_rng(rng)
    axis_rngs = root.spawn(k)
    rate = np.empty((n, k) if k > 1 else n, dtype=np.float64)
    scale = 1.0 / to_deg_per_hour_factor(unit)
    for j, (spec, g) in enumerate(zip(specs, axis_rngs, strict=True)):
        streams = _axis_streams(spec, arma_spec, fs=fs, n=n, duration=duration,
                                flicker=flicker, rng=g)
        col = rate if k == 1 else rate[:, j]
        for i0 in range(0, n, chunk):
            i1 = min(n, i0 + chunk)
            acc = np.full(i1 - i0, spec.bias)
            if spec.R != 0.0:
                acc += spec.internal("R") * (time[i0:i1] + 0.5 / fs)
            for stream in streams:
                acc += stream.next(i0, i1 - i0)
            if drift is not None:
                acc += drift[i0:i1]
            col[i0:i1] = acc * scale if scale != 1.0 else acc
    axes = ("rate",) if k == 1 else tuple(
        f"rate_{c}" for c in ("x", "y", "z")[:k]) if k <= 3 else tuple(
        f"rate_{i + 1}" for i in range(k))
    columns = ("time", *axes) + (("temperature",) if temp is not None else ())
    comments = _describe(specs, arma_spec, fs=fs, n=n, flicker=flicker, units=unit)
    sampling = SamplingReport(1.0 / fs, 0, 1.0 / fs, (), 0.0, 0.0, True, False, 1.0 / fs,
                              "given")
    return Run(rate=rate, time=time, fs_hz=fs, units=unit, axes=axes, temperature=temp,
               columns=columns, source="<simulate_gyro>", sampling=sampling,
               comments=comments)


def _specs(noise: Any, n_axes: int | None) -> tuple[NoiseSpec, ...]:
    if isinstance(noise, Sequence) and not isinstance(noise, str | bytes):
        if len(noise) == 0:
            raise DataError("noise must hold at least one axis specification, got []")
        specs = tuple(NoiseSpec.from_any(s) for s in noise)
        if n_axes is not None and check_int("n_axes", n_axes, minimum=1) != len(specs):
            raise DataError(f"n_axes={n_axes} does not match the {len(specs)} noise "
                            "specifications given")
        return specs
    k = 1 if n_axes is None else check_int("n_axes", n_axes, minimum=1, maximum=64)
    return (NoiseSpec.from_any(noise),) * k


def _temperature(temperature: Any, time: FloatArray, duration: float) -> FloatArray | None:
    if temperature is None:
        return None
    if isinstance(temperature, str):
        temperature = TemperatureProfile.parse(temperature)
    if isinstance(temperature, TemperatureProfile):
        return temperature.evaluate(time, duration_s=duration)
    values = temperature(time) if callable(temperature) else temperature
    arr = np.asarray(values, dtype=np.float64)
    if arr.shape != time.shape:
        raise DataError(f"temperature must have one value per sample ({time.size}), got shape "
                        f"{arr.shape}")
    if not np.all(np.isfinite(arr)):
        raise DataError("temperature contains non-finite values")
    return np.ascontiguousarray(arr)


def _describe(specs: Iterable[NoiseSpec], arma: ArmaSpec | None, *, fs: float, n: int,
              flicker: str, units: str) -> tuple[str, ...]:
    lines = [f"simulated by fogts.simulate_gyro: {n} samples at {fs:g} Hz, rate in {units}, "
             f"flicker={flicker}"]
    for i, spec in enumerate(specs):
        terms = ", ".join(f"{name}={getattr(spec, name):g} {_UNITS[name]}"
                          for name in (f.name for f in fields(spec))
                          if getattr(spec, name) != 0.0) or "no noise"
        lines.append(f"axis {i}: {terms}")
    if arma is not None:
        lines.append(f"arma: ar={list(arma.ar)}, ma={list(arma.ma)}, sigma2={arma.sigma2:g}")
    return tuple(lines)
