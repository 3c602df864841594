"""The classic graphical read-offs of N, K and B from an Allan curve (comparison only).

IEEE Std 952-1997 Annex C and MATLAB's ``allanvar`` example: a line of the term's slope is
drawn through the curve point whose local log-log slope is closest to it; N is that -1/2
line at tau = 1 s, K the +1/2 line at tau = 3 s, and B the floor (the minimum) divided by
the estimator's flicker plateau factor (:data:`~fogts.allan.terms.FLICKER_PLATEAU`).

A read-off is only given where the curve supports it (:func:`unsupported_reason`): N or K
through a segment of about its slope whose slope the points' EDF pin down well enough to
exclude the neighbouring power laws, B only where the curve has a floor
(:func:`fogts.allan.readout.read_curve`).  A read-off that lies outside the fit's interval
or above its upper limit is flagged in words with both numbers (:func:`fit_check`).

The read-offs are read from the whole curve, the one the points table and the curve
read-out show, also when the noise terms are fitted over part of it (``tau_range``,
``--fit-tau-min``/``--fit-tau-max``): a read-off read outside the fit's taus says so
(:attr:`SlopeReadoff.outside`), so that it can be reconciled with the table.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping
from dataclasses import dataclass
from typing import Any

import numpy as np

from fogts._typing import FloatArray
from fogts.allan.confidence import chi2_interval
from fogts.allan.readout import MIN_EDF_FOR_MINIMUM, read_curve
from fogts.allan.terms import B_PLATEAU, TERM_SLOPE, TERMS, flicker_plateau, from_seconds, term_rows
from fogts.units import term_in_units, term_unit

__all__ = ["FIT_CHECKED", "READOFF_SLOPE_TOLERANCE", "FitBound", "SlopeReadoff", "fit_check",
           "readoff_of", "readoff_supported", "slope_readoff", "unsupported_reason"]

#: A read-off line of a term's slope reads that term only through a segment whose local
#: slope is nearer to it than to the neighbouring power laws', which lie 1/2 away
#: (IEEE Std 952-1997 Annex C, Table C.1): within 1/4.
READOFF_SLOPE_TOLERANCE = 0.25
#: The read-offs checked against the fit's bounds (:func:`fit_check`): B and K, which the
#: graphical method reads where the curve is weakest.  N's -1/2 line through a point where
#: the other terms add is biased high by construction, and its fit interval is narrow.
FIT_CHECKED = ("B", "K")
#: The neighbouring power laws' slopes lie this far from a term's slope (Table C.1).
_NEIGHBOUR_GAP = 0.5


@dataclass(frozen=True)
class FitBound:
    """The fit's range of one term, in the term table's degree units, to compare a
    read-off with: its interval (``low``, ``high``) at ``label``'s level, or, for a term the
    fit reports only as a limit, ``high`` is the 95 % upper limit."""

    low: float
    high: float
    label: str
    is_limit: bool


@dataclass(frozen=True)
class SlopeReadoff:
    """The classic graphical read-offs (comparison only; NOT the fitted answer).

    Attributes
    ----------
    N, K, B : float
        In deg/sqrt(h), deg/h^1.5 and deg/h (computed even where not supported; see
        :func:`readoff_supported`).
    tau_N_s, tau_K_s, tau_B_s : float
        The curve point each value was read from.
    slope_N, slope_K : float
        The local slope found there (how well the curve shows the -1/2 or +1/2 line).
    points : tuple
        The read-off points in the curve's own units, for plotting: (name, tau_s, dev).
    quantity : str
        "rate" (units of TERMS) or "accel" (units of ACCEL_TERMS).
    kind : str
        The estimator; ``plateau`` is its flicker plateau factor.
    plateau : float
    notes : tuple of (str, str)
        Term name and why its read-off is not supported by the points' EDF (N, K) or by
        the curve's shape (B: no floor).
    fit_tau_s : (float, float) or None
        The first and last tau of the noise fit, when it was fitted over part of the curve
        (the read-offs are still read from the whole curve, the one the points table shows).
    outside : tuple of str
        The read-offs read outside ``fit_tau_s``: N or K through a segment that leaves it,
        B at a minimum beyond it.
    """

    N: float
    K: float
    B: float
    tau_N_s: float
    tau_K_s: float
    tau_B_s: float
    slope_N: float
    slope_K: float
    points: tuple[tuple[str, float, float], ...] = ()
    quantity: str = "rate"
    kind: str = "oadev"
    plateau: float = B_PLATEAU
    notes: tuple[tuple[str, str], ...] = ()
    fit_tau_s: tuple[float, float] | None = None
    outside: tuple[str, ...] = ()

    def _unit(self, name: str) -> str:
        return term_rows(self.quantity)[name].unit

    def outside_text(self, name: str) -> str:
        """Where the read-off of ``name`` was read, when outside the fit's taus ("" when
        inside or without a fit range)."""
        if name not in self.outside or self.fit_tau_s is None:
            return ""
        lo, hi = self.fit_tau_s
        tau = float(getattr(self, f"tau_{name}_s"))
        where = f"through tau = {tau:.4g} s" if name in ("N", "K") else f"at tau = {tau:.4g} s"
        return f"read {where}, outside the fit range {lo:.4g} .. {hi:.4g} s"

    def to_dict(self, fit: Mapping[str, FitBound] | None = None) -> dict[str, Any]:
        """JSON-safe read-offs; each term also says whether it is ``supported``, why not
        (``note``) and, given the fit's bounds, whether it lies outside them
        (``fit_check``)."""
        def status(name: str) -> dict[str, Any]:
            why = unsupported_reason(self, name)
            check = (fit_check(self, name, fit[name])
                     if fit and name in fit and name in FIT_CHECKED and not why else "")
            return {"supported": not why, "note": why or None, "fit_check": check or None,
                    "outside_fit_range": name in self.outside}

        return {"method": "slope read-off (IEEE 952 Annex C / MATLAB allanvar example); "
                          "comparison only, not the fit",
                "N": {"value": self.N, "unit": self._unit("N"), "tau": self.tau_N_s,
                      "local_slope": self.slope_N, "read_at_tau": TERMS["N"].readoff_tau_s,
                      **status("N")},
                "K": {"value": self.K, "unit": self._unit("K"), "tau": self.tau_K_s,
                      "local_slope": self.slope_K, "read_at_tau": TERMS["K"].readoff_tau_s,
                      **status("K")},
                "B": {"value": self.B if math.isfinite(self.B) else None,
                      "unit": self._unit("B"), "tau": self.tau_B_s, "kind": self.kind,
                      "plateau_factor": self.plateau if math.isfinite(self.plateau) else None,
                      **status("B")}}

    def describe(self, number: Callable[[float], str] = lambda v: f"{v:.4g}",
                 units: str = "deg", fit: Mapping[str, FitBound] | None = None) -> str:
        """The read-offs as one sentence (``number`` formats the values) in ``units``
        (``"deg"``: the term table's engineering units; ``"si"``: :mod:`fogts.units`).

        A term is given as "not read" with the reason when the curve does not support it
        (:func:`unsupported_reason`); given the fit's bounds (``fit``), a read-off outside
        them says so with both numbers (:func:`fit_check`); one read outside the fit's tau
        range says where (:meth:`outside_text`)."""
        def term(name: str) -> str:
            value = term_in_units(name, getattr(self, name), units, self.quantity)
            return f"{name} = {number(value)} {term_unit(name, units, self.quantity)}"

        def read(name: str, how: str) -> str:
            why = unsupported_reason(self, name)
            if why:
                return f"{name} not read ({why})"
            check = (fit_check(self, name, fit[name], number, units)
                     if fit and name in fit and name in FIT_CHECKED else "")
            said = [how, *(text for text in (self.outside_text(name), check) if text)]
            return f"{term(name)} ({'; '.join(said)})"

        at_n, at_k = TERMS["N"].readoff_tau_s, TERMS["K"].readoff_tau_s
        return (f"slope read-offs (comparison only, not the fit): "
                f"{read('N', f'-1/2 line at tau = {at_n:g} s')}, "
                f"{read('K', f'+1/2 line at tau = {at_k:g} s')}, "
                f"{read('B', f'minimum / {self.plateau:.4g}')}")


def unsupported_reason(readoff: SlopeReadoff, name: str) -> str:
    """Why the read-off of ``name`` is not supported by the curve ("" when it is).

    N or K: no segment within :data:`READOFF_SLOPE_TOLERANCE` of its slope, or the
    segment's points' EDF too low (:func:`slope_readoff`); B: no floor, or no flicker
    plateau factor for the estimator."""
    if name in ("N", "K"):
        slope = float(getattr(readoff, f"slope_{name}"))
        sign = "-" if TERM_SLOPE[name] < 0 else "+"
        if not (math.isfinite(slope) and abs(slope - TERM_SLOPE[name]) <= READOFF_SLOPE_TOLERANCE):
            tau = float(getattr(readoff, f"tau_{name}_s"))
            return (f"no segment of slope {sign}1/2: the closest, {slope:+.2f}, starts at "
                    f"tau = {tau:.4g} s")
    elif name == "B" and not math.isfinite(readoff.plateau):
        return f"no flicker-FM plateau factor is established for {readoff.kind}"
    return dict(readoff.notes).get(name, "")


def readoff_supported(readoff: SlopeReadoff, name: str) -> bool:
    """Whether the read-off of ``name`` is supported (:func:`unsupported_reason` is empty).

    Examples
    --------
    >>> tau = 2.0 ** np.arange(-4, 8)
    >>> r = slope_readoff(tau, 0.6 / np.sqrt(tau), 1.0)
    >>> readoff_supported(r, "N"), readoff_supported(r, "K"), readoff_supported(r, "B")
    (True, False, False)
    """
    return not unsupported_reason(readoff, name)


def fit_check(readoff: SlopeReadoff, name: str, bound: FitBound,
              number: Callable[[float], str] = lambda v: f"{v:.4g}", units: str = "deg") -> str:
    """A sentence when the read-off of ``name`` lies outside the fit's ``bound`` (above a
    limit term's 95 % upper limit, or outside a measured term's interval), with both
    numbers in ``units``; "" when it lies inside.

    Examples
    --------
    >>> r = SlopeReadoff(0.1, 0.2, 0.38, 1.0, 3.0, 655.0, -0.5, 0.5)
    >>> fit_check(r, "B", FitBound(0.0, 0.129, "95 % upper limit", True))
    "it lies above the fit's 95 % upper limit B < 0.129 deg/h: the read-off and the fit disagree"
    """
    value = float(getattr(readoff, name))
    if not math.isfinite(value) or not (value > bound.high or (not bound.is_limit
                                                               and value < bound.low)):
        return ""

    def show(v: float) -> str:
        return number(term_in_units(name, v, units, readoff.quantity))

    unit = term_unit(name, units, readoff.quantity)
    where = (f"above the fit's {bound.label} {name} < {show(bound.high)} {unit}" if bound.is_limit
             else f"outside the fit's {bound.label} {show(bound.low)} .. {show(bound.high)} {unit}")
    return f"it lies {where}: the read-off and the fit disagree"


def _segment_note(name: str, tau: FloatArray, slopes: FloatArray, edf: FloatArray | None,
                  i: int) -> str:
    """Why the segment ``i`` (``tau[i] .. tau[i+1]``) does not pin the term's slope down,
    from its points' EDF ("" when it does).

    The segment needs both points at :data:`~fogts.allan.readout.MIN_EDF_FOR_MINIMUM` or
    more EDF (the minimum's rule), and its slope's standard error must leave the slope
    nearer its term's than the neighbouring power laws' (1/2 away) by one standard error.
    The standard error: ``var(ln sigma) = 1/(2 edf)`` per point (chi-squared with ``edf``
    degrees of freedom, NIST SP1065 sec. 5.3), the two points taken as independent (their
    positive correlation would make it smaller: the test is conservative)."""
    if edf is None or not np.isfinite(slopes[i]):
        return ""
    e1, e2 = float(edf[i]), float(edf[i + 1])
    sign = "-" if TERM_SLOPE[name] < 0 else "+"
    segment = f"the {sign}1/2 segment {tau[i]:.4g} .. {tau[i + 1]:.4g} s"
    if not (min(e1, e2) >= MIN_EDF_FOR_MINIMUM):
        return (f"{segment} rests on points with EDF {e1:.3g} and {e2:.3g}, fewer than the "
                f"{MIN_EDF_FOR_MINIMUM:g} a trusted point needs")
    se = math.sqrt(0.5 / e1 + 0.5 / e2) / math.log(tau[i + 1] / tau[i])
    target = TERM_SLOPE[name]
    if abs(slopes[i] - target) + se >= _NEIGHBOUR_GAP:
        return (f"{segment} has slope {slopes[i]:+.2f} ± {se:.2f} (from its points' EDF), "
                f"which does not exclude the neighbouring slopes "
                f"{target - _NEIGHBOUR_GAP:+g} and {target + _NEIGHBOUR_GAP:+g}")
    return ""


def readoff_of(curve: Any, factor: float, quantity: str,
               fit_tau_s: tuple[float, float] | None = None) -> SlopeReadoff:
    """:func:`slope_readoff` of a noise fit's curve (:class:`~fogts.allan.noise_input.
    FitCurve`): its EDF, estimator and, when it has them, the result's own intervals, so
    that the B read-off's floor is the curve read-out's; ``fit_tau_s``: see
    :func:`slope_readoff`."""
    ci = ((curve.ci_low, curve.ci_high)
          if curve.ci_low is not None and curve.ci_high is not None else None)
    return slope_readoff(curve.tau, curve.dev, factor, curve.edf, quantity, kind=curve.kind,
                         ci=ci, fit_tau_s=fit_tau_s)


# Over 80 lines by its numpydoc docstring; the reading is line() and read_curve's floor.
def slope_readoff(tau: FloatArray, dev: FloatArray, factor: float,
                  edf: FloatArray | None = None, quantity: str = "rate", *,
                  kind: str = "oadev",
                  ci: tuple[FloatArray, FloatArray] | None = None,
                  fit_tau_s: tuple[float, float] | None = None) -> SlopeReadoff:
    """The IEEE 952 Annex C / MATLAB ``allanvar`` read-offs of N, K and B.

    Lines of slope -1/2 (+1/2) through the point whose local log-log slope is closest to it,
    read at tau = 1 s (3 s); B = minimum / the estimator's flicker plateau factor.  The
    minimum is :func:`~fogts.allan.readout.read_curve`'s: the lowest point among those with
    at least ``MIN_EDF_FOR_MINIMUM`` degrees of freedom, with the intervals ``ci`` (else
    68.3 % chi-squared intervals from ``edf``); B is not read where the curve has no floor
    there.  N and K are not read
    where the segment's points' EDF do not pin its slope down (:func:`_segment_note`).

    Parameters
    ----------
    tau, dev : ndarray
        The curve (increasing tau, positive deviations).
    factor : float
        Multiplies ``dev`` to give deg/h (m/s^2 for ``quantity="accel"``).
    edf : ndarray, optional
        Equivalent degrees of freedom per point.
    quantity : {"rate", "accel"}
        Gyro (:data:`~fogts.allan.terms.TERMS`) or accelerometer
        (:data:`~fogts.allan.terms.ACCEL_TERMS`) units.
    kind : str
        The estimator of the curve (its flicker plateau factor).
    ci : tuple of ndarray, optional
        The points' confidence bounds ``(low, high)``, as the curve read-out shows them.
    fit_tau_s : (float, float), optional
        The first and last tau of a noise fit over part of the curve: each read-off read
        outside them is listed in :attr:`SlopeReadoff.outside`.

    Returns
    -------
    SlopeReadoff

    Examples
    --------
    >>> tau = 2.0 ** np.arange(-4, 8)
    >>> r = slope_readoff(tau, 0.6 / np.sqrt(tau), 1.0)
    >>> round(r.N, 6), r.slope_N
    (0.01, -0.5)
    """
    logt, logd = np.log10(tau), np.log10(dev)
    slopes = np.diff(logd) / np.diff(logt) if tau.size >= 2 else np.array([math.nan])
    notes: list[tuple[str, str]] = []
    outside: list[str] = []

    def beyond(*taus: float) -> bool:
        if fit_tau_s is None:
            return False
        lo, hi = fit_tau_s
        return any(t < lo * (1 - 1e-9) or t > hi * (1 + 1e-9) for t in taus)

    def line(name: str) -> tuple[float, float, float]:
        at, target = TERMS[name].readoff_tau_s, TERM_SLOPE[name]
        if not np.any(np.isfinite(slopes)):
            return math.nan, math.nan, math.nan
        i = int(np.nanargmin(np.abs(slopes - target)))
        note = _segment_note(name, tau, slopes, edf, i)
        if note:
            notes.append((name, note))
        if beyond(float(tau[i]), float(tau[i + 1])):
            outside.append(name)
        b = logd[i] - target * logt[i]
        return float(10 ** (target * math.log10(at) + b)), float(tau[i]), float(slopes[i])

    n_dev, tau_n, slope_n = line("N")
    k_dev, tau_k, slope_k = line("K")
    plateau = flicker_plateau(kind)
    if tau.size >= 2:
        lo, hi = ci if ci is not None else (None, None)
        if ci is None and edf is not None:
            e = np.where(np.isfinite(edf) & (edf > 0), edf, np.nan)
            lo, hi = chi2_interval(dev, e, 0.683)
        floor = read_curve(tau, dev, lo, hi, edf=edf, kind=kind)
        b_dev, tau_b = floor.dev_min, floor.tau_min_s
        if floor.floor_note:
            notes.append(("B", floor.floor_note))
        if beyond(tau_b):
            outside.append("B")
    else:
        b_dev, tau_b = float(dev[0]), float(tau[0])
        notes.append(("B", "a single point shows no floor"))
    return SlopeReadoff(
        N=from_seconds("N", n_dev * factor, quantity),
        K=from_seconds("K", k_dev * factor, quantity),
        B=from_seconds("B", b_dev * factor / plateau, quantity), tau_N_s=tau_n, tau_K_s=tau_k,
        tau_B_s=tau_b, slope_N=slope_n, slope_K=slope_k,
        points=(("N", TERMS["N"].readoff_tau_s, n_dev), ("K", TERMS["K"].readoff_tau_s, k_dev),
                ("B", tau_b, b_dev)), quantity=quantity, kind=kind, plateau=plateau,
        notes=tuple(notes), fit_tau_s=fit_tau_s, outside=tuple(outside))
