"""What a GMWM noise fit adds to its :class:`~fogts.allan.noise_model.NoiseModel`: the
Gauss-Markov components, the chosen composite model and the J test
(:mod:`fogts.allan.gmwm`)."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

from fogts.tables import fields_dict

__all__ = ["GM_MIN_TC_SAMPLES", "GaussMarkovTerm", "GmwmSummary"]

#: A Gauss-Markov component counts toward the flicker-equivalent B only if its correlation
#: time is at least this many sample periods (:mod:`fogts.allan.gmwm`, "Which components
#: count"): a shorter one is white noise at the taus beyond the first four octaves.
GM_MIN_TC_SAMPLES = 4


@dataclass(frozen=True)
class GaussMarkovTerm:
    """One fitted first-order Gauss-Markov (AR(1)) component.

    Attributes
    ----------
    sigma, sigma_stderr : float
        Stationary standard deviation (deg/h; m/s^2 for an accelerometer) and its
        standard error (delta method on the log parameters).
    t_c, t_c_stderr : float
        Correlation time (s) and its standard error.
    in_b : bool
        Whether it counts toward the flicker-equivalent B: False when ``t_c`` is below
        :data:`GM_MIN_TC_SAMPLES` sample periods (white noise at the data taus; it stays in
        the fitted curve).
    """

    sigma: float
    sigma_stderr: float
    t_c: float
    t_c_stderr: float
    in_b: bool = True

    def to_dict(self) -> dict[str, Any]:
        return fields_dict(self, t_c="t_c_s")


@dataclass(frozen=True)
class GmwmSummary:
    """The GMWM side of a noise fit.

    Attributes
    ----------
    model : str
        The chosen composite model, e.g. ``"N + K + 2 GM"``.
    gauss_markov : tuple of GaussMarkovTerm
        Its Gauss-Markov components (their sum stands for bias instability; ``B`` of the
        NoiseModel is its flicker equivalent, :mod:`fogts.allan.gmwm`).
    j_stat, dof, p_value : float
        The J statistic (the GMWM objective at the optimum with the optimal weights), its
        degrees of freedom (taus minus parameters) and ``P(chi2_dof > J)``.
    level : float
        Level of the J test.
    criterion : str
        The model-choice criterion, ``"J + 2.01 p ln ln n"`` (MMSC-HQIC).
    candidates : tuple of (str, float)
        Every composite model fitted on the way and its criterion value.
    stderr : str
        How the standard errors were obtained (asymptotic sandwich or bootstrap).
    n_bootstrap : int
        Parametric bootstrap replicates (0: asymptotic standard errors).
    """

    model: str
    gauss_markov: tuple[GaussMarkovTerm, ...]
    j_stat: float
    dof: float
    p_value: float
    level: float
    criterion: str
    candidates: tuple[tuple[str, float], ...]
    stderr: str
    n_bootstrap: int = 0

    @property
    def consistent(self) -> bool:
        """Whether the J test accepts the model at ``level``."""
        return not self.p_value < self.level

    @property
    def verdict(self) -> str:
        word = ("consistent with the wavelet variances" if self.consistent
                else "REJECTED: the model misfits the wavelet variances")
        return (f"GMWM J test: J = {self.j_stat:.3g} on {self.dof:g} dof, p = "
                f"{self.p_value:.3g}: {word} at {100 * self.level:g} %")

    def describe(self) -> str:
        lines = [f"GMWM model: {self.model} (chosen by {self.criterion} among "
                 f"{len(self.candidates)} fits); {self.stderr}", self.verdict]
        lines += [f"GM {i + 1}: sigma = {g.sigma:.4g} ± {g.sigma_stderr:.2g}, T_c = "
                  f"{g.t_c:.4g} ± {g.t_c_stderr:.2g} s" + ("" if g.in_b else (
                      f" (below {GM_MIN_TC_SAMPLES} sample periods: white noise at these "
                      "taus, not counted in B)")) for i, g in enumerate(self.gauss_markov)]
        return "\n".join(lines)

    def to_dict(self) -> dict[str, Any]:
        return {"model": self.model, "gauss_markov": [g.to_dict() for g in self.gauss_markov],
                "j_stat": self.j_stat, "dof": self.dof, "p_value": self.p_value,
                "level": self.level, "consistent": self.consistent, "verdict": self.verdict,
                "criterion": self.criterion,
                "candidates": [{"model": m, "criterion": c} for m, c in self.candidates],
                "stderr": self.stderr, "n_bootstrap": self.n_bootstrap}
