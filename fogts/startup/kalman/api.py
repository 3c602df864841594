"""Filter and smooth a series with an ARMA drift model: :func:`arma_kalman`.

:func:`resolve_arma_model` fits the drift model by name first when none is given.
"""

from __future__ import annotations

import warnings
from typing import Any, Literal, get_args

import numpy as np
import pandas as pd

from fogts._typing import ArrayLike1D, FloatArray
from fogts._validate import check_choice, check_positive, pandas_index, to_float_array
from fogts.startup.kalman.result import KalmanResult
from fogts.startup.kalman.runs import (
    FilterRun,
    estimate_measurement_noise,
    exact_run,
    riccati_transient,
    steady_run,
    steady_state,
)
from fogts.startup.kalman.state_space import ArmaStateSpace, arma_state_space

__all__ = ["KALMAN_METHODS", "MODEL_CHOICES", "SMOOTH_ADVICE", "arma_kalman", "resolve_arma_model"]

KalmanMethod = Literal["auto", "exact", "steady-state"]
KALMAN_METHODS: tuple[str, ...] = get_args(KalmanMethod)
#: ``method="auto"`` uses the steady-state filter from this many samples on.
STEADY_STATE_MIN_N = 5000
#: Fewest samples filtered.
MIN_KALMAN_SAMPLES = 10
#: An estimated H below this fraction of sigma2 is reported as negligible.
NEGLIGIBLE_H_RATIO = 1e-3
#: The advice of the note on a negligible estimated measurement noise (``name=`` form: the
#: command line names its option, ``fogts filter --measurement-noise``, and leaves it out
#: where it has none, ``fogts compensate``).
SMOOTH_ADVICE = "; give measurement_noise= (a variance in (rate unit)^2) to smooth"
#: Model names accepted by :func:`resolve_arma_model` (and ``fogts filter --model``).
MODEL_CHOICES: tuple[str, ...] = ("auto", "AR(1)", "AR(2)", "AR(3)", "ARMA(1,1)", "ARMA(2,1)")
_ORDERS = {"AR(1)": (1, 0), "AR(2)": (2, 0), "AR(3)": (3, 0), "ARMA(1,1)": (1, 1),
           "ARMA(2,1)": (2, 1)}


def resolve_arma_model(x: ArrayLike1D, spec: str, *, series: str = "") -> Any:
    """Fit the drift model named by ``spec`` to ``x`` (demeaned first).

    ``"auto"`` runs the candidate selection of :func:`fogts.arma.select.select_arma` and
    returns its best candidate; ``"AR(1)"`` .. ``"ARMA(2,1)"`` fit that order with
    :func:`fogts.arma.fit.fit_arma`.  ``series`` names ``x`` (for example "the
    temperature's EMD rest") in front of the selection's warnings, so that a caller that
    models several series says which one has no white candidate.

    Raises
    ------
    DataError
        ``spec`` is not one of :data:`MODEL_CHOICES`.
    """
    check_choice("model", spec, MODEL_CHOICES)
    arr = to_float_array(x, "x", min_length=MIN_KALMAN_SAMPLES)
    arr = arr - float(np.mean(arr))
    if spec == "auto":
        from fogts.arma.select import select_arma

        if not series:
            return select_arma(arr).best
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            best = select_arma(arr).best
        for w in caught:
            warnings.warn(f"{series}: {w.message}", w.category, stacklevel=2)
        return best
    from fogts.arma.fit import fit_arma

    p, q = _ORDERS[spec]
    return fit_arma(arr, p, q)


def arma_kalman(
    x: ArrayLike1D,
    model: Any,
    *,
    measurement_noise: Literal["estimate"] | float = "estimate",
    method: KalmanMethod = "auto",
    smooth: bool = True,
    demean: bool = True,
) -> KalmanResult:
    """Filter and smooth a series with an ARMA drift model plus white measurement noise.

    Parameters
    ----------
    x : array_like or pandas.Series
        Observations (e.g. the fast "rest" of an EMD trend split,
        :func:`fogts.startup.emd.separate_trend`).
    model : ArmaFit, Selection, Candidate, mapping or ArmaSpec
        The drift model (φ, θ, σ² in statsmodels convention): anything
        :meth:`fogts.arma.spec.ArmaSpec.from_any` accepts.
    measurement_noise : "estimate" or float
        H, the measurement-noise variance in (unit)²; ``"estimate"`` maximises the likelihood
        over H with the ARMA parameters fixed.  When the ARMA model was fitted to the same
        noisy observations, its σ² already contains the white noise, the estimate goes to
        H = 0 and the filter follows the data (the result notes it); give H (for example
        the white noise N² fs of the Allan analysis) to smooth in that case.
    method : {"auto", "exact", "steady-state"}
        ``"exact"``: statsmodels' filter and smoother over the whole record;
        ``"steady-state"``: exact only over the Riccati transient, then the constant gain
        (DARE + lfilter); ``"auto"``: steady-state from 5000 samples on.
    smooth : bool
        Also compute the smoothed series (NaN otherwise).
    demean : bool
        Remove the sample mean first (the ARMA model has none) and add it back.

    Returns
    -------
    KalmanResult

    Raises
    ------
    DataError
        Bad model, option or measurement noise.
    InsufficientDataError
        Fewer than 10 samples.

    Examples
    --------
    >>> import numpy as np
    >>> from scipy.signal import lfilter
    >>> rng = np.random.default_rng(0)
    >>> drift = lfilter([1.0], [1.0, -0.95], rng.normal(0, 0.1, 3000))
    >>> y = drift + rng.normal(0, 0.5, 3000)
    >>> res = arma_kalman(y, {"ar.L1": 0.95, "sigma2": 0.01}, measurement_noise=0.25)
    >>> bool(np.std(res.filtered - drift) < np.std(y - drift))
    True
    """
    check_choice("method", method, KALMAN_METHODS)
    index = pandas_index(x)
    y_in = to_float_array(x, "x", min_length=MIN_KALMAN_SAMPLES)
    ss = arma_state_space(model)
    mean = float(np.mean(y_in)) if demean else 0.0
    y = y_in - mean
    notes: list[str] = []
    want_steady = method == "steady-state" or (method == "auto" and y.size >= STEADY_STATE_MIN_N)
    h, source = _measurement_noise(measurement_noise, y, ss, want_steady, notes)
    P, F, Kf = steady_state(ss, h)
    run, run_method = _filter(y, ss, h, P, want_steady=want_steady, smooth=smooth, notes=notes)

    def wrap(arr: FloatArray, name: str) -> Any:
        return pd.Series(arr, index=index, name=name) if index is not None else arr

    return KalmanResult(
        observed=wrap(y_in, "observed"), filtered=wrap(run.filtered + mean, "filtered"),
        smoothed=wrap(run.smoothed + mean, "smoothed"),
        predicted=wrap(run.predicted + mean, "predicted"), innovations=run.innov,
        model=ss.name, ar=tuple(map(float, ss.ar)), ma=tuple(map(float, ss.ma)),
        sigma2=ss.sigma2, measurement_noise=h, measurement_noise_source=source,
        method=run_method, n_transient=run.n0, steady_gain=tuple(map(float, Kf.ravel())),
        innovation_variance=F, loglike=run.loglike, mean=mean, notes=tuple(notes))


def _measurement_noise(measurement_noise: Any, y: FloatArray, ss: ArmaStateSpace,
                       use_steady: bool, notes: list[str]) -> tuple[float, str]:
    """H and its source, ``"estimated"`` or ``"given"``; a note when the estimate is
    negligible."""
    if not isinstance(measurement_noise, str):
        return check_positive("measurement_noise", measurement_noise, allow_zero=True), "given"
    check_choice("measurement_noise", measurement_noise, ("estimate",))
    h, at_lower = estimate_measurement_noise(y, ss, use_steady=use_steady)
    if at_lower or h < NEGLIGIBLE_H_RATIO * ss.sigma2:
        notes.append(f"the ML estimate of the measurement noise is negligible (H = {h:.3g}): "
                     "the ARMA model already explains the observations (was it fitted to "
                     "them?), so the filter follows the data" + SMOOTH_ADVICE)
    return h, "estimated"


def _filter(y: FloatArray, ss: ArmaStateSpace, h: float, P: FloatArray, *, want_steady: bool,
            smooth: bool, notes: list[str]) -> tuple[FilterRun, str]:
    """The run and its method: steady-state after the Riccati transient when wanted and
    the recursion converges within half the record, exact otherwise."""
    if not want_steady:
        return exact_run(y, ss, h, smooth), "exact"
    n0 = riccati_transient(ss, h, P, limit=max(y.size // 2, 1))
    if n0 is None:
        notes.append("the Riccati recursion did not converge within half the record; "
                     "ran the exact filter")
        return exact_run(y, ss, h, smooth), "exact"
    return steady_run(y, ss, h, n0, smooth), "steady-state"
