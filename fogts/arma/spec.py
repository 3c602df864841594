"""The ARMA parameter type, :class:`ArmaSpec`, and its one coercion, :meth:`ArmaSpec.from_any`.

An ARMA(p, q) model in statsmodels' sign convention (DESIGN.md):

    x_t - const = phi_1 (x_{t-1} - const) + ... + phi_p (x_{t-p} - const)
                  + a_t + theta_1 a_{t-1} + ... + theta_q a_{t-q},   a_t ~ N(0, sigma2).

Every consumer of ARMA parameters (the simulator, the Kalman filter) takes "anything that
describes an ARMA model" and turns it into an :class:`ArmaSpec` with :meth:`ArmaSpec.from_any`.
The fitted types of :mod:`fogts.arma` are recognised by their attributes, so this module
imports none of them.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

import numpy as np

from fogts._validate import check_positive
from fogts.errors import DataError

__all__ = ["ArmaSpec"]

#: Keys of the plain mapping form ``{"ar": [...], "ma": [...], "sigma2": ..., "const": ...}``.
_PLAIN_KEYS = ("ar", "ma", "sigma2", "const")
#: Prefixes of statsmodels' lagged parameter names (``ar.L1``, ``ma.L2``...).
_AR_PREFIX, _MA_PREFIX = "ar.L", "ma.L"


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
            if key not in _PLAIN_KEYS:
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
        """Coerce any description of an ARMA model to an ArmaSpec.

        Accepted, in this order:

        * an ArmaSpec (returned as it is);
        * a string for :meth:`parse`;
        * a tuple ``(ar, ma, sigma2)`` or ``(ar, ma, sigma2, const)``;
        * a selection (anything with ``.best``, e.g. :class:`fogts.arma.select.Selection`):
          its best candidate;
        * a mapping ``{"ar", "ma", "sigma2"[, "const"]}``, a mapping of statsmodels
          parameter names (``ar.L1``, ``ma.L1``, ``sigma2``, ``const``), or either under a
          ``"params"`` key (a ``fogts select`` candidate's JSON);
        * a fitted model with ``.ar`` and ``.ma`` and ``.sigma2`` or ``.params["sigma2"]``
          (:class:`fogts.arma.fit.ArmaFit`, :class:`fogts.arma.select.Candidate`); the
          constant is ``params["const"]`` if present;
        * any other object whose ``.params`` maps statsmodels parameter names to values.

        Raises
        ------
        DataError
            The model is none of these, lacks sigma2, or its parameters are invalid.

        Examples
        --------
        >>> ArmaSpec.from_any({"ar.L2": 0.1, "sigma2": 1.0}).ar
        (0.0, 0.1)
        >>> ArmaSpec.from_any(([0.5], [], 2.0)).sigma2
        2.0
        """
        if isinstance(model, ArmaSpec):
            return model
        if isinstance(model, str):
            return cls.parse(model)
        if isinstance(model, tuple):
            return cls._from_tuple(model)
        if hasattr(model, "best") and not isinstance(model, Mapping):
            if model.best is None:
                raise DataError("the selection has no selected model (every candidate "
                                "failed); pick a candidate explicitly")
            model = model.best
        if isinstance(model, Mapping):
            return cls._from_mapping(model)
        if hasattr(model, "ar") and hasattr(model, "ma"):
            return cls._from_fitted(model)
        params = getattr(model, "params", None)
        if params is not None and hasattr(params, "keys"):
            return cls._from_param_names(dict(params))
        raise DataError(f"model must be an ArmaFit, a Candidate, a Selection (its best "
                        f"candidate is used), a mapping with ar/ma/sigma2 or statsmodels "
                        f"parameter names, an (ar, ma, sigma2) tuple or a string like "
                        f"'ar=0.9;sigma2=1'; got {type(model).__name__}")

    @classmethod
    def _from_tuple(cls, model: tuple[Any, ...]) -> ArmaSpec:
        if len(model) not in (3, 4):
            raise DataError(f"an ARMA tuple must be (ar, ma, sigma2) or (ar, ma, sigma2, "
                            f"const); got {len(model)} items")
        ar, ma, sigma2, *const = model
        return cls(ar=tuple(np.ravel(np.asarray(ar, dtype=np.float64))),
                   ma=tuple(np.ravel(np.asarray(ma, dtype=np.float64))),
                   sigma2=sigma2, const=const[0] if const else 0.0)

    @classmethod
    def _from_mapping(cls, model: Mapping[str, Any]) -> ArmaSpec:
        if "params" in model and isinstance(model["params"], Mapping):
            return cls._from_param_names(model["params"])
        if any(str(k).startswith((_AR_PREFIX, _MA_PREFIX)) for k in model):
            return cls._from_param_names(model)
        unknown = set(model) - set(_PLAIN_KEYS)
        if unknown:
            raise DataError(f"ARMA mapping keys must be ar, ma, sigma2, const or statsmodels "
                            f"names (ar.L1.., ma.L1.., sigma2, const); got "
                            f"{sorted(map(str, unknown))}")
        if "sigma2" not in model:
            raise DataError("an ARMA mapping needs 'sigma2' (the innovation variance)")
        return cls(ar=tuple(model.get("ar", ())), ma=tuple(model.get("ma", ())),
                   sigma2=model["sigma2"], const=model.get("const", 0.0))

    @classmethod
    def _from_fitted(cls, model: Any) -> ArmaSpec:
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

    @classmethod
    def _from_param_names(cls, params: Mapping[str, Any]) -> ArmaSpec:
        if "sigma2" not in params:
            raise DataError("ARMA params need 'sigma2' (the innovation variance)")
        return cls(ar=_lagged(params, _AR_PREFIX), ma=_lagged(params, _MA_PREFIX),
                   sigma2=_number("sigma2", params["sigma2"]),
                   const=_number("const", params.get("const", 0.0)))

    def to_dict(self) -> dict[str, Any]:
        return {"ar": list(self.ar), "ma": list(self.ma), "sigma2": self.sigma2,
                "const": self.const, "order": list(self.order)}


def _lagged(params: Mapping[str, Any], prefix: str) -> tuple[float, ...]:
    """Coefficients ``prefix1, prefix2, ...`` in lag order; a missing lag is 0."""
    by_lag: dict[int, float] = {}
    for key, value in params.items():
        if str(key).startswith(prefix):
            lag = str(key)[len(prefix):]
            if not lag.isdigit() or int(lag) < 1:
                raise DataError(f"ARMA parameter {key!r} is not a lag like {prefix}1")
            by_lag[int(lag)] = _number(str(key), value)
    return tuple(by_lag.get(lag, 0.0) for lag in range(1, max(by_lag, default=0) + 1))


def _number(name: str, value: Any) -> float:
    try:
        return float(value)
    except (TypeError, ValueError):
        raise DataError(f"ARMA parameter {name} must be a number, got {value!r}") from None
