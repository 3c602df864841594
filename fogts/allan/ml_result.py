"""What a maximum-likelihood noise fit adds to its :class:`~fogts.allan.noise_model.NoiseModel`:
the Gauss-Markov components, the likelihood, the decimation and the model choice
(:mod:`fogts.allan.ml`)."""

from __future__ import annotations

from dataclasses import dataclass

from fogts.allan.gmwm_result import GaussMarkovTerm

__all__ = ["MlSummary"]


@dataclass(frozen=True)
class MlSummary:
    """The maximum-likelihood side of a noise fit.

    Attributes
    ----------
    model : str
        The chosen state-space model, e.g. ``"N + K + 2 GM"``.
    gauss_markov : tuple of GaussMarkovTerm
        Its Gauss-Markov components (their sum stands for bias instability; ``B`` of the
        NoiseModel is its flicker equivalent, :func:`fogts.allan.gmwm.log_b_equivalent`).
    log_likelihood : float
        The maximised log-likelihood of the record in the curve's units (block means plus
        within-block part, :mod:`fogts.allan.ml_model`).
    n_params : int
        Number of variance and correlation-time parameters (the diffuse bias and ramp not
        counted).
    decimation : int
        Block length ``L`` of the block means the Kalman filter ran on (1: every sample).
    block_s : float
        Duration of one block, ``L / fs`` (s).
    n_blocks, n_used : int
        Number of blocks, and of samples used (``n_blocks * L``; the incomplete last
        block is left out).
    candidates : tuple of (str, float)
        Every model fitted and its BIC, ``-2 logL + p ln n_used``.
    converged : bool
        Whether the optimiser of the chosen model reported convergence.
    stderr : str
        How the standard errors were obtained.
    """

    model: str
    gauss_markov: tuple[GaussMarkovTerm, ...]
    log_likelihood: float
    n_params: int
    decimation: int
    block_s: float
    n_blocks: int
    n_used: int
    candidates: tuple[tuple[str, float], ...]
    converged: bool
    stderr: str

    def describe(self) -> str:
        """Several lines for :meth:`NoiseModel.summary`."""
        dec = ("every sample (no decimation)" if self.decimation == 1 else
               f"block means of {self.decimation} samples ({self.block_s:.4g} s; "
               f"{self.n_blocks} blocks) with the within-block likelihood")
        lines = [f"ML model: {self.model} (chosen by BIC among {len(self.candidates)} "
                 f"fits), log-likelihood {self.log_likelihood:.6g} on {self.n_used} "
                 f"samples, {dec}; {self.stderr}"
                 + ("" if self.converged else " (optimiser NOT converged)")]
        lines += [f"GM {i + 1}: sigma = {g.sigma:.4g} ± {g.sigma_stderr:.2g}, T_c = "
                  f"{g.t_c:.4g} ± {g.t_c_stderr:.2g} s" for i, g in enumerate(self.gauss_markov)]
        return "\n".join(lines)

    def to_dict(self) -> dict[str, object]:
        return {"model": self.model, "gauss_markov": [g.to_dict() for g in self.gauss_markov],
                "log_likelihood": self.log_likelihood, "n_params": self.n_params,
                "decimation": self.decimation, "block_s": self.block_s,
                "n_blocks": self.n_blocks, "n_used": self.n_used,
                "candidates": [{"model": m, "bic": c} for m, c in self.candidates],
                "converged": self.converged, "stderr": self.stderr}
