"""A simpler candidate the data cannot tell from the selected one: it fails the residual
checks only by a margin within their sampling noise, the selected model's extra
coefficients are not significant and the criterion hardly differs.

The ranking puts every white candidate before every candidate that is not white, and a
whiteness check is a test at a fixed level (Ljung-Box p >= 0.05, |rho| <= 1.96/sqrt(n);
:mod:`fogts.arma.whiteness`).  Passed or failed by a hair, that check decides the rank on
its own.  :func:`equivalent_simpler` finds the case where nothing else separates the two:

* every check the simpler candidate fails is failed *marginally*, and the selected model
  passes it marginally too: both Ljung-Box p values in [``MARGIN_P_LOW``,
  ``MARGIN_P_HIGH``] = [0.025, 0.10] (a factor of two either side of 0.05), both |rho| within
  ``MARGIN_RHO`` = 10 % of the band 1.96/sqrt(n).  A p value is itself a statistic with a
  large sampling spread; only its order of magnitude is reproducible (Boos & Stefanski 2011),
  and a residual autocorrelation has standard error ~1/sqrt(n), so 10 % of the band is
  ~0.2 standard errors;
* the selected model nests the simpler one (``p`` and ``q`` no larger) and each of its
  extra AR/MA coefficients has |t| < 1.96 (:func:`fogts.arma.redundancy.insignificant_terms`);
* the simpler one is fewer than ``CLOSE_CALL`` = 2 criterion units worse (Burnham &
  Anderson 2002, sec. 2.6: Delta AIC <= 2 means substantial support for both).

Decision: the **selection rule is unchanged** and the verdict says that the data cannot
decide.  Box, Jenkins & Reinsel (1994, sec. 1.3.3, the principle of parsimony) prefer the
simpler of two adequate models, but whether the simpler model is adequate is exactly what
the marginal check cannot tell; swapping the rank on a second, data-dependent threshold
would move the knife-edge from 0.05 to the edge of the margin band rather than remove it,
and would make the rank depend on two thresholds instead of one.  So the ranking stays the
pre-declared rule (white first, then the criterion), and the verdict names the simpler
candidate, with the numbers, as an equally good choice.

References
----------
D. D. Boos and L. A. Stefanski, "P-value precision and reproducibility", The American
Statistician 65 (2011) 213-221.
K. P. Burnham and D. R. Anderson, *Model Selection and Multimodel Inference*, 2nd ed.,
Springer 2002, sec. 2.6.
G. E. P. Box, G. M. Jenkins and G. C. Reinsel, *Time Series Analysis: Forecasting and
Control*, 3rd ed., Prentice Hall 1994, sec. 1.3.3.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import asdict, dataclass
from typing import Any

from fogts.arma.candidate import Candidate
from fogts.arma.whiteness import BAND_Z, LB_ALPHA

__all__ = ["CLOSE_CALL", "MARGIN_P_HIGH", "MARGIN_P_LOW", "MARGIN_RHO", "EquivalentSimpler",
           "MarginCheck", "equivalent_simpler"]

#: A simpler candidate within this many criterion units of the selected one is named in
#: the verdict (Burnham & Anderson, *Model Selection and Multimodel Inference*, 2nd ed.,
#: sec. 2.6: Delta AIC <= 2 means substantial support).
CLOSE_CALL = 2.0
#: Ljung-Box p values in [MARGIN_P_LOW, MARGIN_P_HIGH] pass or fail the 0.05 test only
#: marginally (a factor of two either side of it).
MARGIN_P_LOW = LB_ALPHA / 2
MARGIN_P_HIGH = 2 * LB_ALPHA
#: |rho| within this fraction of the band 1.96/sqrt(n) passes or fails it only marginally.
MARGIN_RHO = 0.10


@dataclass(frozen=True)
class MarginCheck:
    """One residual check that the simpler candidate fails and the selected one passes,
    both by a margin within sampling noise: ``rho_a2``, ``rho_ax3`` (values) or
    ``ljung_box(h)`` (p values)."""

    check: str
    selected: float
    simpler: float

    def to_dict(self) -> dict[str, Any]:
        return asdict(self)


@dataclass(frozen=True)
class EquivalentSimpler:
    """A simpler candidate the data cannot tell from the selected one (module docstring).

    Attributes
    ----------
    model, criterion : str
        The simpler candidate, and the criterion that ranks the candidates.
    delta : float
        Its criterion minus the selected model's (< ``CLOSE_CALL``).
    checks : tuple of MarginCheck
        The checks it fails marginally (the selected model passes them marginally).
    extra : tuple of (str, float)
        The selected model's extra coefficients and their t values (each |t| < 1.96).
    """

    model: str
    criterion: str
    delta: float
    checks: tuple[MarginCheck, ...]
    extra: tuple[tuple[str, float], ...]

    def to_dict(self) -> dict[str, Any]:
        return {"model": self.model, "criterion": self.criterion, "delta": self.delta,
                "checks": [c.to_dict() for c in self.checks],
                "extra_params": {name: {"t": t} for name, t in self.extra}}

    def sentence(self, selected: str) -> str:
        """The verdict's sentence, with the numbers."""
        fails = "; ".join(_check_words(c, selected) for c in self.checks)
        extra = ", ".join(f"{name} (t = {t:.2f})" for name, t in self.extra)
        verb = "is" if len(self.extra) == 1 else "are"
        return (f" But {self.model} fails the residual checks only marginally ({fails}), "
                f"{extra} {verb} not "
                f"significant and {self.model} is {self.delta:+.1f} "
                f"{self.criterion.upper()} units: the two describe the drift equally well "
                f"and the data cannot decide between them ({selected} ranks first only "
                f"because it passes the check by that margin); the simpler {self.model} is "
                "as good a choice.")


def _distinct(a: float, b: float, digits: int, spec: str = "") -> tuple[str, str]:
    """``a`` and ``b`` to ``digits`` significant digits, more (up to 6) if they would print
    the same."""
    for d in range(digits, 7):
        sa, sb = f"{a:{spec}.{d}g}", f"{b:{spec}.{d}g}"
        if sa != sb:
            break
    return sa, sb


def _check_words(c: MarginCheck, selected: str) -> str:
    if c.check.startswith("ljung_box"):
        lag = c.check[len("ljung_box"):]
        simpler, sel = _distinct(c.simpler, c.selected, 3)
        return f"Ljung-Box p{lag} = {simpler} against {sel} for {selected}"
    simpler, sel = _distinct(c.simpler, c.selected, 3, "+")
    return f"{c.check} = {simpler} against {sel} for {selected}"


def _marginal_checks(sel: Candidate, c: Candidate) -> tuple[MarginCheck, ...] | None:
    """The checks ``c`` fails, each failed and passed by ``sel`` within the margins; None
    if ``c`` fails any check by more, or is not white for another reason."""
    ds, dc = sel.diagnostics, c.diagnostics
    if ds is None or dc is None:
        return None
    out = []
    for s, k in ((ds.rho_a2, dc.rho_a2), (ds.rho_ax3, dc.rho_ax3)):
        if k.passed:
            continue
        lo, hi = (1 - MARGIN_RHO) * k.band, (1 + MARGIN_RHO) * k.band
        if not (lo <= abs(s.value) <= hi and lo <= abs(k.value) <= hi):
            return None
        out.append(MarginCheck(k.name, s.value, k.value))
    lb_sel = {x.lag: x for x in ds.ljung_box}
    for x in dc.ljung_box:
        if x.passed is not False:
            continue
        s_lb = lb_sel.get(x.lag)
        if s_lb is None or not all(MARGIN_P_LOW <= p <= MARGIN_P_HIGH
                                   for p in (s_lb.pvalue, x.pvalue)):
            return None
        out.append(MarginCheck(f"ljung_box({x.lag})", s_lb.pvalue, x.pvalue))
    return tuple(out) if out else None


def _extra_terms(sel: Candidate, c: Candidate) -> tuple[tuple[str, float], ...] | None:
    """``sel``'s coefficients beyond ``c``'s (``c`` nested in ``sel``) with their t values;
    None if any is significant or has no finite standard error."""
    names = ([f"ar.L{k}" for k in range(c.p + 1, sel.p + 1)]
             + [f"ma.L{k}" for k in range(c.q + 1, sel.q + 1)])
    out = []
    for name in names:
        est, se = sel.params.get(name, math.nan), sel.bse.get(name, math.nan)
        t = est / se if math.isfinite(se) and se > 0 else math.nan
        if not abs(t) < BAND_Z:
            return None
        out.append((name, float(t)))
    return tuple(out)


def equivalent_simpler(sel: Candidate | None, ranked: Sequence[Candidate],
                       criterion: str) -> EquivalentSimpler | None:
    """The simplest candidate (fewest parameters, then lowest criterion) that ``sel``, a
    white selected model, beats only by a marginal whiteness check (module docstring);
    None if there is none.

    Examples
    --------
    >>> equivalent_simpler(None, [], "aic") is None
    True
    """
    if sel is None or not sel.white:
        return None
    found = []
    for c in ranked:
        if (not c.ok or c.white or c.p > sel.p or c.q > sel.q
                or c.p + c.q >= sel.p + sel.q):
            continue
        delta = getattr(c, criterion) - getattr(sel, criterion)
        if not delta < CLOSE_CALL:
            continue
        checks = _marginal_checks(sel, c)
        extra = _extra_terms(sel, c)
        if checks is not None and extra:
            found.append(EquivalentSimpler(c.model, criterion, float(delta), checks, extra))
    if not found:
        return None
    by_name = {c.model: c for c in ranked}
    return min(found, key=lambda e: (by_name[e.model].p + by_name[e.model].q, e.delta))
