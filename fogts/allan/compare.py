"""Allan analysis before and after a denoising filter.

Low-pass filtering a gyro signal (an IIR filter, a moving average) lowers the
angle-random-walk and quantization terms of its Allan analysis, while the long-tau terms
(bias instability, rate random walk) should not change.  This module runs the same
estimator and noise fit on both series and states which terms changed, by how much, and
whether the change exceeds the fits' combined uncertainty.

Filtering changes the noise seen at tau shorter than about ``1/cutoff_hz``: coefficients
from filtered data describe the filtered signal, not the sensor.
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass
from typing import Any

import numpy as np
import pandas as pd

from fogts.allan.api import allan_deviation
from fogts.allan.noise import NOISE_TERMS, NoiseModel, fit_noise
from fogts.allan.result import AllanResult
from fogts.allan.taus import Kind
from fogts.errors import DataError

__all__ = ["AllanComparison", "TermChange", "compare_allan"]

#: A change is called significant when it exceeds this many combined standard errors.
SIGNIFICANCE_Z = 2.0


@dataclass(frozen=True)
class TermChange:
    """One noise term before and after filtering.

    ``significant`` is True when ``|after - before| > 2 sqrt(se_before^2 + se_after^2)``
    (a term at the zero bound, with no standard error, counts as changed when the other
    side's value lies outside its interval).
    """

    term: str
    unit: str
    before: float
    before_stderr: float
    after: float
    after_stderr: float
    ratio: float
    change_pct: float
    significant: bool

    def to_dict(self) -> dict[str, Any]:
        """The fields by name, in field order."""
        return dataclasses.asdict(self)


@dataclass(frozen=True)
class AllanComparison:
    """Allan curves and noise fits of a series before and after filtering.

    Attributes
    ----------
    before, after : AllanResult
    noise_before, noise_after : NoiseModel
    changes : tuple of TermChange
    cutoff_hz : float or None
        The filter's -3 dB frequency; ``1/cutoff_hz`` marks the shortest tau the filter
        leaves alone.
    fit_min_tau_s : float
        Both fits use only taus at or above this (0 = every tau).
    labels : tuple of str
    """

    before: AllanResult
    after: AllanResult
    noise_before: NoiseModel
    noise_after: NoiseModel
    changes: tuple[TermChange, ...]
    cutoff_hz: float | None
    fit_min_tau_s: float = 0.0
    labels: tuple[str, str] = ("before", "after")

    @property
    def caveat(self) -> str:
        edge = f" (about {1.0 / self.cutoff_hz:.3g} s here)" if self.cutoff_hz else ""
        return ("filtering changes the noise seen at tau shorter than about 1/cutoff" + edge
                + "; coefficients from filtered data describe the filtered signal, not the "
                "sensor")

    def dev_ratio(self) -> np.ndarray:
        """after/before deviation at each common tau."""
        return np.asarray(self.after.dev / self.before.dev, dtype=np.float64)

    def to_frame(self) -> pd.DataFrame:
        return pd.DataFrame([c.to_dict() for c in self.changes]).set_index("term")

    def to_dict(self) -> dict[str, Any]:
        return {"labels": list(self.labels), "cutoff_hz": self.cutoff_hz,
                "fit_min_tau_s": self.fit_min_tau_s,
                "terms": {c.term: c.to_dict() for c in self.changes},
                "curves": {self.labels[0]: self.before.to_dict(),
                           self.labels[1]: self.after.to_dict()},
                "noise": {self.labels[0]: self.noise_before.to_dict(),
                          self.labels[1]: self.noise_after.to_dict()},
                "caveat": self.caveat}

    def summary(self) -> str:
        a, b = self.labels
        w = max(22, len(a) + 2, len(b) + 2)  # a long label must not run into the next
        lines = [f"{'term':<5}{'unit':<12}{a:>{w}}{b:>{w}}{'change':>10}  verdict"]
        for c in self.changes:
            before = _cell(self.noise_before, c.term, c.before, c.before_stderr)
            after = _cell(self.noise_after, c.term, c.after, c.after_stderr)
            measured = (_measured(self.noise_before, c.term)
                        or _measured(self.noise_after, c.term))
            change = f"{c.change_pct:>+9.1f}%" if measured else f"{'–':>10}"
            lines.append(f"{c.term:<5}{c.unit:<12}{before:>{w}}{after:>{w}}{change}  "
                         f"{self._verdict(c)}")
        if self.fit_min_tau_s > 0:
            lines.append(f"both fits use tau >= {self.fit_min_tau_s:.3g} s only")
        ratio = self.dev_ratio()
        lines.append(f"deviation after/before: {ratio[0]:.3g} at tau = "
                     f"{self.before.tau_s[0]:.3g} s, {ratio[-1]:.4g} at tau = "
                     f"{self.before.tau_s[-1]:.3g} s")
        lines.append(f"note: {self.caveat}")
        return "\n".join(lines)

    def _verdict(self, c: TermChange) -> str:
        """"changed" / "unchanged (within 2 sigma)"; a term neither fit measures (both
        upper limits) is said to be so: no change can be read from two bounds."""
        if not (_measured(self.noise_before, c.term) or _measured(self.noise_after, c.term)):
            return "not measured (an upper limit before and after)"
        return "changed" if c.significant else "unchanged (within 2 sigma)"


def _measured(model: NoiseModel, term: str) -> bool:
    """Whether ``model`` measures ``term`` (not only an upper limit, not left out)."""
    try:
        return not model[term].is_limit
    except KeyError:
        return False


def _cell(model: NoiseModel, term: str, value: float, stderr: float) -> str:
    """A term's value as the allan summary writes it: ``value ± stderr`` when ``model``
    measures it, ``< x`` (its one-sided 95 % upper limit) when it is only a limit, so a
    bound is not printed as a measurement beside the verdict "not measured"."""
    if term in model.names and model[term].is_limit:
        return f"< {model.upper_limit(term):.3g}"
    return _pm(value, stderr)


def _pm(value: float, stderr: float) -> str:
    if not math.isfinite(stderr):
        return f"{value:.4g}"
    return f"{value:.4g} ± {stderr:.2g}"


def compare_allan(
    before: Any,
    after: Any,
    *,
    fs_hz: float,
    units: str | None = None,
    kind: Kind = "oadev",
    taus: Any = "octave",
    terms: tuple[str, ...] = NOISE_TERMS,
    cutoff_hz: float | None = None,
    fit_min_tau_s: float | None = None,
    labels: tuple[str, str] = ("before", "after"),
) -> AllanComparison:
    """Allan deviation and IEEE-952 fit of two versions of one series, side by side.

    Parameters
    ----------
    before, after : array_like or Series
        The raw and the filtered rate (same length and sample rate).
    fs_hz : float
    units : str, optional
        Rate unit (default deg/h).
    kind, taus : see :func:`fogts.allan.allan_deviation`.
    terms : tuple of str
        Terms to fit (see :func:`fogts.allan.noise.fit_noise`).
    cutoff_hz : float, optional
        The filter's cutoff, for the caveat and the plot.
    fit_min_tau_s : float, optional
        Fit both curves only at tau >= this.  Default: ``3 / cutoff_hz`` when a cutoff is
        given, else every tau.  Below about ``1/cutoff`` a low-passed record's deviation
        *rises* with tau (the integrated angle is smooth there), which no IEEE-952 term
        describes; a fit that includes those taus explains them with spurious K or R.
    labels : (str, str)

    Examples
    --------
    >>> import numpy as np, warnings
    >>> from fogts.preprocess.filters import lowpass
    >>> rng = np.random.default_rng(1)
    >>> x = rng.normal(size=100_000) + np.cumsum(rng.normal(scale=1e-3, size=100_000))
    >>> with warnings.catch_warnings():
    ...     warnings.simplefilter("ignore")
    ...     cmp = compare_allan(x, lowpass(x, fs_hz=100, cutoff_hz=1).filtered, fs_hz=100,
    ...                         terms=("N", "K"), cutoff_hz=1)
    >>> bool(cmp.dev_ratio()[0] < 0.05)  # tau = 0.01 s: the filter removed most noise
    True
    >>> [c.term for c in cmp.changes if c.significant]  # fitted above 3/cutoff: no change
    []
    """
    a = np.asarray(before, dtype=np.float64)
    b = np.asarray(after, dtype=np.float64)
    if a.shape != b.shape or a.ndim != 1:
        raise DataError(f"before and after must be 1-D series of equal length, got shapes "
                        f"{a.shape} and {b.shape}")
    curve_a = _one(allan_deviation(a, fs_hz=fs_hz, kind=kind, taus=taus, units=units))
    curve_b = _one(allan_deviation(b, fs_hz=fs_hz, kind=kind, taus=taus, units=units))
    if fit_min_tau_s is None:
        fit_min_tau_s = 3.0 / cutoff_hz if cutoff_hz else 0.0
    noise_a = fit_noise(_taus_from(curve_a, fit_min_tau_s), terms=terms)
    noise_b = fit_noise(_taus_from(curve_b, fit_min_tau_s), terms=terms)
    changes = tuple(_change(noise_a, noise_b, name) for name in noise_a.names)
    return AllanComparison(curve_a, curve_b, noise_a, noise_b, changes, cutoff_hz,
                           float(fit_min_tau_s), labels)


def _taus_from(curve: AllanResult, min_tau_s: float) -> AllanResult:
    """The curve restricted to tau >= ``min_tau_s`` (at least 3 points kept)."""
    keep = curve.tau_s >= min_tau_s
    if keep.sum() < 3:
        raise DataError(f"fit_min_tau_s={min_tau_s:.4g} s leaves {int(keep.sum())} taus "
                        f"(the curve ends at {curve.tau_s[-1]:.4g} s); a fit needs 3: use a "
                        "higher cutoff or a longer record")
    methods = tuple(np.asarray(curve.alpha_method, dtype=object)[keep]) \
        if curve.alpha_method else ()
    return dataclasses.replace(
        curve, tau_s=curve.tau_s[keep], m=curve.m[keep], n=curve.n[keep],
        dev=curve.dev[keep], ci_low=curve.ci_low[keep], ci_high=curve.ci_high[keep],
        edf=curve.edf[keep], alpha=curve.alpha[keep], alpha_method=methods)


def _one(result: Any) -> AllanResult:
    if not isinstance(result, AllanResult):  # pragma: no cover - 1-D input gives one curve
        raise DataError("expected a single-axis series")
    return result


def _change(before: NoiseModel, after: NoiseModel, name: str) -> TermChange:
    tb, ta = before[name], after[name]
    ratio = ta.value / tb.value if tb.value > 0 else math.inf if ta.value > 0 else 1.0
    change = 100.0 * (ratio - 1.0) if math.isfinite(ratio) else math.inf
    se = math.hypot(tb.stderr, ta.stderr) if math.isfinite(tb.stderr) and math.isfinite(
        ta.stderr) else math.nan
    if math.isfinite(se):
        significant = abs(ta.value - tb.value) > SIGNIFICANCE_Z * se
    else:  # a term at its zero bound: compare against the other's interval
        significant = not (tb.ci_low <= ta.value <= tb.ci_high) or not (
            ta.ci_low <= tb.value <= ta.ci_high)
    return TermChange(name, tb.unit, tb.value, tb.stderr, ta.value, ta.stderr, ratio, change,
                      bool(significant))
