"""Box-Jenkins identification: the data's ACF and PACF and which of them cuts off or tails off.

:func:`correlogram` reads the two functions against their bands by the rule given in its
notes.

References
----------
G. E. P. Box, G. M. Jenkins and G. C. Reinsel, *Time Series Analysis*, 4th ed., sec. 6.2
(identification from the ACF and PACF; the +-2/sqrt(n) band).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any, Literal

import numpy as np
import pandas as pd

from fogts._typing import ArrayLike1D, FloatArray
from fogts._validate import check_int, to_float_array
from fogts.arma.correlation import autocorrelation, partial_autocorrelation
from fogts.arma.whiteness import BAND_Z, LB_ALPHA

__all__ = ["CUTOFF_MAX_LAG", "CUTOFF_STEP", "OUTLIER_Z", "Correlogram", "CorrelogramPattern",
           "correlogram"]

#: Wider band (two-sided 0.1 %) that no lag after a cut-off may leave.
OUTLIER_Z = 3.29
#: Largest lag read as a cut-off (the highest order of the default candidates, AR(3)); a
#: significant tail beyond it "tails off".
CUTOFF_MAX_LAG = 3
#: A cut-off needs its last significant lag at least this many bands out (an abrupt drop).
CUTOFF_STEP = 2.0


@dataclass(frozen=True)
class CorrelogramPattern:
    """How one correlation function behaves after lag 0.

    The ``acf_pattern`` and ``pacf_pattern`` of a :class:`Correlogram`.

    Attributes
    ----------
    kind : {"none", "cuts off", "tails off"}
        ``"none"``: no lag is significant; ``"cuts off"``: it drops abruptly into the band
        after ``lag``; ``"tails off"``: it decays gradually (or is significant too long).
    lag : int
        Last significant lag (0 for ``"none"``).
    """

    kind: Literal["none", "cuts off", "tails off"]
    lag: int

    def describe(self) -> str:
        if self.kind == "none":
            return "no significant lag"
        if self.kind == "cuts off":
            return f"cuts off after lag {self.lag}"
        return f"tails off (significant up to lag {self.lag})"

    def to_dict(self) -> dict[str, Any]:
        return {"kind": self.kind, "lag": self.lag, "text": self.describe()}


@dataclass(frozen=True)
class Correlogram:
    """The data's ACF and PACF with the Box-Jenkins reading of each.

    What :func:`correlogram` returns; a :class:`~fogts.arma.selection.Selection` carries the
    correlogram of the data it selected on.

    Attributes
    ----------
    n : int
        Number of samples.
    nlags : int
        Largest lag.
    band : float
        ``1.96 / sqrt(n)``: the PACF band (Quenouille) and the ACF band at lag 1.
    acf, pacf : ndarray of float64
        Values at lags 0..nlags.
    acf_band : ndarray of float64
        Bartlett band of the ACF at each lag k, ``1.96 sqrt((1 + 2 sum_{j<k} r_j^2) / n)``
        (NaN at lag 0), as statsmodels' ``plot_acf`` draws it.
    acf_pattern, pacf_pattern : CorrelogramPattern
    suggestion : str
        The model family the pattern points to, in words.
    """

    n: int
    nlags: int
    band: float
    acf: FloatArray
    pacf: FloatArray
    acf_band: FloatArray
    acf_pattern: CorrelogramPattern
    pacf_pattern: CorrelogramPattern
    suggestion: str

    def to_frame(self) -> pd.DataFrame:
        lags = np.arange(self.nlags + 1)
        return pd.DataFrame({"acf": self.acf, "acf_band": self.acf_band, "pacf": self.pacf,
                             "pacf_band": np.r_[math.nan, np.full(self.nlags, self.band)]},
                            index=pd.Index(lags, name="lag"))

    def to_dict(self) -> dict[str, Any]:
        return {"n": self.n, "nlags": self.nlags, "band": self.band,
                "acf": self.acf.tolist(), "pacf": self.pacf.tolist(),
                "acf_band": self.acf_band.tolist(),
                "acf_pattern": self.acf_pattern.to_dict(),
                "pacf_pattern": self.pacf_pattern.to_dict(),
                "suggestion": self.suggestion}

    def summary(self) -> str:
        return (f"ACF {self.acf_pattern.describe()}; PACF {self.pacf_pattern.describe()} "
                f"({self.nlags} lags, band +-{self.band:.3g}) -> {self.suggestion}")


def _acf_bands(r: FloatArray, n: int, z: float) -> FloatArray:
    """Bartlett band for each lag k >= 1 under "MA(k - 1)": z sqrt((1 + 2 sum_{j<k} r_j^2) / n).

    ``out[k]`` is the band for lag k (``out[0]`` unused); Box, Jenkins & Reinsel eq. 2.1.15,
    the band statsmodels' ``acf(..., alpha=0.05)`` and ``plot_acf`` draw.
    """
    c = np.concatenate([[0.0], np.cumsum(r[1:-1] ** 2)]) if r.size > 1 else np.zeros(0)
    return np.concatenate([[math.nan], z * np.sqrt((1.0 + 2.0 * c) / n)])


def _pattern(r: FloatArray, n: int, *, bartlett: bool) -> CorrelogramPattern:
    """Box-Jenkins reading of one correlation function r_0..r_K (rule: see correlogram)."""
    from scipy.stats import binom

    K = r.size - 1
    if bartlett:
        band = _acf_bands(r, n, BAND_Z)
        wide = _acf_bands(r, n, OUTLIER_Z)
    else:
        band = np.full(K + 1, BAND_Z / math.sqrt(n))
        wide = np.full(K + 1, OUTLIER_Z / math.sqrt(n))
    a = np.abs(r)
    k = K
    for cand in range(K + 1):
        # white after lag `cand`: the band that applies to every later lag is band[cand + 1]
        if cand == K:
            k = K
            break
        tail = a[cand + 1:]
        b, w = band[cand + 1], wide[cand + 1]
        allowed = int(binom.ppf(0.95, tail.size, LB_ALPHA))
        if not np.any(tail > w) and int(np.count_nonzero(tail > b)) <= allowed:
            k = cand
            break
    # move down to the last lag that is itself significant (against its own band)
    while k > 0 and a[k] <= band[k]:
        k -= 1
    if k == 0:
        return CorrelogramPattern("none", 0)
    if k == 1 or (k <= CUTOFF_MAX_LAG and a[k] >= CUTOFF_STEP * band[k]):
        return CorrelogramPattern("cuts off", k)
    return CorrelogramPattern("tails off", k)


def _resolve(acf: CorrelogramPattern, pacf: CorrelogramPattern
             ) -> tuple[CorrelogramPattern, CorrelogramPattern]:
    """No ARMA process has both functions finite: if both seem to cut off at different lags,
    the longer one is read as tailing off."""
    if acf.kind == pacf.kind == "cuts off" and acf.lag != pacf.lag:
        if acf.lag > pacf.lag:
            return CorrelogramPattern("tails off", acf.lag), pacf
        return acf, CorrelogramPattern("tails off", pacf.lag)
    return acf, pacf


def _suggest(acf: CorrelogramPattern, pacf: CorrelogramPattern) -> str:
    if acf.kind == "none" and pacf.kind == "none":
        return "the data look white (no model needed)"
    if pacf.kind == "cuts off" and acf.kind != "cuts off":
        return f"AR({pacf.lag})-like (PACF cuts off, ACF tails off)"
    if acf.kind == "cuts off" and pacf.kind != "cuts off":
        return f"MA({acf.lag})-like (ACF cuts off, PACF tails off)"
    if acf.kind == "cuts off" and pacf.kind == "cuts off":
        return f"AR({pacf.lag}) or MA({acf.lag})-like (both cut off)"
    if acf.kind == "none" or pacf.kind == "none":
        return "nearly white (weak correlation only)"
    return "ARMA-like (both tail off)"


def correlogram(x: ArrayLike1D, *, nlags: int | None = None) -> Correlogram:
    """ACF and PACF of the data and which of them cuts off or tails off (Box-Jenkins).

    Parameters
    ----------
    x : array_like
        The prepared (demeaned) series.
    nlags : int, optional
        Largest lag; default ``min(40, n // 4)``.

    Returns
    -------
    Correlogram

    Notes
    -----
    Rule (Box, Jenkins & Reinsel sec. 6.2 read the same bands by eye), applied to each
    function over lags 1..K:

    1. bands: the PACF band is b = 1.96/sqrt(n) at every lag (Quenouille); the ACF band at
       lag k is Bartlett's 1.96 sqrt((1 + 2 sum_{j<k} r_j^2) / n), the band under the
       hypothesis that the ACF cut off before lag k;
    2. the function is *white after lag k* if no later lag leaves the wide band (3.29
       instead of 1.96, i.e. 0.1 %) and no more later lags leave the band than chance
       allows (the 95th percentile of a binomial(K - k, 0.05) count); k is the smallest such
       lag, then moved down to the last lag that is itself outside its band;
    3. k = 0: ``"none"`` (no significant lag);
    4. k = 1, or k <= 3 (the highest order of the default candidates) and |r_k| >= 2 x its
       band, i.e. an abrupt drop into the band: ``"cuts off after lag k"``;
    5. otherwise ``"tails off"`` (a gradual, geometric-looking decay);
    6. no ARMA process has both functions finite: if both cut off at different lags, the
       longer one is read as tailing off.

    An AR(p) process shows a PACF that cuts off after p and an ACF that tails off; MA(q)
    the reverse; ARMA both tail off.  This reading is descriptive: the selection itself is
    by the information criterion among candidates with white residuals.

    Examples
    --------
    >>> from scipy.signal import lfilter
    >>> e = np.random.default_rng(0).standard_normal(20000)
    >>> c = correlogram(lfilter([1.0], [1.0, -0.7], e))
    >>> c.pacf_pattern.describe(), c.acf_pattern.kind
    ('cuts off after lag 1', 'tails off')
    """
    arr = to_float_array(x, "x", min_length=10)
    n = arr.shape[0]
    if nlags is None:
        nlags = min(40, n // 4)
    nlags = check_int("nlags", nlags, minimum=1, maximum=n // 2 - 1)
    acf = autocorrelation(arr, nlags=nlags)
    pac = partial_autocorrelation(arr, nlags=nlags, acf=acf)
    ap, pp = _resolve(_pattern(acf, n, bartlett=True), _pattern(pac, n, bartlett=False))
    return Correlogram(n=n, nlags=nlags, band=BAND_Z / math.sqrt(n), acf=acf, pacf=pac,
                       acf_band=_acf_bands(acf, n, BAND_Z), acf_pattern=ap, pacf_pattern=pp,
                       suggestion=_suggest(ap, pp))
