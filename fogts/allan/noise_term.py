"""One fitted IEEE-952 term of a noise fit, :class:`NoiseTerm`, and the rule that says
whether its value is measured or only an upper limit (:data:`Z_MEASURED`).

Produced by :func:`fogts.allan.noise.fit_noise` and collected in
:class:`fogts.allan.noise_model.NoiseModel`; the term table (names, powers, units) is
:mod:`fogts.allan.terms`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

from fogts.allan.readout import MIN_EDF_FOR_MINIMUM

__all__ = ["Z_MEASURED", "NoiseTerm"]


#: A fitted term whose Wald z (value over its standard error, on sigma^2) is below this is
#: reported as an upper limit, not as a measured value: which terms are *measured* then
#: depends on the information in the data, not on how many taus the grid puts in a region.
Z_MEASURED = 2.0


@dataclass(frozen=True)
class NoiseTerm:
    """One fitted IEEE-952 term.

    Attributes
    ----------
    name : str
        ``"Q"``, ``"N"``, ``"B"``, ``"K"`` or ``"R"``.
    value, stderr, ci_low, ci_high : float
        The coefficient in ``unit`` (deg/h based, :data:`fogts.allan.terms.TERM_UNIT`), its
        standard error and its confidence interval at the model's ``confidence``.
        ``stderr`` is NaN at the zero bound (see ``at_bound``).  For Q and N the
        interval also covers the fit with band-limited bias instability
        (:mod:`fogts.allan.noise_band`), so it can reach further than ``z * stderr`` on
        one side.
    unit : str
    c_coeff, c_stderr : float
        ``C_n`` (rate in deg/h, tau in s; :mod:`fogts.allan.terms`) and its standard error.
    c_unit : str
    power : int
        ``n`` in ``C_n^2 tau^n``; the slope of the term's Allan-deviation line is ``n/2``.
    at_bound : bool
        True when the fit put the term at zero (the interval is then an upper limit).
    identifiable : bool
        False when fewer than
        :data:`~fogts.allan.noise_selection.MIN_COVERED_POINTS` data taus lie in the
        term's region (one suffices if its interval excludes 0).
    n_covered : int
        Number of data taus in the term's region (where it makes up at least
        :data:`~fogts.allan.noise_selection.COVERAGE_SHARE` of the fitted sigma^2).
    region_tau_s : tuple of float
        Tau range (s) of the term's region (share of sigma^2 >= COVERAGE_SHARE),
        searched over 1000x beyond the data on each side; ``(nan, nan)`` if nowhere.
    status : str
        ``"fitted"`` (non-zero in the final fit), ``"at_bound"`` (the non-negative fit put
        it at zero, or a GMWM fit has no component for it: ``short_gm``) or ``"dropped"`` (it was positive but neither significant at the
        model's ``significance`` nor visible at two taus, or visible at no tau, so backward
        elimination removed it and refitted); the last two have value 0 and ``at_bound``
        True.
    z_score : float
        Wald statistic ``a / se(a)`` of ``a = C_n^2``: in the final fit for a fitted term,
        when it was dropped for a dropped one, 0 at the bound.
    low_edf_taus : tuple of float
        The data taus where the term dominates the fitted sigma^2 (its line the largest, as
        in the curve read-out's ranges) when all of them have EDF below
        :data:`~fogts.allan.readout.MIN_EDF_FOR_MINIMUM`: the term is then only an upper
        limit (:func:`~fogts.allan.noise_selection.identify_terms`); empty otherwise.
    no_floor : str
        For B, the flicker floor: why the curve read-out finds no floor at the trusted taus
        (the curve still falling where they end), when B also dominates at fewer than two
        trusted points; B is then only an upper limit
        (:func:`~fogts.allan.noise_selection.floorless_flicker`).  Empty otherwise.
    """

    name: str
    value: float
    stderr: float
    ci_low: float
    ci_high: float
    unit: str
    c_coeff: float
    c_stderr: float
    c_unit: str
    power: int
    at_bound: bool
    identifiable: bool
    n_covered: int
    region_tau_s: tuple[float, float]
    status: str = "fitted"
    z_score: float = math.nan
    low_edf_taus: tuple[float, ...] = ()
    no_floor: str = ""
    short_gm: str = ""

    @property
    def is_limit(self) -> bool:
        """Whether the value is only an upper limit: fitted to zero, dropped, fitted with
        z below :data:`Z_MEASURED`, not identifiable (its unidentifiable-term warning says
        "treat its value as an upper limit", and the table's caption "too few taus ... to
        be measured"), dominant only at points with too few EDF (``low_edf_taus``), B on
        a curve without a floor (``no_floor``), or B of a GMWM fit whose Gauss-Markov
        components are all white noise at the data taus (``short_gm``)."""
        return (self.at_bound or not self.z_score >= Z_MEASURED or not self.identifiable
                or bool(self.low_edf_taus) or bool(self.no_floor) or bool(self.short_gm))

    @property
    def limit_reason(self) -> str:
        """Why the value is only an upper limit ("" when it is measured)."""
        why = ([f"dropped, z(C²) = {self.z_score:.2f}"] if self.status == "dropped"
               else [self.short_gm] if self.short_gm
               else ["fit at zero"] if self.at_bound
               else [] if self.z_score >= Z_MEASURED
               else [f"z(C²) = {self.z_score:.2f} < {Z_MEASURED:g}"])
        if not self.identifiable and not why:
            why.append(f"z(C²) = {self.z_score:.2f}, but not identifiable")
        if self.low_edf_taus:
            t = self.low_edf_taus
            where = f"{t[0]:.4g} s" if len(t) == 1 else f"{t[0]:.4g} .. {t[-1]:.4g} s"
            why.append(f"{self.name} dominates only at tau {where}, where the points have "
                       f"EDF < {MIN_EDF_FOR_MINIMUM:g}")
        if self.no_floor:
            why.append(self.no_floor)
        return "; ".join(why)

    @property
    def note(self) -> str:
        """Why the value is only an upper limit, or not identifiable; "" otherwise."""
        note = ("upper limit (fit at zero)" if self.status == "at_bound" else
                f"upper limit (dropped, z(C²) = {self.z_score:.2f})" if self.status == "dropped"
                else "")
        if not self.identifiable:
            note = (note + "; " if note else "") + "not identifiable"
        return note

    @property
    def slope(self) -> float:
        """Log-log slope of this term's Allan-deviation line (-1, -1/2, 0, 1/2, 1)."""
        return self.power / 2.0

    def to_dict(self) -> dict[str, Any]:
        return {"value": self.value, "stderr": self.stderr, "ci_low": self.ci_low,
                "ci_high": self.ci_high, "unit": self.unit, "c_coeff": self.c_coeff,
                "c_stderr": self.c_stderr, "c_unit": self.c_unit,
                "identifiable": self.identifiable, "at_bound": self.at_bound,
                "slope": self.slope, "n_covered": self.n_covered,
                "region_tau": list(self.region_tau_s), "status": self.status,
                "z": self.z_score, "measured": not self.is_limit,
                "limit_reason": self.limit_reason or None}
