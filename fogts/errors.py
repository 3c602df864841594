"""Exception and warning hierarchy of fogts.

Every error raised on bad input names the argument, echoes the offending value and says
what is allowed (DESIGN.md, convention 4).  The CLI maps every :class:`FogtsError` to one
line ``error: ...`` on stderr and exit code 2.
"""

from __future__ import annotations

__all__ = ["ConvergenceWarning", "DataError", "DataQualityWarning", "FogtsError", "FogtsWarning",
           "InsufficientDataError", "ModelFitError", "NotWhiteWarning", "UnidentifiableTermWarning"]


class FogtsError(Exception):
    """Base class of every error fogts raises on purpose."""


class DataError(FogtsError, ValueError):
    """The input data or an argument is invalid (bad value, bad column, bad file)."""


class InsufficientDataError(DataError):
    """The input is valid but too short (or too constant) for the requested analysis."""


class ModelFitError(FogtsError, RuntimeError):
    """A model could not be fitted (optimiser failure, non-finite likelihood, ...)."""


class FogtsWarning(UserWarning):
    """Base class of every warning fogts emits."""


class ConvergenceWarning(FogtsWarning):
    """An optimiser stopped before it met its convergence criterion."""


class DataQualityWarning(FogtsWarning):
    """The data were read, but something about them deserves attention (gaps, jitter)."""


class UnidentifiableTermWarning(FogtsWarning):
    """A noise term's region of tau is not covered by the data, so it cannot be identified."""


class NotWhiteWarning(FogtsWarning):
    """No candidate model left white residuals."""
